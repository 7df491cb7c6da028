"""argparse value types shared by the sub-commands (messages name the value given), and the
error a command raises for arguments that do not fit together."""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

__all__ = [
    "UsageError",
    "check_output_folder",
    "finite_number",
    "input_file",
    "non_negative_number",
    "output_file",
    "output_folder",
    "output_path",
    "positive_int",
    "positive_number",
    "positive_pair",
]


class UsageError(ValueError):
    """Arguments that do not fit together or name a missing input: ``tir-contact`` reports
    the message in one line and exits with code 2 (a usage error)."""


def finite_number(text: str) -> float:
    """A finite float.

    Examples
    --------
    >>> finite_number("2.5")
    2.5
    """
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def positive_number(text: str) -> float:
    """A finite float > 0."""
    value = finite_number(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"expected a finite number > 0, got {text!r}")
    return value


def non_negative_number(text: str) -> float:
    """A finite float >= 0."""
    value = finite_number(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a finite number >= 0, got {text!r}")
    return value


def positive_pair(text: str) -> tuple[float, float]:
    """Two finite floats > 0 written ``A,B``.

    Examples
    --------
    >>> positive_pair("1,5")
    (1.0, 5.0)
    """
    parts = text.split(",")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"expected two numbers 'A,B', got {text!r}")
    return positive_number(parts[0]), positive_number(parts[1])


def positive_int(text: str) -> int:
    """An integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}")
    return value


def input_file(text: str) -> Path:
    """argparse type of an input file option (``--reference IMAGE``): an existing file.

    Examples
    --------
    >>> input_file("/nonexistent/empty.png")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: /nonexistent/empty.png: no such file
    """
    path = Path(text)
    if not path.is_file():
        raise argparse.ArgumentTypeError(
            f"{path}: {'is a folder, expected a file' if path.is_dir() else 'no such file'}")
    return path


def check_output_folder(path: str | Path) -> Path:
    """Check that files can be written into folder `path` (created later where missing).

    The nearest existing folder on the way to `path` must be a folder in which a file can
    be created: a write is tried (a temporary file, removed at once), since permission bits
    do not show a read-only mount, an immutable folder or ``/proc``. Nothing is left behind.

    Parameters
    ----------
    path : str or Path
        The output folder.

    Returns
    -------
    Path
        `path` as a Path.

    Raises
    ------
    ValueError
        One line naming `path` and what is wrong with it.

    Examples
    --------
    >>> import tempfile
    >>> check_output_folder(Path(tempfile.mkdtemp()) / "new" / "out").name
    'out'
    """
    target = Path(path)
    probe = target
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    if not probe.is_dir():
        what = "is" if probe == target else f"lies under {probe}, which is"
        raise ValueError(f"{target}: {what} a file, not a folder")
    try:
        with tempfile.TemporaryFile(dir=probe):
            pass
    except OSError as exc:
        where = "" if probe == target else f" (in {probe})"
        raise ValueError(
            f"{target}: cannot write there{where}: {exc.strerror or exc}"
        ) from None
    return target


def output_folder(text: str) -> Path:
    """argparse type of ``--out DIR``: a folder files can be written into."""
    try:
        return check_output_folder(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def output_file(text: str) -> Path:
    """argparse type of ``--out FILE``: a file whose folder can be written into."""
    target = Path(text)
    if target.is_dir():
        raise argparse.ArgumentTypeError(f"{target}: is a folder, expected a file name")
    try:
        check_output_folder(target.parent if str(target.parent) else Path("."))
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"{target}: {exc}") from None
    return target


def output_path(text: str) -> Path:
    """argparse type of an ``--out`` that is a file or a folder, by what is written."""
    target = Path(text)
    try:
        check_output_folder(target.parent if target.is_file() else target)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return target
