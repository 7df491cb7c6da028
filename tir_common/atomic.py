"""Atomic file writes (a file appears complete or not at all) and JSON-safe values."""

from __future__ import annotations

import json
import math
import numbers
import os
import secrets
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

__all__ = ["atomic_write", "json_safe", "make_temporary", "write_json"]


def atomic_write(path: str | os.PathLike[str], writer: Callable[[Path], object]) -> Path:
    """Write through ``writer(tmp)`` to a temporary file beside `path`, then rename it.

    The temporary file keeps the suffix of `path` (so format-by-extension writers such as
    matplotlib's ``savefig`` work) and is removed when `writer` fails. It is created with
    the permissions a plain ``open(path, "w")`` gives (``0o666`` less the process umask,
    e.g. ``0o644`` under umask ``022``), not the owner-only ``0o600`` of
    :func:`tempfile.mkstemp`, so the renamed file is as readable as any other output.

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
    tmp = make_temporary(path.parent, f".{path.name}.", path.suffix)
    try:
        writer(tmp)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def make_temporary(folder: str | os.PathLike[str], prefix: str, suffix: str = "") -> Path:
    """Create a new empty file ``<folder>/<prefix><random><suffix>`` for writing.

    Like :func:`tempfile.mkstemp` (the name is new, the file created exclusively), but with
    the permissions a plain ``open(name, "w")`` gives: ``0o666`` less the process umask
    (``0o644`` under umask ``022``) instead of ``0o600``, so that a file later renamed to
    its final name is as readable as the other outputs.

    Parameters
    ----------
    folder : str or os.PathLike
        Existing folder.
    prefix, suffix : str
        Start and end of the file name.

    Returns
    -------
    Path
        The created file (empty, closed).

    Examples
    --------
    >>> import tempfile
    >>> tmp = make_temporary(tempfile.mkdtemp(), ".part-", ".csv")
    >>> tmp.name.startswith(".part-"), tmp.suffix, tmp.stat().st_size
    (True, '.csv', 0)
    """
    for _ in range(100):
        tmp = Path(folder) / f"{prefix}{secrets.token_hex(4)}{suffix}"
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"{folder}: no free temporary name {prefix}...{suffix}")


def json_safe(obj: Any) -> Any:
    """Plain JSON values: numpy scalars and arrays to Python, non-finite floats to None.

    Examples
    --------
    >>> import numpy as np
    >>> json_safe({"a": np.float64("nan"), "b": np.arange(2), 3: (np.int64(1), True)})
    {'a': None, 'b': [0, 1], '3': [1, True]}
    """
    if isinstance(obj, Mapping):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [json_safe(v) for v in obj]
    if hasattr(obj, "tolist") and not isinstance(obj, str):
        return json_safe(obj.tolist())
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, numbers.Integral):
        return int(obj)
    if isinstance(obj, numbers.Real):
        x = float(obj)
        return x if math.isfinite(x) else None
    return str(obj)


def write_json(path: str | os.PathLike[str], data: Any, *, sort_keys: bool = True) -> Path:
    """Write :func:`json_safe` `data` as indented UTF-8 JSON, atomically."""
    text = json.dumps(json_safe(data), indent=2, sort_keys=sort_keys, allow_nan=False) + "\n"
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))
