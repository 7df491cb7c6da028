"""TIR bottom view of a sliding tread block: contact pressure, darkness and the frame render
(private helpers of :mod:`synthetic.footage`).

Geometry
--------
* Block coordinate ``xi`` (mm): distance behind the block's leading face (the leading face
  of element 0 at its root), increasing towards the trailing end.
* Element ``i`` hangs from its root centre ``xi = root_centre_mm[i]``; its bottom centre
  trails the root by ``tip_x_mm[i]`` and lies ``tip_depth_mm[i]`` below it (rigid-bar
  kinematics); the ice is ``preload_mm`` below the roots. The bottom face is tilted by
  ``tilt_rad[i]`` (positive: the trailing corner is lifted).
* Face coordinate ``zeta`` (mm): distance from the element's leading bottom corner towards
  its trailing corner, ``0 <= zeta <= l``. The Winkler penetration is
  ``u(zeta) = u_c + (l/2 - zeta) sin(tilt)`` with ``u_c = tip_depth - preload``; the face
  touches the ice where ``u > 0``. The contact is drawn flattened on the ice: face point
  ``zeta`` lies at ``xi = xi_front + zeta`` with ``xi_front`` the leading corner.
* Path coordinates ``(u, v)`` (mm) in the image: ``u`` along the sliding path, equal to
  the image x for ``rotation_deg = 0``; ``v`` across it, 0 on the image's centre row.

Pressure and darkness
---------------------
``p(zeta) = lambda E/h u(zeta)`` (the Winkler foundation of the rigid model,
``c_N / l = E w / h``) scaled by ``lambda`` so that the block carries the nominal load. When
the leading corner touches, the pressure over the front band ``0 <= zeta <= b`` is multiplied
by ``m(t) = s(t) (1 + A 2 sin^2(pi t))``, ``t = zeta / b``, and the element re-normalised to
its force: ``s(t) = sqrt(min(1, 2t))`` is the rise over the rounded edge of a new sample
(zero pressure at the edge itself, like at every other contact boundary), and ``A`` makes
the mean of ``m`` over the band equal to ``kappa``, the mean over the band of the flat-punch
pressure ``p_m a / (pi sqrt(a^2 - x^2))`` (``a = l/2``) relative to its mean ``p_m``: the
pressure peak at the front edge (Fig. 5.11 a), strongest for long elements (G0: 4.5,
G3: 2.2, G7: 1.5 at b = 0.4 mm), with its maximum about b/2 behind the edge.

The darkness (fraction of the free-surface light removed) is
``D(p) = C + (C_max - C) (1 - exp(-p / p_ref))`` inside the contact and 0 outside: ``C`` at
the contact boundary, where the pressure goes to zero, darker with pressure up to
``C_max``. Every contact point is therefore at least ``C`` dark, and a pixel straddling the
boundary is darker than ``C / 2`` exactly when more than about half of it is in contact.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from synthetic._camera import interval_coverage

__all__ = [
    "ContactParams",
    "ElementContact",
    "ElementFrame",
    "PathGeometry",
    "StepProfile",
    "band_factor",
    "block_profile",
    "block_row",
    "element_contacts",
    "ice_transmission",
    "pressure_cells",
    "render_tir_signal",
    "tir_truth_rows",
    "visible_area",
    "visible_length",
]

logger = logging.getLogger(__name__)

#: Nodes of the pressure profile across the front band.
_BAND_NODES = 64
#: Means over the band (t in [0, 1]) of s(t) = sqrt(min(1, 2t)) and of 2 s(t) sin^2(pi t).
_MEAN_S = 5.0 / 6.0
_MEAN_2S_SIN2 = 0.9136834375
#: Node spacing behind the band, mm (upper bound; also at most 1/8 px).
_REST_SPACING_MM = 0.02


@dataclass(frozen=True)
class ElementFrame:
    """Rigid-model state of every element at one frame (block coordinates, mm and rad).

    Attributes
    ----------
    root_centre_mm : (N,) ndarray
        ``xi`` of each element's root centre, mm.
    length_mm : (N,) ndarray
        Element lengths l_i in the sliding direction, mm.
    tip_x_mm : (N,) ndarray
        Trailing displacement of each bottom centre relative to its root, mm.
    tip_depth_mm : (N,) ndarray
        Depth of each bottom centre below its root, mm.
    tilt_rad : (N,) ndarray
        Tilt of each bottom face (the lowest bar), rad, positive with the trailing corner up.
    chord_deg : (N,) ndarray
        The rigid model's ``angle_deg``: chord from the root to the bottom centre, deg.
    preload_mm : float
        Distance from the roots down to the ice, mm.
    """

    root_centre_mm: np.ndarray
    length_mm: np.ndarray
    tip_x_mm: np.ndarray
    tip_depth_mm: np.ndarray
    tilt_rad: np.ndarray
    chord_deg: np.ndarray
    preload_mm: float

    @property
    def n_elements(self) -> int:
        """Number of elements N."""
        return int(self.length_mm.shape[0])

    @property
    def front_corner_mm(self) -> np.ndarray:
        """``xi`` of each element's leading bottom corner, mm."""
        return self.root_centre_mm + self.tip_x_mm - 0.5 * self.length_mm * np.cos(self.tilt_rad)


