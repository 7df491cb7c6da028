"""Tread-block dynamics (chapter 5): rigid-body oscillators, Euler-Bernoulli, Timoshenko."""

from friction_model.dynamics._common import (
    SimulationError,
    SimulationResult,
    constant_preload,
    constant_velocity,
    surface_profile,
    velocity_ramp,
    velocity_step,
)

__all__ = [
    "SimulationError",
    "SimulationResult",
    "constant_preload",
    "constant_velocity",
    "surface_profile",
    "velocity_ramp",
    "velocity_step",
]
