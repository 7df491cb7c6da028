"""What the rig evaluation returns: the table columns and the result records.

A steady run gives a :class:`SteadyRunResult` (its :class:`VelocityWindow` and both average
coefficients of section 4.2.4), an instationary run an :class:`InstationaryRunResult` (its
binned ``mu(v)``, section 4.4); a batch gives an :class:`EvaluationResult` with the tables,
the per-run results and the :class:`EvaluationFailure` of every file that could not be read.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

__all__ = [
    "AMBIENT_COLUMNS",
    "INSTATIONARY_COLUMNS",
    "STEADY_COLUMNS",
    "EvaluationFailure",
    "EvaluationResult",
    "InstationaryRunResult",
    "SteadyRunResult",
    "VelocityWindow",
]

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
