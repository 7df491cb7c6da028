"""Per-frame TIR features against analytic frames and the renderer's ground truth."""

import math

import numpy as np
import pandas as pd
import pytest
from _footage import STEADY_SETTLE_S

from friction_model.geometry import reference_block
from synthetic.footage import CameraSettings, FootageSpec, iter_frames
from tir_contact.features import (
    ELEMENT_FIELDS,
    FRAME_KEYS,
    BlockLayout,
    tir_frame_features,
    tir_frame_records,
)
from tir_contact.flatfield import darkness, reference_from_frames
from tir_contact.segment import segment_frame

PX = 0.1  # mm per pixel of the analytic frames and of the default camera


# -- analytic frames ---------------------------------------------------------------------------
def strips(width, spans, *, rows=12, level=0.8):
    """Darkness image with full-height strips over columns [a, b) (fractional ends allowed)."""
    d = np.zeros((rows, width), np.float32)
    for a, b in spans:
        ia, ib = math.floor(a), math.ceil(b)
        d[:, ia:ib] = level
        d[:, ia] *= 1.0 - (a - ia)  # partial coverage of the edge columns
        if b != ib:
            d[:, ib - 1] *= 1.0 - (ib - b)
    return d


def features(d, layout, **kw):
    return tir_frame_features(d, segment_frame(d), layout, **kw)


def layout4(direction="left", **kw):
    # four 1.0 mm elements (10 px) behind 0.5 mm sipes (5 px)
    return BlockLayout(PX, direction, element_lengths_mm=(1.0,) * 4, sipe_width_mm=0.5, **kw)


def test_two_strips_with_a_gap_are_two_elements_with_exact_lengths():
    d = strips(60, [(5, 15), (20, 30)])
    layout = BlockLayout(PX, "left", element_lengths_mm=(1.0, 1.0), sipe_width_mm=0.5)
    f = features(d, layout)
    el = f.elements
    assert list(el.columns) == ELEMENT_FIELDS
    assert list(f.frame) == FRAME_KEYS
    assert el["element"].tolist() == [0, 1]
    # Edges on pixel boundaries: the half-level crossings are exact (1e-6 for float32).
    np.testing.assert_allclose(el["contact_length_mm"], [1.0, 1.0], atol=1e-6)
    np.testing.assert_allclose(el["front_edge_x_mm"], [0.5, 2.0], atol=1e-6)
    np.testing.assert_allclose(el["contact_area_mm2"], [10 * 12 * PX**2] * 2, rtol=1e-12)
    np.testing.assert_allclose(el["liftoff_mm"], [0.0, 0.0], atol=1e-6)
    assert f.frame["block_in_view"] is True
    assert f.frame["contact_area_mm2"] == pytest.approx(240 * PX**2)
    assert f.frame["contact_ratio"] == pytest.approx(1.0)
    assert f.frame["n_elements_in_contact"] == 2
    assert f.frame["n_regions"] == 2
    assert math.isnan(f.frame["deflection_angle_deg"])  # no trajectory given


def test_sub_pixel_edges_from_partial_coverage():
    # Strip from x = 5.3 px to 17.6 px: the edge columns hold 70 % and 60 % contact.
    # Linear interpolation of the half-level crossing between pixel centres is exact for
    # coverages 0.5 and 1 and within 0.09 px otherwise (a step edge sampled by box pixels).
    d = strips(40, [(5.3, 17.6)])
    layout = BlockLayout(PX, "left", element_lengths_mm=(1.23,))
    el = features(d, layout).elements
    assert el["front_edge_x_mm"].iloc[0] == pytest.approx(0.53, abs=0.009)
    assert el["contact_length_mm"].iloc[0] == pytest.approx(1.23, abs=0.018)


def test_liftoff_is_element_length_minus_contact():
    # Element 1's trailing 0.3 mm are lifted, element 2 touches only over 0.4 mm (less than
    # half its length: it must still be numbered 2, not dropped or shifted).
    d = strips(80, [(5, 15), (20, 27), (35, 39), (50, 60)])
    f = features(d, layout4())
    el = f.elements
    assert el["element"].tolist() == [0, 1, 2, 3]
    np.testing.assert_allclose(el["liftoff_mm"], [0.0, 0.3, 0.6, 0.0], atol=1e-6)
    np.testing.assert_allclose(el["contact_length_mm"], [1.0, 0.7, 0.4, 1.0], atol=1e-6)
    assert f.frame["contact_ratio"] == pytest.approx(31 / 40)


