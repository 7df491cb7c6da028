"""``report.html`` of a test-rig evaluation folder (``tir-contact evaluate --out DIR``).

From the files :func:`friction_model.rig.write_outputs` wrote: the batch figure
(``mu_v.png``), the steady and instationary characteristics and the ambient table, the
failures (``provenance.json``), then one card per run file with its mu(t) plot and its rows.
"""

from __future__ import annotations

import json
import os
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import pandas as pd

from tir_common.atomic import atomic_write
from tir_contact import __version__
from tir_contact.report._html import Cell, esc, fmt, link, page, table

__all__ = ["write_evaluation_report"]

#: Rows of a long table shown in the page (the CSV file holds them all).
MAX_ROWS = 80
#: Columns of the steady characteristic shown per row, with their labels.
STEADY_COLUMNS = (("specimen", "specimen"), ("condition", "condition"), ("run", "run"),
                  ("velocity_mps", "v (m/s)"), ("mu_mean_method1", "μ (method 1)"),
                  ("mu_mean_method2", "μ (method 2)"), ("mu_std_t", "std over time"),
                  ("mu_std_runs", "std over runs"), ("n_runs", "runs"),
                  ("normal_force_N", "F_N (N)"), ("temperature_C", "T (°C)"))


def _frame_table(df: pd.DataFrame, columns: Any = None) -> str:
    """A table of `df` (at most :data:`MAX_ROWS` rows), numbers to 4 digits."""
    cols = [(c, label) for c, label in (columns or [(c, c) for c in df.columns]) if c in df]
    rows = []
    for rec in df.head(MAX_ROWS).itertuples(index=False):
        values = dict(zip(df.columns, rec, strict=True))
        rows.append([Cell(esc(fmt(values[c])), None, "num")
                     if isinstance(values[c], float) else str(values[c]) for c, _ in cols])
    more = (f'<p class="muted">{len(df) - MAX_ROWS} more rows in the CSV file</p>'
            if len(df) > MAX_ROWS else "")
    return table([label for _, label in cols], rows, sortable=True) + more


def _read(path: Path) -> pd.DataFrame | None:
    try:
        return pd.read_csv(path)
    except (OSError, ValueError):
        return None


def write_evaluation_report(folder: str | os.PathLike[str]) -> Path:
    """Write ``folder/report.html`` of the evaluation results in `folder` (from disk).

    Parameters
    ----------
    folder : path
        An ``evaluate --out`` folder.

    Returns
    -------
    Path
        The report.

    Raises
    ------
    ValueError
        `folder` holds neither ``provenance.json`` nor ``steady_characteristic.csv``.
    """
    root = Path(folder)
    steady = _read(root / "steady_characteristic.csv")
    try:
        prov = json.loads((root / "provenance.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        prov = {}
    if steady is None and not prov:
        raise ValueError(f"{root}: no evaluation results (no provenance.json, no "
                         "steady_characteristic.csv)")
    inputs = [str(p) for p in prov.get("inputs", [])]
    failures = prov.get("failures", [])
    parts = [f"<h1>Test-rig evaluation: {esc(root.resolve().name)}</h1>",
             f"<p>{len(inputs)} run file(s), {len(failures)} failed. "
             f'<span class="muted">Built {datetime.now(UTC):%Y-%m-%d %H:%M} UTC by tir-contact '
             f"{esc(__version__)}; rebuild with <code>tir-contact report {esc(root)}</code>."
             "</span></p>"]
    if failures:
        parts.append("<h2>Failed files</h2>" + table(
            ["file", "message"], [[f.get("file", ""), f.get("message", "")] for f in failures],
            row_classes=["failed"] * len(failures)))
    if (root / "mu_v.png").is_file():
        parts.append('<h2>Friction characteristic</h2><img class="plot" src="mu_v.png" '
                     'alt="friction coefficient over velocity, all runs">')
    if steady is not None and len(steady):
        agg = steady[steady["row_type"] == "aggregate"] if "row_type" in steady else steady
        parts.append("<h2>Steady characteristic (mean over repeated runs)</h2>"
                     + _frame_table(agg, STEADY_COLUMNS)
                     + f"<p>{link('steady_characteristic.csv', 'steady_characteristic.csv')}</p>")
    for name, title in (("instationary_characteristic.csv", "Instationary characteristic"),
                        ("ambient.csv", "Ambient conditions")):
        df = _read(root / name)
        if df is not None and len(df):
            parts.append(f"<h2>{title}</h2>" + _frame_table(df) + f"<p>{link(name, name)}</p>")
    parts.append(_run_cards(root, steady, inputs, prov.get("metadata", {})))
    text = page(f"Test-rig evaluation: {root.resolve().name}", "".join(parts), script=True)
    return atomic_write(root / "report.html",
                        lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))


def _run_cards(root: Path, steady: pd.DataFrame | None, inputs: list[str],
               metadata: dict[str, Any]) -> str:
    """One card per run file: its mu(t) plot (``mu_t/<stem>.png``) and its rows."""
    runs = steady[steady["row_type"] == "run"] if steady is not None and "row_type" in steady \
        else None
    files = list(dict.fromkeys([*inputs, *(runs["file"].astype(str) if runs is not None
                                           and "file" in runs else [])]))
    parts = ["<h2>Runs</h2>"] if files else []
    for file in files:
        stem = Path(file).stem
        parts.append(f'<div class="card" id="run-{esc(stem)}"><h3>{esc(file)}</h3>')
        meta = metadata.get(file) or {}
        if meta:
            parts.append('<p class="muted">' + ", ".join(
                f"{esc(k)}: {esc(v)}" for k, v in meta.items()) + "</p>")
        plot = root / "mu_t" / f"{stem}.png"
        if plot.is_file():
            parts.append(f'<img class="plot" src="mu_t/{esc(plot.name)}" loading="lazy" '
                         f'alt="{esc(stem)}: friction coefficient over time">')
        if runs is not None and "file" in runs:
            mine = runs[runs["file"].astype(str) == file]
            if len(mine):
                parts.append(_frame_table(mine, STEADY_COLUMNS))
        parts.append("</div>")
    return "".join(parts)
