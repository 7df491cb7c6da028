"""Analyse one video: footage in, per-frame and per-element contact numbers out.

The pass over the footage is streamed: a first pass reads at most ``reference_frames``
frames spread through the video for the free-surface reference and the contact contrast, the
second reads one frame at a time. Memory does not grow with the video length; only the
result tables (one row per frame and per element) do.

TIR view (thesis section 4.3.6): darkness ``D = 1 - I / I_ref`` against the free-surface
reference (:mod:`tir_contact.calibrate`), contact where ``D`` reaches half the contact
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
import math
import os
import time
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pandas as pd

from tir_contact._darkness import BoxDarkness, Normaliser, RawContactTest
from tir_contact._readers import IMAGE_SUFFIXES, FootageError
from tir_contact.calibrate import Reference, reference_from_frames
from tir_contact.features import EDGE_MARGIN_PX, BlockLayout, _element_records, _frame_rows
from tir_contact.illumination import lit_zone_from_file
from tir_contact.meta import META_FILENAME, clip_footage, read_meta_json
from tir_contact.reference import TirReference, measurable, tir_reference
from tir_contact.segment import (
    _box_and_counts,
    _label_box,
    estimate_contrast,
    segment_frame,
)
from tir_contact.side import ice_line_y_px, side_darkness, side_frame_features

logger = logging.getLogger(__name__)

__all__ = [
    "ELEMENT_COLUMNS",
    "FRAME_COLUMNS",
    "AnalysisOptions",
    "VideoAnalysis",
    "analyze_video",
    "output_name",
    "resolve_footage",
]

#: Columns of ``frames.csv``, in order (the first nine are those of the issue, then extras).
FRAME_COLUMNS = [
    "frame",
    "time_s",
    "block_in_view",
    "block_front_x_mm",
    "contact_area_mm2",
    "contact_ratio",
    "n_elements_in_contact",
    "front_peak_x_mm",
    "front_peak_contrast",
    "block_fully_in_view",
    "n_regions",
    "deflection_angle_deg",
    "tip_deflection_mm",
    "contact_at_lit_rim",
]

#: Columns of ``elements.csv``, in order (element 0 leads).
ELEMENT_COLUMNS = [
    "frame",
    "time_s",
    "element",
    "contact_area_mm2",
    "contact_length_mm",
    "front_edge_x_mm",
    "front_peak_x_mm",
    "front_peak_contrast",
    "liftoff_mm",
    "deflection_angle_deg",
    "front_peak_width_mm",
    "tip_deflection_mm",
]

#: Columns of ``regions.csv`` (every contact region, no geometry needed).
REGION_COLUMNS = [
    "frame",
    "time_s",
    "region",
    "area_mm2",
    "centroid_x_mm",
    "centroid_y_mm",
    "bbox_x0_mm",
    "bbox_y0_mm",
    "bbox_width_mm",
    "bbox_height_mm",
    "mean_darkness",
    "at_lit_rim",
]

#: Files that make a result complete (``--resume`` checks them).
RESULT_FILES = ("frames.csv", "elements.csv", "summary.json")

_RESULT_VERSION = 1


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
    overlay_frames: int = 4
    overlay_video: bool = False
    overlay_video_max_frames: int = 400
    regions: str = "auto"
    plots: bool = False
    parquet: bool = True

    def __post_init__(self) -> None:
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
        if not self.noise_sigmas > 0:
            raise ValueError(f"noise_sigmas must be > 0, got {self.noise_sigmas!r}")


@dataclass
class VideoAnalysis:
    """Result of :func:`analyze_video`.

    Attributes
    ----------
    frames : pandas.DataFrame
        One row per analysed frame (:data:`FRAME_COLUMNS`).
    elements : pandas.DataFrame
        One row per frame and element in contact or in view (:data:`ELEMENT_COLUMNS`).
    regions : pandas.DataFrame or None
        One row per frame and contact region (TIR view; :data:`REGION_COLUMNS`); None when
        not computed (see :attr:`AnalysisOptions.regions`).
    summary : dict
        What ``summary.json`` holds: steady values, reference, skipped frames, settings.
    out_dir : Path or None
        Where the results were written.
    """

    frames: pd.DataFrame
    elements: pd.DataFrame
    regions: pd.DataFrame | None
    summary: dict[str, Any]
    out_dir: Path | None = None
    skipped: list[dict[str, Any]] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """True when every frame was analysed."""
        return not self.skipped


def output_name(path: str | os.PathLike[str]) -> str:
    """Name of a video's result folder: the folder name or the file name without suffix.

    Examples
    --------
    >>> output_name("runs/G3_1mps/footage.avi"), output_name("runs/G3_1mps/frames")
    ('footage', 'frames')
    """
    p = Path(path)
    return p.name if p.is_dir() or not p.suffix else p.stem


def _images_in(folder: Path) -> int:
    try:
        return sum(1 for q in folder.iterdir()
                   if q.is_file() and not q.name.startswith(".")
                   and q.suffix.lower() in IMAGE_SUFFIXES)
    except OSError:
        return 0


def resolve_footage(path: str | os.PathLike[str], *, strict: bool = False) -> tuple[Path, str]:
    """The footage a path means, and its result name.

    A synthetic clip folder (``meta.json`` naming ``frames/...`` or a video file that
    exists) means its frames folder or video, named after the clip folder; this holds for
    a multi-page TIFF in the clip folder too.

    Parameters
    ----------
    path : str or os.PathLike
        What the user named.
    strict : bool
        Raise the ``meta.json`` error of a folder that holds no images and whose
        ``meta.json`` cannot be read (instead of reading the folder as frames, which then
        reports "no image files").

    Returns
    -------
    (Path, str)
        What the reader opens, and the result folder name.
    """
    p = Path(path)
    if p.is_dir():
        inner = clip_footage(p)
        if inner is not None and (inner.exists() or _images_in(p) == 0):
            return inner, p.name
        if strict and inner is None and (p / META_FILENAME).is_file() and _images_in(p) == 0:
            read_meta_json(p / META_FILENAME)  # raises the JSON error, naming the file
    return p, output_name(p)


def footage_fingerprint(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Sizes and modification times of the footage and its metadata (for ``--resume``)."""
    from tir_contact.meta import find_meta

    p = Path(path)
    files = sorted(q for q in p.iterdir() if q.is_file()) if p.is_dir() else [p]
    meta = find_meta(p)
    if meta is not None and meta not in files:
        files.append(meta)
    return {
        "files": len(files),
        "bytes": int(sum(q.stat().st_size for q in files)),
        "mtime_ns": int(max((q.stat().st_mtime_ns for q in files), default=0)),
    }


