"""Settings of the footage analysis (:class:`AnalysisOptions`)."""

from __future__ import annotations

import math
import numbers
import os
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

__all__ = ["AnalysisOptions", "checked_options"]


@dataclass(frozen=True)
class AnalysisOptions:
    """Settings of the analysis (all have defaults that suit the synthetic footage).

    Parameters
    ----------
    reference : str or Path, optional
        Image file of the free surface (no block); built from the footage when omitted.
    reference_frames : int
        Frames sampled for the reference and the contrast (spread through the video).
    percentile : float
        Per-pixel percentile of the sampled frames taken as the free surface.
    contrast : float, optional
        Contact darkness; the threshold is half of it. Estimated from the sampled frames
        (median darkness of clearly dark pixels) when omitted.
    min_darkness : float
        Darkness above which a pixel is surely contact (see
        :func:`tir_contact.segment.estimate_contrast`).
    min_area_px : int
        Smaller contact regions are dropped (noise, dust).
    min_block_fraction : float
        A region that moves through the sampled frames over more than this fraction of the
        lit zone means the block passes a fixed camera (camera mode detection).
    lit_mask : str or Path, optional
        Image file, non-zero where TIR light reaches (the frame's size); found from the
        footage when omitted (:func:`tir_contact.illumination.find_lit_zone`).
    camera : {"auto", "fixed", "follows"}
        ``"fixed"``: the block passes a fixed camera (frames without it give the free
        surface); ``"follows"``: the contact stays in view (camera following the block,
        static test, single image); ``"auto"`` detects it.
    noise_sigmas : float
        Lit pixels whose darkness noise times this reaches the contact threshold are not
        measured (5: a noise peak crosses the threshold in fewer than 1 of 10^6 pixels).
    static_min_darkness : float
        Lowest contact threshold when nothing moves (``camera="follows"``): ice texture
        (bubbles, scratches, dust) removes at most about a third of the light and cannot
        be told from contact by motion there.
    peak_window_mm : float
        Length behind an element's front edge (TIR) searched for the front-edge pressure
        peak, mm (at most half the element's contact is searched); 1 mm holds the 0.4 mm
        edge band of a new sample.
    overlay_frames : int
        Overlay images written (first, middle and last frames with the block, the frame of
        largest contact, ...).
    overlay_video : bool
        Write ``overlay.avi`` (every k-th frame, at most ``overlay_video_max_frames``). Off
        by default: drawing and encoding the frames costs about as much as the analysis.
    overlay_video_max_frames : int
        Frame budget of the overlay video.
    regions : {"auto", "always", "never"}
        Write ``regions.csv`` (every contact region: area, centroid, bounding box).
        ``"auto"``: only when no block geometry is known (then it is the main result).
    plots : bool
        Write the PNG plots of the results over time (:mod:`tir_contact.plots`). Off by
        default: matplotlib costs about 0.1 s a video, and 1 s in each new process.
    parquet : bool
        Also write Parquet copies of the tables when pyarrow is installed.
    """

    reference: str | None = None
    reference_frames: int = 32
    percentile: float = 90.0
    contrast: float | None = None
    min_darkness: float = 0.25
    min_area_px: int = 4
    min_block_fraction: float = 0.02
    lit_mask: str | None = None
    camera: str = "auto"
    noise_sigmas: float = 5.0
    static_min_darkness: float = 0.4
    peak_window_mm: float = 1.0
    overlay_frames: int = 4
    overlay_video: bool = False
    overlay_video_max_frames: int = 400
    regions: str = "auto"
    plots: bool = False
    parquet: bool = True

    def __post_init__(self) -> None:
        for f in fields(self):
            _check_type(f.name, getattr(self, f.name), f.type)
        if self.reference_frames < 1:
            raise ValueError(f"reference_frames must be >= 1, got {self.reference_frames!r}")
        if self.contrast is not None and not 0.0 < self.contrast <= 2.0:
            raise ValueError(f"contrast must lie in (0, 2], got {self.contrast!r}")
        if self.min_area_px < 1:
            raise ValueError(f"min_area_px must be >= 1, got {self.min_area_px!r}")
        if self.regions not in ("auto", "always", "never"):
            raise ValueError(f"regions must be 'auto', 'always' or 'never', got {self.regions!r}")
        if self.camera not in ("auto", "fixed", "follows"):
            raise ValueError(f"camera must be 'auto', 'fixed' or 'follows', got {self.camera!r}")
        if not (math.isfinite(self.peak_window_mm) and self.peak_window_mm > 0):
            raise ValueError(f"peak_window_mm must be a finite number > 0, got "
                             f"{self.peak_window_mm!r}")
        if not self.noise_sigmas > 0:
            raise ValueError(f"noise_sigmas must be > 0, got {self.noise_sigmas!r}")


#: What each annotation of :class:`AnalysisOptions` takes (a file option also a path).
_TYPES: dict[str, tuple[tuple[type, ...], str]] = {
    "int": ((numbers.Integral,), "an int"),
    "float": ((numbers.Real,), "a number"),
    "float | None": ((numbers.Real, type(None)), "a number or None"),
    "bool": ((bool, np.bool_), "True or False"),
    "str": ((str,), "a str"),
    "str | None": ((str, os.PathLike, type(None)), "a file path or None"),
}


def _check_type(name: str, value: Any, annotation: str) -> None:
    """A TypeError naming the option, what it takes and what it got (a bool is no number:
    ``min_area_px=True`` is a slip)."""
    allowed, what = _TYPES[annotation]
    if isinstance(value, bool | np.bool_) and bool not in allowed:
        ok = False
    else:
        ok = isinstance(value, allowed)
    if not ok:
        raise TypeError(f"AnalysisOptions: {name} must be {what}, got {value!r} "
                        f"({type(value).__name__})")


def checked_options(options: Any) -> AnalysisOptions:
    """`options` as given, :class:`AnalysisOptions` defaults for None; anything else is a
    TypeError that shows how to give them (a dict is not taken: a misspelt key would be
    lost the way the dataclass refuses it).

    Examples
    --------
    >>> checked_options(None).min_area_px
    4
    >>> checked_options({"contrast": 0.9})
    Traceback (most recent call last):
    ...
    TypeError: options must be an AnalysisOptions, e.g. AnalysisOptions(contrast=0.9), got dict
    """
    if options is None:
        return AnalysisOptions()
    if isinstance(options, AnalysisOptions):
        return options
    example = ""
    if isinstance(options, dict) and options:
        key, value = next(iter(options.items()))
        example = f"{key}={value!r}"
    raise TypeError(f"options must be an AnalysisOptions, e.g. AnalysisOptions({example}), "
                    f"got {type(options).__name__}")
