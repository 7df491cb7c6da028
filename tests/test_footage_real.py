"""Real-footage features of :mod:`synthetic.footage` against independent truths.

Lit zones, low signal and vignetting, JPEG frames, the following TIR camera, static contact
scenes and patchy real contact (:mod:`synthetic._real_contact`). Frames are small (at most
320 x 160 px) and clips short so that every test runs in about a second.
"""

from __future__ import annotations

import json
import math

import cv2
import numpy as np
import pytest

from friction_model.dynamics.contact import THESIS_CONTACT_RATIO
from synthetic.footage import (
    REAL_TRUTH_COLUMNS,
    TRUTH_COLUMNS,
    CameraSettings,
    FootageSpec,
    iter_frames,
    lit_mask,
    lit_zone,
    model_contact_ratio,
    render_footage,
)

PX = 0.1  # mm/px of the test cameras
#: A camera without static scene clutter: uniform light, no ice imperfections or dust, 16 bit.
CLEAN = {
    "width_px": 160,
    "height_px": 128,
    "bit_depth": 16,
    "illumination_gradient": 0.0,
    "vignetting": 0.0,
    "n_bubbles": 0,
    "n_scratches": 0,
    "groove_depth": 0.0,
    "n_dust": 0,
}
#: The block far from the view (its centre passes 1 s after the single frame).
NO_BLOCK = {"n_frames": 1, "dynamics": "steady", "settle_s": 0.004, "center_time_s": 1.0}


def first(spec: FootageSpec):
    return next(iter_frames(spec))


# -- lit zone --------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("shape", "fraction"),
    [("disc", 0.28), ("ellipse", 0.5), ("band", 0.2), ("disc", 1.0)],
)
def test_lit_fraction_of_the_rendered_frame_is_the_requested_one(shape, fraction):
    cam = CameraSettings(
        **CLEAN, lit_shape=shape, lit_fraction=fraction, lit_rim_mm=2.0, outside_level=0.05
    )
    spec = FootageSpec(camera=cam, noise=False, **NO_BLOCK)
    _, img, truth = first(spec)
    assert truth["contact_area_mm2"].sum() == 0.0
    full = cam.white_level * 65535
    # Threshold half-way between the outside level and the lit level: the definition of the
    # lit mask (light factor s = 1/2 on the zone boundary).
    lit = img >= 0.5 * (1.0 + cam.outside_level) * full
    zone = lit_zone(spec)
    n = img.size
    # The mask and the thresholded image may disagree only on pixels the boundary crosses;
    # the bisection of the zone size stops within the pixels of one boundary ring too. One
    # ring of pixels along the boundary: perimeter / pixel pitch pixels (disc 2 pi R; the
    # ellipse's perimeter is below 2 pi of its larger semi-axis; band: two frame widths).
    if shape == "band":
        ring = 2 * cam.width_px
    else:
        ring = 2 * math.pi * zone.size_mm / PX
    np.testing.assert_allclose(lit.mean(), fraction, atol=ring / n)
    np.testing.assert_allclose(zone.fraction, fraction, atol=ring / n)
    assert np.array_equal(lit, zone.mask) or np.count_nonzero(lit != zone.mask) <= ring
    if fraction < 1:
        # Beyond half the rim outside the zone only outside_level of the light is left;
        # exact up to the rounding to whole DN (no noise).
        d_far = zone.factor <= cam.outside_level + 1e-6
        assert d_far.any()
        np.testing.assert_allclose(img[d_far], cam.outside_level * full, atol=0.5)


