"""Element runs of graded contact (tir_contact.graded through tir_frame_features).

The truth is drawn here, not by the renderer: faces of rough contact whose junctions are
eighth-pixel squares, each in contact with a probability that falls from the face's front
to its back, averaged onto the pixel grid, blurred and noised. The faces' exact extents are
the truth the lengths and fronts are checked against.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from scipy.stats import norm

from tir_contact.features import BlockLayout, tir_frame_features
from tir_contact.graded import FreeLevel, graded_contact, graded_share, presence_runs
from tir_contact.segment import segment_frame

MM_PER_PX = 0.1
SUB = 8  # sub-pixels per pixel along each axis
B, C, SIGMA = 0.02, 0.97, 0.02  # free surface, full contact, pixel noise (darkness)
ROWS, COLS = 60, 200
#: faces: (front, contact length) px; the elements are 3 mm long with 1 mm sipes; the back
#: of elements 1 and 2 is lifted by 0.5 and 1 mm
FACES = [(20.3, 30.0), (60.3, 25.0), (100.3, 20.0)]
#: real contact at a face's front and behind its dense band, and the band's decay length
#: (px): the pressure peak at the front edge (as on the physical blocks' faces)
FRONT, BACK, DECAY_PX = 1.0, 0.08, 3.0


def _junction_field(seed: int, flip: bool = False) -> np.ndarray:
    """Darkness of graded faces (sliding left; mirrored with `flip`): real contact falls
    from :data:`FRONT` at each face's front, over :data:`DECAY_PX`, to :data:`BACK`, the
    share of its junctions that lie behind the front's dense band."""
    rng = np.random.default_rng(seed)
    x = (np.arange(COLS * SUB) + 0.5) / SUB
    share = np.zeros(x.size)
    for front, length in FACES:
        on = (x >= front) & (x < front + length)
        share[on] = BACK + (FRONT - BACK) * np.exp(-(x[on] - front) / DECAY_PX)
    covered = rng.random((ROWS * SUB, COLS * SUB)) < share
    cover = covered.reshape(ROWS, SUB, COLS, SUB).mean(axis=(1, 3))
    cover = cv2.GaussianBlur(cover, (0, 0), 0.6)  # the optics' blur
    d = B + (C - B) * cover + rng.normal(0.0, SIGMA, cover.shape)
    return (d[:, ::-1] if flip else d).astype(np.float32)


def _layout(direction: str = "left") -> BlockLayout:
    return BlockLayout(MM_PER_PX, direction, element_lengths_mm=(3.0, 3.0, 3.0),
                       sipe_width_mm=1.0)


def _features(d: np.ndarray, direction: str = "left", free: FreeLevel | None = None):
    # the analysis's decision level: half of full contact
    contact = segment_frame(d, threshold=0.5 * C)
    return tir_frame_features(d, contact, _layout(direction), free=free)


FREE = FreeLevel(B, SIGMA, C)  # white noise: the correlation area is one pixel


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("direction", ["left", "right"])
def test_graded_faces_read_their_whole_contact_length(seed, direction):
    d = _junction_field(seed, flip=direction == "right")
    el = _features(d, direction, FREE).elements.set_index("element")
    assert el.index.tolist() == [0, 1, 2]  # numbered as drawn
    truth_mm = np.array([length for _, length in FACES]) * MM_PER_PX
    fronts = np.array([front for front, _ in FACES]) * MM_PER_PX
    if direction == "right":
        fronts = COLS * MM_PER_PX - fronts
    ahead_mm = (fronts - el.front_edge_x_mm) * (1 if direction == "left" else -1)
    # The edges are read where the column mean clears the presence level, at the foot of
    # the blurred step outside the drawn edge: as far out as the blur (sigma 0.6 px) brings
    # the level's share of the step, plus the pixel's half, and never inside it (0.2 px
    # for the noise). The level lies 4 sigma / sqrt(rows) above the free surface.
    excess = FREE.level(ROWS) - B
    front_px = norm.isf(excess / ((C - B) * FRONT)) * 0.6 + 0.5
    back_px = norm.isf(excess / ((C - B) * BACK)) * 0.6 + 0.5
    assert np.all(ahead_mm > -0.02) and np.all(ahead_mm < front_px * MM_PER_PX)
    length_err = el.contact_length_mm - truth_mm
    # the upper bound: both edges' feet and half a pixel for the junctions' draw at the back
    assert np.all(length_err > -0.04)
    assert np.all(length_err < (front_px + back_px + 0.5) * MM_PER_PX)
    # the lifted backs are told apart: each face 0.5 mm shorter than the one before (the
    # edges' biases are alike on alike faces: within 1 px)
    np.testing.assert_allclose(np.diff(el.contact_length_mm), [-0.5, -0.5], atol=0.1)
    # each face's area is its unmixed darkness: the drawn share integrated over the face
    share_px = BACK * truth_mm / MM_PER_PX + (FRONT - BACK) * DECAY_PX * (
        1 - np.exp(-truth_mm / MM_PER_PX / DECAY_PX))
    area_mm2 = share_px * ROWS * MM_PER_PX ** 2
    np.testing.assert_allclose(el.contact_area_mm2, area_mm2, rtol=0.05)  # 5 %: the draw


