"""The TIR view: contact seen as darkness against the free surface of the ice.

:meth:`TirView.prepare` decides, once per video from the sampled frames, the lit zone, the
camera mode and the free surface (:func:`tir_contact.reference.tir_reference`, or a user's
``--reference`` fitted to the footage), the contact contrast and threshold, the pixels too
noisy to measure, and the darkness populations the area is measured against
(:func:`tir_contact.measure.area_model`). :meth:`TirView.analyser` gives the per-frame step,
:class:`TirFrames`, one path for every frame:

1. contact pixels ``D >= threshold`` (:class:`tir_contact._darkness.ContactTest`: on the raw
   grey values where the dtype allows, pixel for pixel the same as on the darkness);
2. the box holding them and the darkness ``D`` only in it, widened by the columns the
   features read (:class:`tir_contact._darkness.BoxDarkness`, the arithmetic of
   :func:`tir_contact.flatfield.darkness`), NaN elsewhere;
3. regions (:func:`tir_contact.segment.segment_frame` with the video's threshold and the
   tested pixels);
4. block, elements and front-edge peaks (:func:`tir_contact.features.frame_rows`, the body
   of :func:`tir_contact.features.tir_frame_features`);
5. further columns of the row (:meth:`TirFrames.extra_columns`: the area with its error
   bar) and the regions touching the lit zone's rim.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import cv2
import numpy as np
from scipy.stats import norm

from tir_contact._darkness import BoxDarkness, ContactTest, Normaliser
from tir_contact._percentile import pixelwise_percentile
from tir_contact._readers import FootageError
from tir_contact.features import EDGE_MARGIN_PX, ValidCounts, frame_rows, graded_back_px
from tir_contact.flatfield import Reference
from tir_contact.illumination import LitZone, lit_zone_from_file
from tir_contact.measure import (
    EDGE_PX,
    ZONE_PX,
    AreaModel,
    FrameArea,
    area_model,
    frame_area,
    with_absorbed,
)
from tir_contact.options import AnalysisOptions
from tir_contact.overlay import draw_tir_overlay
from tir_contact.reference import TirReference, absorbed_darkness, measurable, tir_reference
from tir_contact.reference_fit import MAX_NOISE_RATIO, ReferenceFit, fit_reference
from tir_contact.segment import (
    FrameContact,
    _box_and_counts,
    contact_box,
    estimate_contrast,
    segment_frame,
)
from tir_contact.tilt import EdgeTilt, edge_tilt, tilt_warning
from tir_contact.view import FrameResult, fully_in_view, read_reference_file, wants_regions

__all__ = ["TirFrames", "TirView"]


@dataclass
class TirView:
    """The TIR view of one video (:meth:`prepare`).

    Attributes
    ----------
    tir : TirReference
        Lit zone, free surface and noise.
    contrast : float or None
        Contact contrast (the user's, or estimated from the samples).
    threshold : float
        Darkness threshold of contact.
    area_model : AreaModel or None
        The free-surface and contact darkness populations the contact area is measured
        against (:func:`tir_contact.measure.area_model`).
    reference_fit : ReferenceFit or None
        With ``--reference``: gain, shift and residual of the user's image fitted to the
        footage (:func:`tir_contact.reference_fit.fit_reference`).
    edge_tilt : EdgeTilt or None
        The orientation of the contact's edges in the sampled frames
        (:func:`tir_contact.tilt.edge_tilt`).
    """

    name: ClassVar[str] = "tir"
    subject: ClassVar[str] = "contact"
    tir: TirReference
    contrast: float | None
    threshold: float
    area_model: AreaModel | None = None
    reference_fit: ReferenceFit | None = None
    edge_tilt: EdgeTilt | None = None

    @property
    def reference(self) -> Reference:
        """The free surface (pixels too noisy to measure excluded)."""
        return self.tir.reference

    @property
    def method(self) -> str:
        return self.tir.method

    @property
    def camera(self) -> str:
        return self.tir.camera

    @classmethod
    def prepare(cls, samples: list[np.ndarray], shape: tuple[int, int], contact_is: str,
                options: AnalysisOptions, *, optics: tuple[float, str] | None = None,
                travel_px: Sequence[float] | None = None) -> tuple[TirView, list[str]]:
        """The view of a video from its sampled frames, and the warnings found.

        The free surface and noise (:func:`_tir_reference`), the contrast
        (:func:`_contrast`) and threshold (:func:`_threshold`), the pixels too noisy for
        that threshold (:func:`tir_contact.reference.measurable`), then the video's model of
        the darkness populations (:meth:`population_model`). Where the populations separate
        at a higher decision than that first cut (the model's threshold: half the darkness
        of full contact), the pixels too noisy for the first cut but not for the decision
        are measured too, and the model is made again on them (:func:`_remeasured`).
        `optics`: full contact's darkness from the rig's optics and its source
        (:func:`tir_contact.optics.full_contact_from_meta`), for a video without resolved
        contact. `travel_px`: a passing block's displacement at each sample from the first
        (:func:`tir_contact.travel.expected_travel_px`; the camera-mode test's evidence).
        """
        tref, ref_fit, notes = _tir_reference(samples, shape, contact_is, options,
                                              travel_px)
        contrast = options.contrast
        if contrast is None:
            contrast = _contrast(samples, tref, contact_is, options)
        threshold = _threshold(contrast, options, "follows" if _static(tref) else "fixed")
        # pixels too noisy for the threshold are not measured; the darkness noise of the
        # free surface is the same map for every cut and model below
        whole = tref
        sigma = whole.noise.sigma_darkness(whole.reference.image)
        tref = measurable(whole, threshold, n_sigma=options.noise_sigmas, sigma=sigma)
        model = cls.population_model(samples, tref, contact_is, options, sigma=sigma,
                                     optics=optics)
        tref, model = _remeasured(samples, whole, tref, model, threshold, contact_is, options,
                                  sigma, optics)
        if model.static and model.junction_field and contact_is == "dark":
            # a static scene's estimate is the image itself beyond its contact candidates:
            # what it may have absorbed of junctions too faint or small to be candidates,
            # once for the pixels the model kept
            model = with_absorbed(model, absorbed_darkness(tref.reference.image,
                                                           tref.reference.valid))
        # the decision where the two populations separate (tir_contact.measure): half
        # the darkness of full contact, at least the free surface's reach
        threshold, contrast = model.threshold, model.contact_darkness
        tilt = edge_tilt(samples, tref.reference, threshold, contact_is, full_darkness=contrast)
        return cls(tref, contrast, threshold, model, ref_fit, tilt), notes + model.notes

    @staticmethod
    def population_model(samples: list[np.ndarray], tref: TirReference, contact_is: str,
                         options: AnalysisOptions, *, sigma: np.ndarray | None = None,
                         optics: tuple[float, str] | None = None) -> AreaModel:
        """The per-video model of the darkness populations (free surface, contact), made
        once in :meth:`prepare` from the sampled frames (:func:`_area_model`); `sigma`: the
        free surface's darkness noise, when already computed; `optics`: as for
        :meth:`prepare`."""
        return _area_model(samples, tref, contact_is, options, sigma, optics)

    def analyser(self, setup: Any, options: AnalysisOptions) -> TirFrames:
        """The per-frame step of this video."""
        return TirFrames(self, setup, options)

    def overlay(self, setup: Any, frame: np.ndarray, result: FrameResult,
                label: str) -> np.ndarray:
        """The frame with its contact, elements, area and lit zone drawn; dim footage is
        stretched to its lit level."""
        top = setup.max_dn
        bright = self.tir.lit.bright_level
        if math.isfinite(bright) and bright > 0:
            top = min(top, 1.1 * bright)
        return draw_tir_overlay(frame, result.detail.mask, result.element_table(),
                                result.row, mm_per_px=setup.mm_per_px, max_dn=top,
                                label=label, lit=self.tir.lit.mask)

    def warnings(self, frames: Any) -> list[str]:
        """Contact at the lit zone's rim, where part of it may not be seen; a scene where
        nothing moves and no contact is resolved, whose contact may fill the lit zone in the
        frames that show none (their error bar reaches the whole zone: :class:`TirFrames`)."""
        if not len(frames):
            return []
        out = []
        at_rim = int((frames["contact_at_lit_rim"] == True).sum())  # noqa: E712 (NaN: no)
        if at_rim:
            out.append(f"contact touches the rim of the lit zone in {at_rim} of "
                       f"{len(frames)} frames: part of it may lie where too little light "
                       "reaches to see it (lit_mask.png; --lit-mask to give the zone)")
        noisy = _too_noisy(self.tir)
        if noisy is not None:
            out.append(noisy)
        angles = (int(np.isfinite(frames["deflection_angle_deg"].to_numpy(float)).sum())
                  if "deflection_angle_deg" in frames else 0)
        tilted = tilt_warning(self.edge_tilt, angles)
        if tilted is not None:
            out.append(tilted)
        if self.area_model is not None and _may_fill_zone(self.tir, self.area_model):
            # the frames the bar's fill applies to (TirFrames.extra_columns: the same test)
            empty = int((~frames["block_in_view"].astype(bool)).sum())
            bar = (f"; in the {empty} of {len(frames)} frames that show no contact the error "
                   "bar reaches up to the whole lit zone found and its rim band beyond"
                   if empty else "")
            out.append(
                "nothing moves and no contact is resolved: a contact that fills the lit "
                "zone found, or most of it, leaves no free surface at the lit level in view "
                "and cannot be told from a dimly lit free surface or the unlit outside "
                f"(lit zone found: {100 * self.tir.lit.fraction:.0f} % of the frame, "
                f"lit_mask.png{bar}); if such a contact is there, give an empty frame "
                "(--reference) or the lit zone (--lit-mask)")
        return out

    def none_found(self, frames: Any) -> str:
        """Without resolved contact in any frame the areas are the darkness unmixed alone:
        their medians and bar (the camera sample beam.cihx: 58-60 mm2 stood beside "no
        contact found" without a word)."""
        med = frames[["contact_area_mm2", "contact_area_low_mm2",
                      "contact_area_high_mm2"]].median()
        return (f": contact_area_mm2 is the darkness unmixed alone (median {med.iloc[0]:.3g} "
                f"mm2, its bar {med.iloc[1]:.3g}-{med.iloc[2]:.3g} mm2)")

    def images(self) -> dict[str, np.ndarray]:
        """``lit_mask.png``: white where TIR light reaches."""
        return {"lit_mask.png": self.tir.lit.mask.astype(np.uint8) * 255}

    def summary(self) -> dict[str, Any]:
        """Light, noise, contrast, threshold and populations (``summary.json``)."""
        return {
            **_tir_assumptions(self.tir),
            "contrast": self.contrast,
            "threshold": _finite_or_none(self.threshold),
            **({"populations": self.area_model.summary()} if self.area_model is not None
               else {}),
            **({"edge_tilt": self.edge_tilt.summary()} if self.edge_tilt is not None
               else {}),
        }


class TirFrames:
    """The per-frame step of a TIR video: ``frames(k, frame) -> FrameResult``.

    Keeps what does not change between frames: the contact test, the box darkness image,
    the valid-pixel counts of the reference's mask, and whether the area reads only a box
    around the contact (:meth:`extra_columns`).
    """

    def __init__(self, view: TirView, setup: Any, options: AnalysisOptions) -> None:
        self.view = view
        self.setup = setup
        self.options = options
        self.normalise = Normaliser(view.reference, setup.contact_is)
        rim = view.tir.lit.rim
        self._rim = rim if rim is not None and rim.any() else None
        self.want_regions = wants_regions(options, setup)
        self._test = ContactTest(self.normalise, view.threshold)
        self._box = BoxDarkness(self.normalise, setup.shape)
        self._valid_counts = ValidCounts()  # the reference's mask is fixed within a video
        model = view.area_model
        # a fixed camera whose free surface separates from contact: the area reads only
        # the box around the seed pixels (tested like contact, per pixel) and the contact
        self._seeds = (ContactTest(self.normalise, model.seed)
                       if model is not None and not model.static and model.separation > 1.0
                       else None)
        self._area_box: tuple[slice, slice] | None = None  # this frame's, with the seeds
        self._free = model.free_level() if model is not None and model.graded else None
        # a junction field (no resolved contact in the sampled frames): its faint contact
        # is sought where the seeds place it, also where no pixel reaches half coverage
        self._field = model is not None and model.junction_field
        # graded contact's faces reach past the half-coverage box: a face's faint back
        # behind its front band, a leaving face's back ahead of the first band in view
        self._widen = graded_back_px(setup.layout) if self._free is not None else 0
        # a static scene without resolved contact: in a frame that shows none, the lit zone
        # found may be one contact (TirView.warnings), the error bar's other end; its edge
        # is the half-light line to within the rim band, which that contact may go on past
        self._fill_px = 0.0
        if model is not None and _may_fill_zone(view.tir, model):
            past = 0 if model.beyond is None else np.count_nonzero(model.beyond)
            self._fill_px = float(np.count_nonzero(view.tir.lit.mask) + past)

    def segment(self, frame: np.ndarray) -> tuple[np.ndarray, FrameContact, tuple | None]:
        """Steps 1 to 3: the darkness (in the box, NaN elsewhere), the contact, and the
        column sums of the box's darkness (None without contact).

        Where the area reads a box (:meth:`extra_columns`), the darkness is computed in it
        too (it holds the contact's box and the features' columns)."""
        raw = self._test(frame)  # a reused buffer: `raw` does not outlive the frame
        box, counts = _box_and_counts(raw)
        area_box = None
        if self._seeds is not None:
            area_box = _union(contact_box(self._seeds(frame)), box, frame.shape,
                              ZONE_PX + EDGE_PX + 1)
        self._area_box = area_box
        threshold = self.view.threshold
        if box is None:  # no contact
            d = self._box.clear() if area_box is None else self._box.fill(frame, *area_box)
            return d, FrameContact(raw.shape, threshold, 0, d), None
        # the rows and (widened) columns the features read
        rows = box[0]
        cols = slice(max(box[1].start - EDGE_MARGIN_PX - self._widen, 0),
                     min(box[1].stop + EDGE_MARGIN_PX + self._widen, raw.shape[1]))
        # the darkness in the area's box (read alone by the area; it holds the features'
        # columns unless graded contact widened them) and the features' columns
        d = self._box.fill(frame, *_union(area_box, (rows, cols), frame.shape, 0))
        # the features' column sums, while the darkness is still in the cache
        sums = (rows.start, rows.stop, cols.start, cv2.reduce(
            d[rows, cols], 0, cv2.REDUCE_SUM, dtype=cv2.CV_32F).ravel())
        contact = segment_frame(d, threshold=threshold, raw=raw, box=box, counts=counts,
                                min_area_px=self.options.min_area_px)
        return d, contact, sums

    def __call__(self, k: int, frame: np.ndarray) -> FrameResult:
        """Analyse frame `frame`, recorded frame number `k`: contact, block, elements and,
        when wanted, regions."""
        s = self.setup
        t = k / s.fps
        d, contact, sums = self.segment(frame)
        row, el_rows = frame_rows(d, contact, s.layout, self.normalise.valid, t,
                                  self.options.peak_window_mm, sums, self._valid_counts,
                                  self._free, self._area_box if self._field else None)
        row["frame"] = k
        row["time_s"] = t
        row["n_regions"] = contact.n_regions
        self.extra_columns(frame, d, contact, row)
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

    def extra_columns(self, frame: np.ndarray, d: np.ndarray, contact: FrameContact,
                      row: dict[str, Any]) -> None:
        """Step 5: the row's columns from the video's population model and this frame: the
        contact area as a measurement with its error bar
        (:func:`tir_contact.measure.frame_area`).

        `d` is the darkness :meth:`segment` returned for `frame` (NaN outside the box it
        computed); `contact` the segmentation; the video's setup is ``self.setup``, its
        model ``self.view.area_model``.

        A fixed camera whose free surface separates from contact: only the box around the
        seed pixels (:class:`ContactTest` at the model's per-pixel seed level: on the raw
        grey values where the dtype allows) and the contact, grown by the zone around
        contact, is read, with the pixels :meth:`segment` tested; otherwise (a static
        scene, or a free surface that reaches past half of full contact) the whole frame,
        whose darkness budget then counts. In a static scene without resolved contact, a
        frame that shows no contact has the whole lit zone found, and the rim band's width
        past its edge (the edge's tolerance), as its bar's high end: a contact over all of
        it reads as a dim free surface (:func:`_may_fill_zone`).
        """
        model = self.view.area_model
        px2 = self.setup.mm_per_px ** 2
        if model is None:
            area = row["contact_area_mm2"]
            row["contact_area_low_mm2"] = row["contact_area_high_mm2"] = area
            return
        if self._seeds is not None:
            box = self._area_box
            if box is None:
                a = FrameArea(0.0, 0.0, 0.0, 0, 0.0)
            else:
                # the tests of the raw grey values are the darkness's own, pixel for pixel;
                # an integer frame's darkness is NaN exactly at the excluded pixels
                a = frame_area(d, model, box, seeds=self._seeds.last,
                               half=(self._test.last if self.view.threshold == model.threshold
                                     else None),
                               finite=self.normalise.valid if frame.dtype.kind in "ui" else None)
        else:
            a = frame_area(self.normalise(frame), model)
        high = a.high_px
        if self._fill_px and not row["block_in_view"]:
            high = max(high, self._fill_px)  # the whole lit zone found may be one contact
        row["contact_area_mm2"] = a.area_px * px2
        row["contact_area_low_mm2"] = a.low_px * px2
        row["contact_area_high_mm2"] = high * px2

    def _at_rim(self, contact: FrameContact) -> np.ndarray:
        """Which regions (index = label, 0 unused) touch the rim of the lit zone."""
        out = np.zeros(contact.n_regions + 1, bool)
        if contact.box is not None:
            out[contact.box_labels[self._rim[contact.box]]] = True
            out[0] = False
        return out


def _may_fill_zone(tref: TirReference, model: AreaModel) -> bool:
    """A static scene whose free surface was estimated (:func:`_static`: camera
    ``follows`` and no fitted ``--reference``) with no resolved contact in the sampled
    frames, its lit zone found
    in the footage: a contact over the whole lit zone shows no plateau of full contact
    beside free surface either, and its light, a fraction of the free surface's, is read
    as a dim free surface or as the outside: in the frames that show no contact, the error
    bar's high end is the whole lit zone found (:meth:`TirFrames.extra_columns`), and
    :meth:`TirView.warnings` says so."""
    return _static(tref) and tref.lit.method != "file" and model.junction_field


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


#: Share of the lit zone left unmeasured (too noisy) above which the analysis says so: the
#: area then counts contact on less than half of the zone, whatever the contact is.
MAX_UNMEASURED_SHARE = 0.5


def _too_noisy(t: TirReference) -> str | None:
    """A warning when most of the lit zone is too noisy to measure
    (:func:`tir_contact.reference.measurable`): contact there is not counted, and without
    it the area reads low, or zero (helper-11: read noise 6 DN at white level 0.3, 0 mm2 of
    411 without a word)."""
    lit = t.lit.mask
    n_lit = int(np.count_nonzero(lit))
    if not n_lit:
        return None
    share = 1.0 - np.count_nonzero(t.reference.valid & lit) / n_lit
    if share <= MAX_UNMEASURED_SHARE:
        return None
    sigma = t.noise.sigma_darkness(t.reference.image)[lit]
    return (f"{100 * share:.0f} % of the lit zone is too noisy to measure (darkness noise "
            f"{float(np.median(sigma)):.3f}, the median; a pixel is measured where its noise "
            "times noise_sigmas stays below the contact threshold): contact there is not "
            "counted and the area reads low; more light or a longer exposure, or a lower "
            "AnalysisOptions(noise_sigmas=...) at the risk of noise counted as contact")


def _tir_assumptions(t: TirReference) -> dict[str, Any]:
    """What the TIR analysis assumed about the light and the noise (``summary.json``)."""
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
        # a fixed camera's bright percentile, scaled to the free surface's mean by this
        "percentile_excess": t.percentile_excess,
    }


def _finite_or_none(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


# -- prepare: the free surface, contrast, threshold and populations ---------------------------
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
                options: AnalysisOptions, sigma: np.ndarray | None = None,
                optics: tuple[float, str] | None = None) -> AreaModel:
    """The darkness populations of a TIR video (:func:`tir_contact.measure.area_model`) from
    the sampled frames' darkness on the measured pixels (`sigma`: the free surface's
    darkness noise, :meth:`tir_contact.reference.NoiseModel.sigma_darkness`, computed here
    when not given)."""
    norm = Normaliser(tref.reference, contact_is)
    darkness = [norm(f) for f in samples]
    if sigma is None:
        sigma = tref.noise.sigma_darkness(tref.reference.image)
    return area_model(darkness, sigma, contrast=options.contrast,
                      min_cluster_px=options.min_area_px,
                      static=_static(tref), zone_sigma=tref.texture_sigma,
                      zone_corr_px=tref.texture_corr_px, rim=_rim_band(tref.lit),
                      bright=contact_is == "bright", optics=optics,
                      free_measured=tref.free_measured)


def _remeasured(samples: list[np.ndarray], whole: TirReference, tref: TirReference,
                model: AreaModel, threshold: float, contact_is: str,
                options: AnalysisOptions, sigma: np.ndarray | None = None,
                optics: tuple[float, str] | None = None
                ) -> tuple[TirReference, AreaModel]:
    """The measured pixels and the population model at the model's own decision.

    The first cut of the pixels too noisy to measure (:func:`tir_contact.reference.measurable`
    of `whole`, the free surface on the whole lit zone) is taken at `threshold`, the first
    estimate of the contrast's half; the model may then place the half-contact decision
    higher (a contrast first read low: a junction field whose darkness is a fraction of full
    contact's, the darkness of full contact then assumed). A pixel whose noise stays clear
    of that decision cannot cross it by noise: it is measured too, and the model is made
    again on the wider set. Not where the populations do not separate (the decision is then
    the free surface's reach, not contact's, and no measure of contact), and the new model
    is kept only where they still separate in it and its decision stays at least the one
    the pixels were cut at. Else `tref` and `model` as they are (the first model's notes
    are those of the model returned: `summary.json`'s `too_noisy_fraction` tells the cut).

    The dim rim of a lit disc in a dark 8-bit JPEG (white level 0.11, a physical block's
    junction field): 18 % of the frame was cut at the first estimate (0.15) and held up to
    63 % of the contact while the block entered, which no reading of the rest can see.
    `sigma`: the free surface's darkness noise, shared by both cuts and models.
    """
    if not (model.separation > 1.0 and model.threshold > threshold):
        return tref, model
    wider = measurable(whole, model.threshold, n_sigma=options.noise_sigmas, sigma=sigma)
    if np.count_nonzero(wider.reference.valid) <= np.count_nonzero(tref.reference.valid):
        return tref, model
    again = TirView.population_model(samples, wider, contact_is, options, sigma=sigma,
                                     optics=optics)
    if again.separation <= 1.0 or again.threshold < model.threshold:
        return tref, model
    return wider, again


def _rim_band(lit: LitZone) -> tuple[np.ndarray, np.ndarray, int] | None:
    """The lit zone's rim band, the unlit pixels within its width outside the zone (not
    the frame border), and the width (the zone's ``rim_px``; for a zone built without it,
    the rim pixels' largest depth from the edge, which reads up to 1 px over); None
    without a rim."""
    rim = lit.rim
    if rim is None or not rim.any():
        return None
    width = lit.rim_px
    if not width:
        depth = cv2.distanceTransform(np.pad(lit.mask, 1, mode="edge").view(np.uint8),
                                      cv2.DIST_L2, 3)[1:-1, 1:-1]
        width = max(1, round(float(depth[rim].max())))
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * width + 1,) * 2)
    beyond = cv2.dilate(lit.mask.view(np.uint8), disc).view(np.bool_) & ~lit.mask
    return rim, beyond, width


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


