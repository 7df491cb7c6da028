"""Side-view footage: element edges, deflection angle and tip deflection per frame.

A camera beside the track sees the tread block (steel carrier, rubber base, elements) against
a backlight, over the ice slab whose surface line crosses the image (thesis Fig. 4.11 b,
Fig. 5.14). Friction drags each element's tip backwards: the element bends and shears, and
the *deflection angle* is the angle from the vertical (the undeformed element axis) of the
chord from the element's root centre, where it leaves the block base, to the point where its
centreline meets the ice surface (the bottom centre if it does not reach the ice), positive
trailing. The *tip deflection* is the trailing displacement of the bottom centre relative to
the root.

Input
-----
``d``, the darkness image with the rubber positive: ``darkness(frame, reference)`` of
:mod:`tir_contact.flatfield` when frames without the block give a reference (fixed camera),
or :func:`side_darkness` without one (a camera that follows the block). Background and ice
are about 0 in ``d``, the rubber is the largest level (0.92 for dark rubber on the default
backlight, 7.5 for bright rubber on a dark background), the steel carrier lies between.

Method
------
1. *Presence and scale.* Pixels with ``d > min_darkness`` hold the block; the rubber level
   is the median of the upper class (above 0.8 times their 95th percentile). Without such
   pixels the frame has no block. ``n = d / level`` is then 1 on rubber, 0 on background
   and ice, about 0.55-0.65 on the carrier.
2. *Vertical layout.* The rows holding rubber (``n > 0.75``, which leaves the carrier out)
   form one band from the underside of the carrier down to the ice surface line (the ice,
   in front, hides the rest); a band lower than 0.75 element heights is no block (e.g. only
   the carrier's overhang in view). The top rows of the band are the block base, whose ends
   give the leading face of the block and tell which block end lies inside the image.
3. *Edges.* In every band row (all rows at once) the runs with ``n > 0.5`` are found; each
   run edge is placed from the two pixels straddling half contrast, whose summed coverage
   locates an area-sampled step exactly (``x = p + 1.5 - S`` for a rising edge between
   pixels ``p`` and ``p + 1``). Below the base each run is one element; runs are counted
   from the block end inside the image, which with the element lengths indexes the
   elements (element 0 leads). A run too wide for its element (two elements touching
   across a closed sipe) drops that row for it and the elements behind it.
4. *Root.* With sipes, the root row is the sipe ground: the covered fraction of the column
   through the top of each sipe gap whose two elements lie inside the image (median over
   the gaps). A block without sipes (G0) has no visible root line: its outline runs
   vertical along the base and kinks where the element starts, so the root row is the
   break point of a continuous piecewise fit (constant above, quadratic below) of both
   outer faces, by least squares over candidate rows. A weak kink leaves the row
   uncertain, but then the chord angle hardly depends on it (for a straight element the
   chord slope is the face slope).
5. *Centreline fit.* Both faces of all elements are fitted at once with cubics in the depth
   below the root (the Timoshenko centreline of a tip-loaded element, Eq. 5.15/5.16, is a
   cubic), first on the upper 70 % of each element; rows further down where a face leaves
   its fit by more than ``max(0.35 px, 4 x RMS)`` end the side faces (the lifted trailing
   corner of a tilted bottom face), and the fit is repeated above them. The centreline is
   the mean of the two face fits (the midpoint of the faces in one row is the centreline
   to second order in the cross-section rotation). ``edge_fit_rms_px`` is the RMS
   residual of both faces.
6. *End point.* Walking down the fitted centreline (five columns around it averaged), the
   covered fraction of each row gives the lower end of the rubber: where the ice surface
   hides the element, or the bottom centre of a lifted element. The ice line is the
   median of the lowest ends (within 1 px of the deepest), or ``ice_y_px`` when given; an
   element ending more than 0.4 px above it is lifted and ends at its measured bottom
   centre, the others end at the ice line.
7. *Angle and tip.* ``deflection_angle_deg = atan2(x_end - x_root, y_end - y_root)`` with
   ``x`` positive trailing. The bottom centre of an element pressed into the ice is hidden:
   the tip deflection extrapolates the fitted centreline to the depth at which its arc
   length equals the element height (an inextensible centreline); a lifted element's tip
   is its visible bottom centre.

Per-frame values (``SIDE_FRAME_COLUMNS``) are means over the elements measured.

Accuracy and speed on the synthetic footage (default camera with noise, blur, uneven light;
G0, G3, G7 at 1 and 3 m/s, ``tests/test_side.py``): median angle errors 0.004-0.06 deg,
tip deflection errors below 0.005 mm; about 1.5-2 ms per 640 x 256 frame on a shared
2-core machine (0.3 ms more for the darkness with a reference, 2 ms without one).

Limits
------
* The scene must be level (ice line along the image rows within a fraction of a pixel
  over the element, i.e. camera rotation << 1 deg); rotation is not corrected.
* Elements whose edges touch the image border (or an invalid pixel) are partly outside:
  they are listed with NaN values, as are all elements in view when no sipe ground
  between two elements inside the image is seen (the root row is unknown then). When
  neither end of the block base is in view the elements cannot be indexed: none is listed.
  A block showing only a sliver of a few pixels counts as not in view.
* The base must be at least about 0.6 mm (6 px at 0.1 mm/px) thick, and sipes at least
  about 2 px wide where they are narrowest, so that the gaps reach background level.
* The mixed pixel at the ice line reads more or less than its covered fraction in ``d``
  when the ice level differs from the backlight (the reference there mixes both): the
  ice line estimated from ``d`` is biased by up to about 0.25 px (0.5 % of a 6 mm element
  at 0.1 mm/px, 0.1 deg at 24 deg); ``ice_y_px`` from the reference image avoids it.
* An element lifted by less than 0.4 px counts as reaching the ice: its chord ends at the
  ice line and its tip is extrapolated (G7 at 1 m/s is lifted by 0.5 px: 0.05 deg and
  0.03 mm either way).
* Without sipes, the root row comes from the outline kink (step 4), uncertain by a few
  rows when the deflection is about one pixel; the angle error stays below about 0.05 deg
  on G0.

Coordinates: image x to the right and y down. Internally and in ``edges`` / ``lines``
positions are in pixel index coordinates (the centre of pixel ``(r, c)`` is ``x = c``,
``y = r``); millimetre outputs are measured from the left image edge, ``x_mm = (x + 0.5)
mm_per_px``, as in ``ground_truth.csv``.
"""

from __future__ import annotations

import itertools
import logging
import math
from dataclasses import dataclass, field
from typing import Protocol

import cv2
import numpy as np
import pandas as pd

from tir_contact.flatfield import Reference, darkness

__all__ = [
    "SIDE_ELEMENT_COLUMNS",
    "SIDE_FRAME_COLUMNS",
    "ElementEdges",
    "SideFeatures",
    "SideLayoutLike",
    "block_span_px",
    "ice_line_y_px",
    "side_darkness",
    "side_frame_features",
]

logger = logging.getLogger(__name__)