@dataclass(frozen=True)
class ContactParams:
    """Material, load and optics of the contact (see the module notes).

    Attributes
    ----------
    winkler_Pa_per_mm : float
        E / h: Winkler pressure per mm of penetration, Pa/mm.
    width_mm : float
        Block width w, mm.
    load_N : float
        Nominal normal load p L w carried by the block, N.
    contrast : float
        C: darkness of the contact at vanishing pressure (its boundary), fraction of the
        free-surface level.
    contrast_max : float
        C_max >= C: darkness approached at high pressure.
    pressure_ref_Pa : float
        p_ref of the saturating darkness law, Pa.
    band_mm : float
        Width b of the front-edge band, mm.
    """

    winkler_Pa_per_mm: float
    width_mm: float
    load_N: float
    contrast: float
    contrast_max: float
    pressure_ref_Pa: float
    band_mm: float

    def darkness(self, pressure_Pa: np.ndarray) -> np.ndarray:
        """D(p) inside the contact, fraction of the free-surface level."""
        rise = -np.expm1(-np.maximum(pressure_Pa, 0.0) / self.pressure_ref_Pa)
        return self.contrast + (self.contrast_max - self.contrast) * rise


def band_factor(length_mm: float, band_mm: float) -> float:
    """Edge concentration kappa: mean flat-punch pressure over the band / mean pressure.

    ``kappa = 2a / (pi b) * (pi/2 - asin(1 - b/a))`` with ``a = l/2``, the mean of
    ``a / (pi sqrt(a^2 - x^2))`` (times 2 for the mean pressure ``p_m``) over
    ``a - b <= x <= a``; 1 when the band is as wide as the half element.

    Examples
    --------
    >>> round(band_factor(20.0, 0.4), 2), round(band_factor(4.55, 0.4), 2)
    (4.52, 2.18)
    """
    a = 0.5 * length_mm
    b = min(band_mm, a)
    if b <= 0.0:
        return 1.0
    return 2.0 * a / (math.pi * b) * (0.5 * math.pi - math.asin(1.0 - b / a))


@dataclass(frozen=True)
class ElementContact:
    """Contact of one element in one frame.

    Attributes
    ----------
    zeta_start_mm, zeta_end_mm : float
        Contact interval on the face, mm from the leading corner (equal: no contact).
    nodes_mm : (n + 1,) ndarray
        Node positions ``zeta`` of the pressure profile, mm (empty without contact).
    pressure_Pa : (n + 1,) ndarray
        Pressure at the nodes, Pa.
    peak_zeta_mm : float
        ``zeta`` of the pressure maximum, mm (NaN without contact).
    peak_pressure_Pa : float
        Largest pressure, Pa (0 without contact).
    lever_arm_mm : float
        Offset of the pressure centroid from the face centre towards the leading edge, mm
        (the eccentricity e of Eq. 5.20; NaN without contact).
    force_N : float
        Normal force carried, N.
    """

    zeta_start_mm: float
    zeta_end_mm: float
    nodes_mm: np.ndarray
    pressure_Pa: np.ndarray
    peak_zeta_mm: float
    peak_pressure_Pa: float
    lever_arm_mm: float
    force_N: float

    @property
    def length_mm(self) -> float:
        """Contact length along the sliding direction, mm."""
        return self.zeta_end_mm - self.zeta_start_mm


