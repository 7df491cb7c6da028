"""Patchy real contact and static contact scenes, drawn on a supersampled grid (private
helpers of :mod:`synthetic.footage`).

Real contact (Fig. 4.21)
------------------------
Inside the nominal contact the rubber touches the ice only in micro-contact patches. The
patches are a level set of a smooth random field fixed to the rubber: white noise on a grid
of spacing ``px / SUPERSAMPLE`` filtered by a Gaussian of standard deviation
``correlation_mm`` and turned into a uniform field ``U`` in (0, 1) by its ranks. A point of
the nominal contact is in real contact where ``U < phi(p)``, ``phi`` the real contact
fraction of the friction model at the local pressure ``p``
(:func:`friction_model.real_contact_fraction`): the covered share of a region with constant
pressure is ``phi`` (exactly over the whole texture, up to the finite sample of
independent patches over a part of it), and more of the face touches where the pressure is
higher (the front edge).

Every pixel is sampled at ``SUPERSAMPLE x SUPERSAMPLE`` points; its coverage is the share of
its samples in real contact, and its darkness the mean of ``D(p)`` over the covered samples
(0 over the others). The ground-truth real area is the sum of the coverage times the pixel
area: exact for what is drawn.

Static scenes
-------------
Pressure fields in image coordinates (mm, origin at the top-left image corner), each
carrying the nominal load ``p_nominal * A`` over its nominal area ``A``:

* ``round_pad``: a disc of radius ``a``, Hertz-like ``p = 3/2 p_n sqrt(1 - r^2 / a^2)``.
* ``coin``: an annulus ``r_i <= r <= r_o`` (the rim of a flat coin), across the rim the
  elliptic strip profile ``p = 4/pi p_n sqrt(1 - s^2)``, ``s`` from -1 at ``r_i`` to 1 at
  ``r_o``.
* ``three_point``: three discs of radius ``a`` with the Hertz-like profile.
"""

from __future__ import annotations

import functools
import logging
import math
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter

from friction_model import DryWetParameters, real_contact_fraction
from synthetic._render_tir import pressure_cells

__all__ = [
    "SUPERSAMPLE",
    "PatchTexture",
    "StaticScene",
    "pool",
    "pressure_cells",
    "real_fraction",
    "sample_points",
]

logger = logging.getLogger(__name__)

#: Samples per pixel along each axis for patchy and static contact.
SUPERSAMPLE = 4


def sample_points(
    rows: tuple[int, int], cols: tuple[int, int], mm_per_px: float, ss: int = SUPERSAMPLE
) -> tuple[np.ndarray, np.ndarray]:
    """x ((1, n_c ss)) and y ((n_r ss, 1)) of the sub-pixel sample centres, mm.

    ``rows`` and ``cols`` are half-open pixel ranges.
    """
    sub = (np.arange(ss) + 0.5) / ss
    cs = (np.arange(cols[0], cols[1])[:, None] + sub[None, :]).ravel() * mm_per_px
    rs = (np.arange(rows[0], rows[1])[:, None] + sub[None, :]).ravel() * mm_per_px
    return cs[None, :], rs[:, None]


def pool(samples: np.ndarray, ss: int = SUPERSAMPLE) -> np.ndarray:
    """Mean over ``ss x ss`` blocks: (R ss, C ss) -> (R, C)."""
    r, c = samples.shape[0] // ss, samples.shape[1] // ss
    return samples.reshape(r, ss, c, ss).mean(axis=(1, 3))


