"""The free-surface image when the contact never leaves the view, and the image noise.

A TIR frame is read as darkness ``D = 1 - I / I_free`` against the free (contact-free)
surface ``I_free``. When the block passes a fixed camera, each pixel's bright percentile
over the frames is that surface, scaled down to the free surface's mean
(:func:`_excess_over_free_mean`: the percentile of noisy values lies above their mean, and a
reference too bright by a share ``b`` reads every darkness as ``b + D (1 - b)``). In a
static test, a single photograph or a camera that follows the block, no frame shows the
surface under the contact, and it has to be estimated from the frame itself.

Method of :func:`free_surface` (no contact size known in advance):

1. The image is smoothed (Gaussian, 1.5 px) against noise.
2. A grey closing with a disc of ``size`` px (on a copy shrunk to about 256 px) removes
   dark regions narrower than the disc and keeps the illumination: a closing leaves a
   dome-shaped (vignetted) light field as it is.
3. Contact candidates are the lit pixels darker than that closing by more than
   ``candidate_darkness``, with holes filled: a contact wider than the disc is only found
   along its edge, as a ring, and the fill makes it whole. A candidate whose edge is
   softer than the optics make a contact's (:data:`MAX_EDGE_PX`), or a clean step softer
   than the other contacts of the same image, smooth inside and lighter than them
   (:data:`EDGE_RATIO`: a fold of the light), is light, not contact; a region found to
   be light at one disc size stays light at the others. A contact inside a fold, or
   joined with one into a region, is told from it by its darkness against the fold's
   own light (:func:`_soft_cores`, :func:`_split_light`).
4. The disc must be wider than every candidate: when the widest candidate (twice its
   largest inscribed radius) needs more, the disc grows to 1.5 times that plus 10 px and
   steps 2-4 repeat. A contact wider than the disc that reaches the image border (a block
   larger than the view) shows only as its edges, which no hole fill closes: the disc is
   also doubled while that finds clearly more candidate area (over 1.2 times plus 1 % of
   the image). A contact wider than both discs (a face across the whole view, from border
   to border) stays dark under both: when lit pixels outside the candidates, over 1 % of
   the image, are darker than half of full contact against its bright light, the widest
   disc (the whole view) is tried, and kept when at least 90 % of the pixels it adds are
   that dark against its closing (a fall-off or texture it flattens grades down to the
   free surface instead).
5. The free surface is the smoothed image itself away from the candidates (so a soft rim
   or a speck of dust stays where it is). Over each candidate and a margin of 6 px around
   it, a quadratic surface fitted to a ring of free surface around it continues the light
   field (a closing would flatten a light maximum the contact covers).

:class:`NoiseModel` gives the darkness noise of each pixel: grey-value noise grows with the
signal (read noise plus shot noise, ``var = a + b I``), so the darkness noise
``sqrt(a + b I_free) / I_free`` is largest where the light is weakest.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from tir_contact._extension import extend_past_border
from tir_contact._morphology import disc_close, mask_dilate
from tir_contact._percentile import pixelwise_percentile
from tir_contact.flatfield import Reference, darkness
from tir_contact.illumination import LitZone, _fill_holes, find_lit_zone, shrink, whole_frame
from tir_contact.measure import (
    ASSUMED_FULL_DARKNESS,
    LOCAL_FREE_PX,
    _free_mean,
    correlation_area,
)
from tir_contact.travel import carried, column_profiles

__all__ = [
    "CAMERA_MODES",
    "FreeSurface",
    "NoiseModel",
    "TirReference",
    "absorbed_darkness",
    "free_surface",
    "measurable",
    "noise_model",
    "tir_reference",
]

#: Smoothing of the image (Gaussian sigma, px) before the free surface is estimated.
SMOOTH_SIGMA_PX = 1.5
#: Margin (px) around the contact candidates where the closing replaces the image.
MARGIN_PX = 6
#: Gap (px) between a contact and the free-surface ring fitted around it: the contact's
#: blurred edge stays out of the fit, a sipe of a few px between two elements stays in.
RING_GAP_PX = 2


@dataclass(frozen=True)
class FreeSurface:
    """Result of :func:`free_surface`.

    Attributes
    ----------
    image : (M, N) ndarray of float32
        The estimated contact-free surface.
    candidates : (M, N) ndarray of bool
        The contact candidates (holes filled) the estimate went around.
    size_px : int
        Diameter of the closing disc used.
    widest_px : float
        Widest candidate (twice its largest inscribed radius), px.
    texture_sigma, texture_corr_px : float
        Spread (relative) and correlation area (px) of the light's variation at scales
        below :data:`TEXTURE_SCALE_PX` on the free surface at least that far inside the
        lit zone's edge (:func:`_texture`, :func:`_inner`): what an estimate continued
        over a contact cannot follow there.
    first_candidates_px : int
        Candidate pixels of the starting disc, before it grew (the estimate's
        ``candidates`` when it did not grow).
    """

    image: np.ndarray
    candidates: np.ndarray
    size_px: int
    widest_px: float
    texture_sigma: float = 0.0
    texture_corr_px: float = 1.0
    first_candidates_px: int = 0


#: Darkness below the closing that a contact reaches and a fold of the light need not:
#: half the darkness of full contact (:data:`tir_contact.measure.ASSUMED_FULL_DARKNESS`).
CORE_DARKNESS = ASSUMED_FULL_DARKNESS / 2
#: Widest edge (px) of a contact candidate: its depth below the closing over the steepest
#: quarter of its boundary's light gradient. A contact's edge is as sharp as the optics
#: and the 1.5 px smoothing make it (Gaussian blur sigma s: sqrt(2 pi) s, 6.3 px for a
#: 2 px lens blur); light that falls off or folds inside the lit zone does so over tens
#: of pixels, and is not contact.
MAX_EDGE_PX = 8.0


#: A candidate whose edge is a clean step (half-depth width, :func:`_half_depth_widths`,
#: at most :data:`MAX_EDGE_PX`) but more than this many times as wide as the sharpest step
#: in the same image, eased in at its foot, smooth inside and lighter than that image's
#: contacts, is light falling off (a fold), not contact (:func:`_light`). Every contact of
#: one image is seen through the same optics, so their steps are equally sharp: the sharp
#: contacts of the domain, the table and the physical scenes read 3.9-4.7 px (the 1.5 px
#: smoothing alone: 3.8); the 0.3 mm fold of issue 21's table at 0.036 mm/px reads 6.5-6.7
#: px against 4.2-4.5 for the contacts beside it (1.5 times), which the foot width of
#: :func:`_edge_widths` put on either side of :data:`MAX_EDGE_PX` by the seed (three of
#: six seeds read the fold as contact, 180-200 % high). A fold within this factor of the
#: contacts' steps (a 0.15 mm fold here, 4 px) is not told apart from contact: an empty
#: frame (``--reference``) is.
EDGE_RATIO = 1.35
#: The sharpest step the 1.5 px smoothing leaves (sqrt(2 pi) * 1.5 px): a narrower reading
#: is noise, not a sharper optics.
STEP_FLOOR_PX = math.sqrt(2.0 * math.pi) * SMOOTH_SIGMA_PX
#: Texture (the spread of the darkness about its 3 px Gaussian average, 7 px inside its
#: edge, :class:`_Texture`) of a candidate's inside over that of the free surface, at
#: most which the inside is smooth: light carries the free surface's noise (0.7-1 times
#: it, by the share of light left and the noise's kind), texture and flaws (the table's
#: fold reads 0.8-3.9); contact carries its real-contact patches and junctions (the
#: table's patchy contacts 4-50: a weak guard for them, their step is what tells them).
SMOOTH_TEXTURE = 6.0
#: Half-depth pixels a region needs for its step width to be measured (a contact of
#: radius 6 px blurred by the smoothing alone has about 50).
MIN_EDGE_SAMPLES = 50


def _sharp(cand: np.ndarray, smooth: np.ndarray, closed: np.ndarray,
           lit: np.ndarray, grad: np.ndarray, light: np.ndarray | None = None) -> np.ndarray:
    """The sharp-edged part of the candidates `cand`: each 8-connected region whose edge
    width (:func:`_edge_widths`) is at most :data:`MAX_EDGE_PX` and that is not light
    falling off by its step (:func:`_light`); of a soft region (light falling off, a
    fold), the sharp regions darker than half of full contact inside it (a contact that
    lies in the fold) that are not light by their step either, with the soft region's
    pixels within :data:`MARGIN_PX` of them. `grad` is :func:`_gradient` of `smooth`.

    `light` (updated in place): the regions found to be light so far (at the disc sizes
    tried before; light first found at a wider disc that is then not taken does not
    reach back to the kept one), less the contacts found inside them; a region at least
    half in it is light too."""
    if not cand.any():
        return cand
    depth = closed - smooth
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(closed > 0, depth / np.maximum(closed, 1e-6), 0.0)
        rel = np.where(closed > 0, grad / np.maximum(closed, 1e-6), 0.0)
    n, lab = cv2.connectedComponents(cand.astype(np.uint8), connectivity=8, ltype=cv2.CV_32S)
    foot = _edge_widths(lab, n, grad, depth, lit)
    keep = foot <= MAX_EDGE_PX
    keep[0] = False
    texture = _Texture(d, cand, lit)
    steps, cores = _half_depth_widths(lab, n, d, rel, lit)
    measured = keep & np.isfinite(steps)
    found = np.zeros(n, bool)
    image_steps = None  # the image's sharpest step, darkest sharp core, texture
    if measured.any():
        sharpest = max(float(steps[measured].min()), STEP_FLOOR_PX)
        darkest = float(cores[measured & (steps <= EDGE_RATIO * sharpest)].max())
        image_steps = (sharpest, darkest, texture)
        found = _light(lab, n, foot, steps, cores, *image_steps)
    if light is not None and light.any():
        sizes = np.bincount(lab.ravel(), minlength=n)
        found |= 2 * np.bincount(lab[light], minlength=n) >= np.maximum(sizes, 1)
        found[0] = False
    keep &= ~found
    out = keep[lab]
    if image_steps is not None:
        out = _split_light(out, lab, n, keep & (steps > MAX_EDGE_PX), d, depth, rel, grad,
                           lit, image_steps)
    out = _soft_cores(out, cand & ~out, d, depth, closed, rel, grad, lit, image_steps)
    if light is not None:
        light |= found[lab] & ~out  # a contact found inside light stays contact
    return out


def _split_light(out: np.ndarray, lab: np.ndarray, n: int, mixed: np.ndarray, d: np.ndarray,
                 depth: np.ndarray, rel: np.ndarray, grad: np.ndarray, lit: np.ndarray,
                 image_steps: tuple[float, float, _Texture]) -> np.ndarray:
    """`out` without the light inside its `mixed` regions (kept by their foot, but no clean
    step at half depth: a fold joined with a contact, whose flat inside fills the band):
    each such region's contact (darker than half of full contact against its median
    level f, ``(d - f) / (1 - f)``) and :data:`MARGIN_PX` around it stay; the pieces of
    the rest that are light by their own step (:func:`_light`) go."""
    if not mixed[1:].any():
        return out
    region = mixed[lab]
    contact = region & (_against_own_light(lab, n, region, d)[0] > CORE_DARKNESS)
    kept = _within(contact, MARGIN_PX)
    rest = region & ~kept
    if not rest.any():
        return out
    m, rlab = cv2.connectedComponents(rest.astype(np.uint8), connectivity=8, ltype=cv2.CV_32S)
    r_foot = _edge_widths(rlab, m, grad, depth, lit)
    r_steps, r_cores = _half_depth_widths(rlab, m, d, rel, lit)
    gone = _light(rlab, m, r_foot, r_steps, r_cores, *image_steps) | (r_foot > MAX_EDGE_PX)
    gone[0] = False
    return out & ~gone[rlab]


def _soft_cores(out: np.ndarray, soft: np.ndarray, d: np.ndarray, depth: np.ndarray,
                closed: np.ndarray, rel: np.ndarray, grad: np.ndarray, lit: np.ndarray,
                steps: tuple[float, float, _Texture] | None) -> np.ndarray:
    """`out` with the sharp cores of the `soft` regions (:func:`_sharp`) and their pixels
    within :data:`MARGIN_PX`; `steps`: the image's sharpest step, darkest sharp core and
    texture for :func:`_light`, None where no step was measured."""
    core = soft & (d > CORE_DARKNESS)
    if not core.any():
        return out

    def sharp_cores(core: np.ndarray, dk: np.ndarray, dp: np.ndarray, rl: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, int]:
        # the cores of `core` sharp by their foot (darkness `dk`, its depth `dp` in grey
        # values, its relative gradient `rl`) and not light by their step
        m, clab = cv2.connectedComponents(core.astype(np.uint8), connectivity=8,
                                          ltype=cv2.CV_32S)
        c_foot = _edge_widths(clab, m, grad, dp, lit)
        ck = c_foot <= MAX_EDGE_PX
        if steps is not None:
            c_steps, c_cores = _half_depth_widths(clab, m, dk, rl, lit)
            ck &= ~_light(clab, m, c_foot, c_steps, c_cores, *steps)
        ck[0] = False
        return ck[clab], clab, m

    sharp_core, clab, m = sharp_cores(core, d, depth, rel)
    # a contact in a fold deeper than the core level joins the fold's inside in one core,
    # whose edge is the fold's: a soft core is judged again against its own light (its
    # median level f, the fold's where the fold is most of it), its contact darker than
    # half of full contact there, (d - f) / (1 - f), its edge read on that darkness
    dropped = core & ~sharp_core
    if dropped.any():
        d_in, f = _against_own_light(clab, m, dropped, d)
        inner = dropped & (d_in > CORE_DARKNESS)
        if inner.any():
            scale = np.where(dropped, 1.0 / np.maximum(1.0 - f, 1e-6), 1.0)
            sharp_core |= sharp_cores(inner, d_in, np.where(dropped, depth - f * closed,
                                                             depth), rel * scale)[0]
    if sharp_core.any():
        out |= _within(sharp_core, MARGIN_PX) & soft
    return out


def _within(mask: np.ndarray, px: int) -> np.ndarray:
    """The pixels within `px` of `mask` (a dilation by an elliptic disc of 2 px + 1)."""
    return mask_dilate(mask, 2 * px + 1)


def _against_own_light(lab: np.ndarray, n: int, region: np.ndarray, d: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray]:
    """The darkness `d` of the pixels of `region` against their labelled region's own
    light, ``(d - f) / (1 - f)`` with ``f`` the region's median darkness (a fold's level
    where the fold is most of it; 0 outside `region`), and ``f`` per pixel."""
    f = _group_quantiles(lab[region], d[region], n, 0.5)[lab]
    with np.errstate(divide="ignore", invalid="ignore"):
        d_in = np.where(region, (d - f) / np.maximum(1.0 - f, 1e-6), 0.0)
    return d_in, f


def _light(lab: np.ndarray, n: int, foot: np.ndarray, steps: np.ndarray, cores: np.ndarray,
           sharpest: float, darkest: float, texture: _Texture) -> np.ndarray:
    """Which labelled regions are light falling off by their step (:data:`EDGE_RATIO`): a
    clean step (at most :data:`MAX_EDGE_PX` wide, and its `foot` width, :func:`_edge_widths`,
    at least as wide: light that falls off smoothly eases in at its foot, as does any
    blurred step, where a junction field's sharp rim and the coverage grading inside it
    do not) more than :data:`EDGE_RATIO` times as wide as the image's `sharpest`, a
    smooth inside (:data:`SMOOTH_TEXTURE`) and a core lighter than the `darkest` core
    among the image's sharp steps (a smooth contact at full darkness, or as dark as the
    image's other contacts, stays contact)."""
    with np.errstate(invalid="ignore"):
        soft = ((steps > EDGE_RATIO * sharpest) & (steps <= MAX_EDGE_PX) & (foot >= steps)
                & (cores < darkest))
    if not soft[1:].any():
        return soft
    tex = texture.ratio(lab, n)
    with np.errstate(invalid="ignore"):
        return soft & (tex <= SMOOTH_TEXTURE)


