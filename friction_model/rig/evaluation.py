"""Evaluation of linear test-rig force measurements: steady and instationary friction.

Implements the evaluation of thesis sections 4.2.4 and 4.4 for raw runs of the linear
friction test rig (CSV format in ``docs/formats.md``):

* steady runs: find the phase of constant sliding velocity, compute ``mu(t) = F_F / F_N``
  and the average friction coefficient by both methods of section 4.2.4 (method 1: time
  average of ``mu(t)``; method 2: mean ``F_F`` over mean ``F_N``); aggregate up to ten
  repeated runs per specimen, condition and velocity (mean and standard deviation); ambient
  averages per specimen as in Table 4.2;
* instationary runs (constant acceleration then constant deceleration, Fig. 4.22): remove the
  inertial force ``m * a`` of carriage and sample, ``mu = (F_F - m a) / F_N``, and bin it over
  the sliding velocity, separately for the accelerating and the decelerating branch;
* batches: many files, one bad file is reported and skipped, tables and plots written
  atomically to an output folder.

Notes
-----
Units are SI throughout: time in s, velocity in m/s, acceleration in m/s^2, force in N,
mass in kg, pressure in Pa; temperature in degC and relative humidity in percent. Time is
the recorder's clock of each run, starting wherever the file starts. Velocity is positive in
the sliding direction.
"""

from __future__ import annotations

import json
import logging
import math
import os
import sys
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from scipy.integrate import trapezoid
from tqdm import tqdm

from friction_model.rig._io import (
    OPTIONAL_COLUMNS,
    REQUIRED_COLUMNS,
    RigRun,
    RunFormatError,
    read_run,
)
from tir_common.atomic import atomic_write
from tir_common.naming import natural_key
from tir_common.validate import check_nonnegative, check_positive

__all__ = [
    "AMBIENT_COLUMNS",
    "INSTATIONARY_COLUMNS",
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "STEADY_COLUMNS",
    "EvaluationFailure",
    "EvaluationResult",
    "InstationaryParams",
    "InstationaryRunResult",
    "RigRun",
    "RunFormatError",
    "SteadyRunResult",
    "VelocityWindow",
    "WindowParams",
    "aggregate_runs",
    "ambient_table",
    "collect_run_files",
    "evaluate_folder",
    "evaluate_instationary_run",
    "evaluate_runs",
    "evaluate_steady_run",
    "find_constant_velocity_window",
    "friction_coefficient",
    "instationary_characteristic",
    "mean_friction_coefficients",
    "read_run",
    "steady_characteristic",
    "write_outputs",
]

logger = logging.getLogger(__name__)

#: Columns of ``steady_characteristic.csv`` (metadata keys of the files follow as ``meta_*``).
STEADY_COLUMNS = (
    "row_type",
    "file",
    "specimen",
    "condition",
    "run",
    "n_runs",
    "velocity_mps",
    "window_start_s",
    "window_end_s",
    "n_samples",
    "mu_mean_method1",
    "mu_mean_method2",
    "method_rel_diff",
    "mu_std_t",
    "mu_std_runs",
    "normal_force_N",
    "friction_force_N",
    "normal_pressure_Pa",
    "temperature_C",
    "humidity_pct",
)
#: Columns of ``ambient.csv``.
AMBIENT_COLUMNS = (
    "specimen",
    "temperature_C",
    "humidity_pct",
    "temperature_std_C",
    "humidity_std_pct",
    "n_runs",
)
#: Columns of the per-run instationary characteristic (:func:`instationary_characteristic`).
INSTATIONARY_COLUMNS = ("velocity_mps", "branch", "mu", "mu_std", "n")
_INSTATIONARY_FILE_COLUMNS = (
    "file",
    "specimen",
    "condition",
    "run",
    "inertial_mass_kg",
    *INSTATIONARY_COLUMNS,
)
_BRANCHES = ("accelerating", "decelerating")
_TRACE_POINTS = 4000


# ---------------------------------------------------------------------------------------------
# parameters and results


def _check_positive(**values: float) -> None:
    for name, value in values.items():
        check_positive(name, value)


def _check_non_negative(**values: float) -> None:
    for name, value in values.items():
        check_nonnegative(name, value)


@dataclass(frozen=True)
class WindowParams:
    """Parameters of the constant-velocity phase detection.

    See :func:`find_constant_velocity_window` for the meaning of every field.

    Attributes
    ----------
    smoothing_s : float
        Length of the moving-average filter on the velocity (s).
    rel_tol : float
        Relative velocity tolerance about the plateau velocity (dimensionless).
    abs_tol_mps : float
        Absolute floor of the velocity tolerance (m/s).
    max_accel_mps2 : float
        Largest magnitude of the smoothed acceleration inside the plateau (m/s^2).
    settle_s : float
        Settling margin trimmed at both ends of the plateau (s).
    min_velocity_mps : float
        Smallest plateau speed; slower samples count as standstill (m/s).
    min_duration_s : float
        Shortest accepted window after trimming (s).
    """

    smoothing_s: float = 0.02
    rel_tol: float = 0.02
    abs_tol_mps: float = 0.01
    max_accel_mps2: float = 0.5
    settle_s: float = 0.05
    min_velocity_mps: float = 0.02
    min_duration_s: float = 0.05

    def __post_init__(self) -> None:
        _check_positive(
            smoothing_s=self.smoothing_s,
            abs_tol_mps=self.abs_tol_mps,
            max_accel_mps2=self.max_accel_mps2,
            min_velocity_mps=self.min_velocity_mps,
            min_duration_s=self.min_duration_s,
        )
        _check_non_negative(rel_tol=self.rel_tol, settle_s=self.settle_s)