@pytest.mark.parametrize("direction", ["left", "right"])
def test_a_face_leaving_the_view_keeps_its_number(direction):
    """Element 0's front (and its dense band) has left the view, its faint back has not:
    it is found, clipped at the view's end, and the faces behind it keep their numbers."""
    d = _junction_field(0, flip=direction == "right")
    d = d[:, 25:] if direction == "left" else d[:, :-25]
    el = _features(d, direction, FREE).elements.set_index("element")
    assert el.index.tolist() == [0, 1, 2]
    assert np.isnan(el.front_edge_x_mm[0]) and np.isnan(el.liftoff_mm[0])
    # the visible part of face 0: 50.3 - 25 px, its back read at the blur's foot (1 px)
    assert el.contact_length_mm[0] == pytest.approx(2.53, abs=0.1 + 0.05)
    np.testing.assert_allclose(el.contact_length_mm[[1, 2]], [2.5, 2.0], atol=0.3)


def test_the_half_coverage_runs_alone_miss_a_graded_face():
    """Why the presence runs exist: without them a graded face reads a fraction of its
    contact (the dark front only)."""
    d = _junction_field(0)
    el = _features(d).elements
    assert len(el) < 3 or el.contact_length_mm.max() < 0.6 * 3.0


def _plateau(seed: int) -> np.ndarray:
    d = np.full((ROWS, COLS), B, np.float32)
    for front, length in FACES:
        d[:, math.ceil(front): math.ceil(front + length)] = C
    d = cv2.GaussianBlur(d, (0, 0), 0.6)
    return d + np.random.default_rng(seed).normal(0.0, SIGMA, d.shape).astype(np.float32)


def test_a_junction_field_is_graded_and_a_plateau_is_not():
    assert graded_contact([_junction_field(k) for k in range(3)], 0.5 * C, FREE)
    assert not graded_contact([_plateau(k) for k in range(3)], 0.5 * C, FREE)
    # a smooth grey face whose darkness falls linearly to zero at its back: half its
    # columns reach half of its front's darkness
    x = np.arange(COLS)
    ramp = np.where((x >= 20) & (x < 50), 1.0 - (x - 20) / 30.0, 0.0)
    grey = np.broadcast_to(B + (C - B) * ramp, (ROWS, COLS)).astype(np.float32)
    assert graded_share(grey, 0.5 * C, FREE) == pytest.approx(0.5, abs=0.05)
    assert not graded_contact([grey], 0.5 * C, FREE)
    assert graded_share(np.full((ROWS, COLS), B, np.float32), 0.5 * C, FREE) is None


def test_presence_level_is_the_column_noise_above_the_free_surface():
    free = FreeLevel(0.02, 0.03, 0.97)
    assert free.level(100) == pytest.approx(0.02 + 4.0 * 0.03 / 10.0)
    # a single column above the level is noise; two are a run
    p = np.array([0.0, 0.5, 0.0, 0.5, 0.5, 0.0])
    assert presence_runs(p, 0.1) == ([3], [4])
