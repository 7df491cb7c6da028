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
    :func:`render_footage`; real footage: :class:`LitZone`, :func:`lit_zone`,
    :func:`lit_mask`, :func:`model_contact_ratio`, :data:`REAL_TRUTH_COLUMNS`.
Real-footage domain (:mod:`synthetic.domain`; imported on use)
    :func:`sample_spec`, :func:`sample_specs`, :data:`CASE_CLASSES`,
    :func:`real_photo_specs`.
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

_LAZY = {
    "CameraSettings": "synthetic.footage",
    "FootageSpec": "synthetic.footage",
    "LitZone": "synthetic.footage",
    "REAL_TRUTH_COLUMNS": "synthetic.footage",
    "iter_frames": "synthetic.footage",
    "lit_mask": "synthetic.footage",
    "lit_zone": "synthetic.footage",
    "model_contact_ratio": "synthetic.footage",
    "render_footage": "synthetic.footage",
    "CASE_CLASSES": "synthetic.domain",
    "sample_spec": "synthetic.domain",
    "sample_specs": "synthetic.domain",
    "real_photo_specs": "synthetic.domain",
}

__all__ = [
    "CASE_CLASSES",
    "REAL_TRUTH_COLUMNS",
    "RUN_COLUMNS",
    "CameraSettings",
    "EffectSpec",
    "FootageSpec",
    "LitZone",
    "SteadyGrid",
    "iter_frames",
    "lit_mask",
    "lit_zone",
    "make_raw_run",
    "make_raw_runs",
    "make_steady_table",
    "make_transient_table",
    "model_contact_ratio",
    "real_photo_specs",
    "render_footage",
    "sample_spec",
    "sample_specs",
    "write_measurements",
    "write_run_csv",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'synthetic' has no attribute {name!r}")
