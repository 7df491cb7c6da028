"""The one per-frame path of the TIR analysis against its plain definitions.

Truths: ``np.percentile`` for the sorting-network reference, the float32 darkness of the
normaliser for the raw grey-value threshold (pixel for pixel) and for the box darkness (bit
for bit), scikit-image's labelling and small-object removal for the region labelling, numpy
sums for the box and line counts, the plain numpy scoring for the template fit, and, for
the whole step on a rendered clip, a direct float64 numpy darkness ``1 - I / I_ref``,
threshold and scipy labelling of every frame.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import tifffile
from scipy import ndimage
from skimage.measure import label

from tir_contact._darkness import BoxDarkness, Normaliser, RawContactTest
from tir_contact._percentile import pixelwise_percentile
from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.features import _fit_offset
from tir_contact.flatfield import Reference, darkness
from tir_contact.frame import FrameAnalyser
from tir_contact.io import open_footage
from tir_contact.measure import EDGE_PX, ZONE_PX, frame_area
from tir_contact.prepare import prepare_video
from tir_contact.segment import (
    _box_and_counts,
    _may_hold_small,
    contact_box,
    estimate_contrast,
    label_contact,
)


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 17, 32, 33, 64])
@pytest.mark.parametrize("q", [0.0, 10.0, 50.0, 90.0, 97.3, 100.0])
def test_pixelwise_percentile_is_numpys(n, q):
    rng = np.random.default_rng(n)
    frames = [rng.integers(0, 4096, (6, 9), dtype=np.uint16) for _ in range(n)]
    expected = np.percentile(np.stack(frames).astype(float), q, axis=0)
    # numpy interpolates in float64 here too: equal to rounding (1e-9 of a grey value)
    np.testing.assert_allclose(pixelwise_percentile(frames, q), expected, rtol=0, atol=1e-9)
    assert frames[0].dtype == np.uint16  # inputs untouched


@pytest.mark.parametrize("contact_is", ["dark", "bright"])
def test_darkness_is_the_flat_field_ratio_with_nan_where_excluded(contact_is):
    # one convention for excluded pixels: NaN; the values are 1 - I/I_ref (I/I_ref - 1) in
    # float64, written out here
    rng = np.random.default_rng(3)
    ref = rng.uniform(20.0, 250.0, (24, 31))
    valid = rng.random(ref.shape) > 0.2
    frame = rng.integers(0, 256, ref.shape, dtype=np.uint8)
    reference = Reference(ref, valid, "test", 1)
    got = darkness(frame, reference, contact_is=contact_is)
    ratio = frame / ref
    truth = 1.0 - ratio if contact_is == "dark" else ratio - 1.0
    assert got.dtype == np.float32
    assert np.array_equal(np.isnan(got), ~valid)
    # float32: I * (-1/I_ref) + 1, a few ulp of values up to ~12
    np.testing.assert_allclose(got[valid], truth[valid], rtol=0, atol=1e-5)
    # the analysis's normaliser is the same arithmetic, bit for bit
    np.testing.assert_array_equal(Normaliser(reference, contact_is)(frame).view(np.uint32),
                                  got.view(np.uint32))


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
def clip(render_clip, tmp_path_factory):
    return render_clip(tmp_path_factory.mktemp("fast") / "G3", "multitiff", n_frames=120)


#: A pixel whose float64 darkness lies this close to the threshold may fall either side of
#: it in the pipeline's float32 arithmetic (a few ulp of values below 2: 1e-6 is ample).
_AMBIGUOUS = 1e-5


@pytest.mark.parametrize("as_float", [False, True])
def test_one_path_is_a_direct_numpy_darkness_threshold_and_labelling(clip, as_float):
    # every frame through the pipeline's own step (integer frames: the raw grey-value test;
    # float frames: the darkness test) against the definitions written out in float64
    options = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0,
                              regions="always")
    with open_footage(clip / "footage.tif") as reader:
        setup = prepare_video(reader, clip / "footage.tif", None, options)
        analyser = FrameAnalyser(setup, options)
        ref = setup.reference
        t = setup.view.threshold
        seen = 0
        for i in range(0, len(reader), 3):
            frame = reader.get_frame(i)
            if as_float:
                frame = frame.astype(np.float32)
            result = analyser(i, frame)
            d64 = np.where(ref.valid, 1.0 - frame / np.maximum(ref.image, 1e-6), np.nan)
            with np.errstate(invalid="ignore"):
                raw = d64 >= t
                sure = ~(np.abs(d64 - t) < _AMBIGUOUS)
            lab, n = ndimage.label(raw, structure=np.ones((3, 3), int))
            area = np.bincount(lab.ravel(), minlength=n + 1)
            keep = area >= options.min_area_px
            keep[0] = False
            expected = keep[lab]
            mask = result.detail.mask
            np.testing.assert_array_equal(mask[sure], expected[sure], err_msg=f"frame {i}")
            assert result.row["n_regions"] == int(keep.sum()), i
            # the regions' mean darkness is the darkness of their pixels (float32 sums)
            for r in range(result.regions["label"].size):
                pix = result.detail.labels == result.regions["label"][r]
                np.testing.assert_allclose(result.regions["mean_darkness"][r],
                                           d64[pix].mean(), rtol=0, atol=1e-5)
            seen += int(keep.sum() > 0)
            # the area reads the box round the seeds and the contact, with the raw tests
            # as its pixels: the same as frame_area on the whole frame's float32 darkness
            # and that box found by numpy
            want = _boxed_area(frame, setup, analyser.step.normalise)
            for col, px in zip(("contact_area_mm2", "contact_area_low_mm2",
                                "contact_area_high_mm2"), want, strict=True):
                assert result.row[col] == pytest.approx(px * setup.mm_per_px ** 2,
                                                        rel=1e-12, abs=1e-15), (i, col)
    assert seen > 10  # the clip shows contact in most sampled frames


def _boxed_area(frame, setup, normalise):
    """frame_area on the float32 darkness of the whole frame, in the box round the seeds
    and the contact grown by the zone (px: area, low, high)."""
    model = setup.view.area_model
    d = normalise(frame)
    with np.errstate(invalid="ignore"):
        on = (d >= model.seed) | (d >= model.threshold)
    rows, cols = np.flatnonzero(on.any(axis=1)), np.flatnonzero(on.any(axis=0))
    if rows.size == 0:
        return 0.0, 0.0, 0.0
    g = ZONE_PX + EDGE_PX + 1
    box = (slice(max(rows[0] - g, 0), min(rows[-1] + 1 + g, d.shape[0])),
           slice(max(cols[0] - g, 0), min(cols[-1] + 1 + g, d.shape[1])))
    a = frame_area(d, model, box)
    return a.area_px, a.low_px, a.high_px


def test_the_peak_window_option_sets_where_the_front_peak_is_searched(tmp_path):
    # a contact strip from column 50 (5.0 mm) whose darkest band lies 1.5 mm behind its
    # front (columns 65-67, centre 6.65 mm); the peak is searched within peak_window_mm of
    # the front: 1 mm finds the flat front, 2 mm the band
    frames = np.full((10, 40, 200), 200, np.uint8)
    frames[3:7, 10:30, 50:120] = 80  # darkness 0.6
    frames[3:7, 10:30, 65:68] = 20  # darkness 0.9
    tifffile.imwrite(tmp_path / "clip.tif", frames)
    meta = {"fps": 1000, "mm_per_px": 0.1, "sliding_direction": "left"}
    (tmp_path / "meta.json").write_text(json.dumps(meta))
    peaks = {}
    for window in (1.0, 2.0):
        options = AnalysisOptions(overlay_frames=0, camera="fixed", peak_window_mm=window)
        frames_df = analyze_video(tmp_path / "clip.tif", options=options).frames
        peaks[window] = frames_df["front_peak_x_mm"].to_numpy()[3:7]
        assert np.isnan(frames_df["front_peak_x_mm"].to_numpy()[[0, 1, 2, 7, 8, 9]]).all()
    # the first column's centre (sub-pixel shift <= half a column) and the band's centre
    np.testing.assert_allclose(peaks[1.0], 5.05, atol=0.05)
    np.testing.assert_allclose(peaks[2.0], 6.65, atol=0.05)


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.uint32, np.float32])
@pytest.mark.parametrize("contact_is", ["dark", "bright"])
def test_box_darkness_follows_moving_boxes_bit_for_bit(dtype, contact_is):
    # OpenCV's multiply and add into the image view against the normaliser's own float32
    # arithmetic (bit for bit), and the partial clearing of the previous box (NaN outside)
    rng = np.random.default_rng(5)
    top = np.iinfo(dtype).max if np.issubdtype(dtype, np.integer) else 4095.0
    ref = rng.uniform(0.5, top, (23, 37))
    norm = Normaliser(Reference(ref, ref > 0.2 * np.median(ref), "test", 1), contact_is)
    box = BoxDarkness(norm, ref.shape)
    for _ in range(60):
        if np.issubdtype(dtype, np.integer):
            frame = rng.integers(0, top, ref.shape, dtype=dtype, endpoint=True)
        else:
            frame = rng.uniform(0, top, ref.shape).astype(dtype)
        r0, r1 = np.sort(rng.integers(0, 24, 2)) + np.array([0, 1])
        c0, c1 = np.sort(rng.integers(0, 38, 2)) + np.array([0, 1])
        rows, cols = slice(int(r0), int(min(r1, 23))), slice(int(c0), int(min(c1, 37)))
        image = box.fill(frame, rows, cols)
        expected = np.full(ref.shape, np.nan, np.float32)
        expected[rows, cols] = norm(frame)[rows, cols]
        np.testing.assert_array_equal(image.view(np.uint32), expected.view(np.uint32))


def test_box_and_counts_are_the_box_and_line_sums():
    rng = np.random.default_rng(3)
    for trial in range(200):
        raw = rng.random(tuple(rng.integers(1, 30, 2))) < rng.uniform(0.0, 0.3)
        box, counts = _box_and_counts(raw)
        cols = np.flatnonzero(raw.any(axis=0))
        if cols.size == 0:
            assert box is None and counts is None
            continue
        rows = np.flatnonzero(raw.any(axis=1))
        assert box == (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
        np.testing.assert_array_equal(counts[0], raw.sum(axis=0), err_msg=f"trial {trial}")
        np.testing.assert_array_equal(counts[1], raw.sum(axis=1), err_msg=f"trial {trial}")
        # the counts handed to the contact hold only when no region was dropped
        contact = label_contact(raw, 0.5, min_area_px=3)
        np.testing.assert_array_equal(contact.line_counts[0], contact.mask.sum(axis=0))
        np.testing.assert_array_equal(contact.line_counts[1], contact.mask.sum(axis=1))


def test_fit_offset_matches_the_plain_numpy_scoring():
    # the scoring as first written (one (K, N, J) array, np.concatenate of the candidates)
    def plain(starts, ends, fronts, lengths, n_cols, x0_carrier):
        cands = []
        j = next((j for j, c in enumerate(starts) if c > 0), None)
        if j is not None:
            cands.append(starts[j] - fronts)
        if ends[0] < n_cols - 1:
            cands.append(ends[0] + 1.0 - fronts - lengths)
        if np.isfinite(x0_carrier):
            cands.append(np.array([x0_carrier]))
        if not cands:
            return float(starts[0] - fronts[0])
        x0 = np.concatenate(cands)[:, None]
        lo = np.minimum(np.maximum(x0 + fronts, 0.0), n_cols)
        hi = np.minimum(np.maximum(x0 + fronts + lengths, 0.0), n_cols)
        s, e = np.asarray(starts, float), np.asarray(ends, float) + 1.0
        ov = np.minimum(hi[:, :, None], e) - np.maximum(lo[:, :, None], s)
        overlap = np.maximum(ov, 0.0).sum(axis=(1, 2))
        cost = (0.25 * ((hi - lo).sum(axis=1) - overlap) - overlap).tolist()
        best = min(cost) + 0.5
        tied = [x for x, c in zip(x0[:, 0].tolist(), cost, strict=True) if c <= best]
        if len(tied) > 1 and np.isfinite(x0_carrier):
            return min(tied, key=lambda x: abs(x - x0_carrier))
        return tied[0]

    rng = np.random.default_rng(9)
    for _ in range(500):
        n_el = int(rng.integers(1, 6))
        lengths = rng.uniform(5, 60, n_el)
        fronts = np.concatenate([[0.0], np.cumsum(lengths[:-1] + rng.uniform(0, 8))])
        n_cols = int(rng.integers(40, 300))
        cuts = np.sort(rng.choice(np.arange(n_cols + 1), 2 * int(rng.integers(1, 5)),
                                  replace=False))
        starts, ends = cuts[0::2].tolist(), (cuts[1::2] - 1).tolist()
        keep = [k for k in range(len(starts)) if ends[k] >= starts[k]]
        starts, ends = [starts[k] for k in keep], [ends[k] for k in keep]
        if not starts:
            continue
        carrier = float(rng.uniform(-50, n_cols)) if rng.random() < 0.7 else np.nan
        got = _fit_offset(starts, ends, fronts, lengths, n_cols, carrier)
        assert got == plain(starts, ends, fronts, lengths, n_cols, carrier)


def test_small_region_shortcut_is_the_neighbour_count_test():
    # True exactly when some set pixel sees fewer than min_area set pixels in its 3 x 3
    # neighbourhood (zero padding), for every min_area the shortcut handles
    from scipy import ndimage

    rng = np.random.default_rng(4)
    for trial in range(300):
        sub = (rng.random(tuple(rng.integers(1, 20, 2))) < rng.uniform(0.05, 0.95))
        sub = sub.astype(np.uint8)
        nb = ndimage.convolve(sub.astype(int), np.ones((3, 3), int), mode="constant")
        for min_area in range(2, 10):
            expected = bool(np.any((nb < min_area) & (sub > 0)))
            assert _may_hold_small(sub, min_area) == expected, (trial, min_area)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_estimate_contrast_is_the_median_of_the_finite_dark_pixels(dtype):
    rng = np.random.default_rng(8)
    for trial in range(200):
        d = rng.uniform(-1, 1.5, tuple(rng.integers(1, 30, 2))).astype(dtype)
        m = rng.random(d.shape)
        d[m < 0.05] = np.nan
        d[(m > 0.05) & (m < 0.08)] = np.inf
        d[(m > 0.08) & (m < 0.1)] = -np.inf
        min_darkness = float(rng.choice([0.25, 0.0, -np.inf, np.nan, 2.0]))
        dark = d[np.isfinite(d) & (d > min_darkness)]
        expected = float(np.median(dark)) if dark.size else np.nan
        got = estimate_contrast(d, min_darkness=min_darkness)
        assert (np.isnan(expected) and np.isnan(got)) or got == expected, trial