@pytest.mark.parametrize("direction", ["left", "right"])
def test_entering_and_leaving_blocks_are_numbered_from_the_leading_element(direction):
    def frame(spans):
        d = strips(60, spans)
        return d[:, ::-1].copy() if direction == "right" else d

    # Sliding left: the block enters at the right border (elements 2, 3 still outside) ...
    el = features(frame([(35, 45), (50, 60)]), layout4(direction)).elements
    assert el["element"].tolist() == [0, 1]
    assert math.isnan(el["liftoff_mm"].iloc[1])  # element 1 reaches the border
    np.testing.assert_allclose(el["contact_length_mm"], [1.0, 1.0], atol=1e-6)
    # ... and leaves at the left border (elements 0, 1 already gone, element 2 clipped).
    el = features(frame([(0, 4), (9, 19)]), layout4(direction)).elements
    assert el["element"].tolist() == [2, 3]
    assert math.isnan(el["front_edge_x_mm"].iloc[0])  # its front is outside the image
    np.testing.assert_allclose(el["contact_length_mm"], [0.4, 1.0], atol=1e-6)
    expected_front = 0.9 if direction == "left" else 6.0 - 0.9
    assert el["front_edge_x_mm"].iloc[1] == pytest.approx(expected_front, abs=1e-6)


def test_mirrored_frame_gives_mirrored_positions():
    d = strips(80, [(5, 15), (20, 27), (35, 45), (50, 60)])
    left = features(d, layout4("left")).elements
    right = features(d[:, ::-1].copy(), layout4("right")).elements
    assert right["element"].tolist() == left["element"].tolist()
    np.testing.assert_allclose(right["contact_length_mm"], left["contact_length_mm"], atol=1e-6)
    np.testing.assert_allclose(right["front_edge_x_mm"], 8.0 - left["front_edge_x_mm"], atol=1e-6)


def test_closed_sipe_is_split_at_the_template():
    # Elements 1 and 2 touch across a closed sipe: one run of 25 px is split at the sipe
    # centre of the fitted template (x = 32.5 px -> cut at column 32 or 33).
    d = strips(80, [(5, 15), (20, 45), (50, 60)])
    el = features(d, layout4()).elements
    assert el["element"].tolist() == [0, 1, 2, 3]
    assert el["contact_length_mm"].iloc[1] + el["contact_length_mm"].iloc[2] == pytest.approx(2.5)
    assert abs(el["contact_length_mm"].iloc[1] - 1.25) <= 0.05 + 1e-9


def test_front_peak_position_width_and_contrast():
    # A parabolic band on a plateau of 0.8: D = 0.8 + 0.12 (1 - ((x - 9.3) / 3)^2) for
    # |x - 9.3| < 3 px (x at pixel centres), element from column 6 to 40. The parabola
    # through three samples of a parabola recovers its vertex exactly; the FWHM by linear
    # interpolation between pixel centres is within 0.1 px of the exact 3 sqrt(2) px.
    d = strips(60, [(6, 40)])
    xc = np.arange(60) + 0.5
    band = 0.12 * np.clip(1.0 - ((xc - 9.3) / 3.0) ** 2, 0.0, None)
    d[:, 6:40] += band[6:40].astype(np.float32)
    layout = BlockLayout(PX, "left", element_lengths_mm=(3.4,))
    el = features(d, layout).elements.iloc[0]
    assert el["front_peak_x_mm"] == pytest.approx(0.93, abs=1e-4)
    assert el["front_peak_contrast"] == pytest.approx(0.12 * (1 - (0.2 / 3) ** 2), abs=1e-5)
    assert el["front_peak_width_mm"] == pytest.approx(0.3 * math.sqrt(2), abs=0.01)


