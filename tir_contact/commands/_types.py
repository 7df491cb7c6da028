"""argparse value types shared by the sub-commands (messages name the value given)."""

from __future__ import annotations

import argparse
import math

__all__ = [
    "finite_number",
    "non_negative_number",
    "positive_int",
    "positive_number",
    "positive_pair",
]


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
