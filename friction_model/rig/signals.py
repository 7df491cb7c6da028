"""Signal helpers of the rig evaluation: smoothing, differentiation, time means, traces.

All helpers work on 1-D float arrays of one run sampled at about uniform times ``time_s``.
The moving average shrinks at both ends to the samples that exist (no padding).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.integrate import trapezoid

from friction_model.rig._io import RigRun

__all__: list[str] = []

_TRACE_POINTS = 4000


def _moving_average(x: np.ndarray, half: int) -> np.ndarray:
    """Centred moving average over ``2 * half + 1`` samples, shrinking at the ends.

    Sample ``i`` is the mean of ``x[max(i - half, 0) : min(i + half + 1, n)]``, from one
    cumulative sum of ``x`` less its mean. :func:`scipy.ndimage.uniform_filter1d` (with zero
    padding and the count corrected at the ends) gives the same means to about 1e-13 but
    rounds differently; on noise-free synthetic ramps that moves samples lying exactly on a
    velocity-bin edge into the other bin, so the cumulative sum is kept for identical results.
    """
    n = x.shape[0]
    if half <= 0 or n == 0:
        return np.array(x, dtype=float)
    offset = float(np.mean(x))
    c = np.empty(n + 1)
    c[0] = 0.0
    np.cumsum(x - offset, out=c[1:])
    idx = np.arange(n)
    lo = np.maximum(idx - half, 0)
    hi = np.minimum(idx + half + 1, n)
    return (c[hi] - c[lo]) / (hi - lo) + offset


def _lag_derivative(y: np.ndarray, t: np.ndarray, lag: int) -> np.ndarray:
    """Central difference ``(y[i+lag] - y[i-lag]) / (t[i+lag] - t[i-lag])``, clipped at ends."""
    n = y.shape[0]
    idx = np.arange(n)
    lo = np.maximum(idx - lag, 0)
    hi = np.minimum(idx + lag, n - 1)
    return (y[hi] - y[lo]) / (t[hi] - t[lo])


def _half_width(time_s: np.ndarray, smoothing_s: float) -> int:
    """Half width in samples of a moving average of length ``smoothing_s``."""
    dt = float(np.median(np.diff(time_s)))
    return max(1, round(smoothing_s / (2.0 * dt)))


def _time_mean(time_s: np.ndarray, values: np.ndarray) -> float:
    """Time average ``1/T * integral(values dt)`` by the trapezoidal rule."""
    if values.shape[0] < 2:
        return float(values[0])
    return float(trapezoid(values, time_s) / (time_s[-1] - time_s[0]))


def _as_1d(name: str, values: Any) -> np.ndarray:
    """``values`` as a 1-D float array, else ValueError naming ``name``."""
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {arr.shape}")
    return arr


def _signals(*, at_least: int = 0, **values: Any) -> tuple[np.ndarray, ...]:
    """The named signals as 1-D float arrays of one length (at least `at_least` samples),
    else ValueError naming them."""
    arrays = {name: _as_1d(name, v) for name, v in values.items()}
    lengths = {name: a.shape[0] for name, a in arrays.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"arrays must have equal lengths, got {lengths}")
    n = next(iter(lengths.values()), 0)
    if n < at_least:
        raise ValueError(f"need at least {at_least} samples, got {n}")
    return tuple(arrays.values())


def _decimate(n: int) -> slice:
    """A step slice keeping at most about ``_TRACE_POINTS`` of ``n`` samples, for plots."""
    return slice(None, None, max(1, math.ceil(n / _TRACE_POINTS)))


def _run_mean(values: np.ndarray | None) -> float:
    """Mean over the whole run, NaN for a signal that was not recorded."""
    return math.nan if values is None else float(np.mean(values))


def _mu_trace(run: RigRun, reference_N: float) -> dict[str, np.ndarray]:
    """Decimated ``time_s``, ``mu`` (NaN below 5 % of ``reference_N``) and ``velocity_mps``."""
    sl = _decimate(len(run))
    fn = run.normal_force_N[sl]
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(fn > 0.05 * reference_N, run.friction_force_N[sl] / fn, np.nan)
    return {"time_s": run.time_s[sl], "mu": mu, "velocity_mps": run.velocity_mps[sl]}