class _Texture:
    """The darkness's spread about its 3 px Gaussian average (1.4826 times the median of
    its absolute value: the noise's sigma for Gaussian noise) inside regions (eroded by
    7 px, which leaves a step's curvature out; :data:`_TEXTURE_MIN_PX` pixels at least)
    over that of the lit free surface 7 px or more from the candidates."""

    def __init__(self, d: np.ndarray, cand: np.ndarray, lit: np.ndarray) -> None:
        # kept, not computed: most images have no region the step test calls soft
        self._d, self._cand, self._lit = d, cand, lit

    @functools.cached_property
    def res(self) -> np.ndarray:
        """The darkness's absolute residual about its 3 px Gaussian average."""
        d32 = self._d.astype(np.float32)
        return np.abs(d32 - cv2.GaussianBlur(d32, (0, 0), 3.0))

    @functools.cached_property
    def free(self) -> float:
        """The free surface's spread (NaN: under 100 free pixels)."""
        far = cv2.dilate(self._cand.astype(np.uint8), np.ones((15, 15), np.uint8)).astype(bool)
        free = self.res[self._lit & ~far]
        return 1.4826 * float(np.median(free)) if free.size >= 100 else math.nan

    def ratio(self, lab: np.ndarray, n: int) -> np.ndarray:
        """Texture of each region over the free surface's (NaN: too small, or no free
        surface to compare with)."""
        inner = cv2.erode((lab > 0).astype(np.uint8), np.ones((15, 15), np.uint8)).astype(bool)
        keys = lab[inner]
        counts = np.bincount(keys, minlength=n)
        out = np.full(n, math.nan)
        if not math.isfinite(self.free) or self.free <= 0:
            return out
        spread = 1.4826 * _group_quantiles(keys, self.res[inner], n, 0.5)
        ok = counts >= _TEXTURE_MIN_PX
        out[ok] = spread[ok] / self.free
        return out


