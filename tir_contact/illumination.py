"""Where the TIR light reaches: the lit zone of the prism in the camera's view.

Total internal reflection lights only the part of the ice surface that the prism's light
reaches. On real rigs this is often a vignetted disc, an ellipse or a band covering a
minority of the frame, with a soft rim and a dark outside. Nothing outside the lit zone can
be measured, so nothing outside it is ever contact.

Method (:func:`find_lit_zone`), on the free-surface image (a frame, or each pixel's bright
percentile over frames):

1. Shrink the image to about 256 px on its long side (area mean) and smooth it (median of
   5, then a Gaussian of 1.5 px): noise, JPEG blocks and dust go, the illumination stays.
2. Levels: the bright level is the 99.5th percentile; the black level the 0.5th percentile,
   but at most a tenth of the bright level (a frame lit all over has no black).
3. Lit: brighter than the black level plus ``level_fraction`` (default 0.5: the half-light
   line of the rim) of the span between black and the brightest level within 15 % of the
   image (so a vignetted corner, dimmed slowly, stays lit while a rim, dimmed steeply, is
   cut), and brighter than a quarter of the span between black and bright. Contacts inside
   the zone are dark holes in it: a closing with a disc of 3 % of the image and a hole
   fill put them back; bright specks smaller than 0.5 % of the frame are dropped; the rest
   is replaced by its convex hull, which closes the notches of contacts at the rim and
   joins the pieces a contact across the zone cuts; where the seen rim is an ellipse (a lit
   disc or ellipse), the ellipse fitted to it continues the rim under such contacts. The
   fit leaves out the hull's long sides (:data:`CHORD_FRACTION`: the chord along a contact
   that hides the rim) and, fitting again, the points off the ellipse (a chord that is not
   straight), while at least half of the seen rim is kept; the ellipse must hold the lit
   zone (:data:`LIT_OUTSIDE_ELLIPSE`) or else, where it does not (a fit continued far
   from the seen rim, to where the frame cuts the zone, may run a few px inside it), add a
   held contact, through whose gaps light shows (:func:`_adds_lit`), and be no flatter
   than a prism's lit ellipse (:data:`MAX_AXIS_RATIO`), else a band's few curved rim points
   would make one. The zone is the hull and the ellipse together.
4. The rim is the band of ``rim_px`` (default 1 % of the image's long side) inside the
   zone's edge; contact regions that touch it are flagged, since part of them may lie
   where there is too little light to see them.

Assumptions: the lit zone is one convex region (``convex=False`` drops this: then one or a
few regions, each larger than 0.5 % of the frame); its light falls off smoothly.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from tir_contact._morphology import disc_dilate

__all__ = ["LitZone", "find_lit_zone", "lit_zone_from_file", "shrink", "whole_frame"]

#: Long side, px, of the shrunk image the zone is found on.
_WORK_PX = 256


@dataclass(frozen=True)
class LitZone:
    """The lit part of the frame.

    Attributes
    ----------
    mask : (M, N) ndarray of bool
        True where TIR light reaches.
    rim : (M, N) ndarray of bool
        The band inside the zone's edge (empty when the zone fills the frame).
    method : str
        How the zone was found: ``"found"``, ``"whole frame"`` or ``"file"``.
    bright_level, black_level : float
        Grey levels of the lit free surface and of the unlit outside.
    rim_px : int or None
        Width of the rim band, px (None: not known, e.g. a zone built by hand).
    """

    mask: np.ndarray
    rim: np.ndarray
    method: str
    bright_level: float = float("nan")
    black_level: float = float("nan")
    rim_px: int | None = None

    @property
    def fraction(self) -> float:
        """Fraction of the frame that is lit."""
        return float(self.mask.mean())


def shrink(image: np.ndarray) -> tuple[np.ndarray, float]:
    """`image` (float32) reduced by area means to about 256 px on its long side (itself when
    smaller), and the scale factor used: the working image of the lit zone and the
    free-surface closing."""
    h, w = image.shape
    scale = min(1.0, _WORK_PX / max(h, w))
    if scale >= 1.0:
        return image, 1.0
    size = (max(1, round(w * scale)), max(1, round(h * scale)))
    return cv2.resize(image, size, interpolation=cv2.INTER_AREA), scale


def whole_frame(shape: tuple[int, int]) -> LitZone:
    """A lit zone covering the whole frame (no rim)."""
    return LitZone(np.ones(shape, bool), np.zeros(shape, bool), "whole frame")


def _rim_width(shape: tuple[int, int]) -> int:
    """Default width (px) of a lit zone's rim band: 1 % of the image's long side, at least
    2 px."""
    return max(2, round(0.01 * max(shape)))


def _rim(mask: np.ndarray, rim_px: int) -> np.ndarray:
    """Pixels of `mask` within `rim_px` of an unlit pixel; the frame border is not a rim."""
    if mask.all() or rim_px < 1:
        return np.zeros_like(mask)
    padded = np.pad(mask.astype(np.uint8), rim_px + 1, mode="edge")
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * rim_px + 1, 2 * rim_px + 1))
    inner = cv2.erode(padded, k)[rim_px + 1: -rim_px - 1, rim_px + 1: -rim_px - 1]
    return mask & ~inner.astype(bool)


def find_lit_zone(
    image: np.ndarray,
    *,
    level_fraction: float = 0.5,
    floor_fraction: float = 0.25,
    rim_px: int | None = None,
    min_region_fraction: float = 0.005,
    convex: bool = True,
) -> LitZone:
    """Find the lit zone of a free-surface image (see the module notes for the method).

    Parameters
    ----------
    image : (M, N) ndarray
        A frame or a per-pixel bright percentile over frames (dark contact).
    level_fraction : float
        Lit means brighter than black + this fraction of (nearby bright - black), in (0, 1):
        0.5 puts the edge on the rim's half-light line.
    floor_fraction : float
        ... and brighter than black + this fraction of (bright - black) (the dark outside
        far from the zone, where the nearby light is the outside's own).
    rim_px : int, optional
        Width of the rim band, px; default 1 % of the long side (at least 2 px).
    min_region_fraction : float
        Lit regions smaller than this fraction of the frame are dropped.
    convex : bool
        Take the convex hull of the lit regions (a disc, ellipse or band lit through a prism
        is convex; a contact at its rim would otherwise cut a notch into it, one across it
        would cut it in pieces). Pixels the hull adds that are too dark to measure are left
        out later by the noise test (:func:`tir_contact.reference.measurable`).

    Returns
    -------
    LitZone

    Examples
    --------
    >>> yy, xx = np.mgrid[:200, :300]
    >>> disc = np.where((xx - 150) ** 2 + (yy - 100) ** 2 < 60 ** 2, 100.0, 5.0)
    >>> zone = find_lit_zone(disc)
    >>> round(zone.fraction / (np.pi * 60 ** 2 / 60000), 1)  # the disc's share of the frame
    1.0
    """
    img = np.asarray(image, dtype=np.float32)
    if img.ndim != 2:
        raise ValueError(f"image must be 2-D, got shape {img.shape}")
    if not 0.0 < level_fraction < 1.0:
        raise ValueError(f"level_fraction must lie in (0, 1), got {level_fraction!r}")
    h, w = img.shape
    small, scale = shrink(img)
    small = cv2.medianBlur(small, 5)
    small = cv2.GaussianBlur(small, (0, 0), 1.5)
    black, bright = _levels(small)
    if not bright > black:
        return whole_frame((h, w))
    seen = _lit_test(small, black, bright, level_fraction, floor_fraction)
    d = max(3, round(0.03 * max(small.shape)) | 1)
    lit = cv2.morphologyEx(seen, cv2.MORPH_CLOSE,
                           cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (d, d)),
                           borderType=cv2.BORDER_REPLICATE)
    lit = _fill_holes(lit)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(lit, connectivity=8)
    keep = np.zeros(n, bool)
    keep[1:] = stats[1:, cv2.CC_STAT_AREA] >= min_region_fraction * lit.size
    lit = keep[labels].astype(np.uint8)
    if convex and lit.any():
        # a contact at the rim cuts a notch into the zone, a contact across it (a coin's
        # rim across a lit band) cuts it in pieces: the hull of all pieces restores it
        hull = _hull(lit)
        lit = hull | _ellipse_through_rim(lit, hull, small, seen)
    lit = lit.astype(np.float32)
    if scale < 1.0:
        lit = cv2.resize(lit, (w, h), interpolation=cv2.INTER_LINEAR)
    mask = lit >= 0.5
    if not mask.any():
        return LitZone(mask, mask.copy(), "found", bright, black)
    width = _rim_width((h, w)) if rim_px is None else rim_px
    method = "whole frame" if mask.all() else "found"
    return LitZone(mask, _rim(mask, width), method, bright, black, width)


#: An ellipse fitted to the rim is kept when its points lie within this of it (px, on the
#: shrunk working image) in the median, and 2.5 times that at the 90th percentile.
ELLIPSE_FIT_PX = 0.75


def _levels(small: np.ndarray) -> tuple[float, float]:
    """Step 2's black and bright levels of the working image: its 0.5th percentile, at
    most a tenth of the bright level (a frame lit all over has no black), and its 99.5th
    percentile."""
    bright = float(np.percentile(small, 99.5))
    return min(float(np.percentile(small, 0.5)), 0.1 * bright), bright


def _hull(mask: np.ndarray) -> np.ndarray:
    """The convex hull of a non-empty `mask`'s pixels, filled (uint8 0/1)."""
    hull = np.zeros(mask.shape, np.uint8)
    cv2.fillConvexPoly(hull, cv2.convexHull(cv2.findNonZero(np.asarray(mask, np.uint8))), 1)
    return hull


def _lit_test(small: np.ndarray, black: float, bright: float, level_fraction: float = 0.5,
              floor_fraction: float = 0.25) -> np.ndarray:
    """Step 3's test of each pixel of the working image (uint8 0/1): brighter than black
    plus `level_fraction` of the span to the light nearby and than black plus
    `floor_fraction` of the span to `bright`."""
    # against the light nearby (a dilation over 15 % of the image), so that vignetting,
    # which dims a whole region slowly, is not taken for the rim, which dims it steeply
    r = max(1, round(0.15 * max(small.shape)))
    nearby = disc_dilate(small, 2 * r + 1)
    return ((small - black > level_fraction * (nearby - black))
            & (small > black + floor_fraction * (bright - black))).astype(np.uint8)


def _ellipse_through_rim(lit: np.ndarray, hull: np.ndarray, image: np.ndarray | None = None,
                         seen: np.ndarray | None = None) -> np.ndarray:
    """The ellipse through the zone's rim, where the rim is an ellipse (uint8 0/1, or zeros).

    A contact that reaches the rim hides the rim behind it, and the hull cuts across the
    contact along a chord. The rim's points that are seen (on both the zone's edge and the
    hull's, away from the image border and off the hull's long sides, :func:`_chords`) are
    fitted with an ellipse, and fitted again without the points off it (up to
    :data:`TRIM_ROUNDS` times, while half of them stay); where they lie on it (a lit disc or
    ellipse), the ellipse continues the rim under the contact, if it holds the zone
    (:data:`LIT_OUTSIDE_ELLIPSE`) or, given the working `image` and its lit test `seen`
    (:func:`_lit_test`), what it adds to the hull is a held contact, through whose gaps
    light shows (:func:`_adds_lit`; the zone is the union of both, so lit pixels the fit
    misses stay), and it is no flatter than :data:`MAX_AXIS_RATIO`. A band's straight rims
    fit no ellipse and keep the hull.
    """
    h, w = lit.shape
    edge = lit & ~cv2.erode(lit, np.ones((3, 3), np.uint8), borderType=cv2.BORDER_REPLICATE)
    hull_edge = hull & ~cv2.erode(hull, np.ones((3, 3), np.uint8),
                                  borderType=cv2.BORDER_REPLICATE)
    near_hull = cv2.dilate(hull_edge, np.ones((3, 3), np.uint8))
    rim = edge & near_hull & ~_chords(hull_edge)
    rim[:2], rim[-2:], rim[:, :2], rim[:, -2:] = 0, 0, 0, 0
    pts = cv2.findNonZero(rim)
    none = np.zeros_like(lit)
    if pts is None or len(pts) < 20:
        return none
    n_seen = len(pts)
    for _ in range(TRIM_ROUNDS + 1):
        (cx, cy), (a, b), angle = cv2.fitEllipse(pts)
        if not (np.isfinite([cx, cy, a, b]).all() and 0 < a and 0 < b
                and max(a, b) < 4 * max(h, w)):
            return none
        # distance of the rim points from the ellipse, approximately (in its own axes)
        t = np.radians(angle)
        xy = pts.reshape(-1, 2).astype(np.float64) - (cx, cy)
        u = xy[:, 0] * np.cos(t) + xy[:, 1] * np.sin(t)
        v = -xy[:, 0] * np.sin(t) + xy[:, 1] * np.cos(t)
        dist = np.abs(np.hypot(u / (a / 2), v / (b / 2)) - 1.0) * 0.5 * min(a, b)
        # the points off it (the ends of a chord across a hidden rim, where the hull
        # turns onto the chord) are left out and the ellipse fitted again, while the
        # rest holds at least half of the rim that is seen
        off = dist > 2.5 * ELLIPSE_FIT_PX
        if not off.any() or len(pts) - np.count_nonzero(off) < 0.5 * n_seen:
            break
        pts = pts[~off]
    if (np.median(dist) > ELLIPSE_FIT_PX or np.percentile(dist, 90) > 2.5 * ELLIPSE_FIT_PX
            or max(a, b) > MAX_AXIS_RATIO * min(a, b)):
        return none
    out = np.zeros_like(lit)
    cv2.ellipse(out, ((cx, cy), (a, b), angle), 1, thickness=-1)
    # the ellipse continues the rim: the lit zone lies inside it (one fitted to the few
    # rim points a band's straight rims leave cuts the band's ends off), or what it adds
    # is a held contact (a fit continued to where the frame cuts the zone may run a few px
    # inside the zone there)
    grown = cv2.dilate(out, np.ones((5, 5), np.uint8))
    if (np.count_nonzero(lit & ~grown) > LIT_OUTSIDE_ELLIPSE * np.count_nonzero(lit)
            and not (image is not None and seen is not None
                     and _adds_lit(image, seen, out, hull))):
        return none
    return out


#: Pixels (working image) the continuation must add, and the outside must keep, for the
#: test of :func:`_adds_lit`.
MIN_TEST_PX = 50

#: Lit pixels (working image) beyond the hull that show light through a held contact's
#: gaps (:func:`_adds_lit`): a 3 x 3 block, more than a noise pixel leaves after the
#: median of 5 and the 1.5 px Gaussian of step 1.
MIN_SEEN_PX = 9


def _adds_lit(image: np.ndarray, seen: np.ndarray, ellipse: np.ndarray,
              hull: np.ndarray) -> bool:
    """Whether what the ellipse adds to the hull is a contact held over the rim, not the
    unlit outside (a band's ends cut by an ellipse through its few curved rim points) or a
    rim's half-shadow (a vignetted band's, beyond its straight rim).

    Both must hold:

    * light shows through the contact's gaps: at least :data:`MIN_SEEN_PX` of the added
      pixels pass the zone's own lit test `seen` (specks too small to be kept as lit
      regions; a half-shadow or the outside lies below the test everywhere);
    * the added pixels' median grey lies above the 90th percentile of the outside (beyond
      both, by the working image's smoothing and more, 4 px): the added region is not
      drawn from the outside's grey values.
    """
    added = (ellipse > 0) & (hull == 0)
    if np.count_nonzero(added & (seen > 0)) < MIN_SEEN_PX:
        return False
    outside = cv2.dilate(ellipse | hull, np.ones((9, 9), np.uint8)) == 0
    if np.count_nonzero(added) < MIN_TEST_PX or np.count_nonzero(outside) < MIN_TEST_PX:
        return False
    return float(np.median(image[added])) > float(np.percentile(image[outside], 90))


#: A side of the zone's hull longer than this share of the hull's perimeter is a chord
#: across a hidden rim (or a band's straight rim), not the rim of a disc or an ellipse:
#: a digitised ellipse's longest hull side is a few % of its perimeter (measured: 3.5 % for
#: a disc of 65 px radius, 5.3 % for semi-axes 100 x 50 px, 6.5 % for 120 x 40 px).
CHORD_FRACTION = 0.12

#: Rounds of leaving out the rim points off the ellipse and fitting again.
TRIM_ROUNDS = 3

#: Share of the lit zone that may lie more than 2 px outside the ellipse through its rim.
LIT_OUTSIDE_ELLIPSE = 0.002

#: Flattest lit ellipse: a round beam's footprint on the prism face seen at the incidence
#: angle theta has axes 1 : 1 / cos(theta), 2 at the thesis's 60 deg and 2.9 at 70 deg; a
#: flatter fit runs along a band's straight rims (its ends dimmed by vignetting).
MAX_AXIS_RATIO = 3.0


def _chords(hull_edge: np.ndarray) -> np.ndarray:
    """The pixels (bool) within 1 px of the long sides of a hull (its edge, uint8 0/1)."""
    pts = cv2.findNonZero(hull_edge)
    out = np.zeros(hull_edge.shape, np.uint8)
    if pts is None or len(pts) < 3:
        return out.view(bool)
    hull = cv2.convexHull(pts).reshape(-1, 2)
    ends = np.roll(hull, -1, axis=0)
    length = np.hypot(*(ends - hull).T.astype(np.float64))
    for (x0, y0), (x1, y1), n in zip(hull, ends, length, strict=True):
        if n > CHORD_FRACTION * length.sum():
            cv2.line(out, (int(x0), int(y0)), (int(x1), int(y1)), 1, thickness=3)
    return out.view(bool)


def _fill_holes(mask: np.ndarray) -> np.ndarray:
    """`mask` (uint8 0/1) with every background region not reaching the border filled."""
    inverse = (mask == 0).astype(np.uint8)
    _, labels = cv2.connectedComponents(inverse, connectivity=4)
    border = np.unique(np.concatenate([labels[0], labels[-1], labels[:, 0], labels[:, -1]]))
    outside = np.isin(labels, border[border > 0])
    return (~outside).astype(np.uint8)


def lit_zone_from_file(path: str | Path, shape: tuple[int, int]) -> LitZone:
    """A lit zone the user drew: an image file, non-zero where lit, of the frame's size.

    Raises
    ------
    ValueError
        The file cannot be read or its size differs from the frames'.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: the lit-mask image does not exist")
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise ValueError(f"{path}: cannot read the lit-mask image")
    if image.ndim == 3:
        image = image.max(axis=2)
    if image.shape != tuple(shape):
        raise ValueError(f"{path}: lit mask is {image.shape[1]} x {image.shape[0]} px, the "
                         f"footage {shape[1]} x {shape[0]} px")
    mask = image > 0
    width = _rim_width(shape)
    return LitZone(mask, _rim(mask, width), "file", rim_px=width)
