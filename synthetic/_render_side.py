"""Side view of a sliding tread block (Fig. 4.11 b, Fig. 5.14): deformed elements over the
ice surface line (private helpers of :mod:`synthetic.footage`).

Element shape
-------------
Each element is drawn as a Timoshenko cantilever under a transverse force at its free end
(bending plus shear; the static solution of Eq. 5.15/5.16 with the boundary conditions
Eq. 5.27-5.29 and e = 0): with ``eta = x / d`` from the root,

    rho(eta) = [r (eta^2/2 - eta^3/6) + eta] / (r/3 + 1),   r = 4 kappa (d / l)^2
    psi(eta) = 2 eta - eta^2

``rho`` is the deflection over the tip deflection (``r`` is the ratio of the bending to the
shear compliance, kappa = 6/7, G = E/3), ``psi`` the cross-section rotation (bending only)
over its tip value. The centreline runs from the root centre to the rigid model's bottom
centre ``(tip_x, tip_depth)``: ``(xi, Y) = (root + tip_x rho(eta), eta tip_depth)``; the
cross-sections rotate by ``tilt psi(eta)`` so that the bottom face has the rigid model's
tilt. The two sipe faces are the centreline offset by ``-+ l/2`` along the rotated
cross-section. The ice (drawn last) hides what lies below the ice surface line.

Deflection angle
----------------
``deflection_angle_deg`` is the angle from the vertical (the undeformed axis) of the chord
from the element's root centre (where it leaves the block base) to the point where its
centreline meets the ice surface line, positive trailing; for an element whose bottom centre
stays above the ice, the chord to the bottom centre. Both ends are visible in the image,
which is how the analysis measures it.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from synthetic._camera import box_blur_x
from synthetic._render_tir import ElementFrame, PathGeometry

__all__ = [
    "SideLayout",
    "centreline_shape",
    "deflection_angles",
    "element_polygons",
    "ice_texture_frame",
    "polygon_coverage",
    "render_side_signal",
    "rotate_scene",
]

logger = logging.getLogger(__name__)

#: Shear coefficient of a rectangular rubber section (Cowper, nu = 0.5, Eq. 5.19).
_KAPPA = 6.0 / 7.0
#: Centreline samples per element drawn (the polyline deviates < 0.01 px from the cubic).
_N_SHAPE = 33
#: Sub-rows per pixel row of the scanline rasteriser (edge error <= 1/16 px in y; x exact).
_SUBROWS = 8


def centreline_shape(
    length_mm: float, height_mm: float, eta: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Normalised Timoshenko deflection rho(eta) and rotation psi(eta) of a tip-loaded element.

    Parameters
    ----------
    length_mm, height_mm : float
        Element length l (beam thickness) and height d (beam length), mm.
    eta : ndarray
        x / d from the root (0) to the tip (1).

    Returns
    -------
    rho, psi : ndarray
        Deflection and cross-section rotation over their tip values.

    Examples
    --------
    >>> rho, psi = centreline_shape(4.55, 6.0, np.array([0.0, 1.0]))
    >>> rho.tolist(), psi.tolist()
    ([0.0, 1.0], [0.0, 1.0])
    """
    r = 4.0 * _KAPPA * (height_mm / length_mm) ** 2
    eta = np.asarray(eta, dtype=np.float64)
    rho = (r * (eta**2 / 2 - eta**3 / 6) + eta) / (r / 3 + 1)
    psi = 2 * eta - eta**2
    return rho, psi


def deflection_angles(frame: ElementFrame, height_mm: float) -> np.ndarray:
    """The deflection angle of every element (module notes), deg, positive trailing."""
    out = np.empty(frame.n_elements)
    y0 = frame.preload_mm
    for i in range(frame.n_elements):
        xt, yt = float(frame.tip_x_mm[i]), float(frame.tip_depth_mm[i])
        if yt > y0 > 0:
            rho, _ = centreline_shape(float(frame.length_mm[i]), height_mm, np.array([y0 / yt]))
            out[i] = math.degrees(math.atan2(xt * float(rho[0]), y0))
        else:
            out[i] = math.degrees(math.atan2(xt, yt))
    return out


@dataclass(frozen=True)
class SideLayout:
    """Vertical layout of the side view and the grey levels of its parts.

    Attributes
    ----------
    ice_y_mm : float
        Image y of the ice surface line at the image centre, mm.
    base_mm : float
        Rubber above the sipe ground (the block base), mm.
    carrier_mm : float
        Height of the steel carrier plate the sample is glued to, mm.
    carrier_overhang_mm : float
        Overhang of the carrier beyond the block at either end, mm.
    background, rubber, carrier, ice : float
        Levels as fractions of the full-scale level S.
    """

    ice_y_mm: float
    base_mm: float
    carrier_mm: float
    carrier_overhang_mm: float
    background: float
    rubber: float
    carrier: float
    ice: float