def _trapz(y: np.ndarray, x: np.ndarray) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def element_contacts(
    frame: ElementFrame, params: ContactParams, *, node_spacing_mm: float
) -> list[ElementContact]:
    """Contact interval, pressure profile, peak and lever arm of every element.

    Parameters
    ----------
    frame : ElementFrame
    params : ContactParams
    node_spacing_mm : float
        Largest node spacing behind the band, mm (the renderer passes 1/8 px).

    Returns
    -------
    list of ElementContact
        One per element, element 0 first.
    """
    n = frame.n_elements
    raw: list[tuple[float, float, np.ndarray, np.ndarray]] = []
    total_model_force = 0.0
    spacing = min(_REST_SPACING_MM, node_spacing_mm)
    for i in range(n):
        ell = float(frame.length_mm[i])
        uc = float(frame.tip_depth_mm[i] - frame.preload_mm)
        s = math.sin(float(frame.tilt_rad[i]))
        if abs(s) < 1e-12:
            za, zb = (0.0, ell) if uc > 0 else (0.0, 0.0)
        else:
            zstar = 0.5 * ell + uc / s  # u(zstar) = 0
            if s > 0:
                za, zb = 0.0, min(ell, max(zstar, 0.0))
            else:
                za, zb = max(0.0, min(zstar, ell)), ell
        if zb - za <= 1e-9:
            raw.append((0.0, 0.0, np.zeros(0), np.zeros(0)))
            continue
        # Nodes: fine over the front band (when the leading corner touches), coarser behind.
        band = min(params.band_mm, zb - za) if za == 0.0 else 0.0
        parts = []
        if band > 0.0:
            parts.append(np.linspace(0.0, band, _BAND_NODES + 1))
        rest0 = za + band
        if zb - rest0 > 1e-12:
            k = max(2, math.ceil((zb - rest0) / spacing) + 1)
            parts.append(np.linspace(rest0, zb, k)[1 if band > 0 else 0 :])
        nodes = np.concatenate(parts)
        u = np.maximum(uc + (0.5 * ell - nodes) * s, 0.0)
        p_w = params.winkler_Pa_per_mm * u
        force_w = _trapz(p_w, nodes) * params.width_mm * 1e-6
        total_model_force += force_w
        p = p_w
        if band > 0.0:
            kappa = band_factor(ell, params.band_mm)
            amp = max(kappa - _MEAN_S, 0.0) / _MEAN_2S_SIN2
            t = np.clip(nodes / band, 0.0, 1.0)
            rise = np.sqrt(np.minimum(1.0, 2.0 * t))
            p = p_w * np.where(t < 1.0, rise * (1.0 + amp * 2.0 * np.sin(np.pi * t) ** 2), 1.0)
            f_total = _trapz(p, nodes)
            if f_total > 0:
                p = p * (_trapz(p_w, nodes) / f_total)
        raw.append((za, zb, nodes, p))
    scale = params.load_N / total_model_force if total_model_force > 0 else 1.0
    out: list[ElementContact] = []
    for i, (za, zb, nodes, p) in enumerate(raw):
        if nodes.size == 0:
            out.append(ElementContact(0.0, 0.0, nodes, p, math.nan, 0.0, math.nan, 0.0))
            continue
        p = p * scale
        k = int(np.argmax(p))
        peak = float(nodes[k])
        if 0 < k < nodes.size - 1:  # parabolic refinement of the maximum between nodes
            y0, y1, y2 = p[k - 1], p[k], p[k + 1]
            den = y0 - 2 * y1 + y2
            if den < 0 and nodes[k + 1] - nodes[k] == nodes[k] - nodes[k - 1]:
                peak += 0.5 * (y0 - y2) / den * (nodes[k + 1] - nodes[k])
        force = _trapz(p, nodes) * params.width_mm * 1e-6
        centroid = _trapz(p * nodes, nodes) / _trapz(p, nodes)
        ell = float(frame.length_mm[i])
        out.append(
            ElementContact(
                zeta_start_mm=za,
                zeta_end_mm=zb,
                nodes_mm=nodes,
                pressure_Pa=p,
                peak_zeta_mm=peak,
                peak_pressure_Pa=float(p.max()),
                lever_arm_mm=0.5 * ell - centroid,
                force_N=force,
            )
        )
    return out


