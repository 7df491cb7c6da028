"""Grey dilation, erosion and closing of float images by a wide disc, exact and fast.

OpenCV's grey morphology with an elliptic kernel costs about the kernel's area per pixel:
a 201 px disc on a 256 px image took 0.2-0.4 s, most of :func:`tir_contact.prepare_video`
on a static scene. A disc is a stack of horizontal runs, one per kernel row, symmetric
about the centre. The dilation is the maximum over the rows of the image's running
maximum over that row's run, shifted by the row's offset. The running maxima of all
widths come from one another by a growth step (``max`` of two neighbours), so the whole
dilation costs about twice the disc's diameter passes of ``numpy.maximum`` over the
image (padded above and below only), and gives the same values as OpenCV (only maxima
and minima are taken: no rounding). Below :data:`ROWS_FROM_PX` OpenCV is faster and is used.

The border is replicated, as ``cv2.BORDER_REPLICATE`` does. Images are taken as float32
and must be finite (a NaN spreads through ``numpy.maximum`` where OpenCV skips it); the
callers (illumination.py, reference.py) pass finite float32 images.

:func:`mask_dilate` is the binary dilation by the same disc, from the rows' distances to
their nearest set pixel (the rings fitted around contacts in reference.py).
"""

from __future__ import annotations

from functools import lru_cache

import cv2
import numpy as np

__all__ = [
    "MASK_ROWS_FROM_PX",
    "ROWS_FROM_PX",
    "disc_close",
    "disc_dilate",
    "disc_erode",
    "disc_kernel",
    "mask_dilate",
]

#: Disc diameter (px) from which the run decomposition is used (measured on a 256 x 200
#: float image, one core: equal time at about 25 px; 1.2x faster at 31 px, 4x at 101 px,
#: 5x at 201 px).
ROWS_FROM_PX = 25
#: Disc diameter (px) from which :func:`mask_dilate` uses its row distances (a 250 x 250
#: mask with a 130 x 110 block, one core: OpenCV 5x faster at 13 px, about equal at
#: 21-41 px, 1.7x slower at 61 px, 2.8x at 81 px).
MASK_ROWS_FROM_PX = 41


def disc_kernel(size_px: int) -> np.ndarray:
    """OpenCV's elliptic structuring element of `size_px` (odd) x `size_px`."""
    if size_px < 1 or size_px % 2 == 0:
        raise ValueError(f"size_px must be odd and >= 1, got {size_px!r}")
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (size_px, size_px))


def _half_widths(kernel: np.ndarray) -> list[tuple[int, int]]:
    """``(row offset, half width)`` of each row of a kernel made of centred runs, by
    growing half width."""
    k = np.asarray(kernel, bool)
    c = k.shape[0] // 2
    rows = []
    for i, row in enumerate(k):
        xs = np.flatnonzero(row)
        if xs.size == 0:
            continue
        if xs[-1] - xs[0] + 1 != xs.size or xs[0] + xs[-1] != 2 * c:
            raise ValueError("the kernel's rows must be runs centred on its middle column")
        rows.append((i - c, c - int(xs[0])))
    return sorted(rows, key=lambda r: r[1])


@lru_cache(maxsize=64)
def _disc_rows(size_px: int) -> tuple[tuple[int, int], ...]:
    """:func:`_half_widths` of the disc of `size_px`, worked out once per size (the
    ring fit dilates by the same disc around every contact)."""
    return tuple(_half_widths(disc_kernel(size_px)))


def _extreme(image: np.ndarray, size_px: int, op: np.ufunc) -> np.ndarray:
    """``op``-reduction (``np.maximum``: dilation, ``np.minimum``: erosion) over the disc."""
    img = np.asarray(image, np.float32)
    if img.ndim != 2:
        raise ValueError(f"image must be 2-D, got shape {img.shape}")
    if size_px < ROWS_FROM_PX:
        fn = cv2.dilate if op is np.maximum else cv2.erode
        return fn(img, disc_kernel(size_px), borderType=cv2.BORDER_REPLICATE)
    r = size_px // 2
    h = img.shape[0]
    # running extreme over [x - hw, x + hw] of the rows padded by the disc's radius; the
    # columns need no pad: a window cut at the border holds the border pixel, which is
    # all that a replicated border adds
    run = np.pad(img, ((r, r), (0, 0)), mode="edge")
    tmp = np.empty_like(run)
    out: np.ndarray | None = None
    hw = 0
    for dy, want in _disc_rows(size_px):
        while hw < want:
            run, tmp = _wider(run, tmp, op, hw), run
            hw += 1
        rows = run[r + dy: r + dy + h]
        if out is None:
            out = rows.copy()
        else:
            op(out, rows, out=out)
    assert out is not None  # a disc has a middle row
    return out


