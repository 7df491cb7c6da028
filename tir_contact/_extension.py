"""The light continued past the image border for the free-surface closing
(:func:`tir_contact.reference._closing`).

A grey closing by a disc fills every dark region a disc cannot fit into, so what lies past
the border decides what is filled at it. The image is continued by odd reflection
(``2 f(border) - f(inside)``, capped at the border value): a light that falls towards the
border goes on falling, and a dark contact at the border stays dark past it, bounded by
the light beside it, so that the closing fills it.

Where the lit zone's rim crosses the border (a lit disc or ellipse larger than the frame,
a band cut by it), odd reflection is wrong to first order: the rim's light rises from the
dark outside to a plateau, the reflection of a saturating rise narrows the lit part by
about half the rim's width at once, and the plateau goes on straight past the border. The
lit zone's brighter-than sets then have a notch at the border that the zone itself does
not have, and the closing fills the rim there: a lit disc cut by the top and bottom
borders read four false contacts where its rim meets them (0.04-0.12 mm2 each, a static
pad 3-6 % high). So past each border the zone's plateau is continued along its edge's
secant over the few px inside (a convex zone stays convex), and outside that continuation
the light is free (the darkest value): nothing lies there that the closing must fill. The
plateau is the lit part of the border less the rim's rising flank (:func:`rising_flank`):
a contact at the border lies in the lit zone with the plateau's light on either side of
it along the border, and a rise that has not dipped since the unlit outside is no
contact's edge.
"""

from __future__ import annotations

import numpy as np

__all__ = ["FLANK_RISE", "STEP_PX", "continued_lit", "extend_past_border", "rising_flank"]

#: Share of the light's plateau below which a border pixel on the rise from the unlit
#: outside counts as the rim's flank, and the share of it by which the rise may dip (the
#: smoothed light's noise) and still be one rise: the default candidate darkness of the
#: free surface (:func:`tir_contact.reference.free_surface`, 0.1), below which no pixel
#: is a contact candidate, so that a dip the closing must fill is not mistaken for a rise.
FLANK_RISE = 0.1


#: How far inside the border (working px) the zone's edge is read to continue it: a few
#: px, so that the secant is the edge's tangent to within the rim's curvature (a lit disc
#: of 70 working px radius: 0.06 px a row at 4 px) and the edge's pixel steps (0.5 px)
#: move it by at most 0.1 px a row.
STEP_PX = 5


def _running_max_since(g: np.ndarray, start: np.ndarray) -> np.ndarray:
    """The running maximum of `g` restarted at every True of `start`."""
    seg = np.cumsum(start)
    span = float(np.ptp(g)) + 1.0
    return np.maximum.accumulate(g + seg * span) - seg * span


def _flank_from_left(g: np.ndarray, unlit: np.ndarray, reach_px: int) -> np.ndarray:
    """Lit pixels of the border line `g` reached from an unlit pixel on their left by a
    rise that never dips by over :data:`FLANK_RISE` of its running maximum, darker than
    ``1 - FLANK_RISE`` of the brightest light within `reach_px` to their right."""
    after_unlit = np.cumsum(unlit) > 0
    top = _running_max_since(g, unlit)
    dips = np.cumsum((g < (1.0 - FLANK_RISE) * top) & ~unlit)
    # dips since the last unlit pixel: the count less its value there
    rising = dips == np.maximum.accumulate(np.where(unlit, dips, 0))
    windows = np.lib.stride_tricks.sliding_window_view(
        np.concatenate([g, np.full(reach_px, -np.inf)]), reach_px + 1)
    dim = g < (1.0 - FLANK_RISE) * windows.max(axis=1)
    return after_unlit & rising & dim & ~unlit