#: Per-frame columns: block values are means over the elements measured.
SIDE_FRAME_COLUMNS = [
    "block_in_view",
    "block_front_x_mm",
    "n_elements_in_view",
    "deflection_angle_deg",
    "tip_deflection_mm",
]
#: Per-element columns (element 0 leads).
SIDE_ELEMENT_COLUMNS = [
    "element",
    "deflection_angle_deg",
    "tip_deflection_mm",
    "root_x_mm",
    "tip_x_mm",
    "edge_fit_rms_px",
]

#: Rubber above this fraction of its level (the carrier, ~0.55-0.65, stays below).
_RUBBER_ONLY = 0.75
#: Rows below the band top taken as the block base (base >= ~0.6 mm at 0.1 mm/px).
_BASE_ROWS = (2, 6)
#: Smallest residual tolerance of the side-face test, px.
_MIN_TOL_PX = 0.35
#: Fraction of the element's rows used for the first fit (above any lifted corner).
_UPPER_FRACTION = 0.7
#: An element ending this far above the ice line (px) is lifted off the ice.
_LIFT_PX = 0.4


class SideLayoutLike(Protocol):
    """What :func:`side_frame_features` reads of the block layout (duck-typed).

    ``tir_contact.features.BlockLayout`` provides it; any object with these attributes does.
    """

    mm_per_px: float
    sliding_direction: str
    element_lengths_mm: tuple[float, ...] | None
    sipe_width_mm: float
    height_mm: float | None


@dataclass(frozen=True)
class ElementEdges:
    """Fitted outline of one element, pixel index coordinates (for overlays).

    Attributes
    ----------
    element : int
        Element index (0 leads).
    leading, trailing : (k, 2) ndarray
        Fitted leading and trailing faces as polylines ``(x, y)`` from the root row down to
        the lowest row each face was fitted on.
    chord : (2, 2) ndarray
        Root centre and end point ``(x, y)`` of the chord whose angle is reported.
    """

    element: int
    leading: np.ndarray
    trailing: np.ndarray
    chord: np.ndarray


@dataclass(frozen=True)
class SideFeatures:
    """Side-view measurements of one frame.

    Attributes
    ----------
    frame : dict
        Keys :data:`SIDE_FRAME_COLUMNS`; ``block_in_view`` False and NaN values without
        the block.
    elements : pandas.DataFrame
        Columns :data:`SIDE_ELEMENT_COLUMNS`, one row per element in view (rubber of it
        seen, or its root inside the image), element 0 (leading) first; NaN values for
        elements that cannot be measured (partly outside the image, root row unknown).
    edges : tuple of ElementEdges
        Fitted faces and chords of the measured elements (pixel index coordinates).
    root_y_px : float
        Row of the element roots (sipe ground or outline kink), NaN without the block.
    ice_y_px : float
        Row of the ice surface line, NaN when unknown.
    """

    frame: dict
    elements: pd.DataFrame
    edges: tuple[ElementEdges, ...] = field(default=())
    root_y_px: float = math.nan
    ice_y_px: float = math.nan

    @property
    def lines(self) -> dict[int, tuple[tuple[float, float], tuple[float, float]]]:
        """Chord of every measured element: ``{element: ((x_root, y_root), (x_end, y_end))}``,
        pixel index coordinates."""
        return {
            e.element: (
                (float(e.chord[0, 0]), float(e.chord[0, 1])),
                (float(e.chord[1, 0]), float(e.chord[1, 1])),
            )
            for e in self.edges
        }


def _check_contact_is(contact_is: str) -> None:
    if contact_is not in ("dark", "bright"):
        raise ValueError(f"contact_is must be 'dark' or 'bright', got contact_is={contact_is!r}")


def _check_image(name: str, image: np.ndarray) -> np.ndarray:
    arr = np.asarray(image)
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D (M, N) grey image, got shape {arr.shape}")
    if arr.shape[0] < 8 or arr.shape[1] < 8:
        raise ValueError(f"{name} must be at least 8 x 8 px, got shape {arr.shape}")
    return arr