def element_polygons(
    frame: ElementFrame,
    *,
    height_mm: float,
    block_length_mm: float,
    layout: SideLayout,
    u_front: float,
    path: PathGeometry,
) -> tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]]:
    """Outlines (image mm, (k, 2)) of the elements, of the base and of the carrier.

    Returns
    -------
    elements : list of ndarray
        One polygon per element, element 0 first.
    base : list of ndarray
        The block base (one rectangle).
    carrier : list of ndarray
        The carrier plate (one rectangle).
    """
    s = path.direction
    y_root = layout.ice_y_mm - frame.preload_mm
    eta = np.linspace(0.0, 1.0, _N_SHAPE)

    def to_img(xi: np.ndarray, y: np.ndarray) -> np.ndarray:
        # Block coordinates (xi backwards, y down from the image top) to image mm, then the
        # camera rotation about the image centre.
        u = u_front + s * np.asarray(xi)
        x, yy = rotate_scene(path, u, np.asarray(y, dtype=np.float64))
        return np.column_stack([x, yy])

    polys = []
    for i in range(frame.n_elements):
        ell = float(frame.length_mm[i])
        rho, psi = centreline_shape(ell, height_mm, eta)
        xc = frame.root_centre_mm[i] + frame.tip_x_mm[i] * rho
        yc = y_root + frame.tip_depth_mm[i] * eta
        phi = frame.tilt_rad[i] * psi
        dx, dy = 0.5 * ell * np.cos(phi), -0.5 * ell * np.sin(phi)
        front = to_img(xc - dx, yc - dy)
        back = to_img(xc + dx, yc + dy)
        polys.append(np.vstack([front, back[::-1]]))
    y_base = y_root - layout.base_mm
    base = to_img(
        np.array([0.0, block_length_mm, block_length_mm, 0.0]),
        np.array([y_base, y_base, y_root, y_root]),
    )
    o = layout.carrier_overhang_mm
    y_car = y_base - layout.carrier_mm
    carrier = to_img(
        np.array([-o, block_length_mm + o, block_length_mm + o, -o]),
        np.array([y_car, y_car, y_base, y_base]),
    )
    return polys, [base], [carrier]