@dataclass(frozen=True)
class InstationaryParams:
    """Parameters of the instationary evaluation (see :func:`instationary_characteristic`).

    Attributes
    ----------
    bin_width_mps : float
        Width of the velocity bins (m/s).
    smoothing_s : float
        Length of the moving-average filter applied to velocity and forces (s).
    min_velocity_mps : float
        Samples slower than this, and those whose filter window reaches such samples, are
        not evaluated (m/s).
    min_accel_mps2 : float
        Samples with a smoothed acceleration magnitude below this belong to no branch (m/s^2).
    min_samples : int
        Bins with fewer samples are dropped.
    """

    bin_width_mps: float = 0.25
    smoothing_s: float = 0.01
    min_velocity_mps: float = 0.05
    min_accel_mps2: float = 0.2
    min_samples: int = 20

    def __post_init__(self) -> None:
        _check_positive(
            bin_width_mps=self.bin_width_mps,
            smoothing_s=self.smoothing_s,
            min_velocity_mps=self.min_velocity_mps,
            min_accel_mps2=self.min_accel_mps2,
        )
        if not (isinstance(self.min_samples, int) and self.min_samples >= 1):
            raise ValueError(
                f"min_samples must be an int >= 1, got min_samples={self.min_samples!r}"
            )


@dataclass(frozen=True)
class VelocityWindow:
    """The evaluated constant-velocity window of a run.

    Attributes
    ----------
    start, stop : int
        Sample slice ``[start, stop)`` (0-based indices).
    start_s, end_s : float
        Time of the first and of the last sample in the window (s).
    velocity_mps : float
        Plateau velocity, the median smoothed velocity of the plateau (m/s).
    tolerance_mps : float
        Velocity tolerance used about ``velocity_mps`` (m/s).
    """

    start: int
    stop: int
    start_s: float
    end_s: float
    velocity_mps: float
    tolerance_mps: float

    @property
    def duration_s(self) -> float:
        """Window length ``end_s - start_s`` (s)."""
        return self.end_s - self.start_s


@dataclass(frozen=True, eq=False)
class SteadyRunResult:
    """Evaluation of one steady run (one row of ``steady_characteristic.csv``).

    Attributes
    ----------
    file : str
        Source file.
    specimen, condition : str
        Metadata keys ``specimen`` and ``condition`` (empty when absent).
    run : int or None
        Metadata key ``run``.
    window : VelocityWindow
        Evaluated constant-velocity window.
    velocity_mps : float
        Time-averaged measured velocity in the window (m/s).
    mu_mean_method1 : float
        Time average of ``mu(t) = F_F(t) / F_N(t)`` over the window (method 1 of 4.2.4).
    mu_mean_method2 : float
        Time-averaged ``F_F`` over time-averaged ``F_N`` in the window (method 2 of 4.2.4).
    mu_std_t : float
        Sample standard deviation of ``mu(t)`` in the window (dimensionless).
    normal_force_N, friction_force_N : float
        Time-averaged forces in the window (N).
    normal_pressure_Pa : float
        ``normal_force_N`` over the metadata ``nominal_area_mm2`` (Pa), NaN without area.
    temperature_C, humidity_pct : float
        Mean over the whole recording (degC, %), NaN when not recorded.
    metadata : dict
        Metadata of the file.
    trace : dict
        Decimated ``time_s``, ``mu`` (NaN where the sample is unloaded) and ``velocity_mps``
        arrays of the whole run, for plotting.
    """

    file: str
    specimen: str
    condition: str
    run: int | None
    window: VelocityWindow
    velocity_mps: float
    mu_mean_method1: float
    mu_mean_method2: float
    mu_std_t: float
    normal_force_N: float
    friction_force_N: float
    normal_pressure_Pa: float
    temperature_C: float
    humidity_pct: float
    metadata: dict[str, Any] = field(default_factory=dict)
    trace: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    def as_row(self) -> dict[str, Any]:
        """The run row of ``steady_characteristic.csv`` as a dict."""
        m1, m2 = self.mu_mean_method1, self.mu_mean_method2
        row = {
            "row_type": "run",
            "file": self.file,
            "specimen": self.specimen,
            "condition": self.condition,
            "run": self.run,
            "n_runs": 1,
            "velocity_mps": self.velocity_mps,
            "window_start_s": self.window.start_s,
            "window_end_s": self.window.end_s,
            "n_samples": self.window.stop - self.window.start,
            "mu_mean_method1": m1,
            "mu_mean_method2": m2,
            "method_rel_diff": abs(m1 - m2) / abs(m2) if m2 != 0 else math.nan,
            "mu_std_t": self.mu_std_t,
            "mu_std_runs": math.nan,
            "normal_force_N": self.normal_force_N,
            "friction_force_N": self.friction_force_N,
            "normal_pressure_Pa": self.normal_pressure_Pa,
            "temperature_C": self.temperature_C,
            "humidity_pct": self.humidity_pct,
        }
        for key, value in self.metadata.items():
            if key not in ("specimen", "condition", "run"):
                row[f"meta_{key}"] = value
        return row


@dataclass(frozen=True, eq=False)
class InstationaryRunResult:
    """Evaluation of one instationary run.

    Attributes
    ----------
    file, specimen, condition, run
        Source file and metadata, as in :class:`SteadyRunResult`.
    inertial_mass_kg : float
        Mass whose inertial force ``m * a`` was removed (kg).
    table : pandas.DataFrame
        Columns :data:`INSTATIONARY_COLUMNS`, see :func:`instationary_characteristic`.
    temperature_C, humidity_pct : float
        Mean over the whole recording (degC, %), NaN when not recorded.
    metadata : dict
        Metadata of the file.
    trace : dict
        Decimated ``time_s``, ``mu`` (raw ``F_F / F_N``), ``mu_corrected`` (inertia removed,
        smoothed) and ``velocity_mps`` arrays, and the ``accelerating`` / ``decelerating``
        time spans (s), for plotting.
    """

    file: str
    specimen: str
    condition: str
    run: int | None
    inertial_mass_kg: float
    table: pd.DataFrame
    temperature_C: float
    humidity_pct: float
    metadata: dict[str, Any] = field(default_factory=dict)
    trace: dict[str, Any] = field(default_factory=dict, repr=False)

    def tidy(self) -> pd.DataFrame:
        """The table with identity columns prepended, as in ``instationary_characteristic.csv``."""
        out = self.table.copy()
        out.insert(0, "inertial_mass_kg", self.inertial_mass_kg)
        out.insert(0, "run", pd.array([self.run] * len(out), dtype="Int64"))
        out.insert(0, "condition", self.condition)
        out.insert(0, "specimen", self.specimen)
        out.insert(0, "file", self.file)
        return out


