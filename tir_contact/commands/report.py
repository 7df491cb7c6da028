"""``tir-contact report``: (re)build ``report.html`` of a results folder from what is on disk.

DIR is an ``analyze --out`` folder (after ``--resume``, or with result folders merged in
from other runs) or an ``evaluate --out`` folder. ``analyze`` and ``evaluate`` write the
report themselves; this command rebuilds it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

__all__ = ["DESCRIPTION", "add_arguments", "run"]

DESCRIPTION = (
    "Build DIR/report.html from the results in DIR (an analyze or evaluate --out folder): "
    "a sortable table of clips or runs and a card per clip with overlays, plots and links. "
    "Plain HTML, works offline."
)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``tir-contact report``."""
    p.add_argument("folder", type=Path, metavar="DIR",
                   help="an analyze --out or evaluate --out folder")


def run(args: argparse.Namespace) -> int:
    """Write the report; returns 0 (a folder without results is a usage error, exit 2)."""
    from tir_contact.report import write_report

    path = write_report(args.folder)
    print(f"wrote {path}")
    return 0
