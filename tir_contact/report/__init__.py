"""``report.html``: a batch's results to review in a browser, rebuilt from disk.

:func:`write_report` writes ``DIR/report.html`` for an analysis folder (``tir-contact
analyze --out DIR``: a sortable table of clips, failed and warned first, and one card per
clip with overlay thumbnails, plots over time, the steady per-element table and links to
its files) or a test-rig evaluation folder (``tir-contact evaluate --out DIR``: the
characteristics, the batch figure and one card per run). The page is plain HTML and CSS
with relative links and works offline; thumbnails and plots are in ``DIR/report_files/``.
``tir-contact report DIR`` calls it.
"""

from __future__ import annotations

import os
from pathlib import Path

from tir_contact.report.analysis import NoResultsError, collect_clips, write_analysis_report
from tir_contact.report.evaluation import write_evaluation_report

__all__ = ["REPORT_FILENAME", "collect_clips", "write_analysis_report",
           "write_evaluation_report", "write_report"]

#: The report's file name in its folder.
REPORT_FILENAME = "report.html"


def write_report(folder: str | os.PathLike[str]) -> Path:
    """Write ``folder/report.html`` for the results in `folder`, whichever kind they are.

    Parameters
    ----------
    folder : path
        An ``analyze --out`` folder (``batch_report.json`` or ``<clip>/summary.json``) or
        an ``evaluate --out`` folder (``provenance.json`` or ``steady_characteristic.csv``).

    Returns
    -------
    Path
        The report.

    Raises
    ------
    ValueError
        `folder` is not a folder or holds neither kind of results.
    """
    root = Path(folder)
    if not root.is_dir():
        raise ValueError(f"{root}: not a folder (expected an analyze or evaluate --out folder)")
    if (root / "provenance.json").is_file() or (root / "steady_characteristic.csv").is_file():
        return write_evaluation_report(root)
    try:
        return write_analysis_report(root)
    except NoResultsError as exc:  # neither kind: what was looked for of both
        raise ValueError(f"{exc} and no evaluation results (no provenance.json, no "
                         "steady_characteristic.csv)") from None
