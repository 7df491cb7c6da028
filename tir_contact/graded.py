"""Element runs of graded contact: a field of junctions below the pixel.

A tread block's face of rough rubber on ice is not a plateau of full darkness. Real
contact covers a few to about 30 % of it, in junctions smaller than a pixel, densest at the
front edge where the pressure peaks and thinning towards the back. The half-coverage runs of
:mod:`tir_contact.features` (step 1: columns holding at least half as many contact pixels
as the column holding the most) then hold only the dark front of each face: the faces'
contact lengths read a tenth to a half of the truth, and a template fitted to one-pixel
runs numbers the elements wrongly (a physical G3 block at 13 % real contact: four faces
of 4.3 mm in contact, one run of 1.1 mm found and given to the last element).

Model of a column (the contact's ``R`` rows): where no contact lies, its mean darkness is
the free surface's, ``b``, with noise ``s / sqrt(R)``, ``s`` one pixel's noise over its
correlation area (``sigma sqrt(corr_px)``, :class:`tir_contact.measure.AreaModel`). A column
holds contact where its mean lies more than :data:`PRESENCE_Z` noise sigmas above ``b``
(one false column in 30 000). A plateau's half-coverage runs hold every column that holds
contact but the blur's one or two at each edge, a smooth grey face's half of them or more;
a video's contact is *graded* where in the median sampled frame they hold less than
:data:`GRADED_SHARE` of them (:func:`graded_contact`: the rubber's and the load's property,
decided once per video; a frame's share scatters about it). In such a video the runs are
the columns that hold contact (:data:`MIN_RUN_PX` at least), their edges the crossings of
the presence level, and each column's contact area the unmixed darkness
``R (p - b) / (c - b)``, ``c`` full contact's darkness (the measurement's reading,
:func:`tir_contact.measure.frame_area`). Elsewhere nothing changes.

The presence level lies near the free surface: both edges are read at the blur's foot, up
to about two blur sigmas outside a sharp edge (the physical blocks' fronts, 0.04-0.1 mm
ahead), while a back where the pressure and with it the real contact thin out gradually
reads short by the columns whose contact lies below the level.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import cv2
import numpy as np

from tir_contact._columns import column_mean

__all__ = ["GRADED_SHARE", "MIN_RUN_PX", "PRESENCE_Z", "FreeLevel", "GradedRuns",
           "graded_contact", "graded_runs", "graded_share", "presence_runs"]

#: Noise sigmas a column's mean darkness must clear to hold contact: a false column at a
#: rate of 3e-5 (one in about a hundred frames of 300 columns).
PRESENCE_Z = 4.0

#: Contact is graded where the half-coverage runs hold less than this share of the columns
#: that hold contact. A plateau's hold all but its blurred edge columns; a face whose grey
#: follows a smooth pressure profile holds half of them or more (a linear fall to zero: a
#: half; a parabola: 0.71), blur taking that to about 0.4; a field of junctions below the
#: pixel, which reach half coverage only in the dense band at each face's front, a fifth or
#: less.
GRADED_SHARE = 1.0 / 3.0

#: Shortest run (columns) of graded contact: a single column above the presence level is
#: taken for noise.
MIN_RUN_PX = 2


class FreeLevel(NamedTuple):
    """The free surface and full contact in darkness, for the presence test.

    Attributes
    ----------
    offset : float
        Mean darkness of the free surface.
    sigma_px : float
        One pixel's darkness noise over its correlation area (``sigma sqrt(corr_px)``).
    full : float
        Darkness of full contact.
    """

    offset: float
    sigma_px: float
    full: float

    def level(self, n_rows: int) -> float:
        """Mean darkness a column of `n_rows` rows must exceed to hold contact."""
        return self.offset + PRESENCE_Z * self.sigma_px / math.sqrt(max(n_rows, 1))


class GradedRuns(NamedTuple):
    """Runs of graded contact (first and last column of each, in the columns of the
    profile they were found on) with the presence level their edges cross and each
    column's contact area (px)."""

    starts: list[int]
    ends: list[int]
    level: float
    column_px: np.ndarray