def rotate_scene(path: PathGeometry, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotate unrotated image coordinates about the image centre by the camera rotation."""
    if path.rotation_rad == 0.0:
        return np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    xc, yc = path.centre
    c, sn = math.cos(path.rotation_rad), math.sin(path.rotation_rad)
    dx, dy = np.asarray(x) - xc, np.asarray(y) - yc
    return xc + dx * c - dy * sn, yc + dx * sn + dy * c


def polygon_coverage(
    polygons: list[np.ndarray], height_px: int, width_px: int, mm_per_px: float
) -> np.ndarray:
    """Anti-aliased coverage of the union of non-overlapping polygons (summed, clipped to 1).

    A scanline rasteriser: ``8`` sub-rows per pixel row, on each the exact covered length of
    every pixel in x (even-odd rule).

    Parameters
    ----------
    polygons : list of (k, 2) ndarray
        Outlines in image mm (x, y).
    height_px, width_px : int
    mm_per_px : float

    Returns
    -------
    (height_px, width_px) ndarray of float32
        Covered fraction of each pixel.

    Examples
    --------
    >>> sq = np.array([[0.5, 0.0], [2.25, 0.0], [2.25, 1.0], [0.5, 1.0]])
    >>> polygon_coverage([sq], 2, 4, 1.0)[0].tolist()
    [0.5, 1.0, 0.25, 0.0]
    """
    ss = _SUBROWS
    diff = np.zeros((height_px, width_px + 2))
    for poly in polygons:
        p = np.asarray(poly, dtype=np.float64) / mm_per_px
        x0, y0 = p[:, 0], p[:, 1]
        x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
        r0 = max(math.floor(y0.min()), 0)
        r1 = min(math.ceil(y0.max()), height_px)
        if r0 >= r1 or x0.max() <= 0 or x0.min() >= width_px:
            continue
        sub = np.arange(r0 * ss, r1 * ss)
        ys = (sub + 0.5) / ss
        yy = ys[:, None]
        cond = ((y0 <= yy) & (yy < y1)) | ((y1 <= yy) & (yy < y0))
        dy = np.where(y1 == y0, 1.0, y1 - y0)
        xs = np.where(cond, x0 + (yy - y0) / dy * (x1 - x0), np.inf)
        xs.sort(axis=1)
        a, b = xs[:, 0::2], xs[:, 1::2]
        m = min(a.shape[1], b.shape[1])
        a, b = a[:, :m], b[:, :m]
        ok = np.isfinite(b)
        rows = np.broadcast_to((sub // ss)[:, None], a.shape)[ok]
        a = np.clip(a[ok], 0.0, width_px)
        b = np.clip(b[ok], 0.0, width_px)
        for edge, sign in ((b, 1.0), (a, -1.0)):
            fl = np.floor(edge).astype(np.intp)
            fr = edge - fl
            w = sign / ss
            np.add.at(diff, (rows, np.zeros_like(fl)), w)
            np.add.at(diff, (rows, fl), w * (fr - 1.0))
            np.add.at(diff, (rows, fl + 1), -w * fr)
    cov = np.cumsum(diff, axis=1)[:, :width_px]
    return np.clip(cov, 0.0, 1.0).astype(np.float32)


def render_side_signal(
    polygons: tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]],
    *,
    layout: SideLayout,
    path: PathGeometry,
    base: np.ndarray,
    ice_texture: np.ndarray,
    blur_px: float,
    blur_block: bool,
) -> np.ndarray:
    """Noise-free side-view signal of one frame, in units of the full well.

    Parameters
    ----------
    polygons : tuple of three lists of ndarray
        The outlines of the elements, the base and the carrier at this frame, image mm
        (:func:`element_polygons`).
    layout : SideLayout
    path : PathGeometry
    base : (H, W) ndarray
        Static full-scale level S (illumination, dust), units of the full well.
    ice_texture : (H, W) ndarray
        Relative brightness of the ice region at this frame (1 = plain ice).
    blur_px : float
        Motion during the exposure, px.
    blur_block : bool
        True with a fixed camera (the block smears), False with a following camera (the ice
        texture smears).

    Returns
    -------
    (H, W) ndarray of float32
    """
    h, w = base.shape
    px = path.mm_per_px
    elems, base_poly, carrier = polygons
    rubber = polygon_coverage(elems + base_poly, h, w, px)
    steel = polygon_coverage(carrier, h, w, px)
    # Premultiplied layer of the moving block (carrier and rubber do not overlap).
    alpha = np.clip(rubber + steel, 0.0, 1.0)
    colour = rubber * np.float32(layout.rubber) + steel * np.float32(layout.carrier)
    ice = _ice_coverage(path, layout, h, w)
    tex = ice_texture
    if blur_px > 1e-9:
        if blur_block:
            alpha, colour = box_blur_x(alpha, blur_px), box_blur_x(colour, blur_px)
        else:
            tex = box_blur_x(tex, blur_px)
    img = np.float32(layout.background) * (1.0 - alpha) + colour
    img = img * (1.0 - ice) + ice * np.float32(layout.ice) * tex
    return (img * base).astype(np.float32)


def _ice_coverage(path: PathGeometry, layout: SideLayout, h: int, w: int) -> np.ndarray:
    """Coverage of the ice slab below the (possibly rotated) ice surface line."""
    big = 4.0 * (path.width_mm + path.height_mm)
    xs = np.array([-big, big + path.width_mm, big + path.width_mm, -big])
    ys = np.array([layout.ice_y_mm, layout.ice_y_mm, layout.ice_y_mm + big, layout.ice_y_mm + big])
    x, y = rotate_scene(path, xs, ys)
    return polygon_coverage([np.column_stack([x, y])], h, w, path.mm_per_px)


def ice_texture_frame(
    path: PathGeometry,
    layout: SideLayout,
    *,
    bubbles: np.ndarray,
    offset_mm: float,
) -> np.ndarray:
    """Brightness of the ice slab with its bubbles shifted by ``offset_mm`` along x.

    Parameters
    ----------
    bubbles : (n, 4) ndarray
        World x (mm, sorted ascending), depth below the ice line (mm), radius (mm) and
        relative brightening.
    offset_mm : float
        Camera displacement along x since the clip middle (following camera), mm.

    Returns
    -------
    (H, W) ndarray of float32
    """
    px = path.mm_per_px
    h, w = round(path.height_mm / px), round(path.width_mm / px)
    out = np.ones((h, w), dtype=np.float32)
    xs = (np.arange(w) + 0.5) * px
    ys = (np.arange(h) + 0.5) * px
    # Bubbles are sorted by x: only those near the view are drawn (the rotation about the
    # image centre moves a point by less than the image height in x).
    margin = path.height_mm + 1.0
    lo = np.searchsorted(bubbles[:, 0], offset_mm - margin)
    hi = np.searchsorted(bubbles[:, 0], offset_mm + path.width_mm + margin)
    for xw, depth, r, a in bubbles[lo:hi]:
        x0 = xw - offset_mm
        if x0 < -r - 1 or x0 > path.width_mm + r + 1:
            continue
        xr, yr = rotate_scene(path, np.array([x0]), np.array([layout.ice_y_mm + depth]))
        cx, cy = float(xr[0]), float(yr[0])
        c0, c1 = max(int((cx - r) / px) - 2, 0), min(int((cx + r) / px) + 3, w)
        r0, r1 = max(int((cy - r) / px) - 2, 0), min(int((cy + r) / px) + 3, h)
        if c0 >= c1 or r0 >= r1:
            continue
        rho = np.hypot(xs[None, c0:c1] - cx, ys[r0:r1, None] - cy)
        out[r0:r1, c0:c1] *= (1.0 + a * np.clip((r - rho) / px + 0.5, 0.0, 1.0)).astype(np.float32)
    return out
