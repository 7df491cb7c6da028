"""tir-contact: TIR contact analysis of tread blocks sliding on ice.

Public API (imported lazily so that ``tir-contact --help`` stays fast)
----------------------------------------------------------------------
Footage readers (:mod:`tir_contact.io`)
    :func:`open_footage`, :class:`FootageReader`, :class:`FrameFolderReader`,
    :class:`MultiPageTiffReader`, :class:`VideoFileReader`, :class:`MrawReader`,
    :class:`CineReader`, :class:`ArrayReader`, :class:`FootageError`; the readers' registry
    :func:`register_reader`, :func:`unregister_reader`, :func:`readers`.
Metadata (:mod:`tir_contact.meta`)
    :func:`load_meta`; full contact's darkness from the rig's optics
    (:mod:`tir_contact.optics`): :func:`contact_darkness`.
Reference and segmentation (:mod:`tir_contact.flatfield`, :mod:`tir_contact.segment`)
    :func:`reference_from_frames`, :func:`reference_from_frame`, :func:`darkness`,
    :class:`Reference`, :func:`segment_frame`, :class:`FrameContact`, :func:`region_table`;
    a user's reference fitted to the footage (:mod:`tir_contact.reference_fit`):
    :func:`fit_reference`, :class:`ReferenceFit`.
Features (:mod:`tir_contact.features`, :mod:`tir_contact.side`)
    :class:`BlockLayout`, :func:`tir_frame_features`, :func:`tir_frame_records`,
    :class:`FrameFeatures`, :class:`FreeLevel` (graded contact, :mod:`tir_contact.graded`),
    :func:`side_frame_features`, :func:`side_darkness`,
    :func:`ice_line_y_px`, :func:`block_span_px`, :class:`SideFeatures`.
Views (:mod:`tir_contact.view`, :mod:`tir_contact.tir_view`, :mod:`tir_contact.side_view`)
    :class:`View`, :class:`TirView`, :class:`SideView`, :class:`FrameResult`: one object per
    view, prepared per video, with its per-frame step.
Whole videos and batches (:mod:`tir_contact.analyze`, :mod:`tir_contact.batch`)
    :func:`analyze_video`, :class:`AnalysisOptions`, :class:`VideoAnalysis`,
    :func:`find_footage`, :func:`analyze_batch`, :class:`BatchReport`.
The demo (:mod:`tir_contact.demo`)
    :func:`run_demo`, :class:`DemoResult`.

The friction model and the test-rig evaluation are in the sibling package
:mod:`friction_model`; synthetic data in :mod:`synthetic`.
"""

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version
from typing import Any

try:
    __version__ = version("tir-contact")
except PackageNotFoundError:  # pragma: no cover - running from a source tree without install
    __version__ = "0.0.0+unknown"

_LAZY = {
    "ArrayReader": "tir_contact.io",
    "CineReader": "tir_contact.io",
    "FootageError": "tir_contact.io",
    "FootageReader": "tir_contact.io",
    "FrameFolderReader": "tir_contact.io",
    "MrawReader": "tir_contact.io",
    "MultiPageTiffReader": "tir_contact.io",
    "VideoFileReader": "tir_contact.io",
    "load_meta": "tir_contact.meta",
    "contact_darkness": "tir_contact.optics",
    "Reference": "tir_contact.flatfield",
    "darkness": "tir_contact.flatfield",
    "reference_from_frame": "tir_contact.flatfield",
    "reference_from_frames": "tir_contact.flatfield",
    "ReferenceFit": "tir_contact.reference_fit",
    "fit_reference": "tir_contact.reference_fit",
    "FrameContact": "tir_contact.segment",
    "segment_frame": "tir_contact.segment",
    "open_footage": "tir_contact.io",
    "region_table": "tir_contact.segment",
    "BlockLayout": "tir_contact.features",
    "FrameFeatures": "tir_contact.features",
    "tir_frame_features": "tir_contact.features",
    "tir_frame_records": "tir_contact.features",
    "FreeLevel": "tir_contact.graded",
    "SideFeatures": "tir_contact.side",
    "side_darkness": "tir_contact.side",
    "side_frame_features": "tir_contact.side",
    "ice_line_y_px": "tir_contact.side",
    "block_span_px": "tir_contact.side",
    "View": "tir_contact.view",
    "FrameResult": "tir_contact.view",
    "TirView": "tir_contact.tir_view",
    "SideView": "tir_contact.side_view",
    "AnalysisOptions": "tir_contact.analyze",
    "VideoAnalysis": "tir_contact.analyze",
    "analyze_video": "tir_contact.analyze",
    "BatchReport": "tir_contact.batch",
    "analyze_batch": "tir_contact.batch",
    "find_footage": "tir_contact.batch",
    "readers": "tir_contact.io",
    "register_reader": "tir_contact.io",
    "unregister_reader": "tir_contact.io",
    "DemoResult": "tir_contact.demo",
    "run_demo": "tir_contact.demo",
}

__all__ = ["__version__", *sorted(_LAZY)]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'tir_contact' has no attribute {name!r}")
