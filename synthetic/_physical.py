"""Physical contact scenes: contact from mechanics, grey levels from optics (private helpers
of :mod:`synthetic.footage`).

A physical scene does not draw contact as a shape with a darkness law. It solves the
contact of a rough rubber surface on the flat ice or prism (:mod:`synthetic.roughness`,
tamaas), turns every point's gap into the reflected light of frustrated TIR
(:mod:`synthetic.ftir`), blurs that light by the lens and integrates it over the pixels.
The ground truth is read off the same solution: the true contact area (gap 0), the area
within a tenth of the evanescent depth, and the nominal area, each counted over the
sub-pixel samples inside the lit mask.

Scenes
------
``rough_pad``
    A flat round pad of radius ``a`` with a rough face under the nominal pressure ``p``
    (uniform: the rough-contact idealisation; the pressure rise at a real punch's rim is
    left out). Its contact is solved once on a periodic tile (``tile_points`` points per
    side at the roughness's grid spacing) and the tile repeats across the pad.
``rough_sphere``
    A rough sphere of radius ``R``: the rough heights plus the parabola ``-r^2 / (2 R)``
    on one tile at least 5 Hertz radii wide, under the load ``F = p pi a_H^2`` (``p`` the
    mean Hertz pressure). Its nominal area is the smooth sphere's Hertz disc at that load.

What the renderer assumes (and the pipeline must not): the light reflected at each point
depends only on the local gap (no light scattered back by the rubber out of the evanescent
zone apart from the Fresnel reflection at contact); the rubber surface is Gaussian and
self-affine; the pad presses uniformly; a periodic tile repeats across larger pads.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter

from synthetic._real_contact import pool
from synthetic.ftir import FtirOptics
from synthetic.roughness import (
    ContactField,
    Roughness,
    e_star_Pa,
    hertz_contact_radius_m,
    rough_heights,
    solve_contact,
)

__all__ = [
    "PHYSICAL_SCENES",
    "PhysicalRender",
    "PhysicalSetup",
    "render_physical",
    "scene_contact",
    "scene_contact_tile",
]

#: Static scenes rendered from contact mechanics and optics.
PHYSICAL_SCENES = ("rough_pad", "rough_sphere")
#: Largest solver tile side, grid points: a 512^2 rough contact solves in 2-6 s on one core.
MAX_TILE_POINTS = 512
#: Smallest tile side in units of the Hertz radius (the periodic images of the sphere change
#: its contact radius by under 0.1 % at 5 radii).
SPHERE_TILE_RADII = 5.0


@dataclass(frozen=True)
class PhysicalSetup:
    """What a physical scene needs besides the camera.

    Parameters
    ----------
    scene : {"rough_pad", "rough_sphere"}
    roughness : Roughness
    optics : FtirOptics
    pressure_Pa : float
        Nominal pressure (pad) or mean Hertz pressure (sphere), Pa.
    pad_radius_mm : float
        Pad radius, mm.
    sphere_radius_mm : float
        Sphere radius, mm.
    centre_mm : (float, float)
        Contact centre in image coordinates, mm.
    seed : int
        Seed of the rough surface.
    optical_blur_mm : float
        Standard deviation of the lens's Gaussian point-spread function in the object plane,
        mm (0: ideal lens).
    """

    scene: str
    roughness: Roughness
    optics: FtirOptics
    pressure_Pa: float
    pad_radius_mm: float
    sphere_radius_mm: float
    centre_mm: tuple[float, float]
    seed: int
    optical_blur_mm: float = 0.0

    @property
    def hertz_radius_mm(self) -> float:
        """Hertz radius of the smooth sphere at the scene's load, mm (``a = 3 pi p R / (4 E*)``
        from ``p = F / (pi a^2)`` and Hertz's ``a^3 = 3 F R / (4 E*)``)."""
        r = self.sphere_radius_mm * 1e-3
        e = e_star_Pa()
        a = 3.0 * math.pi * self.pressure_Pa * r / (4.0 * e)
        load = self.pressure_Pa * math.pi * a * a
        return hertz_contact_radius_m(load, r, e) * 1e3

    @property
    def nominal_radius_mm(self) -> float:
        """Radius of the nominal contact disc, mm."""
        return self.pad_radius_mm if self.scene == "rough_pad" else self.hertz_radius_mm