def test_strong_vignetting_and_low_signal():
    # white_level 0.4: the free surface at the image centre at 0.4 x 255 = 102 DN (the real
    # photograph peaks near 100); vignetting 0.6 leaves 40 % in the corners (the model
    # 1 - v rho^2, rho from the image centre over the half diagonal, at the pixel centre).
    # Noise-free, so the only error is the rounding to whole DN (0.5).
    cam = CameraSettings(**{**CLEAN, "bit_depth": 8, "white_level": 0.4, "vignetting": 0.6})
    _, img, _ = first(FootageSpec(camera=cam, noise=False, **NO_BLOCK))
    h, w = img.shape
    centre = img[h // 2 - 1 : h // 2 + 1, w // 2 - 1 : w // 2 + 1].astype(float)
    np.testing.assert_allclose(centre, 0.4 * 255, atol=0.6)
    rho2 = ((w / 2 - 0.5) ** 2 + (h / 2 - 0.5) ** 2) / ((w / 2) ** 2 + (h / 2) ** 2)
    assert rho2 > 0.98  # the corner pixel: 40 % of the centre light, up to 1.4 %
    np.testing.assert_allclose(float(img[0, 0]), 0.4 * 255 * (1 - 0.6 * rho2), atol=0.51)


def test_twelve_bit_low_signal_noise_follows_the_sensor_model():
    # 12 bit, white level 0.3: mean 0.3 x 4095 DN; the noise is shot noise of 0.3 x 16000 e-
    # plus 20 e- read noise: sd = sqrt(4800 + 400) e- x 4095 / 16000 DN = 18.5 DN. Over the
    # 20480 pixels the sample sd has a relative standard error of 1/sqrt(2 x 20480) = 0.5 %;
    # 3 % allowed. The mean is within 3 x 18.5 / sqrt(20480) = 0.4 DN; 1 DN allowed.
    cam = CameraSettings(**{**CLEAN, "bit_depth": 12}, white_level=0.3)
    _, img, _ = first(FootageSpec(camera=cam, **NO_BLOCK))
    assert img.dtype == np.uint16
    np.testing.assert_allclose(img.mean(), 0.3 * 4095, atol=1.0)
    sd = math.sqrt(0.3 * 16000 + 20**2) * 4095 / 16000
    np.testing.assert_allclose(img.std(), sd, rtol=0.03)


# -- JPEG ------------------------------------------------------------------------------------
def test_jpeg_frames_decode_to_what_iter_frames_yields(tmp_path):
    cam = CameraSettings(width_px=160, height_px=128, jpeg_quality=80)
    spec = FootageSpec(preset="G3", camera=cam, n_frames=3, dynamics="steady", settle_s=0.004)
    plain = FootageSpec(
        preset="G3",
        camera=CameraSettings(width_px=160, height_px=128),
        n_frames=3,
        dynamics="steady",
        settle_s=0.004,
    )
    out = render_footage(spec, tmp_path / "clip")
    meta = json.loads((out / "meta.json").read_text())
    assert meta["frame_pattern"] == "frames/frame_{frame:06d}.jpg"
    assert meta["jpeg_quality"] == 80
    for (k, img, _), (_, raw, _) in zip(iter_frames(spec), iter_frames(plain), strict=True):
        assert img.shape == (128, 160) and img.dtype == np.uint8
        on_disk = cv2.imread(str(out / "frames" / f"frame_{k:06d}.jpg"), cv2.IMREAD_UNCHANGED)
        assert np.array_equal(on_disk, img)
        # Independent path: OpenCV's own JPEG round trip of the uncompressed frame.
        ok, buf = cv2.imencode(".jpg", raw, [cv2.IMWRITE_JPEG_QUALITY, 80])
        assert ok and np.array_equal(cv2.imdecode(buf, cv2.IMREAD_GRAYSCALE), img)


def test_jpeg_needs_eight_bits_and_jpg_needs_jpeg(tmp_path):
    with pytest.raises(ValueError, match="bit_depth must be 8 with jpeg_quality"):
        CameraSettings(bit_depth=12, jpeg_quality=90)
    spec = FootageSpec(n_frames=1, dynamics="steady", settle_s=0.004)
    with pytest.raises(ValueError, match="jpeg_quality must be set"):
        render_footage(spec, tmp_path, fmt="jpg")


# -- following TIR camera ----------------------------------------------------------------------
def test_tir_follow_camera_fixes_the_block_and_moves_the_ice():
    # 1 m/s at 1000 frames/s and 0.1 mm/px: the ice moves exactly 10 px per frame, to the
    # right while the block slides left. The block (80 mm wide, centreline 44 mm below the
    # image centre row) starts 4 mm below it, row 104, and leaves the top rows to the ice.
    cam = CameraSettings(
        **{**CLEAN, "n_bubbles": 40, "n_scratches": 10}, fps=1000.0, exposure_s=0.0
    )
    spec = FootageSpec(
        preset="G3",
        camera=cam,
        n_frames=5,
        dynamics="steady",
        settle_s=0.004,
        follow_camera=True,
        noise=False,
        lateral_offset_mm=44.0,
    )
    frames = list(iter_frames(spec))
    fronts = [t.loc[t["element"] == 0, "front_edge_x_mm"].iloc[0] for _, _, t in frames]
    np.testing.assert_allclose(fronts, fronts[0], atol=1e-12)
    areas = [t.loc[t["element"] == -1, "contact_area_mm2"].iloc[0] for _, _, t in frames]
    np.testing.assert_allclose(areas, areas[0], rtol=1e-12)
    top = slice(0, 100)  # rows above the block
    a, b = frames[1][1][top].astype(float), frames[2][1][top].astype(float)
    assert a.std() > 0  # the ice has structure to follow
    errs = {s: np.abs(a[:, 20 - s : 140 - s] - b[:, 20:140]).mean() for s in range(-15, 16)}
    assert min(errs, key=errs.get) == 10
    assert errs[10] <= 0.5  # bilinear shift by a whole pixel: exact up to rounding


def test_side_follow_camera_angles_stay_exact():
    # The side view's following camera draws the same model state as the fixed one: the
    # ground-truth deflection angles of both are the rigid model's (identical floats).
    kw = {"view": "side", "n_frames": 3, "dynamics": "steady", "settle_s": 0.004}
    fixed = [t for _, _, t in iter_frames(FootageSpec(**kw))][1]
    follow = [t for _, _, t in iter_frames(FootageSpec(follow_camera=True, **kw))][1]
    e_fix = fixed.set_index("element")["deflection_angle_deg"]
    e_fol = follow.set_index("element")["deflection_angle_deg"]
    common = e_fix.index.intersection(e_fol.index)
    common = common[common >= 0]
    assert len(common) > 0
    np.testing.assert_array_equal(e_fix[common], e_fol[common])


# -- static scenes ------------------------------------------------------------------------------
def test_round_pad_area_is_pi_r_squared_and_shows_dark():
    spec = FootageSpec(scene="round_pad", camera=CameraSettings(**CLEAN), noise=False, n_frames=2)
    frames = list(iter_frames(spec))
    _, img, truth = frames[0]
    assert list(truth.columns) == list(TRUTH_COLUMNS + REAL_TRUTH_COLUMNS)
    r = spec.pad_radius_mm
    area = truth.loc[truth["element"] == 0, "contact_area_mm2"].iloc[0]
    # Sampled on 4 x 4 points per pixel (h = 0.025 mm): the sampled disc differs from the
    # true one only in the sample cells its rim crosses, about 2 pi r / h cells of h^2 each,
    # so by at most 2 pi r h = 0.43 mm^2 (1.8 %).
    np.testing.assert_allclose(area, math.pi * r * r, atol=2 * math.pi * r * 0.025)
    # The image: darker than C/2 where more than about half the pixel touches; the rim's
    # pixels (2 pi r / px of them) decide either way: one ring of pixels of tolerance.
    dark = 1.0 - img.astype(float) / (spec.camera.white_level * 65535)
    measured = np.count_nonzero(dark > 0.5 * spec.contrast) * PX * PX
    np.testing.assert_allclose(measured, area, atol=2 * math.pi * r * PX)
    # Static: the same contact in every frame.
    assert np.array_equal(frames[1][1], img)
    assert frames[1][2]["contact_area_mm2"].tolist() == truth["contact_area_mm2"].tolist()


def test_contact_outside_the_lit_zone_does_not_count(tmp_path):
    # Three 1 mm points: two well inside a central lit disc (radius about 3.4 mm), one 6 mm
    # out, beyond the soft rim. The outer one is in the image but has no visible area.
    cam = CameraSettings(**CLEAN, lit_shape="disc", lit_fraction=0.2, lit_rim_mm=1.0)
    pts = ((-1.5, 0.0), (1.5, 0.0), (0.0, -6.0))
    spec = FootageSpec(scene="three_point", camera=cam, point_positions_mm=pts, n_frames=1)
    _, _, truth = first(spec)
    areas = truth.set_index("element")["contact_area_mm2"]
    assert areas[2] == 0.0  # exactly: no sample of it lies in the mask
    # The inner two: pi r^2 each, tolerance of the sampled rim (see the round-pad test).
    np.testing.assert_allclose(areas[[0, 1]], math.pi, atol=2 * math.pi * 0.025)
    np.testing.assert_allclose(areas[-1], areas[0] + areas[1], rtol=1e-12)
    out = render_footage(spec, tmp_path / "pts")
    mask = cv2.imread(str(out / "lit_mask.png"), cv2.IMREAD_UNCHANGED)
    assert np.array_equal(mask, lit_mask(spec).astype(np.uint8) * 255)
    meta = json.loads((out / "meta.json").read_text())
    assert "block" not in meta
    assert meta["scene"] == "three_point"
    assert meta["lit_zone"]["mask_file"] == "lit_mask.png"
    from tir_contact.meta import load_meta

    loaded = load_meta(out / "meta.json")
    assert loaded["view"] == "tir" and loaded["mm_per_px"] == PX


def test_coin_contact_is_the_rim_annulus():
    spec = FootageSpec(
        scene="coin", coin_radii_mm=(4.0, 5.0), camera=CameraSettings(**CLEAN), n_frames=1
    )
    _, _, truth = first(spec)
    area = truth.loc[truth["element"] == 0, "contact_area_mm2"].iloc[0]
    # pi (r_o^2 - r_i^2) = 28.27 mm^2; two rims of sample cells: 2 pi (r_o + r_i) h.
    np.testing.assert_allclose(area, math.pi * (25 - 16), atol=2 * math.pi * 9 * 0.025)


# -- patchy real contact -------------------------------------------------------------------------
def _sample_tol(phi: float, area_mm2: float, sigma_mm: float) -> float:
    """Three standard errors of a covered share phi over ``area_mm2`` of patches.

    The field is Gaussian-filtered white noise of filter sd ``sigma``: its correlation is
    exp(-r^2 / (4 sigma^2)), of integral 4 pi sigma^2, which bounds the correlation area of
    the thresholded field; ``area / (4 pi sigma^2)`` independent patches then give the
    binomial standard error ``sqrt(phi (1 - phi) / n)`` (conservative: over three seeds
    the G0, G3 and G7 ratios scattered by 0.006, a third of this estimate).
    """
    n = area_mm2 / (4 * math.pi * sigma_mm**2)
    return 3 * math.sqrt(phi * (1 - phi) / n)


def test_patchy_pad_covers_the_model_fraction():
    # Round pad of 2.75 mm with patches of sigma 0.05 mm: the real area over the nominal
    # one is the mean of phi(p) over the Hertz profile (model_contact_ratio), within the
    # finite sample of patches.
    spec = FootageSpec(
        scene="round_pad",
        real_contact="patchy",
        patch_correlation_mm=0.05,
        camera=CameraSettings(**CLEAN),
        n_frames=1,
    )
    _, _, truth = first(spec)
    row = truth.loc[truth["element"] == 0].iloc[0]
    expected = model_contact_ratio(spec)
    # phi over the Hertz profile of 2.5 bar mean: 0.68 (2.5 bar) ^ 0.22 weighted, about 0.67
    assert 0.5 < expected < 0.8
    tol = _sample_tol(expected, row["nominal_contact_area_mm2"], 0.05)
    np.testing.assert_allclose(row["real_contact_fraction"], expected, atol=tol)
    np.testing.assert_allclose(
        row["contact_area_mm2"], row["real_contact_fraction"] * row["nominal_contact_area_mm2"]
    )


def _patchy_steady(preset: str, patch_correlation_mm: float) -> FootageSpec:
    """One noise-free frame of `preset` in steady sliding with patchy real contact, the block
    wholly in view (256 px wide, clean camera)."""
    return FootageSpec(
        preset=preset,
        real_contact="patchy",
        patch_correlation_mm=patch_correlation_mm,
        camera=CameraSettings(**{**CLEAN, "width_px": 256}),
        noise=False,
        n_frames=1,
        dynamics="steady",
        settle_s=0.004,
    )


@pytest.fixture(scope="module")
def patchy_ratios():
    """Ground-truth contact ratio (real area / nominal block area in view) of G0 and G7,
    steady state, block wholly in view along the path (20 mm in a 25.6 mm image)."""
    out = {}
    for preset in ("G0", "G7"):
        spec = _patchy_steady(preset, patch_correlation_mm=0.1)
        _, img, truth = first(spec)
        total = truth.loc[truth["element"] == -1].iloc[0]
        band_mm2 = 20.0 * spec.camera.height_px * PX  # L x visible width
        out[preset] = (spec, total["contact_area_mm2"] / band_mm2, total, img)
    return out


def test_patchy_contact_ratio_follows_the_model_and_falls_from_g0_to_g7(patchy_ratios):
    model = {}
    for preset, (spec, ratio, total, _) in patchy_ratios.items():
        model[preset] = model_contact_ratio(spec)
        tol = _sample_tol(0.7, total["nominal_contact_area_mm2"], 0.1)
        np.testing.assert_allclose(ratio, model[preset], atol=tol)
    g0, g7 = patchy_ratios["G0"][1], patchy_ratios["G7"][1]
    assert g0 > g7 + 0.3
    # Fig. 4.21: about 0.70 (G0) and 0.25 (G7), read from the figure to +-0.05, the accuracy
    # the README claims for the models (rigid block, real_contact_fraction; predicted, not
    # fitted to Fig. 4.21). The rendered footage's ratio (the truth a TIR analysis would
    # measure) is held to the same +-0.05 plus its sampling tolerance.
    for preset in ("G0", "G7"):
        np.testing.assert_allclose(model[preset], THESIS_CONTACT_RATIO[preset], atol=0.05)
        tol = _sample_tol(0.7, patchy_ratios[preset][2]["nominal_contact_area_mm2"], 0.1)
        np.testing.assert_allclose(patchy_ratios[preset][1], THESIS_CONTACT_RATIO[preset],
                                   atol=0.05 + tol)


def test_patchy_image_darkness_integrates_to_the_real_area(patchy_ratios):
    # Sum of the pixel darkness over D: every covered sample is at least C dark and at
    # most C_max, so the covered area lies between sum(d) px^2 / C_max and / C.
    for spec, _, total, img in patchy_ratios.values():
        d = 1.0 - img.astype(float) / (spec.camera.white_level * 65535)
        integral = d.sum() * PX * PX
        real = total["contact_area_mm2"]
        assert integral / spec.contrast_max <= real * (1 + 1e-3) + 0.01
        assert integral / spec.contrast >= real * (1 - 1e-3) - 0.01


def test_solid_block_with_a_lit_disc_counts_only_the_lit_contact():
    cam = CameraSettings(**{**CLEAN, "width_px": 256}, lit_shape="disc", lit_fraction=0.3)
    spec = FootageSpec(preset="G0", camera=cam, n_frames=1, dynamics="steady", settle_s=0.004)
    _, _, truth = first(spec)
    total = truth.loc[truth["element"] == -1].iloc[0]
    # G0 in the steady state touches with its whole face (contact fraction ~1): the lit
    # contact is the mask's pixels under the face, counted independently here from the mask.
    full = FootageSpec(
        preset="G0",
        camera=CameraSettings(**{**CLEAN, "width_px": 256}),
        n_frames=1,
        dynamics="steady",
        settle_s=0.004,
    )
    face = first(full)[2]
    row = face.loc[face["element"] == 0].iloc[0]
    x0 = row["front_edge_x_mm"]
    x1 = x0 + row["contact_length_mm"]
    mask = lit_mask(spec)
    cols = (np.arange(mask.shape[1]) + 0.5) * PX
    # pixels whose centre lies on the contact: exact up to the two partial edge columns
    expected = np.count_nonzero(mask[:, (cols > x0) & (cols < x1)]) * PX * PX
    edge_cols = 2 * np.count_nonzero(mask.any(axis=0) & (np.abs(cols - x0) < PX)) + 2
    np.testing.assert_allclose(
        total["contact_area_mm2"], expected, atol=edge_cols * mask.shape[0] * PX * PX
    )
    assert total["contact_area_mm2"] == total["nominal_contact_area_mm2"]


# -- back-compatibility and validation -----------------------------------------------------------
def test_default_spec_has_the_old_outputs(tmp_path):
    spec = FootageSpec(n_frames=2, dynamics="steady", settle_s=0.004)
    assert not spec.uses_real_footage_fields
    assert spec.truth_columns == TRUTH_COLUMNS
    out = render_footage(spec, tmp_path / "plain")
    assert not (out / "lit_mask.png").exists()
    meta = json.loads((out / "meta.json").read_text())
    for key in ("lit_zone", "scene", "real_contact", "jpeg_quality"):
        assert key not in meta
    assert "lit_shape" not in meta["spec"]["camera"]


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"view": "side", "scene": "coin"}, "scene must be 'block' for view='side'"),
        ({"view": "side", "real_contact": "patchy"}, "real_contact must be 'solid'"),
        ({"scene": "round_pad", "follow_camera": True}, "follow_camera must be False"),
        ({"coin_radii_mm": (5.0, 4.0)}, "coin_radii_mm"),
        ({"point_positions_mm": ((0.0, 0.0),)}, "point_positions_mm must hold three"),
        ({"pad_radius_mm": 0.0}, "pad_radius_mm must lie"),
        ({"patch_correlation_mm": -1.0}, "patch_correlation_mm must lie"),
    ],
)
def test_bad_real_footage_fields_raise_naming_the_field(kw, match):
    with pytest.raises(ValueError, match=match):
        FootageSpec(**kw)


