"""The lit zone of the TIR view: where the totally reflected light reaches the camera
(private helper of :mod:`synthetic.footage`).

In real rigs the TIR light often fills only part of the frame: a vignetted disc, an ellipse
or a band, with a soft rim and a dark outside. The zone is described by a signed distance
``d`` (mm, positive inside) to its boundary; the light factor is

``L = outside + (1 - outside) * s(d)``, ``s(d) = smoothstep(1/2 + d / rim)``

(``s = 1/2`` on the boundary, 0 beyond ``rim/2`` outside, 1 beyond ``rim/2`` inside; the
rim is at least one pixel wide). The **lit mask** is ``d >= 0`` at the pixel centre, i.e.
the pixels whose light factor is at least half-way between the outside level and the full
level; the zone's size is chosen so that the mask covers the requested fraction of the
frame (to one pixel's worth of its perimeter).

Notes
-----
Image coordinates in mm from the top-left image corner, x along the columns, y along the
rows; pixel ``(r, c)`` has its centre at ``((c + 1/2) px, (r + 1/2) px)``.
"""

from __future__ import annotations

import logging
import math

import numpy as np

__all__ = ["LIT_SHAPES", "fold_factor", "lit_distance", "lit_factor", "lit_zone_size"]

logger = logging.getLogger(__name__)

#: Shapes of the lit zone; "full" is the whole frame evenly lit (no zone).
LIT_SHAPES = ("full", "disc", "ellipse", "band")


def _centre_offsets(
    height_px: int, width_px: int, mm_per_px: float, center_mm: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray]:
    """x and y of the pixel centres relative to the zone centre, mm ((1, W) and (H, 1))."""
    xs = (np.arange(width_px, dtype=np.float64) + 0.5) * mm_per_px
    ys = (np.arange(height_px, dtype=np.float64) + 0.5) * mm_per_px
    xc = 0.5 * width_px * mm_per_px + center_mm[0]
    yc = 0.5 * height_px * mm_per_px + center_mm[1]
    return (xs - xc)[None, :], (ys - yc)[:, None]


