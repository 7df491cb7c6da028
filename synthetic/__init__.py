"""Synthetic data with exact ground truth.

Public API
----------
Test-rig runs (:mod:`synthetic.rig`)
    :func:`make_raw_run`, :func:`write_run_csv`.
Measurement data with hidden, switchable effects (:mod:`synthetic.measurements`)
    :class:`EffectSpec`, :class:`SteadyGrid`, :func:`make_steady_table`,
    :func:`make_transient_table`, :func:`make_raw_runs`, :func:`write_measurements`.
Footage (:mod:`synthetic.footage`, TIR and side view; imported on use)
    :class:`FootageSpec`, :class:`CameraSettings`, :func:`iter_frames`,
    :func:`render_footage`.
"""

from importlib import import_module
from typing import Any

from synthetic.measurements import (
    EffectSpec,
    SteadyGrid,
    make_raw_runs,
    make_steady_table,
    make_transient_table,
    write_measurements,
)
from synthetic.rig import RUN_COLUMNS, make_raw_run, write_run_csv

_LAZY = ("CameraSettings", "FootageSpec", "iter_frames", "render_footage")

__all__ = [
    "RUN_COLUMNS",
    "CameraSettings",
    "EffectSpec",
    "FootageSpec",
    "SteadyGrid",
    "iter_frames",
    "make_raw_run",
    "make_raw_runs",
    "make_steady_table",
    "make_transient_table",
    "render_footage",
    "write_measurements",
    "write_run_csv",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(import_module("synthetic.footage"), name)
    raise AttributeError(f"module 'synthetic' has no attribute {name!r}")
