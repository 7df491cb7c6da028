"""Finding the constant-velocity phase of a steady run (thesis section 4.2.4).

The velocity is smoothed and differentiated (:mod:`.signals`); the samples that move with a
small acceleration form boolean masks, whose short interruptions are closed
(:func:`_close_gaps`, a morphological closing) and whose contiguous spans are found
(:func:`_true_runs`). :func:`find_constant_velocity_window`
returns the evaluated window; :func:`_search_plateau` also says what it found when there is
no window, for the error message.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from friction_model.rig.params import WindowParams
from friction_model.rig.results import VelocityWindow
from friction_model.rig.signals import (
    _half_width,
    _lag_derivative,
    _moving_average,
    _signals,
)

__all__ = ["find_constant_velocity_window"]


def _true_runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Starts and stops (exclusive) of the contiguous True runs of a boolean array.

    From the edges of the mask (``np.diff``): :func:`scipy.ndimage.label` with
    :func:`scipy.ndimage.find_objects` gives the same spans but took 1.7 ms instead of 0.3 ms
    on a 180 000-sample run, and far longer on masks with many short runs.
    """
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)


def _close_gaps(mask: np.ndarray, max_gap: int) -> np.ndarray:
    """Set False runs of at most ``max_gap`` samples with True on both sides to True.

    This is the morphological closing with a flat element of ``max_gap + 1`` samples on a
    mask padded with False, done on the few gaps themselves: the closing by
    :func:`scipy.ndimage.grey_closing` gives the same mask (the tests compare both with a
    naive loop) but took three times as long on a 180 000-sample run.
    """
    starts, stops = _true_runs(~mask)
    inner = (starts > 0) & (stops < mask.shape[0]) & (stops - starts <= max_gap)
    if not inner.any():
        return mask
    delta = np.zeros(mask.shape[0] + 1, dtype=np.int64)
    np.add.at(delta, starts[inner], 1)
    np.add.at(delta, stops[inner], -1)
    return mask | (np.cumsum(delta[:-1]) > 0)


@dataclass(frozen=True)
class _PlateauSearch:
    window: VelocityWindow | None
    candidate: tuple[int, int] | None  # longest band span before trimming, [start, stop)
    velocity_mps: float
    tolerance_mps: float


def _search_plateau(
    time_s: np.ndarray, velocity_mps: np.ndarray, p: WindowParams
) -> _PlateauSearch:
    half = _half_width(time_s, p.smoothing_s)
    v_s = _moving_average(velocity_mps, half)
    a_s = _lag_derivative(v_s, time_s, half)
    # noise spikes shorter than the filter must not split a plateau
    max_gap = 2 * half + 1
    quiet = np.abs(a_s) <= p.max_accel_mps2
    starts, stops = _true_runs(_close_gaps(quiet & (np.abs(v_s) >= p.min_velocity_mps), max_gap))
    if starts.size == 0:
        return _PlateauSearch(None, None, math.nan, math.nan)
    k = int(np.argmax(stops - starts))
    s0, e0 = int(starts[k]), int(stops[k])
    v_plateau = float(np.median(v_s[s0:e0]))
    tol = max(p.rel_tol * abs(v_plateau), p.abs_tol_mps)
    band = _close_gaps(quiet & (np.abs(v_s - v_plateau) <= tol), max_gap)
    b_starts, b_stops = _true_runs(band)
    if b_starts.size == 0:
        return _PlateauSearch(None, None, v_plateau, tol)
    overlap = np.minimum(b_stops, e0) - np.maximum(b_starts, s0)
    j = int(np.argmax(overlap))
    bs, be = int(b_starts[j]), int(b_stops[j])
    i0 = int(np.searchsorted(time_s, time_s[bs] + p.settle_s, side="left"))
    i1 = int(np.searchsorted(time_s, time_s[be - 1] - p.settle_s, side="right"))
    window = None
    if i1 - i0 >= 2 and time_s[i1 - 1] - time_s[i0] >= p.min_duration_s:
        window = VelocityWindow(
            start=i0,
            stop=i1,
            start_s=float(time_s[i0]),
            end_s=float(time_s[i1 - 1]),
            velocity_mps=v_plateau,
            tolerance_mps=tol,
        )
    return _PlateauSearch(window, (bs, be), v_plateau, tol)


