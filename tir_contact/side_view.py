"""The side view: the block's elements seen from the side against a backlight.

:meth:`SideView.prepare` decides, once per video from the sampled frames, the background
reference (the user's ``--reference``, the samples' percentile image
:func:`tir_contact.flatfield.reference_from_frames`, or none: each frame's own background),
the camera mode (whether the block translates), and the ice line's tilt that each frame is
turned level by. :meth:`SideView.analyser` gives the per-frame step, :class:`SideFrames`:
darkness against the background (:func:`tir_contact.side.side_darkness`) and element chords
(:func:`tir_contact.side.side_frame_features`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import cv2
import numpy as np

from tir_contact._darkness import Normaliser
from tir_contact.flatfield import Reference, reference_from_frames
from tir_contact.options import AnalysisOptions
from tir_contact.overlay import draw_side_overlay
from tir_contact.side import (
    block_span_px,
    ice_line_tilt_deg,
    ice_line_y_px,
    level_image,
    side_darkness,
    side_frame_features,
)
from tir_contact.view import FrameResult, fully_in_view, read_reference_file, wants_regions

__all__ = ["SideFrames", "SideView"]


@dataclass
class SideView:
    """The side view of one video (:meth:`prepare`).

    Attributes
    ----------
    reference : Reference or None
        The background without the block (None: each frame's own background).
    method : str
        How the reference was made.
    camera : {"fixed", "follows"}
    level_deg : float
        The ice line's tilt against the image rows, deg; each frame (and the reference) is
        turned by it about the image centre before its features are found, so angles are
        against the ice surface's normal (0 when under :data:`MIN_LEVEL_DEG`).
    level_valid : ndarray of bool or None
        Turned level: the pixels that come from inside the frame.
    contrast : float or None
        The user's ``contrast`` setting (reported in ``summary.json``; not used here).
    """

    name: ClassVar[str] = "side"
    subject: ClassVar[str] = "block"
    reference_fit: ClassVar[None] = None  # no user reference is fitted in the side view
    reference: Reference | None
    method: str
    camera: str
    level_deg: float = 0.0
    level_valid: np.ndarray | None = None
    contrast: float | None = None

    @classmethod
    def prepare(cls, samples: list[np.ndarray], shape: tuple[int, int], contact_is: str,
                options: AnalysisOptions) -> tuple[SideView, list[str]]:
        """The view of a video from its sampled frames, and the warnings found."""
        side_camera: str | None = None
        reference: Reference | None
        if options.reference is not None:
            reference = read_reference_file(options.reference, shape)
            method = "file"
        elif len(samples) >= 5 and options.camera != "follows":
            reference = reference_from_frames(samples, contact_is=contact_is,
                                              percentile=options.percentile)
            method = "percentile"
            if options.camera == "auto":
                reference, method, side_camera = _side_mode(samples, reference, contact_is,
                                                            options)
        else:
            reference, method = None, f"per-frame background ({len(samples)} frame(s) sampled)"
        notes: list[str] = []
        # without a reference, the median of a few samples shows the block where it stays
        median = (np.median(np.stack(samples[:9]).astype(np.float32), axis=0)
                  if reference is None else None)
        reference, level_deg, level_valid = _level_side(median, reference, contact_is)
        if level_deg:
            method += f", turned level by {level_deg:+.2f} deg"
        if median is not None:
            notes += _wide_block_note(median, contact_is)
        camera = side_camera or ("fixed" if reference is not None else "follows")
        return cls(reference, method, camera, level_deg, level_valid, options.contrast), notes

    def analyser(self, setup: Any, options: AnalysisOptions) -> SideFrames:
        """The per-frame step of this video."""
        return SideFrames(self, setup, options)

    def summary(self) -> dict[str, Any]:
        """``summary.json``'s contrast and threshold (none: the side view has no threshold)."""
        return {"contrast": self.contrast, "threshold": None}

    def overlay(self, setup: Any, frame: np.ndarray, result: FrameResult,
                label: str) -> np.ndarray:
        """The frame with the elements' chords, angles and the ice line drawn."""
        lines = getattr(result.detail, "lines", {}) or {}
        return draw_side_overlay(frame, result.element_table(), lines,
                                 ice_y_px=getattr(result.detail, "ice_y_px", None),
                                 max_dn=setup.max_dn, label=label)

    def warnings(self, frames: Any) -> list[str]:
        """None of the side view's own (its footage's are the common ones)."""
        return []

    def none_found(self, frames: Any) -> str:
        """Nothing: without a block a side view's frames hold no values."""
        return ""

    def images(self) -> dict[str, np.ndarray]:
        """None: the side view writes only the tables."""
        return {}


class SideFrames:
    """The per-frame step of a side-view video: ``frames(k, frame) -> FrameResult``.

    It finds no contact regions: ``regions.csv`` (wanted as for TIR footage) has none.
    """

    def __init__(self, view: SideView, setup: Any, options: AnalysisOptions) -> None:
        self.view = view
        self.setup = setup
        self.want_regions = wants_regions(options, setup)
        # the ice line of the (levelled) reference, fixed for the video
        self.ice_y_px: float | None = (
            ice_line_y_px(view.reference.image, contact_is=setup.contact_is)
            if view.reference is not None else None
        )

    def __call__(self, k: int, frame: np.ndarray) -> FrameResult:
        """A side-view frame: element chords, deflection angles and tip deflections."""
        s, v = self.setup, self.view
        t = k / s.fps
        if v.level_deg:  # the ice line along the rows: angles against the ice's normal
            frame = level_image(frame, v.level_deg)
            if v.reference is None:  # a reference excludes the corners the turn brought in
                frame = np.where(v.level_valid, frame, np.median(frame))
        d = side_darkness(frame, contact_is=s.contact_is, reference=v.reference)
        valid = v.reference.valid if v.reference is not None else v.level_valid
        feats = side_frame_features(d, s.layout, valid=valid, ice_y_px=self.ice_y_px)
        row = {"frame": k, "time_s": t, **feats.frame}
        row["block_fully_in_view"] = bool(row.get("block_in_view")) and fully_in_view(
            row.get("block_front_x_mm", np.nan), s)
        el = feats.elements.copy()
        el.insert(0, "time_s", t)
        el.insert(0, "frame", k)
        return FrameResult(row, el, None, feats)


# -- prepare: camera mode, reference and level ------------------------------------------------
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


