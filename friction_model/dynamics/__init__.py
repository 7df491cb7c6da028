"""Tread-block dynamics (chapter 5): rigid-body oscillators, Euler-Bernoulli, Timoshenko.

Public API
----------
Inputs, solver and results
    :class:`SolverOptions` (method, tolerances, largest step of every simulator),
    :func:`constant_velocity`, :func:`velocity_step`, :func:`velocity_ramp`,
    :func:`constant_preload`, :func:`surface_profile`, :class:`SimulationResult`,
    :class:`SimulationError`.
Rigid bodies (section 5.1)
    :class:`SdofParams`, :func:`simulate_sdof`, :class:`BlockParams`,
    :func:`simulate_block_dynamics`, :func:`element_surface_profiles`.
Euler-Bernoulli beam (section 5.2)
    :class:`EulerBernoulliParams`, :func:`simulate_euler_bernoulli`,
    :func:`eb_natural_frequencies`.
Timoshenko beam (section 5.3)
    :class:`TimoshenkoParams`, :func:`simulate_timoshenko`, :func:`static_tip_deflection`,
    :func:`natural_frequencies_timoshenko`, :func:`fdm_natural_frequencies`,
    :func:`lever_arm`, :func:`preload_for_normal_force`, :func:`cowper_shear_coefficient`,
    :func:`beam_column_static`, :func:`buckling_load`, :func:`fdm_buckling_load`;
    the elastic root from the measured deflection (:mod:`~friction_model.dynamics.root`):
    :func:`identify_root_stiffness`, :func:`steady_beam_column`.
Contact ratio and sweeps
    :func:`reference_contact_ratios`, :func:`run_sweep`, :func:`parameter_grid`,
    :func:`timoshenko_point`, :func:`dry_wet_point`.
"""

from friction_model.dynamics._common import (
    SimulationError,
    SimulationResult,
    constant_preload,
    constant_velocity,
    surface_profile,
    velocity_ramp,
    velocity_step,
)
from friction_model.dynamics.contact import reference_contact_ratios
from friction_model.dynamics.euler_bernoulli import (
    EulerBernoulliParams,
    eb_natural_frequencies,
    simulate_euler_bernoulli,
)
from friction_model.dynamics.rigid import (
    BlockParams,
    SdofParams,
    element_surface_profiles,
    simulate_block_dynamics,
    simulate_sdof,
)
from friction_model.dynamics.root import (
    MEASURED_DEFLECTION_M,
    RootIdentification,
    identify_root_stiffness,
    steady_beam_column,
)
from friction_model.dynamics.solver import SolverOptions
from friction_model.dynamics.stick_slip import predict_stick_slip
from friction_model.dynamics.sweep import (
    dry_wet_point,
    parameter_grid,
    run_sweep,
    timoshenko_point,
)
from friction_model.dynamics.timoshenko import (
    TimoshenkoParams,
    beam_column_static,
    buckling_load,
    cowper_shear_coefficient,
    fdm_buckling_load,
    fdm_natural_frequencies,
    lever_arm,
    natural_frequencies_timoshenko,
    preload_for_normal_force,
    simulate_timoshenko,
    static_tip_deflection,
)

__all__ = [
    "MEASURED_DEFLECTION_M",
    "BlockParams",
    "EulerBernoulliParams",
    "RootIdentification",
    "SdofParams",
    "SimulationError",
    "SimulationResult",
    "SolverOptions",
    "TimoshenkoParams",
    "beam_column_static",
    "buckling_load",
    "constant_preload",
    "constant_velocity",
    "cowper_shear_coefficient",
    "dry_wet_point",
    "eb_natural_frequencies",
    "element_surface_profiles",
    "fdm_buckling_load",
    "fdm_natural_frequencies",
    "identify_root_stiffness",
    "lever_arm",
    "natural_frequencies_timoshenko",
    "parameter_grid",
    "predict_stick_slip",
    "preload_for_normal_force",
    "reference_contact_ratios",
    "run_sweep",
    "simulate_block_dynamics",
    "simulate_euler_bernoulli",
    "simulate_sdof",
    "simulate_timoshenko",
    "static_tip_deflection",
    "steady_beam_column",
    "surface_profile",
    "timoshenko_point",
    "velocity_ramp",
    "velocity_step",
]
