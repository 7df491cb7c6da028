"""The sliding block with physical real contact (private helper of :mod:`synthetic.footage`).

``real_contact="physical"``: every element's face is rough; where the block model presses
it (its pressure cells along ``xi``, :func:`synthetic._render_tir.pressure_cells`), the
rough contact at that local pressure is the solved contact of :mod:`synthetic.roughness`,
and its light the frustrated-TIR reflectance of :mod:`synthetic.ftir`.

Precompute, then translate
--------------------------
1. The rough contact is solved once per pressure level on one periodic tile (``TILE_POINTS``
   points per side): levels a factor ``LEVEL_RATIO`` apart from a quarter of the nominal
   pressure to above the highest cell pressure of the clip's first frame. A cell of the
   face takes the level nearest its pressure (in log): every point of the face shows a
   state solved by the contact solver, at a pressure within +-19 % of its own.
2. Each level's reflectance, contact and near-contact indicator are averaged over the
   pixel rows (the block moves along the image x axis, so a pixel row always sees the same
   band of the rubber) and over bins of ``bin_mm`` along ``xi``. Each element has its own
   random offset into the tile, so neighbouring elements do not show one pattern.
3. A frame gathers, for every ``xi`` bin, the level of its cell, and integrates the bins
   over each pixel's footprint (and the exposure's motion) exactly: cumulative sums of a
   piecewise-constant profile, as :class:`synthetic._render_tir.StepProfile` does in one
   dimension.

The truth is integrated from the same bins without motion blur (the state at the frame's
centre time): true contact (gap 0) and near contact (gap below a tenth of the evanescent
depth) of every element inside the lit mask.

Assumptions: rotation 0 (the path along the image rows); the rubber's roughness travels
with the block and the ice is smooth (thesis section 2.2: polished by the run-in); a tile
repeats along an element (about 1.3 mm at the default roughness).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from synthetic._physical import scene_contact_tile
from synthetic.ftir import FtirOptics
from synthetic.roughness import Roughness

__all__ = [
    "LEVEL_RATIO",
    "TILE_POINTS",
    "BinIntegrals",
    "FrameBins",
    "PhysicalBlock",
    "level_index",
    "level_pressures_Pa",
    "physical_fractions",
]

#: Grid points per side of the block's rough tile (256: a level solves in about 0.5 s).
TILE_POINTS = 256
#: Pressure ratio of neighbouring levels: sqrt(2), so a cell is within 2^(1/4) (19 %) of
#: its level.
LEVEL_RATIO = math.sqrt(2.0)


class FrameBins(NamedTuple):
    """One frame's face on ``xi`` bins, for every pixel row the block covers."""

    dark: np.ndarray  # (rows, M) darkness 1 - R
    covered: np.ndarray  # (rows, M) share in true contact
    near: np.ndarray  # (rows, M) share within a tenth of the evanescent depth
    xi0_mm: float  # xi of the first bin's start
    element: np.ndarray  # (M,) element of each bin, -1 outside contact


@dataclass(frozen=True)
class _Levels:
    pressure_Pa: np.ndarray  # (K,)
    light: np.ndarray  # (n_elem, K, rows, nb) reflectance row means
    covered: np.ndarray  # (n_elem, K, rows, nb)
    near: np.ndarray  # (n_elem, K, rows, nb)


def _periodic_row_means(tile: np.ndarray, starts: np.ndarray, width: float) -> np.ndarray:
    """Means of a periodic tile's rows over ``[s, s + width)`` (rows, fractional) per start."""
    n = tile.shape[0]
    cum = np.concatenate([np.zeros((1, tile.shape[1])), np.cumsum(tile, axis=0)])
    total = cum[-1]

    def integral(t: np.ndarray) -> np.ndarray:
        k = np.floor(t).astype(np.int64)
        wraps, i = np.divmod(k, n)
        frac = (t - k)[:, None]
        return wraps[:, None] * total[None, :] + cum[i] + frac * tile[i]

    return (integral(starts + width) - integral(starts)) / width


