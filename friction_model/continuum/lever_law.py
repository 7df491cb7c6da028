"""The lever arm of Eq. 5.21 refitted to the continuum, and the beam run with it.

The beam of section 5.3 moves the normal force off the tip's axis by the lever arm
e(phi) of Eq. 5.21/5.22, a characteristic the thesis guessed (Fig. 5.12 a: e ~ 0 below
10 deg, 1.9 mm beyond 40 deg). The continuum gives e directly: the offset of the normal
resultant of the face pressure. :func:`lever_arm_sweep` drags the element with growing
friction at the operating normal force (the tilt grows with mu); :func:`fit_lever_arm_law`
fits e1..e4 of Eq. 5.21 to e over the face's section rotation phi(d) (the beam's tip
rotation), and :func:`beam_steady_state` runs the steady beam-column
(:func:`friction_model.dynamics.root.steady_beam_column`) with the Fig. 5.12 a law, with the
refitted law, or with a constant lever arm. Nothing of the rig enters the fit.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import pandas as pd

from friction_model.compound import REFERENCE_COMPOUND, Compound
from friction_model.continuum.analysis import solve_element
from friction_model.continuum.model import ElementSpec
from friction_model.continuum.outputs import element_outputs
from friction_model.dynamics.root import steady_beam_column

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


def fit_lever_arm_law(phi_rad: np.ndarray, lever_arm_m: np.ndarray,
                      length_m: float) -> dict[str, float]:
    """e1..e4 of Eq. 5.21 fitted to lever arms over the tip rotation.

    The project's one Eq. 5.21 fit (:func:`friction_model.identification.fit_lever_arm`,
    within the bounds of ``TimoshenkoParams``), returned as ``TimoshenkoParams`` fields.

    Returns
    -------
    dict
        ``e1, e2_per_rad, e3_m, e4_m`` and the residual ``rms_m``.
    """
    from friction_model.identification import fit_lever_arm

    fit = fit_lever_arm(np.clip(np.asarray(phi_rad, dtype=float), 0.0, None),
                        np.asarray(lever_arm_m, dtype=float), element_length_m=length_m)
    return {**{k: float(v) for k, v in fit.params.items()}, "rms_m": float(fit.rmse_m)}


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
        :func:`~friction_model.dynamics.root.steady_beam_column`'s values and
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
