"""One frame in, its numbers out: the per-frame step of :func:`tir_contact.analyze.analyze_video`.

:func:`analyze_frame` is the plain function: a frame and the video's
:class:`~tir_contact.prepare.VideoSetup` in, a :class:`FrameResult` out, for TIR and side
view alike. Its stages are each one call:

* TIR: darkness against the free surface (:class:`tir_contact._darkness.Normaliser`; zero
  outside the measured part of the lit zone), threshold and regions
  (:mod:`tir_contact.segment`), block, elements and front-edge peaks
  (:mod:`tir_contact.features`), regions touching the lit zone's rim;
* side view: darkness against the background (:func:`tir_contact.side.side_darkness`) and
  element chords (:func:`tir_contact.side.side_frame_features`).

:class:`FrameAnalyser` does the same for every frame of a video and keeps what does not
change between frames: the TIR threshold evaluated on the raw grey values
(:class:`tir_contact._darkness.RawContactTest`) and the darkness computed only in the box
that holds the contact (:class:`tir_contact._darkness.BoxDarkness`). Both paths give the
same numbers bit for bit (``tests/test_fast_path.py``); the fast one is what keeps the
analysis within 10x of a bare read-and-threshold pass (``benchmarks/bench_analyze.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
import pandas as pd

from tir_contact._darkness import BoxDarkness, Normaliser, RawContactTest
from tir_contact.features import (
    EDGE_MARGIN_PX,
    ElementRow,
    ValidCounts,
    element_records,
    frame_rows,
)
from tir_contact.measure import EDGE_PX, ZONE_PX, FrameArea, frame_area
from tir_contact.options import AnalysisOptions
from tir_contact.prepare import VideoSetup
from tir_contact.segment import FrameContact, _box_and_counts, _label_box, label_contact
from tir_contact.side import ice_line_y_px, level_image, side_darkness, side_frame_features

__all__ = ["FrameAnalyser", "FrameResult", "analyze_frame"]


@dataclass(slots=True)
class FrameResult:
    """What one frame gave.

    Attributes
    ----------
    row : dict
        The frame's row of ``frames.csv`` (``frame``, ``time_s`` and the measured columns).
    elements : list of ElementRow or pandas.DataFrame
        TIR: one :class:`~tir_contact.features.ElementRow` per element in contact
        (:meth:`element_table` makes a table of them); side view: the element table.
    regions : dict of ndarray or None
        TIR: every contact region's columns (pixels), when regions are wanted.
    detail : FrameContact or SideFeatures
        The segmentation (TIR) or the side-view features, for drawing overlays.
    """

    row: dict[str, Any]
    elements: list[ElementRow] | pd.DataFrame
    regions: dict[str, np.ndarray] | None
    detail: Any

    def element_table(self) -> pd.DataFrame:
        """The elements as a table with ``frame`` and ``time_s`` first."""
        if isinstance(self.elements, pd.DataFrame):
            return self.elements
        rec = element_records(self.elements)
        df = pd.DataFrame({name: rec[name] for name in rec.dtype.names})
        df.insert(0, "time_s", self.row["time_s"])
        df.insert(0, "frame", self.row["frame"])
        return df


def analyze_frame(frame: np.ndarray, setup: VideoSetup, options: AnalysisOptions | None = None,
                  *, k: int = 0) -> FrameResult:
    """Analyse one frame of a video whose setup is known (the plain path).

    Parameters
    ----------
    frame : (M, N) ndarray
        The frame.
    setup : VideoSetup
        What :func:`tir_contact.prepare.prepare_video` found for the video.
    options : AnalysisOptions, optional
        Settings (the defaults when omitted).
    k : int
        The frame's recorded number (its time is ``k / fps``).

    Returns
    -------
    FrameResult
    """
    return FrameAnalyser(setup, options or AnalysisOptions(), fast=False)(k, frame)


def _labels_in(contact: FrameContact, box: tuple[slice, slice],
               same: bool) -> tuple[np.ndarray, int] | None:
    """The segmentation's region labels placed in `box` (which holds the contact's box),
    when it segmented at the measurement's threshold (`same`)."""
    if not same:
        return None
    lab = np.zeros((box[0].stop - box[0].start, box[1].stop - box[1].start), np.int32)
    if contact.box is not None and contact.box_labels is not None:
        r, c = contact.box
        lab[r.start - box[0].start:r.stop - box[0].start,
            c.start - box[1].start:c.stop - box[1].start] = contact.box_labels
    return lab, contact.n_regions + 1


