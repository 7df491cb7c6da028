"""Grey morphology by a wide disc (:mod:`tir_contact._morphology`).

Truth: OpenCV's own grey dilation, erosion and closing with the same elliptic kernel and
a replicated border. Only maxima and minima are taken, so the values must be equal, not
close.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from tir_contact._morphology import (
    MASK_ROWS_FROM_PX,
    ROWS_FROM_PX,
    disc_close,
    disc_dilate,
    disc_erode,
    disc_kernel,
    mask_dilate,
)


def _image(shape: tuple[int, int], seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    img = cv2.GaussianBlur(rng.random(shape, dtype=np.float32), (0, 0), 2.0)
    img[shape[0] // 3: shape[0] // 2, 5: shape[1] // 2] *= 0.2  # a dark block
    return img


# shapes narrower than the disc too (the border is then most of the reach), down to one
# and two columns (the widening step reads its neighbours at both ends)
@pytest.mark.parametrize("shape", [(64, 90), (37, 120), (120, 25), (40, 2), (40, 1)])
@pytest.mark.parametrize("size_px", [3, ROWS_FROM_PX, 57, 101])
def test_disc_morphology_equals_opencv(shape, size_px):
    img = _image(shape, size_px)
    k = disc_kernel(size_px)
    rep = cv2.BORDER_REPLICATE
    assert np.array_equal(disc_dilate(img, size_px), cv2.dilate(img, k, borderType=rep))
    assert np.array_equal(disc_erode(img, size_px), cv2.erode(img, k, borderType=rep))
    assert np.array_equal(disc_close(img, size_px),
                          cv2.morphologyEx(img, cv2.MORPH_CLOSE, k, borderType=rep))


@pytest.mark.parametrize("shape", [(64, 90), (120, 25)])
@pytest.mark.parametrize("size_px", [1, 13, MASK_ROWS_FROM_PX, 61, 101])
@pytest.mark.parametrize("fill", [0.0, 0.002, 0.05, 1.0])
def test_mask_dilation_equals_opencv(shape, size_px, fill):
    rng = np.random.default_rng(size_px)
    m = rng.random(shape) < fill
    m[shape[0] // 2, 0] = fill > 0  # a set pixel on the border (the reach cut there)
    want = cv2.dilate(m.astype(np.uint8), disc_kernel(size_px)).astype(bool)
    assert np.array_equal(mask_dilate(m, size_px), want)


def test_even_or_empty_disc_is_refused():
    img = _image((20, 20), 0)
    for bad in (0, 4, -3):
        with pytest.raises(ValueError, match="size_px must be odd"):
            disc_dilate(img, bad)
    with pytest.raises(ValueError, match="2-D"):
        disc_close(np.zeros((3, 4, 5), np.float32), 45)