def test_lit_area_of_a_rotated_path_is_the_clipped_polygon_area():
    # A disc lit zone covering every pixel (fraction 1): the truth counts the contact inside
    # the lit pixels by pixel coverage, which must equal the exact area of the contact
    # polygons clipped to the image (the "full" truth, visible_area) to rounding (1e-9).
    kw = {
        "preset": "G3",
        "n_frames": 1,
        "dynamics": "steady",
        "settle_s": 0.004,
        "center_time_s": 0.0,
    }
    base = {"width_px": 256, "height_px": 128, "rotation_deg": 12.0}
    lit = FootageSpec(camera=CameraSettings(**base, lit_shape="disc", lit_fraction=1.0), **kw)
    assert lit_mask(lit).all()
    full = FootageSpec(camera=CameraSettings(**base), **kw)
    a = first(lit)[2].set_index("element")["contact_area_mm2"]
    b = first(full)[2].set_index("element")["contact_area_mm2"]
    assert a.index.tolist() == b.index.tolist() and b[-1] > 100
    np.testing.assert_allclose(a, b, rtol=1e-9)


def test_patchy_front_edge_touches_more_and_is_darker():
    # G0: the front band (0.4 mm) carries about 4.5 x the mean pressure, so phi(p) there is
    # ~4.5^0.22 = 1.4 x larger (near 1 against 0.68) and D(p) larger too: the model's mean
    # darkness phi D is about 0.8 in the band (from 0 at the rounded edge) against 0.54
    # mid-element (measured over three seeds: 0.81-0.83 against 0.53).
    # With patches of sd 0.05 mm the band's 3 full columns x 12.8 mm hold about
    # 3.8 mm^2 / (4 pi 0.05^2) = 120 independent patches: standard error 0.03 of the mean
    # darkness. Asserted: at least half the model's difference (0.15, 5 standard errors).
    spec = _patchy_steady("G0", patch_correlation_mm=0.05)
    _, img, truth = first(spec)
    row = truth.loc[truth["element"] == 0].iloc[0]
    x0, length = row["front_edge_x_mm"], row["contact_length_mm"]
    d = 1.0 - img.astype(float) / (spec.camera.white_level * 65535)
    cols = np.arange(img.shape[1])
    left, right = cols * PX, (cols + 1) * PX  # pixel edges, mm
    band = (left >= x0) & (right <= x0 + spec.edge_band_mm)
    mid = (left >= x0 + 0.5 * length - 2.0) & (right <= x0 + 0.5 * length + 2.0)
    assert band.sum() >= 3 and mid.sum() >= 30
    assert d[:, band].mean() >= d[:, mid].mean() + 0.15
