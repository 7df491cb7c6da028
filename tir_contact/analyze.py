"""Analyse one video: footage in, per-frame and per-element contact numbers out.

The pass over the footage is streamed: a first pass reads at most ``reference_frames``
frames spread through the video for the free-surface reference and the contact contrast, the
second reads one frame at a time. Memory does not grow with the video length; only the
result tables (one row per frame and per element) do.

TIR view (thesis section 4.3.6): darkness ``D = 1 - I / I_ref`` against the free-surface
reference (:mod:`tir_contact.flatfield`), contact where ``D`` reaches half the contact
contrast (:mod:`tir_contact.segment`), then block position, elements, front-edge peaks,
lift-off and deflection (:mod:`tir_contact.features`). Side view: element chords and
deflection angles (:mod:`tir_contact.side`).

Reference (TIR, :func:`tir_contact.reference.tir_reference`). The lit zone, where TIR light
reaches, is found on the bright image (each pixel's 90th percentile over the sampled frames);
nothing outside it is ever contact. The camera mode is detected: when something moves
through the sampled frames the block passes a fixed camera and the percentile image is the
free surface; when nothing moves (a camera following the block, a static test, a single
image) the free surface under the contact is estimated from the median image itself
(:func:`tir_contact.reference.free_surface`). The free-surface noise is measured, and lit
pixels whose darkness noise would reach the contact threshold (the soft rim of the lit
zone) are not measured. Side view: the percentile reference when frames without the block
exist, else each frame's own background. ``summary.json`` says what was assumed (lit
fraction, camera mode, reference method, noise); ``--lit-mask``, ``--reference`` and
``--camera`` override it.
"""


from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from tir_common.progress import progress_bar
from tir_contact._readers import FootageError
from tir_contact.frame import FrameAnalyser, FrameResult, analyze_frame
from tir_contact.io import open_footage
from tir_contact.options import AnalysisOptions, checked_options
from tir_contact.outputs import (
    ELEMENT_COLUMNS,
    FRAME_COLUMNS,
    REGION_COLUMNS,
    RESULT_FILES,
    Tables,
    VideoAnalysis,
    _OverlayVideo,
    _summary,
    footage_warnings,
    write_results,
)
from tir_contact.prepare import (
    VideoSetup,
    footage_fingerprint,
    output_name,
    prepare_video,
    resolve_footage,
)

logger = logging.getLogger(__name__)

__all__ = [
    "ELEMENT_COLUMNS",
    "FRAME_COLUMNS",
    "REGION_COLUMNS",
    "RESULT_FILES",
    "AnalysisOptions",
    "FrameAnalyser",
    "FrameResult",
    "VideoAnalysis",
    "VideoSetup",
    "analyze_frame",
    "analyze_video",
    "footage_fingerprint",
    "footage_warnings",
    "output_name",
    "prepare_video",
    "resolve_footage",
]