@dataclass(frozen=True)
class EvaluationFailure:
    """A file that could not be evaluated.

    Attributes
    ----------
    file : str
        The file (or folder) concerned.
    message : str
        Why, naming column and row where they apply.
    """

    file: str
    message: str


@dataclass
class EvaluationResult:
    """Result of a batch evaluation.

    Attributes
    ----------
    steady : pandas.DataFrame
        ``steady_characteristic.csv``: one ``run`` row per steady run, then one
        ``aggregate`` row per specimen, condition and velocity (columns :data:`STEADY_COLUMNS`
        plus ``meta_*``).
    ambient : pandas.DataFrame
        ``ambient.csv``: Table 4.2 style ambient averages (columns :data:`AMBIENT_COLUMNS`).
    instationary : pandas.DataFrame
        ``instationary_characteristic.csv``: the binned characteristic of every instationary
        run; empty when there were none.
    failures : list of EvaluationFailure
        Files that could not be evaluated, in input order.
    steady_runs, instationary_runs : list
        Per-run results (:class:`SteadyRunResult`, :class:`InstationaryRunResult`).
    files : list of pathlib.Path
        Every file that was attempted.
    parameters : dict
        Every evaluation parameter, for the provenance record.
    outputs : dict of str to pathlib.Path
        Files written by :func:`write_outputs` (empty until then).
    """

    steady: pd.DataFrame
    ambient: pd.DataFrame
    instationary: pd.DataFrame
    failures: list[EvaluationFailure]
    steady_runs: list[SteadyRunResult]
    instationary_runs: list[InstationaryRunResult]
    files: list[Path]
    parameters: dict[str, Any] = field(default_factory=dict)
    outputs: dict[str, Path] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """True when every file was evaluated."""
        return not self.failures


# ---------------------------------------------------------------------------------------------
# signal helpers


def _moving_average(x: np.ndarray, half: int) -> np.ndarray:
    """Centred moving average over ``2 * half + 1`` samples, shrinking at the ends."""
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


def _true_runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Starts and stops (exclusive) of the contiguous True runs of a boolean array."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)


def _close_gaps(mask: np.ndarray, max_gap: int) -> np.ndarray:
    """Set False runs of at most ``max_gap`` samples with True on both sides to True."""
    starts, stops = _true_runs(~mask)
    inner = (starts > 0) & (stops < mask.shape[0]) & (stops - starts <= max_gap)
    if not inner.any():
        return mask
    delta = np.zeros(mask.shape[0] + 1, dtype=np.int64)
    np.add.at(delta, starts[inner], 1)
    np.add.at(delta, stops[inner], -1)
    return mask | (np.cumsum(delta[:-1]) > 0)


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
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {arr.shape}")
    return arr


def _check_same_length(**arrays: np.ndarray) -> None:
    lengths = {name: a.shape[0] for name, a in arrays.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"arrays must have equal lengths, got {lengths}")


def _decimate(n: int) -> slice:
    return slice(None, None, max(1, math.ceil(n / _TRACE_POINTS)))


def _run_mean(values: np.ndarray | None) -> float:
    return math.nan if values is None else float(np.mean(values))


# ---------------------------------------------------------------------------------------------
# steady evaluation


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
    t = _as_1d("time_s", time_s)
    v = _as_1d("velocity_mps", velocity_mps)
    _check_same_length(time_s=t, velocity_mps=v)
    if t.shape[0] < 2:
        raise ValueError(f"need at least 2 samples, got {t.shape[0]}")
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
    ff = _as_1d("friction_force_N", friction_force_N)
    fn = _as_1d("normal_force_N", normal_force_N)
    _check_same_length(friction_force_N=ff, normal_force_N=fn)
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
    t = _as_1d("time_s", time_s)
    ff = _as_1d("friction_force_N", friction_force_N)
    fn = _as_1d("normal_force_N", normal_force_N)
    _check_same_length(time_s=t, friction_force_N=ff, normal_force_N=fn)
    if t.shape[0] == 0:
        raise ValueError("need at least one sample")
    method1 = _time_mean(t, ff / fn)
    method2 = _time_mean(t, ff) / _time_mean(t, fn)
    return method1, method2


def _check_loaded(run: RigRun, start: int, stop: int, what: str) -> None:
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


def _mu_trace(run: RigRun, reference_N: float) -> dict[str, np.ndarray]:
    sl = _decimate(len(run))
    fn = run.normal_force_N[sl]
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(fn > 0.05 * reference_N, run.friction_force_N[sl] / fn, np.nan)
    return {"time_s": run.time_s[sl], "mu": mu, "velocity_mps": run.velocity_mps[sl]}


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
        When no constant-velocity phase is found, or the normal force is ``<= 0`` inside the
        window; the message names file, column and row.
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


# ---------------------------------------------------------------------------------------------
# instationary evaluation


@dataclass(frozen=True)
class _Instationary:
    table: pd.DataFrame
    used: np.ndarray  # bool mask of evaluated samples
    branch_masks: dict[str, np.ndarray]
    mu_corrected: np.ndarray


