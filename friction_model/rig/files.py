"""Finding the run files of a batch: folders expand into their ``*.csv`` files."""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from tir_common.naming import natural_key

__all__ = ["collect_run_files"]


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
