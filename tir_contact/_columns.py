"""Column means of the darkness over a band of rows: the profile the features and the
test for graded contact read (:mod:`tir_contact.features`, :mod:`tir_contact.graded`)."""

from __future__ import annotations

import math

import cv2
import numpy as np

__all__ = ["ColumnSums", "column_mean"]

#: Column sums of the darkness known beforehand: (r0, r1, c0, sums of rows r0..r1-1 for
#: columns c0, c0 + 1, ...), as OpenCV's reduction gives them (each column on its own).
ColumnSums = tuple[int, int, int, np.ndarray]


def column_mean(d: np.ndarray, r0: int, r1: int, c0: int, c1: int,
                sums: ColumnSums | None = None, fill: float = 0.0) -> np.ndarray:
    """Mean of `d` over rows r0..r1-1 for columns c0..c1-1, ignoring NaN; `fill` where a
    column has no measured pixel.

    `sums`, when it covers these rows and columns, spares the summation (the sums of the
    fast path, taken while the darkness was still in the cache).

    Examples
    --------
    >>> d = np.array([[1.0, np.nan, np.nan], [3.0, 4.0, np.nan]], np.float32)
    >>> column_mean(d, 0, 2, 0, 3, fill=-1.0).tolist()
    [2.0, 4.0, -1.0]
    """
    sub = d[r0:r1, c0:c1]
    if sub.dtype != np.float32:
        sub = sub.astype(np.float32)
    if (sums is not None and sums[0] == r0 and sums[1] == r1 and sums[2] <= c0
            and c1 - sums[2] <= sums[3].size and sums[3].dtype == np.float32):
        total = sums[3][c0 - sums[2] : c1 - sums[2]]
    else:
        total = cv2.reduce(sub, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32F).ravel()
    out = total / np.float32(r1 - r0)
    if math.isfinite(np.add.reduce(out)):  # every column finite (one sum, not a mask)
        return out
    bad = ~np.isfinite(out)
    if bad.any():  # columns with excluded pixels: mean over the finite ones
        cols = np.flatnonzero(bad)
        block = sub[:, cols]
        cnt = np.isfinite(block).sum(axis=0)
        out[cols] = np.where(cnt > 0, np.nansum(block, axis=0) / np.maximum(cnt, 1), fill)
    return out
