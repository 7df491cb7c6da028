"""Atomic file writes: a file appears complete or not at all (shared by every writer)."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path

__all__ = ["atomic_write"]


def atomic_write(path: str | os.PathLike[str], writer: Callable[[Path], object]) -> Path:
    """Write through ``writer(tmp)`` to a temporary file beside `path`, then rename it.

    The temporary file keeps the suffix of `path` (so format-by-extension writers such as
    matplotlib's ``savefig`` work) and is removed when `writer` fails.

    Parameters
    ----------
    path : str or os.PathLike
        Final file; its folder must exist.
    writer : callable
        Called with the temporary path; must create that file.

    Returns
    -------
    Path
        `path`.

    Examples
    --------
    >>> import tempfile
    >>> target = Path(tempfile.mkdtemp()) / "a.txt"
    >>> atomic_write(target, lambda tmp: tmp.write_text("done")).read_text()
    'done'
    """
    path = Path(path)
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    tmp = Path(name)
    try:
        writer(tmp)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path
