"""Contact area as a measurement: two darkness populations, unmixing and an error bar.

Model of a TIR image read as darkness ``D = 1 - I / I_free`` against the free-surface
estimate (:mod:`tir_contact.flatfield`, :mod:`tir_contact.reference`)::

    D = b + e + c * phi

* ``b``: the free surface's offset, the bias of the estimate (an envelope of a textured
  surface lies above its mean; a bright percentile of noisy frames above the mean level);
* ``e``: the free surface's fluctuation, zero mean: the camera's noise (known per pixel from
  the noise model) and the texture the estimate does not follow, spread ``sigma_texture``,
  correlated over ``corr_px`` pixels (measured from the variance of block means);
* ``c``: the darkness of full contact (what is left of the light where rubber touches;
  stray light and the camera's black level keep it below 1);
* ``phi``: the share of the pixel in contact, blurred by the optics.

Two populations follow. The **free surface** is measured where contact cannot reach it:
contact only adds darkness, so the side of the darkness distribution below its median is
free surface alone; its spread, taken as symmetric about the median, gives the darkness a
free pixel reaches (``seed`` threshold: the expected number of free pixels of a frame
above it is :data:`FALSE_SEEDS_PER_FRAME`). Where that extrapolation passes half of full
contact, the texture may be bounded rather than Gaussian (bubbles and dust in the ice, a
static estimate's large-scale error), and the reach is read off the free pixels instead:
the darkest pixel away from resolved contact (:func:`_measured_reach`), when that lies
lower and more than three noise sigmas below the core level it is read against
(:func:`_bounded_reach`; half of full contact is the given contrast or the assumed
darkness here, ``c`` being measured after). **Contact** is either *resolved* (patches wider
than the blur: their pixels reach ``c`` and a blurred edge is half covered at ``c / 2``) or
*unresolved* (junctions below a pixel: a pixel reads ``c * phi``). A resolved region is a
connected region at the half-contact threshold with an interior (a pixel whose 3 x 3
neighbourhood is all above it); its area is its pixel count. Everything else that is
significantly dark (a seed pixel and its neighbours) is unmixed: its area is
``sum(D - b) / c``. In a static scene that shows resolved contact, the free-surface
estimate is continued over the contact from around it and keeps the ice's bubbles and
scratches dark there: its seeds and unmixed pixels are read against the local free
surface instead (the darkness's grey opening by a disc as wide as the zone around
resolved contact, :func:`_over_local_free`), and only seeds within that zone
(:data:`ZONE_PX`) are contact (farther ones may be the ice's dust; inside it, at a level
that adds the light's texture the estimate cannot follow there, :func:`_over_zone_level`),
and, beyond it, thin
contact (too thin or small to be resolved) where it reaches the half-contact threshold
over the local free surface, its blur unmixed with it: the segmentation's own decision,
which the free surface's reach does not pass; not in the lit zone's rim band, where the
light's own fall-off reaches as dark.

Where the sampled frames show no resolved contact and the free surface is the video's own (a
fixed camera: the box around the seeds is read), the contact is a field of junctions below
the pixel whose share, and darkness, falls continuously to zero at the field's edge, below
any seed level: in a frame with contact, every pixel of the box outside the resolved edges
is unmixed (the free surface's fluctuation is zero-mean about ``b`` there; its noise over
the box is in the error bar, a drift of the light from frame to frame is not: it adds its
darkness times the box's pixels). A physical block's faces at 2-27 % real contact: 5 % of
their optical contact lay below the seeds' zone.

``c`` is measured on the resolved interiors in the sampled frames (:data:`MIN_FULL_PX`
pixels at least; taken deeper inside while their median still rises, where the blur has
left small contacts no pixel at full darkness: :func:`_plateau`) as the level a wholly
covered pixel reads (their upper decile less its noise, at least their median: rough
contact's interiors are partly covered, :func:`_full_level`; with the free surface
measured, the optics' value where they read below it but clear half of it, since partial
cover is then what lowers them: :func:`_optics_level`), or given by the user, or, when the
video shows no resolved contact, assumed:
:data:`ASSUMED_FULL_DARKNESS`, the frustrated-TIR contrast of rubber on ice or glass (a
contact reflects 2-4 % of the light; Fresnel), within :data:`ASSUMED_FULL_RANGE` (stray
light); the summary says so.

The error bar (:func:`frame_area`): the resolved count over the plausible decisions
(thresholds from the free surface's reach, at least ``c / 4``, to ``3 c / 4``), and the
unmixed area over ``c``'s range plus twice its noise: the free surface's fluctuation summed
over the unmixed pixels (correlated over ``corr_px``) and the uncertainty of ``b``; in a
static scene down to the frame's darkness budget and to the resolved contact alone (the
seeds beside it may be the ice's dust) and up to the zone read against the video's free
surface instead of the local one (a junction field denser than the opening's disc looks
like a plateau to it) and to the significant seed clusters beyond the zone (junctions of
the same contact farther out); where ``c`` is a weak plateau
(:attr:`AreaModel.weak_plateau`), down to the zone's darkness as the share covered of each
pixel; up to the unlit pixels that contact in the lit zone's rim band may cover past the
found edge, and down by the contact the band holds (the edge is the half-light line to
within the band, so that contact may lie past the true one); in a static scene without
resolved contact (dark contact), up to the frame read against its free-surface estimate
without the dark spots narrower than :data:`LOCAL_FREE_PX` it followed
(:func:`with_absorbed`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace

import cv2
import numpy as np
from scipy.stats import norm

from tir_contact.graded import FreeLevel, graded_contact

__all__ = [
    "ASSUMED_FULL_DARKNESS",
    "ASSUMED_FULL_RANGE",
    "EDGE_PX",
    "ZONE_PX",
    "AreaModel",
    "FrameArea",
    "area_model",
    "correlation_area",
    "frame_area",
    "with_absorbed",
]

#: Darkness of full contact when the video shows no resolved contact: frustrated TIR of
#: rubber (n about 1.5) on ice (1.31) or glass (1.52) at 60 deg returns 2-4 % of the light.
ASSUMED_FULL_DARKNESS = 0.97
#: The range of that assumption: stray light or a black level may take back up to 15 %.
ASSUMED_FULL_RANGE = (0.85, 1.0)
#: Resolved interior pixels (over the sampled frames) needed to measure full contact: the
#: median of 9 values is known to 0.4 sigma of the noise, well inside the range that
#: the error bar carries.
MIN_FULL_PX = 9
#: Resolved contact darker than the free surface's reach but below half the assumed full
#: darkness is full contact (seen through stray light) when its interior darkness is a
#: plateau: the spread from its 10th to its 90th percentile at most this share of its
#: median (noise and a 0.3-0.4 pressure grading give 0.3-0.5); contact covering part of
#: each pixel spreads down to the free surface (the physical block at 0.1 mm/px: about 3).
MAX_PLATEAU_SPREAD = 1.0
#: Noise sigmas of a free pixel by which such a plateau's lower decile must clear the
#: level it was cut at (the free surface's reach): a plateau at ``c`` with the noise's
#: spread has its lower decile 1.28 sigma below ``c``, and with ``c`` 2.56 sigma above the
#: cut it loses 0.5 % of its pixels to the cut. Pixels that pass the cut only by
#: their noise or their share of junctions (a field of junctions below the pixel whose
#: darkness tops out near the reach) pile up just above it instead: their lower decile is
#: the cut, and the spread test alone reads the cut's own narrow slice as a plateau (a
#: physical block at 6.5 % real contact, 8-bit JPEG at a white level of 0.11: nine
#: interior pixels, lower decile 0.3 sigma above the reach, taken for full contact
#: through 83 % stray light and read 280 % high).
PLATEAU_CLEARANCE_SIGMAS = float(norm.ppf(0.9))
#: Expected free-surface pixels per frame above the seed threshold.
FALSE_SEEDS_PER_FRAME = 0.05
#: Sampled frames the free surface's statistics are taken from, at most.
MAX_FREE_FRAMES = 8
#: Free-surface values the statistics are taken from, at most (an even subsample). The
#: subsamples are sorted before their median and percentiles are taken: numpy's values are
#: those of the sorted multiset whatever the order, so they are the same to the bit, and
#: numpy 2's vectorised sort plus the partitions of an ordered array take a third to a
#: half of the partitions of an unordered one (2 x 10^5 float32 values: 1.3 ms against 3.8
#: for three quartiles).
MAX_FREE_VALUES = 200_000
#: Side of the blocks whose means give the free surface's correlation area, px.
CORR_BLOCK_PX = 8
#: Deep interior pixels near an edge pixel (within :data:`LOCAL_PX`) needed to unmix it
#: against their darkness rather than the video's.
MIN_LOCAL_PX = 9
#: Margin (px) around a resolved region whose pixels belong to its blurred edge.
EDGE_PX = 2
#: Reach (px) of the deep interior whose darkness an edge pixel is unmixed against: the
#: edge band (:data:`EDGE_PX` each side of the threshold) and as far again.
LOCAL_PX = 2 * EDGE_PX + 2
#: Standard deviations of the noise terms in the error bar (about 95 %).
BAND_SIGMAS = 2.0

_CROSS3 = np.ones((3, 3), np.uint8)
_EDGE = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * EDGE_PX + 1,) * 2)
ZONE_PX = 8
_ZONE = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * ZONE_PX + 1,) * 2)
_LOCAL = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * LOCAL_PX + 1,) * 2)


@dataclass(frozen=True)
class AreaModel:
    """The two darkness populations of one video (:func:`area_model`).

    Attributes
    ----------
    offset : float
        ``b``: median darkness of the free surface.
    sigma_texture : float
        Spread of the free surface beyond the camera's noise (texture the free-surface
        estimate does not follow).
    sigma_free : float
        Median spread of a free pixel (texture and noise together).
    corr_px : float
        Correlation area of the free surface's fluctuation, px (1: white noise).
    n_free : int
        Free-surface pixels the statistics come from.
    mean_free, sd_free : float
        Mean and standard deviation of their darkness (dust, bubbles and scratches
        included, which the median and the spread below it leave out).
    seed : (M, N) ndarray of float32
        Darkness a free pixel reaches (per pixel: the noise varies with the light); NaN
        where not measured.
    seed_median : float
        Median of `seed` over the measured pixels.
    contact_darkness, contact_low, contact_high : float
        ``c`` and its plausible range.
    contact_source : {"measured", "given", "assumed", "optics"}
    n_full_px : int
        Resolved interior pixels ``c`` was measured on (a given ``c``: the sampled frames'
        interior pixels at half of it); under :data:`MIN_FULL_PX`, no contact in the
        sampled frames is resolved (junctions below the pixel only).
    threshold : float
        The half-contact threshold: ``c / 2``, at least the free surface's reach.
    separation : float
        ``(c / 2 - b) / (seed_median - b)``: how far the half-contact decision lies beyond
        the free surface's reach (> 1: the populations separate).
    notes : list of str
    min_cluster_px : int
        See :func:`area_model`.
    static : bool
        See :func:`area_model`.
    zone_sigma, zone_corr_px : float
        See :func:`area_model`.
    rim, beyond : (M, N) ndarray of bool or None
        The lit zone's rim band and the unlit pixels within `rim_px` outside it; see
        :func:`area_model`.
    rim_px : int
        The rim band's width.
    reach_measured : bool
        The free surface's reach was read off its pixels (:func:`_measured_reach`), the
        Gaussian extrapolation passing half of full contact; False: the extrapolation.
    weak_plateau : bool
        ``c`` was measured on a plateau of the regions above the free surface's reach
        (clearing it: :data:`PLATEAU_CLEARANCE_SIGMAS`),
        because fewer than :data:`MIN_FULL_PX` interior pixels reach half the assumed
        darkness of full contact (:func:`area_model`): full contact seen through stray
        light, or contact covering the same share of every pixel (many junctions below a
        pixel each), which a single image cannot tell apart; the error bar's low end holds
        the second reading. With the free surface measured, the plateau may be read as
        that cover (``contact_source`` ``"optics"``: ``c`` is then the optics' value and
        the plateau's reading lies in the range below it, :func:`_optics_level`).
    field_offset : float
        Mean darkness of the free surface away from any contact (:func:`_free_mean`): the
        level a junction field's box, every pixel of it summed, is read against (its
        noise's skew, from 8-bit steps and JPEG, puts the mean above the median ``b``);
        NaN: not known, or the contact is not graded (the only readings that use it).
    field_offset_spread : float
        How much the free surface's offset varies between places away from contact
        (:func:`_free_tiles`): the pixels summed against ``field_offset`` may lie where it
        differs by this much, which the error bar holds (:func:`frame_area`); 0 where not
        known.
    graded : bool
        The contact is graded: a field of junctions below the pixel that reaches half of
        full contact only in the dense band at each face's front
        (:func:`tir_contact.graded.graded_contact`), or nowhere (no contact resolved:
        under :data:`MIN_FULL_PX` interior pixels); the features then find the elements'
        runs where the columns hold contact at all (:mod:`tir_contact.graded`).
    absorbed : (M, N) ndarray of float32 or None
        A static junction field (no contact resolved, the free surface estimated from
        images that show the contact; :func:`with_absorbed`): the share of the light by
        which the estimate lies below its closing by the local free surface's disc at each
        pixel (:func:`tir_contact.reference.absorbed_darkness`), where it followed dark
        spots narrower than the disc (junctions or the light's texture), less its median
        over the measured pixels (the closing's lift over the free surface's own noise) and
        at least 0; NaN where not measured. The error bar's high end reads the frame
        against the estimate without the spots (:func:`frame_area`). None elsewhere.
    """

    offset: float
    sigma_texture: float
    sigma_free: float
    corr_px: float
    n_free: int
    mean_free: float
    sd_free: float
    seed: np.ndarray = field(repr=False)
    seed_median: float
    contact_darkness: float
    contact_low: float
    contact_high: float
    contact_source: str
    n_full_px: int
    threshold: float
    separation: float
    notes: list[str] = field(default_factory=list)
    min_cluster_px: int = 4
    static: bool = False
    zone_sigma: float = 0.0
    zone_corr_px: float = 1.0
    rim: np.ndarray | None = field(default=None, repr=False)
    beyond: np.ndarray | None = field(default=None, repr=False)
    rim_px: int = 0
    weak_plateau: bool = False
    reach_measured: bool = False
    graded: bool = False
    field_offset: float = math.nan
    field_offset_spread: float = 0.0
    absorbed: np.ndarray | None = field(default=None, repr=False)

    @property
    def junction_field(self) -> bool:
        """No contact in the sampled frames is resolved (under :data:`MIN_FULL_PX` interior
        pixels): whatever contact there is, is a field of junctions below the pixel."""
        return self.n_full_px < MIN_FULL_PX

    @property
    def free_mean(self) -> float:
        """The level summed free pixels are read against: the free surface's mean away from
        contact where known (``field_offset``), else its median ``b``."""
        return self.field_offset if math.isfinite(self.field_offset) else self.offset

    def free_level(self) -> FreeLevel:
        """The presence test's levels of graded contact (:mod:`tir_contact.graded`): the
        free surface's darkness (its mean away from contact where known, else its median
        ``b``) and one pixel's noise over the correlation area (a static scene's whole
        spread, its dust and texture staying in its free surface), and full contact's
        darkness."""
        sigma = max(self.sd_free, self.sigma_free) if self.static else self.sigma_free
        # a column's mean follows the free surface's mean, not its median
        return FreeLevel(self.free_mean, sigma * math.sqrt(self.corr_px),
                         self.contact_darkness)

    def summary(self) -> dict[str, object]:
        """The populations as ``summary.json`` records them."""
        r = 6
        return {
            "free_surface": {
                "darkness_offset": round(self.offset, r),
                "texture_sigma": round(self.sigma_texture, r),
                "sigma": round(self.sigma_free, r),
                "correlation_px": round(self.corr_px, 3),
                "reach": round(self.seed_median, r),
                "reach_source": "measured" if self.reach_measured else "gaussian",
                "n_pixels": self.n_free,
                "mean_away_from_contact": (round(self.field_offset, r)
                                           if math.isfinite(self.field_offset) else None),
                "mean_spread_between_places": round(self.field_offset_spread, r),
            },
            "contact": {
                "darkness": round(self.contact_darkness, r),
                "darkness_range": [round(self.contact_low, r), round(self.contact_high, r)],
                "source": self.contact_source,
                "n_resolved_pixels": self.n_full_px,
                "weak_plateau": self.weak_plateau,
                "graded": self.graded,
            },
            "threshold": round(self.threshold, r),
            "separation": round(self.separation, 3) if math.isfinite(self.separation)
            else None,
        }


def _free_statistics(samples: list[np.ndarray], sigma_noise: np.ndarray,
                     level: float = ASSUMED_FULL_DARKNESS / 2
                     ) -> tuple[float, float, float, int, float, float]:
    """``b``, the spread below it, the texture's spread (beyond the noise), the pixel count,
    the mean and the standard deviation of the free surface: the measured pixels away from
    any pixel darker than `level` (:data:`EDGE_PX` and the 3 x 3 neighbourhood around it),
    the spread from the part of their darkness distribution below its median (which
    contact, only adding darkness, does not reach)."""
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * EDGE_PX + 3,) * 2)
    parts = []
    for d in samples:
        with np.errstate(invalid="ignore"):
            core = (d > level).astype(np.uint8)
        away = ~cv2.dilate(core, kernel).astype(bool) & np.isfinite(d)
        parts.append(d[away])
    values = np.concatenate(parts) if parts else np.zeros(0, np.float32)
    if values.size < 100:
        return 0.0, 0.0, 0.0, int(values.size), 0.0, 0.0
    n_values = int(values.size)
    # an even subsample: a percentile of 2 x 10^5 values is known to 0.3 % of the spread
    values = np.sort(values[::max(1, n_values // MAX_FREE_VALUES)])  # MAX_FREE_VALUES
    b = float(np.median(values))
    # the 16th percentile lies one sigma below the median of a normal population
    spread = max(b - float(np.percentile(values, 100 * norm.cdf(-1.0))), 0.0)
    noise = float(np.median(sigma_noise[np.isfinite(sigma_noise)])) if np.isfinite(
        sigma_noise).any() else 0.0
    texture = math.sqrt(max(spread ** 2 - noise ** 2, 0.0))
    return (b, spread, texture, n_values, float(np.mean(values, dtype=np.float64)),
            float(np.std(values, dtype=np.float64)))


#: Side (px) of the tiles :func:`_free_mean` tests for contact.
FREE_TILE_PX = 16


def _free_mean(samples: list[np.ndarray], sigma_px: float) -> float:
    """Mean darkness of the free surface away from contact (:func:`_free_tiles`); NaN from
    fewer than 100 pixels."""
    return _free_tiles(samples, sigma_px)[0]


#: Tiles (each with at least a whole tile's worth of free values over the samples) the
#: spread of the free surface's offset between tiles is read from, at least.
MIN_SPREAD_TILES = 4


def _free_tiles(samples: list[np.ndarray], sigma_px: float) -> tuple[float, float]:
    """Mean darkness of the free surface away from contact, and how much its offset varies
    between places (its spread between tiles, the tiles' own noise taken out).

    The mean: of the pixels in the tiles of :data:`FREE_TILE_PX` whose mean darkness, and
    their neighbours', lies within 5 tile noise sigmas (`sigma_px`: one pixel's noise over
    its correlation area) of the lower quartile of the tile means (a free tile's, where a
    quarter of the tiles is free: a junction field, however sparse, lifts its tiles' means
    past that, a single noise pixel does not); NaN from fewer than 100 pixels.

    The spread: the standard deviation of the tiles' means (each over the samples that show
    it free, :data:`MIN_SPREAD_TILES` tiles or more with a tile's worth of values), less
    their noise (``sigma_px^2 / n`` for ``n`` values), 0 where fewer tiles tell. A fixed
    camera's reference lies above the free light's mean by a share that follows the light
    and how often the block covered each pixel
    (:func:`tir_contact.reference._excess_over_free_mean`); a junction field's box, every
    pixel summed against the mean, may lie where the offset differs from it by this much
    (the physical renders: 0.1-0.2 % of the light on a block's path in a small lit zone,
    1-3 % of the area of a sparse field).
    """
    t = FREE_TILE_PX
    sums: np.ndarray | None = None
    counts: np.ndarray | None = None
    parts = []
    for d in samples:
        h, w = (d.shape[0] // t) * t, (d.shape[1] // t) * t
        if not (h and w):
            continue
        sub = d[:h, :w].reshape(h // t, t, w // t, t)
        finite = np.isfinite(sub)
        n = finite.sum(axis=(1, 3))
        total = np.where(finite, sub, 0.0).sum(axis=(1, 3))
        mean = total / np.maximum(n, 1)
        ok = n >= t * t // 2
        if not ok.any():
            continue
        level = float(np.percentile(mean[ok], 25.0)) + 5.0 * sigma_px / t
        lifted = (mean > level) | ~ok
        free = ~cv2.dilate(lifted.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
        if sums is None:
            sums, counts = np.zeros(n.shape), np.zeros(n.shape)
        sums += np.where(free, total, 0.0)
        counts += np.where(free, n, 0)
        parts.append(sub[finite & free[:, None, :, None]])
    if sums is None or counts.sum() < 100:
        return math.nan, 0.0
    # the mean as the values' own (the same sum, to the last bit, as before the spread)
    mean = float(np.mean(np.concatenate(parts), dtype=np.float64))
    told = counts >= t * t
    if int(told.sum()) < MIN_SPREAD_TILES:
        return mean, 0.0
    tiles = sums[told] / counts[told]
    noise = float(np.mean(sigma_px ** 2 / counts[told]))
    return mean, math.sqrt(max(float(np.var(tiles)) - noise, 0.0))


def correlation_area(samples: list[np.ndarray], b: float, spread: float) -> float:
    """Correlation area (px) of a stationary field around `b` with spread `spread`:
    ``K var(block mean) / var(pixel)`` over blocks of ``K`` = :data:`CORR_BLOCK_PX` squared
    pixels wholly finite and below ``b + 4 spread`` (no contact); between 1 and ``K``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> round(correlation_area([rng.normal(0, 1, (256, 256))], 0.0, 1.0), 1)  # white noise
    1.0
    """
    if spread <= 0:
        return 1.0
    k = CORR_BLOCK_PX
    means, pixels = [], []
    for d in samples[:8]:
        h, w = (d.shape[0] // k) * k, (d.shape[1] // k) * k
        if h == 0 or w == 0:
            continue
        blocks = d[:h, :w].reshape(h // k, k, w // k, k).swapaxes(1, 2).reshape(-1, k * k)
        with np.errstate(invalid="ignore"):
            ok = np.isfinite(blocks).all(axis=1) & (blocks < b + 4 * spread).all(axis=1)
        if ok.any():
            means.append(blocks[ok].mean(axis=1))
            pixels.append(blocks[ok].ravel())
    if not means or sum(m.size for m in means) < 10:
        return 1.0
    m, p = np.concatenate(means), np.concatenate(pixels)
    var_p = float(p.var())
    if var_p <= 0:
        return 1.0
    return float(np.clip(k * k * float(m.var()) / var_p, 1.0, k * k))


def _resolved(mask: np.ndarray) -> np.ndarray:
    """The resolved part of `mask`: its opening by a 3 x 3 square, the pixels that belong
    to a 3 x 3 square wholly inside it (contact wider than 3 px; a thinner line or spot is
    seen below the resolution, and unmixed)."""
    u8 = mask.view(np.uint8) if mask.dtype == np.bool_ else mask.astype(np.uint8)
    return cv2.morphologyEx(u8, cv2.MORPH_OPEN, _CROSS3, borderType=cv2.BORDER_CONSTANT,
                            borderValue=0).view(np.bool_)


def _interiors(samples: list[np.ndarray], level: float) -> np.ndarray:
    """Darkness of the pixels inside the regions above `level` whose 3 x 3 neighbourhood
    all reaches it (a blur of up to a pixel has left them)."""
    return next(_interior_levels(samples, level))


def _erode(mask: np.ndarray) -> np.ndarray:
    """`mask` (uint8) less its pixels with a 3 x 3 neighbour outside it (or the border)."""
    return cv2.erode(mask, _CROSS3, borderType=cv2.BORDER_CONSTANT, borderValue=0)


def _interior_mask(d: np.ndarray, level: float) -> np.ndarray:
    """The pixels of `d` whose 3 x 3 neighbourhood all reaches `level` (uint8; NaN does
    not reach it)."""
    with np.errstate(invalid="ignore"):
        return _erode((d >= level).astype(np.uint8))


def _interior_levels(samples: list[np.ndarray], level: float) -> Iterator[np.ndarray]:
    """Darkness of the interiors of the regions above `level`, ever deeper: the pixels 1,
    2, 3, ... px (chessboard) inside them, until none is left."""
    masks = [_interior_mask(d, level) for d in samples]
    while True:
        full = [d[m.view(np.bool_)] for d, m in zip(samples, masks, strict=True)]
        values = np.concatenate(full) if full else np.zeros(0, np.float32)
        yield values
        if values.size == 0:
            return
        masks = [_erode(m) for m in masks]


def _plateau(samples: list[np.ndarray], level: float) -> np.ndarray:
    """Darkness of full contact's plateau: the interiors (:func:`_interiors`) of the regions
    above `level`, taken deeper while their median still rises significantly, at most
    :data:`MAX_PLATEAU_DEPTH_PX` deep, and :data:`MIN_FULL_PX` of them are left.

    The lens's blur spreads a contact's edge inwards: a resolved patch only a few times
    wider than the blur (the junctions of rough contact) has no pixel at the plateau at its
    first interior pixel, and its median darkness rises with the depth (a rough sphere's
    0.78 at 1 px, 0.91 at 2; full contact 0.97). A wide contact's interior is at the
    plateau from the first pixel on (its median moves by the noise's share, or by a
    pressure grading's under 1 % a pixel), and keeps it. Significant: above 3 standard
    errors of the two medians and above :data:`PLATEAU_RISE` of the outer one
    (:func:`_rises`).
    """
    levels = _interior_levels(samples, level)
    values = next(levels)
    if values.size < MIN_FULL_PX:
        return values
    stats = _median_se(values)
    for depth, deeper in enumerate(levels, start=2):
        if depth > MAX_PLATEAU_DEPTH_PX or deeper.size < MIN_FULL_PX:
            break
        inner = _median_se(deeper)
        if not _rises(stats, inner):
            break
        values, stats = deeper, inner
    return values


#: Rise of the interior's median darkness from one pixel of depth to the next, as a share
#: of it, below which the interior is at its plateau: a wide contact's pressure grading or
#: patchiness moves it by 0.3-0.7 % a pixel (domain renders: a static pad, a bright patchy
#: block), the blur of a contact a few pixels wide by 5-15 % (rough spheres and pads).
PLATEAU_RISE = 0.02
#: Deepest interior (px) full contact's darkness is read from: a lens blur of up to 2 px
#: (sigma) reaches about 3 sigma into a contact. Bright contact's darkness has no upper
#: bound, and a graded glow would otherwise be followed to its peak.
MAX_PLATEAU_DEPTH_PX = LOCAL_PX


#: Share of full contact's darkness above which a pixel is surely inside resolved contact
#: when the free surface's reach is measured (:func:`_measured_reach`): the half-contact
#: decision's upper end (:func:`frame_area`'s band).
CORE_SHARE = 0.75


def _measured_reach(samples: list[np.ndarray], core_level: float) -> float:
    """The darkness the free surface reaches, measured: the largest darkness over the
    sampled frames of the pixels farther than :data:`LOCAL_PX` from any pixel at
    `core_level` (resolved contact and its blurred edge, which the lens's blur of up to
    2 px sigma keeps within 3 sigma of the interior); NaN where the samples hold fewer
    than :data:`MIN_FULL_PX` such core pixels in all, or no pixel is left.

    The Gaussian reach (:func:`area_model`) extrapolates the spread of the free surface's
    bright half to the false-seed rate; a texture that is not Gaussian, bounded instead
    (bubbles and dust in the ice, a static estimate's large-scale error), lies far below
    that extrapolation, and the largest darkness its pixels take is a direct reading of
    where it ends (with :data:`MAX_FREE_FRAMES` frames of 10^4-10^5 pixels, the level a
    free pixel passes about once in those frames; the false-seed rate asks for a few
    times rarer, so the reading is lowered by no more than the last pixels' noise).
    Unresolved contact away from the cores counts as free surface here, which only
    raises the reading (the Gaussian reach stays the bound). A Gaussian texture wider than
    the noise passes the guard of :func:`_bounded_reach` too and reads a little below its
    extrapolation (the largest of the sampled pixels against the false-seed rate's level:
    a few times more false seeds).

    Examples
    --------
    >>> rng = np.random.default_rng(2)
    >>> d = rng.uniform(0.0, 0.4, (100, 100)).astype(np.float32)  # bounded texture
    >>> d[30:60, 30:60] = 0.95                                     # resolved contact
    >>> round(_measured_reach([d], 0.75 * 0.97), 2)
    0.4
    """
    top, n_core = -math.inf, 0
    for d in samples:
        with np.errstate(invalid="ignore"):
            core = (d >= core_level).astype(np.uint8)
        n_core += int(np.count_nonzero(core))
        away = ~cv2.dilate(core, _LOCAL).view(np.bool_) & np.isfinite(d)
        if away.any():
            top = max(top, float(d[away].max()))
    return top if n_core >= MIN_FULL_PX and math.isfinite(top) else math.nan


def _bounded_reach(few: list[np.ndarray], noise: float, seed: np.ndarray,
                   seed_median: float, b: float, contrast: float | None
                   ) -> tuple[np.ndarray, float, bool]:
    """The per-pixel seed level, its median and whether it was measured: where the Gaussian
    reach `seed_median` passes half of full contact (the given `contrast`, else the assumed
    :data:`ASSUMED_FULL_DARKNESS`: a measured ``c`` comes later, from the seeds' level),
    the reach read off the free pixels (:func:`_measured_reach`) when it lies lower (a
    bounded texture ends far below the extrapolation) and not within three noise sigmas
    of the core level (there it may be the free surface cut at the level, its pixels past
    it taken for cores; `noise`: the camera's median darkness noise); else `seed` and
    `seed_median` as they are."""
    full = float(contrast) if contrast is not None else ASSUMED_FULL_DARKNESS
    if not (math.isfinite(seed_median) and seed_median > full / 2):
        return seed, seed_median, False
    top = _measured_reach(few, CORE_SHARE * full)
    if not (math.isfinite(top) and top < min(seed_median, CORE_SHARE * full - 3.0 * noise)):
        return seed, seed_median, False
    reach = max(top, b)
    return np.minimum(seed, np.float32(reach)), reach, True


#: Quantile of the resolved interiors' darkness from which full contact's level is read
#: (:func:`_full_level`).
FULL_QUANTILE = 0.9
_FULL_Z = float(norm.ppf(FULL_QUANTILE))  # noise sigmas the quantile lies above a plateau


def _full_level(values: np.ndarray, noise: float, *, bounded: bool = True
                ) -> tuple[float, float, float]:
    """Full contact's darkness ``c`` and its plausible range from the darkness of the
    resolved interiors `values` (:func:`_plateau`).

    A resolved interior holds pixels wholly covered by rubber and, in rough contact, pixels
    covered in part: a cluster of junctions a few pixels wide is resolved as a region, and
    its pixels read their coverage (a physical block at 27-31 % real contact in 0.1 mm
    pixels: interiors from 0.64 to 1.0, median 0.85, full contact 0.98), so their median
    reads the mix, not full contact, and every area unmixed against it is read that much
    too high (18 %). A wholly covered pixel reads full contact's level plus its noise: the
    interiors' :data:`FULL_QUANTILE` quantile less as many sigmas of the camera's darkness
    noise `noise` is that level where enough of them are wholly covered. :func:`area_model`
    gives the noise map's median over the whole frame: at the free surface's light, which
    bounds the noise at contact's lower light, and larger still where the lit zone is small
    (its unlit pixels are noisier), which keeps the correction short of the upper decile
    (the lit pixels' own median was tried: a static scene's interiors also spread by the
    light its estimate cannot follow, and a dark noisy static pad then read its full level
    too high, its bar holding the truth in 1 of 32 frames instead of 32). A plateau with
    noise alone reads its own level (its 90th percentile lies 1.28 sigma above it); one
    graded by pressure, its upper part. Never below the median. The range: the 10th and
    90th percentiles. All three of an even subsample of at most :data:`MAX_FREE_VALUES`.
    Where `bounded` is False (bright contact, whose darkness grows without a full level; a
    weak plateau, read as it is), the median.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> cover = rng.uniform(0.6, 1.0, 4000)               # junction clusters, in part
    >>> v = (0.97 * np.where(cover > 0.85, 1.0, cover)
    ...      + rng.normal(0, 0.01, 4000)).astype(np.float32)
    >>> round(float(np.median(v)), 2), round(_full_level(v, 0.01)[0], 2)
    (0.77, 0.96)
    """
    # an even subsample, as for the free surface's statistics (a block's interiors over
    # the sampled frames reach 10^6 values; the deciles of 2 x 10^5 are known to 0.1 % of
    # the population)
    values = np.sort(values[::max(1, values.size // MAX_FREE_VALUES)])  # MAX_FREE_VALUES
    c = float(np.median(values))
    c_lo, c_hi = (float(v) for v in np.percentile(values, [10.0, 100 * FULL_QUANTILE]))
    if bounded:
        c = max(c, c_hi - _FULL_Z * noise)
    return c, c_lo, c_hi


def _weak_plateau(samples: list[np.ndarray], reach: float, sigma: float
                  ) -> tuple[np.ndarray, float] | None:
    """Weaker contact than half of full contact's assumed darkness: the interiors of the
    regions above the free surface's `reach` and the level they were cut at, where their
    darkness is a plateau (full contact seen with stray light, contact through a water
    film, or a dense field of junctions below the pixel: :attr:`AreaModel.weak_plateau`),
    not a spread reaching down to the free surface (:data:`MAX_PLATEAU_SPREAD`: partial
    contact below the resolution) nor a slice just past the reach
    (:data:`PLATEAU_CLEARANCE_SIGMAS` of `sigma`, a free pixel's darkness spread); None
    else."""
    above = float(np.nextafter(np.float32(reach), np.float32(1)))
    low = _interiors(samples, above)
    if low.size < MIN_FULL_PX:
        return None
    q10, q50, q90 = np.percentile(low, [10.0, 50.0, 90.0])
    if (q50 > 0 and (q90 - q10) / q50 <= MAX_PLATEAU_SPREAD
            and q10 - reach >= PLATEAU_CLEARANCE_SIGMAS * sigma):
        return low, above
    return None


def _optics_level(c: float, c_hi: float, sigma: float,
                  optics: tuple[float, str] | None, notes: list[str],
                  excess: Callable[[], float]) -> tuple[float, float, str]:
    """Full contact's darkness where the free surface is measured (the rig's empty frame):
    ``(c, c_hi, source)`` from the interiors' level `c` and upper end `c_hi`
    (:func:`_full_level`), `sigma` a free pixel's darkness spread; a note is added to
    `notes` where the optics' value is taken.

    With the free surface measured, neither its texture nor its light's fall-off lowers the
    interiors' level; what does is contact covering part of each interior pixel (a rough
    face's junctions below the pixel, clustered too densely to leave any pixel wholly
    covered), stray light, or contact that is itself weak (through a water film). Full
    contact's darkness from the optics (``optics``, else :data:`ASSUMED_FULL_DARKNESS`) is
    taken where the interiors read below it but their level clears half of it by
    :data:`PLATEAU_CLEARANCE_SIGMAS` times `sigma` (a flat plateau at that level loses
    at most a tenth of its pixels to the decision the optics' value sets): the regions
    resolved as contact stay resolved, and only the share of each pixel unmixed against
    it changes. Interiors below that are weak contact, whose own level is the measure
    (the optics' decision would drop them), unless their darkness varies from pixel to
    pixel by at least :data:`NEIGHBOUR_EXCESS` times what the noise gives (`excess`,
    :func:`_neighbour_excess`, computed only then): a smooth weak contact (a water film,
    stray light) varies from pixel to pixel by its noise alone (and the curvature of its
    blurred edge), contact covering part of each pixel by its cover too (the junctions of
    neighbouring pixels are not the same).
    The range keeps reaching down to the interiors' readings (``contact_low``, their lower
    decile: the error bar's high end holds stray light, a film). `sigma` is the free
    surface's spread (noise and texture; with an empty frame, about the noise). Measured
    (stop 51, seeds 0, 7 and 29's static physical draws with their empty frame): the
    interiors at 0.52-0.89 where the optics give 0.978.
    """
    c_opt = optics[0] if optics is not None else ASSUMED_FULL_DARKNESS
    clears = c - PLATEAU_CLEARANCE_SIGMAS * sigma >= c_opt / 2
    if not c < c_opt or not (clears or excess() >= NEIGHBOUR_EXCESS):
        return c, c_hi, "measured"
    if c_hi >= c_opt:
        # the interiors' own range reaches the optics' value: they agree, nothing to say
        # (a note for 0.977 against 0.9779 told the user nothing; helper-11)
        return c_opt, c_hi, "optics"
    notes.append(
        f"full contact's darkness read on the resolved interiors ({c:.3f}) lies below the "
        f"optics' value ({c_opt:.4g}"
        + (f", {optics[1]}" if optics is not None else ", assumed")
        + "): with the free surface measured (--reference) that is contact covering part "
        "of each pixel, or stray light; the optics' value is taken and the error bar "
        "reaches up to the interiors' reading; give --contrast if you know the setup's")
    return c_opt, max(c_hi, c_opt), "optics"


#: Pixel-to-pixel variation of resolved interiors, over the noise's, from which they are
#: read as contact covering part of each pixel (:func:`_optics_level`,
#: :func:`_neighbour_excess`): the noise alone gives at most 1 (the free surface's noise map
#: bounds that of darker contact); a single-frame empty frame's own noise, 8-bit JPEG and
#: the curvature of a blurred edge lift a smooth contact up to about 1.55 (analysed with
#: their empty frame, stop 51: a contact at 0.3-0.4 through a water film 1.26, three points
#: through 0-30 % stray light 0.70-1.11, a rough pad through 15 % stray light 0.74; smooth
#: patches of 6-20 px blurred by 2 px at noise 0.005-0.02 0.9-1.55). The weak plateaus of
#: partly covered physical draws read 1.4-10.4: half of them clear this.
NEIGHBOUR_EXCESS = 2.0


def _neighbour_excess(samples: list[np.ndarray], level: float, sigma_noise: np.ndarray
                      ) -> float:
    """How much more the darkness of the interiors at `level` (:func:`_interiors`) varies
    from pixel to pixel than the camera's noise `sigma_noise` lets it: the robust spread
    (1.4826 median absolute deviation) of the second differences along rows and columns
    (``d[i-1] - 2 d[i] + d[i+1]``, three interior pixels in a line) over sqrt(6) times the
    noise's median over the interiors; 0 where there are fewer than :data:`MIN_FULL_PX`
    such differences.

    Second differences, not first: a smooth darkness that slopes (the lens blur's edge of
    a contact a few pixels wide, a pressure grading) moves first differences by its slope
    and second ones only by its curvature. Smooth patches of 6-12 px at darkness 0.3-0.48,
    blurred by 2 px, noise 0.005-0.02: first differences 2.1-8.7 times the noise's, second
    ones 0.9-1.6 times.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> flat = (0.35 + rng.normal(0, 0.02, (60, 60))).astype(np.float32)
    >>> cover = (0.978 * rng.uniform(0.2, 0.5, (60, 60))).astype(np.float32)
    >>> sigma = np.full((60, 60), 0.02, np.float32)
    >>> [round(_neighbour_excess([d], 0.1, sigma), 1) for d in (flat, cover)]
    [1.0, 4.7]
    """
    diffs, noise = [], []
    for d in samples:
        inside = _interior_mask(d, level).view(np.bool_)
        rows = inside[:, 2:] & inside[:, 1:-1] & inside[:, :-2]
        cols = inside[2:, :] & inside[1:-1, :] & inside[:-2, :]
        diffs.append((d[:, 2:] - 2 * d[:, 1:-1] + d[:, :-2])[rows])
        diffs.append((d[2:, :] - 2 * d[1:-1, :] + d[:-2, :])[cols])
        noise.append(sigma_noise[inside])
    dif, sig = np.concatenate(diffs), np.concatenate(noise)
    sig = sig[np.isfinite(sig)]
    if dif.size < MIN_FULL_PX or sig.size == 0:
        return 0.0
    spread = 1.4826 * float(np.median(np.abs(dif - np.median(dif))))
    return spread / (math.sqrt(6.0) * max(float(np.median(sig)), 1e-9))


def _median_se(v: np.ndarray) -> tuple[float, float]:
    """Median of `v` and its standard error (1.2533 s / sqrt(n), s the robust spread), on an
    even subsample of at most :data:`MAX_FREE_VALUES` values."""
    v = np.sort(v[::max(1, v.size // MAX_FREE_VALUES)])  # sorted: MAX_FREE_VALUES
    q25, q50, q75 = np.percentile(v, [25.0, 50.0, 75.0])
    return float(q50), 1.2533 * float(q75 - q25) / 1.349 / math.sqrt(v.size)


def _rises(outer: tuple[float, float], inner: tuple[float, float]) -> bool:
    """Whether the median of the deeper interior (`inner`, :func:`_median_se`) lies
    significantly above that of the outer one (:func:`_plateau`).

    The inner pixels are a subset of the outer ones, so adding the two errors as if
    independent makes the test conservative. Texture correlated over a few pixels near the
    level lifts the deeper pixels too (they are the ones it raised past the level): on a
    plateau of 0.55 with texture 0.08-0.10 correlated over 3-4 px, the first interior's
    median is 0.58-0.60 and the deepest taken 0.60-0.62; a blurred contact rises by more.
    """
    (m0, s0), (m1, s1) = outer, inner
    return m1 - m0 > max(3.0 * math.hypot(s0, s1), PLATEAU_RISE * abs(m0))


#: The end of a static scene's note where no contact is resolved.
_STATIC_SPOTS_NOTE = ("; in this static scene faint dark spots may as well be the ice's dust, "
                      "bubbles or scratches: the error bar reaches down to no contact")


def area_model(samples: list[np.ndarray], sigma_noise: np.ndarray, *,
               contrast: float | None = None, min_cluster_px: int = 4,
               static: bool = False, zone_sigma: float = 0.0,
               zone_corr_px: float = 1.0,
               rim: tuple[np.ndarray, np.ndarray, int] | None = None,
               bright: bool = False, optics: tuple[float, str] | None = None,
               free_measured: bool = False) -> AreaModel:
    """The free-surface and contact populations of a video (module notes).

    Parameters
    ----------
    samples : list of (M, N) ndarray
        Darkness of sampled frames against the free surface, NaN where not measured.
    sigma_noise : (M, N) ndarray
        The camera's darkness noise at each pixel
        (:meth:`tir_contact.reference.NoiseModel.sigma_darkness`).
    contrast : float, optional
        Darkness of full contact, when the user knows it.
    min_cluster_px : int
        Unresolved contact alone (no resolved contact in the video): clusters of seed
        pixels smaller than this are free surface (noise, dust).
    static : bool
        The free surface was estimated from images that show the contact (a static scene,
        a camera that follows the block): dust, bubbles and scratches are then dark in it,
        and clusters of seeds far from resolved contact are taken for them when the video
        shows resolved contact at all.
    zone_sigma, zone_corr_px : float
        A static scene: the spread and correlation area of the light the free surface
        estimate cannot follow over a contact
        (:attr:`tir_contact.reference.FreeSurface.texture_sigma`); the error bar adds it
        over the contact's pixels.
    rim : (rim band, beyond, width px), optional
        The lit zone's rim band (:attr:`tir_contact.illumination.LitZone.rim`), the unlit
        pixels within its width outside the zone, and the width. The zone's edge is the
        rim's half-light line, placed on the image to within the band: contact in the
        band may go on that far beyond it, and the error bar's high end holds it, or lie
        beyond the true line, and its low end holds that (:func:`frame_area`).
    bright : bool
        Bright contact (brighter than the free surface, its darkness growing without a
        full level): ``c`` is the median of the interiors (:func:`_full_level`).
    optics : (float, str), optional
        Full contact's darkness from the rig's optics and its source in words
        (:func:`tir_contact.optics.full_contact_from_meta`): ``c`` where no contact is
        resolved, instead of :data:`ASSUMED_FULL_DARKNESS`; its range stays
        :data:`ASSUMED_FULL_RANGE` (stray light and the black level only lower it; the
        rubber's index is rarely known to better than 1.45-1.6).
    free_measured : bool
        The free surface is a measured image (the rig's empty frame as ``--reference``):
        resolved interiors that read below full contact's darkness from the optics (or
        :data:`ASSUMED_FULL_DARKNESS`) but clear half of it are then read against that
        value (:func:`_optics_level`).

    Returns
    -------
    AreaModel

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> d = rng.normal(0.0, 0.02, (120, 160)).astype(np.float32)
    >>> d[40:80, 50:110] += 0.8                       # one resolved contact, darkness 0.8
    >>> m = area_model([d], np.full(d.shape, 0.02, np.float32))
    >>> m.contact_source, round(m.contact_darkness, 2), round(m.threshold, 2)
    ('measured', 0.8, 0.4)
    """
    sigma_noise = np.asarray(sigma_noise, np.float32)
    # twice: away from half of full contact, then away from the first pass's reach too
    # (contact too faint for a core shifts the median otherwise)
    # the free surface from at most MAX_FREE_FRAMES of the samples, spread through them
    few = samples[::max(1, math.ceil(len(samples) / MAX_FREE_FRAMES))]
    n_lit = max(int(np.isfinite(samples[0]).sum()), 1) if samples else 1
    z = float(norm.isf(FALSE_SEEDS_PER_FRAME / n_lit))
    b, spread, texture, n_free, mean, sd_all = _free_statistics(few, sigma_noise)
    noise = float(np.nanmedian(sigma_noise)) if np.isfinite(sigma_noise).any() else 0.0
    first = b + z * math.hypot(texture, noise)
    if math.isfinite(first) and first < ASSUMED_FULL_DARKNESS / 2:
        # the mean and the spread of the whole free surface (dust and bubbles included,
        # which the second pass would cut away with faint contact) stay the first pass's
        b, spread, texture, n_free, _, _ = _free_statistics(few, sigma_noise, first)
    corr = correlation_area(few, b, spread)
    with np.errstate(invalid="ignore"):
        sig = np.sqrt(sigma_noise.astype(np.float64) ** 2 + texture ** 2)
    seed = (b + z * sig).astype(np.float32)
    finite = np.isfinite(seed) & np.isfinite(samples[0]) if samples else np.isfinite(seed)
    seed_median = float(np.median(seed[finite])) if finite.any() else math.nan
    seed, seed_median, measured = _bounded_reach(few, noise, seed, seed_median, b, contrast)
    sigma_free = float(np.median(sig[finite])) if finite.any() else 0.0
    notes: list[str] = []
    reach = seed_median if math.isfinite(seed_median) else 0.0
    n_full, weak = 0, False
    if contrast is not None:
        c, c_lo, c_hi, source = float(contrast), float(contrast), float(contrast), "given"
        n_full = int(_interiors(samples, max(c / 2, reach)).size)
    else:
        cut = max(ASSUMED_FULL_DARKNESS / 2, reach)
        values = _plateau(samples, cut)
        if values.size < MIN_FULL_PX and reach < ASSUMED_FULL_DARKNESS / 2 and not static:
            # not in a static scene, whose free surface keeps the ice's dust, bubbles and
            # scratches dark (they take up to a third of the light, as a plateau too)
            found = _weak_plateau(samples, reach, sigma_free)
            if found is not None:
                (values, cut), weak = found, True
        n_full = int(values.size)
        if n_full >= MIN_FULL_PX:
            c, c_lo, c_hi = _full_level(values, noise, bounded=not (weak or bright))
            source = "measured"
            if free_measured and not bright:
                c, c_hi, source = _optics_level(c, c_hi, sigma_free, optics, notes,
                                                lambda: _neighbour_excess(few, cut, sigma_noise))
            if weak and source == "measured":
                notes.append(
                    f"full contact's darkness is read from a weak plateau ({c:.3f}): full "
                    f"contact seen through stray light of {1 - c / ASSUMED_FULL_DARKNESS:.0%} "
                    f"of the light, or contact covering {c / ASSUMED_FULL_DARKNESS:.0%} of "
                    "each pixel (junctions below the pixel, many to a pixel); the error bar "
                    "reaches down to the second reading; give --contrast if you know which")
        else:
            c = optics[0] if optics is not None else ASSUMED_FULL_DARKNESS
            c_lo, c_hi = min(ASSUMED_FULL_RANGE[0], c), ASSUMED_FULL_RANGE[1]
            source = "assumed"
            notes.append(
                f"no contact in the sampled frames is resolved (wider than 3 px at a plateau "
                f"of darkness): the contact area is the darkness fraction "
                f"against an assumed full-contact darkness of {c:.4g} "
                + (f"({optics[1]}) " if optics is not None else "")
                + f"(range {c_lo:g}-{c_hi:g}); give --contrast with the darkness of full "
                "contact of your setup if it has stray light"
                + (_STATIC_SPOTS_NOTE if static else ""))
    threshold = max(c / 2, reach)
    separation = ((c / 2 - b) / (reach - b)) if reach > b else math.inf
    if separation <= 1.0:
        notes.append(_not_separated(reach, texture, b, c, threshold))
    model = AreaModel(b, texture, sigma_free, corr, n_free, mean, sd_all, seed, reach, c,
                      c_lo, c_hi, source, n_full, threshold, separation, notes,
                      int(min_cluster_px), bool(static), float(zone_sigma), float(zone_corr_px),
                      *(rim if rim is not None and np.any(rim[1]) else (None, None, 0)),
                      weak_plateau=weak, reach_measured=measured)
    return _graded_model(model, samples, few)


def _not_separated(reach: float, texture: float, offset: float, full: float,
                   threshold: float) -> str:
    """The note of a free surface whose darkness `reaches` past half of `full` contact's:
    resolved contact counted above the `threshold` only, or none at all where the free
    surface reaches past full contact itself."""
    reaches = (f"contact and free surface do not separate: the free surface's darkness "
               f"reaches {reach:.3f} (texture {texture:.3f}, offset {offset:+.3f}), ")
    if reach >= full:  # no darkness a contact can have lies above the decision
        return (reaches + f"beyond the darkness of full contact itself ({full:.3f}): no "
                "contact can be told from the free surface (is this TIR footage of the lit "
                "zone?); the area is unmixed only and its error bar is wide")
    return (reaches + f"beyond half the darkness of full contact ({full / 2:.3f}); resolved "
            f"contact is counted above {threshold:.3f} only, the rest is unmixed and its "
            "error bar is wide")


def with_absorbed(model: AreaModel, absorbed: np.ndarray) -> AreaModel:
    """A static junction field's `model` with what its free-surface estimate may have
    absorbed (:attr:`AreaModel.absorbed`), and a note that
    says what the bar's high end then reads (a clause of the static scene's note on faint
    dark spots where it has one).

    Parameters
    ----------
    model : AreaModel
        A static scene's model (``model.static``) without resolved contact
        (``model.junction_field``).
    absorbed : (M, N) ndarray
        :func:`tir_contact.reference.absorbed_darkness` of its free-surface estimate.

    Returns
    -------
    AreaModel

    Raises
    ------
    ValueError
        If `model` is not a static junction field.
    """
    if not (model.static and model.junction_field):
        raise ValueError("absorbed darkness is read only for a static scene without resolved "
                         f"contact, got static={model.static}, "
                         f"junction_field={model.junction_field}")
    high = (f"high end reads the frame against the free-surface estimate without the dark "
            f"spots narrower than {LOCAL_FREE_PX} px it followed, which may be junctions "
            "too faint or small to be taken for contact")
    notes = list(model.notes)
    for k, note in enumerate(notes):
        if note.endswith(_STATIC_SPOTS_NOTE):
            notes[k] = f"{note}, and its {high}"
            break
    else:
        notes.append(f"no contact is resolved in this static scene: the error bar's {high}; "
                     "give an empty frame (--reference) to measure the free surface")
    a = np.asarray(absorbed, np.float32)
    measured = a[np.isfinite(a)]
    # the closing's lift over a free pixel's noise and fine texture, the level the followed
    # spots stand above: the median over the measured pixels
    base = np.float32(np.median(measured)) if measured.size else np.float32(0.0)
    return replace(model, absorbed=np.maximum(a - base, np.float32(0.0)), notes=notes)


def _graded_model(model: AreaModel, samples: list[np.ndarray], few: list[np.ndarray]
                  ) -> AreaModel:
    """`model` with whether its contact is graded (none resolved: whatever contact there is
    lies below the pixel; else :func:`tir_contact.graded.graded_contact`) and the free
    surface's mean away from contact (:func:`_free_mean`).

    A graded contact's few plateaus may be its densest clusters of junctions, not full
    contact: where full contact's darkness was measured on them below the range of full
    contact without stray light (:data:`ASSUMED_FULL_RANGE`), its range reaches up to
    that range's top, and the error bar's low end with it."""
    graded = (model.junction_field
              or graded_contact(samples, model.threshold, model.free_level()))
    high, notes = model.contact_high, model.notes
    if graded and model.contact_source == "measured" and not model.weak_plateau \
            and model.contact_darkness < ASSUMED_FULL_RANGE[0]:
        high = max(high, ASSUMED_FULL_RANGE[1])
        notes = [*notes, (
            f"full contact's darkness ({model.contact_darkness:.3f}) is read on "
            f"{model.n_full_px} px of a field of junctions: full contact seen through stray "
            "light, or the field's densest clusters; the error bar reaches down to full "
            f"contact at {high:g}; give --contrast if you know which")]
    # the free surface's mean: read against by a junction field's box and by graded
    # contact's columns (their means)
    offset, spread = (_free_tiles(few, model.sigma_free * math.sqrt(model.corr_px))
                      if graded else (math.nan, 0.0))
    return replace(model, graded=graded, contact_high=high, notes=notes, field_offset=offset,
                   field_offset_spread=spread)


def _past_rim(touch: np.ndarray, model: AreaModel, box: tuple[slice, slice] | None) -> int:
    """Unlit pixels within ``model.rim_px`` of `touch`, the contact zone's pixels in the lit
    zone's rim band (of the frame, or of ``frame[box]``): where contact at the rim may go
    on unseen, the half-light line being placed to within the band. With a box, counted
    in the box grown by that width (contact near the box's edge reaches past it)."""
    width = model.rim_px
    beyond = model.beyond
    touch = touch.view(np.uint8)
    if box is not None:  # the box grown by the width, the touching pixels placed in it
        h, w = beyond.shape
        (r0, r1), (c0, c1) = box[0].indices(h)[:2], box[1].indices(w)[:2]
        top, left = min(width, r0), min(width, c0)
        bottom, right = min(width, h - r1), min(width, w - c1)
        touch = cv2.copyMakeBorder(touch, top, bottom, left, right, cv2.BORDER_CONSTANT,
                                   value=0)
        beyond = beyond[r0 - top : r1 + bottom, c0 - left : c1 + right]
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * width + 1,) * 2)
    return int(np.count_nonzero(cv2.dilate(touch, disc).view(np.bool_) & beyond))


def _in_rim(touch: np.ndarray, counted: np.ndarray, u: np.ndarray, sum_un: np.ndarray,
            b_un: float, model: AreaModel) -> float:
    """What the bar's low end counted (px) of the contact zone's pixels in the lit zone's
    rim band (`touch`): its resolved pixels it counted whole (`counted`: at or above the
    low end's threshold), and, outside a static scene (whose low end counts none of it),
    the unmixed excess of the summed pixels (`sum_un`, read in `u` against `b_un`) over
    full contact's high end. The half-light line placed to within the band, that contact
    may lie beyond the true one."""
    n = float(np.count_nonzero(touch & counted))
    if not model.static:
        un = touch & sum_un
        if un.any():
            excess = float(np.sum(u[un] - b_un, dtype=np.float64))
            n += max(excess, 0.0) / max(model.contact_high, 1e-6)
    return n


@dataclass(frozen=True)
class FrameArea:
    """Contact area of one frame with its error bar, px (:func:`frame_area`).

    Attributes
    ----------
    area_px, low_px, high_px : float
        The area and the range it takes over the plausible decisions.
    resolved_px : int
        Pixels of resolved contact (counted).
    unmixed_px : float
        Area of unresolved contact (the darkness fraction), px.
    """

    area_px: float
    low_px: float
    high_px: float
    resolved_px: int
    unmixed_px: float


def _kept_clusters(d: np.ndarray, seeds: np.ndarray, half: np.ndarray, resolved: np.ndarray,
                   model: AreaModel, finite: np.ndarray, box: tuple[slice, slice] | None = None
                   ) -> tuple[np.ndarray, np.ndarray | None]:
    """The seed pixels that are contact: those within :data:`ZONE_PX` of an anchor (resolved
    contact, or a region above the half-contact threshold of ``min_cluster_px`` pixels at
    least that the image border cuts, too thin to be resolved only because the view ends
    there: their unresolved neighbours) and, in a video without resolved contact, the
    8-connected clusters of seeds whose summed excess darkness is significant against the
    free surface's fluctuation summed over them (correlated over ``corr_px``) at the seed
    level's false-alarm rate, unless the scene is static and shows resolved contact (its
    free surface keeps the dust dark, which resolved contact tells apart). The rest (noise,
    a texture or dust spot) is free surface.

    In that static scene the seeds inside the zone are contact where they pass the zone's
    own level (:func:`_over_zone_level`: the light's texture the estimate cannot follow
    there added; those below it are judged as the seeds beyond the zone are), and, beyond
    the zone, the seeds at the half-contact threshold (`d`,
    read against the local free surface, of the frame or of ``frame[box]``; outside the
    lit zone's rim band, ``model.rim``) are contact too: thin contact, a junction too thin
    or small for the 3 x 3 opening, is contact by the segmentation's own decision, which
    the free surface (its reach below that threshold) does not pass; its blur is unmixed
    with it in the kept seeds' envelope (:func:`_envelope`). Dust and bubbles fainter than
    half of full contact are not taken; flaws that reach it (overlapping bubbles or
    scratches on crowded ice) are. In the rim band the light's own fall-off reaches as
    dark.

    Second: in that static scene, the rest of the clusters beyond the anchors' zone that
    pass the significance test (junctions of the same contact farther out, or the ice's
    dust: the error bar's high end holds them); None elsewhere."""
    if not seeds.any():
        return seeds, None
    anchors = resolved | _at_border(_clusters(half, model.min_cluster_px))
    near = (cv2.dilate(anchors.view(np.uint8), _ZONE).astype(bool) & seeds
            if anchors.any() else np.zeros(seeds.shape, bool))
    static_shown = _shows_contact(model)
    # the seed level in the free surface's sigmas above b (where the reach is the Gaussian
    # extrapolation: the quantile of the frame's false-alarm rate per pixel)
    z = (model.seed_median - model.offset) / max(model.sigma_free, 1e-9)
    if static_shown:  # dust is dark here: resolved contact shows where contact is
        if model.zone_sigma > 0 and near.any():
            near &= _over_zone_level(d, model, z, box)
        seeds = seeds & ~near
        if not seeds.any():
            return near, None
    n, lab = cv2.connectedComponents(seeds.view(np.uint8), connectivity=8, ltype=cv2.CV_32S)
    inside = seeds & finite
    excess = np.bincount(lab[inside], weights=d[inside] - model.offset, minlength=n)
    size = np.bincount(lab[inside], minlength=n)
    # a static scene's free surface keeps its dust, bubbles and scratches: a cluster is
    # weighed against the free surface's whole spread (them included), not its noise
    sigma = max(model.sd_free, model.sigma_free) if model.static else model.sigma_free
    noise = sigma * np.sqrt(np.maximum(size, 1) * model.corr_px)
    keep = (size >= model.min_cluster_px) & (excess > z * noise)
    keep[0] = False
    if static_shown:
        # thin contact beyond the zone: at half of full contact over the local free surface
        with np.errstate(invalid="ignore"):
            thin = (d >= model.threshold) & seeds
        if model.rim is not None:
            thin &= ~(model.rim if box is None else model.rim[box])
        return near | thin, keep[lab] & ~thin
    return keep[lab] | near, None


def _over_zone_level(d: np.ndarray, model: AreaModel, z: float,
                     box: tuple[slice, slice] | None) -> np.ndarray:
    """Where a static scene's darkness `d` (read against the local free surface, of the
    frame or of ``frame[box]``) passes the seed level of the zone around resolved
    contact: the frame's seed level ``model.seed`` with the spread of the light the
    estimate continues over the contact but cannot follow there (``model.zone_sigma``,
    the free surface's texture) added in quadrature, `z` of it (the frame's seed level in
    the free surface's sigmas: the same false-alarm rate per pixel); at most the
    half-contact threshold, where the segmentation itself calls a pixel contact.

    At the frame's own level the texture's dark side passes there and its envelope is
    unmixed as contact (the load series' first frame at 1 bar: 2140 px of envelope, 1960
    of them free surface, read 262 px of contact where 110 px are true; on 29 draws of
    the series each load read 5-18 % high on average, now -6 to +1 %). The seeds below
    the level go on to the tests beyond the zone (:func:`_kept_clusters`): at the
    half-contact threshold they are thin contact, else the bar's high end may hold them.
    """
    seed = model.seed if box is None else model.seed[box]
    level = model.offset + np.hypot(seed - np.float32(model.offset),
                                    np.float32(z * model.zone_sigma))
    with np.errstate(invalid="ignore"):
        return d >= np.minimum(level, np.float32(model.threshold))


def _shows_contact(model: AreaModel) -> bool:
    """A static scene whose sampled frames show resolved contact (:data:`MIN_FULL_PX`
    interior pixels at least; a given contrast does not make it so): its free surface
    keeps the ice's dust, bubbles and scratches dark, and the resolved contact shows where
    contact is."""
    return model.static and not model.junction_field


def _envelope(seeds: np.ndarray) -> np.ndarray:
    """The envelope of seed pixels (bool): the seeds, their neighbours within the edge
    margin and the gaps between them narrower than it (every pixel in it unmixed)."""
    return cv2.morphologyEx(cv2.dilate(seeds.view(np.uint8), _EDGE), cv2.MORPH_CLOSE,
                            _EDGE).view(np.bool_)


def _static_high(d: np.ndarray, sum_un: np.ndarray, excess_un: float,
                 maybe: np.ndarray | None, inner: np.ndarray, finite: np.ndarray,
                 b: float) -> float:
    """What a static scene's error bar adds above the unmixed excess `excess_un` (read
    over `sum_un` against the local free surface): the zone read against the video's
    free surface instead, where that holds more (a junction field denser than the
    opening's disc looks like a plateau to it), and the significant seed clusters `maybe`
    beyond the zone (junctions of the same contact farther out, or the ice's dust; their
    envelope outside `inner`, the zone and the resolved edges), read against it too."""
    extra = max(float(np.sum(d[sum_un] - b, dtype=np.float64)) - excess_un, 0.0)
    if maybe is not None and maybe.any():
        env = _envelope(maybe) & ~inner & finite
        extra += max(float(np.sum(d[env] - b, dtype=np.float64)), 0.0)
    return extra


def _at_border(mask: np.ndarray) -> np.ndarray:
    """The 8-connected regions of `mask` that touch the image border."""
    if not mask.any():
        return mask
    n, lab = cv2.connectedComponents(mask.view(np.uint8), connectivity=8, ltype=cv2.CV_32S)
    keep = np.zeros(n, bool)
    for edge in (lab[0], lab[-1], lab[:, 0], lab[:, -1]):
        keep[edge] = True
    keep[0] = False
    return keep[lab]


def _clusters(mask: np.ndarray, min_px: int) -> np.ndarray:
    """The 8-connected regions of `mask` of at least `min_px` pixels."""
    if min_px <= 1 or not mask.any():
        return mask
    _, lab, stats, _ = cv2.connectedComponentsWithStats(mask.view(np.uint8), connectivity=8)
    keep = stats[:, cv2.CC_STAT_AREA] >= min_px
    keep[0] = False
    return keep[lab]


def _resolved_area(d: np.ndarray, resolved: np.ndarray, zone_res: np.ndarray, b: float,
                   c: float, t_lo: float) -> tuple[float, int]:
    """Area (px) of resolved contact, and its pixels at or above `t_lo`: its deep interior
    (pixels :data:`EDGE_PX` or more inside a resolved region) counted, every pixel one (a
    contact's darkness may vary inside it, as with pressure), and its edge band (`zone_res`
    less the deep interior) unmixed against the mean darkness of the deep pixels within
    :data:`LOCAL_PX` of it (where the blur has left the full darkness), or against `c`
    where there is none.

    The deep interior lies inside `resolved`, at or above the half-contact threshold (so
    at or above `t_lo`, which is at most that threshold) and measured; only the band's
    pixels are read one by one.
    """
    if not resolved.any():
        return 0.0, 0
    deep = cv2.erode(resolved.view(np.uint8), _EDGE, borderType=cv2.BORDER_CONSTANT,
                     borderValue=0)
    n_deep = cv2.countNonZero(deep)
    band = np.flatnonzero(zone_res & ~deep.view(np.bool_))
    if band.size == 0:
        return float(n_deep), n_deep
    size = (2 * LOCAL_PX + 1,) * 2
    # deep pixels and their summed darkness in each pixel's neighbourhood
    w = cv2.boxFilter(deep, cv2.CV_16U, size, normalize=False, borderType=cv2.BORDER_CONSTANT)
    v = cv2.boxFilter(cv2.copyTo(d, deep, np.zeros(d.shape, np.float32)), -1, size,
                      normalize=False, borderType=cv2.BORDER_CONSTANT)
    w_b = w.ravel().take(band).astype(np.float32)
    v_b = v.ravel().take(band)
    d_b = d.ravel().take(band) if d.flags.c_contiguous else d[np.unravel_index(band, d.shape)]
    # enough deep pixels near: their mean; else the video's c
    full = np.where(w_b >= MIN_LOCAL_PX, v_b / np.maximum(w_b, 1.0), c)
    scale = np.maximum(full - b, 1e-3)
    area = n_deep + float(np.sum((d_b - b) / scale, dtype=np.float64))
    return area, n_deep + int(np.count_nonzero(d_b >= t_lo))


def _absorbed_budget(d: np.ndarray, finite: np.ndarray, model: AreaModel) -> float:
    """A static junction field's darkness budget read against its estimate without the
    dark spots it may have absorbed: with ``A`` = ``model.absorbed``, a pixel's darkness
    ``d`` against the estimate is ``1 - (1 - d)(1 - A)`` against that one; summed over the
    measured pixels less the free surface's mean (read against the estimate itself), over
    full contact's low end."""
    if not np.any(finite):
        return 0.0
    a = model.absorbed[finite]
    x = d[finite]
    total = float(np.sum(x + a * (1.0 - x) - model.mean_free, dtype=np.float64))
    return total / max(model.contact_low, 1e-6)


def _budget(d: np.ndarray, finite: np.ndarray, model: AreaModel) -> tuple[float, float]:
    """The frame's darkness budget: the excess darkness of every measured pixel over the
    free surface's mean (its dust and texture included), as contact area (px), and its
    standard deviation (the free surface's whole fluctuation summed over the frame,
    correlated over ``corr_px``, and the uncertainty of the mean)."""
    n = int(np.count_nonzero(finite))
    if n == 0:
        return 0.0, 0.0
    c = model.contact_darkness
    total = float(np.sum(d[finite] - model.mean_free, dtype=np.float64)) / c
    sd_sum = model.sd_free * math.sqrt(n * model.corr_px)
    sd_b = n * model.sd_free * math.sqrt(model.corr_px / max(model.n_free, 1))
    return total, math.hypot(sd_sum, sd_b) / c


#: Disc (px) of the grey opening that gives a static scene's local free surface around
#: unresolved contact (:func:`_over_local_free`): as wide as the zone unresolved contact
#: is sought in around resolved contact (``2 ZONE_PX + 1``): the opening uses that zone's
#: disc, ``_ZONE``.
LOCAL_FREE_PX = 2 * ZONE_PX + 1


def _over_local_free(d: np.ndarray, finite: np.ndarray, b: float) -> np.ndarray:
    """A static scene's darkness over its local free surface, plus ``b``: ``d`` less the
    grey opening of its 5 x 5 mean by a disc of :data:`LOCAL_FREE_PX` (at least ``b``;
    unmeasured pixels taken at ``b``), ``b`` added back (the opening of the noisy darkness
    itself follows the noise's lower envelope, about two sigma low, and every reading
    would gain that much).

    A static scene's free-surface estimate is continued over the contact from around it
    (:func:`tir_contact.reference.free_surface`) and cannot follow the ice's bubbles and
    scratches there: they stay in the darkness as plateaus wider than the disc, which the
    opening keeps, while junctions below the pixel (spots of 1-3 px, and their clusters
    narrower than the disc) rise above it. Texture narrower than the disc (a bubble's rim,
    a scratch) still rises above it. Resolved contact is read from ``d`` itself.
    """
    bf = np.float32(b)
    filled = np.where(finite, d, bf).astype(np.float32, copy=False)
    # an opening of noisy darkness follows the noise's lower envelope (about 2 sigma
    # below its mean over a plateau), which would lift every pixel's reading by that
    # much: the opening is taken of the 5 x 5 mean (noise down to a fifth)
    smooth = cv2.blur(filled, (5, 5), borderType=cv2.BORDER_REPLICATE)
    local = np.maximum(cv2.morphologyEx(smooth, cv2.MORPH_OPEN, _ZONE,
                                        borderType=cv2.BORDER_REPLICATE), bf)
    return np.where(finite, d - local + bf, np.float32(np.nan)).astype(np.float32,
                                                                         copy=False)


def _unmixed_part(u: np.ndarray, edge: np.ndarray, zone: np.ndarray, zone_un: np.ndarray,
                  finite: np.ndarray, model: AreaModel, *, field: bool
                  ) -> tuple[np.ndarray, float, float]:
    """The pixels unmixed beyond the resolved part, the faint contact missed beyond them
    (px) and the level they are read against.

    The zone's, read against ``b``, and the excess darkness of a ring around the zone (faint
    contact beyond it); in a junction field (no resolved contact in the sampled frames;
    `field`: a box with contact in this frame) the box's every measured pixel (none is
    beyond them: module notes), read against the free surface's mean
    (``model.field_offset``): free pixels summed, not chosen for being dark.
    """
    if field and model.junction_field:
        return ~edge & finite, 0.0, model.free_mean
    ring = cv2.dilate(zone.view(np.uint8), _EDGE).view(np.bool_) & ~zone & finite
    missed = max(float(np.sum(u[ring] - model.offset, dtype=np.float64)), 0.0)
    return zone_un, missed / model.contact_darkness, model.offset


def _zone_sd(model: AreaModel, n_z: int, n_un: int) -> float:
    """Standard deviation (px of area) of a zone of `n_z` pixels read against the free
    surface, `n_un` of them summed (unmixed beyond the resolved contact): the free
    surface's fluctuation summed over the zone (correlated over ``corr_px``), the
    uncertainty of its mean, a static scene's light the estimate continues over the
    contact but cannot follow there, and graded contact's summed pixels lying where the
    free surface's offset differs from its mean by its spread between places (not averaged
    down over the pixels: it is the light's and the block's path's, not noise)."""
    if not n_z:
        return 0.0
    sd_sum = model.sigma_free * math.sqrt(n_z * model.corr_px)
    sd_b = n_z * model.sigma_free * math.sqrt(model.corr_px / max(model.n_free, 1))
    sd_zone = model.zone_sigma * math.sqrt(n_z * model.zone_corr_px)
    sd_place = n_un * model.field_offset_spread
    total = math.sqrt(sd_sum ** 2 + sd_b ** 2 + sd_zone ** 2 + sd_place ** 2)
    return total / model.contact_darkness


def frame_area(d: np.ndarray, model: AreaModel, box: tuple[slice, slice] | None = None, *,
               half: np.ndarray | None = None, seeds: np.ndarray | None = None,
               finite: np.ndarray | None = None) -> FrameArea:
    """Contact area of one frame's darkness `d` (module notes), with its error bar.

    Parameters
    ----------
    d : (M, N) ndarray of float32
        Darkness, NaN where not measured: of the whole frame, or of ``frame[box]``.
    model : AreaModel
    box : (slice, slice), optional
        Only this part of the frame holds contact (the rest is free surface: no seed
        there); the frame's darkness budget is then not drawn on.
    half, seeds, finite : ndarray of bool, optional
        ``d >= model.threshold``, ``d >= model.seed`` and ``isfinite(d)``, when already
        known (the analysis tests the raw grey values,
        :class:`tir_contact._darkness.ContactTest`), of `d`'s shape. Given `seeds` are
        used as they are; a static scene that shows resolved contact reads its own
        against the local free surface (:func:`_over_local_free`) when they are not
        given (the analysis gives them only for a fixed camera).

    Returns
    -------
    FrameArea

    Examples
    --------
    >>> rng = np.random.default_rng(2)
    >>> d = rng.normal(0.0, 0.02, (120, 160)).astype(np.float32)
    >>> d[40:80, 50:110] += 0.8
    >>> m = area_model([d], np.full(d.shape, 0.02, np.float32))
    >>> a = frame_area(d, m)
    >>> a.resolved_px, a.low_px <= 2400 <= a.high_px
    (2400, True)
    """
    whole = box is None
    seed = model.seed
    if box is not None:
        full = d.shape == seed.shape
        # one copy of the box: every read below is of contiguous memory
        d = np.ascontiguousarray(d[box]) if full else d
        half, seeds, finite = (x[box] if x is not None and full else x
                               for x in (half, seeds, finite))
        seed = seed[box]
    c, b = model.contact_darkness, model.offset
    if finite is None:
        finite = np.isfinite(d)
    # the darkness unresolved contact is read from: a static scene that shows resolved
    # contact, over its local free surface (its bubbles and scratches stay dark there)
    static_shown = _shows_contact(model)
    u = _over_local_free(d, finite, b) if static_shown else d
    with np.errstate(invalid="ignore"):
        seeds = u >= seed if seeds is None else seeds.copy()
        if half is None:
            half = d >= model.threshold
    resolved = _resolved(half)
    edge = cv2.dilate(resolved.view(np.uint8), _EDGE).view(np.bool_)
    seeds &= ~edge  # seeds on a resolved region's edge are its own
    maybe = None
    if seeds.any():
        seeds, maybe = _kept_clusters(u, seeds, half, resolved, model, finite, box)
        near = _envelope(seeds)  # the unresolved contact's envelope
    else:
        near = seeds
    zone_res = edge & finite
    zone_un = near & ~edge & finite
    zone = zone_res | zone_un
    sum_un, missed, b_un = _unmixed_part(u, edge, zone, zone_un, finite, model,
                                         field=not whole and zone.any())
    # the resolved part over the plausible decisions: counted at any threshold between the
    # free surface's reach (at least c / 4) and 3 c / 4, or unmixed
    t_lo = max(model.seed_median, c / 4) if math.isfinite(model.seed_median) else c / 4
    t_lo = min(t_lo, model.threshold)
    t_hi = max(0.75 * c, model.threshold)
    part_res, res_hi = _resolved_area(d, resolved, zone_res, b, c, t_lo)
    excess_un = float(np.sum(u[sum_un] - b_un, dtype=np.float64))
    n_un = int(np.count_nonzero(sum_un))
    n_z = int(np.count_nonzero(zone_res)) + n_un
    with np.errstate(invalid="ignore"):
        counted = resolved & (d >= t_hi)  # the resolved pixels the low end counts
    res_lo = int(np.count_nonzero(counted))
    # the unresolved part over c's range; both parts' noise
    sd = _zone_sd(model, n_z, n_un)
    area = part_res + excess_un / c
    res_alone = min(part_res, res_lo)  # the resolved part's low end
    low = res_alone + excess_un / max(model.contact_high, 1e-6) - BAND_SIGMAS * sd
    if model.static:
        # a static scene: every seed kept beside the resolved contact may be the ice's dust,
        # bubbles or scratches, which its free surface keeps dark: the bar reaches down to
        # the resolved contact alone (to no contact at all where none is resolved)
        low = min(low, res_alone - BAND_SIGMAS * sd)
    if model.weak_plateau:
        # the other reading of a weak plateau: every pixel of the zone covered in part (many
        # junctions below the pixel), its darkness the share covered of full contact
        # (c measured: no junction field, the unmixed pixels are the zone's own)
        full = ASSUMED_FULL_RANGE[1]
        alt = (float(np.sum(d[zone_res] - b, dtype=np.float64)) + excess_un) / full
        low = min(low, alt - BAND_SIGMAS * sd * c / full)  # sd is in area at c
    high_un = excess_un + (_static_high(d, sum_un, excess_un, maybe, zone | edge, finite, b)
                           if static_shown else 0.0)
    high = (max(part_res, res_hi) + high_un / max(model.contact_low, 1e-6) + missed
            + BAND_SIGMAS * sd)
    # a junction field read against the free surface's mean: the median's reading too
    shift = (b_un - b) * n_un / c
    low, high = low - max(-shift, 0.0), high + max(shift, 0.0)
    if model.rim is not None:
        # the found edge is the half-light line to within the rim band: contact in the band
        # may go on past it, or lie past the true line
        touch = zone & (model.rim if box is None else model.rim[box])
        if touch.any():
            high += _past_rim(touch, model, box)
            low -= _in_rim(touch, counted, u, sum_un, b_un, model)
    if whole:  # the whole frame: its darkness budget (module notes)
        budget, sd_g = _budget(d, finite, model)
        # where the free surface reaches past half of full contact, the seeds cannot see
        # faint contact: the budget is the estimate when it holds clearly more
        if model.separation <= 1.0 and budget - area > BAND_SIGMAS * sd_g:
            area = budget
            low = min(low, budget - BAND_SIGMAS * sd_g)
        elif model.static:
            # a static scene: the seeds near contact may be the ice's dust, bubbles and
            # scratches, which its free surface keeps dark (they are chosen for being
            # dark, so their excess is not zero-mean); the budget, with the free surface's
            # mean (dust included) taken out everywhere, is the other plausible decision
            low = min(low, budget - BAND_SIGMAS * sd_g)
        high = max(high, budget + BAND_SIGMAS * sd_g)
        if model.absorbed is not None:
            # a static junction field: read against the estimate without the dark spots
            # it may have followed (junctions it took for the light), over full contact's
            # low end
            high = max(high, _absorbed_budget(d, finite, model)
                       + BAND_SIGMAS * sd_g * c / max(model.contact_low, 1e-6))
    area = max(area, 0.0)  # a field's box of noise alone may sum below zero
    low, high = max(min(low, area), 0.0), max(high, area)
    n_res = int(np.count_nonzero(resolved))
    return FrameArea(float(area), float(low), float(high), n_res, float(excess_un / c))
