"""One element of a reference sample at one sliding speed and pressure: every output.

:func:`analyse_element` builds the element of the preset (geometry from
:mod:`friction_model.geometry`, the one rubber from :mod:`friction_model.compound`), loads
it with the pressure on its face (N = p l w, as the beam models) and the friction of
Eq. 5.24 fitted to Table 4.6 at the sliding speed (the law of the chapter-5 predictions,
:func:`friction_model.dynamics.stick_slip.table_4_6_eq_5_24`), solves the linear or the
neo-Hookean model and returns the outputs and the modal frequencies. The steady state is
quasi-static (E0); the frequencies are given at E0 and at the modulus of their own
frequency (the compound's causal E(f)), as the beam's stick-slip prediction does.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from friction_model.compound import REFERENCE_COMPOUND, Compound
from friction_model.continuum.hyperelastic import solve_neo_hookean
from friction_model.continuum.linear import solve_linear
from friction_model.continuum.model import ElementSpec, build_mesh
from friction_model.continuum.modes import modal_frequencies, own_modulus_frequency_Hz
from friction_model.continuum.outputs import ElementOutputs, element_outputs
from friction_model.continuum.state import ElementState
from tir_common.validate import check_range

__all__ = ["MODELS", "ElementAnalysis", "analyse_element", "solve_element"]

#: The two material models.
MODELS = ("linear", "neo-hookean")


@dataclass(frozen=True)
class ElementAnalysis:
    """The outputs of :func:`analyse_element`.

    Attributes
    ----------
    outputs : ElementOutputs
        Tip deflection, slope, bending / shear, contact, lever arm.
    state : ElementState
        The solution (mesh, fields, reactions).
    velocity_mps, pressure_Pa : float
        Sliding speed and face pressure.
    frequencies_sliding_Hz, frequencies_stuck_Hz : ndarray
        Lowest natural frequencies at E0 with the face sliding / stuck on the ice.
    first_sliding_own_modulus_Hz, first_stuck_own_modulus_Hz : float
        The first of each at the modulus of its own frequency.
    """

    outputs: ElementOutputs
    state: ElementState
    velocity_mps: float
    pressure_Pa: float
    frequencies_sliding_Hz: np.ndarray
    frequencies_stuck_Hz: np.ndarray
    first_sliding_own_modulus_Hz: float
    first_stuck_own_modulus_Hz: float


def solve_element(spec: ElementSpec, *, normal_force_N: float, mu: float,
                  model: str = "linear", **options: Any) -> ElementState:
    """Mesh ``spec`` and solve it on the ice with the ``model`` (``"linear"``, ``"neo-hookean"``).

    Examples
    --------
    >>> s = solve_element(ElementSpec(n_length=4), normal_force_N=91.0, mu=0.0)
    >>> round(float(s.face_force_N_per_m.sum()) * 0.08, 6)
    91.0
    """
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}, got model={model!r}")
    em = build_mesh(spec)
    if model == "linear":
        return solve_linear(em, normal_force_N=normal_force_N, mu=mu, **options)
    return solve_neo_hookean(em, normal_force_N=normal_force_N, mu=mu, **options)


def analyse_element(
    preset: str = "G3",
    *,
    velocity_mps: float = 1.0,
    pressure_bar: float = 2.5,
    model: str = "linear",
    element: int = 0,
    compound: Compound = REFERENCE_COMPOUND,
    friction: Callable[[float], float] | None = None,
    n_modes: int = 3,
    **spec_fields: Any,
) -> ElementAnalysis:
    """Solve one element of ``preset`` sliding at ``velocity_mps`` under ``pressure_bar``.

    Parameters
    ----------
    preset : str
        Reference sample (G0, G3, ...; :func:`friction_model.geometry.reference_block`).
    velocity_mps : float
        Sliding speed, m/s (sets mu).
    pressure_bar : float
        Nominal pressure on the element's face, bar.
    model : {"linear", "neo-hookean"}
    element : int
        Which element of the sample (0: the leading one).
    compound : Compound
        The rubber (default the one rubber).
    friction : callable, optional
        mu(v); default Eq. 5.24 fitted to Table 4.6 (G3, 2.5 bar, -5 degC).
    n_modes : int
        Frequencies per face condition.
    **spec_fields
        Further :class:`ElementSpec` fields (``n_length``, ``base_thickness_m``, ...).

    Returns
    -------
    ElementAnalysis
    """
    v = check_range("velocity_mps", velocity_mps, 1e-6, 100.0, unit="m/s")
    p = check_range("pressure_bar", pressure_bar, 1e-3, 100.0, unit="bar") * 1e5
    if friction is None:
        from friction_model.dynamics.stick_slip import table_4_6_eq_5_24

        friction = table_4_6_eq_5_24().mu
    mu = float(friction(v))
    spec = ElementSpec.from_preset(preset, element=element, compound=compound, **spec_fields)
    N = p * spec.length_m * spec.width_m
    state = solve_element(spec, normal_force_N=N, mu=mu, model=model)
    slide = modal_frequencies(state, face="sliding", n_modes=n_modes)
    stuck = modal_frequencies(state, face="stuck", n_modes=n_modes)
    n = compound.modulus_exponent
    f0 = compound.reference_frequency_Hz
    return ElementAnalysis(
        outputs=element_outputs(state),
        state=state,
        velocity_mps=v,
        pressure_Pa=p,
        frequencies_sliding_Hz=slide,
        frequencies_stuck_Hz=stuck,
        first_sliding_own_modulus_Hz=own_modulus_frequency_Hz(float(slide[0]), n, f0),
        first_stuck_own_modulus_Hz=own_modulus_frequency_Hz(float(stuck[0]), n, f0),
    )
