"""Stick-slip of the Timoshenko element predicted from the one rubber (Fig. 5.16).

Nothing is tuned to a stick-slip number: the G3 element (section 5.3), the constant normal
force of 2.5 bar on its face, the Haringx beam-column, Eq. 5.24 fitted to the chapter 4
characteristic of G3 (Table 4.6, cold-dry 2.5 bar) and the rubber of
:data:`friction_model.compound.REFERENCE_COMPOUND`. The modulus is that of the vibration's
own frequency (fixed point f = f1(E(f)) of the first mode of the loaded element, E(f) of the
compound's causal constant-loss model) and the Kelvin-Voigt damping that of its loss factor,
k_i = tan(delta) / (2 pi f). The zero-crossing steepness k4 of Eq. 5.24 is not determined by
Table 4.6 (its data start at 1 m/s); :data:`K4_INTERVAL_S_PER_M` spans it.

:data:`PREDICTED_STICK_SLIP_HZ` freezes the result of :func:`predict_stick_slip` (BDF at
rtol 1e-5, 40 nodes, zero crossings over the last 30 ms: a few Hz), recomputed by a slow test.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import replace
from functools import lru_cache
from typing import Any

import numpy as np
import pandas as pd
import scipy.linalg

from friction_model.compound import REFERENCE_COMPOUND, Compound
from friction_model.contact.laws import ArctanExponentialLaw, fit_law
from friction_model.dynamics._common import velocity_ramp
from friction_model.dynamics.element_step import modulus_ratio
from friction_model.dynamics.timoshenko import TimoshenkoParams, _system, simulate_timoshenko
from friction_model.thesis_data import table_4_6_targets

logger = logging.getLogger(__name__)

__all__ = [
    "K4_INTERVAL_S_PER_M",
    "PREDICTED_EXTRA_MODULUS_HZ",
    "PREDICTED_STICK_SLIP_HZ",
    "limit_cycle_run",
    "loaded_first_frequency_Hz",
    "loaded_mode_at_own_modulus_Hz",
    "predict_stick_slip",
    "table_4_6_eq_5_24",
]

#: Central value and interval of the zero-crossing steepness k4 of Eq. 5.24, s/m.
K4_CENTRAL_S_PER_M = 50.0
K4_INTERVAL_S_PER_M = (20.0, 200.0)
#: Frozen :func:`predict_stick_slip` limit-cycle frequencies, Hz, at k4 = 20, 50, 200 s/m
#: (tolerance of the method: ~5 Hz, from rtol 1e-5 and the 30 ms counting window).
PREDICTED_STICK_SLIP_HZ = {20.0: 857.0, 50.0: 826.0, 200.0: 793.0}
#: Frozen :func:`predict_stick_slip` limit-cycle frequencies, Hz, at k4 = 50 s/m with an extra
#: frequency stiffening of strength s on top of the compound's own E(f) (the discrepancy
#: candidate evaluated on the loaded element; same method tolerance).
PREDICTED_EXTRA_MODULUS_HZ = {
    0.0: 826.0,
    0.5: 1190.9,
    1.0: 1547.0,
    1.5: 1839.9,
    2.0: 2095.1,
    3.0: 2541.1,
    5.0: 3285.9,
}
_PRESSURE_PA = 2.5e5
_V0_MPS = 1.0


@lru_cache(maxsize=8)
def table_4_6_eq_5_24(k4_s_per_m: float = K4_CENTRAL_S_PER_M) -> ArctanExponentialLaw:
    """Eq. 5.24 fitted to the cold/dry 2.5 bar characteristic of Table 4.6, k4 held fixed.

    Parameters
    ----------
    k4_s_per_m : float
        Zero-crossing steepness k4, s/m (not determined by Table 4.6, whose data start at
        1 m/s; :data:`K4_INTERVAL_S_PER_M` spans it).

    Returns
    -------
    friction_model.contact.laws.ArctanExponentialLaw
    """
    rows = table_4_6_targets()
    rows = rows[rows["curve"] == "cold-dry 2.5 bar"]
    return fit_law(
        ArctanExponentialLaw, rows["velocity_mps"], rows["mu_target"], fixed={"k4": k4_s_per_m}
    ).law


def _element(compound: Compound) -> TimoshenkoParams:
    return TimoshenkoParams(
        E_Pa=compound.E0_Pa,
        density_kg_m3=compound.density_kg_m3,
        kelvin_voigt_s=0.0,
        contact_stiffness_N_m=1.0,  # unused: applied normal force
    )


def loaded_first_frequency_Hz(params: Any, normal_force_N: float) -> float:
    """First natural frequency of the element under the axial force N, Hz.

    Eigenvalues of (K - N G) x = omega^2 M x with the finite-difference operators of
    ``params`` (Haringx by default; the tip free, as in sliding).
    """
    s = _system(params)
    w2 = scipy.linalg.eigvals((s.K - normal_force_N * s.G).toarray() / s.mass[:, None]).real
    return float(math.sqrt(np.min(w2[w2 > 0])) / (2.0 * math.pi))


def loaded_mode_at_own_modulus_Hz(params: Any, normal_force_N: float,
                                  modulus_Pa: Callable[[float], float],
                                  *, start_Hz: float = 500.0) -> float:
    """The loaded first mode of an element whose modulus depends on the frequency, Hz.

    The fixed point ``f = loaded_first_frequency_Hz(params with E = modulus_Pa(f), N)``,
    iterated from `start_Hz` to a relative change below 1e-9 (at most 200 steps).
    """
    f = float(start_Hz)
    for _ in range(200):
        f_new = loaded_first_frequency_Hz(replace(params, E_Pa=modulus_Pa(f)), normal_force_N)
        if abs(f_new - f) < 1e-9 * f:
            return f_new
        f = f_new
    return f


def limit_cycle_run(
    params: TimoshenkoParams,
    friction: Any,
    normal_force_N: float,
    v0_mps: float,
    t_end_s: float,
    window_s: float,
) -> tuple[Any, pd.DataFrame]:
    """Run a Timoshenko element from rest up to `v0_mps` (a 10 ms ramp) under a constant
    normal force, and keep the last `window_s` of it (the limit cycle of Fig. 5.16).

    Parameters
    ----------
    params : TimoshenkoParams
    friction : friction law
        mu(v) of the contact (e.g. :func:`table_4_6_eq_5_24`).
    normal_force_N : float
        Constant normal force, N.
    v0_mps : float
        Carrier speed after the ramp, m/s.
    t_end_s, window_s : float
        Simulated time and the final window kept, s (output every 5 us).

    Returns
    -------
    result : SimulationResult
        The whole run (:func:`~friction_model.dynamics.timoshenko.simulate_timoshenko`).
    window : pandas.DataFrame
        The rows of ``result.data`` after ``t_end_s - window_s``.
    """
    res = simulate_timoshenko(
        params,
        velocity=velocity_ramp(0.0, v0_mps, 0.0, 0.01),
        normal_force=normal_force_N,
        friction=friction,
        t_end_s=t_end_s,
        n_output=int(t_end_s * 2e5) + 1,  # 5 us samples
    )
    return res, res.data[res.data["time_s"] > t_end_s - window_s]


def predict_stick_slip(
    *,
    k4_s_per_m: float = K4_CENTRAL_S_PER_M,
    compound: Compound = REFERENCE_COMPOUND,
    extra_modulus_strength: float = 0.0,
    t_end_s: float = 0.08,
    window_s: float = 0.03,
) -> dict[str, float]:
    """Stick-slip limit cycle of the G3 element with the one rubber.

    Parameters
    ----------
    k4_s_per_m : float
        Zero-crossing steepness k4 of Eq. 5.24, s/m.
    compound : Compound
        The rubber.
    extra_modulus_strength : float
        Strength s of an additional frequency stiffening on top of the compound's own,
        E(f) = E_compound(f) (1 + s alpha log10(f / f0)) (the discrepancy candidate
        ``frequency_dependent_modulus``,
        :func:`friction_model.dynamics.element_step.modulus_ratio`).
    t_end_s, window_s : float
        Simulated time and the final window analysed, s.

    Returns
    -------
    dict
        ``frequency_Hz`` (limit cycle, zero crossings; 0 if steady sliding is stable),
        ``amplitude_mm``, ``mean_deflection_mm``, ``linear_mode_Hz`` (fixed point of the
        loaded first mode), ``E_Pa``, ``kelvin_voigt_s``, ``normal_force_N``.
    """
    base = _element(compound)
    N = _PRESSURE_PA * base.area_m2
    s_extra = float(extra_modulus_strength)

    def modulus(f: float) -> float:
        extra = float(modulus_ratio(f, strength=s_extra)) if s_extra > 0 else 1.0
        return float(compound.storage_modulus_Pa(f)) * extra

    f = loaded_mode_at_own_modulus_Hz(base, N, modulus)
    E = modulus(f)
    k_i = compound.kelvin_voigt_s(f)
    p = replace(base, E_Pa=E, kelvin_voigt_s=k_i)
    _, d = limit_cycle_run(p, table_4_6_eq_5_24(float(k4_s_per_m)), N, _V0_MPS, t_end_s,
                           window_s)
    t, x = d["time_s"].to_numpy(), d["tip_deflection_mm"].to_numpy()
    xc = x - x.mean()
    i = np.flatnonzero((xc[:-1] < 0) & (xc[1:] >= 0))
    oscillating = i.size > 2 and np.ptp(x) > 1e-3
    freq = (i.size - 1) / (t[i[-1]] - t[i[0]]) if oscillating else 0.0
    return {
        "frequency_Hz": float(freq),
        "amplitude_mm": 0.5 * float(np.ptp(x)),
        "mean_deflection_mm": float(x.mean()),
        "linear_mode_Hz": f,
        "E_Pa": E,
        "kelvin_voigt_s": k_i,
        "normal_force_N": N,
    }