def test_deflection_from_the_carrier_trajectory():
    # Carrier at rest (v = 0) with its centre on the image centre (4 mm): the undeformed
    # front of the 4-element block (5.5 mm long) lies at 1.25 mm. Contact fronts 0.3 mm
    # behind the undeformed fronts (sliding left: trailing is +x) give a 0.3 mm tip
    # deflection and atan(0.3 / 6) for elements 6 mm high.
    layout = layout4(velocity_mps=0.0, center_time_s=0.0, height_mm=6.0)
    fronts = [12.5 + 3.0 + 15 * i for i in range(4)]
    d = strips(80, [(a, a + 8) for a in fronts])
    f = features(d, layout, time_s=0.01)
    np.testing.assert_allclose(f.elements["tip_deflection_mm"], 0.3, atol=1e-6)
    expected = math.degrees(math.atan2(0.3, 6.0))
    np.testing.assert_allclose(f.elements["deflection_angle_deg"], expected, atol=1e-5)
    assert f.frame["deflection_angle_deg"] == pytest.approx(expected, abs=1e-5)
    # Moving carrier: 1 m/s for 1 ms moves it 1 mm to the left (10 px).
    moving = layout4(velocity_mps=1.0, center_time_s=0.0, height_mm=6.0)
    f = features(strips(80, [(a - 10, a - 2) for a in fronts]), moving, time_s=0.001)
    np.testing.assert_allclose(f.elements["tip_deflection_mm"], 0.3, atol=1e-6)


def test_valid_mask_reduces_the_nominal_area():
    d = strips(60, [(5, 15), (20, 30)], rows=12)
    valid = np.ones(d.shape, bool)
    valid[:, 20:25] = False  # half of element 1 unlit: neither contact nor nominal area
    d[~valid] = np.nan
    layout = BlockLayout(PX, "left", element_lengths_mm=(1.0, 1.0), sipe_width_mm=0.5)
    f = features(d, layout, valid=valid)
    assert f.frame["contact_area_mm2"] == pytest.approx(180 * PX**2)
    assert f.frame["contact_ratio"] == pytest.approx(1.0)


@pytest.mark.parametrize("direction", ["left", "right"])
def test_a_run_cut_where_the_lit_zone_ends_is_clipped(direction):
    # Two 1 mm elements whose contact reaches past the lit zone on the leading side (the
    # first 3 px of element 0's 10 px unlit, as at a lit disc's rim under a following
    # camera): the element's front is the lit zone's end, not an edge, and its lift-off
    # (which needs the whole element) unknown, as at the image border; element 1 keeps
    # both. Truth: the analytic strips.
    d = strips(60, [(10, 20), (25, 35)], rows=12)
    valid = np.ones(d.shape, bool)
    if direction == "left":
        valid[:, :13] = False
    else:  # mirrored: the leading side is the right
        d, valid = d[:, ::-1].copy(), valid.copy()
        valid[:, 47:] = False
    d[~valid] = np.nan
    layout = BlockLayout(PX, direction, element_lengths_mm=(1.0, 1.0), sipe_width_mm=0.5)
    el = features(d, layout, valid=valid).elements.set_index("element")
    assert math.isnan(el.loc[0, "front_edge_x_mm"]) and math.isnan(el.loc[0, "liftoff_mm"])
    assert el.loc[0, "contact_length_mm"] == pytest.approx(0.7, abs=1e-6)  # the lit part
    assert el.loc[1, "liftoff_mm"] == pytest.approx(0.0, abs=1e-6)
    front = 2.5 if direction == "left" else 3.5
    assert el.loc[1, "front_edge_x_mm"] == pytest.approx(front, abs=1e-6)


def test_an_element_reaching_past_the_lit_zone_has_no_liftoff():
    # Element 0's template (columns 10-20, fitted from both elements) starts 2 px before
    # the lit zone's end at column 12; its contact (patchy: columns 14-20) does not reach
    # that end, so its front edge stands, but whether it lifts off cannot be seen.
    d = strips(60, [(14, 20), (25, 35)], rows=12)
    valid = np.ones(d.shape, bool)
    valid[:, :12] = False
    d[~valid] = np.nan
    layout = BlockLayout(PX, "left", element_lengths_mm=(1.0, 1.0), sipe_width_mm=0.5)
    el = features(d, layout, valid=valid).elements.set_index("element")
    assert el.loc[0, "front_edge_x_mm"] == pytest.approx(1.4, abs=1e-6)
    assert math.isnan(el.loc[0, "liftoff_mm"])
    assert el.loc[1, "liftoff_mm"] == pytest.approx(0.0, abs=1e-6)
    whole = features(d, layout).elements.set_index("element")  # no view given: the image
    assert whole.loc[0, "liftoff_mm"] == pytest.approx(0.4, abs=1e-6)


