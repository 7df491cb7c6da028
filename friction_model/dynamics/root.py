"""The elastic root of a tread-block element, identified from the measured deflection.

The block base under the sipes is not rigid: the compliance of the base (the 14 mm of the
block below the 6 mm sipes and the rubber around the element root) lets the element root
rotate. :func:`identify_root_stiffness` identifies that rotational stiffness from the one
deflection measurement the thesis gives (1.6 mm at 1 m/s, 2.5 bar, Fig. 5.14): the only
number of the thesis used as a fit target in the beam models. :func:`steady_beam_column` is
the closed-form steady state of the Timoshenko beam-column it uses.

(These lived in :mod:`friction_model.compound` until that module and
:mod:`friction_model.dynamics.timoshenko` imported each other; the rubber is now a leaf.)
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace
from typing import Any

from scipy.optimize import brentq

from friction_model.compound import REFERENCE_COMPOUND, Compound
from friction_model.dynamics.timoshenko import (
    TimoshenkoParams,
    beam_column_static,
    buckling_load,
    lever_arm,
)

logger = logging.getLogger(__name__)

__all__ = [
    "MEASURED_DEFLECTION_M",
    "RootIdentification",
    "identify_root_stiffness",
    "steady_beam_column",
]

#: Measured steady tip deflection of a G3 element at 1 m/s, 2.5 bar (Fig. 5.14), m.
MEASURED_DEFLECTION_M = 1.6e-3


@dataclass(frozen=True)
class RootIdentification:
    """Result of :func:`identify_root_stiffness`.

    Attributes
    ----------
    root_stiffness_Nm_per_rad : float
        Rotational stiffness of the element root (block base), N m/rad.
    tip_deflection_m, tip_slope_rad, bending_angle_rad, root_rotation_rad : float
        Steady state at the identification point (the first equals the target).
    params : TimoshenkoParams
        The element with that root.
    """

    root_stiffness_Nm_per_rad: float
    tip_deflection_m: float
    tip_slope_rad: float
    bending_angle_rad: float
    root_rotation_rad: float
    params: TimoshenkoParams


def steady_beam_column(
    params: TimoshenkoParams, *, normal_force_N: float, mu: float, tol_rad: float = 1e-12
) -> dict[str, float]:
    """Steady sliding state of the Timoshenko element under a constant normal force.

    At steady sliding (v_rel = v0) the element is the static beam-column of
    :func:`friction_model.dynamics.timoshenko.beam_column_static` under the tip force
    mu N, the axial force N and the lever-arm moment -e(phi(d)) N (Eq. 5.20-5.22); the
    moment depends on the tip rotation, found by Brent's method.

    Parameters
    ----------
    params : TimoshenkoParams
        Element (Haringx or Engesser beam-column).
    normal_force_N : float
        N, N.
    mu : float
        Friction coefficient at the sliding speed.
    tol_rad : float
        Convergence of the tip rotation, rad.

    Returns
    -------
    dict
        ``tip_deflection_m, tip_slope_rad, bending_angle_rad, root_rotation_rad,
        lever_arm_m``.
    """
    N = float(normal_force_N)
    P = mu * N

    def rotation(phi: float) -> float:
        e = float(lever_arm(params, phi))
        return beam_column_static(params, P, axial_force_N=N, moment_Nm=-e * N)[1]

    # the lever arm acts against the tilt, so the solution lies between 0 and the
    # rotation without it (a fixed-point iteration diverges near the buckling load)
    phi_free = rotation(0.0)
    if phi_free == 0.0:
        phi = 0.0
    else:
        phi = brentq(lambda a: rotation(a) - a, 0.0, phi_free, xtol=tol_rad, rtol=1e-14)
    e = float(lever_arm(params, phi))
    r_tip, phi = beam_column_static(params, P, axial_force_N=N, moment_Nm=-e * N)
    e = float(lever_arm(params, phi))
    kGA = params.kGA
    if params.beam_column == "haringx":
        slope = (1.0 + N / kGA) * phi + P / kGA
    else:
        slope = (phi + P / kGA) / (1.0 - N / kGA)
    # root rotation: EI phi'(0) = k phi(0), with the moment at the root
    # M(0) = -e N + P d + N r(d)
    k = params.root_stiffness_Nm_per_rad
    m_root = -e * N + P * params.height_m + N * r_tip
    phi0 = 0.0 if k is None else m_root / k
    return {
        "tip_deflection_m": float(r_tip),
        "tip_slope_rad": float(math.atan(slope)),
        "bending_angle_rad": float(phi),
        "root_rotation_rad": float(phi0),
        "lever_arm_m": e,
    }


def identify_root_stiffness(
    *,
    compound: Compound = REFERENCE_COMPOUND,
    mu: float,
    normal_force_N: float,
    target_deflection_m: float = MEASURED_DEFLECTION_M,
    **element: Any,
) -> RootIdentification:
    """Root rotational stiffness that gives the measured steady deflection (Fig. 5.14).

    The element (Haringx beam-column, E0 of ``compound``: the steady state is
    quasi-static) slides steadily under the constant normal force with friction mu; its
    root stiffness k is found by Brent's method so that the steady tip deflection equals
    ``target_deflection_m``.

    Parameters
    ----------
    compound : Compound
        The rubber.
    mu : float
        Friction coefficient at the sliding speed (Eq. 5.24 at 1 m/s).
    normal_force_N : float
        Normal force on the element, N.
    target_deflection_m : float
        Measured steady deflection, m (1.6 mm).
    **element
        Further :class:`~friction_model.dynamics.timoshenko.TimoshenkoParams` fields
        (geometry, lever arm, grid); E, G and the density come from ``compound``.

    Returns
    -------
    RootIdentification

    Raises
    ------
    ValueError
        If the clamped element already deflects more than the target (no root compliance
        can be identified) or the target needs a root softer than 1e-4 N m/rad.
    """
    element.setdefault("kelvin_voigt_s", 0.0)
    element.setdefault("contact_stiffness_N_m", 1.0)
    base = TimoshenkoParams(
        E_Pa=compound.E0_Pa,
        density_kg_m3=compound.density_kg_m3,
        G_Pa=compound.E0_Pa / (2.0 * (1.0 + compound.poisson_ratio)),
        **element,
    )

    def deflection(k: float | None) -> float:
        p = replace(base, root_stiffness_Nm_per_rad=k)
        return steady_beam_column(p, normal_force_N=normal_force_N, mu=mu)["tip_deflection_m"]

    clamped = deflection(None)
    if clamped >= target_deflection_m:
        raise ValueError(
            f"the clamped element already deflects {clamped * 1e3:.3f} mm >= the target "
            f"{target_deflection_m * 1e3:.3f} mm: no root compliance to identify"
        )
    k_lo, k_hi = 1e-4, 1e6

    def gap(log_k: float) -> float:
        k = 10.0**log_k
        p = replace(base, root_stiffness_Nm_per_rad=k)
        if normal_force_N >= buckling_load(p):
            return 1.0  # buckled: softer than any finite target
        return deflection(k) - target_deflection_m

    if gap(math.log10(k_lo)) < 0:
        raise ValueError("the target deflection needs a root softer than 1e-4 N m/rad")
    log_k = brentq(gap, math.log10(k_lo), math.log10(k_hi), xtol=1e-12)
    k = 10.0**log_k
    p = replace(base, root_stiffness_Nm_per_rad=k)
    st = steady_beam_column(p, normal_force_N=normal_force_N, mu=mu)
    logger.debug("identified root stiffness %.4g N m/rad", k)
    return RootIdentification(
        root_stiffness_Nm_per_rad=k,
        tip_deflection_m=st["tip_deflection_m"],
        tip_slope_rad=st["tip_slope_rad"],
        bending_angle_rad=st["bending_angle_rad"],
        root_rotation_rad=st["root_rotation_rad"],
        params=p,
    )