def _instationary(
    t: np.ndarray,
    v: np.ndarray,
    ff: np.ndarray,
    fn: np.ndarray,
    mass: float,
    p: InstationaryParams,
) -> _Instationary:
    half = _half_width(t, p.smoothing_s)

    def smooth(x: np.ndarray) -> np.ndarray:
        return _moving_average(_moving_average(x, half), half)

    # The acceleration (central differences of the velocity) and the forces pass through the
    # same linear filter, so the inertial part of F_F and m*a stay aligned through the kinks
    # of the velocity profile.
    n = t.shape[0]
    v_ss = smooth(v)
    a_ss = smooth(np.gradient(v, t))
    ff_ss = smooth(ff)
    fn_ss = smooth(fn)
    # drop samples whose filter support (4*half + 1 samples) reaches a standstill sample or
    # the end of the record, where the shrinking filter is no longer the same for all signals
    support = 2 * half
    still = np.abs(v_ss) < p.min_velocity_mps
    csum = np.concatenate(([0], np.cumsum(still)))
    idx = np.arange(n)
    lo = np.maximum(idx - support, 0)
    hi = np.minimum(idx + support + 1, n)
    used = (csum[hi] - csum[lo] == 0) & (idx >= support) & (idx < n - support)
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = (ff_ss - mass * a_ss) / fn_ss
    speed_up = a_ss * np.sign(v_ss)
    masks = {
        "accelerating": used & (speed_up >= p.min_accel_mps2),
        "decelerating": used & (speed_up <= -p.min_accel_mps2),
    }
    frames = []
    for branch in _BRANCHES:
        m = masks[branch]
        if not m.any():
            continue
        vb = np.abs(v_ss[m])
        mub = mu[m]
        bins = np.floor(vb / p.bin_width_mps).astype(np.int64)
        count = np.bincount(bins)
        keep = np.flatnonzero(count >= p.min_samples)
        if keep.size == 0:
            continue
        nz = np.maximum(count, 1)
        mean_mu = np.bincount(bins, weights=mub) / nz
        mean_v = np.bincount(bins, weights=vb) / nz
        sq = np.bincount(bins, weights=(mub - mean_mu[bins]) ** 2)
        std_mu = np.sqrt(sq / np.maximum(count - 1, 1))
        frames.append(
            pd.DataFrame(
                {
                    "velocity_mps": mean_v[keep],
                    "branch": branch,
                    "mu": mean_mu[keep],
                    "mu_std": std_mu[keep],
                    "n": count[keep].astype(np.int64),
                }
            )
        )
    if frames:
        table = pd.concat(frames, ignore_index=True)
    else:
        table = pd.DataFrame({c: pd.Series(dtype=float) for c in INSTATIONARY_COLUMNS})
        table["branch"] = table["branch"].astype(object)
        table["n"] = table["n"].astype(np.int64)
    return _Instationary(table, used, masks, mu)


def instationary_characteristic(
    time_s: np.ndarray,
    velocity_mps: np.ndarray,
    friction_force_N: np.ndarray,
    normal_force_N: np.ndarray,
    *,
    inertial_mass_kg: float,
    bin_width_mps: float = 0.25,
    smoothing_s: float = 0.01,
    min_velocity_mps: float = 0.05,
    min_accel_mps2: float = 0.2,
    min_samples: int = 20,
) -> pd.DataFrame:
    """Instationary friction characteristic ``mu(v)`` of a ramp-up / ramp-down run.

    Thesis section 4.4, Fig. 4.22: the carriage accelerates and decelerates at constant
    rates, the velocity is never constant. The inertial force of carriage and sample is
    removed from the friction force, ``mu = (F_F - m a) / F_N``, and ``mu`` is averaged in
    velocity bins, separately while accelerating and while decelerating.

    Parameters
    ----------
    time_s : (N,) array_like of float
        Sample times (s), strictly increasing, about uniformly spaced.
    velocity_mps : (N,) array_like of float
        Sliding velocity (m/s).
    friction_force_N, normal_force_N : (N,) array_like of float
        Friction force including the inertial force, and normal force (N).
    inertial_mass_kg : float
        Mass of carriage and sample seen by the friction force sensor (kg); 0 disables the
        inertia removal.
    bin_width_mps : float
        Width of the velocity bins ``[k w, (k+1) w)`` (m/s).
    smoothing_s : float
        Length of the centred moving average (s), applied twice. Velocity, forces and the
        acceleration ``a`` (central differences of the velocity) all pass this same filter,
        so the inertial part of ``F_F`` and ``m a`` stay aligned through the kinks of the
        velocity profile.
    min_velocity_mps : float
        Samples slower than this, and samples whose filter support reaches one or the end of
        the record, are left out (m/s); this removes standstill and the start and stop
        transients.
    min_accel_mps2 : float
        Samples whose speed grows at ``>= min_accel_mps2`` form the ``accelerating``
        branch, samples whose speed falls at ``>= min_accel_mps2`` the ``decelerating``
        branch (m/s^2).
    min_samples : int
        Bins with fewer samples are dropped.

    Returns
    -------
    pandas.DataFrame
        Columns ``velocity_mps`` (mean sliding speed of the samples in the bin, m/s),
        ``branch`` (``"accelerating"`` or ``"decelerating"``), ``mu`` (mean of the
        inertia-corrected, filtered ``mu`` of the bin), ``mu_std`` (sample standard deviation
        of those values) and ``n`` (number of samples); sorted by branch then velocity.
    """
    t = _as_1d("time_s", time_s)
    v = _as_1d("velocity_mps", velocity_mps)
    ff = _as_1d("friction_force_N", friction_force_N)
    fn = _as_1d("normal_force_N", normal_force_N)
    _check_same_length(time_s=t, velocity_mps=v, friction_force_N=ff, normal_force_N=fn)
    _check_non_negative(inertial_mass_kg=inertial_mass_kg)
    if t.shape[0] < 2:
        raise ValueError(f"need at least 2 samples, got {t.shape[0]}")
    params = InstationaryParams(
        bin_width_mps=bin_width_mps,
        smoothing_s=smoothing_s,
        min_velocity_mps=min_velocity_mps,
        min_accel_mps2=min_accel_mps2,
        min_samples=min_samples,
    )
    return _instationary(t, v, ff, fn, float(inertial_mass_kg), params).table


