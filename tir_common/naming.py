"""Natural ordering of file and run names (``f2`` before ``f10``)."""

from __future__ import annotations

import re
from typing import Any

__all__ = ["natural_key"]

_NATURAL_SPLIT = re.compile(r"(\d+)")


def natural_key(name: str) -> tuple[Any, ...]:
    """Sort key that orders embedded numbers by value.

    Parameters
    ----------
    name : str
        A file or run name.

    Returns
    -------
    tuple
        The text parts (case-folded) and numbers in order, then the name itself to break ties.

    Examples
    --------
    >>> sorted(["run10.csv", "run2.csv", "Run1.csv"], key=natural_key)
    ['Run1.csv', 'run2.csv', 'run10.csv']
    """
    parts = _NATURAL_SPLIT.split(name)
    # (kind, number, text) triples: numbers and text never meet in one comparison
    key = tuple((1, int(p), "") if i % 2 else (0, 0, p.casefold()) for i, p in enumerate(parts))
    return (key, name)
