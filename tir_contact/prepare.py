"""Before the first frame: footage, metadata, reference and threshold of one video.

:func:`prepare_video` reads the metadata and a sample of frames spread through the video
and returns a :class:`VideoSetup`, everything the per-frame step
(:mod:`tir_contact.frame`) needs. :func:`resolve_footage` says what a user's path means.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from scipy.stats import norm

from tir_contact._darkness import Normaliser
from tir_contact._percentile import pixelwise_percentile
from tir_contact._readers import IMAGE_SUFFIXES, FootageError
from tir_contact.features import BlockLayout
from tir_contact.flatfield import Reference, reference_from_frames
from tir_contact.illumination import lit_zone_from_file
from tir_contact.measure import AreaModel, area_model
from tir_contact.meta import META_FILENAME, clip_footage, find_meta, load_meta, read_meta_json
from tir_contact.options import AnalysisOptions
from tir_contact.reference import TirReference, measurable, tir_reference
from tir_contact.reference_fit import MAX_NOISE_RATIO, ReferenceFit, fit_reference
from tir_contact.segment import estimate_contrast
from tir_contact.side import block_span_px, ice_line_tilt_deg, ice_line_y_px, level_image

__all__ = [
    "VideoSetup",
    "footage_fingerprint",
    "output_name",
    "prepare_video",
    "resolve_footage",
]


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


def _read_reference_file(path: str, shape: tuple[int, int], min_relative: float = 0.2) -> Reference:

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
    """True when some sampled side-view frame has a block-sized region darker than the
    reference above the ice line (below it the ice moves under a following camera too)."""
    h = reference.image.shape[0]
    try:
        ice = ice_line_y_px(reference.image, contact_is=contact_is)
    except ValueError:
        ice = float(h)
    # above the ice line, less a margin for a tilted scene (8 deg over the width)
    top = int(np.clip(ice - 0.15 * reference.image.shape[1], 0, h)) if math.isfinite(ice) else h
    if top < 0.1 * h:
        top = h
    norm = Normaliser(reference, contact_is)
    need = options.min_block_fraction * reference.image.size
    rows, cols = slice(0, top), slice(None)
    kernel = np.ones((3, 3), np.uint8)  # an opening: isolated noise pixels are no block
    return any(cv2.countNonZero(cv2.morphologyEx(
        (norm.region(f, rows, cols) > options.min_darkness).astype(np.uint8),
        cv2.MORPH_OPEN, kernel)) > need for f in samples)


#: A side-view block translates (the camera is fixed) when an end of its base moves by more
#: than this share of the base's length in view across the sampled frames. The base is
#: rigid; under a camera that follows the block it only shakes on the rig's compliance (a
#: velocity step from 0.5 to 3 m/s shakes G3's base by 0.2 mm, 1 % of its length, in the
#: renders), while the elements shear and bend (their edges sweep millimetres). A block
#: that moves by less than a tenth of its length over the whole video is as good as still
#: (a static test).
TRANSLATION_SHARE = 0.1


def _block_translates(samples: list[np.ndarray], contact_is: str) -> bool | None:
    """Whether the block of a side view translates through the sampled frames: it is
    missing from some but not all of them, or an end of its base
    (:func:`tir_contact.side.block_span_px`; one at the image border counts as there)
    moves by more than :data:`TRANSLATION_SHARE` of the base's length in view. None when
    no sample shows it."""
    spans = [block_span_px(f, contact_is=contact_is) for f in samples]
    seen = np.array([sp for sp in spans if sp is not None], float).reshape(-1, 2)
    if not len(seen):
        return None
    if len(seen) < len(spans):
        return True
    # an end at the border (NaN) lies at least there
    ends = np.where(np.isnan(seen), [0.0, samples[0].shape[1] - 1.0], seen)
    length = float(np.median(ends[:, 1] - ends[:, 0]))
    return bool(np.ptp(ends, axis=0).max() > TRANSLATION_SHARE * length)


def _side_mode(samples: list[np.ndarray], reference: Reference, contact_is: str,
               options: AnalysisOptions) -> tuple[Reference | None, str, str]:
    """A side view's camera mode and reference (`reference`: the samples' percentile image).

    ``"fixed"`` when the block translates (:func:`_block_translates`; when no sample shows
    a block, when some sampled frame differs from the percentile image at all); the
    percentile image is the reference unless it still shows the block (a block that never
    leaves the view), when each frame is normalised by its own background
    (:func:`tir_contact.side.side_darkness`). ``"follows"`` otherwise: the block stays
    where it is, only its elements deform, and no frame shows the background behind it.
    """
    translates = _block_translates(samples, contact_is)
    if translates is None:  # no block in any sample: does anything differ at all?
        translates = _frames_differ(samples, reference, contact_is, options)
    if not translates:
        return None, "per-frame background (the block does not translate)", "follows"
    if block_span_px(reference.image, contact_is=contact_is) is not None:
        return None, "per-frame background (the block never leaves the view)", "fixed"
    return reference, "percentile", "fixed"


@dataclass
class VideoSetup:
    """What is fixed for all frames of one video (:func:`prepare_video`).

    Attributes
    ----------
    meta : dict
        The metadata used.
    view, contact_is : str
    fps, mm_per_px : float
    layout : BlockLayout
    reference : Reference or None
        Free surface (TIR) or background (side view; None: each frame's own).
    reference_method : str
    contrast : float or None
    n_frames : int
    shape : (int, int)
    max_dn : float
    skipped : list of dict
        Sampled frames that could not be read.
    numbers : ndarray of int
        Recorded frame number of each frame.
    bad : set of int
        Indices of frames that could not be read.
    grey_range : (float, float)
        1st and 99th percentile of the sampled pixels.
    camera : {"fixed", "follows"}
    tir : TirReference or None
        Lit zone, free surface and noise of a TIR video.
    threshold : float
        Darkness threshold of contact (TIR; NaN for the side view).
    level_deg : float
        Side view: the ice line's tilt against the image rows, deg; each frame (and the
        reference) is turned by it about the image centre before its features are found,
        so angles are against the ice surface's normal (0 when under 0.1 deg).
    level_valid : ndarray of bool or None
        Side view turned level: the pixels that come from inside the frame.
    notes : list of str
        Warnings found while preparing (``summary.json`` lists them).
    reference_fit : ReferenceFit or None
        TIR with ``--reference``: gain, shift and residual of the user's image fitted to
        the footage (:func:`tir_contact.reference_fit.fit_reference`).
    area_model : AreaModel or None
        TIR: the free-surface and contact darkness populations the contact area is measured
        against (:func:`tir_contact.measure.area_model`).
    """
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
    level_deg: float = 0.0  # side view: tilt of the ice line; frames are turned level by it
    level_valid: np.ndarray | None = None  # side view: pixels inside the frame once turned
    notes: list[str] = field(default_factory=list)  # what the user must know (warnings)
    reference_fit: ReferenceFit | None = None  # TIR: the user's reference fitted (gain, shift)
    area_model: AreaModel | None = None  # TIR: free-surface and contact darkness populations


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


def prepare_video(reader: Any, path: Path, overrides: Mapping[str, Any] | None,
                  options: AnalysisOptions) -> VideoSetup:
    """What the analysis of each frame needs, from the metadata and sampled frames.

    Reads the metadata, samples ``options.reference_frames`` frames spread through the
    video and finds (TIR) the lit zone, the camera mode, the free surface, the noise and
    the contact threshold (:func:`tir_contact.reference.tir_reference`), or (side view) the
    background reference.

    Parameters
    ----------
    reader : footage reader
        An open reader (:func:`tir_contact.io.open_footage`).
    path : Path
        The footage (for messages and the metadata).
    overrides : mapping, optional
        Metadata by dotted key, winning over ``meta.json``.
    options : AnalysisOptions

    Returns
    -------
    VideoSetup

    Raises
    ------
    FootageError
        No frames, no readable sampled frame, or bad metadata.
    """

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
    side_camera: str | None = None
    ref_fit: ReferenceFit | None = None
    fit_notes: list[str] = []
    if view == "tir":
        tref, ref_fit, fit_notes = _tir_reference(samples, shape, contact_is, options)
        reference, method = tref.reference, tref.method
    elif options.reference is not None:
        reference = _read_reference_file(options.reference, shape)
        method = "file"
    elif len(samples) >= 5 and options.camera != "follows":
        reference = reference_from_frames(samples, contact_is=contact_is,
                                          percentile=options.percentile)
        method = "percentile"
        if options.camera == "auto":
            reference, method, side_camera = _side_mode(samples, reference, contact_is, options)
    else:
        reference, method = None, f"per-frame background ({len(samples)} frame(s) sampled)"
    level_deg, level_valid, notes = 0.0, None, list(fit_notes)
    if view == "side":
        # without a reference, the median of a few samples shows the block where it stays
        median = (np.median(np.stack(samples[:9]).astype(np.float32), axis=0)
                  if reference is None else None)
        reference, level_deg, level_valid = _level_side(median, reference, contact_is)
        if level_deg:
            method += f", turned level by {level_deg:+.2f} deg"
        if median is not None:
            notes += _wide_block_note(median, contact_is)
    contrast = options.contrast
    if contrast is None and tref is not None:
        contrast = _contrast(samples, tref, contact_is, options)
    threshold = math.nan
    model = None
    if tref is not None:  # pixels too noisy for the threshold are not measured
        threshold = _threshold(contrast, options, tref.camera)
        tref = measurable(tref, threshold, n_sigma=options.noise_sigmas)
        reference = tref.reference
        model = _area_model(samples, tref, contact_is, options)
        notes += model.notes
        # the decision where the two populations separate (tir_contact.measure): half
        # the darkness of full contact, at least the free surface's reach
        threshold, contrast = model.threshold, model.contact_darkness
    layout = BlockLayout.from_meta(meta)
    camera = tref.camera if tref is not None else side_camera or (
        "fixed" if reference is not None else "follows")
    return VideoSetup(meta, view, contact_is, float(meta["fps"]), float(meta["mm_per_px"]), layout,
                  reference, method, contrast, n, shape, max_dn, skipped, numbers, bad,
                  grey_range, camera, tref, threshold, level_deg, level_valid, notes,
                  ref_fit, model)


#: A side view without a block-free frame needs the block to leave some background beside
#: it in each row (its rows are two-toned, :func:`tir_contact.side.side_darkness`): above
#: this share of the image width a warning is given (G3 following camera with a holder
#: plate across the frame: 96 % of the width still measures every element in view, 89 %
#: with the same errors as 62 %, 0.002-0.005 deg median).
MAX_SIDE_BLOCK_SHARE = 0.97


def _wide_block_note(image: np.ndarray, contact_is: str) -> list[str]:
    """A warning when the block spans too much of a following side camera's width (`image`:
    the median of some frames)."""
    if contact_is == "bright":  # bright rubber on a dark background: mirror it
        image = float(image.max()) - image
    # rubber: below a quarter of the backlight's level (the image's 95th percentile); a
    # steel holder, plate or carriage (about 0.4 of it) and the ice (0.6) are not
    rubber = image < 0.25 * float(np.percentile(image, 95))
    cols = np.flatnonzero(rubber.mean(axis=0) > 0.05)
    # from the first to the last column with rubber (sipes between the elements included)
    share = (float(cols[-1] - cols[0] + 1) / image.shape[1]) if cols.size else 0.0
    if share <= MAX_SIDE_BLOCK_SHARE:
        return []
    return [f"the block spans {100 * share:.0f} % of the image width and no frame shows the "
            "background without it: the background of each row is estimated beside the "
            "block, which needs free background there (widen the view, or give "
            "--reference)"]


#: Side views whose ice line is tilted by less than this (deg) are not turned.
MIN_LEVEL_DEG = 0.1


def _level_side(median: np.ndarray | None, reference: Reference | None,
                contact_is: str) -> tuple[Reference | None, float, np.ndarray | None]:
    """The side view's tilt (:func:`tir_contact.side.ice_line_tilt_deg` on the reference,
    or on `median`, the median of some samples), and the reference turned level by it."""
    image = reference.image if reference is not None else median
    tilt = ice_line_tilt_deg(image, contact_is=contact_is)
    if not math.isfinite(tilt) or abs(tilt) < MIN_LEVEL_DEG:
        return reference, 0.0, None
    inside = level_image(np.ones(image.shape, np.float32), tilt) > 0.999
    if reference is not None:
        turned = level_image(reference.image, tilt, border=math.nan)
        turned = np.where(np.isfinite(turned), turned, 0.0)
        reference = Reference(turned.astype(np.float64), reference.valid & inside,
                              reference.method, reference.n_frames)
    return reference, tilt, inside


def _contrast(samples: list[np.ndarray], tref: TirReference, contact_is: str,
              options: AnalysisOptions) -> float | None:
    """Contact contrast: the median over the samples of each one's median darkness of the
    pixels surely in contact, darker than ``min_darkness`` and than ``noise_sigmas`` times
    their darkness noise (on a dim free surface, bright contact on a dark one above all,
    noise alone passes ``min_darkness``)."""
    norm = Normaliser(tref.reference, contact_is)
    sure = np.maximum(np.float32(options.min_darkness), np.float32(options.noise_sigmas)
                      * tref.noise.sigma_darkness(tref.reference.image))[::2, ::2]
    every_other = (slice(None, None, 2), slice(None, None, 2))
    # every other row and column: a median needs no more
    values = [estimate_contrast(norm.region(f, *every_other), min_darkness=sure)
              for f in samples]
    finite = [v for v in values if np.isfinite(v)]
    return float(np.median(finite)) if finite else None


def _area_model(samples: list[np.ndarray], tref: TirReference, contact_is: str,
                options: AnalysisOptions) -> AreaModel:
    """The darkness populations of a TIR video (:func:`tir_contact.measure.area_model`) from
    the sampled frames' darkness on the measured pixels."""
    norm = Normaliser(tref.reference, contact_is)
    darkness = [norm(f) for f in samples]
    sigma = tref.noise.sigma_darkness(tref.reference.image)
    return area_model(darkness, sigma, contrast=options.contrast,
                      min_cluster_px=options.min_area_px,
                      static=tref.camera == "follows", zone_sigma=tref.texture_sigma,
                      zone_corr_px=tref.texture_corr_px)


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
                   options: AnalysisOptions
                   ) -> tuple[TirReference, ReferenceFit | None, list[str]]:
    """Lit zone, camera mode, free surface and noise (:func:`tir_contact.reference.tir_reference`)
    with the user's lit mask and reference image, when given.

    A user's reference is first fitted to the footage (gain and shift,
    :func:`tir_contact.reference_fit.fit_reference`) against the footage's own estimate;
    a reference that does not fit is not used (a warning says so, naming the file and the
    residual), and the footage's own estimate stands.
    """
    lit = lit_zone_from_file(options.lit_mask, shape) if options.lit_mask else None
    kwargs = dict(contact_is=contact_is, percentile=options.percentile,
                  min_darkness=options.min_darkness,
                  min_block_fraction=options.min_block_fraction)
    try:
        own = tir_reference(samples, camera=options.camera, lit=lit, **kwargs)
        if options.reference is None:
            return own, None, []
        raw = _read_reference_file(options.reference, shape).image
        fit = fit_reference(raw, _free_image(samples, own, contact_is, options.percentile),
                            noise=own.noise, lit=own.lit.mask, contact_is=contact_is)
        if not fit.fits:
            note = (f"{options.reference}: the reference image does not fit the footage: "
                    f"after the best gain ({fit.gain:.3f}) and shift ({fit.shift_px[0]:+.2f}, "
                    f"{fit.shift_px[1]:+.2f}) px its residual on the free surface is "
                    f"{fit.residual_rms:.3f} in darkness, {fit.noise_ratio:.1f} times the "
                    f"noise (at most {MAX_NOISE_RATIO:g}); it was not used, the free surface "
                    "was estimated from the footage")
            own = dataclasses.replace(own, method=own.method + " (the --reference image "
                                      "did not fit)")
            return own, fit, [note]
        # where the shifted reference has no data (a strip along the border), the
        # footage's own estimate
        image = np.where(fit.inside, fit.image, own.reference.image.astype(np.float32))
        tref = tir_reference(samples, camera=options.camera, lit=own.lit, image=image,
                             **kwargs)
        method = (f"file, fitted: gain {fit.gain:.3f}, shift ({fit.shift_px[0]:+.2f}, "
                  f"{fit.shift_px[1]:+.2f}) px")
        return dataclasses.replace(tref, method=method), fit, []
    except ValueError as exc:
        raise FootageError(str(exc), options.lit_mask) from exc