#: Inside pixels a region needs for its texture to be measured.
_TEXTURE_MIN_PX = 30
#: Share of a region's core depth between which its step is read (where a blurred step's
#: gradient is within 25 % of its peak).
_HALF_BAND = (0.35, 0.65)


def _half_depth_widths(lab: np.ndarray, n: int, d: np.ndarray, rel: np.ndarray,
                       lit: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Step width (px) of each labelled region (NaN where it has fewer than
    :data:`MIN_EDGE_SAMPLES` step pixels), and its core depth (the 90th percentile of its
    darkness `d` against the closing): that depth over the median relative gradient `rel`
    of the lit pixels of it and its 2 px margin whose darkness lies within
    :data:`_HALF_BAND` of it. A step blurred by a Gaussian of sigma s reads sqrt(2 pi) s
    whatever its depth, where the foot width (:func:`_edge_widths`) grows with the depth."""
    widths = np.full(n, math.nan)
    inside = lab > 0
    core = _group_quantiles(lab[inside], d[inside], n, 0.9)
    # the region and its 2 px margin (labels are exact in float32 below 2**24)
    grown = cv2.dilate(lab.astype(np.float32), np.ones((5, 5), np.uint8)).astype(np.int32)
    owner = np.where(lab > 0, lab, grown)  # a region's own pixels stay its own
    level = core[owner]
    band = (owner > 0) & lit & (d >= _HALF_BAND[0] * level) & (d <= _HALF_BAND[1] * level)
    g, counts = _group_medians(owner[band], rel[band], n)
    ok = (counts >= MIN_EDGE_SAMPLES) & (g > 0)
    ok[0] = False
    widths[ok] = core[ok] / g[ok]
    return widths, core


def _grouped(keys: np.ndarray, values: np.ndarray, n: int
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """`values` sorted by key, then by value (one sort for all keys), with each key's
    count and start in it, for keys ``0..n-1``."""
    v = values[np.lexsort((values, keys))]
    counts = np.bincount(keys, minlength=n)
    starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
    return v, counts, starts


def _group_quantiles(keys: np.ndarray, values: np.ndarray, n: int, q: float) -> np.ndarray:
    """The `q` quantile (the value at rank ``floor(q (count - 1))``) of `values` for each
    key in ``0..n-1``, 0 for keys that do not occur."""
    v, counts, starts = _grouped(keys, values, n)
    out = np.zeros(n)
    has = counts > 0
    out[has] = v[starts[has] + np.floor(q * (counts[has] - 1)).astype(np.int64)]
    return out


def _gradient(smooth: np.ndarray) -> np.ndarray:
    """Magnitude of the light's gradient, grey values per px."""
    gx = cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=3, scale=0.125)
    gy = cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=3, scale=0.125)
    return cv2.magnitude(gx, gy)


def _edge_widths(lab: np.ndarray, n: int, grad: np.ndarray, depth: np.ndarray,
                 lit: np.ndarray) -> np.ndarray:
    """Edge width (px) of each labelled region (index = label): its median depth below the
    closing over the median gradient on its lit boundary ring (0 for a
    region without one: it is kept)."""
    mask = (lab > 0).astype(np.uint8)
    inner = cv2.erode(mask, np.ones((3, 3), np.uint8)).astype(bool)
    ring = cv2.dilate(mask, np.ones((3, 3), np.uint8)).astype(bool) & ~inner & lit
    owner = cv2.dilate(lab.astype(np.float32), np.ones((3, 3), np.uint8)).astype(np.int32)
    g, counts = _group_medians(owner[ring], grad[ring], n)
    dk, _ = _group_medians(lab[lab > 0], depth[lab > 0], n)
    has = counts > 0
    widths = np.zeros(n)
    with np.errstate(divide="ignore", invalid="ignore"):
        widths[has] = np.where(g[has] > 0, dk[has] / g[has], np.inf)
    return widths