def test_elements_beyond_the_lit_zone_are_numbered_as_beyond_the_image():
    # Three 1 mm elements behind 0.5 mm sipes; the leading one lies wholly where the lit
    # zone has not begun (columns 0-12 unlit). Truth: the same frame cut at column 13,
    # where the image border hides it: the two seen elements are 1 and 2, in full contact.
    d = strips(60, [(0, 10), (15, 25), (30, 40)], rows=12)
    valid = np.ones(d.shape, bool)
    valid[:, :13] = False
    lit = np.where(valid, d, np.nan).astype(np.float32)
    layout = BlockLayout(PX, "left", element_lengths_mm=(1.0,) * 3, sipe_width_mm=0.5)
    el = features(lit, layout, valid=valid).elements
    cut = features(d[:, 13:].copy(), layout).elements
    assert el["element"].tolist() == cut["element"].tolist() == [1, 2]
    np.testing.assert_allclose(el["liftoff_mm"], 0.0, atol=1e-6)
    # without geometry: a strip that starts at the lit zone's end has no front there
    cut_strip = np.where(valid, strips(60, [(10, 20), (25, 35)], rows=12), np.nan)
    free = features(cut_strip.astype(np.float32), BlockLayout(PX, "left"), valid=valid)
    assert math.isnan(free.frame["block_front_x_mm"])
    assert math.isnan(free.frame["front_peak_x_mm"])
    seen = features(lit, BlockLayout(PX, "left"), valid=valid)  # starts 2 px inside it
    assert seen.frame["block_front_x_mm"] == pytest.approx(1.5)


def test_without_geometry_the_contact_is_one_strip():
    yy, xx = np.mgrid[0:40, 0:60]
    d = np.where((xx - 30) ** 2 + (yy - 20) ** 2 <= 100, 0.8, 0.0).astype(np.float32)
    d[:, 21:23] += np.where(d[:, 21:23] > 0, 0.1, 0.0).astype(np.float32)  # darker front
    for direction, front in (("left", 2.0), ("right", 4.1)):
        f = features(d, BlockLayout(PX, direction))
        assert f.elements.empty and list(f.elements.columns) == ELEMENT_FIELDS
        assert f.frame["block_in_view"] is True
        assert f.frame["contact_area_mm2"] == pytest.approx(np.count_nonzero(d) * PX**2)
        assert f.frame["block_front_x_mm"] == pytest.approx(front)  # leading column boundary
        assert math.isnan(f.frame["contact_ratio"])
        # no elements to count: NaN, not 0 ("none in contact"; helper-11)
        assert math.isnan(f.frame["n_elements_in_contact"])
    assert math.isnan(features(np.zeros_like(d), BlockLayout(PX, "left"))
                      .frame["n_elements_in_contact"])
    f = features(d, BlockLayout(PX, "left"))
    assert f.frame["front_peak_x_mm"] == pytest.approx(2.2, abs=0.05)  # the darker columns
    assert f.frame["front_peak_contrast"] == pytest.approx(0.1, abs=1e-5)


def test_empty_frame():
    f = features(np.zeros((10, 30), np.float32), layout4())
    assert f.frame["block_in_view"] is False
    assert f.frame["contact_area_mm2"] == 0.0 and f.frame["n_elements_in_contact"] == 0
    assert math.isnan(f.frame["block_front_x_mm"]) and math.isnan(f.frame["contact_ratio"])
    assert f.elements.empty


def test_records_fast_path_matches_the_dataframe():
    d = strips(80, [(5, 15), (20, 27), (35, 45), (50, 60)])
    frame, rec = tir_frame_records(d, segment_frame(d), layout4())
    f = features(d, layout4())
    assert frame == pytest.approx(f.frame, nan_ok=True)
    pd.testing.assert_frame_equal(pd.DataFrame(rec), f.elements)