def _free_image(samples: list[np.ndarray], own: TirReference, contact_is: str,
                percentile: float) -> np.ndarray:
    """The footage's free surface wherever it shows, for fitting a user's reference.

    A block passing a fixed camera may cover a pixel in most frames: there each pixel's
    bright `percentile` over the samples, less its expected excess over the mean (the
    normal order statistic times the noise, :func:`_percentile_excess`); a static scene:
    each pixel's median.
    """
    if len(samples) == 1:
        return np.asarray(samples[0], np.float32)
    if own.camera == "fixed" and len(samples) >= 5:
        q = percentile if contact_is == "dark" else 100.0 - percentile
        image = np.asarray(pixelwise_percentile(samples, q), np.float32)
        excess = _percentile_excess(len(samples), q) * own.noise.sigma_grey(image)
        return (image - excess).astype(np.float32)
    return np.asarray(pixelwise_percentile(samples, 50.0), np.float32)


def _percentile_excess(n: int, q: float) -> float:
    """Expected `q`-th percentile (linear interpolation, as numpy's) of `n` standard normal
    values: Blom's approximation ``Phi^-1((i - 0.375) / (n + 0.25))`` of the order
    statistics either side, interpolated.

    Examples
    --------
    >>> round(_percentile_excess(32, 90.0), 2), _percentile_excess(7, 50.0)  # Monte Carlo: 1.201
    (1.2, 0.0)
    """
    pos = q / 100.0 * (n - 1)
    i = min(math.floor(pos), n - 1)
    f = pos - i

    def blom(k: int) -> float:  # k 0-based
        return float(norm.ppf((k + 1 - 0.375) / (n + 0.25)))

    return (1 - f) * blom(i) + (f * blom(i + 1) if f > 0 else 0.0)
