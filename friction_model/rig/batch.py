"""The batch workflow: evaluate many run files, then write every output.

:func:`evaluate_runs` reads every file (:func:`.read_run`), evaluates it as a steady
(:mod:`.steady`) or an instationary run (:mod:`.instationary`), records a bad file as a
failure and goes on, and builds the tables (:mod:`.aggregate`); :func:`evaluate_folder` then
writes them (:mod:`.write`).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterable
from dataclasses import asdict
from pathlib import Path

import pandas as pd

from friction_model.rig._io import RunFormatError, read_run
from friction_model.rig.aggregate import ambient_table, steady_characteristic
from friction_model.rig.files import collect_run_files
from friction_model.rig.instationary import evaluate_instationary_run
from friction_model.rig.params import InstationaryParams, WindowParams
from friction_model.rig.results import (
    _INSTATIONARY_FILE_COLUMNS,
    EvaluationFailure,
    EvaluationResult,
    InstationaryRunResult,
    SteadyRunResult,
)
from friction_model.rig.steady import evaluate_steady_run
from friction_model.rig.write import write_outputs
from tir_common.progress import progress_bar
from tir_common.validate import check_nonnegative

__all__ = ["evaluate_folder", "evaluate_runs"]

logger = logging.getLogger(__name__)


def _empty_folders(paths: list[str | os.PathLike[str]]) -> list[EvaluationFailure]:
    """A failure for every given folder without ``*.csv`` files."""
    failures = []
    for raw in paths:
        p = Path(raw)
        if p.is_dir() and not any(q.is_file() for q in p.glob("*.csv")):
            failures.append(EvaluationFailure(str(p), "folder contains no *.csv files"))
    return failures


def _ambient(
    steady_runs: list[SteadyRunResult], inst_runs: list[InstationaryRunResult]
) -> pd.DataFrame:
    """:func:`.ambient_table` over every evaluated run, steady then instationary."""
    rows = [
        {"specimen": r.specimen, "temperature_C": r.temperature_C, "humidity_pct": r.humidity_pct}
        for r in (*steady_runs, *inst_runs)
    ]
    return ambient_table(pd.DataFrame(rows, columns=["specimen", "temperature_C", "humidity_pct"]))


def _instationary_table(inst_runs: list[InstationaryRunResult]) -> pd.DataFrame:
    """The characteristics of all instationary runs, one below the other."""
    if inst_runs:
        return pd.concat([r.tidy() for r in inst_runs], ignore_index=True)
    return pd.DataFrame({c: pd.Series(dtype=object) for c in _INSTATIONARY_FILE_COLUMNS})


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
        Show a progress bar on stderr; None (default) shows it only when stderr is a
        terminal.

    Returns
    -------
    EvaluationResult
        Tables, per-run results and failures (nothing is written).

    Raises
    ------
    FileNotFoundError
        When none of `paths` exists (a mistyped path: there is nothing to evaluate). One
        missing among others is a failure of the result, as a broken file is.
    """
    window = window if window is not None else WindowParams()
    inst_params = instationary_params if instationary_params is not None else InstationaryParams()
    if inertial_mass_kg is not None:
        check_nonnegative("inertial_mass_kg", inertial_mass_kg)
    paths = list(paths)
    if paths and not any(Path(p).exists() for p in paths):
        raise FileNotFoundError(f"{', '.join(str(p) for p in paths)}: does not exist")
    failures = _empty_folders(paths)
    files = collect_run_files(paths)
    steady_runs: list[SteadyRunResult] = []
    inst_runs: list[InstationaryRunResult] = []
    with progress_bar(len(files), progress=progress, desc="evaluate", unit="run") as bar:
        for path in files:
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
            bar.update(1)
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
        steady=steady_characteristic(steady_runs),
        ambient=_ambient(steady_runs, inst_runs),
        instationary=_instationary_table(inst_runs),
        failures=failures,
        steady_runs=steady_runs,
        instationary_runs=inst_runs,
        files=files,
        parameters=parameters,
    )


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

    Raises
    ------
    FileNotFoundError
        When none of `paths` exists; nothing is written (see :func:`evaluate_runs`).
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