class PatchTexture:
    """Uniform random field ``U`` in (0, 1) with smooth patches, on a regular grid.

    Parameters
    ----------
    origin_mm : (float, float)
        Coordinates (a, b) of the grid's first node, mm.
    extent_mm : (float, float)
        Extent along a and b, mm.
    spacing_mm : float
        Node spacing, mm.
    correlation_mm : float
        Standard deviation of the Gaussian filter, mm (the patch size is about twice it).
    rng : numpy.random.Generator
    """

    def __init__(
        self,
        origin_mm: tuple[float, float],
        extent_mm: tuple[float, float],
        spacing_mm: float,
        correlation_mm: float,
        rng: np.random.Generator,
    ) -> None:
        na = max(1, math.ceil(extent_mm[0] / spacing_mm) + 1)
        nb = max(1, math.ceil(extent_mm[1] / spacing_mm) + 1)
        field = rng.standard_normal((na, nb)).astype(np.float32)
        field = gaussian_filter(field, sigma=correlation_mm / spacing_mm, mode="wrap")
        ranks = np.empty(field.size, dtype=np.float64)
        ranks[np.argsort(field, axis=None, kind="stable")] = np.arange(field.size)
        self.values = ((ranks + 0.5) / field.size).reshape(na, nb).astype(np.float32)
        self.origin = origin_mm
        self.spacing = spacing_mm

    def grid(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """U on the grid of 1-D ``a`` (columns) and ``b`` (rows): shape (b.size, a.size)."""
        ia = np.clip(np.rint((a - self.origin[0]) / self.spacing), 0, self.values.shape[0] - 1)
        ib = np.clip(np.rint((b - self.origin[1]) / self.spacing), 0, self.values.shape[1] - 1)
        return self.values[ia.astype(np.intp)][:, ib.astype(np.intp)].T

    def __call__(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """U at the points (a, b) (mm), nearest node; points off the grid clamp to its edge."""
        ia = np.clip(np.rint((a - self.origin[0]) / self.spacing), 0, self.values.shape[0] - 1)
        ib = np.clip(np.rint((b - self.origin[1]) / self.spacing), 0, self.values.shape[1] - 1)
        return self.values[ia.astype(np.intp), ib.astype(np.intp)]


@dataclass(frozen=True)
class StaticScene:
    """A static contact: discs or an annulus in image coordinates, mm.

    Attributes
    ----------
    kind : {"round_pad", "coin", "three_point"}
    centres_mm : ((n, 2) tuple)
        Centre (x, y) of each contact, mm.
    radius_mm : float
        Disc radius (pad, points) or outer radius (coin), mm.
    inner_radius_mm : float
        Coin: inner radius of the contact rim, mm (0 for discs).
    pressure_Pa : float
        Mean pressure over the nominal contact area, Pa.
    """

    kind: str
    centres_mm: tuple[tuple[float, float], ...]
    radius_mm: float
    inner_radius_mm: float
    pressure_Pa: float

    @property
    def element_area_mm2(self) -> float:
        """Nominal area of one contact, mm^2."""
        return math.pi * (self.radius_mm**2 - self.inner_radius_mm**2)

    @property
    def peak_pressure_Pa(self) -> float:
        """Largest pressure of the profile, Pa."""
        return self.pressure_Pa * (4.0 / math.pi if self.kind == "coin" else 1.5)

    def pressure(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pressure (Pa, 0 outside) and contact index (-1 outside) at the points (x, y)."""
        shape = np.broadcast_shapes(np.shape(x), np.shape(y))
        p = np.zeros(shape)
        idx = np.full(shape, -1, dtype=np.intp)
        for i, (xc, yc) in enumerate(self.centres_mm):
            r = np.hypot(x - xc, y - yc)
            if self.kind == "coin":
                half = 0.5 * (self.radius_mm - self.inner_radius_mm)
                s = (r - 0.5 * (self.radius_mm + self.inner_radius_mm)) / half
                inside = np.abs(s) < 1.0
                val = 4.0 / math.pi * self.pressure_Pa * np.sqrt(np.clip(1.0 - s * s, 0.0, 1.0))
            else:
                inside = r < self.radius_mm
                q = np.clip(1.0 - (r / self.radius_mm) ** 2, 0.0, 1.0)
                val = 1.5 * self.pressure_Pa * np.sqrt(q)
            p = np.where(inside, val, p)
            idx = np.where(inside, i, idx)
        return p, idx

    def bbox_px(
        self, mm_per_px: float, height_px: int, width_px: int
    ) -> tuple[tuple[int, int], tuple[int, int]]:
        """Half-open pixel row and column ranges that hold every contact (clipped)."""
        c = np.asarray(self.centres_mm)
        r = self.radius_mm
        c0 = max(math.floor((c[:, 0].min() - r) / mm_per_px) - 1, 0)
        c1 = min(math.ceil((c[:, 0].max() + r) / mm_per_px) + 1, width_px)
        r0 = max(math.floor((c[:, 1].min() - r) / mm_per_px) - 1, 0)
        r1 = min(math.ceil((c[:, 1].max() + r) / mm_per_px) + 1, height_px)
        return (r0, max(r0, r1)), (c0, max(c0, c1))


def real_fraction(pressure_Pa: np.ndarray) -> np.ndarray:
    """Real contact fraction phi(p) of the friction model at its default parameters.

    :func:`friction_model.real_contact_fraction` with
    :class:`friction_model.DryWetParameters` (``phi = clip(0.68 (p / 2.5 bar)^0.22, 0.01,
    1)`` at the time of writing); 0 where ``p <= 0``.
    """
    p = np.asarray(pressure_Pa, dtype=np.float64)
    phi = np.asarray(real_contact_fraction(np.maximum(p, 1e-300), _default_params()))
    return np.where(p > 0, phi, 0.0)


@functools.cache
def _default_params() -> DryWetParameters:
    """The default dry/wet parameters (one instance per process)."""
    return DryWetParameters()
