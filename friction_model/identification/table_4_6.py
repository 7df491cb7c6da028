"""Calibration of one shared parameter set of the dry/wet model on Table 4.6 of the thesis.

Table 4.6 gives the fitted measured characteristics of the three-sipe block G3 for
1 <= v <= 7 m/s (Eq. 4.8 and Eq. 4.9)::

    T = -5 degC, rH < 50 %:  mu = 0.2   v^-0.5 + 0.095  (2.5 bar)
                             mu = 0.125 v^-0.5 + 0.05   (5 bar)
    T = -1 degC, rH > 90 %:  mu = 0.03  v^0.5  + 0.075  (2.5 bar)
                             mu = 0.02  v^0.5  + 0.04   (5 bar)

Only temperature, humidity and pressure differ between the four curves; every model
parameter is shared. The humidity of the curves is given as a bound only; we take 40 % for
"rH < 50 %" and 95 % for "rH > 90 %".
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from friction_model.contact.drywet import DryWetParameters, friction_table
from friction_model.geometry import BlockGeometry, reference_block
from friction_model.thesis_data import TABLE_4_6, table_4_6_targets

logger = logging.getLogger(__name__)

__all__ = [
    "CALIBRATED_PARAMETERS",
    "TABLE_4_6",
    "CalibrationResult",
    "calibrate_table_4_6",
    "evaluate_on_table_4_6",
    "table_4_6_targets",
]

#: Parameters fitted by :func:`calibrate_table_4_6` with their (lower, upper) bounds.
CALIBRATED_PARAMETERS: dict[str, tuple[float, float]] = {
    "boundary_shear_Pa": (1e3, 2e5),
    "critical_film_m": (1e-8, 3e-6),
    "contact_fraction_ref": (0.05, 1.0),
    "contact_pressure_exponent": (0.0, 1.0),
}


@dataclass(frozen=True)
class CalibrationResult:
    """Outcome of :func:`calibrate_table_4_6`.

    Attributes
    ----------
    params : DryWetParameters
        The calibrated, shared parameter set.
    table : pandas.DataFrame
        Targets and model values per point (``mu_target``, ``mu_model``, ``residual``).
    rmse : dict
        RMSE of mu per curve and ``"all"``.
    cost_evaluations : int
        Number of model evaluations used.
    """

    params: DryWetParameters
    table: pd.DataFrame
    rmse: dict[str, float]
    cost_evaluations: int

    def summary(self) -> str:
        """Human-readable report of the fitted parameters and the RMSE per curve."""
        lines = ["Calibrated dry/wet model on Table 4.6 (G3, v = 1..7 m/s):"]
        for name in CALIBRATED_PARAMETERS:
            lines.append(f"  {name:28s} = {getattr(self.params, name):.4g}")
        lines.append("RMSE of mu per curve:")
        for name, value in self.rmse.items():
            lines.append(f"  {name:28s}   {value:.4f}")
        return "\n".join(lines)


def evaluate_on_table_4_6(
    params: DryWetParameters,
    *,
    geometry: BlockGeometry | None = None,
    velocities_mps: Sequence[float] | None = None,
) -> tuple[pd.DataFrame, dict[str, float]]:
    """Model values and RMSE per curve of a parameter set on the Table 4.6 targets."""
    geometry = geometry or reference_block("G3")
    targets = table_4_6_targets(velocities_mps)
    model = friction_table(geometry, targets, params)
    table = targets.assign(mu_model=model["mu"].to_numpy(), regime=model["regime"].to_numpy())
    table["residual"] = table["mu_model"] - table["mu_target"]
    rmse = {
        name: float(np.sqrt(np.mean(g["residual"] ** 2)))
        for name, g in table.groupby("curve", sort=False)
    }
    rmse["all"] = float(np.sqrt(np.mean(table["residual"] ** 2)))
    return table, rmse


def _to_unit(name: str, value: float) -> float:
    lo, hi = CALIBRATED_PARAMETERS[name]
    if lo > 0:
        return (np.log(value) - np.log(lo)) / (np.log(hi) - np.log(lo))
    return (value - lo) / (hi - lo)


def _from_unit(name: str, u: float) -> float:
    lo, hi = CALIBRATED_PARAMETERS[name]
    if lo > 0:
        return float(np.exp(np.log(lo) + u * (np.log(hi) - np.log(lo))))
    return float(lo + u * (hi - lo))


def calibrate_table_4_6(
    *,
    start: DryWetParameters | None = None,
    n_starts: int = 4,
    rng: int | np.random.Generator | None = 0,
    geometry: BlockGeometry | None = None,
    max_nfev: int = 400,
) -> CalibrationResult:
    """Fit one shared parameter set of the dry/wet model to the four Table 4.6 curves.

    The parameters in :data:`CALIBRATED_PARAMETERS` are fitted (bounded least squares on
    mu at v = 1..7 m/s, log-scaled where positive); ``mu_dry = 1.5`` stays at the thesis
    value and the heat fraction stays at the thesis's K = 1 (fitted within [0.6, 1] it
    ends on 1). The bound water layer (``qll_thickness_m``, ``humidity_gain``) is not
    fitted: Table 4.6 varies humidity only together with temperature, so it cannot
    separate the two (a free fit drives the layer to zero).
    Several starts: the given/default set plus random ones.

    Parameters
    ----------
    start : DryWetParameters, optional
        Starting point and source of the fixed parameters (defaults when omitted).
    n_starts : int, optional
        Number of starts (the first is ``start``).
    rng : int or numpy.random.Generator or None, optional
        Seed for the random starts.
    geometry : BlockGeometry, optional
        Block of the measurements; G3 by default.
    max_nfev : int, optional
        Maximum model evaluations per start.

    Returns
    -------
    CalibrationResult
    """
    start = start or DryWetParameters()
    geometry = geometry or reference_block("G3")
    gen = np.random.default_rng(rng)
    names = list(CALIBRATED_PARAMETERS)
    targets = table_4_6_targets()
    y = targets["mu_target"].to_numpy()
    n_eval = 0

    def params_of(u: np.ndarray) -> DryWetParameters:
        return start.with_(**{n: _from_unit(n, ui) for n, ui in zip(names, u, strict=True)})

    def residuals(u: np.ndarray) -> np.ndarray:
        nonlocal n_eval
        n_eval += 1
        model = friction_table(geometry, targets, params_of(u))
        return model["mu"].to_numpy() - y

    u0 = np.array([np.clip(_to_unit(n, getattr(start, n)), 0.0, 1.0) for n in names])
    starts = [u0] + [gen.uniform(0.05, 0.95, len(names)) for _ in range(max(n_starts - 1, 0))]
    best = None
    for i, u in enumerate(starts):
        sol = least_squares(
            residuals, u, bounds=(0.0, 1.0), x_scale=0.1, diff_step=1e-3, max_nfev=max_nfev
        )
        logger.info("start %d: cost %.3g", i, sol.cost)
        if best is None or sol.cost < best.cost:
            best = sol
    params = params_of(best.x)
    table, rmse = evaluate_on_table_4_6(params, geometry=geometry)
    return CalibrationResult(params=params, table=table, rmse=rmse, cost_evaluations=n_eval)