def test_layout_from_meta():
    meta = {"mm_per_px": 0.05, "sliding_direction": "Right", "center_time_s": 0.05,
            "block": {"length_mm": 20, "n_sipes": 3, "sipe_width_mm": 0.6, "height_mm": 6,
                      "width_mm": 80},
            "conditions": {"velocity_mps": 1.0}}
    lay = BlockLayout.from_meta(meta)
    assert lay.sliding_direction == "right" and lay.n_elements == 4
    assert lay.element_lengths_mm == pytest.approx((4.55,) * 4)
    assert lay.block_length_mm == pytest.approx(20.0)
    assert (lay.velocity_mps, lay.center_time_s, lay.height_mm) == (1.0, 0.05, 6.0)
    meta["block"]["element_lengths_mm"] = [5.0, 4.0, 4.0, 5.2]
    assert BlockLayout.from_meta(meta).element_fronts_mm == pytest.approx((0, 5.6, 10.2, 14.8))
    assert BlockLayout.from_meta({"mm_per_px": 0.1, "sliding_direction": "left"}).n_elements == 0


def test_bad_input():
    with pytest.raises(ValueError, match="sliding_direction"):
        BlockLayout(PX, "up")
    with pytest.raises(ValueError, match="mm_per_px"):
        BlockLayout(0.0, "left")
    with pytest.raises(ValueError, match=r"element_lengths_mm\[1\]"):
        BlockLayout(PX, "left", element_lengths_mm=(1.0, -1.0))
    with pytest.raises(ValueError, match="'sliding_direction'"):
        BlockLayout.from_meta({"mm_per_px": 0.1})
    with pytest.raises(ValueError, match=r"meta 'block': the sipes .* leave no rubber"):
        BlockLayout.from_meta({"mm_per_px": 0.1, "sliding_direction": "left",
                               "block": {"length_mm": 2, "n_sipes": 3, "sipe_width_mm": 1}})
    d = np.zeros((4, 5), np.float32)
    with pytest.raises(ValueError, match="shape"):
        tir_frame_features(np.zeros((4, 6)), segment_frame(d), layout4())


# -- against the renderer's ground truth -------------------------------------------------------
FPS = 1500.0  # 1 m/s: 0.67 mm (6.7 px) per frame; 150 frames hold the whole pass
N_FRAMES = 150


# G3 both ways in the default run (the sliding direction flips the front edge); the presets
# with one and with eight elements run with -m slow (test_side and test_real_footage keep G0
# and G7 footage in the default run)
@pytest.fixture(scope="module", params=[pytest.param(("G0", "left"), marks=pytest.mark.slow),
                                        ("G3", "left"),
                                        pytest.param(("G7", "left"), marks=pytest.mark.slow),
                                        ("G3", "right")], ids=lambda p: "-".join(p))
def clip(request):
    """Features and truth of a rendered clip (default camera: noise, blur, uneven light,
    bubbles, scratches, dust; steady block state)."""
    preset, direction = request.param
    spec = FootageSpec(preset=preset, n_frames=N_FRAMES, velocity_mps=1.0, dynamics="steady",
                       sliding_direction=direction, camera=CameraSettings(fps=FPS), seed=5,
                       settle_s=STEADY_SETTLE_S)
    frames = list(iter_frames(spec))
    ref = reference_from_frames((f for _, f, _ in frames), n_total=len(frames))
    g = reference_block(preset)
    layout = BlockLayout.from_meta({
        "mm_per_px": PX, "sliding_direction": direction,
        "center_time_s": (N_FRAMES - 1) / (2 * FPS),
        "block": {"element_lengths_mm": g.element_lengths.tolist(),
                  "sipe_width_mm": g.sipe_width_mm, "height_mm": g.height_mm,
                  "width_mm": g.width_mm},
        "conditions": {"velocity_mps": 1.0},
    })
    blocks, elements = [], []
    for k, image, _ in frames:
        d = darkness(image, ref)
        f = tir_frame_features(d, segment_frame(d), layout, valid=ref.valid, time_s=k / FPS)
        blocks.append({"frame": k, **f.frame})
        elements.append(f.elements.assign(frame=k, found=True))
    truth = pd.concat([t for _, _, t in frames], ignore_index=True)
    block = pd.DataFrame(blocks).merge(truth[truth.element == -1], on="frame",
                                       suffixes=("", "_true"))
    el = pd.concat(elements, ignore_index=True).merge(
        truth[truth.element >= 0], on=["frame", "element"], how="outer", suffixes=("", "_true"))
    el["found"] = el["found"].fillna(False).astype(bool)
    return preset, block, el