# --------------------------------------------------------------------------------------------
# reference and normalisation


def _read_reference_file(path: str, shape: tuple[int, int], min_relative: float = 0.2) -> Reference:
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise FootageError(f"{path}: cannot read the reference image", path)
    if image.ndim == 3:
        image = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    if image.shape != shape:
        raise FootageError(
            f"{path}: reference size {image.shape[1]}x{image.shape[0]} differs from the "
            f"footage's {shape[1]}x{shape[0]}",
            path,
        )
    image = image.astype(float)
    valid = image > min_relative * float(np.median(image))
    return Reference(image, valid, "file", 1)


def _frames_differ(samples: list[np.ndarray], reference: Reference, contact_is: str,
                   options: AnalysisOptions) -> bool:
    """True when some sampled frame has a block-sized region darker than the reference."""
    norm = Normaliser(reference, contact_is)
    need = options.min_block_fraction * reference.image.size
    return any(int((norm(f) > options.min_darkness).sum()) > need for f in samples)


# --------------------------------------------------------------------------------------------
# the per-video pass


@dataclass
class _Setup:
    meta: dict[str, Any]
    view: str
    contact_is: str
    fps: float
    mm_per_px: float
    layout: Any
    reference: Reference | None
    reference_method: str
    contrast: float | None
    n_frames: int
    shape: tuple[int, int]
    max_dn: float
    skipped: list[dict[str, Any]]
    numbers: np.ndarray  # recorded frame number of each readable frame (reader.frame_numbers)
    bad: set[int] = field(default_factory=set)  # indices of frames that could not be read
    grey_range: tuple[float, float] = (0.0, 0.0)  # 1st and 99th percentile of sampled pixels
    camera: str = "fixed"  # "fixed": the block passes the camera; "follows": it stays in view
    tir: TirReference | None = None  # lit zone, free surface and noise of a TIR video
    threshold: float = math.nan  # darkness threshold of contact (TIR)


def _sample_frames(reader: Any, n_sample: int, skipped: list[dict[str, Any]],
                   bad: set[int], numbers: np.ndarray) -> list[np.ndarray]:
    n = len(reader)
    idx = np.unique(np.linspace(0, n - 1, min(n, n_sample)).round().astype(int))
    frames = []
    for i in idx:
        try:
            frames.append(reader.get_frame(int(i)))
        except FootageError as exc:
            skipped.append({"frame": int(numbers[i]), "reason": str(exc)})
            bad.add(int(i))
    return frames