def lit_distance(
    shape: str,
    size_mm: float,
    *,
    height_px: int,
    width_px: int,
    mm_per_px: float,
    center_mm: tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    """Signed distance of each pixel centre to the zone boundary, mm (positive inside).

    Parameters
    ----------
    shape : {"disc", "ellipse", "band"}
        Disc of radius ``size_mm``; ellipse with semi-axes ``size_mm`` across x and
        ``size_mm * H / W`` across y (the frame's aspect ratio); band of half-height
        ``size_mm`` across the full frame width, along x (the sliding direction).
    size_mm : float
        Zone size, mm.
    height_px, width_px : int
    mm_per_px : float
    center_mm : (float, float)
        Zone centre relative to the image centre, (x, y), mm.

    Returns
    -------
    (height_px, width_px) ndarray of float64
        For the ellipse the distance is the radial approximation
        ``(1 - rho) * min(a, b)`` with ``rho`` the normalised elliptic radius (exact on the
        boundary, where the mask is decided).
    """
    dx, dy = _centre_offsets(height_px, width_px, mm_per_px, center_mm)
    if shape == "disc":
        return size_mm - np.hypot(dx, dy)
    if shape == "ellipse":
        a = size_mm
        b = size_mm * height_px / width_px
        rho = np.hypot(dx / a, dy / b)
        return (1.0 - rho) * min(a, b)
    if shape == "band":
        return np.broadcast_to(size_mm - np.abs(dy), (height_px, width_px)).copy()
    raise ValueError(f"lit_shape must be one of {list(LIT_SHAPES[1:])} here, got {shape!r}")


def lit_zone_size(
    shape: str,
    fraction: float,
    *,
    height_px: int,
    width_px: int,
    mm_per_px: float,
    center_mm: tuple[float, float] = (0.0, 0.0),
) -> float:
    """Zone size (mm) whose lit mask covers ``fraction`` of the frame (bisection).

    The mask grows monotonically with the size; the result is the smallest size (to
    1e-9 of the frame diagonal) whose mask fraction reaches ``fraction``.
    """
    n = height_px * width_px
    target = math.ceil(fraction * n - 1e-9)
    lo = 0.0
    diag = math.hypot(width_px, height_px) * mm_per_px
    hi = 2.0 * (diag + abs(center_mm[0]) + abs(center_mm[1]))
    if shape == "ellipse":
        hi *= max(1.0, width_px / height_px)

    def count(size: float) -> int:
        d = lit_distance(
            shape,
            size,
            height_px=height_px,
            width_px=width_px,
            mm_per_px=mm_per_px,
            center_mm=center_mm,
        )
        return int(np.count_nonzero(d >= 0.0))

    for _ in range(200):
        if hi - lo <= 1e-9 * diag:
            break
        mid = 0.5 * (lo + hi)
        if count(mid) >= target:
            hi = mid
        else:
            lo = mid
    return hi


def lit_factor(
    distance_mm: np.ndarray, *, rim_mm: float, mm_per_px: float, outside: float
) -> np.ndarray:
    """Light factor ``outside + (1 - outside) s(d)`` of each pixel (see the module notes).

    Parameters
    ----------
    distance_mm : (H, W) ndarray
        :func:`lit_distance`.
    rim_mm : float
        Width of the soft rim, mm (at least one pixel is used).
    mm_per_px : float
    outside : float
        Light left outside the zone, fraction of the full level.

    Returns
    -------
    (H, W) ndarray of float32
    """
    rim = max(rim_mm, mm_per_px)
    t = np.clip(0.5 + distance_mm / rim, 0.0, 1.0)
    s = t * t * (3.0 - 2.0 * t)
    return (outside + (1.0 - outside) * s).astype(np.float32)


def fold_factor(
    height_px: int,
    width_px: int,
    *,
    mm_per_px: float,
    x_mm: float,
    width_mm: float,
    edge_mm: float,
    depth: float,
) -> np.ndarray:
    """Light factor of a darker fold across the lit zone: a band along y where the light
    falls steeply to ``1 - depth``.

    The band's flat core holds the columns whose centre lies within ``width_mm / 2`` of
    the line ``x = W/2 + x_mm`` (mm from the image centre); over ``edge_mm`` on each side
    the light rises back to 1 along a raised cosine (a fold in a prism's coating, a
    crease of a light guide). The factor multiplies the illumination (free surface and
    contact alike), it is a property of the light, not of the contact.

    Assumes: the fold is straight and parallel to the image's y axis, its depth is the
    same along its length, and it is fixed to the camera.

    Parameters
    ----------
    height_px, width_px : int
    mm_per_px : float
    x_mm : float
        Centre line of the fold from the image centre along x, mm.
    width_mm : float
        Width of its flat core, mm.
    edge_mm : float
        Width of each edge (the fall-off), mm; 0: a step.
    depth : float
        Share of the light lost in the core, in [0, 1).

    Returns
    -------
    (H, W) ndarray of float32

    Examples
    --------
    >>> f = fold_factor(4, 10, mm_per_px=1.0, x_mm=0.0, width_mm=2.0, edge_mm=0.0, depth=0.5)
    >>> f[0].tolist()
    [1.0, 1.0, 1.0, 1.0, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0]
    """
    x = (np.arange(width_px, dtype=np.float64) + 0.5) * mm_per_px
    outside = np.abs(x - (0.5 * width_px * mm_per_px + x_mm)) - 0.5 * width_mm
    if edge_mm > 0.0:
        t = np.clip(outside / edge_mm, 0.0, 1.0)
        dark = 0.5 * (1.0 + np.cos(math.pi * t))
    else:
        dark = (outside <= 0.0).astype(np.float64)
    row = (1.0 - depth * dark).astype(np.float32)
    return np.broadcast_to(row, (height_px, width_px)).copy()
