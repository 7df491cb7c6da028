"""Measured values of the thesis that the models are fitted to or checked against.

:data:`TABLE_4_6` holds the four G3 friction characteristics of Table 4.6 (section 4.4);
:func:`table_4_6_targets` samples them. They are data, used by the calibration
(:mod:`friction_model.identification.table_4_6`) and by the stick-slip prediction
(:mod:`friction_model.dynamics.stick_slip`), so they live below both.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

__all__ = ["TABLE_4_6", "table_4_6_targets"]

#: Table 4.6: (curve name, temperature_C, humidity_pct, pressure_bar, law, A, B).
TABLE_4_6: tuple[tuple[str, float, float, float, str, float, float], ...] = (
    ("cold-dry 2.5 bar", -5.0, 40.0, 2.5, "decreasing", 0.2, 0.095),
    ("cold-dry 5 bar", -5.0, 40.0, 5.0, "decreasing", 0.125, 0.05),
    ("warm-humid 2.5 bar", -1.0, 95.0, 2.5, "increasing", 0.03, 0.075),
    ("warm-humid 5 bar", -1.0, 95.0, 5.0, "increasing", 0.02, 0.04),
)


def table_4_6_targets(velocities_mps: Sequence[float] | None = None) -> pd.DataFrame:
    """The four Table 4.6 characteristics sampled at ``velocities_mps``.

    Parameters
    ----------
    velocities_mps : sequence of float, optional
        Sliding velocities, m/s; 1, 2, ..., 7 by default (the measured range).

    Returns
    -------
    pandas.DataFrame
        ``curve, velocity_mps, pressure_bar, pressure_Pa, temperature_C, humidity_pct,
        mu_target``.

    Raises
    ------
    ValueError
        A velocity that is not finite and > 0 (the laws diverge at standstill).

    Examples
    --------
    >>> t = table_4_6_targets([1.0])
    >>> [round(x, 3) for x in t["mu_target"]]
    [0.295, 0.175, 0.105, 0.06]
    """
    v = np.asarray(velocities_mps if velocities_mps is not None else np.arange(1.0, 8.0), float)
    if v.ndim != 1 or not np.all(np.isfinite(v)) or np.any(v <= 0):
        # the laws A v^(+-1/2) + B hold for sliding (helper-12: 0 m/s gave mu inf)
        raise ValueError(f"velocities_mps must be a sequence of finite velocities > 0 m/s, "
                         f"got {velocities_mps!r}")
    rows = []
    for name, T, rh, p_bar, law, A, B in TABLE_4_6:
        mu = A * v**-0.5 + B if law == "decreasing" else A * v**0.5 + B
        for vi, mi in zip(v, mu, strict=True):
            rows.append(
                {
                    "curve": name,
                    "velocity_mps": float(vi),
                    "pressure_bar": p_bar,
                    "pressure_Pa": p_bar * 1e5,
                    "temperature_C": T,
                    "humidity_pct": rh,
                    "mu_target": float(mi),
                }
            )
    return pd.DataFrame(rows)