def test_element_contact_length(clip):
    _, _, el = clip
    both = el[el.found & el.contact_length_mm_true.notna()]
    err = (both.contact_length_mm - both.contact_length_mm_true).abs()
    # Required: median abs error <= 0.1 mm (1 px). Measured ~0.005 mm: sub-pixel edges.
    assert err.median() <= 0.1
    assert err.max() <= 0.1  # every element, also the ones cut by the image border


def test_front_edge_and_front_peak_position(clip):
    _, _, el = clip
    both = el[el.found & el.front_edge_x_mm.notna()]
    assert len(both) > 50
    # Front edge: half-level crossing, step-edge error < 0.1 px; 0.5 px is a binary edge.
    assert (both.front_edge_x_mm - both.front_edge_x_mm_true).abs().median() <= 0.05
    # Required: the front peak within 1 pixel (median). Measured ~0.01 mm.
    peak = both[both.front_peak_x_mm.notna()]
    assert (peak.front_peak_x_mm - peak.front_peak_x_mm_true).abs().median() <= 0.1


def test_block_area_and_empty_frames(clip):
    _, block, _ = clip
    seen = block[block.contact_area_mm2_true > 0]
    rel = (seen.contact_area_mm2 / seen.contact_area_mm2_true - 1).abs()
    assert rel.median() <= 0.02  # required: 2 %
    empty = block[~block.in_view]
    assert len(empty) >= 10  # the clip starts and ends without the block
    assert not empty.block_in_view.any()
    # Block reported only where some contact is in view (the truth's in_view also counts a
    # lifted face just inside the border, which shows no contact).
    assert (block[block.block_in_view].contact_area_mm2_true > 0).all()


def test_element_numbering_in_entering_and_leaving_frames(clip):
    preset, _, el = clip
    n = reference_block(preset).n_elements
    wrong = []
    partial_frames = 0
    for k, g in el.groupby("frame"):
        ours = set(g.loc[g.found, "element"])
        sure = set(g.loc[g.contact_length_mm_true > 0.15, "element"])  # > 1.5 px in view
        some = set(g.loc[g.contact_length_mm_true > 0, "element"])
        if not sure <= ours <= some:
            wrong.append(k)
        if 0 < len(some) < n:
            partial_frames += 1
    assert wrong == []
    if n > 1:
        assert partial_frames >= 10  # entering and leaving frames were tested


def test_contact_ratio_and_liftoff(clip):
    _, block, el = clip
    # Whole block in view (image 64 mm, block 20 mm): the visible width is the image height,
    # so the contact ratio equals the truth's contact fraction; 0.02 covers the 1.5 % area
    # error of the segmentation of the narrow G7 strips.
    inside = el[el.found & el.liftoff_mm.notna()]
    per_frame = inside.groupby("frame").size()
    sel = block[block.frame.isin(per_frame.index[per_frame == per_frame.max()])]
    assert len(sel) > 10
    assert (sel.contact_ratio - sel.contact_fraction).abs().median() <= 0.02
    ell = inside.contact_length_mm_true / inside.contact_fraction
    true_liftoff = ell - inside.contact_length_mm_true
    # Lift-off = l - contact length: the same 0.1 mm as the contact length.
    assert (inside.liftoff_mm - true_liftoff).abs().median() <= 0.1


def test_deflection(clip):
    preset, _, el = clip
    ok = el[el.found & el.tip_deflection_mm.notna()]
    assert len(ok) > 50
    g = reference_block(preset)
    ell = g.element_lengths[ok.element.to_numpy()]
    tilt = np.radians(ok.tilt_deg.to_numpy())
    # The measured contact front is the leading bottom corner, which trails the bottom
    # centre's displacement by l/2 (1 - cos tilt) (module limits): with that stated offset
    # the carrier method is exact to the edge accuracy (0.05 mm).
    corner = ok.tip_deflection_mm_true.to_numpy() + 0.5 * ell * (1 - np.cos(tilt))
    assert np.median(np.abs(ok.tip_deflection_mm.to_numpy() - corner)) <= 0.05
    # Angle atan(tip / h) against the truth's chord angle: within 1 deg (measured 0.05 deg
    # for G0, 0.4 deg for G3, 0.85 deg for G7, whose elements tilt by ~30 deg).
    assert (ok.deflection_angle_deg - ok.deflection_angle_deg_true).abs().median() <= 1.0