def _group_medians(keys: np.ndarray, values: np.ndarray, n: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Median of `values` for each key in ``0..n-1`` (as :func:`numpy.median`: the mean of
    the two middle values of an even group, in the values' dtype; 0 for keys that do not
    occur) and each key's count; one sort instead of a pass over the image per key."""
    v, counts, starts = _grouped(keys, values, n)
    has = counts > 0
    med = np.zeros(n)
    c, s0 = counts[has], starts[has]
    lo, hi = v[s0 + (c - 1) // 2], v[s0 + c // 2]
    med[has] = np.where(c % 2 == 1, hi, (lo + hi) / v.dtype.type(2))
    return med, counts


#: Widest disc (px, on the working image) of a closing done at the working scale; a wider
#: one works on block maxima (:func:`_closing`). Discs up to this size keep the exact
#: closing (a disc grows past it only for contact that fills most of the image).
MAX_DISC_PX = 201


def _closing(smooth: np.ndarray, size_px: int, lit: np.ndarray | None = None) -> np.ndarray:
    """Grey closing with a disc of `size_px`, on a shrunk copy, back at full size; `lit`:
    the lit zone, whose rim is free past the border (:mod:`tir_contact._extension`)."""
    h, w = smooth.shape
    small, scale = shrink(smooth)
    zone = None
    if lit is not None and not lit.all():
        zone = cv2.resize(lit.astype(np.float32), small.shape[::-1],
                          interpolation=cv2.INTER_AREA) if scale < 1.0 else lit
    d = max(3, round(size_px * scale) | 1)
    # A wider disc works on the maxima of pool x pool blocks with a disc shrunk alike: the
    # closing is an upper envelope, which block maxima keep (block means lowered it where
    # texture peaks set it), and its shape varies over the disc's size, not the pool's
    # (a 401 px disc took 1 s, 30x a 101 px one; tests/test_closing.py holds it to the
    # full-resolution closing).
    pool = math.ceil(d / MAX_DISC_PX)
    hs, ws = small.shape
    if pool > 1:
        hp, wp = -(-hs // pool) * pool, -(-ws // pool) * pool
        small = np.pad(small, ((0, hp - hs), (0, wp - ws)), mode="edge").reshape(
            hp // pool, pool, wp // pool, pool).max(axis=(1, 3))
        if zone is not None:
            zone = np.pad(np.asarray(zone, np.float32), ((0, hp - hs), (0, wp - ws)),
                          mode="edge").reshape(hp // pool, pool, wp // pool, pool).max(
                              axis=(1, 3))
        d = max(3, round(d / pool) | 1)
    # The image is extended past its border by odd reflection (2 f(border) - f(inside)),
    # which continues a light falling towards the border: a mirror or a constant would
    # turn it into a valley the closing fills. A closing leaves light fields whose
    # brighter-than sets are convex (a vignetted disc or band) exactly as they are.
    # A dark contact near the border would come back as a bright bump: the extension is
    # capped at the border value. Past the lit zone's rim where it crosses the border the
    # light is free (tir_contact._extension).
    pad = d // 2 + 2
    lit_zone = None if zone is None else np.asarray(zone) > 0.5
    big = extend_past_border(small, lit_zone, pad, d // 2)
    closed = disc_close(big, d)  # OpenCV's closing with its elliptic disc, faster
    blurred = cv2.GaussianBlur(closed, (0, 0), 1.0)
    if lit_zone is not None:
        # The Gaussian lifts a steep edge's dark foot above the closing (the ring by
        # which a contact wider than the disc shows its edges and grows the disc). At the
        # lit zone's edge that foot is the rim's light (0.1-0.25 darkness where the rim
        # crosses the border): within the blur's reach (3 sigma) of the unlit outside
        # the closing is smoothed but not lifted.
        near = cv2.dilate((~np.pad(lit_zone, pad, mode="edge")).astype(np.uint8),
                          np.ones((7, 7), np.uint8)).astype(bool)
        blurred = np.where(near, np.minimum(blurred, closed), blurred)
    lift = np.maximum(closed - big, 0.0)  # what the closing itself fills
    closed = blurred
    if pool == 1 and scale >= 1.0:
        return np.maximum(closed[pad:-pad, pad:-pad], smooth)
    # back at full size, interpolated in the padded closing: a resize of the cropped one
    # holds the first working row over the half working pixel beyond its centre, which
    # on a steep rim crossing the border (1 px a row) read 0.3 darkness
    fy = (np.arange(h) + 0.5) * (hs / h) / pool - 0.5 + pad
    fx = (np.arange(w) + 0.5) * (ws / w) / pool - 0.5 + pad
    map_x, map_y = np.meshgrid(fx.astype(np.float32), fy.astype(np.float32))
    closed = cv2.remap(closed, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    if lit_zone is not None:
        # and there no pixel is lifted above the image by more than the closing fills the
        # working pixels by it: the light interpolated from the working scale lies above
        # the image on a steep rim's foot (0.1 darkness at 0.4 x), which is no fill
        lift, rim = (cv2.remap(x, map_x, map_y, cv2.INTER_LINEAR,
                               borderMode=cv2.BORDER_REPLICATE)
                     for x in (lift, near.astype(np.float32)))
        closed = np.where(rim > 0, np.minimum(closed, smooth + lift), closed)
    return np.maximum(closed, smooth)  # a closing never lies below the image


def free_surface(
    image: np.ndarray,
    lit: np.ndarray | None = None,
    *,
    contact_is: str = "dark",
    candidate_darkness: float = 0.1,
    size_px: int = 101,
    grow: bool = True,
    texture: bool = True,
) -> FreeSurface:
    """Estimate the contact-free surface of an image that shows contact (module notes).

    Parameters
    ----------
    image : (M, N) ndarray
        A frame, or the temporal median of the frames of a static test.
    lit : (M, N) ndarray of bool, optional
        Where light reaches (:func:`tir_contact.illumination.find_lit_zone`); all of it by
        default.
    contact_is : {"dark", "bright"}
        Bright contact uses an opening instead of a closing (the image is mirrored).
    candidate_darkness : float
        Darkness against the closing above which a pixel is a contact candidate.
    size_px : int
        Starting diameter of the closing disc, px.
    grow : bool
        Let the disc grow with the widest candidate (False: keep `size_px`, e.g. per frame
        of a video whose contact size is known from its first frames).
    texture : bool
        Measure the texture the estimate does not follow
        (:attr:`FreeSurface.texture_sigma`; False: 0 and 1, where it is not used).

    Returns
    -------
    FreeSurface

    Examples
    --------
    >>> yy, xx = np.mgrid[:120, :160]
    >>> light = 200.0 - 0.008 * ((xx - 80) ** 2 + (yy - 60) ** 2)  # vignetted
    >>> contact = (xx - 75) ** 2 + (yy - 55) ** 2 < 35 ** 2        # 70 px across
    >>> fs = free_surface(np.where(contact, 0.3 * light, light), size_px=31)
    >>> fs.size_px > 70, float(np.abs(fs.image / light - 1).max()) < 0.05
    (True, True)
    """
    img = np.asarray(image, dtype=np.float32)
    if img.ndim != 2:
        raise ValueError(f"image must be 2-D, got shape {img.shape}")
    if contact_is not in ("dark", "bright"):
        raise ValueError(f"contact_is must be 'dark' or 'bright', got {contact_is!r}")
    top = float(img.max()) if img.size else 0.0
    work = img if contact_is == "dark" else top - img
    lit_mask = np.ones(img.shape, bool) if lit is None else np.asarray(lit, bool)
    smooth = cv2.GaussianBlur(work, (0, 0), SMOOTH_SIGMA_PX, borderType=cv2.BORDER_REPLICATE)
    size = max(3, int(size_px) | 1)
    largest = 2 * max(img.shape) + 1
    grad = _gradient(smooth)  # the candidates' edge widths, at any disc size
    # light falling off found at any disc size (filled in by _sharp): a property of the
    # image's light, not of the disc, so a region the step test reads on either side of
    # its bound at two sizes cannot make the disc grow
    light = np.zeros(img.shape, bool)

    def candidates(size: int) -> tuple[np.ndarray, np.ndarray, float]:
        closed = _closing(smooth, size, lit_mask)
        # a pixel the closing leaves unlit (grey 0: black footage) has no light to lose:
        # its darkness is 0, not 1 (which made every pixel a candidate and grew the disc
        # to the whole image, 30x the time of a normal clip)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = np.where(closed > 0, 1.0 - smooth / np.maximum(closed, 1e-6), 0.0)
        cand = _fill_holes(((d > candidate_darkness) & lit_mask).astype(np.uint8)).astype(bool)
        cand = _sharp(cand, smooth, closed, lit_mask, grad, light)
        widest = 0.0
        if cand.any():
            dist = cv2.distanceTransform(cand.astype(np.uint8), cv2.DIST_L2, 5)
            # no free pixel at all (black footage): the distance is huge; cap at the image
            widest = min(2.0 * float(dist.max()), float(max(img.shape)))
        return closed, cand, widest

    def no_more(trial: tuple[np.ndarray, np.ndarray, float]) -> bool:
        # a wider disc's candidates are not clearly more (1.2 times plus 1 % of the image)
        return trial[1].sum() <= 1.2 * cand.sum() + 0.01 * cand.size

    closed, cand, widest = candidates(size)
    first = int(np.count_nonzero(cand))
    for _ in range(6):
        if not grow or size >= largest:
            break
        need = math.ceil(1.5 * widest + 10) | 1
        if need > size:  # a candidate as wide as the disc: grow the disc past it
            size = min(need, largest)
            closed, cand, widest = candidates(size)
            continue
        # A contact wider than the disc shows only its edges, and where it reaches the
        # image border (a block larger than the view) no hole fill makes it whole: a
        # disc twice as wide finds clearly more candidate area then.
        wider = min(2 * size + 1, largest)
        trial = candidates(wider)
        if no_more(trial) and wider < largest and _dark_beyond(smooth, cand, lit_mask):
            # contact wider than both discs (a block filling the view from border to
            # border) is dark under both alike: the widest disc (the whole view) fills it,
            # and the pixels it adds are contact when they are at contact's darkness
            trial = candidates(largest)
            if not _contact_dark(trial, cand, smooth):
                break
            wider = largest
        if no_more(trial):
            break
        size, (closed, cand, widest) = wider, trial
    margin = _within(cand, MARGIN_PX)
    surface = np.where(margin, closed, smooth).astype(np.float32)
    near = _within(cand, RING_GAP_PX)
    _fit_over_contacts(surface, smooth, margin, near, lit_mask, widest)
    if contact_is == "bright":
        surface = (top - surface).astype(np.float32)
    tex, tex_corr = _texture(smooth, _inner(lit_mask, ~margin)) if texture else (0.0, 1.0)
    return FreeSurface(surface, cand, size, widest, tex, tex_corr, first)


def _dark_beyond(smooth: np.ndarray, cand: np.ndarray, lit: np.ndarray) -> bool:
    """Whether the lit pixels outside the candidates `cand` that are darker than half of
    full contact against the bright light (the 95th percentile of the lit image) are over
    1 % of the image: only then can contact wider than the discs remain unfound (the
    widest disc's closing is not tried otherwise)."""
    values = smooth[lit]
    if values.size == 0:
        return False
    bright = float(np.percentile(values, 95.0))
    dark = (smooth < (1.0 - ASSUMED_FULL_DARKNESS / 2) * bright) & lit & ~cand
    return int(np.count_nonzero(dark)) > 0.01 * smooth.size


def _contact_dark(trial: tuple[np.ndarray, np.ndarray, float], cand: np.ndarray,
                  smooth: np.ndarray) -> bool:
    """Whether the candidates a wider disc adds (`trial`: its closing and candidates, over
    the candidates `cand` of the narrower one) are contact: at least 90 % of them darker
    against its closing than half of full contact (the resolved contact's threshold, at
    the assumed full darkness). A light field's fall-off, a rim or a texture that the
    widest disc flattens grades down to the free surface instead."""
    closed, wide, _ = trial
    extra = wide & ~cand
    if not extra.any():
        return False
    with np.errstate(divide="ignore", invalid="ignore"):
        d = 1.0 - smooth[extra] / np.maximum(closed[extra], 1e-6)
    return float(np.percentile(d, 10.0)) >= ASSUMED_FULL_DARKNESS / 2


#: Scale (Gaussian sigma, px) of the light field an estimate over a contact continues:
#: twice the margin around the candidates.
TEXTURE_SCALE_PX = 2 * MARGIN_PX


def _inner(lit: np.ndarray, free: np.ndarray) -> np.ndarray:
    """The `free` lit pixels farther than :data:`TEXTURE_SCALE_PX` from the lit zone's edge
    (all the free lit pixels where that leaves under :data:`MIN_TEXTURE_PX`): the light
    field the texture is read against (a Gaussian over that scale) holds little of the
    unlit outside there, whose fall-off at the rim would read as texture."""
    if lit.all():
        return free
    dist = cv2.distanceTransform(lit.astype(np.uint8), cv2.DIST_L2, 3)
    inner = (dist > TEXTURE_SCALE_PX) & free
    return inner if np.count_nonzero(inner) >= MIN_TEXTURE_PX else lit & free


#: Fewest free pixels the texture is measured on.
MIN_TEXTURE_PX = 100


def _texture(smooth: np.ndarray, free: np.ndarray) -> tuple[float, float]:
    """Robust spread (1.4826 MAD) of ``smooth / field - 1`` on the `free` pixels, ``field``
    the light smoothed over :data:`TEXTURE_SCALE_PX`, and its correlation area in px
    (:func:`tir_contact.measure.correlation_area`)."""
    if free.sum() < MIN_TEXTURE_PX:
        return 0.0, 1.0
    field = cv2.GaussianBlur(smooth, (0, 0), TEXTURE_SCALE_PX)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(free & (field > 0), smooth / np.maximum(field, 1e-6) - 1.0, np.nan)
    values = t[np.isfinite(t)]
    if values.size < MIN_TEXTURE_PX:  # no light to measure it on (black footage)
        return 0.0, 1.0
    mid = float(np.median(values))
    sigma = float(1.4826 * np.median(np.abs(values - mid)))
    return sigma, correlation_area([t], mid, sigma)


#: Contacts (largest first) whose free surface is fitted by a quadratic; the rest keep the
#: closing.
MAX_FITTED = 16


def _fit_over_contacts(surface: np.ndarray, smooth: np.ndarray, margin: np.ndarray,
                       near: np.ndarray, lit: np.ndarray, widest: float) -> None:
    """Replace the closing over each contact by a quadratic fitted around it (in place).

    A closing cannot restore a light maximum that the contact covers (a vignetted centre):
    it leaves it flat. A quadratic surface ``c0 + c1 x + ... + c5 y^2`` fitted to the free
    surface in a ring around the contact (as wide as half the widest contact, at least
    15 px) continues the curvature. Rings with too few lit pixels keep the closing.
    """
    n, labels, stats, _ = cv2.connectedComponentsWithStats(margin.astype(np.uint8), 8)
    if n <= 1:
        return
    ring_px = max(15, round(widest / 2))
    order = np.argsort(stats[1:, cv2.CC_STAT_AREA])[::-1][:MAX_FITTED] + 1
    h, w = surface.shape
    for k in order:
        x0, y0, bw, bh = (int(v) for v in stats[k, :4])
        r0, r1 = max(0, y0 - ring_px), min(h, y0 + bh + ring_px)
        c0, c1 = max(0, x0 - ring_px), min(w, x0 + bw + ring_px)
        inside = labels[r0:r1, c0:c1] == k
        ring = mask_dilate(inside, 2 * ring_px + 1) & ~near[r0:r1, c0:c1] & lit[r0:r1, c0:c1]
        if ring.sum() < 30:
            continue
        yy, xx = np.nonzero(ring)
        scale = float(max(r1 - r0, c1 - c0))
        coef, *_ = np.linalg.lstsq(_quadratic(yy, xx, scale), smooth[r0:r1, c0:c1][ring],
                                   rcond=None)
        iy, ix = np.nonzero(inside)
        surface[r0 + iy, c0 + ix] = (_quadratic(iy, ix, scale) @ coef).astype(np.float32)


def _quadratic(y: np.ndarray, x: np.ndarray, scale: float) -> np.ndarray:
    """Design matrix of a quadratic surface in ``(x, y) / scale``."""
    u, v = x / scale, y / scale
    return np.stack([np.ones_like(u), u, v, u * u, u * v, v * v], axis=1)


@dataclass(frozen=True)
class NoiseModel:
    """Grey-value noise of the free surface: ``var(I) = a + b * I`` (read + shot noise).

    Attributes
    ----------
    a : float
        Signal-independent variance, DN².
    b : float
        Variance per DN of signal (shot noise), DN.
    n_pixels : int
        Free-surface pixels the model was fitted to.
    """

    a: float
    b: float
    n_pixels: int

    def sigma_grey(self, level: np.ndarray | float) -> np.ndarray:
        """Standard deviation of a grey value at `level`, DN."""
        return np.sqrt(np.maximum(self.a + self.b * np.asarray(level, float), 0.0))

    def sigma_darkness(self, free: np.ndarray) -> np.ndarray:
        """Standard deviation of the darkness ``1 - I / free`` at each pixel."""
        free = np.asarray(free, np.float64)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = self.sigma_grey(free) / free
        return np.where(free > 0, s, np.inf).astype(np.float32)


#: Residual values a noise model is fitted to, at most.
MAX_NOISE_SAMPLES = 200_000


def noise_model(residuals: list[np.ndarray], levels: np.ndarray,
                usable: np.ndarray) -> NoiseModel:
    """Fit :class:`NoiseModel` to noise residuals of the free surface.

    The robust variance (1.4826 x the median absolute deviation, squared) of the residuals
    is taken in ten bins of the free-surface level and a line ``a + b I`` fitted
    (``a, b >= 0``). The MAD ignores the minority of pixels where a residual holds
    contact or texture rather than noise.

    Parameters
    ----------
    residuals : list of (M, N) ndarray
        Pure-noise residuals in grey values: the difference of two frames of a static
        scene divided by sqrt(2), or a frame minus its free surface.
    levels : (M, N) ndarray
        The free-surface grey level of each pixel.
    usable : (M, N) ndarray of bool
        Lit pixels away from any contact.

    Returns
    -------
    NoiseModel

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> level = np.tile(np.linspace(20, 200, 300), (200, 1))
    >>> res = [rng.normal(0, np.sqrt(4 + 0.5 * level)) for _ in range(2)]
    >>> m = noise_model(res, level, np.ones(level.shape, bool))
    >>> bool(abs(m.a - 4) < 1.5), bool(abs(m.b - 0.5) < 0.03)
    (True, True)
    """
    idx = np.flatnonzero(np.asarray(usable, bool))
    if not idx.size or not residuals:
        return NoiseModel(0.0, 0.0, 0)
    # an even subsample of at most MAX_NOISE_SAMPLES values in all: the variance of a
    # bin of 10^4 values is known to 1.4 % already
    idx = idx[::max(1, math.ceil(idx.size * len(residuals) / MAX_NOISE_SAMPLES))]
    ref = np.asarray(levels, np.float32).ravel()[idx]
    res = np.concatenate([np.asarray(r, np.float32).ravel()[idx] for r in residuals])
    lev = np.tile(ref, len(residuals))
    finite = np.isfinite(res)  # NaN: a residual that is not noise (contact in a sample)
    if not finite.all():
        res, lev = res[finite], lev[finite]
        if not res.size:
            return NoiseModel(0.0, 0.0, 0)
    edges = np.unique(np.percentile(ref, np.linspace(0, 100, 11)))
    bins = np.clip(np.searchsorted(edges, lev, side="right") - 1, 0, max(len(edges) - 2, 0))
    level_list, variances = [], []
    for b in range(max(len(edges) - 1, 0)):
        pick = bins == b
        if pick.sum() < 50:
            continue
        r = res[pick]
        mad = float(np.median(np.abs(r - np.median(r))))
        level_list.append(float(np.median(lev[pick])))
        variances.append((1.4826 * mad) ** 2)
    if not level_list:
        mad = float(np.median(np.abs(res - np.median(res))))
        return NoiseModel((1.4826 * mad) ** 2, 0.0, int(res.size))
    x, y = np.array(level_list), np.array(variances)
    if len(x) >= 2 and np.ptp(x) > 0:
        b, a = np.polyfit(x, y, 1)
        if b < 0:
            a, b = float(np.mean(y)), 0.0
        elif a < 0:
            a, b = 0.0, float(np.sum(x * y) / np.sum(x * x))
    else:
        a, b = float(y.mean()), 0.0
    return NoiseModel(float(a), float(b), int(res.size))


# --------------------------------------------------------------------------------------------
# the reference of one TIR video


#: Bright contact: the free surface is taken as at least this fraction of the contact's
#: level (the largest 99.9th percentile of a sample).
BRIGHT_FLOOR = 0.05
#: Bright contact: a lit zone of the free surface is taken when its median light is at
#: least this many times the outside's (and the outside holds light at all).
BRIGHT_LIT_CONTRAST = 2.0


def absorbed_darkness(surface: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """The share of the light by which a static scene's free-surface estimate lies below
    its grey closing by the local free surface's disc
    (:data:`tir_contact.measure.LOCAL_FREE_PX`): the estimate's darkness against that
    closing (:func:`tir_contact.flatfield.darkness`). It holds the dark spots narrower than
    the disc the estimate followed, which may be junctions it took for the light (those
    not found as contact candidates are the image itself there) or the light's own
    texture; the closing also lifts every pixel to its noise's upper envelope
    (:func:`tir_contact.measure.with_absorbed` takes the median lift out).

    Parameters
    ----------
    surface : (M, N) ndarray
        The estimate, grey values (:attr:`tir_contact.flatfield.Reference.image`).
    valid : (M, N) ndarray of bool
        The measured pixels; NaN elsewhere.

    Returns
    -------
    (M, N) ndarray of float32

    Examples
    --------
    >>> s = np.full((40, 40), 100.0, np.float32); s[20, 20] = 60.0  # a followed spot
    >>> a = absorbed_darkness(s, np.ones(s.shape, bool))
    >>> round(float(a[20, 20]), 2), float(a[5, 5])
    (0.4, 0.0)
    """
    s = np.asarray(surface, np.float32)
    closed = disc_close(s, LOCAL_FREE_PX)  # a closing never lies below the image
    return darkness(s, Reference(closed, np.asarray(valid, bool), "closing", 1))


def lit_zone_of_surface(free: np.ndarray) -> LitZone:
    """Bright contact: the lit zone as the free surface shows it, else the whole frame.

    Under bright contact the free surface is dark, but the light escaping it still shows
    where the TIR light reaches, and contact glows wherever light reaches it, the little
    light outside the zone included. The zone is found on the free-surface estimate (the
    contact removed, so that a static glowing contact is not taken for the zone) and kept
    when its median light is at least :data:`BRIGHT_LIT_CONTRAST` times the outside's; a
    surface without light (a dark field quantised to 0-1 grey values) or without a clear
    zone keeps the whole frame.

    Examples
    --------
    >>> yy = np.mgrid[:100, :120][0]
    >>> band = np.where((yy > 30) & (yy < 70), 40.0, 8.0)
    >>> round(lit_zone_of_surface(band).fraction, 2)
    0.39
    >>> lit_zone_of_surface(np.zeros((100, 120))).method
    'whole frame'
    """
    img = np.asarray(free, np.float32)
    zone = find_lit_zone(img)
    if zone.method == "found" and zone.mask.any() and not zone.mask.all():
        inside = float(np.median(img[zone.mask]))
        outside = float(np.median(img[~zone.mask]))
        if inside >= BRIGHT_LIT_CONTRAST * max(outside, 1.0):
            return zone
    return whole_frame(img.shape)

#: Camera modes: the block passes a fixed camera, or the contact stays in view (a camera that
#: follows the block, a static test, a single photograph).
CAMERA_MODES = ("fixed", "follows")


@dataclass(frozen=True)
class TirReference:
    """Everything the darkness of a TIR video is measured against.

    Attributes
    ----------
    reference : Reference
        Free-surface image; ``valid`` is the lit zone less the pixels too noisy to measure
        (see :func:`measurable`).
    lit : LitZone
        Where TIR light reaches.
    camera : {"fixed", "follows"}
        ``"fixed"``: the block passes the camera, so some frames show each pixel free;
        ``"follows"``: the contact stays in view (no frame shows the surface under it).
    method : str
        How the free surface was made, in words (for ``summary.json``).
    noise : NoiseModel
        Grey-value noise of the free surface.
    texture_sigma, texture_corr_px : float
        Free surface estimated from the image (a static scene): the light's variation the
        estimate cannot follow over a contact (:attr:`FreeSurface.texture_sigma`); 0 and 1
        when frames show the free surface.
    percentile_excess : float
        A fixed camera's bright percentile: the share by which it lay above the free
        surface's mean, taken out of ``reference`` (:func:`_excess_over_free_mean`); 0 else.
    free_measured : bool
        ``reference`` is a measured image of the free surface (the rig's empty frame, a
        user's ``--reference`` that fits the footage), not an estimate from the footage.
    """

    reference: Reference
    lit: LitZone
    camera: str
    method: str
    noise: NoiseModel
    texture_sigma: float = 0.0
    texture_corr_px: float = 1.0
    percentile_excess: float = 0.0
    free_measured: bool = False


def _median(frames: list[np.ndarray]) -> np.ndarray:
    """Pixel-wise median of the frames, float32 (a sorting network: 20x numpy's median)."""

    if len(frames) == 1:
        return np.asarray(frames[0], np.float32)
    return np.asarray(pixelwise_percentile(frames, 50.0), np.float32)


def _moving(samples: list[np.ndarray], median: np.ndarray, base: np.ndarray, lit: np.ndarray,
            min_darkness: float, min_fraction: float, contact_is: str = "dark") -> bool:
    """True when some sampled frame differs from the others by a block-sized darker region.

    Each frame is compared with `median`, the pixel-wise median of the samples, as
    darkness against `base`; a 3 x 3 opening removes isolated noise pixels. A region darker
    by `min_darkness` over more than `min_fraction` of the lit pixels means something moved.
    """
    need = max(16.0, min_fraction * float(lit.sum()))
    kernel = np.ones((3, 3), np.uint8)
    for dark in _departures(samples, median, base, lit, contact_is):
        diff = (dark > min_darkness).astype(np.uint8)
        if cv2.countNonZero(cv2.morphologyEx(diff, cv2.MORPH_OPEN, kernel)) > need:
            return True
    return False


def _departures(samples: list[np.ndarray], median: np.ndarray, base: np.ndarray,
                lit: np.ndarray, contact_is: str = "dark") -> Iterator[np.ndarray]:
    """Each sample's darkness against `median`, in units of `base`, 0 outside `lit`
    (contact positive, for bright contact too)."""
    inv = np.where(lit, 1.0 / np.maximum(base, 1e-6), 0.0).astype(np.float32)
    sign = np.float32(1.0 if contact_is == "dark" else -1.0)
    for f in samples:
        yield (median - np.asarray(f, np.float32)) * inv * sign


#: Contact runs in a sampled frame where a stretch of columns is darker than the samples'
#: median by this many robust spreads (each column's spread over the samples, their median
#: over the columns) ...
RUN_SIGMAS = 6.0
#: ... over at least this share of the lit zone's extent along the rows.
MIN_RUN_FRACTION = 0.03
#: Contact translates when the runs' centres over the samples span this share of the lit
#: zone's extent along the rows: a block passing a fixed camera crosses the view, held
#: contact (a static test, a camera that follows the block) stays. Measured on 168
#: rendered TIR clips (seed 0's 200 domain draws, 24 physical draws of seeds 0 and 7; the
#: pipeline's own samples): at most 0.22 where the contact is held (133 clips), 0.77-0.97
#: where a block passes and :func:`_moving` misses it (faint patchy contact, 10 clips).
MIN_TRAVEL_FRACTION = 0.6


def _widest_run(on: np.ndarray) -> tuple[int, int]:
    """Start and length of the longest run of True in a 1-D bool array (0, 0 for none)."""
    edges = np.diff(np.concatenate(([0], on.astype(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    if starts.size == 0:
        return 0, 0
    k = int(np.argmax(ends - starts))
    return int(starts[k]), int(ends[k] - starts[k])


def _travel(samples: list[np.ndarray], median: np.ndarray, lit: np.ndarray,
            contact_is: str = "dark") -> float:
    """How far darker contact travels along the rows through the sampled frames, as a
    share of the lit zone's extent along them (0 when it is seen in fewer than 2 samples).

    Each frame's darkness against `median` is averaged down each column of the lit zone
    (a profile along the sliding direction, over the columns from the zone's first to its
    last) and its median over those columns taken out (exposure). Per frame, the widest
    run of columns darker than the samples' median profile by :data:`RUN_SIGMAS` robust
    spreads, if it is :data:`MIN_RUN_FRACTION` of the extent or wider, is the contact's
    place; the travel is the span of those places.
    """
    cols = np.flatnonzero(lit.any(axis=0))
    if len(samples) < 2 or cols.size < 2:
        return 0.0
    prof = column_profiles(samples, median, lit, slice(int(cols[0]), int(cols[-1]) + 1),
                           contact_is)
    prof -= np.median(prof, axis=1, keepdims=True)
    mid = np.median(prof, axis=0)
    spread = 1.4826 * np.median(np.abs(prof - mid), axis=0)
    sigma = max(float(np.median(spread)), 1e-6)
    width = prof.shape[1]
    places = []
    for p in prof:
        start, length = _widest_run(p - mid > RUN_SIGMAS * sigma)
        if length >= MIN_RUN_FRACTION * width:
            places.append(start + 0.5 * length)
    return (max(places) - min(places)) / width if len(places) >= 2 else 0.0


def _translates(samples: list[np.ndarray], median: np.ndarray, lit: np.ndarray,
                contact_is: str = "dark") -> bool:
    """True when darker contact travels :data:`MIN_TRAVEL_FRACTION` of the lit zone's
    extent along the rows through the sampled frames (:func:`_travel`): a block passing a
    fixed camera whose contact is too faint or too patchy for :func:`_moving`'s block-sized
    region (rough real contact)."""
    return _travel(samples, median, lit, contact_is) >= MIN_TRAVEL_FRACTION


def _auto_mode(frames: list[np.ndarray], median: np.ndarray, bright: np.ndarray,
               lit: np.ndarray, contact_is: str, min_darkness: float,
               min_block_fraction: float, travel_px: Sequence[float] | None
               ) -> tuple[str, FreeSurface | None]:
    """The camera mode from the samples (:func:`tir_reference`, step 2), and the static
    free surface of their median where the travel test made it (None otherwise).

    Before the travel test (helper-11, stop 56): a physical-contact block at 1 m/s passing a
    fixed camera (0.1 mm/px, 640 px) on 10, 20, 40 and 80 frames was taken as held, its area
    -44, -34, -29 and -22 % (-4.4, -2.6, -1.8 and -0.4 % as "fixed"): it covers most of the
    view in every sample, so no sample differs by a block-sized region, and it travels under
    :data:`MIN_TRAVEL_FRACTION` of the view.
    """
    if len(frames) < 2:
        return "follows", None
    if (_moving(frames, median, bright, lit, min_darkness, min_block_fraction, contact_is)
            or _translates(frames, median, lit, contact_is)):
        return "fixed", None
    if travel_px is None:
        return "follows", None
    held = free_surface(median, lit, contact_is=contact_is)
    if carried(frames, held.image, lit, travel_px, contact_is):
        return "fixed", None
    return "follows", held


#: A block the samples hold is bordered by the pixels its edges sweep: within this many
#: px outside it (:func:`_held`).
HELD_BORDER_PX = 5


def _held(cand: np.ndarray, samples: list[np.ndarray], bright: np.ndarray, lit: np.ndarray,
          min_darkness: float, contact_is: str = "dark") -> np.ndarray:
    """The regions of `cand` (dark regions of the fixed camera's percentile image `bright`)
    that a passing block holds in every sample.

    A pixel is swept where some sample is darker than `bright` by `min_darkness` (free in
    enough samples to set the percentile, covered in one; a 3 x 3 opening takes out single
    noise pixels). A held block covers its pixels in every sample, so none of them is
    swept, and its leading and trailing edges sweep the pixels beside it: a region is held
    where less than half of its core (the pixels :data:`HELD_BORDER_PX` inside its edge,
    or its inner half where it is narrower) is swept and at least half of the lit pixels within
    :data:`HELD_BORDER_PX` outside it are (the region also holds the columns the block
    covers in all but a sample or two, swept, around a core swept nowhere: 6 % of a G0
    band's interior at 3 m/s in 10 frames). A static dark patch of
    the light field or of the ice (a shadow, frost, a mark on the prism) is swept nowhere
    around it, or, where the block passes over it, inside it too (the review of 4aafa86:
    a 120 px patch of darkness 0.5 read as contact in every frame, +19 %).
    """
    out = np.zeros(cand.shape, bool)
    if not cand.any():
        return out
    swept = np.zeros(cand.shape, np.uint8)
    for dark in _departures(samples, bright, bright, lit, contact_is):
        swept |= (dark > min_darkness).view(np.uint8)
    swept = cv2.morphologyEx(swept, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8)).view(bool)
    n, lab = cv2.connectedComponents(cand.view(np.uint8), connectivity=8)
    ring_kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * HELD_BORDER_PX + 1,) * 2)
    for k in range(1, n):
        region = lab == k
        ring = cv2.dilate(region.view(np.uint8), ring_kernel).view(bool) & ~region & lit
        # its core: the pixels at least HELD_BORDER_PX inside its edge, or in a narrower
        # region (an element band of a fine view) the inner half of its width
        depth = cv2.distanceTransform(region.view(np.uint8), cv2.DIST_L2, 3)
        inner = depth >= min(float(HELD_BORDER_PX), 0.5 * float(depth.max()))
        if (ring.any() and inner.any()
                and np.count_nonzero(swept & inner) < 0.5 * np.count_nonzero(inner)
                and np.count_nonzero(swept & ring) >= 0.5 * np.count_nonzero(ring)):
            out |= region
    return out


def _fixed_free(bright: np.ndarray, frames: list[np.ndarray], mask: np.ndarray,
                contact_is: str, min_darkness: float, min_block_fraction: float
                ) -> tuple[np.ndarray, np.ndarray, str]:
    """A fixed camera's free surface: the percentile image `bright`, where it still holds
    the block replaced by a fitted surface; ``(free, candidates, method)``."""
    cand = np.zeros(bright.shape, bool)
    free, method = bright, "percentile"
    need = min_block_fraction * max(1, mask.sum())
    # one grown estimate; its first disc's candidates tell whether the percentile image
    # still holds the block (a slow pass)
    fs = free_surface(bright, mask, contact_is=contact_is,
                      candidate_darkness=min_darkness, texture=False)
    if fs.first_candidates_px > need:
        if fs.candidates.sum() > need:
            free, cand = fs.image, fs.candidates
            method = ("percentile, the block it still holds replaced by a fitted "
                      "surface")
    else:
        # a block wider than the first disc that the samples hold leaves no
        # candidate in its closing (a G0 block, one 20 mm element, passing 2.5 mm
        # in 10 frames: read as free surface, 55 of 512 mm2): the grown estimate
        # finds dark regions of any width, and of them the ones a passing block
        # holds are replaced (_held: a static dark patch of the light or the ice,
        # which the grown disc finds as well, is not)
        held = _held(fs.candidates, frames, bright, mask, min_darkness, contact_is)
        if held.sum() > need:
            near = cv2.dilate(held.view(np.uint8), np.ones(
                (2 * MARGIN_PX + 1,) * 2, np.uint8)).view(bool)
            free = np.where(near, fs.image, bright).astype(np.float32)
            cand = held
            method = ("percentile, the block it holds in every sample replaced by "
                      "a fitted surface")
    return free, cand, method


def _residuals(samples: list[np.ndarray], free: np.ndarray,
               min_darkness: float = math.inf) -> list[np.ndarray]:
    """Noise residuals: differences of consecutive samples / sqrt(2), or frame - free.

    A difference is noise only where neither sample holds contact: where either reads
    more than `min_darkness` off the free surface (``|1 - I / free|``, either polarity) it
    is NaN. A passing block covers a pixel in one sample and not in the next; its stripes
    had made the differences of a short pass mostly contact, and the robust spread of
    such a bin tens of DN (a 120-frame pass of G7: 42 DN for 2.1, every pixel then too
    noisy to measure and no contact found in any frame).
    """
    f32 = [np.asarray(f, np.float32) for f in samples[:9]]
    if len(f32) < 2:
        return [f32[0] - free]
    if not math.isfinite(min_darkness):
        return [(a - b) / math.sqrt(2.0) for a, b in itertools.pairwise(f32)]
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(free > 0, 1.0 / np.asarray(free, np.float32), np.nan)
        off = [np.abs(1.0 - f * inv) > min_darkness for f in f32]
    return [np.where(oa | ob, np.nan, (a - b) / math.sqrt(2.0)).astype(np.float32)
            for (a, oa), (b, ob) in itertools.pairwise(zip(f32, off, strict=True))]


def tir_reference(
    samples: list[np.ndarray],
    *,
    contact_is: str = "dark",
    percentile: float = 90.0,
    camera: str = "auto",
    lit: LitZone | None = None,
    image: np.ndarray | None = None,
    min_darkness: float = 0.25,
    min_block_fraction: float = 0.02,
    travel_px: Sequence[float] | None = None,
) -> TirReference:
    """Lit zone, camera mode, free surface and noise of a TIR video from sampled frames.

    1. The bright image is each pixel's `percentile` over the samples (their median when
       fewer than 5); its lit zone is found (:func:`tir_contact.illumination.find_lit_zone`)
       unless `lit` is given. Bright contact on a dark surface has no lit zone to find:
       the whole frame is used.
    2. Camera mode (unless `camera` names it): ``"fixed"`` when some sample differs from the
       median of the samples by a darker region larger than `min_block_fraction` of the lit
       zone (something passed), or when darker contact travels across the view through the
       samples (:func:`_translates`: faint or patchy contact), or when the contact is
       shifted between two samples as far as the metadata's travel says a passing block is
       (`travel_px`, :func:`tir_contact.travel.carried`: a short clip or slow pass whose
       block covers most of the view in every sample); ``"follows"`` otherwise (also for
       fewer than 2 samples).
    3. Free surface: ``"fixed"``: the bright image, in which the passing block is absent;
       should it still hold a block-sized dark region (a slow block), that region is
       replaced by :func:`free_surface`. ``"follows"``: :func:`free_surface` of the median
       of the samples.
    4. Noise (:func:`noise_model`) from the differences of consecutive samples (a single
       frame: its residual against the free surface, which also counts fine texture and
       so errs on the safe side).

    Parameters
    ----------
    samples : list of (M, N) ndarray
        Frames spread through the video.
    contact_is : {"dark", "bright"}
    percentile : float
        Per-pixel percentile of a fixed camera's free surface.
    camera : {"auto", "fixed", "follows"}
    lit : LitZone, optional
        The lit zone (e.g. from a user's mask file).
    image : (M, N) ndarray, optional
        A free-surface image given by the user: used as it is (mode `camera`, ``"fixed"``
        when ``"auto"``).
    min_darkness : float
        Darkness that surely is contact (camera-mode test and slow-block test).
    min_block_fraction : float
        Share of the lit zone a moving region must cover to count as a passing block.
    travel_px : sequence of float, optional
        Displacement (px) of a block passing a fixed camera at each sample from the first
        (:func:`tir_contact.travel.expected_travel_px`; None: unknown, the samples alone
        decide).

    Returns
    -------
    TirReference
    """

    if camera not in ("auto", *CAMERA_MODES):
        raise ValueError(f"camera must be 'auto', 'fixed' or 'follows', got {camera!r}")
    if contact_is not in ("dark", "bright"):
        raise ValueError(f"contact_is must be 'dark' or 'bright', got {contact_is!r}")
    frames = [np.asarray(f) for f in samples]
    q = percentile if contact_is == "dark" else 100.0 - percentile
    median = _median(frames)  # the moving test and a static free surface both need it
    bright = pixelwise_percentile(frames, q).astype(np.float32) if len(frames) >= 5 else median
    shape = bright.shape
    find_lit = lit is None
    if find_lit:
        lit = find_lit_zone(bright) if contact_is == "dark" else whole_frame(shape)
    mask = lit.mask
    tex = (0.0, 1.0)  # the texture a static scene's estimate does not follow (below)
    excess = 0.0  # a fixed camera's percentile over the free surface's mean (below)
    residuals: list[np.ndarray] | None = None  # the noise model's, once made
    if image is not None:
        free = np.asarray(image, np.float32)
        # a measured free surface does not say how the camera moves: the mode given (the
        # analysis passes the one its own estimate decided), "fixed" when left to auto
        mode = camera if camera in CAMERA_MODES else "fixed"
        method, cand = "file", np.zeros(shape, bool)
    else:
        held = None  # the static estimate, when the camera-mode test made it
        mode = camera
        if mode == "auto":
            mode, held = _auto_mode(frames, median, bright, mask, contact_is, min_darkness,
                                    min_block_fraction, travel_px)
        if mode == "fixed" and len(frames) >= 5:
            free, cand, method = _fixed_free(bright, frames, mask, contact_is, min_darkness,
                                             min_block_fraction)
            if contact_is == "dark":
                # the noise model's residuals (frame differences: the free surface's scale
                # does not enter) also set the excess's tile test
                residuals = _residuals(frames, free, min_darkness)
                excess = _excess_over_free_mean(frames, free, mask & ~cand, residuals[:3])
                free = free * np.float32(1.0 - excess)
        else:
            fs = held if held is not None else free_surface(median, mask, contact_is=contact_is)
            free, cand = fs.image, fs.candidates
            tex = (fs.texture_sigma, fs.texture_corr_px)
            method = (f"fitted free surface ({len(frames)} frame(s); closing "
                      f"{fs.size_px} px)")
    if contact_is == "bright" and find_lit:
        # the lit zone as the free-surface estimate shows it (known limit: the inverted
        # image the estimate works on takes a strongly vignetted lit zone, or one narrower
        # than the largest contact, for a held contact and flattens it; --lit-mask then)
        lit = lit_zone_of_surface(free)
        mask = lit.mask
    if contact_is == "bright":
        # Bright contact on a dark surface: the surface may carry almost no light (a dark
        # field, quantised to 0-1 grey values), and a darkness against it is noise. Below
        # a twentieth of the bright contact's level the surface is taken as that level:
        # the contact is then found by its grey value above the surface.
        level = max(float(np.percentile(f[::2, ::2], 99.9)) for f in frames)
        free = np.maximum(free, np.float32(BRIGHT_FLOOR * level))
    away = mask & ~cv2.dilate(cand.astype(np.uint8), np.ones((9, 9), np.uint8)).astype(bool)
    if residuals is None:
        residuals = _residuals(frames, free, min_darkness)
    noise = noise_model(residuals, free, away)
    ref = Reference(free.astype(np.float64), mask.copy(), method, len(frames))
    return TirReference(ref, lit, mode, method, noise, *tex, percentile_excess=excess)


#: Sampled frames the free surface's mean is measured on (:func:`_excess_over_free_mean`), at
#: most: as the area model's (:data:`tir_contact.measure.MAX_FREE_FRAMES`).
EXCESS_FRAMES = 8


def _excess_over_free_mean(frames: list[np.ndarray], bright: np.ndarray,
                           where: np.ndarray, diffs: list[np.ndarray]) -> float:
    """The share ``b`` by which a fixed camera's bright percentile image lies above the free
    surface's mean: the mean darkness ``1 - I / bright`` of the free surface away from
    contact (:func:`tir_contact.measure._free_mean`: tiles whose mean lies within a few
    tile noise sigmas of the lower quartile of the tile means) in up to
    :data:`EXCESS_FRAMES` of the `frames`, over the pixels `where` (the lit zone less
    the contact the percentile image still holds). 0 where fewer than 100 pixels tell.

    (Not :func:`tir_contact.tir_view._percentile_excess`, the expected excess of a normal
    sample's percentile, with which a user's reference is fitted: this one is measured.)

    Each pixel's 90th percentile over 32 noisy frames lies about 1.2 noise sigmas above its
    mean (1-2 % of the light in the renders), and more where the block covered the pixel in
    some frames. Against it, a free pixel reads ``b`` and a pixel at darkness ``D`` reads
    ``b + D (1 - b)``: the free surface's offset is taken out of every reading, the factor
    ``1 - b`` is not, and where full contact's darkness is not read from the image (the
    rig's optics, an assumed value) every unmixed area came out short by ``b`` (the
    physical renders' junction fields: 1.6-2.6 % below their optical contact). Scaling the
    percentile image by ``1 - b`` makes it the free surface's mean: ``I / I_free``
    exactly. Its noise sets the tile test: the spread of `diffs` (differences of
    consecutive frames over sqrt 2, :func:`_residuals`), robust, against the median light.
    """
    few = frames[::max(1, math.ceil(len(frames) / EXCESS_FRAMES))]
    light = bright[where]
    if light.size < 100 or not np.isfinite(light).all() or float(np.median(light)) <= 0:
        return 0.0
    # the noise only sets the tiles' test: every 4th pixel tells it
    values = np.concatenate([r[where][::4] for r in diffs])
    values = values[np.isfinite(values)]  # NaN: contact in one of a pair's samples
    if values.size < 100:
        return 0.0
    sigma = 1.4826 * float(np.median(np.abs(values))) / float(np.median(light[::4]))
    inv = np.where(where, 1.0 / np.maximum(bright, 1e-6), np.nan).astype(np.float32)
    darkness = [1.0 - np.asarray(f, np.float32) * inv for f in few]
    b = _free_mean(darkness, sigma)
    return float(b) if math.isfinite(b) else 0.0


def measurable(tref: TirReference, threshold: float, *, n_sigma: float = 5.0,
               sigma: np.ndarray | None = None) -> TirReference:
    """`tref` with ``reference.valid`` cut to the lit pixels whose noise stays clear of the
    threshold: ``n_sigma * sigma_D <= threshold`` (see :meth:`NoiseModel.sigma_darkness`).

    Where the light is too weak (the soft rim, a dim corner) a noise peak would cross the
    contact threshold; such pixels are not measured rather than counted as speckle.
    `sigma`: ``sigma_D`` of `tref`'s free surface, when the caller has it already.
    """
    if sigma is None:
        sigma = tref.noise.sigma_darkness(tref.reference.image)
    valid = tref.lit.mask & (n_sigma * sigma <= threshold)
    return dataclasses.replace(tref, reference=dataclasses.replace(tref.reference, valid=valid))