def _prepare(reader: Any, path: Path, overrides: Mapping[str, Any] | None,
             options: AnalysisOptions) -> _Setup:
    from tir_contact.meta import load_meta

    meta = load_meta(path, overrides, frame_rate=reader.frame_rate)
    n = len(reader)
    if n == 0:
        raise FootageError(f"{path}: the footage has no frames", path)
    view, contact_is = meta["view"], meta["contact_is"]
    skipped: list[dict[str, Any]] = []
    bad: set[int] = set()
    numbers = np.asarray(reader.frame_numbers, dtype=np.int64)
    samples = _sample_frames(reader, options.reference_frames, skipped, bad, numbers)
    if not samples:
        raise FootageError(f"{path}: none of the sampled frames could be read "
                           f"(first reason: {skipped[0]['reason']})", path)
    shape = samples[0].shape
    max_dn = float(meta.get("max_dn") or (2 ** reader.bit_depth - 1))
    pixels = np.concatenate([f[::4, ::4].ravel() for f in samples])
    grey_range = (float(np.percentile(pixels, 1)), float(np.percentile(pixels, 99)))
    reference: Reference | None
    tref: TirReference | None = None
    if view == "tir":
        tref = _tir_reference(samples, shape, contact_is, options)
        reference, method = tref.reference, tref.method
    elif options.reference is not None:
        reference = _read_reference_file(options.reference, shape)
        method = "file"
    elif len(samples) >= 5 and options.camera != "follows":
        reference = reference_from_frames(samples, contact_is=contact_is,
                                          percentile=options.percentile)
        method = "percentile"
        if options.camera == "auto" and not _frames_differ(samples, reference, contact_is,
                                                           options):
            # no sampled frame differs from the percentile image: the block is in every frame
            # (a camera following the block) or in none; the side view then normalises each
            # frame by its own background (tir_contact.side.side_darkness)
            reference, method = None, "per-frame background (no frame without the block)"
    else:
        reference, method = None, f"per-frame background ({len(samples)} frame(s) sampled)"
    contrast = options.contrast
    if contrast is None and view == "tir":
        norm = Normaliser(reference, contact_is)
        values = [estimate_contrast(norm(f), min_darkness=options.min_darkness) for f in samples]
        finite = [v for v in values if np.isfinite(v)]
        contrast = float(np.median(finite)) if finite else None
    threshold = math.nan
    if tref is not None:  # pixels too noisy for the threshold are not measured
        threshold = _threshold(contrast, options, tref.camera)
        tref = measurable(tref, threshold, n_sigma=options.noise_sigmas)
        reference = tref.reference
    layout = BlockLayout.from_meta(meta)
    camera = tref.camera if tref is not None else (
        "fixed" if reference is not None else "follows")
    return _Setup(meta, view, contact_is, float(meta["fps"]), float(meta["mm_per_px"]), layout,
                  reference, method, contrast, n, shape, max_dn, skipped, numbers, bad,
                  grey_range, camera, tref, threshold)


def _threshold(contrast: float | None, options: AnalysisOptions, camera: str) -> float:
    """The darkness threshold of contact: half the contrast, at least half ``min_darkness``.

    When nothing moves (``camera="follows"``) the free surface under a static dark spot is
    estimated, so ice texture (bubbles, scratches, dust: they remove at most about a third
    of the light, where contact removes most of it) would count as contact; the threshold
    is then at least ``static_min_darkness``.
    """
    floor = 0.5 * options.min_darkness
    if camera == "follows":
        floor = max(floor, options.static_min_darkness)
    if contrast is None or not math.isfinite(contrast):
        return floor
    return max(0.5 * contrast, floor)


def _tir_reference(samples: list[np.ndarray], shape: tuple[int, int], contact_is: str,
                   options: AnalysisOptions) -> TirReference:
    """Lit zone, camera mode, free surface and noise (:func:`tir_contact.reference.tir_reference`)
    with the user's lit mask and reference image, when given."""
    lit = lit_zone_from_file(options.lit_mask, shape) if options.lit_mask else None
    image = (_read_reference_file(options.reference, shape).image
             if options.reference is not None else None)
    try:
        return tir_reference(samples, contact_is=contact_is, percentile=options.percentile,
                             camera=options.camera, lit=lit, image=image,
                             min_darkness=options.min_darkness,
                             min_block_fraction=options.min_block_fraction)
    except ValueError as exc:
        raise FootageError(str(exc), options.lit_mask) from exc


def _fully_in_view(front_mm: float, setup: _Setup, margin_mm: float = 0.5) -> bool:
    if not math.isfinite(front_mm) or setup.layout.element_lengths_mm is None:
        return math.isfinite(front_mm)
    total = setup.layout.block_length_mm
    width_mm = setup.shape[1] * setup.mm_per_px
    back = front_mm + total if setup.layout.sliding_direction == "left" else front_mm - total
    lo, hi = min(front_mm, back), max(front_mm, back)
    return lo >= margin_mm and hi <= width_mm - margin_mm