def presence_runs(p: np.ndarray, level: float, min_px: int = MIN_RUN_PX
                  ) -> tuple[list[int], list[int]]:
    """First and last index of each run of ``p > level`` at least `min_px` long.

    Examples
    --------
    >>> presence_runs(np.array([0, 1, 1, 0, 1, 0, 1, 1, 1.0]), 0.5)
    ([1, 6], [2, 8])
    """
    on = np.zeros(p.size + 2, np.bool_)
    np.greater(p, level, out=on[1:-1])
    change = np.flatnonzero(on[1:] != on[:-1])
    starts, stops = change[0::2], change[1::2]
    keep = stops - starts >= min_px
    return starts[keep].tolist(), (stops[keep] - 1).tolist()


def graded_runs(p: np.ndarray, n_rows: int, free: FreeLevel) -> GradedRuns | None:
    """The runs of graded contact on the column-mean darkness `p` (module notes), None where
    no column holds contact.

    Parameters
    ----------
    p : (N,) ndarray
        Mean darkness of each column over the contact's `n_rows` rows (NaN: not measured).
    n_rows : int
    free : FreeLevel

    Examples
    --------
    A face whose contact thins from the front (column 10) to the back (column 29) above a
    free surface at 0.02 (noise 0.02 a pixel, 100 rows): 20 columns hold contact, 632 px of
    it unmixed.

    >>> p = np.full(40, 0.02)
    >>> p[10:30] = np.linspace(0.6, 0.04, 20)
    >>> g = graded_runs(p, 100, FreeLevel(0.02, 0.02, 0.97))
    >>> g.starts, g.ends, round(g.level, 3), round(float(g.column_px[10:30].sum()))
    ([10], [29], 0.028, 632)
    """
    level = free.level(n_rows)
    finite = np.nan_to_num(p, nan=free.offset)
    starts, ends = presence_runs(finite, level)
    if not starts:
        return None
    column_px = (finite - free.offset) * (n_rows / max(free.full - free.offset, 1e-6))
    return GradedRuns(starts, ends, level, column_px)


def graded_share(d: np.ndarray, threshold: float, free: FreeLevel) -> float | None:
    """Share of the columns holding contact that the half-coverage runs hold in one frame's
    darkness `d` (NaN: not measured), over the rows holding half-coverage contact; only the
    presence runs that hold half-coverage contact count (a face's faint back, not the free
    surface's texture elsewhere). None without half-coverage contact.

    Examples
    --------
    >>> d = np.full((50, 40), 0.02, np.float32)
    >>> d[:, 10:13] = 0.9              # a face's dense front ...
    >>> d[:, 13:30] = 0.1              # ... and its junction field
    >>> round(graded_share(d, 0.45, FreeLevel(0.02, 0.02, 0.97)), 3)
    0.15
    """
    d = np.asarray(d, np.float32)
    if d.size == 0:
        return None
    with np.errstate(invalid="ignore"):
        half = (d >= threshold).view(np.uint8)
    counts = cv2.reduce(half, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
    top = int(counts.max())
    if top == 0:
        return None
    rows = np.flatnonzero(cv2.reduce(half, 1, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel())
    r0, r1 = int(rows[0]), int(rows[-1]) + 1
    p = column_mean(d, r0, r1, 0, d.shape[1], fill=free.offset)
    on = counts >= (top + 1) // 2  # the half-coverage runs' rule (tir_contact.features)
    starts, ends = presence_runs(p, free.level(r1 - r0), 1)
    held = [e - s + 1 for s, e in zip(starts, ends, strict=True) if on[s:e + 1].any()]
    return int(np.count_nonzero(on)) / sum(held) if held else None


def graded_contact(samples: list[np.ndarray], threshold: float, free: FreeLevel) -> bool:
    """Whether a video's contact is graded: the median :func:`graded_share` of its sampled
    frames' darkness with half-coverage contact lies under :data:`GRADED_SHARE` (the
    rubber's and the load's property, decided once: a frame's share scatters about it).

    Examples
    --------
    >>> d = np.full((50, 40), 0.02, np.float32)
    >>> d[:, 10:13] = 0.9
    >>> d[:, 13:30] = 0.1
    >>> graded_contact([d, d], 0.45, FreeLevel(0.02, 0.02, 0.97))
    True
    >>> d[:, 13:30] = 0.9              # a plateau
    >>> graded_contact([d], 0.45, FreeLevel(0.02, 0.02, 0.97))
    False
    """
    shares = [s for d in samples if (s := graded_share(d, threshold, free)) is not None]
    return bool(shares) and float(np.median(shares)) < GRADED_SHARE
