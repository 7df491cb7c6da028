"""Writing a batch evaluation: tables, figures and a provenance record, each atomically."""

from __future__ import annotations

import json
import os
from dataclasses import asdict
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pandas as pd

from friction_model.rig.figures import _plot_mu_t, _plot_mu_v
from friction_model.rig.results import EvaluationResult
from tir_common.atomic import atomic_write

__all__ = ["write_outputs"]


def _write_csv(df: pd.DataFrame, path: Path) -> Path:
    """Write ``df`` as CSV (no index, ``\\n`` line ends) to ``path`` atomically."""
    return atomic_write(path, lambda tmp: df.to_csv(tmp, index=False, lineterminator="\n"))


def _package_version() -> str:
    """The installed version of tir-contact, ``0.0.0+unknown`` when not installed."""
    try:
        return version("tir-contact")
    except PackageNotFoundError:
        return "0.0.0+unknown"


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