class _FrameAnalyser:
    """Analyses single frames of one video with fixed settings."""

    def __init__(self, setup: _Setup, options: AnalysisOptions) -> None:
        self.setup = setup
        self.options = options
        self.normalise = (
            Normaliser(setup.reference, setup.contact_is) if setup.reference else None
        )
        self.ice_y_px: float | None = None
        rim = setup.tir.lit.rim if setup.tir is not None else None
        self._rim = rim if rim is not None and rim.any() else None
        self.want_regions = options.regions == "always" or (
            options.regions == "auto" and setup.layout.element_lengths_mm is None
        )
        # fast path (fixed reference and contrast): threshold the raw frame, compute the
        # darkness only around the contact (tir_contact._darkness)
        self._threshold = setup.threshold
        self._raw_tests: dict[str, RawContactTest | None] = {}  # by dtype character
        self._raw_buf: np.ndarray | None = None
        self._sums: tuple | None = None  # column sums of the last box darkness (fast path)
        self._box = (
            BoxDarkness(self.normalise, setup.shape)
            if self.normalise is not None and setup.view == "tir"
            else None
        )

    def darkness(self, frame: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.normalise(frame), self.normalise.valid

    def _raw_test(self, frame: np.ndarray) -> RawContactTest | None:
        if self._box is None or not math.isfinite(self._threshold):
            return None
        test = self._raw_tests.get(frame.dtype.char, False)
        if test is False:
            test = RawContactTest.build(self.normalise, self._threshold, frame.dtype)
            self._raw_tests[frame.dtype.char] = test
        return test

    def segment(self, frame: np.ndarray) -> tuple[np.ndarray, np.ndarray, Any]:
        """Darkness, valid mask and contact of a TIR frame."""
        test = self._raw_test(frame)
        raw = None
        self._sums = None
        if test is not None:  # into one reused buffer: `raw` does not outlive the frame
            if self._raw_buf is None or self._raw_buf.shape != frame.shape:
                self._raw_buf = np.empty(frame.shape, np.bool_)
            raw = test(frame, out=self._raw_buf)
        if raw is None:
            d, valid = self.darkness(frame)
            contact = segment_frame(d, contrast=2.0 * self._threshold,
                                    min_darkness=self.options.min_darkness,
                                    min_area_px=self.options.min_area_px)
            return d, valid, contact
        box, counts = _box_and_counts(raw)
        if box is None:
            d = self._box.clear()
        else:  # the rows and (widened) columns the features read
            rows = box[0]
            cols = slice(max(box[1].start - EDGE_MARGIN_PX, 0),
                         min(box[1].stop + EDGE_MARGIN_PX, raw.shape[1]))
            d = self._box.fill(frame, rows, cols)
            # the features' column sums, while the darkness is still in the cache
            self._sums = (rows.start, rows.stop, cols.start, cv2.reduce(
                d[rows, cols], 0, cv2.REDUCE_SUM, dtype=cv2.CV_32F).ravel())
        contact = _label_box(raw, self._threshold, d, self.options.min_area_px, box, counts)
        return d, self.normalise.valid, contact

    def tir(self, k: int, frame: np.ndarray) -> tuple[dict, np.ndarray, dict | None, Any]:
        row, el_rows, regions, contact = self.tir_rows(k, frame)
        return row, _element_records(el_rows), regions, contact

    def tir_rows(self, k: int, frame: np.ndarray) -> tuple[dict, list[tuple], dict | None, Any]:
        """:meth:`tir` with the elements as tuples of the fields of ``ELEMENT_DTYPE``."""
        s = self.setup
        t = k / s.fps
        d, valid, contact = self.segment(frame)
        row, el_rows = _frame_rows(d, contact, s.layout, valid, t, 1.0, self._sums)
        row["frame"] = k
        row["time_s"] = t
        row["n_regions"] = contact.n_regions
        row["block_fully_in_view"] = row["block_in_view"] and _fully_in_view(
            row["block_front_x_mm"], s)
        at_rim = self._at_rim(contact)
        row["contact_at_lit_rim"] = bool(at_rim[1:].any())
        regions = None
        if self.want_regions:
            regions = contact.region_arrays()
            regions["frame"] = np.full(contact.n_regions, k)
            regions["at_lit_rim"] = at_rim[1:]
        return row, el_rows, regions, contact

    def _at_rim(self, contact: Any) -> np.ndarray:
        """Which regions (index = label, 0 unused) touch the rim of the lit zone."""
        out = np.zeros(contact.n_regions + 1, bool)
        if self._rim is not None and contact.box is not None:
            out[np.unique(contact.box_labels[self._rim[contact.box]])] = True
            out[0] = False
        return out

    def side(self, k: int, frame: np.ndarray) -> tuple[dict, pd.DataFrame, Any]:
        s = self.setup
        t = k / s.fps
        d = side_darkness(frame, contact_is=s.contact_is, reference=s.reference)
        valid = s.reference.valid if s.reference is not None else None
        if self.ice_y_px is None and s.reference is not None:
            self.ice_y_px = ice_line_y_px(s.reference.image, contact_is=s.contact_is)
        feats = side_frame_features(d, s.layout, valid=valid, ice_y_px=self.ice_y_px)
        row = {"frame": k, "time_s": t, **feats.frame}
        row["block_fully_in_view"] = bool(row.get("block_in_view")) and _fully_in_view(
            row.get("block_front_x_mm", np.nan), s)
        el = feats.elements.copy()
        el.insert(0, "time_s", t)
        el.insert(0, "frame", k)
        return row, el, feats


def _reorder(df: pd.DataFrame, columns: list[str]) -> pd.DataFrame:
    """`columns` first (NaN where missing), then any further columns (`df` itself when it
    holds exactly `columns`, in order)."""
    if list(df.columns) == columns:
        return df
    for c in columns:
        if c not in df.columns:
            df[c] = np.nan
    return df[columns + [c for c in df.columns if c not in columns]]


def _concat(parts: list[pd.DataFrame], columns: list[str]) -> pd.DataFrame:
    parts = [p for p in parts if len(p)]
    return _reorder(pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(), columns)


def _element_frame(el: Any, k: int, fps: float) -> pd.DataFrame:
    """A frame's element rows as a DataFrame (records of the fast path, or a table)."""
    if isinstance(el, pd.DataFrame):
        return el
    df = pd.DataFrame({name: el[name] for name in el.dtype.names})
    df.insert(0, "time_s", k / fps)
    df.insert(0, "frame", k)
    return df


def _records_table(rows: list[tuple], frames: list[int], fps: float) -> pd.DataFrame:
    """The elements table from the element tuples of every frame, built once."""
    if not rows:
        return pd.DataFrame(columns=ELEMENT_COLUMNS)
    rec = _element_records(rows)
    frame = np.array(frames, dtype=np.int64)
    data = {"frame": frame, "time_s": frame / fps}
    data.update({name: rec[name] for name in rec.dtype.names})
    return _reorder(pd.DataFrame(data), ELEMENT_COLUMNS)


def _regions_table(regions: list[dict], setup: _Setup) -> pd.DataFrame:
    """``regions.csv`` in mm from the per-frame region arrays."""
    if not regions:
        return pd.DataFrame(columns=REGION_COLUMNS)
    cat = {key: np.concatenate([r[key] for r in regions]) for key in regions[0]}
    mm, mm2 = setup.mm_per_px, setup.mm_per_px ** 2
    return pd.DataFrame({
        "frame": cat["frame"], "time_s": cat["frame"] / setup.fps, "region": cat["label"],
        "area_mm2": cat["area_px"] * mm2,
        "centroid_x_mm": (cat["centroid_x_px"] + 0.5) * mm,
        "centroid_y_mm": (cat["centroid_y_px"] + 0.5) * mm,
        "bbox_x0_mm": cat["bbox_x0_px"] * mm, "bbox_y0_mm": cat["bbox_y0_px"] * mm,
        "bbox_width_mm": cat["bbox_width_px"] * mm, "bbox_height_mm": cat["bbox_height_px"] * mm,
        "mean_darkness": cat["mean_darkness"],
        "at_lit_rim": cat["at_lit_rim"].astype(bool),
    }, columns=REGION_COLUMNS)


def _steady(frames: pd.DataFrame, elements: pd.DataFrame) -> dict[str, Any]:
    """Means and standard deviations over the frames with the whole block in view.

    Each mean and standard deviation is pandas' own (``Series.mean``, ``Series.std``) of
    the selected values, without building the selected tables and groups.
    """
    full = frames["block_fully_in_view"].to_numpy().astype(bool)
    out: dict[str, Any] = {"n_frames": int(full.sum())}
    for col in ("contact_area_mm2", "contact_ratio", "front_peak_contrast",
                "deflection_angle_deg", "tip_deflection_mm"):
        if col not in frames:
            continue
        values = pd.Series(frames[col].to_numpy()[full])
        finite = int(values.notna().sum())
        if finite:
            out[col] = {"mean": float(values.mean()),
                        "std": float(values.std(ddof=1)) if finite > 1 else 0.0}
    if out["n_frames"] and len(elements):
        frame_no = elements["frame"].to_numpy()
        sel = np.isin(frame_no, frames["frame"].to_numpy()[full])
        element = elements["element"].to_numpy()
        columns = [c for c in ("contact_area_mm2", "contact_length_mm", "front_peak_contrast",
                               "liftoff_mm", "deflection_angle_deg", "tip_deflection_mm",
                               "front_peak_width_mm") if c in elements]
        arrays = {c: elements[c].to_numpy() for c in columns}
        per = {}
        for e in np.unique(element[sel]):  # ascending, as groupby
            rows = sel & (element == e)
            means = {}
            for col in columns:
                values = pd.Series(arrays[col][rows])
                if values.notna().any():
                    means[col] = float(values.mean())
            per[str(int(e))] = means
        out["elements"] = per
    return out


def _overlay_choice(frames: pd.DataFrame, n: int) -> list[int]:
    inview = frames[frames["block_in_view"].astype(bool)]
    if inview.empty or n <= 0:
        return [int(frames["frame"].iloc[len(frames) // 2])] if n > 0 and len(frames) else []
    picks = [int(inview["frame"].iloc[0]), int(inview["frame"].iloc[len(inview) // 2]),
             int(inview["frame"].iloc[-1])]
    if inview["contact_area_mm2"].notna().any():
        picks.append(int(inview.loc[inview["contact_area_mm2"].idxmax(), "frame"]))
    extra = np.linspace(0, len(inview) - 1, n + 2).round().astype(int)[1:-1]
    picks += [int(inview["frame"].iloc[i]) for i in extra]
    seen: list[int] = []
    for p in picks:
        if p not in seen:
            seen.append(p)
    return sorted(seen[:n])


def analyze_video(
    path: str | os.PathLike[str],
    out: str | os.PathLike[str] | None = None,
    *,
    overrides: Mapping[str, Any] | None = None,
    options: AnalysisOptions | None = None,
    name: str | None = None,
    progress: bool | None = False,
    progress_position: int = 0,
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
    from tqdm.auto import tqdm

    from tir_contact.io import open_footage

    options = options or AnalysisOptions()
    path, default_name = resolve_footage(path, strict=True)
    name = name or default_name
    t0 = time.perf_counter()
    with open_footage(path) as reader:
        setup = _prepare(reader, path, overrides, options)
        analyser = _FrameAnalyser(setup, options)
        rows: list[dict] = []
        elements: list[pd.DataFrame] = []
        el_rows: list[tuple] = []  # TIR element records, as tuples (one array at the end)
        el_frames: list[int] = []
        regions: list[dict] = []
        skipped = list(setup.skipped)
        bad = setup.bad
        numbers = setup.numbers.tolist()
        video = (
            _OverlayVideo(setup, options, Path(out))
            if out is not None and options.overlay_video
            else None
        )
        bar = tqdm(total=setup.n_frames, desc=name, unit="frame", leave=False,
                   disable=progress is False, position=progress_position, dynamic_ncols=True)
        tick = None if bar.disable else bar.update
        get_frame = reader.get_frame
        tir = analyser.tir_rows if setup.view == "tir" else None
        try:
            for i in range(setup.n_frames):
                if tick is not None:
                    tick(1)
                if i in bad:
                    continue
                k = numbers[i]  # the recorded frame number: time is k / fps
                try:
                    frame = get_frame(i)
                except FootageError as exc:
                    skipped.append({"frame": k, "reason": str(exc)})
                    logger.warning("%s", exc)
                    continue
                if tir is not None:
                    row, el, reg, contact = tir(k, frame)
                    if reg is not None:
                        regions.append(reg)
                    extra = contact
                    if el:
                        el_rows += el
                        el_frames += [k] * len(el)
                    if video is not None:
                        el = _element_records(el)
                else:
                    row, el, extra = analyser.side(k, frame)
                    elements.append(el)
                rows.append(row)
                if video is not None:
                    video.add(i, k, frame, row, el, extra)
        finally:
            bar.close()
            if video is not None:
                video.close()
        elapsed = time.perf_counter() - t0
        if setup.view == "tir" and rows:  # rows with exactly FRAME_COLUMNS: built by column
            frames_df = pd.DataFrame({c: [r[c] for r in rows] for c in FRAME_COLUMNS})
        else:
            frames_df = _reorder(pd.DataFrame(rows), FRAME_COLUMNS)
        if setup.view == "tir":
            elements_df = _records_table(el_rows, el_frames, setup.fps)
        else:
            elements_df = _concat(elements, ELEMENT_COLUMNS)
        regions_df = _regions_table(regions, setup) if analyser.want_regions else None
        if not len(frames_df):
            raise FootageError(
                f"{path}: no frame could be read (first reason: {skipped[0]['reason']})", path
            )
        skipped.sort(key=lambda s: s["frame"])
        summary = _summary(path, name, setup, options, frames_df, elements_df, skipped, elapsed,
                           lost=list(reader.lost_frames))
        for text in summary["warnings"]:  # the batch (and the CLI) reports them as warnings
            logger.info("%s: %s", path, text)
        result = VideoAnalysis(frames_df, elements_df, regions_df, summary, None, skipped)
        if out is not None:
            result.out_dir = _write(result, Path(out) / name, reader, analyser, video)
    return result


#: Below this fraction of full scale, the brightest 1 % of pixels are not a lit field.
DARK_FOOTAGE_FRACTION = 0.03
#: Above this fraction of full scale, the darkest 1 % of pixels are saturated.
SATURATED_FRACTION = 0.98


def footage_warnings(setup: _Setup, frames: pd.DataFrame, lost: list[int]) -> list[str]:
    """What the user must know about a video whose numbers may mean nothing.

    Footage without a lit field (black), saturated footage (white), a video in which no
    frame shows contact or the block, gaps in the recorded frame numbers, and frames lost
    from a container that was cut short.
    """
    out = []
    low, high = setup.grey_range
    if high <= DARK_FOOTAGE_FRACTION * setup.max_dn:
        out.append(f"no lit field: the brightest 1 % of pixels reach grey {high:.0f} of "
                   f"{setup.max_dn:.0f} (black footage?)")
    elif low >= SATURATED_FRACTION * setup.max_dn:
        out.append(f"saturated footage: even the darkest 1 % of pixels reach grey {low:.0f} "
                   f"of {setup.max_dn:.0f}")
    in_view = frames["block_in_view"].astype(bool)
    if len(frames) and not in_view.any():
        what = "contact" if setup.view == "tir" else "block"
        out.append(f"no {what} found in any of the {len(frames)} frames analysed "
                   f"(reference: {setup.reference_method})")
    if "contact_at_lit_rim" in frames and len(frames):
        at_rim = int(frames["contact_at_lit_rim"].astype(bool).sum())
        if at_rim:
            out.append(f"contact touches the rim of the lit zone in {at_rim} of {len(frames)} "
                       "frames: part of it may lie where too little light reaches to see it "
                       "(lit_mask.png; --lit-mask to give the zone)")
    numbers = setup.numbers
    jumps = np.flatnonzero(np.diff(numbers) > 1)
    if len(jumps):
        missing = int(sum(numbers[j + 1] - numbers[j] - 1 for j in jumps))
        first = int(jumps[0])
        out.append(f"{missing} frame number(s) missing from the footage in {len(jumps)} "
                   f"gap(s), the first from frame {numbers[first]} to {numbers[first + 1]}; "
                   "times follow the frame numbers")
    if lost:
        out.append(f"the container was cut short: {len(lost)} frame(s) lost "
                   f"({lost[0]}-{lost[-1]})")
    return out


def _gaps(numbers: np.ndarray) -> list[dict[str, int]]:
    jumps = np.flatnonzero(np.diff(numbers) > 1)
    return [{"after": int(numbers[j]), "before": int(numbers[j + 1]),
             "missing": int(numbers[j + 1] - numbers[j] - 1)} for j in jumps]


def _summary(path: Path, name: str, setup: _Setup, options: AnalysisOptions,
             frames: pd.DataFrame, elements: pd.DataFrame, skipped: list[dict[str, Any]],
             elapsed: float, lost: list[int]) -> dict[str, Any]:
    from tir_contact import __version__

    ref = setup.reference
    in_view = frames["block_in_view"].astype(bool)
    return {
        "result_version": _RESULT_VERSION,
        "complete": True,
        "video": str(path),
        "name": name,
        "view": setup.view,
        "n_frames": setup.n_frames,
        "n_frames_analysed": len(frames),
        "frames_without_block": int((~in_view).sum()),
        "frames_with_whole_block": int(frames["block_fully_in_view"].astype(bool).sum()),
        "skipped_frames": skipped,
        "lost_frames": lost,
        "frame_gaps": _gaps(setup.numbers),
        "warnings": footage_warnings(setup, frames, lost),
        "steady": _steady(frames, elements),
        "reference": {
            "method": setup.reference_method,
            "n_frames": ref.n_frames if ref is not None else 1,
            "excluded_fraction": ref.excluded_fraction if ref is not None else None,
        },
        "camera": setup.camera,
        **_tir_assumptions(setup),
        "contrast": setup.contrast,
        "threshold": _finite_or_none(setup.threshold),
        "meta": setup.meta,
        "options": asdict(options),
        "fingerprint": footage_fingerprint(path),
        "frames_per_s": len(frames) / elapsed if elapsed > 0 else None,
        "package_version": __version__,
    }


def _tir_assumptions(setup: _Setup) -> dict[str, Any]:
    """What the TIR analysis assumed about the light and the noise (``summary.json``)."""
    t = setup.tir
    if t is None:
        return {}
    lit = t.lit.mask
    sigma = t.noise.sigma_darkness(t.reference.image)
    measured = t.reference.valid
    return {
        "lit_fraction": float(lit.mean()),
        "lit_zone": {
            "method": t.lit.method,
            "fraction": float(lit.mean()),
            "bright_level": _finite_or_none(t.lit.bright_level),
            "black_level": _finite_or_none(t.lit.black_level),
            "measured_fraction": float(measured.mean()),
            "too_noisy_fraction": float((lit & ~measured).mean()),
        },
        "noise": {
            "grey_variance_a_dn2": t.noise.a,
            "grey_variance_b_dn": t.noise.b,
            "darkness_sigma_median": _finite_or_none(float(np.median(sigma[measured]))
                                                     if measured.any() else math.nan),
        },
    }


def _finite_or_none(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


class _OverlayVideo:
    """Streams every k-th overlay frame into ``overlay.avi`` in a staging file."""

    def __init__(self, setup: _Setup, options: AnalysisOptions, folder: Path) -> None:
        from tir_contact._outdir import temporary_name

        self.setup = setup
        self.step = max(1, math.ceil(setup.n_frames / options.overlay_video_max_frames))
        folder.mkdir(parents=True, exist_ok=True)
        self.path = folder / temporary_name("overlay", ".avi")
        self.writer = None

    def add(self, i: int, k: int, frame: np.ndarray, row: dict, el: Any, extra: Any) -> None:
        """Add frame index `i` (recorded frame number `k`) when it is on the video's step."""
        import cv2

        if i % self.step:
            return
        el = _element_frame(el, k, self.setup.fps)
        img = _draw(self.setup, k, frame, row, el, extra)
        if self.writer is None:
            fourcc = cv2.VideoWriter_fourcc(*"MJPG")
            fps = min(25.0, self.setup.fps)
            self.writer = cv2.VideoWriter(str(self.path), fourcc, fps,
                                          (img.shape[1], img.shape[0]))
        self.writer.write(img)

    def close(self) -> None:
        if self.writer is not None:
            self.writer.release()
            self.writer = None


def _draw(setup: _Setup, k: int, frame: np.ndarray, row: dict, el: pd.DataFrame,
          extra: Any) -> np.ndarray:
    from tir_contact.overlay import draw_side_overlay, draw_tir_overlay

    label = f"frame {k}  t = {k / setup.fps * 1e3:.2f} ms"
    if setup.view == "tir":
        lit, top = None, setup.max_dn
        if setup.tir is not None:  # dim footage is stretched to its lit level
            lit = setup.tir.lit.mask
            bright = setup.tir.lit.bright_level
            if math.isfinite(bright) and bright > 0:
                top = min(top, 1.1 * bright)
        return draw_tir_overlay(frame, extra.mask, el, row, mm_per_px=setup.mm_per_px,
                                max_dn=top, label=label, lit=lit)
    lines = getattr(extra, "lines", {}) or {}
    return draw_side_overlay(frame, el, lines, ice_y_px=getattr(extra, "ice_y_px", None),
                             max_dn=setup.max_dn, label=label)


def _write(result: VideoAnalysis, final: Path, reader: Any, analyser: _FrameAnalyser,
           video: _OverlayVideo | None) -> Path:
    import cv2

    from tir_contact._outdir import replace_folder, staging_folder, write_json
    from tir_contact.plots import plot_video_results

    options, setup = analyser.options, analyser.setup
    stage = staging_folder(final)
    try:
        tables = {"frames": result.frames, "elements": result.elements}
        if result.regions is not None:
            tables["regions"] = result.regions
        for stem, df in tables.items():
            df.to_csv(stage / f"{stem}.csv", index=False, lineterminator="\n",
                      float_format="%.6g")
        if options.parquet and _has_pyarrow():
            for stem, df in tables.items():
                df.to_parquet(stage / f"{stem}.parquet", index=False)
        if options.plots:
            plot_video_results(result.frames, result.elements, stage, view=setup.view,
                               title=result.summary["name"])
        if options.overlay_frames > 0:
            (stage / "overlays").mkdir()
            index_of = {int(n): i for i, n in enumerate(setup.numbers)}
            for k in _overlay_choice(result.frames, options.overlay_frames):
                try:
                    frame = reader.get_frame(index_of[k])
                except FootageError:
                    continue
                if setup.view == "tir":
                    row, el, _, extra = analyser.tir(k, frame)
                else:
                    row, el, extra = analyser.side(k, frame)
                cv2.imwrite(str(stage / "overlays" / f"frame_{k:06d}.png"),
                            _draw(setup, k, frame, row, _element_frame(el, k, setup.fps),
                                  extra))
        if video is not None and video.path.exists() and video.path.stat().st_size > 0:
            os.replace(video.path, stage / "overlay.avi")
        if setup.tir is not None:  # the lit zone, white where TIR light reaches
            cv2.imwrite(str(stage / "lit_mask.png"), setup.tir.lit.mask.astype(np.uint8) * 255)
        write_json(stage / "summary.json", result.summary)
        return replace_folder(stage, final)
    except BaseException:
        import shutil

        shutil.rmtree(stage, ignore_errors=True)
        raise
    finally:
        if video is not None:
            video.path.unlink(missing_ok=True)


def _has_pyarrow() -> bool:
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        return False
    return True
