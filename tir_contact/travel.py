"""Whether the contact in a TIR video travels as the metadata says a passing block does.

A camera fixed to the prism sees a sliding block cross the view at the sliding velocity; a
camera that follows the block (or a static test) holds the contact where it is. Where the
samples alone do not tell (a short clip, a slow pass, faint patchy contact: the block
covers most of the view in every sample and no sample is free of it), the metadata does:
over the time between two samples a passing block travels ``v dt / mm_per_px`` px along the
sliding direction (:func:`expected_travel_px`). The contact's profile along the rows in the
later sample is then the earlier one shifted by that much; held contact's is not shifted
(:func:`column_profiles`). The hypothesis that correlates clearly better wins
(:func:`carried`).

Measured (profiles of darkness against the samples' fitted free surface; seed 0's domain
draws and the physical block of :mod:`synthetic`): the lag of held contact was 0 px on all 26
static and following-camera TIR clips of seed 0's first 40 domain draws (the following
cameras' samples 50-150 px of a passing block's travel apart); a physical block at 1 m/s
over 10, 40 and 80 frames (expected -22.5, -97.5, -197.5 px) gave -21, -105 and -210 px,
a 20-frame G3 pass -47 px for -47.5.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

#: The lag is decided only where the expected travel is at least this many px: the two
#: hypotheses (0 and the travel less :data:`TRAVEL_TOLERANCE` of it) then lie 6 px apart,
#: six of the lag's 1 px steps (held contact measured at 0 px; a deforming contact's
#: front moves by a few px).
MIN_TRAVEL_PX = 8.0
#: The later sample of the pair is the last whose expected travel is at most this share of
#: the lit zone's extent along the rows, so that most of the contact stays in view in both.
MAX_TRAVEL_SHARE = 0.5
#: Shifts whose overlap of the two profiles is shorter than this share of the extent are
#: not compared.
MIN_OVERLAP_SHARE = 0.25


def expected_travel_px(meta: Mapping[str, Any], frame_numbers: Sequence[int]) -> np.ndarray | None:
    """Signed displacement along the rows (px, + to the right) of a block passing a fixed
    camera at each of `frame_numbers` from the first, by the metadata's
    ``conditions.velocity_mps``, ``fps``, ``mm_per_px`` and ``sliding_direction``; None
    without a velocity. The direction is ``sliding_direction``'s: the velocity's sign is
    not read (its magnitude is the speed), and :func:`carried` tests both ways anyway.

    Examples
    --------
    >>> meta = {"fps": 4000, "mm_per_px": 0.1, "sliding_direction": "left",
    ...         "conditions": {"velocity_mps": 1.0}}
    >>> expected_travel_px(meta, [0, 4, 8]).tolist()
    [-0.0, -10.0, -20.0]
    """
    velocity = (meta.get("conditions") or {}).get("velocity_mps")
    if velocity is None or not np.isfinite(float(velocity)):
        return None
    sign = -1.0 if str(meta["sliding_direction"]).lower() == "left" else 1.0
    dt_s = (np.asarray(frame_numbers, float) - float(frame_numbers[0])) / float(meta["fps"])
    return sign * abs(float(velocity)) * 1e3 * dt_s / float(meta["mm_per_px"])


def column_profiles(samples: Sequence[np.ndarray], base: np.ndarray, lit: np.ndarray,
                    cols: slice, contact_is: str = "dark") -> np.ndarray:
    """Each sample's darkness against `base` (``(base - f) / base``, contact positive; 0
    outside `lit`) averaged down each column `cols` of the lit zone: one profile along the
    rows per sample, (n_samples, n_cols) float32.

    Examples
    --------
    >>> base = np.full((4, 3), 100.0, np.float32)
    >>> frame = base.copy(); frame[:2, 1] = 50.0
    >>> column_profiles([frame], base, np.ones((4, 3), bool), slice(0, 3)).tolist()
    [[0.0, 0.25, 0.0]]
    """
    base = np.asarray(base, np.float32)
    inv = np.where(lit, 1.0 / np.maximum(base, 1e-6), 0.0).astype(np.float32)
    sign = np.float32(1.0 if contact_is == "dark" else -1.0)
    n = np.maximum(lit[:, cols].sum(axis=0), 1).astype(np.float32)
    return np.array([(((base - np.asarray(f, np.float32)) * inv * sign)[:, cols]).sum(axis=0)
                     / n for f in samples], np.float32)


def _correlation(a: np.ndarray, b: np.ndarray, s: int) -> float:
    """Pearson correlation of ``a[x]`` with ``b[x + s]`` over their overlap (-inf where it
    is shorter than :data:`MIN_OVERLAP_SHARE` of the length or flat)."""
    n = len(a)
    x, y = (a[:n - s], b[s:]) if s >= 0 else (a[-s:], b[:n + s])
    if len(x) < MIN_OVERLAP_SHARE * n:
        return -np.inf
    x = x - x.mean()
    y = y - y.mean()
    den = float(np.sqrt((x * x).sum() * (y * y).sum()))
    return float((x * y).sum()) / den if den > 0 else -np.inf


#: A passing block's contact deforms between the samples: its lag is looked for within
#: this share of the expected travel around it (measured within 8 %: -21, -105 and -210
#: px for -22.5, -97.5 and -197.5).
TRAVEL_TOLERANCE = 0.25
#: The hypothesis whose correlation is higher by this many of the correlation's sampling
#: errors wins; nearer than that (a periodic tread whose pitch fits the travel, held
#: contact whose junctions renew) the profiles do not tell.
CORRELATION_SIGMAS = 3.0


def _correlation_sigma(a: np.ndarray, r: float) -> float:
    """Sampling error of a correlation `r` between two profiles like `a`: (1 - r^2) /
    sqrt(n - 3) over its n independent stretches (its length over its correlation length:
    twice the lag at which its autocorrelation falls below 1/2)."""
    x = a - a.mean()
    den = float(x @ x)
    width = len(a)
    if den > 0:
        for lag in range(1, len(a) // 2):
            if float(x[:-lag] @ x[lag:]) / den < 0.5:
                width = 2 * lag
                break
    n = len(a) / max(width, 1)
    return (1.0 - min(r * r, 1.0)) / np.sqrt(max(n - 3.0, 1.0))


def carried(samples: Sequence[np.ndarray], free: np.ndarray, lit: np.ndarray,
            travel_px: Sequence[float], contact_is: str = "dark") -> bool | None:
    """True when the contact travels between two samples as a block passing a fixed camera
    does, False when it is held; None when the profiles cannot tell: under
    :data:`MIN_TRAVEL_PX` of expected travel between the first sample and the last within
    :data:`MAX_TRAVEL_SHARE` of the lit extent, or neither hypothesis correlating clearly
    better.

    The darkness profiles along the rows (against `free`, a free surface fitted to the
    samples' median: the light field's own fall-off, static in either case, taken out) of
    the pair are correlated at the shift 0 (held) and at the best shift within
    :data:`TRAVEL_TOLERANCE` of the expected travel, either way (carried); the one higher by
    :data:`CORRELATION_SIGMAS` sampling errors wins (before: the best shift anywhere up to
    twice the travel, nearer the travel than 0: a held periodic tread whose junctions renew
    aliased to its pitch, helper-14's review).

    Parameters
    ----------
    samples : sequence of (M, N) ndarray
        The sampled frames, in time order.
    free : (M, N) ndarray
        A free-surface estimate (the same for every sample).
    lit : (M, N) ndarray of bool
    travel_px : sequence of float
        Expected displacement of each sample from the first (:func:`expected_travel_px`).
    contact_is : {"dark", "bright"}

    Raises
    ------
    ValueError
        `travel_px` not one finite value per sample.
    """
    travel = np.asarray(travel_px, float)
    if travel.shape != (len(samples),) or not np.all(np.isfinite(travel)):
        raise ValueError(f"travel_px must hold one finite displacement (px) per sample "
                         f"({len(samples)}), got {travel_px!r}")
    cols = np.flatnonzero(lit.any(axis=0))
    if len(samples) < 2 or cols.size < 2:
        return None
    extent = int(cols[-1] - cols[0] + 1)
    k = int(np.flatnonzero(np.abs(travel) <= MAX_TRAVEL_SHARE * extent)[-1])
    expected = float(travel[k])
    if abs(expected) < MIN_TRAVEL_PX:
        return None
    span = slice(int(cols[0]), int(cols[-1]) + 1)
    a, b = column_profiles([samples[0], samples[k]], free, lit, span, contact_is)
    # either way along the rows: a block passing against sliding_direction is a fixed
    # camera too (outputs._against_direction then says so)
    lo, hi = abs(expected) * (1 - TRAVEL_TOLERANCE), abs(expected) * (1 + TRAVEL_TOLERANCE)
    window = range(int(np.ceil(lo)), int(hi) + 1)
    at_travel = max(_correlation(a, b, sg * s) for s in window for sg in (1, -1))
    at_rest = _correlation(a, b, 0)
    if not (np.isfinite(at_travel) or np.isfinite(at_rest)):
        return None
    margin = CORRELATION_SIGMAS * _correlation_sigma(a, max(at_travel, at_rest))
    if at_travel - at_rest > margin:
        return True
    if at_rest - at_travel > margin:
        return False
    return None
