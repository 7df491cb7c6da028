"""Helpers that every package of the project may use; this package imports none of them.

:mod:`tir_common.atomic`
    :func:`atomic_write`, :func:`write_json`, :func:`json_safe`, :func:`make_temporary`: a
    file appears complete or not at all; one JSON encoding of numpy values.
:mod:`tir_common.validate`
    :func:`check_number` and its short forms: one message for a bad scalar parameter.
:mod:`tir_common.schema`
    :class:`Schema` of :class:`Field` s: one declarative check of a record (``meta.json``,
    a parameter file, a rig run's header); :class:`FieldError` names key, rule and value.
:mod:`tir_common.progress`
    :func:`progress_bar`: one tqdm bar, one meaning of ``progress=None`` (terminal only).
:mod:`tir_common.naming`
    :func:`natural_key`: ``run2`` before ``run10``.
"""

from tir_common.atomic import atomic_write, json_safe, make_temporary, write_json
from tir_common.naming import natural_key
from tir_common.progress import progress_bar, show_progress
from tir_common.schema import Field, FieldError, Schema
from tir_common.validate import (
    ParameterTypeError,
    check_nonnegative,
    check_number,
    check_positive,
    check_range,
    check_real,
)

__all__ = [
    "Field",
    "FieldError",
    "ParameterTypeError",
    "Schema",
    "atomic_write",
    "check_nonnegative",
    "check_number",
    "check_positive",
    "check_range",
    "check_real",
    "json_safe",
    "make_temporary",
    "natural_key",
    "progress_bar",
    "show_progress",
    "write_json",
]
