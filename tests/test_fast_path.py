"""The fast per-frame path of the TIR analysis against its plain definitions.

Truths: ``np.percentile`` for the sorting-network reference, the float32 darkness of the
normaliser for the raw grey-value threshold (pixel for pixel), scikit-image's labelling and
small-object removal for the region labelling, and the plain full-frame path of
``analyze_video`` for the whole analysis (the fast path must give the same tables).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from skimage.measure import label

import tir_contact.analyze as analyze_module
from synthetic.footage import CameraSettings, FootageSpec, render_footage
from tir_contact._darkness import BoxDarkness, Normaliser, RawContactTest
from tir_contact._percentile import pixelwise_percentile
from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.calibrate import Reference
from tir_contact.segment import contact_box, label_contact


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 17, 32, 33, 64])
@pytest.mark.parametrize("q", [0.0, 10.0, 50.0, 90.0, 97.3, 100.0])
def test_pixelwise_percentile_is_numpys(n, q):
    rng = np.random.default_rng(n)
    frames = [rng.integers(0, 4096, (6, 9), dtype=np.uint16) for _ in range(n)]
    expected = np.percentile(np.stack(frames).astype(float), q, axis=0)
    # numpy interpolates in float64 here too: equal to rounding (1e-9 of a grey value)
    np.testing.assert_allclose(pixelwise_percentile(frames, q), expected, rtol=0, atol=1e-9)
    assert frames[0].dtype == np.uint16  # inputs untouched


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
@pytest.mark.parametrize("contact_is", ["dark", "bright"])
def test_raw_threshold_equals_the_darkness_threshold_pixel_for_pixel(dtype, contact_is):
    rng = np.random.default_rng(7)
    top = np.iinfo(dtype).max
    for trial in range(40):
        ref = rng.uniform(0.5, top, (24, 31))
        if trial % 2:
            ref = np.round(ref * 2) / 2  # percentile references are often half-integers
        valid = ref > 0.2 * np.median(ref)
        norm = Normaliser(Reference(ref, valid, "test", 1), contact_is)
        t = float(rng.uniform(0.01, 0.9))
        test = RawContactTest.build(norm, t, dtype)
        assert test is not None
        # random frames and frames right at the crossing (where rounding decides)
        edge = ref * (1 - t) if contact_is == "dark" else ref * (1 + t)
        for frame in (rng.integers(0, top + 1, ref.shape, dtype=dtype),
                      np.clip(np.floor(edge), 0, top).astype(dtype),
                      np.clip(np.ceil(edge), 0, top).astype(dtype)):
            np.testing.assert_array_equal(test(frame), norm(frame) >= np.float32(t))


def test_raw_threshold_declines_what_it_cannot_do():
    ref = np.full((4, 4), 200.0)
    norm = Normaliser(Reference(ref, ref > 0, "test", 1), "dark")
    assert RawContactTest.build(norm, 0.3, np.float32) is None  # float frames
    assert RawContactTest.build(norm, 0.0, np.uint8) is None  # no positive threshold
    test = RawContactTest.build(norm, 0.3, np.uint8)
    assert test(np.zeros((4, 4), np.uint16)) is None  # another dtype: the caller falls back


def test_box_darkness_is_the_darkness_inside_and_nan_outside():
    rng = np.random.default_rng(2)
    ref = rng.uniform(100, 250, (20, 30))
    norm = Normaliser(Reference(ref, ref > 0, "test", 1), "dark")
    box = BoxDarkness(norm, ref.shape)
    frame = rng.integers(0, 256, ref.shape, dtype=np.uint8)
    first = box.fill(frame, slice(2, 9), slice(4, 20)).copy()
    np.testing.assert_array_equal(first[2:9, 4:20], norm(frame)[2:9, 4:20])
    second = box.fill(frame, slice(10, 12), slice(0, 3))  # the old box is cleared
    assert np.isnan(second[2:9, 4:20]).all()
    assert np.isfinite(second).sum() == 2 * 3


def test_label_contact_matches_scikit_image():
    rng = np.random.default_rng(11)
    for trial in range(400):
        raw = rng.random(tuple(rng.integers(1, 25, 2))) < rng.uniform(0.02, 0.8)
        min_area = int(rng.integers(1, 12))
        contact = label_contact(raw, 0.5, min_area_px=min_area)
        truth = label(raw, connectivity=2)
        areas = np.bincount(truth.ravel())[1:]
        kept = np.isin(truth, 1 + np.flatnonzero(areas >= min_area))
        np.testing.assert_array_equal(contact.mask, kept, err_msg=f"trial {trial}")
        assert contact.n_regions == int((areas >= min_area).sum())
        assert contact.area_px == int(kept.sum())
        if contact.box is not None:
            assert contact_box(kept) is not None
            np.testing.assert_array_equal(contact.labels > 0, kept)


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fast") / "G3"
    spec = FootageSpec(preset="G3", velocity_mps=3.0, n_frames=120, dynamics="steady",
                       camera=CameraSettings(mm_per_px=0.2, width_px=320, height_px=128))
    render_footage(spec, folder, fmt="multitiff", progress=False)
    return folder


@pytest.mark.parametrize("regions", ["auto", "always"])
def test_fast_path_gives_the_plain_paths_tables(clip, monkeypatch, regions):
    options = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0,
                              regions=regions)
    fast = analyze_video(clip, options=options)
    monkeypatch.setattr(analyze_module._FrameAnalyser, "_raw_test", lambda self, frame: None)
    plain = analyze_video(clip, options=options)
    assert fast.frames["block_in_view"].any()
    pd.testing.assert_frame_equal(fast.frames, plain.frames)
    pd.testing.assert_frame_equal(fast.elements, plain.elements)
    if regions == "always":
        pd.testing.assert_frame_equal(fast.regions, plain.regions)