def evaluate_instationary_run(
    run: RigRun,
    *,
    inertial_mass_kg: float | None = None,
    params: InstationaryParams | None = None,
) -> InstationaryRunResult:
    """Evaluate one instationary run (see :func:`instationary_characteristic`).

    Parameters
    ----------
    run : RigRun
        The run, e.g. from :func:`read_run`.
    inertial_mass_kg : float, optional
        Mass of carriage and sample (kg); overrides the metadata key ``inertial_mass_kg``.
    params : InstationaryParams, optional
        Bin width and filter parameters; defaults of :class:`InstationaryParams` if omitted.

    Returns
    -------
    InstationaryRunResult
        The binned characteristic and the run's identity and ambient means.

    Raises
    ------
    RunFormatError
        When no mass is known, no accelerating or decelerating phase is found, or the normal
        force is ``<= 0`` at an evaluated sample.
    """
    p = params if params is not None else InstationaryParams()
    if inertial_mass_kg is None:
        inertial_mass_kg = run.metadata.get("inertial_mass_kg")
        if inertial_mass_kg is None:
            raise RunFormatError(
                run.path,
                f"metadata key 'inertial_mass_kg' missing from the header (file lines 1 to "
                f"{run.header_line - 1}); expected '# inertial_mass_kg: <kg>' or an inertial "
                "mass argument",
                column="inertial_mass_kg",
            )
    else:
        _check_non_negative(inertial_mass_kg=inertial_mass_kg)
    mass = float(inertial_mass_kg)
    t = run.time_s
    res = _instationary(t, run.velocity_mps, run.friction_force_N, run.normal_force_N, mass, p)
    used = np.flatnonzero(res.used)
    if used.size == 0 or res.table.empty:
        raise run.error(
            f"column 'velocity_mps': no accelerating or decelerating phase found in "
            f"{run.where(0)} to {run.where(len(run) - 1)}; expected samples moving at >= "
            f"{p.min_velocity_mps} m/s with |acceleration| >= {p.min_accel_mps2} m/s^2 filling "
            f"bins of {p.bin_width_mps} m/s with >= {p.min_samples} samples",
            column="velocity_mps",
        )
    bad = used[run.normal_force_N[used] <= 0.0]
    if bad.size:
        i = int(bad[0])
        raise run.error(
            f"column 'normal_force_N', {run.where(i)}: expected a normal force > 0 N at every "
            f"evaluated (moving) sample, got {float(run.normal_force_N[i])!r} N",
            column="normal_force_N",
            index=i,
        )
    spans = {}
    for branch, mask in res.branch_masks.items():
        idx = np.flatnonzero(mask)
        if idx.size:
            spans[branch] = (float(t[idx[0]]), float(t[idx[-1]]))
    reference = float(np.median(run.normal_force_N[used]))
    trace: dict[str, Any] = _mu_trace(run, reference)
    trace["mu_corrected"] = np.where(res.used, res.mu_corrected, np.nan)[_decimate(len(run))]
    trace["spans"] = spans
    logger.debug("%s: instationary, m = %.4g kg, %d bins", run.path, mass, len(res.table))
    return InstationaryRunResult(
        file=str(run.path),
        specimen=run.specimen,
        condition=run.condition,
        run=run.run_number,
        inertial_mass_kg=mass,
        table=res.table,
        temperature_C=_run_mean(run.temperature_C),
        humidity_pct=_run_mean(run.humidity_pct),
        metadata=dict(run.metadata),
        trace=trace,
    )


# ---------------------------------------------------------------------------------------------
# aggregation


def _empty_steady() -> pd.DataFrame:
    return pd.DataFrame({c: pd.Series(dtype=object) for c in STEADY_COLUMNS})