def _row_levels(img: np.ndarray, contact_is: str) -> np.ndarray:
    """Per-row level of background and ice (the block is the minority of each row)."""
    q = 75.0 if contact_is == "dark" else 25.0
    step = max(1, img.shape[1] // 160)
    return np.percentile(img[:, ::step], q, axis=1)


#: A row whose darkest and brightest pixels (5th and 99th percentile) differ by more than
#: this share of the brighter is two-toned (rubber and backlight): its background is the
#: median of its brighter class, however much of the row the block covers.
_TWO_TONED = 0.5


def _background_levels(img: np.ndarray, contact_is: str) -> np.ndarray:
    """Per-row level of the background (backlight, holder, ice) behind a side view's block.

    Each row's level is its 75th percentile (25th for bright rubber, :func:`_row_levels`),
    which is background while the block covers less than a quarter of the row. A row that
    holds rubber and backlight is two-toned (:data:`_TWO_TONED`): its level is at least
    (bright rubber: at most) the median of the pixels on the background's side of the
    midpoint between its 5th and 99th percentile, which holds while any backlight shows
    beside the block (a block spanning 90 % of the width, a holder plate across the whole
    frame above it). Rows without rubber (a plate or carriage across the width, the ice,
    the backlight alone) keep the percentile.
    """
    step = max(1, img.shape[1] // 160)
    sub = img[:, ::step].astype(np.float32)
    lo, hi = np.percentile(sub, [5.0, 99.0], axis=1)
    levels = _row_levels(img, contact_is)
    two = hi - lo > _TWO_TONED * np.maximum(hi, 1e-6)
    if not two.any():
        return levels
    mid = 0.5 * (lo + hi)[two, None]
    rows = sub[two]
    side = rows > mid if contact_is == "dark" else rows < mid
    cls = np.nanmedian(np.where(side, rows, np.nan), axis=1)
    # the percentile stands while it lies in the background's class beyond its median
    # (the block covers under half the row): the same numbers as before for such rows
    levels[two] = (np.maximum if contact_is == "dark" else np.minimum)(levels[two], cls)
    return levels


#: The ice line is the lowest step of the row levels at least this share of the strongest
#: (a holder plate across the frame above the block steps more than the ice surface).
_ICE_STEP_SHARE = 0.5


def _step_crossing(profile: np.ndarray) -> float:
    """Sub-pixel position (index coordinates) of the lowest step (highest index) of a 1-D
    profile that is at least :data:`_ICE_STEP_SHARE` of its strongest."""
    n = profile.shape[0]
    grad = np.zeros(n)
    grad[2:-2] = profile[4:] - profile[:-4]
    mag = np.abs(grad)
    r = int(np.argmax(mag))
    peak = (mag >= _ICE_STEP_SHARE * mag[r]) & (mag >= np.roll(mag, 1)) & (
        mag >= np.roll(mag, -1))
    r = max(r, int(np.flatnonzero(peak)[-1]))
    lo_a, lo_b = max(r - 8, 0), max(r - 3, 1)
    hi_a, hi_b = min(r + 4, n - 1), min(r + 9, n)
    above = float(np.median(profile[lo_a:lo_b]))
    below = float(np.median(profile[hi_a:hi_b]))
    if above == below:
        return float(r)
    a, b = max(r - 3, 0), min(r + 4, n)
    frac = np.clip((profile[a:b] - below) / (above - below), 0.0, 1.0)
    # Rows a..b-1 straddle the step; a full row above counts 1: the step lies at the top
    # edge of row a plus the covered rows, minus half a pixel for index coordinates.
    return float(a + frac.sum() - 0.5)


def ice_line_y_px(image: np.ndarray, *, contact_is: str = "dark") -> float:
    """Row of the ice surface line in a raw side-view frame or reference image.

    The per-row level of the background and ice (a percentile over the columns that
    ignores the block) steps at the ice surface; the line is the half-level crossing of
    that step, with the mixed row counted by its level (sub-pixel). The ice lies below
    everything else: of the steps at least half as strong as the strongest (a holder
    plate across the frame steps more), the lowest is taken.

    Parameters
    ----------
    image : (M, N) ndarray
        Grey frame or reference image (any dtype).
    contact_is : {"dark", "bright"}
        Polarity of the rubber (dark rubber on a bright backlight, or bright on dark).

    Returns
    -------
    float
        Ice surface row, pixel index coordinates (the centre of row r is r).

    Examples
    --------
    >>> img = np.full((40, 30), 200.0)
    >>> img[30:] = 120.0
    >>> img[29] = 160.0   # the line crosses row 29 at its middle
    >>> round(ice_line_y_px(img), 3)
    29.0
    """
    _check_contact_is(contact_is)
    img = _check_image("image", image).astype(np.float32)
    return _step_crossing(_row_levels(img, contact_is))


def ice_line_tilt_deg(image: np.ndarray, *, contact_is: str = "dark",
                      n_strips: int = 16, tolerance_px: float = 1.5) -> float:
    """Tilt of the ice surface line against the image rows, deg (positive: falling to the
    right, i.e. the scene turned from +x towards +y).

    The image is cut into `n_strips` column strips; in each, the ice line is found as in
    :func:`ice_line_y_px`. Strips in which the level above that step is not the backlight
    (the block covers them) are left out. The line through two strips' rows that the most
    strips agree with (within `tolerance_px`) is refined by least squares over those strips.

    Returns
    -------
    float
        The tilt, deg; NaN when fewer than 4 strips agree.

    Examples
    --------
    >>> yy, xx = np.mgrid[:120, :300].astype(float)
    >>> line = 80 + np.tan(np.radians(3.0)) * (xx - 150)   # area-sampled step: 200 to 120
    >>> img = 200.0 - 80.0 * np.clip(yy + 0.5 - line, 0.0, 1.0)
    >>> round(ice_line_tilt_deg(img), 1)
    3.0
    """
    _check_contact_is(contact_is)
    img = _check_image("image", image).astype(np.float32)
    h, w = img.shape
    # the backlight and ice levels of the whole image: a strip counts only where the level
    # above its step is the backlight (under the block it is the rubber, and the step there
    # is the rubber's lower edge, not the ice line)
    whole = _row_levels(img, contact_is)
    y_all = _step_crossing(whole)
    back = float(np.median(whole[: max(1, int(y_all) - 3)]))
    ice = float(np.median(whole[min(h - 1, int(y_all) + 4):]))
    edges = np.linspace(0, w, n_strips + 1).round().astype(int)
    xs, ys = [], []
    for a, b in itertools.pairwise(edges):
        if b - a >= 2:
            prof = _row_levels(img[:, a:b], contact_is)
            y = _step_crossing(prof)
            above = float(np.median(prof[max(0, int(y) - 10): max(1, int(y) - 3)]))
            if abs(above - back) <= 0.25 * abs(back - ice):
                xs.append(0.5 * (a + b - 1))
                ys.append(y)
    if len(xs) < 4:
        return math.nan
    x, y = np.array(xs), np.array(ys)
    best = np.zeros(len(x), bool)
    for i, j in itertools.combinations(range(len(x)), 2):
        slope = (y[j] - y[i]) / (x[j] - x[i])
        inl = np.abs(y - (y[i] + slope * (x - x[i]))) <= tolerance_px
        if inl.sum() > best.sum():
            best = inl
    if best.sum() < 4:
        return math.nan
    slope = np.polyfit(x[best], y[best], 1)[0]
    return float(np.degrees(np.arctan(slope)))


def level_image(image: np.ndarray, tilt_deg: float, *, border: float = 0.0) -> np.ndarray:
    """`image` turned by `tilt_deg` about its centre so that a line of that tilt becomes a
    row (float32; pixels from outside the image take `border`)."""
    h, w = image.shape
    m = cv2.getRotationMatrix2D(((w - 1) / 2.0, (h - 1) / 2.0), tilt_deg, 1.0)
    return cv2.warpAffine(np.asarray(image, np.float32), m, (w, h), flags=cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_CONSTANT, borderValue=float(border))


def _illumination_shape(img: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """Smooth illumination shape along the rows from the background and ice pixels.

    The illumination is a gradient times a vignetting, ``(1 + g x)(1 - v r^2)``: within
    the per-row normalisation the terms ``x^a y^b`` (a = 1..3, b = 0..2) reproduce it. The
    fit uses the pixels within 15 % of their row level on a grid of about 32 x 64.
    """
    h, w = img.shape
    sy, sx = max(1, h // 32), max(1, w // 64)
    sub = img[::sy, ::sx] / np.maximum(levels[::sy, None], 1e-6)
    xs = (np.arange(0, w, sx) + 0.5) / w - 0.5
    ys = (np.arange(0, h, sy) + 0.5) / h - 0.5
    ok = np.abs(sub - 1.0) < 0.15
    yy, xx = np.broadcast_arrays(ys[:, None], xs[None, :])
    x, y, z = xx[ok], yy[ok], sub[ok] - 1.0
    pw = [(a, b) for b in range(3) for a in range(1, 4)]
    if x.size < 8 * len(pw):
        return np.ones_like(img, dtype=np.float32)
    xp, yp = [np.ones_like(x), x, x * x, x * x * x], [np.ones_like(y), y, y * y]
    a_mat = np.stack([xp[a] * yp[b] for a, b in pw], axis=1)
    coef = np.linalg.solve(a_mat.T @ a_mat + 1e-9 * np.eye(len(pw)), a_mat.T @ z)
    xf = (np.arange(w) + 0.5) / w - 0.5
    yf = (np.arange(h) + 0.5) / h - 0.5
    # separable evaluation: sum over b of y^b times a polynomial in x
    out = np.ones((h, w), dtype=np.float32)
    for b in range(3):
        px_b = sum(c * xf**a for c, (a, bb) in zip(coef, pw, strict=True) if bb == b)
        out += (yf[:, None] ** b * px_b[None, :]).astype(np.float32)
    return out


def side_darkness(
    frame: np.ndarray, *, contact_is: str = "dark", reference: Reference | None = None
) -> np.ndarray:
    """Darkness of a side-view frame, rubber positive, with or without a clean reference.

    With ``reference`` (frames without the block, fixed camera) this is
    :func:`tir_contact.flatfield.darkness`. Without one (a camera that follows the block,
    which never leaves the image) the background is estimated from the frame itself: each
    row's level of backlight or ice is a percentile over the columns (75th for dark rubber,
    25th for bright), refined by a smooth illumination shape fitted to the pixels within
    15 % of their row level, so ``d = 1 - I / B`` (dark) or ``I / B - 1`` (bright).

    Parameters
    ----------
    frame : (M, N) ndarray
        Grey frame.
    contact_is : {"dark", "bright"}
        Dark rubber on a bright backlight, or bright rubber on a dark background.
    reference : Reference, optional
        Block-free reference image.

    Returns
    -------
    (M, N) ndarray of float32
        About 0 on backlight and ice, the rubber's contrast on rubber.

    Notes
    -----
    The self-referenced estimate needs every row to be mostly free of the block (the
    block spans less than about half the image width).

    Examples
    --------
    >>> img = np.full((16, 40), 200.0)
    >>> img[4:10, 10:20] = 20.0
    >>> d = side_darkness(img)
    >>> round(float(d[5, 12]), 3), round(float(d[2, 2]), 3)
    (0.9, 0.0)
    """
    _check_contact_is(contact_is)
    img = _check_image("frame", frame)
    if reference is not None:
        return darkness(img, reference, contact_is=contact_is)
    img = img.astype(np.float32)
    levels = _background_levels(img, contact_is)
    shape = _illumination_shape(img, levels)
    levels = _background_levels(img / shape, contact_is)
    bg = np.maximum(shape * levels[:, None].astype(np.float32), np.float32(1e-6))
    ratio = img / bg
    d = 1.0 - ratio if contact_is == "dark" else ratio - 1.0
    return d.astype(np.float32)


#: Darkness level below which :func:`block_span_px` sees no rubber: dark rubber reflects
#: under a quarter of the backlight (0.92 in the renders), dust and bubbles remove at most
#: about a third of the light, a steel holder 0.6.
_RUBBER_LEVEL = 0.7


def block_span_px(
    frame: np.ndarray, *, contact_is: str = "dark", min_darkness: float = 0.3
) -> tuple[float, float] | None:
    """Left and right end (columns) of the block base in a side-view frame, or None.

    The frame is normalised by its own background (:func:`side_darkness`); the rubber is
    darkness above half its level (as in :func:`side_frame_features`; no rubber when that
    level is under :data:`_RUBBER_LEVEL`, 3 x 3 specks dropped), and the block base
    is the rows holding the most rubber: the rigid part of the block between its holder and
    the elements, as long as the block (the carrier, the holder plate and the carriage
    above it read as less than rubber or as background). An end at the image border is
    NaN (it may lie outside).

    Returns
    -------
    (float, float) or None
        Median over the base rows of the first and last rubber column; None when the frame
        shows no rubber.

    Examples
    --------
    >>> img = np.full((40, 80), 200.0)
    >>> img[10:14, 20:60] = 15.0            # base
    >>> img[14:30, 20:28] = img[14:30, 40:48] = 15.0   # two elements
    >>> block_span_px(img)
    (20.0, 59.0)
    """
    d = side_darkness(frame, contact_is=contact_is)
    hi = d[d > min_darkness]
    if hi.size < 8:
        return None
    p95 = float(np.percentile(hi, 95))
    level = float(np.median(hi[hi > 0.8 * p95]))
    if level < _RUBBER_LEVEL:
        return None  # dust, bubbles or steel: nothing as dark as rubber
    # a 3 x 3 opening drops specks and one-pixel lines; the block is a region
    rubber = cv2.morphologyEx((d > 0.5 * level).astype(np.uint8), cv2.MORPH_OPEN,
                              np.ones((3, 3), np.uint8)).astype(bool)
    count = rubber.sum(axis=1)
    if count.max() < 3:
        return None
    rows = np.nonzero(count >= 0.9 * count.max())[0]
    cols = [np.nonzero(rubber[r])[0] for r in rows]
    left = float(np.median([c[0] for c in cols]))
    right = float(np.median([c[-1] for c in cols]))
    w = d.shape[1]
    return (math.nan if left <= 0 else left, math.nan if right >= w - 1 else right)


def _empty(listed: np.ndarray | None = None) -> SideFeatures:
    """Features of a frame without measurements: no block, or ``listed`` elements in view
    that cannot be measured (NaN rows)."""
    el = np.zeros(0, np.int64) if listed is None else np.asarray(listed, dtype=np.int64)
    frame = {
        "block_in_view": bool(el.size > 0),
        "block_front_x_mm": math.nan,
        "n_elements_in_view": int(el.size),
        "deflection_angle_deg": math.nan,
        "tip_deflection_mm": math.nan,
    }
    table = pd.DataFrame(
        {"element": el, **{c: np.full(el.size, np.nan) for c in SIDE_ELEMENT_COLUMNS[1:]}}
    )
    return SideFeatures(frame, table)


@dataclass(frozen=True)
class _Runs:
    """Rubber runs of every row of the band: row, edges (index coordinates), cut flags."""

    row: np.ndarray
    left: np.ndarray
    right: np.ndarray
    cut_left: np.ndarray
    cut_right: np.ndarray


def _runs(n: np.ndarray, ok: np.ndarray) -> _Runs:
    """Half-contrast runs of every row, edges placed from the two straddling pixels.

    For an area-sampled step from level ``b`` to ``r`` the two pixels ``p, p + 1`` that
    straddle the half level hold the whole transition, and their summed coverage
    ``S = sum (n - b) / (r - b)`` places it exactly: a rising edge at ``x = p + 1.5 - S``,
    a falling one at ``x = p + S - 0.5`` (index coordinates). ``b`` and ``r`` are the
    pixels just outside the pair (this removes a local shading such as a dust shadow on
    the background); where those are not plain background and rubber (another edge close
    by) the nominal levels 0 and 1 are used.
    """
    rows, w = n.shape
    b = np.zeros((rows, w + 2), dtype=bool)
    b[:, 1:-1] = n > 0.5
    okp = np.zeros((rows, w + 2), dtype=bool)
    okp[:, 1:-1] = ok
    npad = np.zeros((rows, w + 6), dtype=np.float32)  # original column c at c + 3
    npad[:, 3:-3] = n
    npad[:, :3] = n[:, :1]
    npad[:, -3:] = n[:, -1:]
    # a transition between padded columns j and j + 1 lies between original j - 1 and j
    rr, jr = np.divmod(np.flatnonzero(~b[:, :-1] & b[:, 1:]), w + 1)
    rf, jf = np.divmod(np.flatnonzero(b[:, :-1] & ~b[:, 1:]), w + 1)

    def coverage(r_: np.ndarray, j: np.ndarray, rising: bool) -> np.ndarray:
        # the pair is at npad columns j + 2, j + 3; two pixels outside on either side
        lo, lo2, hi, hi2 = (npad[r_, j + k] for k in (1, 0, 4, 5))
        if not rising:
            lo, lo2, hi, hi2 = hi, hi2, lo, lo2
        plain = (lo < 0.35) & (hi > 0.65) & (np.abs(lo - lo2) < 0.1) & (np.abs(hi - hi2) < 0.1)
        lo, hi = np.where(plain, lo, 0.0), np.where(plain, hi, 1.0)
        return (npad[r_, j + 2] + npad[r_, j + 3] - 2.0 * lo) / (hi - lo)

    p_r, p_f = jr - 1, jf - 1
    left = np.clip(p_r + 1.5 - coverage(rr, jr, True), p_r - 0.5, p_r + 1.5)
    right = np.clip(p_f + coverage(rf, jf, False) - 0.5, p_f - 0.5, p_f + 1.5)
    cut_l = ~okp[rr, jr] | ~okp[rr, jr + 1]
    cut_r = ~okp[rf, jf] | ~okp[rf, jf + 1]
    return _Runs(rr, left.astype(float), right.astype(float), cut_l, cut_r)


def _batched_cubic(
    e: np.ndarray, s: np.ndarray, x: np.ndarray, w: np.ndarray, n_el: int
) -> np.ndarray:
    """Weighted least-squares cubics in ``s`` for every element at once.

    ``e`` element of each sample, ``s`` scaled depth (0 to 1), ``x`` (k, 2) left and right
    edges, ``w`` sample weights (0 or 1). Returns coefficients (n_el, 4, 2), low order
    first; the normal equations are solved with a tiny ridge for elements with few rows.
    """
    pw = s[:, None] ** np.arange(7)[None, :]  # (k, 7)
    mom = np.stack([np.bincount(e, weights=w * pw[:, k], minlength=n_el) for k in range(7)], 1)
    ata = mom[:, _HANKEL]  # (n_el, 4, 4)
    ata = ata + 1e-9 * np.eye(4)[None]
    atb = np.stack(
        [
            np.stack(
                [np.bincount(e, weights=w * x[:, j] * pw[:, k], minlength=n_el) for k in range(4)],
                1,
            )
            for j in range(2)
        ],
        2,
    )  # (n_el, 4, 2)
    return np.linalg.solve(ata, atb)


#: Index of the moment sum s^(i+j) in the normal matrix of a cubic.
_HANKEL = np.add.outer(np.arange(4), np.arange(4))


def _hinge_root(faces: list[tuple[np.ndarray, np.ndarray]], lo: float, hi: float) -> float:
    """Row of the kink between the vertical base faces and the elements below them.

    The faces share the break row ``y_r``: ``x = a`` above it and ``x = a + b h + c h^2``
    below (``h = y - y_r``). Candidates every 2 px, then every 0.25 px around the best;
    the least summed squared residual is refined by a parabola through its neighbours.
    """
    if not faces or hi - lo < 4.0:
        return math.nan

    def sse(cands: np.ndarray) -> np.ndarray:
        out = np.zeros(cands.size)
        for y, x in faces:
            hh = np.maximum(y[None, :] - cands[:, None], 0.0)  # (K, R)
            m = [np.full(cands.size, float(y.size))] + [
                (hh**k).sum(1) for k in range(1, 5)
            ]
            ata = np.stack([np.stack([m[i + j] for j in range(3)], -1) for i in range(3)], -2)
            atb = np.stack([np.full(cands.size, x.sum()), hh @ x, (hh * hh) @ x], -1)
            coef = np.linalg.solve(ata + 1e-9 * np.eye(3), atb[..., None])[..., 0]
            out += float(x @ x) - (coef * atb).sum(1)
        return out

    coarse = np.arange(lo, hi, 2.0)
    best = float(coarse[int(np.argmin(sse(coarse)))])
    fine = np.arange(max(lo, best - 2.5), min(hi, best + 2.5) + 1e-9, 0.25)
    s = sse(fine)
    k = int(np.argmin(s))
    if 0 < k < fine.size - 1:
        den = s[k - 1] - 2.0 * s[k] + s[k + 1]
        if den > 0:
            return float(fine[k] + 0.125 * (s[k - 1] - s[k + 1]) / den)
    return float(fine[k])


def _sipe_root(n: np.ndarray, runs: _Runs, cand: np.ndarray) -> float:
    """Row of the sipe ground: column profile through the top of the sipe gaps.

    A gap counts when both runs beside it are inside the image and its column has rubber
    (the base) above and background below; the first split rows with such gaps decide.
    """
    for split_row in cand[:8].tolist():
        sel = np.nonzero(runs.row == split_row + 1)[0]
        a, b = split_row - 3, min(split_row + 3, n.shape[0])
        if a < 0:
            continue
        tops = []
        for k0, k1 in itertools.pairwise(sel):
            if (runs.cut_left[k0] or runs.cut_right[k0] or runs.cut_left[k1]
                    or runs.cut_right[k1]):
                continue  # an element beside the gap is partly outside the image
            col = round(0.5 * float(runs.right[k0] + runs.left[k1]))
            prof = n[a:b, col]
            if prof[0] < _RUBBER_ONLY or prof[-1] > 1.0 - _RUBBER_ONLY:
                continue
            tops.append(a + float(np.clip(prof, 0.0, 1.0).sum()) - 0.5)
        if tops:
            return float(np.median(tops))
    return math.nan


def _ends_along_centre(
    n: np.ndarray, centre: np.ndarray, scale: np.ndarray, r_a: np.ndarray, root: float
) -> np.ndarray:
    """Lower end of the rubber along each fitted centreline (index coordinates).

    Five columns around the centreline (interpolated) are averaged per row; from row
    ``r_a`` down, each row counts by its level between the rubber just above ``r_a`` and
    the ice or background in the last rows of ``n`` (area-sampled: the sum is the end).
    """
    h, w = n.shape
    if r_a.size == 0:
        return np.zeros(0)
    r0 = int(max(r_a.min() - 3, 0))
    rows = np.arange(r0, h)
    s = (rows[None, :] - root) / scale[:, None]  # (E, R)
    xc = sum(centre[:, k, None] * s**k for k in range(4))
    xs = np.clip(xc[:, :, None] + np.arange(-2, 3)[None, None, :], 0.0, w - 1.001)
    c0 = xs.astype(np.intp)
    f = xs - c0
    rr = rows[None, :, None]
    v = (n[rr, c0] * (1 - f) + n[rr, c0 + 1] * f).mean(axis=2)  # (E, R)
    rel = rows[None, :] - r_a[:, None]
    above = (rel >= -3) & (rel < 0)
    top = (v * above).sum(1) / np.maximum(above.sum(1), 1)
    bottom = v[:, -2:].mean(1)
    span = top - bottom
    frac = np.clip((v - bottom[:, None]) / np.where(span > 0, span, 1.0)[:, None], -0.5, 1.5)
    end = r_a + (frac * (rel >= 0)).sum(1) - 0.5
    return np.where((span >= 0.5) & (rows.size >= 8), end, np.nan)


def _tip_depths(centre: np.ndarray, scale: np.ndarray, height_px: float) -> np.ndarray:
    """Depth below the root at which each centreline's arc length is the element height."""
    tt = np.linspace(0.0, 1.2 * height_px, 61)
    s = tt[None, :] / scale[:, None]
    slope = (centre[:, 1, None] + 2 * centre[:, 2, None] * s + 3 * centre[:, 3, None] * s**2)
    ds = np.hypot(1.0, slope / scale[:, None])
    arc = np.concatenate(
        [np.zeros((scale.size, 1)), np.cumsum(0.5 * (ds[:, 1:] + ds[:, :-1]) * np.diff(tt), 1)], 1
    )
    k = np.clip((arc < height_px).sum(1), 1, tt.size - 1)  # first sample at or past it
    rows = np.arange(scale.size)
    a0, a1 = arc[rows, k - 1], arc[rows, k]
    return tt[k - 1] + (height_px - a0) / np.maximum(a1 - a0, 1e-12) * (tt[k] - tt[k - 1])


def _cubic(coef: np.ndarray, s: np.ndarray) -> np.ndarray:
    return coef[..., 0] + s * (coef[..., 1] + s * (coef[..., 2] + s * coef[..., 3]))


def _listed_by_geometry(
    lengths: tuple[float, ...], sipe_mm: float, px: float, end_x: float, from_front: bool, w: int
) -> np.ndarray:
    """Elements whose root span overlaps the image (working frame, leading end left)."""
    ell = np.asarray(lengths, dtype=float) / px
    gap = float(sipe_mm) / px
    fronts = np.concatenate([[0.0], np.cumsum(ell[:-1] + gap)])
    total = fronts[-1] + ell[-1]
    edge = end_x + 0.5 if from_front else end_x + 0.5 - total  # pixel-edge coordinates
    lo, hi = edge + fronts, edge + fronts + ell
    return np.nonzero((hi > 0.5) & (lo < w - 0.5))[0]


@dataclass(frozen=True)
class _SideGeometry:
    """What the side view knows of the block, in pixels of the working frame."""

    px: float
    flip: bool  # the block slides right: the image is mirrored to put the leading end left
    lengths: tuple[float, ...] | None
    n_el: int | None
    sipe_mm: float
    height_px: float


def _side_geometry(layout: SideLayoutLike) -> _SideGeometry:
    """Check the layout and read what the side view needs of it."""
    px = float(layout.mm_per_px)
    if not (math.isfinite(px) and px > 0):
        raise ValueError(f"layout.mm_per_px must be a number > 0, got {layout.mm_per_px!r}")
    direction = layout.sliding_direction
    if direction not in ("left", "right"):
        raise ValueError(
            f"layout.sliding_direction must be 'left' or 'right', got {direction!r}"
        )
    lengths = layout.element_lengths_mm
    h_mm = getattr(layout, "height_mm", None)
    return _SideGeometry(
        px=px,
        flip=direction == "right",
        lengths=lengths,
        n_el=len(lengths) if lengths is not None else None,
        sipe_mm=float(getattr(layout, "sipe_width_mm", 0.0) or 0.0),
        height_px=float(h_mm) / px if h_mm else math.nan,
    )


def _working_image(
    d: np.ndarray, valid: np.ndarray | None, flip: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Darkness (0 where unusable) and the usable pixels, leading end on the left."""
    arr = _check_image("d", d).astype(np.float32, copy=False)
    ok = np.isfinite(arr)
    if valid is not None:
        valid = np.asarray(valid, dtype=bool)
        if valid.shape != arr.shape:
            raise ValueError(f"valid has shape {valid.shape}, expected {arr.shape} as d")
        ok &= valid
    if not ok.all():
        arr = np.where(ok, arr, np.float32(0.0))
    if flip:  # x grows towards the trailing side
        arr, ok = arr[:, ::-1], ok[:, ::-1]
    return arr, ok


@dataclass(frozen=True)
class _Band:
    """The rubber band (carrier underside down to the ice) in the working frame.

    ``n`` is the darkness over the rubber level in the band rows (and a few ice rows below)
    and the block's columns; ``runs`` its half-contrast runs; per run, ``order`` counts the
    runs of its row from the left and ``from_right`` from the right.
    """

    n: np.ndarray
    runs: _Runs
    top: int
    nrow: int
    c0: int
    w: int
    per_row: np.ndarray
    order: np.ndarray
    from_right: np.ndarray

    def to_mm(self, x: np.ndarray | float, geo: _SideGeometry) -> np.ndarray | float:
        """Band-window x (index coordinates) to image mm from the left edge."""
        xi = x + self.c0
        return ((self.w - 1 - xi if geo.flip else xi) + 0.5) * geo.px


def _rubber_band(
    arr: np.ndarray, ok: np.ndarray, geo: _SideGeometry, min_darkness: float
) -> _Band | None:
    """Steps 1 and 2: the rubber level, the band of rows holding rubber, its runs."""
    h, w = arr.shape
    sub = arr[::3, ::3]
    hi = sub[sub > min_darkness]
    if hi.size < 8:
        return None
    p95 = float(np.partition(hi, int(0.95 * (hi.size - 1)))[int(0.95 * (hi.size - 1))])
    level = float(np.median(hi[hi > 0.8 * p95]))
    count = (arr > _RUBBER_ONLY * level).view(np.uint8).sum(axis=1, dtype=np.int32)
    peak = int(np.argmax(count))
    inband = count >= max(3, 0.2 * count[peak])
    if not inband[peak]:
        return None
    top, bot = peak, peak
    while top > 0 and inband[top - 1]:
        top -= 1
    while bot < h - 1 and inband[bot + 1]:
        bot += 1
    nrow = bot + 1 - top
    if nrow < max(16, 0.75 * geo.height_px if math.isfinite(geo.height_px) else 0):
        return None  # too low for base plus elements (e.g. only the carrier in view)
    # the block's columns (and 3 px of background either side)
    cols_in = np.nonzero(arr[top : bot + 1].max(axis=0) > 0.5 * level)[0]
    c0, c1 = max(int(cols_in[0]) - 3, 0), min(int(cols_in[-1]) + 4, w)
    n = arr[top : min(bot + 6, h), c0:c1] / np.float32(level)  # a few ice rows below
    runs = _runs(n[:nrow], ok[top : bot + 1, c0:c1])
    rr = runs.row
    per_row = np.bincount(rr, minlength=nrow)
    order = np.arange(rr.size) - np.searchsorted(rr, np.arange(nrow))[rr]
    return _Band(n, runs, top, nrow, c0, w, per_row, order, per_row[rr] - 1 - order)


def _block_end(band: _Band, geo: _SideGeometry) -> tuple[bool, bool, float, np.ndarray] | None:
    """The block base's leading and trailing faces: which is cut, the end in view, and the
    elements whose roots the geometry puts inside the image; None if they cannot be indexed.
    """
    runs, rr = band.runs, band.runs.row
    b0, b1 = _BASE_ROWS
    base = (rr >= b0) & (rr < b1) & (band.per_row[rr] == 1)
    if not base.any():
        return None
    front_cut = bool(runs.cut_left[base].any())
    back_cut = bool(runs.cut_right[base].any())
    if front_cut and (back_cut or geo.n_el is None):
        return None  # neither end in view: the elements cannot be indexed
    end_x = float(np.median(runs.right[base] if front_cut else runs.left[base]))
    listed = (
        _listed_by_geometry(geo.lengths, geo.sipe_mm, geo.px, end_x + band.c0, not front_cut,
                            band.w)
        if geo.lengths is not None
        else np.zeros(0, dtype=np.int64)
    )
    return front_cut, back_cut, end_x, listed


def _root_row(band: _Band, geo: _SideGeometry, front_cut: bool, back_cut: bool) -> float:
    """Steps 3 and 4: the root row from the sipe ground, else the kink of the outer faces."""
    runs, rr, per_row, nrow = band.runs, band.runs.row, band.per_row, band.nrow
    b0, b1 = _BASE_ROWS
    split = per_row >= 2
    split[:b1] = False
    cand = np.nonzero(split[:-2] & split[1:-1] & split[2:])[0]
    single = geo.n_el == 1 or (geo.n_el is None and cand.size == 0)
    if not single:
        return _sipe_root(band.n, runs, cand) if cand.size else math.nan
    if front_cut or back_cut:
        return math.nan  # the only element is partly outside the image
    inner = (rr >= b0) & (rr < nrow - 1) & (per_row[rr] == 1)
    return _hinge_root(
        [(rr[inner].astype(float), runs.left[inner]),
         (rr[inner].astype(float), runs.right[inner])],
        float(b1),
        nrow - 8.0,
    )


def _elements_without_root(band: _Band, geo: _SideGeometry, front_cut: bool,
                           listed: np.ndarray) -> SideFeatures:
    """No sipe ground between two elements inside the image (or a partial single element):
    the elements in view are listed without values."""
    logger.debug("side view: root row not found, elements listed without values")
    seen = np.unique((geo.n_el - 1 - band.from_right) if front_cut else band.order)
    if geo.n_el is None:
        return _empty(seen)
    seen = seen[(seen >= 0) & (seen < geo.n_el)]
    return _empty(np.union1d(listed, seen))


def _element_samples(
    band: _Band, geo: _SideGeometry, root: float, front_cut: bool
) -> tuple[np.ndarray, np.ndarray]:
    """The element index of every run (counted from the block end in view) and the runs
    used for the fits, sorted by element with rows ascending within each element."""
    rr, nrow = band.runs.row, band.nrow
    pos = band.from_right if front_cut else band.order
    idx = geo.n_el - 1 - band.from_right if front_cut else band.order
    usable = (rr > root + 1.0) & (rr < nrow - 1) & (idx >= 0)
    if geo.n_el is not None:
        usable &= idx < geo.n_el
        max_w = np.asarray(geo.lengths, dtype=float) / geo.px * 1.6 + 3.0
        bad = np.zeros(rr.size, dtype=bool)
        bad[usable] = (band.runs.right - band.runs.left)[usable] > max_w[idx[usable]]
        if bad.any():
            spoil = np.full(nrow, np.iinfo(np.int64).max)
            np.minimum.at(spoil, rr[bad], pos[bad])
            usable &= pos < spoil[rr]  # a merged run spoils its row from there on
    sel = np.nonzero(usable)[0]
    sel = sel[np.argsort(idx[sel], kind="stable")]
    return idx, sel


@dataclass(frozen=True)
class _FaceFits:
    """Cubic fits of both faces of every element, in ``s = (row - root) / scale``."""

    coef: np.ndarray  # (E, 4, 2): leading and trailing face
    centre: np.ndarray  # (E, 4): the centreline
    scale: np.ndarray  # (E,) rows from the root to the element's last sample
    rms: np.ndarray  # (E,) rms residual of the kept rows, px
    s_last: np.ndarray  # (E,) s of the last kept row
    seen: np.ndarray  # (E,) the element has samples
    fitted: np.ndarray  # element indices with a usable fit


def _fit_faces(band: _Band, root: float, idx: np.ndarray, sel: np.ndarray) -> _FaceFits:
    """Step 5: cubic fits of both faces, the upper part first, then down to the first row
    where a face leaves that fit (a lifted or squeezed lower end)."""
    runs = band.runs
    e_s = idx[sel]
    n_idx = int(e_s[-1]) + 1 if e_s.size else 0
    n_rows = np.bincount(e_s, minlength=n_idx)
    seen = n_rows > 0
    starts = np.concatenate([[0], np.cumsum(n_rows)[:-1]]).astype(np.int64)
    n_cut = np.bincount(e_s, weights=(runs.cut_left | runs.cut_right)[sel], minlength=n_idx)
    fit_ok = (n_rows >= 10) & (n_cut == 0)
    t_s = runs.row[sel] - root
    scale = np.where(seen, t_s[np.maximum(starts + n_rows - 1, 0)] if e_s.size else 1.0, 1.0)
    scale = np.maximum(scale, 1.0)
    s_s = t_s / scale[e_s]
    xs = np.column_stack([runs.left[sel], runs.right[sel]])
    upper = (s_s <= _UPPER_FRACTION).astype(float)
    coef = _batched_cubic(e_s, s_s, xs, upper, n_idx)
    res = xs - _cubic(np.moveaxis(coef[e_s], 2, 1), s_s[:, None])
    ss_u = np.bincount(e_s, weights=upper * (res**2).sum(1), minlength=n_idx)
    rms_u = np.sqrt(ss_u / np.maximum(2 * np.bincount(e_s, weights=upper, minlength=n_idx), 1))
    tol = np.maximum(_MIN_TOL_PX, 4.0 * rms_u)
    off = (np.abs(res) > tol[e_s, None]).any(1) & (upper == 0)
    # keep each element's rows above its first row off the fit
    cum_off = np.concatenate([[0], np.cumsum(off)])
    keep = (cum_off[1:] - cum_off[starts[e_s]] == 0).astype(float)
    coef = _batched_cubic(e_s, s_s, xs, keep, n_idx)
    res = xs - _cubic(np.moveaxis(coef[e_s], 2, 1), s_s[:, None])
    n_keep = np.bincount(e_s, weights=keep, minlength=n_idx)
    rms = np.sqrt(
        np.bincount(e_s, weights=keep * (res**2).sum(1), minlength=n_idx)
        / np.maximum(2 * n_keep, 1)
    )
    last = np.clip(starts + n_keep.astype(np.int64) - 1, 0, max(e_s.size - 1, 0))
    s_last = np.where(n_keep > 0, s_s[last] if e_s.size else 0.0, 0.0)
    fit_ok &= n_keep >= 8
    return _FaceFits(coef, coef.mean(axis=2), scale, rms, s_last, seen, np.nonzero(fit_ok)[0])


def _element_ends(
    band: _Band, fits: _FaceFits, root: float, ice_y_px: float | None
) -> tuple[float, np.ndarray, np.ndarray]:
    """Step 6: the ice line (band rows), which elements are lifted and their end rows."""
    el = fits.fitted
    r_a = np.floor(root + fits.s_last[el] * fits.scale[el]).astype(np.int64) - 1
    ends = _ends_along_centre(band.n, fits.centre[el], fits.scale[el], r_a, root)
    if ice_y_px is not None:
        ice = float(ice_y_px) - band.top
    elif np.isfinite(ends).any():
        fe = ends[np.isfinite(ends)]
        ice = float(np.median(fe[fe > fe.max() - 1.0]))
    else:
        ice = math.nan
    lifted = np.isfinite(ends) & (ends < ice - _LIFT_PX) if math.isfinite(ice) else (
        np.isfinite(ends))
    return ice, lifted, np.where(lifted, ends, ice)


def _chords(
    fits: _FaceFits, root: float, y_end: np.ndarray, lifted: np.ndarray, height_px: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Step 7: chord ends ``x0`` (root), ``x1`` (end), angle (deg) and tip deflection (px)."""
    el = fits.fitted
    centre, scale = fits.centre[el], fits.scale[el]
    t_end = y_end - root
    x0 = centre[:, 0]
    x1 = _cubic(centre, t_end / scale)
    angle = np.degrees(np.arctan2(x1 - x0, t_end))
    if math.isfinite(height_px) and el.size:
        t_tip = np.maximum(_tip_depths(centre, scale, height_px), t_end)
        tip = np.where(lifted, x1 - x0, _cubic(centre, t_tip / scale) - x0)
    else:
        tip = np.where(lifted, x1 - x0, np.nan)
    return x0, x1, angle, tip


def _element_edges(
    band: _Band, geo: _SideGeometry, fits: _FaceFits, root: float, y_end: np.ndarray,
    x0: np.ndarray, x1: np.ndarray, fine: np.ndarray,
) -> tuple[ElementEdges, ...]:
    """Fitted faces and chords of the measured elements in image pixels (for overlays)."""
    el, top, c0 = fits.fitted, band.top, band.c0
    sl = fits.s_last[el][:, None] * np.linspace(0.0, 1.0, 16)[None, :]
    yl = sl * fits.scale[el][:, None] + root + top
    coef = fits.coef
    xf = np.stack([_cubic(coef[el, None, :, 0], sl), _cubic(coef[el, None, :, 1], sl)]) + c0
    cx = np.column_stack([x0, x1]) + c0
    if geo.flip:
        xf, cx = (band.w - 1) - xf, (band.w - 1) - cx
    faces = np.stack([xf, np.broadcast_to(yl, xf.shape)], axis=-1)  # (2, E, 16, 2)
    chords = np.stack([cx, np.column_stack([np.full(el.size, root + top), y_end + top])], -1)
    return tuple(
        ElementEdges(int(el[j]), faces[0, j], faces[1, j], chords[j])
        for j in np.nonzero(fine)[0].tolist()
    )


def side_frame_features(
    d: np.ndarray,
    layout: SideLayoutLike,
    *,
    valid: np.ndarray | None = None,
    ice_y_px: float | None = None,
    min_darkness: float = 0.3,
) -> SideFeatures:
    """Element edges, deflection angles and tip deflections of one side-view frame.

    Parameters
    ----------
    d : (M, N) ndarray
        Darkness image, rubber positive (:func:`side_darkness`); NaN counts as invalid.
    layout : BlockLayout-like
        ``mm_per_px``, ``sliding_direction`` (direction the block moves in the image),
        ``element_lengths_mm`` (element 0 leads; None: elements indexed by their order
        from the leading end), ``sipe_width_mm`` and ``height_mm`` (element height: tip
        deflection of elements pressed into the ice and the least height of the rubber
        band; None gives NaN tips).
    valid : (M, N) ndarray of bool, optional
        False where the image cannot be used; elements whose edges touch such pixels are
        listed with NaN values.
    ice_y_px : float, optional
        Row of the ice surface line (index coordinates), e.g. :func:`ice_line_y_px` of the
        reference image; default: estimated from the element ends.
    min_darkness : float
        Darkness above which a pixel may be block (backlight and ice stay below it).

    Returns
    -------
    SideFeatures

    Notes
    -----
    Angles in degrees from the vertical, positive when the element's lower end trails
    (lies behind its root, against the sliding direction); lengths in mm of the image
    plane; ``root_x_mm``, ``tip_x_mm`` (the chord's lower end) and ``block_front_x_mm``
    (the leading face of the block base) from the left image edge. Method and limits:
    module docstring (its numbered steps are the private functions called here).

    Examples
    --------
    A 4 mm element on a base, its faces tilted 10 deg backwards (the block slides left):

    >>> from types import SimpleNamespace
    >>> lay = SimpleNamespace(mm_per_px=0.1, sliding_direction="left",
    ...                       element_lengths_mm=(4.0,), sipe_width_mm=0.0, height_mm=6.0)
    >>> d = np.zeros((120, 160), np.float32)
    >>> d[20:40, 40:80] = 0.9                                   # base
    >>> yy, xx = np.mgrid[0:120, 0:160] + 0.5
    >>> x0 = 40 + np.tan(np.radians(10.0)) * (yy - 40)           # leading face
    >>> d[(yy > 40) & (yy < 100) & (xx > x0) & (xx < x0 + 40)] = 0.9
    >>> f = side_frame_features(d, lay)
    >>> round(f.frame["deflection_angle_deg"], 1), f.frame["n_elements_in_view"]
    (10.0, 1)
    """
    geo = _side_geometry(layout)
    arr, ok = _working_image(d, valid, geo.flip)
    band = _rubber_band(arr, ok, geo, min_darkness)
    if band is None:
        return _empty()
    end = _block_end(band, geo)
    if end is None:
        return _empty()
    front_cut, back_cut, end_x, listed = end
    root = _root_row(band, geo, front_cut, back_cut)
    if not math.isfinite(root):
        return _elements_without_root(band, geo, front_cut, listed)
    idx, sel = _element_samples(band, geo, root, front_cut)
    fits = _fit_faces(band, root, idx, sel)
    ice, lifted, y_end = _element_ends(band, fits, root, ice_y_px)
    x0, x1, angle, tip = _chords(fits, root, y_end, lifted, geo.height_px)
    el = fits.fitted
    # the table: measured elements, then those seen or expected in view without a value
    all_el = np.union1d(np.union1d(el, np.nonzero(fits.seen)[0]), listed).astype(np.int64)
    k = np.searchsorted(all_el, el)
    cols = {c: np.full(all_el.size, np.nan) for c in SIDE_ELEMENT_COLUMNS[1:]}
    cols["deflection_angle_deg"][k] = angle
    cols["tip_deflection_mm"][k] = tip * geo.px
    cols["root_x_mm"][k] = band.to_mm(x0, geo)
    cols["tip_x_mm"][k] = band.to_mm(x1, geo)
    cols["edge_fit_rms_px"][k] = fits.rms[el]
    table = pd.DataFrame({"element": all_el, **cols})  # columns in SIDE_ELEMENT_COLUMNS order
    fine = np.isfinite(angle)
    in_view = bool(all_el.size > 0)
    frame = {
        "block_in_view": in_view,
        "block_front_x_mm": float(band.to_mm(end_x, geo)) if in_view and not front_cut
        else math.nan,
        "n_elements_in_view": int(all_el.size),
        "deflection_angle_deg": float(angle[fine].mean()) if fine.any() else math.nan,
        "tip_deflection_mm": float(np.nanmean(tip[fine]) * geo.px)
        if np.isfinite(tip[fine]).any()
        else math.nan,
    }
    return SideFeatures(
        frame,
        table,
        _element_edges(band, geo, fits, root, y_end, x0, x1, fine),
        root_y_px=root + band.top,
        ice_y_px=ice + band.top if math.isfinite(ice) else math.nan,
    )