def find_constant_velocity_window(
    time_s: np.ndarray,
    velocity_mps: np.ndarray,
    *,
    smoothing_s: float = 0.02,
    rel_tol: float = 0.02,
    abs_tol_mps: float = 0.01,
    max_accel_mps2: float = 0.5,
    settle_s: float = 0.05,
    min_velocity_mps: float = 0.02,
    min_duration_s: float = 0.05,
) -> VelocityWindow:
    """Find the phase of constant sliding velocity of a run.

    The velocity is smoothed with a centred moving average of length ``smoothing_s`` and
    differentiated over the same length. The plateau velocity ``v_p`` is the median smoothed
    velocity of the longest contiguous span that moves (``|v| >= min_velocity_mps``) with a
    small acceleration (``|a| <= max_accel_mps2``). The plateau is the longest contiguous
    span, overlapping that one, where ``|v - v_p| <= max(rel_tol * |v_p|, abs_tol_mps)`` and
    ``|a| <= max_accel_mps2``; ``settle_s`` is trimmed from both of its ends. Interruptions
    no longer than the filter (noise spikes) do not split a span.

    Parameters
    ----------
    time_s : (N,) array_like of float
        Sample times (s), strictly increasing, about uniformly spaced.
    velocity_mps : (N,) array_like of float
        Sliding velocity (m/s).
    smoothing_s : float
        Length of the moving average and of the differentiation baseline (s).
    rel_tol : float
        Velocity tolerance relative to the plateau velocity (0.02 is 2 %).
    abs_tol_mps : float
        Absolute floor of the velocity tolerance (m/s), for slow plateaus.
    max_accel_mps2 : float
        Largest smoothed acceleration magnitude counted as constant velocity (m/s^2).
    settle_s : float
        Settling margin removed at each end of the plateau (s).
    min_velocity_mps : float
        Slower samples are standstill and never form a plateau (m/s).
    min_duration_s : float
        Shortest accepted window after trimming (s).

    Returns
    -------
    VelocityWindow
        Sample slice, times and plateau velocity of the window.

    Raises
    ------
    ValueError
        When no constant-velocity phase of at least ``min_duration_s`` exists, or for bad
        parameters or arrays.
    """
    t, v = _signals(time_s=time_s, velocity_mps=velocity_mps, at_least=2)
    params = WindowParams(
        smoothing_s=smoothing_s,
        rel_tol=rel_tol,
        abs_tol_mps=abs_tol_mps,
        max_accel_mps2=max_accel_mps2,
        settle_s=settle_s,
        min_velocity_mps=min_velocity_mps,
        min_duration_s=min_duration_s,
    )
    search = _search_plateau(t, v, params)
    if search.window is None:
        raise ValueError(_no_plateau_detail(search, params, t, lambda i: f"sample {i}"))
    return search.window


def _no_plateau_detail(
    search: _PlateauSearch, p: WindowParams, t: np.ndarray, where: Callable[[int], str]
) -> str:
    head = "column 'velocity_mps': no constant-velocity phase found"
    if search.candidate is None:
        return (
            f"{head} in {where(0)} to {where(t.shape[0] - 1)}: expected a span moving at "
            f">= {p.min_velocity_mps} m/s with |acceleration| <= {p.max_accel_mps2} m/s^2 "
            "(smoothed)"
        )
    s, e = search.candidate
    return (
        f"{head}: the longest span within +-{search.tolerance_mps:.4g} m/s of "
        f"{search.velocity_mps:.4g} m/s is {where(s)} to {where(e - 1)} "
        f"({t[e - 1] - t[s]:.4g} s); expected at least min_duration_s={p.min_duration_s} s "
        f"after trimming settle_s={p.settle_s} s at each end"
    )
