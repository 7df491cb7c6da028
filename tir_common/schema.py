"""One small declarative validator for records of named values: metadata, parameter files.

A :class:`Field` says what one key holds (its kind, bounds or choices, unit, whether it is
required and what it means); :meth:`Field.check` returns the value in its plain form (a float,
an int, a lower-case choice, ...) or raises :class:`FieldError`, whose message names the key,
what was expected and what was given::

    'fps' must be a number > 0, got -3 (int)

A :class:`Schema` is the set of fields of one record: :meth:`Schema.check` checks a whole
mapping (required keys present, no unknown keys when closed, every value). Callers put the
file (or command-line option) in front of the message and raise their own error type, so
every reader says the same things the same way. Scalar bounds are checked by
:func:`tir_common.validate.check_number`.

Kinds: ``"number"`` (finite real number), ``"integer"``, ``"text"``, ``"bool"``, ``"choice"``
(one of ``choices``, case-insensitive, returned in lower case), ``"object"`` (a mapping),
``"numbers"`` (a list of finite numbers) and ``"mapping"`` (names to a number or null).

Examples
--------
>>> fps = Field("fps", "number", "frame rate", unit="Hz", low=0, low_open=True)
>>> fps.check("5000", from_text=True)
5000.0
>>> fps.check(-3)
Traceback (most recent call last):
...
tir_common.schema.FieldError: 'fps' must be a number > 0, got -3 (int)
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from tir_common.validate import check_number

__all__ = ["KINDS", "Field", "FieldError", "Schema"]

#: The kinds a :class:`Field` may have.
KINDS = ("number", "integer", "text", "bool", "choice", "object", "numbers", "mapping")


class FieldError(ValueError):
    """A value that breaks its field: ``'<key>' <what>``, e.g. ``'fps' must be a number > 0``.

    Parameters
    ----------
    key : str
        The key concerned (dotted for nested keys, ``[i]`` for list items).
    what : str
        What is wrong, e.g. ``"must be a number > 0, got -3 (int)"`` or ``"is missing"``.
    expected : str, optional
        The expected type and range (:meth:`Field.expected`), when a value was wrong.
    value : object, optional
        The value given.
    """

    def __init__(self, key: str, what: str, *, expected: str = "", value: Any = None) -> None:
        super().__init__(f"'{key}' {what}")
        self.key = key
        self.what = what
        self.expected = expected
        self.value = value


def _show(value: Any, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters for messages."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _is_number(x: Any) -> bool:
    return isinstance(x, numbers.Real) and not isinstance(x, bool)


def _parse_number(text: str, decimal: str, integer: bool) -> float | int:
    """A number written as text; the decimal mark ``decimal`` or a point."""
    if integer:
        try:
            return int(text)
        except ValueError:
            pass
    if decimal == "," and "." not in text:
        text = text.replace(",", ".")
    return float(text)


@dataclass(frozen=True)
class Field:
    """What one key of a record holds.

    Parameters
    ----------
    key : str
        The key, dotted for a nested one (``"block.n_sipes"``).
    kind : str
        One of :data:`KINDS`.
    description : str
        Meaning, for help texts and documentation.
    unit : str
        Unit of a number (also in the key's name by the project's convention).
    required : bool
        Whether a record must give the key (:meth:`Schema.check`).
    low, high : float, optional
        Inclusive bounds of a number or integer; ``low_open`` makes the lower one exclusive.
    choices : tuple of str
        Allowed values of a ``"choice"`` (lower case).
    """

    key: str
    kind: str
    description: str = ""
    unit: str = ""
    required: bool = False
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    choices: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {self.kind!r}")
        if self.kind == "choice" and not self.choices:
            raise ValueError(f"field {self.key!r}: a choice needs choices")

    def expected(self) -> str:
        """The expected type and range, as said in error messages.

        Examples
        --------
        >>> Field("n", "integer", low=0).expected()
        'an integer >= 0'
        >>> Field("rh", "number", low=0, high=100).expected()
        'a number in [0, 100]'
        >>> Field("view", "choice", choices=("tir", "side")).expected()
        "one of 'tir', 'side'"
        """
        simple = {
            "text": "text",
            "bool": "true or false",
            "object": "a JSON object",
            "numbers": "a list of numbers",
            "mapping": "a JSON object of numbers",
        }
        if self.kind in simple:
            return simple[self.kind]
        if self.kind == "choice":
            return "one of " + ", ".join(repr(c) for c in self.choices)
        noun = "an integer" if self.kind == "integer" else "a number"
        if self.low is not None and self.high is not None:
            return f"{noun} in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}]"
        if self.low is not None:
            return f"{noun} {'>' if self.low_open else '>='} {self.low:g}"
        if self.high is not None:
            return f"{noun} <= {self.high:g}"
        return noun if self.kind == "integer" else "a finite number"

    def error(self, value: Any, key: str | None = None) -> FieldError:
        """The :class:`FieldError` saying that ``value`` is not what this field holds."""
        return FieldError(
            key or self.key,
            f"must be {self.expected()}, got {_show(value)} ({type(value).__name__})",
            expected=self.expected(),
            value=value,
        )

    def check(self, value: Any, *, from_text: bool = False, decimal: str = ".") -> Any:
        """Return ``value`` in its plain form, or raise :class:`FieldError`.

        Parameters
        ----------
        value : object
            The value read (JSON value, or text with ``from_text``).
        from_text : bool
            Accept a number written as text (a command-line option, a ``key: value`` line).
        decimal : str
            Decimal mark of such text (a point is always accepted).

        Returns
        -------
        object
            float for a number, int for an integer, the stripped lower-case text of a
            choice, a dict for an object or mapping, a list of floats for numbers.
        """
        if self.kind in ("number", "integer"):
            return self._check_number(value, from_text=from_text, decimal=decimal)
        if self.kind == "choice":
            if not isinstance(value, str) or value.strip().lower() not in self.choices:
                raise self.error(value)
            return value.strip().lower()
        if self.kind == "text":
            if not isinstance(value, str):
                raise self.error(value)
            return value
        if self.kind == "bool":
            if not isinstance(value, bool):
                raise self.error(value)
            return value
        if self.kind == "object":
            if not isinstance(value, Mapping):
                raise self.error(value)
            return dict(value)
        if self.kind == "numbers":
            return self._check_numbers(value)
        return self._check_mapping(value)

    def _check_number(self, value: Any, *, from_text: bool, decimal: str) -> float | int:
        integer = self.kind == "integer"
        number = value
        if isinstance(value, str) and from_text:
            try:
                number = _parse_number(value.strip(), decimal, integer)
            except ValueError:
                raise self.error(value) from None
        if not _is_number(number) or not math.isfinite(number):
            raise self.error(value)
        if integer:
            if not float(number).is_integer():
                raise self.error(value)
            number = int(number)
        try:
            check_number(self.key, number, low=self.low, high=self.high, low_open=self.low_open)
        except ValueError:
            raise self.error(value) from None
        return number if integer else float(number)

    def _check_numbers(self, value: Any) -> list[float]:
        if isinstance(value, str | bytes) or not isinstance(value, Iterable):
            raise self.error(value)
        out = list(value)
        item = Field(self.key, "number")
        for i, x in enumerate(out):
            if not _is_number(x) or not math.isfinite(x):
                raise item.error(x, key=f"{self.key}[{i}]")
        return [float(x) for x in out]

    def _check_mapping(self, value: Any) -> dict[str, float | None]:
        if not isinstance(value, Mapping):
            raise self.error(value)
        out: dict[str, float | None] = {}
        for k, x in value.items():
            if x is None or (isinstance(x, float) and not math.isfinite(x)):
                out[str(k)] = None  # not determined (e.g. an infinite standard error)
            elif _is_number(x) and math.isfinite(x):
                out[str(k)] = float(x)
            else:
                raise FieldError(
                    f"{self.key}.{k}",
                    f"must be a number or null, got {_show(x)} ({type(x).__name__})",
                    expected="a number or null",
                    value=x,
                )
        return out


@dataclass(frozen=True)
class Schema:
    """The fields of one record (a JSON object, a section of one, a file header).

    Parameters
    ----------
    name : str
        The record's name, said in messages about unknown keys.
    fields : tuple of Field
        Its fields; their keys are relative to the record (no prefix).
    closed : bool
        Whether keys without a field are errors (else they are kept as given).
    """

    name: str
    fields: tuple[Field, ...]
    closed: bool = True

    def __getitem__(self, key: str) -> Field:
        for f in self.fields:
            if f.key == key:
                return f
        raise KeyError(key)

    def __contains__(self, key: object) -> bool:
        return any(f.key == key for f in self.fields)

    @property
    def keys(self) -> tuple[str, ...]:
        """The keys of the fields, in order."""
        return tuple(f.key for f in self.fields)

    def check(self, record: Any, *, prefix: str = "") -> dict[str, Any]:
        """Check a whole record; JSON null counts as not given.

        Parameters
        ----------
        record : mapping
            The record.
        prefix : str
            Put before every key in messages (``"geometry."``).

        Returns
        -------
        dict
            Every given value of a field in its plain form, in field order, then (for an
            open schema) the other keys as given.

        Raises
        ------
        FieldError
            The record is not a mapping, a required key is missing, a value breaks its field,
            or (closed) a key has no field; the first problem in field order.
        """
        if not isinstance(record, Mapping):
            raise FieldError(
                prefix.rstrip(".") or self.name,
                f"must be a JSON object, got {type(record).__name__}",
                expected="a JSON object",
                value=record,
            )
        out: dict[str, Any] = {}
        for f in self.fields:
            value = record.get(f.key)
            if value is None:
                if f.required:
                    raise FieldError(prefix + f.key, "is missing")
                continue
            try:
                out[f.key] = f.check(value)
            except FieldError as exc:
                raise FieldError(
                    prefix + exc.key, exc.what, expected=exc.expected, value=exc.value
                ) from None
        unknown = sorted(set(record) - set(self.keys))
        if unknown and self.closed:
            raise FieldError(
                prefix + unknown[0],
                f"is not a known key of '{self.name}' (known: {sorted(self.keys)})",
            )
        for key in unknown:
            out[key] = record[key]
        return out