def aggregate_runs(
    runs: pd.DataFrame,
    *,
    velocity_rel_tol: float = 0.05,
    velocity_abs_tol_mps: float = 0.02,
) -> pd.DataFrame:
    """Aggregate repeated runs per specimen, condition and sliding velocity.

    Runs of one specimen and condition are grouped by velocity: sorted by velocity, a new
    group starts where the velocity exceeds the previous run's by more than
    ``max(velocity_rel_tol * v, velocity_abs_tol_mps)``.

    Parameters
    ----------
    runs : pandas.DataFrame
        Run rows with at least ``specimen``, ``condition``, ``velocity_mps``,
        ``mu_mean_method1``, ``mu_mean_method2`` (e.g. the ``run`` rows of
        :func:`steady_characteristic`).
    velocity_rel_tol : float
        Relative velocity difference that separates two groups.
    velocity_abs_tol_mps : float
        Absolute floor of that difference (m/s).

    Returns
    -------
    pandas.DataFrame
        One ``aggregate`` row per group, columns :data:`STEADY_COLUMNS`: means over the runs
        of velocity, ``mu_mean_method1``, ``mu_mean_method2``, ``mu_std_t``, forces,
        pressure, temperature and humidity; ``mu_std_runs`` the sample standard deviation
        (``ddof=1``) of ``mu_mean_method1`` over the runs (NaN for one run); ``n_runs``;
        ``n_samples`` the total. ``file``, ``run`` and the window times are empty.
    """
    _check_non_negative(velocity_rel_tol=velocity_rel_tol)
    _check_positive(velocity_abs_tol_mps=velocity_abs_tol_mps)
    if runs.empty:
        return _empty_steady()
    rows = []
    keyed = runs.assign(
        specimen=runs["specimen"].fillna("").astype(str),
        condition=runs["condition"].fillna("").astype(str),
    )
    for (specimen, condition), group in keyed.groupby(["specimen", "condition"], sort=False):
        group = group.sort_values("velocity_mps", kind="stable")
        v = group["velocity_mps"].to_numpy(float)
        gaps = np.diff(v) > np.maximum(velocity_rel_tol * np.abs(v[:-1]), velocity_abs_tol_mps)
        cluster = np.concatenate(([0], np.cumsum(gaps)))
        for _, sub in group.groupby(cluster, sort=True):
            mu1 = sub["mu_mean_method1"].to_numpy(float)
            m1 = float(np.mean(mu1))
            m2 = float(sub["mu_mean_method2"].mean())

            def mean(col: str, sub: pd.DataFrame = sub) -> float:
                if col not in sub:
                    return math.nan
                values = pd.to_numeric(sub[col], errors="coerce")
                return float(values.mean()) if values.notna().any() else math.nan

            rows.append(
                {
                    "row_type": "aggregate",
                    "file": None,
                    "specimen": specimen,
                    "condition": condition,
                    "run": None,
                    "n_runs": len(sub),
                    "velocity_mps": mean("velocity_mps"),
                    "window_start_s": math.nan,
                    "window_end_s": math.nan,
                    "n_samples": int(sub["n_samples"].sum()) if "n_samples" in sub else None,
                    "mu_mean_method1": m1,
                    "mu_mean_method2": m2,
                    "method_rel_diff": abs(m1 - m2) / abs(m2) if m2 != 0 else math.nan,
                    "mu_std_t": mean("mu_std_t"),
                    "mu_std_runs": float(np.std(mu1, ddof=1)) if mu1.size > 1 else math.nan,
                    "normal_force_N": mean("normal_force_N"),
                    "friction_force_N": mean("friction_force_N"),
                    "normal_pressure_Pa": mean("normal_pressure_Pa"),
                    "temperature_C": mean("temperature_C"),
                    "humidity_pct": mean("humidity_pct"),
                }
            )
    out = pd.DataFrame(rows, columns=list(STEADY_COLUMNS))
    order = sorted(
        range(len(out)),
        key=lambda i: (
            natural_key(out.at[i, "specimen"]),
            natural_key(out.at[i, "condition"]),
            out.at[i, "velocity_mps"],
        ),
    )
    return out.iloc[order].reset_index(drop=True)


def steady_characteristic(
    results: Sequence[SteadyRunResult],
    *,
    velocity_rel_tol: float = 0.05,
    velocity_abs_tol_mps: float = 0.02,
) -> pd.DataFrame:
    """Steady friction characteristic: run rows followed by aggregate rows.

    Parameters
    ----------
    results : sequence of SteadyRunResult
        Evaluated steady runs.
    velocity_rel_tol, velocity_abs_tol_mps : float
        Velocity grouping of :func:`aggregate_runs` (dimensionless, m/s).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`STEADY_COLUMNS` then ``meta_<key>`` for the other metadata keys of
        the files; ``row_type`` is ``"run"`` or ``"aggregate"``.
    """
    if not results:
        return _empty_steady()
    runs = pd.DataFrame([r.as_row() for r in results])
    aggregates = aggregate_runs(
        runs, velocity_rel_tol=velocity_rel_tol, velocity_abs_tol_mps=velocity_abs_tol_mps
    )
    meta_cols = [c for c in runs.columns if c not in STEADY_COLUMNS]
    table = pd.concat([runs, aggregates], ignore_index=True)
    table = table[[*STEADY_COLUMNS, *meta_cols]]
    table["run"] = pd.array(table["run"].tolist(), dtype="Int64")
    table["n_runs"] = table["n_runs"].astype(np.int64)
    table["n_samples"] = table["n_samples"].astype(np.int64)
    return table