def rising_flank(g: np.ndarray, lit: np.ndarray, reach_px: int) -> np.ndarray:
    """The border pixels past which the light is free: unlit ones and those on the rim's
    rising flank (from either side; module notes).

    Parameters
    ----------
    g : (N,) ndarray
        The light along one image border.
    lit : (N,) ndarray of bool
        Where the lit zone reaches that border.
    reach_px : int
        How far along the border the flank's plateau is looked for (the closing disc's
        radius).

    Returns
    -------
    (N,) ndarray of bool

    Examples
    --------
    A rim rising from the unlit outside to a plateau that holds a dark contact:

    >>> g = np.array([5, 5, 40, 120, 190, 200, 200, 60, 60, 200, 200, 190, 100, 5.0])
    >>> lit = g > 50
    >>> rising_flank(g, lit, 4).astype(int)
    array([1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1])
    """
    g = np.asarray(g, np.float64)
    unlit = ~np.asarray(lit, bool)
    if not unlit.any():
        return unlit
    left = _flank_from_left(g, unlit, reach_px)
    right = _flank_from_left(g[::-1], unlit[::-1], reach_px)[::-1]
    return unlit | left | right


def _runs(on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First and last index of each run of True in `on`."""
    edge = np.diff(np.concatenate(([0], on.astype(np.int8), [0])))
    return np.flatnonzero(edge == 1), np.flatnonzero(edge == -1) - 1


def continued_lit(on: np.ndarray, inside: np.ndarray, step_px: int, rows: int
                  ) -> np.ndarray:
    """The lit runs of a border line continued `rows` px past the border along the
    secant of their ends over the `step_px` px inside (`inside`: the line that far in):
    a convex zone stays convex. Row 0 of the result is the farthest from the border.

    Examples
    --------
    A run that narrows by one px a row at each end towards the border narrows on past
    it, to nothing two rows out:

    >>> on = np.zeros(12, bool); on[4:8] = True
    >>> inside = np.zeros(12, bool); inside[2:10] = True
    >>> continued_lit(on, inside, 2, 2).astype(int)
    array([[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0]])
    """
    n = on.size
    out = np.zeros((rows, n), bool)
    k = np.arange(rows, 0, -1, dtype=np.float64)
    x = np.arange(n)
    starts_in, ends_in = _runs(inside)
    for a, b in zip(*_runs(on), strict=True):
        overlap = np.minimum(ends_in, b) - np.maximum(starts_in, a)
        da = db = 0.0
        if overlap.size and overlap.max() >= 0:
            j = int(np.argmax(overlap))
            da, db = (a - starts_in[j]) / step_px, (b - ends_in[j]) / step_px
        lo, hi = a + k * da, b + k * db
        out |= (x[None, :] >= lo[:, None] - 0.5) & (x[None, :] <= hi[:, None] + 0.5)
    return out


def extend_past_border(small: np.ndarray, lit: np.ndarray | None, pad: int,
                       reach_px: int) -> np.ndarray:
    """`small` padded by `pad` on every side: odd reflection capped at the border value,
    the darkest value where the lit zone continued past the border ends (module notes).

    The zone's plateau (lit, less the rim's rising flank, :func:`rising_flank`) along
    each border is continued past it along the secant of its ends over :data:`STEP_PX`
    inside (:func:`continued_lit`); past the border the light is free outside that.
    Nothing changes where `lit` is None or the zone fills the image.
    """
    big = np.minimum(np.pad(small, pad, mode="reflect", reflect_type="odd"),
                     np.pad(small, pad, mode="edge"))
    if lit is None or lit.all():
        return big
    h, w = small.shape
    black = big.dtype.type(big.min())
    step = min(STEP_PX, h - 1, w - 1)
    if step < 1:
        return big
    # each border: its line, the line `step` px inside, the zone on both, and the pad
    # strip past it with its rows from the farthest to the border (the left and right
    # strips transposed to that)
    borders = (
        (small[0], small[step], lit[0], lit[step], big[:pad, pad:pad + w]),
        (small[-1], small[-1 - step], lit[-1], lit[-1 - step],
         big[pad + h:, pad:pad + w][::-1]),
        (small[:, 0], small[:, step], lit[:, 0], lit[:, step], big[pad:pad + h, :pad].T),
        (small[:, -1], small[:, -1 - step], lit[:, -1], lit[:, -1 - step],
         big[pad:pad + h, pad + w:].T[::-1]),
    )
    for g, g_in, on, on_in, strip in borders:
        plateau = on & ~rising_flank(g, on, reach_px)
        plateau_in = on_in & ~rising_flank(g_in, on_in, reach_px)
        strip[~continued_lit(plateau, plateau_in, step, pad)] = black
    return big
