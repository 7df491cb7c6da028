"""Steady runs: ``mu(t)`` and the average friction coefficient by both methods (section 4.2.4).

Method 1 is the time average of ``mu(t) = F_F / F_N`` over the constant-velocity window
(:mod:`.plateaus`), method 2 the mean friction force over the mean normal force.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from friction_model.rig._io import RigRun
from friction_model.rig.params import WindowParams
from friction_model.rig.plateaus import _no_plateau_detail, _search_plateau
from friction_model.rig.results import SteadyRunResult
from friction_model.rig.signals import (
    _mu_trace,
    _run_mean,
    _signals,
    _time_mean,
)

__all__ = ["evaluate_steady_run", "friction_coefficient", "mean_friction_coefficients"]

logger = logging.getLogger(__name__)


def friction_coefficient(friction_force_N: np.ndarray, normal_force_N: np.ndarray) -> np.ndarray:
    """Time-resolved friction coefficient ``mu(t) = F_F(t) / F_N(t)``.

    Parameters
    ----------
    friction_force_N : (N,) array_like of float
        Friction force F_F (N).
    normal_force_N : (N,) array_like of float
        Normal force F_N (N), > 0.

    Returns
    -------
    (N,) ndarray of float
        ``mu(t)`` (dimensionless).
    """
    ff, fn = _signals(friction_force_N=friction_force_N, normal_force_N=normal_force_N)
    return ff / fn


def mean_friction_coefficients(
    time_s: np.ndarray, friction_force_N: np.ndarray, normal_force_N: np.ndarray
) -> tuple[float, float]:
    """Average friction coefficient by both methods of thesis section 4.2.4.

    Parameters
    ----------
    time_s : (N,) array_like of float
        Sample times of the evaluated window (s), strictly increasing.
    friction_force_N, normal_force_N : (N,) array_like of float
        Friction and normal force (N), ``normal_force_N > 0``.

    Returns
    -------
    method1 : float
        ``1/T * integral(F_F / F_N dt)``, the time average of ``mu(t)``.
    method2 : float
        ``integral(F_F dt) / integral(F_N dt)``, mean friction over mean normal force.

    Notes
    -----
    Time averages use the trapezoidal rule; for uniform sampling this is the arithmetic mean
    of the thesis with the two end samples weighted by one half.
    """
    t, ff, fn = _signals(
        time_s=time_s, friction_force_N=friction_force_N, normal_force_N=normal_force_N
    )
    if t.shape[0] == 0:
        raise ValueError("need at least one sample")
    method1 = _time_mean(t, ff / fn)
    method2 = _time_mean(t, ff) / _time_mean(t, fn)
    return method1, method2


def _check_loaded(run: RigRun, start: int, stop: int, what: str) -> None:
    """Raise the run's error at the first sample in ``[start, stop)`` with ``F_N <= 0``."""
    fn = run.normal_force_N[start:stop]
    bad = np.flatnonzero(fn <= 0.0)
    if bad.size:
        i = start + int(bad[0])
        got = float(fn[bad[0]])
        raise run.error(
            f"column 'normal_force_N', {run.where(i)}: expected a normal force > 0 N inside "
            f"the {what} ({run.where(start)} to {run.where(stop - 1)}), got {got!r} N",
            column="normal_force_N",
            index=i,
        )


def _check_signs(run: RigRun, start: int, stop: int) -> None:
    """Raise the run's error when the window's mean velocity or friction force is not
    positive: the format's convention (velocity positive in the sliding direction, friction
    positive against the motion), which a rig logging the other way breaks (mu < 0). The
    advice follows the signs found: both negative, both columns flipped; one, that one;
    a velocity of 0, no motion."""
    means = {col: float(np.mean(getattr(run, col)[start:stop]))
             for col in ("velocity_mps", "friction_force_N")}
    bad = [col for col, mean in means.items() if not mean > 0.0]
    if not bad:
        return
    col = bad[0]
    if means["velocity_mps"] == 0.0:
        advice = "the carriage does not move in it"
    elif len(bad) == 2:
        advice = "flip the signs of velocity_mps and friction_force_N"
    else:
        advice = f"flip the sign of {col}"
    unit = "m/s" if col == "velocity_mps" else "N"
    raise run.error(
        f"column {col!r}: mean {means[col]:.4g} {unit} in the constant-velocity window "
        f"({run.where(start)} to {run.where(stop - 1)}); the sign convention is velocity "
        "positive in the sliding direction and friction force positive against the motion: "
        + advice,
        column=col,
        index=start,
    )


def evaluate_steady_run(run: RigRun, *, window: WindowParams | None = None) -> SteadyRunResult:
    """Evaluate one steady run: constant-velocity window and both average coefficients.

    Parameters
    ----------
    run : RigRun
        The run, e.g. from :func:`read_run`.
    window : WindowParams, optional
        Window detection parameters; defaults of :class:`WindowParams` when omitted.

    Returns
    -------
    SteadyRunResult
        Window, ``mu`` by both methods, ``mu(t)`` scatter, mean forces, ambient means.

    Raises
    ------
    RunFormatError
        When no constant-velocity phase is found, the normal force is ``<= 0`` inside the
        window, or the window's mean velocity or friction force is not positive (the sign
        convention); the message names file, column and row.
    """
    params = window if window is not None else WindowParams()
    t = run.time_s
    search = _search_plateau(t, run.velocity_mps, params)
    if search.window is None:
        index = None if search.candidate is None else search.candidate[0]
        raise run.error(
            _no_plateau_detail(search, params, t, run.where), column="velocity_mps", index=index
        )
    win = search.window
    i0, i1 = win.start, win.stop
    _check_loaded(run, i0, i1, "constant-velocity window")
    _check_signs(run, i0, i1)
    tw = t[i0:i1]
    ff = run.friction_force_N[i0:i1]
    fn = run.normal_force_N[i0:i1]
    mu_t = ff / fn
    method1 = _time_mean(tw, mu_t)
    mean_ff = _time_mean(tw, ff)
    mean_fn = _time_mean(tw, fn)
    area = run.metadata.get("nominal_area_mm2")
    result = SteadyRunResult(
        file=str(run.path),
        specimen=run.specimen,
        condition=run.condition,
        run=run.run_number,
        window=win,
        velocity_mps=_time_mean(tw, run.velocity_mps[i0:i1]),
        mu_mean_method1=method1,
        mu_mean_method2=mean_ff / mean_fn,
        mu_std_t=float(np.std(mu_t, ddof=1)),
        normal_force_N=mean_fn,
        friction_force_N=mean_ff,
        normal_pressure_Pa=mean_fn / (area * 1e-6) if area else math.nan,
        temperature_C=_run_mean(run.temperature_C),
        humidity_pct=_run_mean(run.humidity_pct),
        metadata=dict(run.metadata),
        trace=_mu_trace(run, mean_fn),
    )
    logger.debug(
        "%s: window %.4f-%.4f s at %.4g m/s, mu %.5f / %.5f",
        run.path,
        win.start_s,
        win.end_s,
        result.velocity_mps,
        result.mu_mean_method1,
        result.mu_mean_method2,
    )
    return result