def _smooth_size(n: int) -> int:
    """Smallest even number >= n whose prime factors are 2, 3 and 5 (fast FFT sizes)."""
    m = max(int(n), 16)
    while True:
        k = m
        for f in (2, 3, 5):
            while k % f == 0:
                k //= f
        if k == 1 and m % 2 == 0:
            return m
        m += 1


@functools.lru_cache(maxsize=64)
def scene_contact_tile(
    roughness: Roughness, n_points: int, seed: int, pressure_Pa: float
) -> ContactField:
    """The rough contact of one periodic tile (``n_points`` per side at the roughness's grid
    spacing) under the nominal pressure ``pressure_Pa`` (cached)."""
    size = n_points * roughness.grid_spacing_mm
    if size < roughness.long_wavelength_mm:
        raise ValueError(
            f"roughness {roughness.name!r}: a tile of {n_points} points ({size:.3g} mm) is "
            f"shorter than the long wavelength {roughness.long_wavelength_mm} mm"
        )
    h = rough_heights(roughness, size, n_points, seed)
    return solve_contact(h, size, pressure_Pa, e_star_Pa())


@functools.lru_cache(maxsize=8)
def scene_contact(setup: PhysicalSetup) -> ContactField:
    """Solve the scene's contact once (cached per setup).

    Returns
    -------
    ContactField
        On a tile centred on the contact centre: the pad's repeating tile, or the sphere's
        tile with the sphere at its centre.
    """
    rough = setup.roughness
    dx = rough.grid_spacing_mm
    if setup.scene == "rough_pad":
        want = max(2.0 * setup.pad_radius_mm, 2.0 * rough.long_wavelength_mm)
        n = min(_smooth_size(math.ceil(want / dx)), MAX_TILE_POINTS)
        return scene_contact_tile(rough, n, setup.seed, setup.pressure_Pa)
    a = setup.hertz_radius_mm
    want = max(SPHERE_TILE_RADII * a, 2.0 * rough.long_wavelength_mm)
    n = _smooth_size(math.ceil(want / dx))
    size = n * dx
    h = rough_heights(rough, size, n, setup.seed)
    x = ((np.arange(n) + 0.5) / n - 0.5) * size * 1e-3
    r2 = x[None, :] ** 2 + x[:, None] ** 2
    profile = h - r2 / (2.0 * setup.sphere_radius_mm * 1e-3)
    load_N = setup.pressure_Pa * math.pi * (a * 1e-3) ** 2
    return solve_contact(profile, size, load_N / (size * 1e-3) ** 2, e_star_Pa())


@dataclass(frozen=True)
class PhysicalRender:
    """A physical scene on the camera's pixels.

    Attributes
    ----------
    reflectance : (H, W) ndarray of float32
        Mean reflected light of each pixel relative to the free surface (1 away from the
        contact), after the lens blur.
    covered : (H, W) ndarray of float32
        Share of each pixel's area in true contact (gap 0).
    near : (H, W) ndarray of float32
        Share of each pixel's area with a gap below a tenth of the evanescent depth.
    nominal : (H, W) ndarray of float32
        Share of each pixel's area inside the nominal contact disc.
    optical : (H, W) ndarray of float32
        Each pixel's optical contact: its darkness ``1 - R(gap)`` before the lens blur, over
        the darkness of full contact ``1 - R(0)`` (a gap within the evanescent depth darkens
        too: the share a perfect TIR reading counts as contact).
    """

    reflectance: np.ndarray
    covered: np.ndarray
    near: np.ndarray
    nominal: np.ndarray
    optical: np.ndarray


