"""The contact test and the darkness of TIR frames where the features read it.

:class:`~tir_contact.flatfield.Normaliser` computes the darkness ``D`` of a whole frame
(float32, NaN at excluded pixels: :func:`tir_contact.flatfield.darkness`). Most of a frame
is free surface, though, and only the contact's neighbourhood is ever read.
:class:`RawContactTest` therefore
thresholds the *raw* frame against a per-pixel grey-value limit that is exactly equivalent
to ``D >= threshold`` (found by evaluating the normaliser's own float32 arithmetic at the
limit, so no pixel flips by rounding), and :class:`BoxDarkness` computes ``D`` only inside
the contact's box; :class:`ContactTest` is the test the analysis runs (on the raw grey
values where the dtype allows, else on the darkness).
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from tir_contact.flatfield import Normaliser

__all__ = ["BoxDarkness", "ContactTest", "Normaliser", "RawContactTest"]


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
    def build(cls, normaliser: Normaliser, threshold: float | np.ndarray,
              dtype: np.dtype) -> RawContactTest | None:
        """The test of ``D >= threshold`` (a number, or one per pixel: NaN never passes)."""
        dtype = np.dtype(dtype)
        if not np.issubdtype(dtype, np.unsignedinteger):
            return None
        if np.ndim(threshold) == 0:
            if not (math.isfinite(threshold) and threshold > 0):
                return None
            t32 = np.float32(threshold)
        else:
            t32 = np.asarray(threshold, np.float32)
            finite = np.isfinite(t32)
            if not finite.any() or (t32[finite] <= 0).any():
                return None
        top = int(np.iinfo(dtype).max)
        scale, offset = normaliser.scale, normaliser.offset
        dark = normaliser.contact_is == "dark"
        valid = normaliser.valid & (scale != 0) & np.isfinite(t32)

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

    def __call__(self, frame: np.ndarray, out: np.ndarray | None = None) -> np.ndarray | None:
        """Contact pixels (bool), or None when the frame's dtype is not the limit's.

        `out`, a bool array of the frame's shape, receives the result (no new array).
        """
        if frame.dtype != self.limit.dtype or frame.shape != self.limit.shape:
            return None
        if self.dark:
            return np.less(frame, self.limit, out=out)
        return np.greater(frame, self.limit, out=out)


class ContactTest:
    """Contact pixels ``D >= threshold`` of whole frames, written into a reused buffer.

    On the raw grey values (:class:`RawContactTest`, pixel for pixel the same) where the
    frame's dtype allows it; otherwise (float frames, a limit the dtype cannot hold) on the
    frame's darkness. Excluded pixels (NaN darkness) never pass.
    """

    def __init__(self, normaliser: Normaliser, threshold: float) -> None:
        self.normaliser = normaliser
        self.threshold = threshold
        self._raw: dict[str, RawContactTest | None] = {}  # by dtype character
        self._buf: np.ndarray | None = None

    @property
    def last(self) -> np.ndarray | None:
        """The last call's result (the reused buffer), None before the first."""
        return self._buf

    def __call__(self, frame: np.ndarray) -> np.ndarray:
        """The contact pixels of `frame` (bool; valid until the next call)."""
        if self._buf is None or self._buf.shape != frame.shape:
            self._buf = np.empty(frame.shape, np.bool_)
        test = self._raw.get(frame.dtype.char, False)
        if test is False:
            test = RawContactTest.build(self.normaliser, self.threshold, frame.dtype)
            self._raw[frame.dtype.char] = test
        raw = test(frame, out=self._buf) if test is not None else None
        if raw is None:
            with np.errstate(invalid="ignore"):  # NaN compares False: excluded
                raw = np.greater_equal(self.normaliser(frame), self.threshold, out=self._buf)
        return raw


class BoxDarkness:
    """A full-frame darkness image that holds values only where they were computed.

    :meth:`fill` writes ``D`` into a box (and sets the rest of the previous box back to
    NaN), so the image is the frame's darkness inside the box and NaN (excluded)
    elsewhere: code that reads outside the box gets NaN, never a stale value.
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
        n_rows, n_cols = self.image.shape
        rows, cols = slice(*rows.indices(n_rows)), slice(*cols.indices(n_cols))
        if rows.step != 1 or cols.step != 1:
            self.clear()
            self.image[rows, cols] = self.normaliser.region(frame, rows, cols)
        else:
            self._clear_outside(rows, cols)
            _region_into(self.normaliser, frame, rows, cols, self.image[rows, cols])
        self._last = (rows, cols)
        return self.image

    def _clear_outside(self, rows: slice, cols: slice) -> None:
        """Set the pixels of the last box that lie outside ``[rows, cols]`` back to NaN."""
        if self._last is None:
            return
        r_o, c_o = self._last
        if r_o.step != 1 or c_o.step != 1:
            self.clear()
            return
        img = self.image
        if rows.start > r_o.start:  # above the new rows
            img[r_o.start : min(r_o.stop, rows.start), c_o] = np.nan
        if rows.stop < r_o.stop:  # below
            img[max(r_o.start, rows.stop) : r_o.stop, c_o] = np.nan
        mid = slice(max(r_o.start, rows.start), min(r_o.stop, rows.stop))
        if mid.start < mid.stop:  # beside, in the rows both boxes share
            if cols.start > c_o.start:
                img[mid, c_o.start : min(c_o.stop, cols.start)] = np.nan
            if cols.stop < c_o.stop:
                img[mid, max(c_o.start, cols.stop) : c_o.stop] = np.nan
        self._last = None


def _region_into(normaliser: Normaliser, frame: np.ndarray, rows: slice, cols: slice,
                 out: np.ndarray) -> None:
    """Write :meth:`Normaliser.region` into `out` (a float32 view), bit for bit.

    The grey values go into `out` as float32 (numpy's cast, as ``astype`` makes it), then
    OpenCV multiplies them by the float32 scale and adds the float32 offset in place, each
    rounded once as in numpy: no temporary, about half numpy's time on strided views.
    """
    src = frame[rows, cols]
    if frame.dtype.kind not in "biuf" or src.ndim != 2 or 0 in src.shape:
        out[...] = normaliser.region(frame, rows, cols)
        return
    out[...] = src  # the grey values as float32 (exact for these dtypes)
    res = cv2.multiply(out, normaliser.scale[rows, cols], dst=out)
    res = cv2.add(res, normaliser.offset[rows, cols], dst=out)
    if not np.may_share_memory(res, out):  # OpenCV did not write in place: copy
        out[...] = res
