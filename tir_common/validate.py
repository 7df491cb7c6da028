"""One validator for scalar parameters: the message names the parameter, the rule and the value.

Every package checks its scalar inputs through :func:`check_number` (or one of its short
forms), so that a bad value reads the same wherever it is given::

    speed_mps must be a finite number > 0, got speed_mps=-1.0

A value that is not a real number at all (a string, ``None``, ``True``) raises
:class:`ParameterTypeError`, which is both a :class:`TypeError` and a :class:`ValueError`, so
that callers catching either keep working.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = [
    "ParameterTypeError",
    "check_nonnegative",
    "check_number",
    "check_positive",
    "check_range",
    "check_real",
]


class ParameterTypeError(TypeError, ValueError):
    """A parameter that is not a real number (``bool`` and strings included)."""


def _as_real(name: str, value: object) -> float:
    if isinstance(value, bool | np.bool_ | str | bytes) or value is None:
        raise ParameterTypeError(
            f"{name} must be a real number, got {type(value).__name__} {value!r}"
        )
    if not isinstance(value, numbers.Real):
        try:
            if np.ndim(value) != 0:
                raise TypeError
            value = float(value)  # 0-d arrays and other real-valued scalars
        except (TypeError, ValueError):
            raise ParameterTypeError(
                f"{name} must be a real number, got {type(value).__name__} {value!r}"
            ) from None
    return float(value)


def check_number(
    name: str,
    value: object,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    unit: str = "",
) -> float:
    """Return ``value`` as a finite float within its bounds, else raise with a clear message.

    Parameters
    ----------
    name : str
        The parameter's name, as the user wrote it (with its unit suffix, ``speed_mps``).
    value : object
        A real number (Python or numpy scalar, 0-d array); ``bool`` and strings are refused.
    low, high : float, optional
        Inclusive bounds; ``low_open=True`` makes the lower bound exclusive (``> low``),
        ``high_open=True`` the upper one (``< high``).
    unit : str
        Unit written after the bounds in the message.

    Returns
    -------
    float

    Raises
    ------
    ParameterTypeError
        ``value`` is not a real number.
    ValueError
        ``value`` is NaN, infinite or outside the bounds.

    Examples
    --------
    >>> check_number("mu", 0.2, low=0, high=1)
    0.2
    >>> check_number("gap_m", 0.0, low=0, low_open=True)
    Traceback (most recent call last):
    ...
    ValueError: gap_m must be a finite number > 0, got gap_m=0.0
    >>> check_number("vignetting", 1.0, low=0, high=1, high_open=True)
    Traceback (most recent call last):
    ...
    ValueError: vignetting must lie in [0, 1), got vignetting=1.0
    """
    x = _as_real(name, value)
    below = low is not None and (x <= low if low_open else x < low)
    above = high is not None and (x >= high if high_open else x > high)
    if math.isfinite(x) and not below and not above:
        return x
    u = f" {unit}" if unit else ""
    if low is not None and high is not None:
        left, right = "(" if low_open else "[", ")" if high_open else "]"
        rule = f"lie in {left}{low:g}, {high:g}{right}{u}"
    elif low is not None:
        rule = f"be a finite number {'>' if low_open else '>='} {low:g}{u}"
    elif high is not None:
        rule = f"be a finite number {'<' if high_open else '<='} {high:g}{u}"
    else:
        rule = "be finite"
    raise ValueError(f"{name} must {rule}, got {name}={x!r}")


def check_positive(name: str, value: object) -> float:
    """:func:`check_number` with ``value > 0``."""
    return check_number(name, value, low=0.0, low_open=True)


def check_nonnegative(name: str, value: object) -> float:
    """:func:`check_number` with ``value >= 0``."""
    return check_number(name, value, low=0.0)


def check_range(name: str, value: object, low: float, high: float, *, unit: str = "") -> float:
    """:func:`check_number` with ``low <= value <= high``."""
    return check_number(name, value, low=low, high=high, unit=unit)



def check_real(name: str, value: object, *, rule: str = "finite") -> float:
    """:func:`check_number` with a rule written as text: ``"finite"``, ``"> 0"`` or ``">= 0"``."""
    if rule == "finite":
        return check_number(name, value)
    if rule == "> 0":
        return check_positive(name, value)
    if rule == ">= 0":
        return check_nonnegative(name, value)
    raise ValueError(f"rule must be 'finite', '> 0' or '>= 0', got {rule!r}")