def level_pressures_Pa(nominal_pressure_Pa: float, max_pressure_Pa: float) -> np.ndarray:
    """The pressure levels of a clip: a quarter of the nominal pressure upwards by
    :data:`LEVEL_RATIO`, to the first level at or past ``max_pressure_Pa``."""
    lo = 0.25 * nominal_pressure_Pa
    n_levels = max(2, math.ceil(math.log(max(max_pressure_Pa, lo) / lo, LEVEL_RATIO)) + 1)
    return lo * LEVEL_RATIO ** np.arange(n_levels)


def level_index(pressure_Pa: np.ndarray, levels_Pa: np.ndarray) -> np.ndarray:
    """Index of the level nearest (in log) to each pressure, clipped to the levels."""
    p = np.maximum(np.asarray(pressure_Pa, dtype=np.float64), 1e-30)
    j = np.rint(np.log(p / levels_Pa[0]) / math.log(LEVEL_RATIO))
    return np.clip(j, 0, levels_Pa.size - 1).astype(np.int64)


def physical_fractions(
    roughness: Roughness, seed: int, pressure_Pa: np.ndarray, nominal_pressure_Pa: float
) -> np.ndarray:
    """Solved real-contact share ``A_r / A_0`` of the level each pressure takes (0 at 0)."""
    p = np.asarray(pressure_Pa, dtype=np.float64)
    levels = level_pressures_Pa(nominal_pressure_Pa, float(p.max()) if p.size else 0.0)
    j = level_index(p, levels)
    share = np.array(
        [
            scene_contact_tile(roughness, TILE_POINTS, seed, float(q)).contact_fraction
            for q in levels
        ]
    )
    return np.where(p > 0, share[j], 0.0)


class PhysicalBlock:
    """Precomputed physical contact of a block's faces (see the module notes).

    Parameters
    ----------
    roughness : Roughness
    optics : FtirOptics
    seed : int
    n_elements : int
    row_v_mm : (rows,) ndarray
        Lateral coordinate ``v`` (from the block centreline) of the top of each pixel row
        the block can cover, mm.
    mm_per_px : float
    nominal_pressure_Pa : float
    max_pressure_Pa : float
        Highest cell pressure to cover with a level.
    """

    def __init__(
        self,
        roughness: Roughness,
        optics: FtirOptics,
        seed: int,
        *,
        n_elements: int,
        row_v_mm: np.ndarray,
        mm_per_px: float,
        nominal_pressure_Pa: float,
        max_pressure_Pa: float,
    ) -> None:
        dx = roughness.grid_spacing_mm
        self.tile_mm = TILE_POINTS * dx
        k = 1
        while k * 2 * dx <= mm_per_px / 8.0 and TILE_POINTS % (k * 2) == 0:
            k *= 2
        self.bin_mm = k * dx
        self.nb = TILE_POINTS // k
        levels = level_pressures_Pa(nominal_pressure_Pa, max_pressure_Pa)
        n_levels = levels.size
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(4,)))
        self.offsets_mm = rng.uniform(0.0, self.tile_mm, size=(n_elements, 2))  # (xi, v)
        depth = optics.evanescent_depth_m
        shape = (n_elements, n_levels, row_v_mm.size, self.nb)
        light = np.empty(shape, np.float32)
        covered = np.empty(shape, np.float32)
        near = np.empty(shape, np.float32)
        for j, p in enumerate(levels):
            solved = scene_contact_tile(roughness, TILE_POINTS, seed, float(p))
            maps = (
                optics.reflectance(solved.gap_m),
                (solved.gap_m == 0.0).astype(np.float64),
                (solved.gap_m < 0.1 * depth).astype(np.float64),
            )
            for e in range(n_elements):
                starts = (row_v_mm - self.offsets_mm[e, 1]) / dx
                for out, m in zip((light, covered, near), maps, strict=True):
                    rows = _periodic_row_means(m, starts, mm_per_px / dx)
                    out[e, j] = rows.reshape(rows.shape[0], self.nb, k).mean(axis=2)
        self.levels = _Levels(levels, light, covered, near)

    def bins(self, nodes: np.ndarray, p_mid: np.ndarray, elem: np.ndarray) -> FrameBins:
        """Darkness, contact and near-contact of every row and ``xi`` bin of one frame.

        Parameters
        ----------
        nodes, p_mid, elem
            The pressure cells of the frame (:func:`synthetic._render_tir.pressure_cells`).

        Returns
        -------
        FrameBins
        """
        d = self.bin_mm
        xi0 = math.floor(float(nodes[0]) / d) * d
        m = max(1, math.ceil((float(nodes[-1]) - xi0) / d))
        centres = xi0 + (np.arange(m) + 0.5) * d
        k = np.searchsorted(nodes, centres, side="right") - 1
        inside = (k >= 0) & (k < p_mid.size)
        kk = np.clip(k, 0, max(p_mid.size - 1, 0))
        p = np.where(inside, p_mid[kk], 0.0)
        e = np.where(inside & (p > 0), elem[kk], -1)
        lv = self.levels
        j = level_index(p, lv.pressure_Pa)
        ee = np.maximum(e, 0)
        col = np.floor((centres - self.offsets_mm[ee, 0]) / d).astype(np.int64) % self.nb
        touch = (e >= 0)[None, :]
        dark = np.where(touch, 1.0 - lv.light[ee, j, :, col].T, 0.0)
        covered = np.where(touch, lv.covered[ee, j, :, col].T, 0.0)
        near = np.where(touch, lv.near[ee, j, :, col].T, 0.0)
        return FrameBins(dark, covered, near, xi0, e)