def _wider(run: np.ndarray, spare: np.ndarray, op: np.ufunc, hw: int) -> np.ndarray:
    """The running extreme over ``[x - hw - 1, x + hw + 1]`` from `run`, the one over
    ``[x - hw, x + hw]`` (each row's window cut at its ends), written into `spare`.

    From half width 1 on, the windows at ``x - 1`` and ``x + 1`` overlap and together
    span the wider one, so one pass of `op` gives it; at the ends the one window inside
    holds all the cut window does. The first step (from the pixels themselves) takes two.
    """
    if run.shape[1] == 1:
        spare[:] = run
    elif hw == 0:
        op(run[:, :-1], run[:, 1:], out=spare[:, :-1])
        spare[:, -1] = run[:, -1]
        op(spare[:, 1:], run[:, :-1], out=spare[:, 1:])
    else:
        op(run[:, :-2], run[:, 2:], out=spare[:, 1:-1])
        spare[:, 0] = run[:, 1]
        spare[:, -1] = run[:, -2]
    return spare


def disc_dilate(image: np.ndarray, size_px: int) -> np.ndarray:
    """Grey dilation of a float image by the disc :func:`disc_kernel` of `size_px`.

    Examples
    --------
    >>> img = np.random.default_rng(0).random((40, 50), dtype=np.float32)
    >>> k = disc_kernel(45)
    >>> ref = cv2.dilate(img, k, borderType=cv2.BORDER_REPLICATE)
    >>> bool(np.array_equal(disc_dilate(img, 45), ref))
    True
    """
    return _extreme(image, size_px, np.maximum)


def disc_erode(image: np.ndarray, size_px: int) -> np.ndarray:
    """Grey erosion of a float image by the disc :func:`disc_kernel` of `size_px`."""
    return _extreme(image, size_px, np.minimum)


def disc_close(image: np.ndarray, size_px: int) -> np.ndarray:
    """Grey closing (dilation, then erosion) of a float image by a disc of `size_px`."""
    return disc_erode(disc_dilate(image, size_px), size_px)


def mask_dilate(mask: np.ndarray, size_px: int) -> np.ndarray:
    """Binary dilation of `mask` by the disc :func:`disc_kernel` of `size_px`, as
    ``cv2.dilate`` gives it (nothing outside the image is set).

    OpenCV's binary dilation by a non-rectangular kernel also costs about the kernel's
    area per pixel (a 61 px disc on a 250 x 250 box: 3.0 ms, here 1.8 ms). Here each
    row's distance to its nearest set pixel is found once (two running extremes of the
    set pixels' columns); a pixel is in the dilation where some kernel row's offset row
    lies within that row's half width, about the disc's diameter passes in all. Below
    :data:`MASK_ROWS_FROM_PX` OpenCV is faster and is used.

    Examples
    --------
    >>> m = np.random.default_rng(0).random((40, 50)) > 0.98
    >>> ref = cv2.dilate(m.astype(np.uint8), disc_kernel(61)).astype(bool)
    >>> bool(np.array_equal(mask_dilate(m, 61), ref))
    True
    """
    m = np.asarray(mask, bool)
    if m.ndim != 2:
        raise ValueError(f"mask must be 2-D, got shape {m.shape}")
    if size_px < MASK_ROWS_FROM_PX:
        return cv2.dilate(m.astype(np.uint8), disc_kernel(size_px)).astype(bool)
    h, w = m.shape
    far = np.int32(h + w + size_px + 2)  # farther than any half width
    col = np.arange(w, dtype=np.int32)
    left = np.maximum.accumulate(np.where(m, col, -far), axis=1)
    right = np.minimum.accumulate(np.where(m, col, 2 * far)[:, ::-1], axis=1)[:, ::-1]
    r = size_px // 2
    dist = np.full((h + 2 * r, w), far, np.int32)
    dist[r:r + h] = np.minimum(col - left, right - col)
    reach = np.full((h, w), far, np.int32)  # the least (row distance - half width)
    for dy, hw in _disc_rows(size_px):
        np.minimum(reach, dist[r + dy: r + dy + h] - hw, out=reach)
    return reach <= 0