def analyze_video(
    path: str | os.PathLike[str],
    out: str | os.PathLike[str] | None = None,
    *,
    overrides: Mapping[str, Any] | None = None,
    options: AnalysisOptions | None = None,
    name: str | None = None,
    progress: bool | None = False,
    progress_position: int = 0,
    on_frame: Callable[[FrameResult], None] | None = None,
) -> VideoAnalysis:
    """Analyse one video (TIR or side view, as ``meta.json`` says).

    Parameters
    ----------
    path : str or os.PathLike
        Footage: a frame folder or a video/stack/camera file (see
        :func:`tir_contact.io.open_footage`), with its ``meta.json``.
    out : str or os.PathLike, optional
        Output root; results go to ``out/<name>/`` (written to a staging folder and moved
        into place when complete). Nothing is written when omitted.
    overrides : mapping, optional
        Metadata by dotted key, winning over ``meta.json`` (see
        :func:`tir_contact.meta.load_meta`).
    options : AnalysisOptions, optional
        Analysis settings.
    name : str, optional
        Result folder name; :func:`output_name` of `path` by default.
    progress : bool or None
        Show a progress bar (None: only on a terminal).
    progress_position : int
        Line of the progress bar (for parallel batches).
    on_frame : callable, optional
        Called with each frame's :class:`~tir_contact.frame.FrameResult` as it is made
        (e.g. to look at its contact mask, ``result.detail.mask``, which the tables do not
        keep).

    Returns
    -------
    VideoAnalysis

    Raises
    ------
    FootageError
        The footage cannot be opened, has no frames, or its metadata is missing or wrong.
        Single unreadable frames do not raise: they are skipped and listed in
        ``summary["skipped_frames"]``.

    Examples
    --------
    >>> import tempfile, json, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> frames = np.full((8, 16, 24), 200, np.uint8); frames[4, 5:10, 10:20] = 40
    >>> import tifffile; tifffile.imwrite(folder / "clip.tif", frames)
    >>> meta = {"fps": 1000, "mm_per_px": 0.1, "sliding_direction": "left"}
    >>> _ = (folder / "meta.json").write_text(json.dumps(meta))
    >>> result = analyze_video(folder / "clip.tif")
    >>> round(float(result.frames.loc[4, "contact_area_mm2"]), 6)  # 5 x 10 px of 0.01 mm2
    0.5
    """
    options = checked_options(options)
    path, default_name = resolve_footage(path, strict=True)
    name = name or default_name
    t0 = time.perf_counter()
    with open_footage(path) as reader:
        setup = prepare_video(reader, path, overrides, options)
        analyser = FrameAnalyser(setup, options)
        tables = Tables(setup, analyser.want_regions)
        skipped = list(setup.skipped)
        video = (
            _OverlayVideo(setup, options, Path(out))
            if out is not None and options.overlay_video
            else None
        )
        bar = progress_bar(setup.n_frames, progress=progress, desc=name, unit="frame",
                           leave=False, position=progress_position)
        try:
            for i, k, frame in _frames(reader, setup, skipped, None if bar.disable else bar):
                result = analyser(k, frame)
                tables.add(result)
                if on_frame is not None:
                    on_frame(result)
                if video is not None:
                    video.add(i, frame, result)
        finally:
            bar.close()
            if video is not None:
                video.close()
        elapsed = time.perf_counter() - t0
        frames_df = tables.frames()
        if not len(frames_df):
            raise FootageError(
                f"{path}: no frame could be read (first reason: {skipped[0]['reason']})", path
            )
        elements_df = tables.elements()
        skipped.sort(key=lambda s: s["frame"])
        summary = _summary(path, name, setup, options, frames_df, elements_df, skipped, elapsed,
                           lost=list(reader.lost_frames))
        for text in summary["warnings"]:  # the batch (and the CLI) reports them as warnings
            logger.info("%s: %s", path, text)
        result = VideoAnalysis(frames_df, elements_df, tables.regions(), summary, None, skipped)
        if out is not None:
            result.out_dir = write_results(result, Path(out) / name, reader, analyser, options,
                                           video)
    return result


def _frames(reader: Any, setup: VideoSetup, skipped: list[dict[str, Any]],
            bar: Any) -> Iterator[tuple[int, int, np.ndarray]]:
    """``(index, recorded frame number, frame)`` of every readable frame, streamed; frames
    that cannot be read are added to `skipped` and logged."""
    numbers = setup.numbers.tolist()
    get_frame = reader.get_frame
    for i in range(setup.n_frames):
        if bar is not None:
            bar.update(1)
        if i in setup.bad:
            continue
        k = numbers[i]  # the recorded frame number: time is k / fps
        try:
            frame = get_frame(i)
        except FootageError as exc:
            skipped.append({"frame": k, "reason": str(exc)})
            logger.warning("%s", exc)
            continue
        yield i, k, frame
