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


def test_contact_across_the_whole_view_is_found_and_the_light_continued(monkeypatch):
    """A block face across the whole view (a camera that follows the block, close up: the
    face runs from the top to the bottom border over 75 % of the width, the free surface
    shows in two side bands only), darkness 0.75, on a vignetted light field with 1 %
    noise. Discs narrower than the view leave the face as dark as it is (it is wider than
    they are): the free surface was the face's own light, no contact. The widest disc
    fills it: the estimate continues the light under it to 1 % (the field is a quadratic,
    which the fit over the contact continues from the side bands' noisy pixels: 0.05-0.15 %
    over five noise draws)."""
    rng = np.random.default_rng(3)
    yy, xx = np.mgrid[:100, :300]
    light = 160.0 - 0.0012 * (xx - 150.0) ** 2 - 0.002 * (yy - 50.0) ** 2
    img = light.copy()
    img[:, 38:262] *= 0.25
    img = (img + rng.normal(0.0, 1.5, img.shape)).astype(np.float32)
    face = (slice(None), slice(45, 255))
    fs = reference.free_surface(img)
    assert fs.candidates[face].mean() > 0.99
    assert np.abs(fs.image[face] / light[face] - 1.0).max() < 0.01
    # without the widest disc (the earlier rule): the face is taken for free surface
    monkeypatch.setattr(reference, "_dark_beyond", lambda *a: False)
    old = reference.free_surface(img)
    assert old.candidates[face].mean() < 0.1


@pytest.mark.parametrize(("h", "w", "radius_px", "center_y"), [
    (256, 640, 161.0, 128.0),  # cut by the top and bottom borders
    (256, 640, 144.0, 128.0),  # cut nearer its top and bottom
    (512, 640, 157.0, 400.0),  # cut by the bottom border only
])
def test_free_surface_of_a_lit_disc_cut_by_the_border_is_its_light(h, w, radius_px, center_y):
    """A lit disc larger than the frame, no contact, a steep rim (tanh over 4 px, grey 4 to
    190), no noise: the estimate is the light itself on the lit zone. Before the zone was
    continued past the border along its edge (tir_contact._extension) it read the rim
    where the rim meets the border 0.5-0.75 darker than the light there (the closing
    filled a notch the continuation made), and took it for contact candidates; the
    steep rim's foot read 0.1-0.25 from the Gaussian smoothing and the interpolation
    back from the working scale. Tolerance: 0.05, under half the candidate darkness
    (0.1)."""
    from tir_contact.illumination import find_lit_zone

    yy, xx = np.mgrid[:h, :w].astype(float)
    dist = np.hypot(xx - w / 2, yy - center_y) - radius_px
    light = (4.0 + 186.0 * 0.5 * (1 - np.tanh(dist / 4.0))).astype(np.float32)
    lit = find_lit_zone(light).mask
    assert 0 < lit[0].sum() < w or 0 < lit[-1].sum() < w  # the rim crosses a border
    fs = reference.free_surface(light, lit)
    smooth = cv2.GaussianBlur(light, (0, 0), reference.SMOOTH_SIGMA_PX,
                              borderType=cv2.BORDER_REPLICATE)
    excess = (1.0 - smooth / fs.image)[lit]
    assert excess.max() < 0.05
    assert not fs.candidates.any()