class StepProfile:
    """A piecewise-constant darkness profile along ``xi`` with its first two integrals.

    ``D = values[k]`` on ``[nodes[k], nodes[k+1])``, 0 outside; ``F(x) = int_-inf^x D`` and
    ``G(x) = int_-inf^x F`` are exact (piecewise linear and quadratic).

    Parameters
    ----------
    nodes : (n + 1,) ndarray
        Strictly non-decreasing cell boundaries, mm.
    values : (n,) ndarray
        Darkness on each cell.
    """

    def __init__(self, nodes: np.ndarray, values: np.ndarray) -> None:
        self.nodes = np.asarray(nodes, dtype=np.float64)
        self.values = np.asarray(values, dtype=np.float64)
        h = np.diff(self.nodes)
        f = np.concatenate([[0.0], np.cumsum(self.values * h)])
        g = np.concatenate([[0.0], np.cumsum(f[:-1] * h + 0.5 * self.values * h * h)])
        self.F_nodes, self.G_nodes = f, g

    @property
    def empty(self) -> bool:
        """True when the profile has no cell."""
        return self.values.size == 0

    def _locate(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        k = np.clip(np.searchsorted(self.nodes, q, side="right") - 1, 0, self.values.size - 1)
        tau = q - self.nodes[k]
        below = q < self.nodes[0]
        above = q >= self.nodes[-1]
        return k, tau, below, above

    def F(self, q: np.ndarray) -> np.ndarray:
        """First integral at ``q`` (mm), same shape."""
        if self.empty:
            return np.zeros_like(q, dtype=np.float64)
        k, tau, below, above = self._locate(q)
        out = self.F_nodes[k] + self.values[k] * tau
        out = np.where(below, 0.0, out)
        return np.where(above, self.F_nodes[-1], out)

    def G(self, q: np.ndarray) -> np.ndarray:
        """Second integral at ``q`` (mm), same shape."""
        if self.empty:
            return np.zeros_like(q, dtype=np.float64)
        k, tau, below, above = self._locate(q)
        out = self.G_nodes[k] + self.F_nodes[k] * tau + 0.5 * self.values[k] * tau * tau
        out = np.where(below, 0.0, out)
        return np.where(above, self.G_nodes[-1] + self.F_nodes[-1] * (q - self.nodes[-1]), out)

    def box_mean(self, lo: np.ndarray, hi: np.ndarray, blur_mm: float) -> np.ndarray:
        """Mean darkness over ``[lo, hi]`` (pixel footprint, mm), box-blurred by ``blur_mm``.

        The blur averages over shifts of the footprint by ``-blur/2 .. +blur/2`` (the motion
        during an exposure centred on the frame time). Blurs below 1 % of the footprint are
        ignored: they move no edge by more than 0.002 of a pixel, and the second
        differences of G would lose precision to cancellation.
        """
        width = hi - lo
        if self.empty:
            return np.zeros(np.shape(width))
        # A mean of D lies in the hull of its values and 0. The differences of F and G lose
        # about eps * |G| / (width * blur) to cancellation (1e-9 for G ~ 1e3 mm^2 over a
        # 0.03 mm pixel and a 0.0016 mm blur), which can step just outside that hull: clip
        # to it, which moves no value further from the exact mean.
        low = min(0.0, float(self.values.min()))
        high = max(0.0, float(self.values.max()))
        if blur_mm <= 0.01 * float(np.min(np.abs(width))):
            return np.clip((self.F(hi) - self.F(lo)) / width, low, high)
        h = 0.5 * blur_mm
        out = (self.G(hi + h) - self.G(lo + h) - self.G(hi - h) + self.G(lo - h)) / (
            width * blur_mm
        )
        # Footprints wholly beside the profile are exactly zero (not ~1e-12 of cancellation).
        left = np.maximum(lo, hi) + h <= self.nodes[0]
        right = np.minimum(lo, hi) - h >= self.nodes[-1]
        return np.where(left | right, 0.0, np.clip(out, low, high))


def block_profile(
    frame: ElementFrame, contacts: list[ElementContact], params: ContactParams
) -> StepProfile:
    """The darkness of the whole block along ``xi`` as one :class:`StepProfile`.

    Cells take the darkness at their midpoint pressure (the mean of the node pressures); the
    gaps between element contacts are cells of zero darkness (:func:`pressure_cells`).
    """
    nodes, p_mid, element = pressure_cells(frame, contacts)
    if not p_mid.size:
        return StepProfile(nodes, p_mid)
    return StepProfile(nodes, np.where(element >= 0, params.darkness(p_mid), 0.0))


def pressure_cells(
    frame: ElementFrame, contacts: list[ElementContact]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cells of the block's contact pressure along ``xi`` (as drawn for patchy contact).

    Parameters
    ----------
    frame : ElementFrame
    contacts : list of ElementContact

    Returns
    -------
    nodes : (n + 1,) ndarray
        Cell boundaries, mm (``xi``).
    pressure : (n,) ndarray
        Midpoint pressure of each cell, Pa (0 in the gaps between elements).
    element : (n,) ndarray of int
        Element of each cell (-1 in the gaps).

    Notes
    -----
    A trailing footprint that overlaps its neighbour starts where the neighbour ends. The
    cells of :func:`block_profile` and of the patchy contact.
    """
    front = frame.front_corner_mm
    nodes_all: list[np.ndarray] = []
    p_all: list[np.ndarray] = []
    e_all: list[np.ndarray] = []
    last = -math.inf
    for i, c in enumerate(contacts):
        if c.nodes_mm.size < 2:
            continue
        xs = front[i] + c.nodes_mm
        p = c.pressure_Pa
        if xs[0] < last:  # neighbouring footprints overlap: the trailing one starts later
            logger.debug("element %d footprint overlaps its neighbour; clipped", i)
            keep = xs > last
            if not keep.any():
                continue
            p = np.concatenate([[np.interp(last, xs, p)], p[keep]])
            xs = np.concatenate([[last], xs[keep]])
        if nodes_all:
            p_all.append(np.zeros(1))
            e_all.append(np.full(1, -1))
        nodes_all.append(xs)
        p_all.append(0.5 * (p[1:] + p[:-1]))
        e_all.append(np.full(xs.size - 1, i))
        last = xs[-1]
    if not nodes_all:
        return np.zeros(1), np.zeros(0), np.zeros(0, dtype=np.intp)
    return (
        np.concatenate(nodes_all),
        np.concatenate(p_all),
        np.concatenate(e_all).astype(np.intp),
    )



@dataclass(frozen=True)
class PathGeometry:
    """Where the block's path runs through the image (mm, see the module notes).

    Attributes
    ----------
    width_mm, height_mm : float
        Image size, mm.
    mm_per_px : float
        Pixel pitch, mm.
    rotation_rad : float
        Angle of the path against the image x axis, rad (positive: rotated from +x towards
        +y, i.e. clockwise on screen).
    lateral_mm : float
        Offset ``v`` of the block centreline from the image centre, mm.
    direction : int
        +1 when the block slides towards -u (``"left"``), -1 towards +u (``"right"``).
    block_width_mm : float
        Block width w across the path, mm.
    """

    width_mm: float
    height_mm: float
    mm_per_px: float
    rotation_rad: float
    lateral_mm: float
    direction: int
    block_width_mm: float

    @property
    def centre(self) -> tuple[float, float]:
        """Image centre (x, y), mm."""
        return 0.5 * self.width_mm, 0.5 * self.height_mm

    def to_image(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Path coordinates (u, v) to image (x, y), mm."""
        xc, yc = self.centre
        c, s = math.cos(self.rotation_rad), math.sin(self.rotation_rad)
        du = np.asarray(u, dtype=np.float64) - xc
        v = np.asarray(v, dtype=np.float64)
        return xc + du * c - v * s, yc + du * s + v * c

    def to_path(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Image (x, y) to path coordinates (u, v), mm."""
        xc, yc = self.centre
        c, s = math.cos(self.rotation_rad), math.sin(self.rotation_rad)
        dx = np.asarray(x, dtype=np.float64) - xc
        dy = np.asarray(y, dtype=np.float64) - yc
        return xc + dx * c + dy * s, -dx * s + dy * c

    def u_of_xi(self, xi: np.ndarray | float, u_front: float) -> np.ndarray:
        """Path coordinate u of block coordinate ``xi`` with the leading face at ``u_front``."""
        return u_front + self.direction * np.asarray(xi, dtype=np.float64)

    def lateral_coverage(self) -> np.ndarray:
        """(H, W) fraction of each pixel inside the block's lateral extent (static).

        Exact for ``rotation_rad = 0``; with rotation the pixel is approximated by its extent
        ``mm_per_px`` across the path around its centre.
        """
        px = self.mm_per_px
        h, w = round(self.height_mm / px), round(self.width_mm / px)
        lo = self.lateral_mm - 0.5 * self.block_width_mm
        hi = self.lateral_mm + 0.5 * self.block_width_mm
        if self.rotation_rad == 0.0:
            yc = self.centre[1]
            cov = interval_coverage(lo + yc, hi + yc, h, px)
            return np.broadcast_to(cov[:, None], (h, w)).astype(np.float32)
        xs = (np.arange(w) + 0.5) * px
        ys = (np.arange(h) + 0.5) * px
        _, v = self.to_path(xs[None, :], ys[:, None])
        cov = np.clip(np.minimum(v + 0.5 * px, hi) - np.maximum(v - 0.5 * px, lo), 0.0, px) / px
        return cov.astype(np.float32)


def render_tir_signal(
    profile: StepProfile,
    path: PathGeometry,
    *,
    u_front: float,
    blur_mm: float,
    lateral: np.ndarray,
    base: np.ndarray,
    contrast: float,
    bright: bool,
) -> np.ndarray:
    """Noise-free TIR signal of one frame, in units of the full well.

    Parameters
    ----------
    profile : StepProfile
        Darkness of the block along ``xi``.
    path : PathGeometry
    u_front : float
        Path coordinate of the block's leading face at the frame time, mm.
    blur_mm : float
        Distance travelled during the exposure, mm.
    lateral : (H, W) ndarray
        :meth:`PathGeometry.lateral_coverage`.
    base : (H, W) ndarray
        Static full-scale level S of the scene (illumination, ice, dust), units of the full
        well.
    contrast : float
        C_max (the free level of the bright polarity is ``S (1 - C_max)``).
    bright : bool
        Contact bright on a dark free surface instead of dark on bright.

    Returns
    -------
    (H, W) ndarray of float32
    """
    h, w = base.shape
    px = path.mm_per_px
    free = base * np.float32(1.0 - contrast) if bright else base
    if profile.empty:
        return free.copy()
    xs = np.arange(w + 1, dtype=np.float64) * px
    if path.rotation_rad == 0.0:
        xi = (xs - u_front) * path.direction
        dark = profile.box_mean(xi[:-1], xi[1:], blur_mm).astype(np.float32)
        cols = np.nonzero(dark > 0)[0]
        out = free.copy()
        if cols.size:
            c0, c1 = int(cols[0]), int(cols[-1]) + 1
            contact = lateral[:, c0:c1] * dark[None, c0:c1]
            out[:, c0:c1] = base[:, c0:c1] * (
                (np.float32(1.0 - contrast) + contact) if bright else (1.0 - contact)
            )
        return out
    # Rotated path: each pixel's horizontal mid-row segment maps to an interval in u.
    c, s = math.cos(path.rotation_rad), math.sin(path.rotation_rad)
    xc, yc = path.centre
    ys = (np.arange(h, dtype=np.float64) + 0.5) * px
    u = xc + (xs[None, :] - xc) * c + (ys[:, None] - yc) * s
    xi = (u - u_front) * path.direction
    lo_xi = profile.nodes[0] - blur_mm
    hi_xi = profile.nodes[-1] + blur_mm
    inside = (np.maximum(xi[:, :-1], xi[:, 1:]) >= lo_xi) & (
        np.minimum(xi[:, :-1], xi[:, 1:]) <= hi_xi
    )
    cols = np.nonzero(inside.any(axis=0))[0]
    out = free.copy()
    if cols.size:
        c0, c1 = int(cols[0]), int(cols[-1]) + 1
        dark = profile.box_mean(xi[:, c0:c1], xi[:, c0 + 1 : c1 + 1], blur_mm).astype(np.float32)
        contact = lateral[:, c0:c1] * dark
        out[:, c0:c1] = base[:, c0:c1] * (
            (np.float32(1.0 - contrast) + contact) if bright else (1.0 - contact)
        )
    return out


def _clip_polygon(poly: np.ndarray, xmax: float, ymax: float) -> np.ndarray:
    """Sutherland-Hodgman clip of a convex polygon (k, 2) to ``[0, xmax] x [0, ymax]``."""
    pts = [tuple(p) for p in poly]
    for axis, bound, keep_below in (
        (0, 0.0, False),
        (0, xmax, True),
        (1, 0.0, False),
        (1, ymax, True),
    ):
        if not pts:
            break
        new: list[tuple[float, float]] = []
        for j in range(len(pts)):
            a, b = pts[j - 1], pts[j]
            ina = a[axis] <= bound if keep_below else a[axis] >= bound
            inb = b[axis] <= bound if keep_below else b[axis] >= bound
            if inb:
                if not ina:
                    new.append(_cross(a, b, axis, bound))
                new.append(b)
            elif ina:
                new.append(_cross(a, b, axis, bound))
        pts = new
    return np.asarray(pts, dtype=np.float64).reshape(-1, 2)


def _cross(
    a: tuple[float, float], b: tuple[float, float], axis: int, bound: float
) -> tuple[float, float]:
    t = (bound - a[axis]) / (b[axis] - a[axis])
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))


def _area(poly: np.ndarray) -> float:
    if poly.shape[0] < 3:
        return 0.0
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def visible_area(path: PathGeometry, u0: float, u1: float) -> float:
    """Area (mm^2) of the block strip ``u0 <= u <= u1`` (full width) inside the image."""
    lo, hi = min(u0, u1), max(u0, u1)
    if hi - lo <= 0:
        return 0.0
    if path.rotation_rad == 0.0:  # axis-aligned: the product of the two overlaps
        yc = 0.5 * path.height_mm + path.lateral_mm
        dy = min(yc + 0.5 * path.block_width_mm, path.height_mm) - max(
            yc - 0.5 * path.block_width_mm, 0.0
        )
        dx = min(hi, path.width_mm) - max(lo, 0.0)
        return max(dx, 0.0) * max(dy, 0.0)
    v0 = path.lateral_mm - 0.5 * path.block_width_mm
    v1 = path.lateral_mm + 0.5 * path.block_width_mm
    uu = np.array([lo, hi, hi, lo])
    vv = np.array([v0, v0, v1, v1])
    x, y = path.to_image(uu, vv)
    return _area(_clip_polygon(np.column_stack([x, y]), path.width_mm, path.height_mm))


def visible_length(path: PathGeometry, u0: float, u1: float) -> float:
    """Length (mm) of the centreline segment ``u0 <= u <= u1`` inside the image."""
    lo, hi = min(u0, u1), max(u0, u1)
    if hi - lo <= 0:
        return 0.0
    (xa, xb), (ya, yb) = path.to_image(np.array([lo, hi]), np.full(2, path.lateral_mm))
    t0, t1 = 0.0, 1.0
    for p0, d, bound in ((xa, xb - xa, path.width_mm), (ya, yb - ya, path.height_mm)):
        if abs(d) < 1e-15:
            if p0 < 0 or p0 > bound:
                return 0.0
            continue
        ta, tb = (0.0 - p0) / d, (bound - p0) / d
        t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
    return max(0.0, t1 - t0) * (hi - lo)


def tir_truth_rows(
    frame: ElementFrame,
    contacts: list[ElementContact],
    path: PathGeometry,
    *,
    u_front: float,
    deflection_deg: np.ndarray,
) -> list[dict[str, float | int | bool]]:
    """Ground-truth rows (elements in view, then the block total) of one TIR frame.

    Positions are image x (mm from the left image edge) of points on the block centreline;
    areas and lengths count only what lies inside the image.
    """
    rows: list[dict[str, float | int | bool]] = []
    front = frame.front_corner_mm
    v_line = np.array([path.lateral_mm])
    xs_front, xs_peak = [], []
    for i, c in enumerate(contacts):
        ell = float(frame.length_mm[i])
        u_face0 = path.u_of_xi(front[i], u_front)
        u_face1 = path.u_of_xi(front[i] + ell, u_front)
        if visible_area(path, float(u_face0), float(u_face1)) <= 0.0:
            continue
        if c.length_mm > 0:
            ua = float(path.u_of_xi(front[i] + c.zeta_start_mm, u_front))
            ub = float(path.u_of_xi(front[i] + c.zeta_end_mm, u_front))
            area = visible_area(path, ua, ub)
            length = visible_length(path, ua, ub)
            x_front = float(path.to_image(np.array([ua]), v_line)[0][0])
            u_pk = path.u_of_xi(front[i] + c.peak_zeta_mm, u_front)
            x_peak = float(path.to_image(np.array([u_pk]), v_line)[0][0])
        else:
            area = length = 0.0
            x_front = x_peak = math.nan
        xs_front.append(x_front)
        xs_peak.append((c.peak_pressure_Pa, x_peak))
        rows.append(
            element_row(i, frame, c, area, length, x_front, x_peak, float(deflection_deg[i]))
        )
    rows.append(block_row(rows, frame, xs_front, xs_peak, direction=path.direction))
    return rows


def element_row(
    i: int,
    frame: ElementFrame,
    c: ElementContact,
    area_mm2: float,
    length_mm: float,
    x_front_mm: float,
    x_peak_mm: float,
    deflection_deg: float,
) -> dict[str, float | int | bool]:
    """Ground-truth row of element ``i`` in view (both views share the columns)."""
    return {
        "element": i,
        "in_view": True,
        "contact_area_mm2": area_mm2,
        "contact_length_mm": length_mm,
        "front_edge_x_mm": x_front_mm,
        "front_peak_x_mm": x_peak_mm,
        "deflection_angle_deg": deflection_deg,
        "tilt_deg": math.degrees(float(frame.tilt_rad[i])),
        "tip_deflection_mm": float(frame.tip_x_mm[i]),
        "contact_fraction": c.length_mm / float(frame.length_mm[i]),
        "normal_force_N": c.force_N,
        "peak_pressure_MPa": c.peak_pressure_Pa * 1e-6,
        "lever_arm_mm": c.lever_arm_mm,
    }


def block_row(
    rows: list[dict[str, float | int | bool]],
    frame: ElementFrame,
    xs_front: list[float],
    xs_peak: list[tuple[float, float]],
    *,
    direction: int,
) -> dict[str, float | int | bool]:
    """The block-total row (element -1) from the element rows of one frame.

    ``xs_front`` and ``xs_peak`` hold, per element row, the front-edge x and
    ``(peak pressure, peak x)``; the block's front edge is the leading contact edge, its
    peak that of the same element.
    """
    nan = math.nan
    if not rows:
        return {
            "element": -1,
            "in_view": False,
            "contact_area_mm2": 0.0,
            "contact_length_mm": 0.0,
            "front_edge_x_mm": nan,
            "front_peak_x_mm": nan,
            "deflection_angle_deg": nan,
            "tilt_deg": nan,
            "tip_deflection_mm": nan,
            "contact_fraction": nan,
            "normal_force_N": nan,
            "peak_pressure_MPa": nan,
            "lever_arm_mm": nan,
        }
    # The leading contact edge (smallest x when sliding left, direction +1) and the pressure
    # peak of the element it belongs to.
    lead = [(direction * xf, xp) for xf, (_, xp) in zip(xs_front, xs_peak, strict=True)]
    lead = [t for t in lead if not math.isnan(t[0])]
    x_front, x_peak = (direction * min(lead)[0], min(lead)[1]) if lead else (nan, nan)
    face_len = float(np.sum(frame.length_mm))
    return {
        "element": -1,
        "in_view": True,
        "contact_area_mm2": float(sum(r["contact_area_mm2"] for r in rows)),
        "contact_length_mm": float(sum(r["contact_length_mm"] for r in rows)),
        "front_edge_x_mm": x_front,
        "front_peak_x_mm": x_peak,
        "deflection_angle_deg": float(np.mean([r["deflection_angle_deg"] for r in rows])),
        "tilt_deg": float(np.mean([r["tilt_deg"] for r in rows])),
        "tip_deflection_mm": float(np.mean([r["tip_deflection_mm"] for r in rows])),
        "contact_fraction": float(
            sum(r["contact_fraction"] * frame.length_mm[r["element"]] for r in rows)
            / sum(frame.length_mm[r["element"]] for r in rows)
        )
        if face_len > 0
        else nan,
        "normal_force_N": float(sum(r["normal_force_N"] for r in rows)),
        "peak_pressure_MPa": float(max(r["peak_pressure_MPa"] for r in rows)),
        "lever_arm_mm": nan,
    }


#: Length range of the ice's scratches, mm (uniform): a track used a few times.
SCRATCH_LENGTH_MM = (3.0, 20.0)
#: The thesis's TIR field of view, mm (640 x 256 px at 0.1 mm/px), and the flaws of its
#: ice seen in it: "the few bubbles" of Fig. 4.20 b (12) and the scratches of a track used
#: a few times (5).
THESIS_FIELD_MM = (64.0, 25.6)
THESIS_BUBBLES = 12
THESIS_SCRATCHES = 5


def ice_flaws_expected(
    width_mm: float,
    height_mm: float,
    *,
    bubbles_per_field: float = THESIS_BUBBLES,
    scratches_per_field: float = THESIS_SCRATCHES,
) -> tuple[float, float]:
    """Mean numbers of the ice's bubbles and scratches a view of ``width_mm`` x
    ``height_mm`` holds, for an ice with the given numbers in :data:`THESIS_FIELD_MM`.

    Bubbles (0.05-0.3 mm, frozen into the ice) are counted by area; scratches
    (:data:`SCRATCH_LENGTH_MM` long, far longer than a micro view) by the ones that cross
    the view: their starts over the view and a margin of its perimeter times the mean
    length over pi (Buffon's needle).

    Examples
    --------
    >>> [round(n, 3) for n in ice_flaws_expected(64.0, 25.6)]
    [12.0, 5.0]
    >>> [round(n, 3) for n in ice_flaws_expected(2.0, 2.0)]  # a micro view: clean ice
    [0.029, 0.073]
    """
    mean_length = sum(SCRATCH_LENGTH_MM) / 2

    def crossing(w: float, h: float) -> float:  # scratches seen, per scratch start density
        return w * h + 2.0 * (w + h) * mean_length / math.pi

    field_w, field_h = THESIS_FIELD_MM
    bubbles = bubbles_per_field * width_mm * height_mm / (field_w * field_h)
    scratches = scratches_per_field * crossing(width_mm, height_mm) / crossing(field_w, field_h)
    return bubbles, scratches


def ice_transmission(
    path: PathGeometry,
    *,
    rng: np.random.Generator,
    n_bubbles: int,
    n_scratches: int,
    groove_depth: float,
) -> np.ndarray:
    """Static light transmission of the ice imperfections seen from below (dimensionless).

    * Air bubbles: radius drawn from [0.05, 0.3] mm (bubbles frozen into clear ice, Fig.
      4.20 b), a dark rim (light leaves the totally reflected path at the bubble wall) over a
      lighter core, removing a fraction drawn from [0.15, 0.35] at the rim.
    * Scratches: straight segments of length [3, 20] mm and width [0.03, 0.1] mm at random
      angles, removing [0.1, 0.25] of the light.
    * A worn groove along the path (a rut left by earlier passes): a cos^2 profile of width
      [2, 6] mm centred within +-30 % of the image height of the path centreline, removing
      ``groove_depth`` at its centre.

    Returns
    -------
    (H, W) ndarray of float32
        Transmission in (0, 1].
    """
    px = path.mm_per_px
    h, w = round(path.height_mm / px), round(path.width_mm / px)
    xs = (np.arange(w) + 0.5) * px
    ys = (np.arange(h) + 0.5) * px
    out = np.ones((h, w), dtype=np.float64)
    for _ in range(n_bubbles):
        x0, y0 = rng.uniform(0, path.width_mm), rng.uniform(0, path.height_mm)
        r = rng.uniform(0.05, 0.3)
        a = rng.uniform(0.15, 0.35)
        c0, c1 = max(int((x0 - r) / px) - 2, 0), min(int((x0 + r) / px) + 3, w)
        r0, r1 = max(int((y0 - r) / px) - 2, 0), min(int((y0 + r) / px) + 3, h)
        if c0 >= c1 or r0 >= r1:
            continue
        rho = np.hypot(xs[None, c0:c1] - x0, ys[r0:r1, None] - y0)
        inside = np.clip((r - rho) / px + 0.5, 0.0, 1.0)  # anti-aliased disc edge
        prof = a * (0.4 + 0.6 * np.clip(rho / r, 0.0, 1.0) ** 4)
        out[r0:r1, c0:c1] *= 1.0 - inside * prof
    for _ in range(n_scratches):
        x0, y0 = rng.uniform(0, path.width_mm), rng.uniform(0, path.height_mm)
        length = rng.uniform(*SCRATCH_LENGTH_MM)
        ang = rng.uniform(0.0, math.pi)
        width = rng.uniform(0.03, 0.1)
        a = rng.uniform(0.1, 0.25)
        dx, dy = math.cos(ang), math.sin(ang)
        px_ = xs[None, :] - x0
        py_ = ys[:, None] - y0
        t = np.clip(px_ * dx + py_ * dy, 0.0, length)
        dist = np.hypot(px_ - t * dx, py_ - t * dy)
        # Coverage of a line of width `width` by a pixel, approximated by its distance ramp.
        wpx = width / px
        cov = np.clip(0.5 * max(wpx, 1.0) + 0.5 - dist / px, 0.0, 1.0) * min(wpx, 1.0)
        out *= 1.0 - a * cov
    if groove_depth > 0:
        vg = path.lateral_mm + rng.uniform(-0.3, 0.3) * path.height_mm
        wg = rng.uniform(2.0, 6.0)
        _, v = path.to_path(xs[None, :], ys[:, None])
        d = np.abs(v - vg)
        prof = np.where(d < 0.5 * wg, np.cos(np.pi * d / wg) ** 2, 0.0)
        out *= 1.0 - groove_depth * prof
    return out.astype(np.float32)
