"""Darkness of TIR frames against a fixed reference, and its fast path on raw grey values.

:class:`Normaliser` computes the darkness ``D`` of a whole frame (float32, 0 at excluded
pixels). Most of a frame is free surface, though, and only the contact's neighbourhood is
ever read. :class:`RawContactTest` therefore thresholds the *raw* frame against a
per-pixel grey-value limit that is exactly equivalent to ``D >= threshold`` (found by
evaluating the normaliser's own float32 arithmetic at the limit, so no pixel flips by
rounding), and :class:`BoxDarkness` computes ``D`` only inside the contact's box.
"""

from __future__ import annotations

import math

import numpy as np

from tir_contact.calibrate import Reference, reference_from_frame

__all__ = ["BoxDarkness", "Normaliser", "RawContactTest"]


class Normaliser:
    """Darkness of a frame against a fixed reference, with invalid pixels at 0.

    ``D = 1 - I / I_ref`` for dark contact, ``I / I_ref - 1`` for bright contact, in
    float32 (one multiply and one add per pixel).
    """

    def __init__(self, reference: Reference, contact_is: str) -> None:
        self.reference = reference
        self.valid = reference.valid
        self.contact_is = contact_is
        inv = np.where(reference.valid, 1.0 / np.maximum(reference.image, 1e-6), 0.0)
        sign = -1.0 if contact_is == "dark" else 1.0
        self.scale = (sign * inv).astype(np.float32)
        self.offset = (-sign * reference.valid).astype(np.float32)

    @classmethod
    def own_background(cls, frame: np.ndarray, contact_is: str, size_px: int) -> Normaliser:
        """Normaliser against the frame's own background (no clean reference)."""
        return cls(reference_from_frame(frame, contact_is=contact_is, size_px=size_px),
                   contact_is)

    def __call__(self, frame: np.ndarray) -> np.ndarray:
        d = frame.astype(np.float32)
        d *= self.scale
        d += self.offset
        return d

    def region(self, frame: np.ndarray, rows: slice, cols: slice) -> np.ndarray:
        """The darkness of ``frame[rows, cols]``, bit-identical to ``self(frame)[rows, cols]``."""
        d = frame[rows, cols].astype(np.float32)
        d *= self.scale[rows, cols]
        d += self.offset[rows, cols]
        return d


class RawContactTest:
    """``D >= threshold`` evaluated on the raw unsigned-integer frame, pixel for pixel exact.

    Dark contact: ``D`` falls with the grey value, so contact is ``I < limit``; bright
    contact: ``I > limit``. The limit per pixel is the first grey value past the threshold
    crossing, found with the normaliser's own float32 arithmetic. Excluded pixels never
    pass.

    Use :meth:`build`, which returns None where the fast path does not apply (float frames,
    a threshold <= 0, or a limit the dtype cannot hold).
    """

    def __init__(self, limit: np.ndarray, dark: bool) -> None:
        self.limit = limit
        self.dark = dark

    @classmethod
    def build(cls, normaliser: Normaliser, threshold: float,
              dtype: np.dtype) -> RawContactTest | None:
        dtype = np.dtype(dtype)
        if not np.issubdtype(dtype, np.unsignedinteger) or not (math.isfinite(threshold)
                                                               and threshold > 0):
            return None
        top = int(np.iinfo(dtype).max)
        t32 = np.float32(threshold)
        scale, offset = normaliser.scale, normaliser.offset
        dark = normaliser.contact_is == "dark"
        valid = normaliser.valid & (scale != 0)

        def passes(f: np.ndarray) -> np.ndarray:  # D(f) >= threshold, the normaliser's way
            d = f.astype(np.float32)
            d *= scale
            d += offset
            return d >= t32

        # Work in the mirrored grey value g (g = I for dark contact, top - I for bright),
        # where contact is always g <= G: G = the largest passing g, -1 for none. First
        # estimate from the crossing, then fix by the float32 evaluation.
        def passes_g(g: np.ndarray) -> np.ndarray:
            g = np.clip(g, 0, top)
            return passes(g if dark else top - g)

        with np.errstate(divide="ignore", invalid="ignore"):
            x = (t32.astype(np.float64) - offset) / np.where(valid, scale, 1.0)
        xg = np.nan_to_num(x if dark else top - x, nan=-1.0)
        g = np.clip(np.floor(xg), -1, top).astype(np.int64)
        g[~valid] = -1
        for _ in range(8):
            up = (g < top) & passes_g(g + 1)
            down = (g >= 0) & ~passes_g(g)
            if not (up.any() or down.any()):
                break
            g = g + up - down
        else:
            return None
        if g.max() + 1 > top:  # a limit the dtype cannot hold
            return None
        # dark: contact I < G + 1; bright: contact I > top - (G + 1)
        limit = g + 1 if dark else top - (g + 1)
        return cls(limit.astype(dtype), dark)

    def __call__(self, frame: np.ndarray) -> np.ndarray | None:
        """Contact pixels (bool), or None when the frame's dtype is not the limit's."""
        if frame.dtype != self.limit.dtype or frame.shape != self.limit.shape:
            return None
        return np.less(frame, self.limit) if self.dark else np.greater(frame, self.limit)


class BoxDarkness:
    """A full-frame darkness image that holds values only where they were computed.

    :meth:`fill` writes ``D`` into a box (and clears the previous box back to NaN), so the
    image is the frame's darkness inside the box and NaN (excluded) elsewhere: code that
    reads outside the box gets NaN, never a stale value.
    """

    def __init__(self, normaliser: Normaliser, shape: tuple[int, int]) -> None:
        self.normaliser = normaliser
        self.image = np.full(shape, np.nan, np.float32)
        self._last: tuple[slice, slice] | None = None

    def clear(self) -> np.ndarray:
        """The image with the last box set back to NaN (all NaN)."""
        if self._last is not None:
            self.image[self._last] = np.nan
            self._last = None
        return self.image

    def fill(self, frame: np.ndarray, rows: slice, cols: slice) -> np.ndarray:
        """The image holding the darkness of ``frame[rows, cols]`` and NaN elsewhere."""
        self.clear()
        self.image[rows, cols] = self.normaliser.region(frame, rows, cols)
        self._last = (rows, cols)
        return self.image
