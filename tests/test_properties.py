"""Property tests of the TIR chain (darkness -> segmentation -> features) with hypothesis.

Random contact shapes inside a block footprint, noise levels and bit depths. Invariants:
an empty frame has zero area; the contact area never exceeds the block footprint; flipping
the image left-right together with the sliding direction gives the same numbers (positions
mirrored).
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tir_contact.features import BlockLayout, tir_frame_features
from tir_contact.flatfield import Reference, darkness
from tir_contact.segment import segment_frame

H, W = 48, 96
MM_PER_PX = 0.1
CONTRAST = 0.75  # darkness of touching rubber, as in the synthetic renderer


def _scene(seed: int, bit_depth: int, noise: float, shapes: list[tuple[int, int, int, int]]):
    """Reference and frame: uneven illumination, contact rectangles of darkness CONTRAST."""
    rng = np.random.default_rng(seed)
    max_dn = 2**bit_depth - 1
    x = np.linspace(0.0, 1.0, W)
    ref = 0.8 * max_dn * (0.7 + 0.3 * x)[None, :] * np.ones((H, 1))
    d = np.zeros((H, W))
    for r0, r1, c0, c1 in shapes:
        d[r0:r1, c0:c1] = CONTRAST
    frame = ref * (1.0 - d) * (1.0 + noise * rng.standard_normal((H, W)))
    dtype = np.uint8 if bit_depth == 8 else np.uint16
    frame = np.clip(np.round(frame), 0, max_dn).astype(dtype)
    return Reference(ref, np.ones((H, W), bool), "percentile", 32), frame


block = st.tuples(st.integers(2, 20), st.integers(8, 40))  # (top row, left column) of block
BLOCK_H, BLOCK_W = 24, 40


@st.composite
def shapes_in_block(draw):
    top, left = draw(block)
    n = draw(st.integers(0, 4))
    shapes = []
    for _ in range(n):
        r0 = draw(st.integers(top, top + BLOCK_H - 2))
        r1 = draw(st.integers(r0 + 1, top + BLOCK_H))
        c0 = draw(st.integers(left, left + BLOCK_W - 2))
        c1 = draw(st.integers(c0 + 1, left + BLOCK_W))
        shapes.append((r0, r1, c0, c1))
    return (top, left), shapes


common = settings(max_examples=60, deadline=None,
                  suppress_health_check=[HealthCheck.too_slow])


@common
@given(seed=st.integers(0, 2**16), bit_depth=st.sampled_from([8, 12, 16]),
       noise=st.floats(0.0, 0.05))
def test_empty_frame_has_zero_area(seed, bit_depth, noise):
    # noise up to 5 % is 7.5 sigma below the threshold C/2 = 0.375: never contact
    ref, frame = _scene(seed, bit_depth, noise, [])
    contact = segment_frame(darkness(frame, ref), contrast=CONTRAST)
    assert contact.area_px == 0 and contact.n_regions == 0
    f = tir_frame_features(darkness(frame, ref), contact, BlockLayout(MM_PER_PX, "left"))
    assert f.frame["contact_area_mm2"] == 0 and not f.frame["block_in_view"]


@common
@given(seed=st.integers(0, 2**16), bit_depth=st.sampled_from([8, 12, 16]),
       noise=st.floats(0.0, 0.05), scene=shapes_in_block(), estimate=st.booleans())
def test_area_never_exceeds_the_block(seed, bit_depth, noise, scene, estimate):
    (top, left), shapes = scene
    ref, frame = _scene(seed, bit_depth, noise, shapes)
    d = darkness(frame, ref)
    contact = segment_frame(d, contrast=None if estimate else CONTRAST, min_area_px=1)
    assert contact.area_px <= BLOCK_H * BLOCK_W
    footprint = np.zeros((H, W), bool)
    footprint[top : top + BLOCK_H, left : left + BLOCK_W] = True
    assert not (contact.mask & ~footprint).any()
    # every drawn pixel is found when the threshold is the known contrast's half
    drawn = np.zeros((H, W), bool)
    for r0, r1, c0, c1 in shapes:
        drawn[r0:r1, c0:c1] = True
    if not estimate:
        assert (contact.mask == drawn).all()


@common
@given(seed=st.integers(0, 2**16), bit_depth=st.sampled_from([8, 12, 16]),
       noise=st.floats(0.0, 0.03), left=st.integers(5, 40),
       lengths=st.tuples(st.integers(6, 14), st.integers(6, 14)), gap=st.integers(2, 6),
       lift=st.integers(0, 4))
def test_flipping_image_and_direction_gives_the_same_numbers(
    seed, bit_depth, noise, left, lengths, gap, lift
):
    # a two-element block sliding left: element 0 on the left, element 1's back lifted
    l0, l1 = lengths
    shapes = [(8, 40, left, left + l0), (8, 40, left + l0 + gap, left + l0 + gap + l1 - lift)]
    ref, frame = _scene(seed, bit_depth, noise, shapes)
    layout = BlockLayout(MM_PER_PX, "left", element_lengths_mm=(l0 * MM_PER_PX, l1 * MM_PER_PX),
                         sipe_width_mm=gap * MM_PER_PX)
    flipped_layout = BlockLayout(MM_PER_PX, "right", element_lengths_mm=layout.element_lengths_mm,
                                 sipe_width_mm=layout.sipe_width_mm)
    ref_f = Reference(ref.image[:, ::-1].copy(), ref.valid, "percentile", 32)
    a = tir_frame_features(darkness(frame, ref), segment_frame(darkness(frame, ref),
                           contrast=CONTRAST), layout)
    d_f = darkness(np.ascontiguousarray(frame[:, ::-1]), ref_f)
    b = tir_frame_features(d_f, segment_frame(d_f, contrast=CONTRAST), flipped_layout)
    width_mm = W * MM_PER_PX
    assert a.frame["contact_area_mm2"] == b.frame["contact_area_mm2"]
    assert a.frame["n_elements_in_contact"] == b.frame["n_elements_in_contact"]
    np.testing.assert_allclose(a.frame["block_front_x_mm"], width_mm - b.frame["block_front_x_mm"],
                               atol=1e-9)
    ea, eb = a.elements.set_index("element"), b.elements.set_index("element")
    assert list(ea.index) == list(eb.index) == [0, 1]
    for col in ("contact_area_mm2", "contact_length_mm", "liftoff_mm", "front_peak_contrast"):
        np.testing.assert_allclose(ea[col], eb[col], atol=1e-9, equal_nan=True)
    for col in ("front_edge_x_mm", "front_peak_x_mm"):
        np.testing.assert_allclose(ea[col], width_mm - eb[col], atol=1e-9, equal_nan=True)
    # and the numbers are the drawn ones. Edges are sub-pixel half-contrast crossings of
    # the column darkness: grey-level rounding and <= 3 % noise move them by well under
    # 0.1 px (0.01 mm) on these sharp edges
    np.testing.assert_allclose(ea["contact_length_mm"], [l0 * MM_PER_PX, (l1 - lift) * MM_PER_PX],
                               atol=0.1 * MM_PER_PX)