class BinIntegrals:
    """First and second integrals of piecewise-constant rows along ``xi`` (bins of
    ``bin_mm`` from ``xi0_mm``), for exact box means over pixel footprints.

    Built once per model state; :meth:`box_means` then costs two gathers per query. The
    arithmetic is :meth:`synthetic._render_tir.StepProfile.box_mean`'s on a uniform grid and
    for many rows at once.
    """

    def __init__(self, values: np.ndarray, xi0_mm: float, bin_mm: float) -> None:
        rows, m = values.shape
        self.values, self.xi0, self.d, self.m = values, float(xi0_mm), float(bin_mm), m
        d = self.d
        self.f = np.concatenate([np.zeros((rows, 1)), np.cumsum(values, axis=1) * d], axis=1)
        inc = self.f[:, :-1] * d + 0.5 * values * d * d
        self.g = np.concatenate([np.zeros((rows, 1)), np.cumsum(inc, axis=1)], axis=1)
        self.low = min(0.0, float(values.min())) if values.size else 0.0
        self.high = max(0.0, float(values.max())) if values.size else 0.0

    def _locate(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = (q - self.xi0) / self.d
        tc = np.clip(t, 0.0, self.m)
        i = np.minimum(np.floor(tc).astype(np.int64), self.m - 1)
        return t, i, (tc - i) * self.d

    def first(self, q: np.ndarray) -> np.ndarray:
        """``int_-inf^q`` of each row, (rows, len(q))."""
        _, i, tau = self._locate(q)
        return self.f[:, i] + self.values[:, i] * tau

    def second(self, q: np.ndarray) -> np.ndarray:
        """Second integral of each row at ``q``, (rows, len(q))."""
        t, i, tau = self._locate(q)
        inner = self.g[:, i] + self.f[:, i] * tau + 0.5 * self.values[:, i] * tau * tau
        return inner + self.f[:, -1:] * (np.maximum(t - self.m, 0.0) * self.d)

    def box_means(self, lo: np.ndarray, hi: np.ndarray, blur_mm: float = 0.0) -> np.ndarray:
        """Means over ``[lo, hi]`` (mm), box-blurred by ``blur_mm``; (rows, len(lo)).

        Clipped to the hull of the values and 0 (cancellation can step 1e-9 outside it).
        """
        width = hi - lo
        if blur_mm <= 0.01 * float(np.min(np.abs(width))):
            out = (self.first(hi) - self.first(lo)) / width
        else:
            h = 0.5 * blur_mm
            out = (
                self.second(hi + h) - self.second(lo + h) - self.second(hi - h)
                + self.second(lo - h)
            ) / (width * blur_mm)
        return np.clip(out, self.low, self.high)