def _static(tref: TirReference) -> bool:
    """Whether the free surface under a static scene was estimated (nothing passed the
    camera and no reference image measured it): the static threshold floor and the
    estimate's texture then apply. A fitted ``--reference`` measures it, whatever the
    camera mode."""
    return tref.camera == "follows" and not tref.free_measured


def _tir_reference(samples: list[np.ndarray], shape: tuple[int, int], contact_is: str,
                   options: AnalysisOptions, travel_px: Sequence[float] | None = None
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
        own = tir_reference(samples, camera=options.camera, lit=lit, travel_px=travel_px,
                            **kwargs)
        if options.reference is None:
            return own, None, []
        raw = read_reference_file(options.reference, shape).image
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
        image = _covered_reference(fit, own)
        tref = tir_reference(samples, camera=own.camera, lit=own.lit, image=image,
                             **kwargs)
        method = (f"file, fitted: gain {fit.gain:.3f}, shift ({fit.shift_px[0]:+.2f}, "
                  f"{fit.shift_px[1]:+.2f}) px")
        return dataclasses.replace(tref, method=method, free_measured=True), fit, []
    except ValueError as exc:
        raise FootageError(str(exc), options.lit_mask) from exc


def _covered_reference(fit: ReferenceFit, own: TirReference) -> np.ndarray:
    """The fitted reference, and in the strip along the border that the shifted reference
    does not cover (``fit.inside`` False, as wide as the shift): the footage's own free
    surface where its frames show each pixel free (a block passing a fixed camera), else
    the reference's nearest covered pixel (``fit.image`` there: its edge, replicated).

    A static scene's own estimate is continued over the contact from around it and keeps
    the ice's bubbles and a bias of its level (measured on seed 7's small static rough pad
    and sphere: 0.06-0.31 darkness over the 3 px strip of a (3, -2) px shift, read as 47 and
    15 % extra contact); the light field changes little over the few pixels of a shift, so the
    reference's edge is the better estimate there.
    """
    if own.camera != "fixed":
        return fit.image
    return np.where(fit.inside, fit.image, own.reference.image.astype(np.float32))


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
