"""The free-surface closing with a disc wider than the working scale
(:func:`tir_contact.reference._closing`, :data:`~tir_contact.reference.MAX_DISC_PX`).

Truth: the same closing done with the full disc on the full image (OpenCV's exact grey
closing, 15-60x the time), on a vignetted light field with 3 % texture and a dark block
that covers most of it.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import tir_contact.reference as reference

TEXTURE = 0.03  # relative spread of the light's texture


def _scene() -> np.ndarray:
    rng = np.random.default_rng(0)
    yy, xx = np.mgrid[:160, :160]
    light = 200.0 - 0.004 * ((xx - 80) ** 2 + (yy - 70) ** 2)
    tex = cv2.GaussianBlur(rng.normal(0, 1, (160, 160)).astype(np.float32), (0, 0), 2.0)
    tex *= TEXTURE / tex.std()
    img = (light * (1 + tex)).astype(np.float32)
    img[25:140, 20:145] *= 0.1  # contact wider than the 101 px starting disc
    return img


@pytest.mark.parametrize("size_px", [241, pytest.param(321, marks=pytest.mark.slow)])
def test_wide_disc_closing_is_the_full_resolution_closing(size_px, monkeypatch):
    img = _scene()
    assert size_px > reference.MAX_DISC_PX  # the shrunk path
    fast = reference._closing(img, size_px)
    monkeypatch.setattr(reference, "MAX_DISC_PX", 10 ** 6)
    exact = reference._closing(img, size_px)
    rel = np.abs(fast / exact - 1.0)
    # block maxima lift the envelope by at most the texture's rise within a block: the
    # median stays under a tenth of the texture's spread, the largest under one spread
    # (measured: 0.07 % and 1.4-2.3 %)
    assert np.median(rel) < 0.1 * TEXTURE
    assert rel.max() < TEXTURE
