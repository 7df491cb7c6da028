"""The lever arm of Eq. 5.21 refitted to the continuum, and the beam run with it.

The beam of section 5.3 moves the normal force off the tip's axis by the lever arm
e(phi) of Eq. 5.21/5.22, a characteristic the thesis guessed (Fig. 5.12 a: e ~ 0 below
10 deg, 1.9 mm beyond 40 deg). The continuum gives e directly: the offset of the normal
resultant of the face pressure. :func:`lever_arm_sweep` drags the element with growing
friction at the operating normal force (the tilt grows with mu); :func:`fit_lever_arm_law`
fits e1..e4 of Eq. 5.21 to e over the face's section rotation phi(d) (the beam's tip
rotation), and :func:`beam_steady_state` runs the steady beam-column
(:func:`friction_model.compound.steady_beam_column`) with the Fig. 5.12 a law, with the
refitted law, or with a constant lever arm. Nothing of the rig enters the fit.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from friction_model.compound import REFERENCE_COMPOUND, Compound, steady_beam_column
from friction_model.continuum.analysis import solve_element
from friction_model.continuum.model import ElementSpec
from friction_model.continuum.outputs import element_outputs

__all__ = ["beam_steady_state", "fit_lever_arm_law", "lever_arm_sweep", "winkler_contact_length"]


def lever_arm_sweep(spec: ElementSpec, *, normal_force_N: float, mus: Sequence[float],
                    model: str = "neo-hookean") -> pd.DataFrame:
    """Lever arm, face rotation and tip values of the element dragged with each mu.

    Returns
    -------
    pandas.DataFrame
        ``mu, bending_rad, tip_slope_rad, lever_arm_m, tip_deflection_m, liftoff_m``.
    """
    rows = []
    for mu in mus:
        o = element_outputs(solve_element(spec, normal_force_N=normal_force_N, mu=float(mu),
                                          model=model))
        rows.append({"mu": float(mu), "bending_rad": o.bending_rad,
                     "tip_slope_rad": o.tip_slope_rad, "lever_arm_m": o.lever_arm_m,
                     "tip_deflection_m": o.tip_deflection_m, "liftoff_m": o.liftoff_m})
    return pd.DataFrame(rows)


def _eq_5_21(phi: np.ndarray, length_m: float, e1: float, e2: float, e3: float, e4: float):
    """Eq. 5.21: e = l/4 - e3 + atan(-e1 + e2 phi) (l/2 - e4) / pi, m (phi >= 0)."""
    return 0.25 * length_m - e3 + np.arctan(-e1 + e2 * phi) / math.pi * (0.5 * length_m - e4)


def fit_lever_arm_law(phi_rad: np.ndarray, lever_arm_m: np.ndarray, length_m: float,
                      *, e2_max_per_rad: float = 1e4) -> dict[str, float]:
    """Least-squares e1..e4 of Eq. 5.21 to lever arms over the tip rotation.

    e3 and e4 stay in [-l/2, l/2], e1 in [-50, 50] and e2 in [0, ``e2_max_per_rad``] (the
    bounds of :class:`~friction_model.dynamics.timoshenko.TimoshenkoParams`); the fit starts
    from the Fig. 5.12 a law and from a steep one and keeps the better.

    Parameters
    ----------
    phi_rad, lever_arm_m : ndarray
        Tip rotations (>= 0, rad) and lever arms (m).
    length_m : float
        Element length l, m.
    e2_max_per_rad : float
        Largest e2, 1/rad.

    Returns
    -------
    dict
        ``e1, e2_per_rad, e3_m, e4_m`` (the fields of ``TimoshenkoParams``) and ``rms_m``.

    Examples
    --------
    >>> phi = np.linspace(0.0, 1.0, 30)
    >>> e = _eq_5_21(phi, 4.55e-3, 12.0, 28.0, 0.0, 1e-4)
    >>> fit = fit_lever_arm_law(phi, e, 4.55e-3)
    >>> round(fit["rms_m"] * 1e6, 3)
    0.0
    """
    from friction_model.dynamics.timoshenko import TimoshenkoParams

    phi = np.clip(np.asarray(phi_rad, dtype=float), 0.0, None)
    e = np.asarray(lever_arm_m, dtype=float)
    half = 0.5 * length_m

    def resid(x):
        return _eq_5_21(phi, length_m, *x) - e

    lb = [-50.0, 0.0, -half, -half]
    ub = [50.0, e2_max_per_rad, half, half]
    fig = TimoshenkoParams(length_m=max(length_m, 3.8e-3 * 1.0001), contact_stiffness_N_m=1.0)
    e3, e4 = fig.lever_arm_e3_e4
    starts = [[12.0, 28.0, float(np.clip(e3, -half, half)), float(np.clip(e4, -half, half))],
              [1.0, 0.5 * e2_max_per_rad, 0.0, 0.0]]
    best = min((least_squares(resid, x0, bounds=(lb, ub)) for x0 in starts),
               key=lambda r: float(np.sum(r.fun**2)))
    e1, e2, e3, e4 = (float(v) for v in best.x)
    return {"e1": e1, "e2_per_rad": e2, "e3_m": e3, "e4_m": e4,
            "rms_m": float(np.sqrt(np.mean(best.fun**2)))}


def winkler_contact_length(lever_arm_m: float, length_m: float) -> float:
    """Contact length of a rigid face on a Winkler bed with the resultant offset e, m.

    Linear pressure: the whole face while |e| <= l/6, else a triangle of 3 (l/2 - |e|).

    Examples
    --------
    >>> winkler_contact_length(0.0, 6.0), winkler_contact_length(2.0, 6.0)
    (6.0, 3.0)
    """
    e = abs(lever_arm_m)
    return float(length_m if e <= length_m / 6.0 else 3.0 * (0.5 * length_m - e))


def beam_steady_state(*, mu: float, normal_force_N: float, compound: Compound = REFERENCE_COMPOUND,
                      **element: Any) -> dict[str, float]:
    """Steady sliding state of the Haringx Timoshenko element (one rubber, E0).

    Parameters
    ----------
    mu, normal_force_N : float
    compound : Compound
    **element
        :class:`~friction_model.dynamics.timoshenko.TimoshenkoParams` fields (geometry,
        ``e1, e2_per_rad, e3_m, e4_m`` or ``lever_arm_m``).

    Returns
    -------
    dict
        :func:`~friction_model.compound.steady_beam_column`'s values and
        ``contact_length_m`` (Winkler, from e), ``liftoff_m``.
    """
    from friction_model.dynamics.timoshenko import TimoshenkoParams

    base = TimoshenkoParams(E_Pa=compound.E0_Pa, density_kg_m3=compound.density_kg_m3,
                            kelvin_voigt_s=0.0, contact_stiffness_N_m=1.0)
    params = replace(base, **element)
    out = steady_beam_column(params, normal_force_N=normal_force_N, mu=mu)
    contact = winkler_contact_length(out["lever_arm_m"], params.length_m)
    out["contact_length_m"] = contact
    out["liftoff_m"] = params.length_m - contact
    return out