def ambient_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Ambient averages per specimen, like thesis Table 4.2.

    Parameters
    ----------
    runs : pandas.DataFrame
        One row per run with columns ``specimen``, ``temperature_C`` (degC) and
        ``humidity_pct`` (%); extra columns are ignored, NaN values skipped.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`AMBIENT_COLUMNS`. The first row, specimen ``"Average"``, averages over
        all runs; then one row per specimen in natural order with the mean and the sample
        standard deviation over its runs.
    """
    cols = list(AMBIENT_COLUMNS)
    if runs.empty:
        return pd.DataFrame({c: pd.Series(dtype=object) for c in cols})
    data = pd.DataFrame(
        {
            "specimen": runs["specimen"].fillna("").astype(str).to_numpy(),
            "temperature_C": pd.to_numeric(runs["temperature_C"], errors="coerce").to_numpy(),
            "humidity_pct": pd.to_numeric(runs["humidity_pct"], errors="coerce").to_numpy(),
        }
    )

    def summary(name: str, part: pd.DataFrame) -> dict[str, Any]:
        return {
            "specimen": name,
            "temperature_C": part["temperature_C"].mean(),
            "humidity_pct": part["humidity_pct"].mean(),
            "temperature_std_C": part["temperature_C"].std(ddof=1),
            "humidity_std_pct": part["humidity_pct"].std(ddof=1),
            "n_runs": len(part),
        }

    rows = [summary("Average", data)]
    for name in sorted(data["specimen"].unique(), key=natural_key):
        rows.append(summary(name, data[data["specimen"] == name]))
    return pd.DataFrame(rows, columns=cols)


# ---------------------------------------------------------------------------------------------
# batch


def collect_run_files(paths: Iterable[str | os.PathLike[str]]) -> list[Path]:
    """Expand folders into their ``*.csv`` files in natural sort order.

    Parameters
    ----------
    paths : iterable of str or path-like
        Files and folders; files are kept as given (even when they do not exist, so that the
        batch reports them), folders contribute their ``*.csv`` files (not recursive).

    Returns
    -------
    list of pathlib.Path
        Files without duplicates, in input order, folders expanded in natural order
        (``run_2.csv`` before ``run_10.csv``).
    """
    files: list[Path] = []
    seen: set[Path] = set()
    for raw in paths:
        path = Path(raw)
        if path.is_dir():
            found = sorted(
                (p for p in path.glob("*.csv") if p.is_file()), key=lambda p: natural_key(p.name)
            )
        else:
            found = [path]
        for p in found:
            key = p.resolve()
            if key not in seen:
                seen.add(key)
                files.append(p)
    return files


def evaluate_runs(
    paths: Iterable[str | os.PathLike[str]],
    *,
    instationary: bool = False,
    inertial_mass_kg: float | None = None,
    window: WindowParams | None = None,
    instationary_params: InstationaryParams | None = None,
    progress: bool | None = None,
) -> EvaluationResult:
    """Evaluate many run files; a bad file is recorded as a failure and skipped.

    Parameters
    ----------
    paths : iterable of str or path-like
        Run CSV files and folders of them (see :func:`collect_run_files`).
    instationary : bool
        Evaluate every run as instationary. Otherwise a run is instationary when its
        metadata says ``kind: instationary`` and steady else.
    inertial_mass_kg : float, optional
        Mass of carriage and sample for instationary runs (kg); overrides the metadata.
    window : WindowParams, optional
        Constant-velocity window detection of steady runs.
    instationary_params : InstationaryParams, optional
        Bin width and filtering of instationary runs.
    progress : bool, optional
        Show a tqdm progress bar on stderr; by default only when stderr is a terminal.

    Returns
    -------
    EvaluationResult
        Tables, per-run results and failures (nothing is written).
    """
    window = window if window is not None else WindowParams()
    inst_params = instationary_params if instationary_params is not None else InstationaryParams()
    if inertial_mass_kg is not None:
        _check_non_negative(inertial_mass_kg=inertial_mass_kg)
    paths = list(paths)
    failures: list[EvaluationFailure] = []
    for raw in paths:
        p = Path(raw)
        if p.is_dir() and not any(q.is_file() for q in p.glob("*.csv")):
            failures.append(EvaluationFailure(str(p), "folder contains no *.csv files"))
    files = collect_run_files(paths)
    if progress is None:
        progress = sys.stderr.isatty()
    steady_runs: list[SteadyRunResult] = []
    inst_runs: list[InstationaryRunResult] = []
    for path in tqdm(files, desc="evaluate", unit="run", disable=not progress):
        try:
            run = read_run(path)
            if instationary or run.kind == "instationary":
                inst_runs.append(
                    evaluate_instationary_run(
                        run, inertial_mass_kg=inertial_mass_kg, params=inst_params
                    )
                )
            else:
                steady_runs.append(evaluate_steady_run(run, window=window))
        except RunFormatError as exc:
            failures.append(EvaluationFailure(str(path), exc.detail))
            logger.info("skipped %s", exc)
        except OSError as exc:
            reason = exc.strerror or str(exc)
            failures.append(EvaluationFailure(str(path), f"cannot read file: {reason}"))
            logger.info("skipped %s: %s", path, exc)
    steady = steady_characteristic(steady_runs)
    ambient_rows = [
        {"specimen": r.specimen, "temperature_C": r.temperature_C, "humidity_pct": r.humidity_pct}
        for r in (*steady_runs, *inst_runs)
    ]
    ambient = ambient_table(
        pd.DataFrame(ambient_rows, columns=["specimen", "temperature_C", "humidity_pct"])
    )
    if inst_runs:
        instationary_table = pd.concat([r.tidy() for r in inst_runs], ignore_index=True)
    else:
        instationary_table = pd.DataFrame(
            {c: pd.Series(dtype=object) for c in _INSTATIONARY_FILE_COLUMNS}
        )
    parameters = {
        "instationary": instationary,
        "inertial_mass_kg": inertial_mass_kg,
        "window": asdict(window),
        "instationary_params": asdict(inst_params),
    }
    logger.info(
        "evaluated %d steady and %d instationary runs, %d failures",
        len(steady_runs),
        len(inst_runs),
        len(failures),
    )
    return EvaluationResult(
        steady=steady,
        ambient=ambient,
        instationary=instationary_table,
        failures=failures,
        steady_runs=steady_runs,
        instationary_runs=inst_runs,
        files=files,
        parameters=parameters,
    )


# ---------------------------------------------------------------------------------------------
# output


def _write_csv(df: pd.DataFrame, path: Path) -> Path:
    return atomic_write(path, lambda tmp: df.to_csv(tmp, index=False, lineterminator="\n"))


def _save_figure(fig: Any, path: Path) -> Path:
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))


def _package_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("tir-contact")
    except PackageNotFoundError:
        return "0.0.0+unknown"


def _plot_mu_t(result: SteadyRunResult | InstationaryRunResult, path: Path) -> Path:
    from matplotlib.figure import Figure

    tr = result.trace
    fig = Figure(figsize=(8.0, 4.5), layout="constrained")
    ax = fig.subplots()
    ax.plot(tr["time_s"], tr["mu"], lw=0.6, color="0.35", label=r"$\mu(t) = F_F/F_N$")
    if isinstance(result, SteadyRunResult):
        w = result.window
        ax.axvspan(w.start_s, w.end_s, color="tab:green", alpha=0.2, label="evaluated window")
        ax.axhline(result.mu_mean_method1, color="tab:green", lw=1.2, label=r"$\bar\mu$ (method 1)")
        title = f"v = {result.velocity_mps:.3g} m/s, mu = {result.mu_mean_method1:.4f}"
        inside = tr["mu"][(tr["time_s"] >= w.start_s) & (tr["time_s"] <= w.end_s)]
    else:
        ax.plot(tr["time_s"], tr["mu_corrected"], lw=1.0, color="tab:blue", label="inertia removed")
        colours = {"accelerating": "tab:red", "decelerating": "tab:blue"}
        for branch, (t0, t1) in tr["spans"].items():
            ax.axvspan(t0, t1, color=colours[branch], alpha=0.12, label=branch)
        title = f"instationary, m = {result.inertial_mass_kg:.4g} kg"
        inside = tr["mu_corrected"]
    finite = inside[np.isfinite(inside)]
    if finite.size:
        lo, hi = np.percentile(finite, [0.5, 99.5])
        pad = 0.5 * (hi - lo) + 0.02
        ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(r"friction coefficient $\mu$ [-]")
    ax2 = ax.twinx()
    ax2.plot(tr["time_s"], tr["velocity_mps"], lw=0.8, color="tab:orange")
    ax2.set_ylabel("sliding velocity v [m/s]", color="tab:orange")
    ident = " ".join(x for x in (result.specimen, result.condition) if x)
    run = f" run {result.run}" if result.run is not None else ""
    ax.set_title(f"{Path(result.file).name}: {ident}{run} - {title}", fontsize=9)
    ax.legend(loc="lower right", fontsize=8)
    return _save_figure(fig, path)


def _plot_mu_v(result: EvaluationResult, path: Path) -> Path:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.5), layout="constrained")
    ax = fig.subplots()
    steady = result.steady
    if not steady.empty:
        runs = steady[steady["row_type"] == "run"]
        agg = steady[steady["row_type"] == "aggregate"]
        ax.plot(runs["velocity_mps"], runs["mu_mean_method1"], ".", color="0.6", ms=3)
        for (specimen, condition), g in agg.groupby(["specimen", "condition"], sort=False):
            label = " ".join(x for x in (str(specimen), str(condition)) if x) or "steady"
            ax.errorbar(
                g["velocity_mps"],
                g["mu_mean_method1"],
                yerr=g["mu_std_runs"].fillna(0.0),
                fmt="o",
                capsize=3,
                label=f"{label} (steady)",
            )
    styles = {"accelerating": "-", "decelerating": "--"}
    for r in result.instationary_runs:
        ident = " ".join(x for x in (r.specimen, r.condition) if x) or Path(r.file).stem
        for branch, g in r.table.groupby("branch", sort=False):
            ax.plot(g["velocity_mps"], g["mu"], styles[branch], label=f"{ident} {branch}")
    ax.set_xlabel("sliding velocity v [m/s]")
    ax.set_ylabel(r"friction coefficient $\mu$ [-]")
    ax.set_xlim(left=0.0)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    return _save_figure(fig, path)


def write_outputs(
    result: EvaluationResult, out_dir: str | os.PathLike[str], *, plots: bool = True
) -> dict[str, Path]:
    """Write the tables, plots and a provenance record of a batch evaluation.

    Every file is written to a temporary file in ``out_dir`` and moved into place with
    :func:`os.replace`, so a reader never sees a half-written file.

    Parameters
    ----------
    result : EvaluationResult
        From :func:`evaluate_runs`.
    out_dir : str or path-like
        Output folder, created when missing.
    plots : bool
        Also write ``mu_v.png`` and ``mu_t/<run>.png`` for every run.

    Returns
    -------
    dict of str to pathlib.Path
        Written files by name: ``steady_characteristic``, ``ambient``,
        ``instationary_characteristic`` (only with instationary runs), ``provenance``,
        ``mu_v`` and ``mu_t:<file>``; also stored in ``result.outputs``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written: dict[str, Path] = {}
    written["steady_characteristic"] = _write_csv(result.steady, out / "steady_characteristic.csv")
    written["ambient"] = _write_csv(result.ambient, out / "ambient.csv")
    if result.instationary_runs:
        written["instationary_characteristic"] = _write_csv(
            result.instationary, out / "instationary_characteristic.csv"
        )
    if plots:
        trace_dir = out / "mu_t"
        trace_dir.mkdir(exist_ok=True)
        used: set[str] = set()
        for r in (*result.steady_runs, *result.instationary_runs):
            stem = Path(r.file).stem
            name, k = stem, 1
            while name in used:
                k += 1
                name = f"{stem}_{k}"
            used.add(name)
            written[f"mu_t:{r.file}"] = _plot_mu_t(r, trace_dir / f"{name}.png")
        written["mu_v"] = _plot_mu_v(result, out / "mu_v.png")
    provenance = {
        "package": "tir-contact",
        "version": _package_version(),
        "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
        "parameters": result.parameters,
        "inputs": [str(p) for p in result.files],
        "failures": [asdict(f) for f in result.failures],
        "metadata": {
            r.file: {k: v for k, v in r.metadata.items()}
            for r in (*result.steady_runs, *result.instationary_runs)
        },
        "outputs": sorted(p.name for p in written.values() if p.parent == out),
    }
    text = json.dumps(provenance, indent=2, default=str) + "\n"
    written["provenance"] = atomic_write(
        out / "provenance.json", lambda tmp: tmp.write_text(text, encoding="utf-8")
    )
    result.outputs = written
    return written


def evaluate_folder(
    paths: Iterable[str | os.PathLike[str]] | str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    *,
    instationary: bool = False,
    inertial_mass_kg: float | None = None,
    window: WindowParams | None = None,
    instationary_params: InstationaryParams | None = None,
    plots: bool = True,
    progress: bool | None = None,
) -> EvaluationResult:
    """Evaluate run files and folders and write every output to ``out_dir``.

    :func:`evaluate_runs` followed by :func:`write_outputs`; what succeeded is written even
    when some files failed (see ``result.failures``).

    Parameters
    ----------
    paths : path-like or iterable of path-like
        Run CSV files and folders of them.
    out_dir : str or path-like
        Output folder.
    instationary, inertial_mass_kg, window, instationary_params, progress
        See :func:`evaluate_runs`.
    plots : bool
        Write the PNG plots.

    Returns
    -------
    EvaluationResult
        With ``outputs`` filled in.
    """
    if isinstance(paths, str | os.PathLike):
        paths = [paths]
    result = evaluate_runs(
        paths,
        instationary=instationary,
        inertial_mass_kg=inertial_mass_kg,
        window=window,
        instationary_params=instationary_params,
        progress=progress,
    )
    write_outputs(result, out_dir, plots=plots)
    return result