def _tile_lookup(
    field: np.ndarray, x_mm: np.ndarray, y_mm: np.ndarray, origin: tuple[float, float], dx: float
) -> np.ndarray:
    """Values of a periodic tile at image points (nearest grid cell, wrapping)."""
    n = field.shape[0]
    i = np.floor((x_mm - origin[0]) / dx).astype(np.int64) % n
    j = np.floor((y_mm - origin[1]) / dx).astype(np.int64) % n
    return field[j, i]


def render_physical(
    setup: PhysicalSetup, *, height_px: int, width_px: int, mm_per_px: float
) -> PhysicalRender:
    """Render the scene's reflected light and its truth fields on the camera's pixels.

    Each pixel is sampled on an ``S x S`` sub-grid with ``S = ceil(mm_per_px / dx)`` (``dx``
    the solver grid), so every solver cell under a pixel is seen at least once; the lens
    blur is a Gaussian on that sub-grid; pixel values are sub-grid means.
    """
    contact = scene_contact(setup)
    dx = contact.grid_spacing_mm
    ss = max(1, math.ceil(mm_per_px / dx - 1e-9))
    step = mm_per_px / ss
    cx, cy = setup.centre_mm
    radius = setup.nominal_radius_mm
    reach = radius + 4.0 * setup.optical_blur_mm + 2.0 * mm_per_px
    if setup.scene == "rough_sphere":
        reach = max(reach, 0.5 * contact.size_mm)
    c0 = max(math.floor((cx - reach) / mm_per_px), 0)
    c1 = min(math.ceil((cx + reach) / mm_per_px), width_px)
    r0 = max(math.floor((cy - reach) / mm_per_px), 0)
    r1 = min(math.ceil((cy + reach) / mm_per_px), height_px)
    shape = (height_px, width_px)
    refl = np.ones(shape, dtype=np.float32)
    covered = np.zeros(shape, dtype=np.float32)
    near = np.zeros(shape, dtype=np.float32)
    nominal = np.zeros(shape, dtype=np.float32)
    optical = np.zeros(shape, dtype=np.float32)
    if c0 >= c1 or r0 >= r1:
        return PhysicalRender(refl, covered, near, nominal, optical)
    sub = (np.arange(ss) + 0.5) / ss
    xs = ((np.arange(c0, c1)[:, None] + sub[None, :]).ravel() * mm_per_px)[None, :]
    ys = ((np.arange(r0, r1)[:, None] + sub[None, :]).ravel() * mm_per_px)[:, None]
    half = 0.5 * contact.size_mm
    origin = (cx - half, cy - half)
    gap = _tile_lookup(contact.gap_m, xs, ys, origin, dx)
    inside_disc = (xs - cx) ** 2 + (ys - cy) ** 2 <= radius * radius
    if setup.scene == "rough_pad":
        gap = np.where(inside_disc, gap, np.inf)
    else:
        on_tile = (np.abs(xs - cx) < half) & (np.abs(ys - cy) < half)
        gap = np.where(on_tile, gap, np.inf)
    light = setup.optics.reflectance(gap)
    optical[r0:r1, c0:c1] = pool((1.0 - light) / setup.optics.contact_darkness, ss)
    if setup.optical_blur_mm > 0.0:
        light = gaussian_filter(light, setup.optical_blur_mm / step, mode="nearest")
    depth = setup.optics.evanescent_depth_m
    refl[r0:r1, c0:c1] = pool(light, ss)
    covered[r0:r1, c0:c1] = pool((gap == 0.0).astype(np.float64), ss)
    near[r0:r1, c0:c1] = pool((gap < 0.1 * depth).astype(np.float64), ss)
    nominal[r0:r1, c0:c1] = pool(inside_disc.astype(np.float64), ss)
    return PhysicalRender(refl, covered, near, nominal, optical)