def _union(a: tuple[slice, slice] | None, b: tuple[slice, slice] | None,
           shape: tuple[int, int], grow: int) -> tuple[slice, slice] | None:
    """The box holding boxes `a` and `b` (either may be None), grown by `grow` px."""
    boxes = [x for x in (a, b) if x is not None]
    if not boxes:
        return None
    r0 = max(min(x[0].start for x in boxes) - grow, 0)
    r1 = min(max(x[0].stop for x in boxes) + grow, shape[0])
    c0 = max(min(x[1].start for x in boxes) - grow, 0)
    c1 = min(max(x[1].stop for x in boxes) + grow, shape[1])
    return slice(r0, r1), slice(c0, c1)


def fully_in_view(front_mm: float, setup: VideoSetup, margin_mm: float = 0.5) -> bool:
    """True when the whole block footprint lies in the image (`margin_mm` from its ends)."""
    if not math.isfinite(front_mm) or setup.layout.element_lengths_mm is None:
        return math.isfinite(front_mm)
    total = setup.layout.block_length_mm
    width_mm = setup.shape[1] * setup.mm_per_px
    back = front_mm + total if setup.layout.sliding_direction == "left" else front_mm - total
    lo, hi = min(front_mm, back), max(front_mm, back)
    return lo >= margin_mm and hi <= width_mm - margin_mm


class FrameAnalyser:
    """Analyses the frames of one video with fixed settings: ``analyser(k, frame)``.

    Parameters
    ----------
    setup : VideoSetup
    options : AnalysisOptions
    fast : bool
        Threshold TIR frames on their raw grey values and compute the darkness only in the
        contact's box (same results as the plain path; integer frames only).
    """

    def __init__(self, setup: VideoSetup, options: AnalysisOptions, *, fast: bool = True) -> None:
        self.setup = setup
        self.options = options
        tir = setup.view == "tir"
        self.normalise = (Normaliser(setup.reference, setup.contact_is)
                          if tir and setup.reference is not None else None)
        # side view: the ice line of the (levelled) reference, fixed for the video
        self.ice_y_px: float | None = (
            ice_line_y_px(setup.reference.image, contact_is=setup.contact_is)
            if not tir and setup.reference is not None else None
        )
        rim = setup.tir.lit.rim if setup.tir is not None else None
        self._rim = rim if rim is not None and rim.any() else None
        self.want_regions = options.regions == "always" or (
            options.regions == "auto" and setup.layout.element_lengths_mm is None
        )
        self._threshold = setup.threshold
        self._fast = fast
        self._valid_counts = ValidCounts()  # the reference's mask is fixed within a video
        self._raw_tests: dict[str, RawContactTest | None] = {}  # by dtype character
        self._raw_buf: np.ndarray | None = None
        self._box = (
            BoxDarkness(self.normalise, setup.shape) if self.normalise is not None else None
        )

    def __call__(self, k: int, frame: np.ndarray) -> FrameResult:
        """Analyse frame `frame`, recorded frame number `k`."""
        return self.tir(k, frame) if self.setup.view == "tir" else self.side(k, frame)

    # TIR ------------------------------------------------------------------------------------

    def _raw_test(self, frame: np.ndarray) -> RawContactTest | None:
        if not self._fast or self._box is None or not math.isfinite(self._threshold):
            return None
        test = self._raw_tests.get(frame.dtype.char, False)
        if test is False:
            test = RawContactTest.build(self.normalise, self._threshold, frame.dtype)
            self._raw_tests[frame.dtype.char] = test
        return test

    def segment(self, frame: np.ndarray) -> tuple[np.ndarray, FrameContact, tuple | None]:
        """Darkness, contact and (fast path) the column sums of the box's darkness."""
        test = self._raw_test(frame)
        raw = None
        if test is not None:  # into one reused buffer: `raw` does not outlive the frame
            if self._raw_buf is None or self._raw_buf.shape != frame.shape:
                self._raw_buf = np.empty(frame.shape, np.bool_)
            raw = test(frame, out=self._raw_buf)
        if raw is None:  # the plain path: the whole frame's darkness, thresholded
            d = self.normalise(frame)
            contact = label_contact(d >= self._threshold, self._threshold, d,
                                    min_area_px=self.options.min_area_px)
            return d, contact, None
        box, counts = _box_and_counts(raw)
        sums = None
        if box is None:
            d = self._box.clear()
        else:  # the rows and (widened) columns the features read
            rows = box[0]
            cols = slice(max(box[1].start - EDGE_MARGIN_PX, 0),
                         min(box[1].stop + EDGE_MARGIN_PX, raw.shape[1]))
            d = self._box.fill(frame, rows, cols)
            # the features' column sums, while the darkness is still in the cache
            sums = (rows.start, rows.stop, cols.start, cv2.reduce(
                d[rows, cols], 0, cv2.REDUCE_SUM, dtype=cv2.CV_32F).ravel())
        contact = _label_box(raw, self._threshold, d, self.options.min_area_px, box, counts)
        return d, contact, sums

    def tir(self, k: int, frame: np.ndarray) -> FrameResult:
        """A TIR frame: contact, block, elements and, when wanted, regions."""
        s = self.setup
        t = k / s.fps
        d, contact, sums = self.segment(frame)
        row, el_rows = frame_rows(d, contact, s.layout, self.normalise.valid, t, 1.0, sums,
                                   self._valid_counts)
        row["frame"] = k
        row["time_s"] = t
        row["n_regions"] = contact.n_regions
        self._measure(frame, row, contact)
        row["block_fully_in_view"] = row["block_in_view"] and fully_in_view(
            row["block_front_x_mm"], s)
        at_rim = self._at_rim(contact) if self._rim is not None else None
        row["contact_at_lit_rim"] = at_rim is not None and bool(at_rim[1:].any())
        regions = None
        if self.want_regions:
            regions = contact.region_arrays()
            regions["frame"] = np.full(contact.n_regions, k)
            regions["at_lit_rim"] = (at_rim[1:] if at_rim is not None
                                     else np.zeros(contact.n_regions, bool))
        return FrameResult(row, el_rows, regions, contact)

    def _measure(self, frame: np.ndarray, row: dict[str, Any], contact: FrameContact) -> None:
        """The frame's contact area as a measurement, with its error bar
        (:func:`tir_contact.measure.frame_area`).

        A fixed camera whose free surface separates from contact: only the box around the
        seed pixels (found on the raw grey values, :class:`RawContactTest` at the model's
        per-pixel seed level) and the contact, grown by the zone around contact, is read;
        otherwise (a static scene, or a free surface that reaches past half of full
        contact) the whole frame, whose darkness budget then counts.
        """
        model = self.setup.area_model
        px2 = self.setup.mm_per_px ** 2
        if model is None:
            area = row["contact_area_mm2"]
            row["contact_area_low_mm2"] = row["contact_area_high_mm2"] = area
            return
        a = None
        if not model.static and model.separation > 1.0:
            test = self._seed_test(frame)
            if test is not None:
                seeds = test(frame)
                box = _union(_box_and_counts(seeds)[0], contact.box, frame.shape, ZONE_PX
                             + EDGE_PX + 1)
                if box is None:
                    a = FrameArea(0.0, 0.0, 0.0, 0, 0.0)
                else:
                    a = frame_area(self.normalise.region(frame, *box), model, box,
                                   _labels_in(contact, box, self.setup.threshold
                                              == model.threshold))
        if a is None:
            a = frame_area(self.normalise(frame), model)
        row["contact_area_mm2"] = a.area_px * px2
        row["contact_area_low_mm2"] = a.low_px * px2
        row["contact_area_high_mm2"] = a.high_px * px2

    def _seed_test(self, frame: np.ndarray) -> RawContactTest | None:
        """The model's seed level as a test of the raw grey values (per dtype)."""
        if not self._fast:
            return None
        key = "seed" + frame.dtype.char
        test = self._raw_tests.get(key, False)
        if test is False:
            test = RawContactTest.build(self.normalise, self.setup.area_model.seed,
                                        frame.dtype)
            self._raw_tests[key] = test
        return test

    def _at_rim(self, contact: FrameContact) -> np.ndarray:
        """Which regions (index = label, 0 unused) touch the rim of the lit zone."""
        out = np.zeros(contact.n_regions + 1, bool)
        if contact.box is not None:
            out[contact.box_labels[self._rim[contact.box]]] = True
            out[0] = False
        return out

    # side view ------------------------------------------------------------------------------

    def side(self, k: int, frame: np.ndarray) -> FrameResult:
        """A side-view frame: element chords, deflection angles and tip deflections."""
        s = self.setup
        t = k / s.fps
        if s.level_deg:  # the ice line along the rows: angles against the ice's normal
            frame = level_image(frame, s.level_deg)
            if s.reference is None:  # a reference excludes the corners the turn brought in
                frame = np.where(s.level_valid, frame, np.median(frame))
        d = side_darkness(frame, contact_is=s.contact_is, reference=s.reference)
        valid = s.reference.valid if s.reference is not None else s.level_valid
        feats = side_frame_features(d, s.layout, valid=valid, ice_y_px=self.ice_y_px)
        row = {"frame": k, "time_s": t, **feats.frame}
        row["block_fully_in_view"] = bool(row.get("block_in_view")) and fully_in_view(
            row.get("block_front_x_mm", np.nan), s)
        el = feats.elements.copy()
        el.insert(0, "time_s", t)
        el.insert(0, "frame", k)
        return FrameResult(row, el, None, feats)
