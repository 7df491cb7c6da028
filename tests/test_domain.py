"""The real-footage domain sampler (:mod:`synthetic.domain`): determinism and ranges."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from synthetic.domain import CASE_CLASSES, real_photo_specs, sample_spec, sample_specs
from synthetic.footage import iter_frames, lit_mask, lit_zone

N = 300  # draws for the range checks (about 0.2 s); every class expected 43 times


@pytest.fixture(scope="module")
def draws():
    return sample_specs(N, seed=11)


def test_same_seed_same_specs_other_seed_other_specs():
    a = [(s.to_dict(), c) for s, c in sample_specs(20, seed=3)]
    b = [(s.to_dict(), c) for s, c in sample_specs(20, seed=3)]
    c = [(s.to_dict(), c) for s, c in sample_specs(20, seed=4)]
    assert a == b
    assert a != c
    # sample_spec with a seed is one draw of a fresh generator of that seed
    assert sample_spec(7)[0] == sample_spec(np.random.default_rng(7))[0]


def test_every_case_class_is_drawn_with_its_scene(draws):
    cases = [c for _, c in draws]
    counts = {c: cases.count(c) for c in CASE_CLASSES}
    # 300 draws of 7 equally likely classes: 42.9 expected each, binomial sd 6.1; a class
    # below 15 (4.6 sd low) would mean a broken draw.
    assert min(counts.values()) >= 15, counts
    scene_of = {
        "tir static pad": "round_pad",
        "tir static coin": "coin",
        "tir static three-point": "three_point",
    }
    for spec, case in draws:
        assert spec.view == ("tir" if case.startswith("tir") else "side")
        assert spec.scene == scene_of.get(case, "block")
        assert spec.follow_camera == (case in ("tir follow camera", "side follow"))


def test_ranges_are_the_documented_ones(draws):
    specs = [s for s, _ in draws]
    cams = [s.camera for s in specs]
    lit = [c for c in cams if c.lit_shape != "full"]
    assert {c.lit_shape for c in lit} == {"disc", "ellipse", "band"}
    assert all(0.2 <= c.lit_fraction <= 1.0 for c in lit)
    assert all(0.02 <= c.outside_level <= 0.1 for c in lit)
    assert all(0.0 <= c.vignetting <= 0.6 for c in cams)
    # the recorded free surface stays below saturation
    assert all(0.3 <= c.white_level * c.gain <= 0.9 for c in cams)
    assert {c.bit_depth for c in cams} == {8, 12}
    jpeg = [c for c in cams if c.jpeg_quality is not None]
    assert jpeg and all(c.bit_depth == 8 and 70 <= c.jpeg_quality <= 95 for c in jpeg)
    assert all(0.5 <= s.velocity_mps <= 3.0 for s in specs)
    assert all(40 <= s.n_frames <= 120 for s in specs)
    assert {s.preset for s in specs} == {"G0", "G3", "G5", "G6", "G7"}
    assert {s.real_contact for s in specs if s.view == "tir"} == {"solid", "patchy"}
    assert all(
        s.real_contact == "solid" and s.camera.lit_shape == "full"
        for s in specs
        if s.view == "side"
    )
    # The lit shares span the range: uniform on [0.2, 1] over about 300 x 5/7 x 0.75 = 160
    # lit TIR clips, the chance that none falls within 0.04 (5 % of the range) of an end is
    # 0.95^160 = 3e-4.
    fr = [c.lit_fraction for c in lit]
    assert min(fr) < 0.24 and max(fr) > 0.96


def test_a_fixed_camera_pass_fills_the_clip(draws):
    # Unless the frame rate was clipped to [500, 20000]: the travel over the clip is the
    # image width plus the block length plus 10 mm (float arithmetic: 1e-12 relative).
    n = 0
    for spec, case in draws:
        cam = spec.camera
        if case != "tir passing block" or cam.fps in (500.0, 20000.0):
            continue
        travel = spec.velocity_mps * 1e3 * (spec.n_frames - 1) / cam.fps
        np.testing.assert_allclose(travel, cam.width_px * cam.mm_per_px + 30.0, rtol=1e-12)
        n += 1
    assert n > 10


def test_near_rim_points_lie_near_the_lit_rim(draws):
    # Three-point clips with a disc-shaped lit zone: points drawn at 75-95 % of the disc's
    # radius (near the rim) or within 50 %; the disc's radius from its pixel count
    # (sqrt(A / pi)) is exact to the boundary's pixel ring (1 px).
    checked = 0
    for spec, case in draws:
        cam = spec.camera
        if case != "tir static three-point" or cam.lit_shape != "disc":
            continue
        radius = math.sqrt(lit_mask(spec).sum() / math.pi) * cam.mm_per_px
        for dx, dy in spec.point_positions_mm:
            rel = math.hypot(dx, dy) / radius
            assert rel <= 0.5 + 0.01 or 0.75 - 0.01 <= rel <= 0.95 + 0.01
        checked += 1
    assert checked > 0


@pytest.mark.parametrize("case", [
    c if c in ("tir static pad", "side follow") else pytest.param(c, marks=pytest.mark.slow)
    for c in CASE_CLASSES])  # two classes in the default run, the rest with -m slow
def test_each_case_class_renders(draws, case):
    spec = next(s for s, c in draws if c == case)
    cam = spec.camera
    short = dataclasses.replace(spec, n_frames=2)
    frames = list(iter_frames(short))
    _, img, truth = frames[1]
    assert img.shape == (cam.height_px, cam.width_px)
    assert img.dtype == (np.uint8 if cam.bit_depth == 8 else np.uint16)
    assert list(truth.columns)[:2] == ["frame", "time_s"]
    assert (truth["contact_area_mm2"] >= 0).all()
    # the clock: frame k at k / fps
    assert truth["time_s"].to_numpy() == pytest.approx(1.0 / cam.fps, rel=1e-12)
    # something is in contact, and the block total is the sum of its elements (float sums)
    total = truth.loc[truth["element"] == -1, "contact_area_mm2"]
    assert len(total) == 1 and total.iloc[0] > 0
    assert total.iloc[0] == pytest.approx(
        truth.loc[truth["element"] >= 0, "contact_area_mm2"].sum(), rel=1e-12)
    # the recorded level: values within the bit depth (12-bit in uint16 stays <= 4095), and
    # the bright free surface (99.5th percentile of the lit pixels) at white_level x gain of
    # full scale. Measured 0.79-1.10 over 42 draws of all classes (vignetting up to 0.6 away
    # from the centre lowers it, noise and JPEG raise it); 0.6-1.3 allowed, while a wrong
    # bit-depth scale is off by 16x.
    full = 2**cam.bit_depth - 1
    assert int(img.max()) <= full
    lit = lit_mask(spec) if spec.view == "tir" else np.ones(img.shape, bool)
    level = np.percentile(img[lit], 99.5) / (cam.white_level * cam.gain * full)
    assert 0.6 < level < 1.3


def test_bad_sampler_arguments_raise():
    with pytest.raises(ValueError, match="n must be >= 0"):
        sample_specs(-1)
    with pytest.raises(TypeError, match="n must be an integer"):
        sample_specs(2.0)


def test_real_photo_specs_look_like_the_photographs():
    # The real FTIR photograph: 8-bit JPEG 640 x 512, grey 0-101, median 9, lit disc over
    # ~28 % of the frame, pad radius 2.75 mm = 77 px at 0.0357 mm/px.
    specs = real_photo_specs(n_frames=1)
    pad = specs["round pad"]
    _, img, truth = next(iter_frames(pad))
    assert img.shape == (512, 640) and img.dtype == np.uint8
    # Median: outside level 0.09 x 0.4 x 255 = 9.2 DN times the vignetting (0.5-1) over
    # the dark 72 %: 5-9 DN; the photograph's 9 within 4 DN.
    assert abs(float(np.median(img)) - 9) <= 4
    # The bright free surface: the 99th percentile near 101 (white level 0.4 = 102 DN at
    # the centre, +-2.5 % gradient and the noise); 10 DN allowed.
    assert abs(float(np.percentile(img, 99)) - 101) <= 10
    # Lit share: the bisection hits 28 % to one ring of boundary pixels (2 pi R / px).
    ring = 2 * math.pi * lit_zone(pad).size_mm / 0.0357
    np.testing.assert_allclose(lit_mask(pad).mean(), 0.28, atol=ring / img.size)
    nominal = truth.loc[truth["element"] == 0, "nominal_contact_area_mm2"].iloc[0]
    # pi 2.75^2 = 23.76 mm^2, to the sampled rim (2 pi r h, h = 0.0357 / 4 mm)
    np.testing.assert_allclose(nominal, math.pi * 2.75**2, atol=2 * math.pi * 2.75 * 0.0357 / 4)


def test_physical_draws_light_the_view_as_the_domain_does():
    """A physical draw's lit zone is the domain's, scaled with the view: centre and rim drawn
    for a static view of 0.03-0.08 mm/px (rim 0.3-3 mm) keep their size in pixels, 3.75 to
    100 px, at the physical scale (0.004-0.12 mm/px). A rim left in mm spanned up to 470 px
    of a 100-300 px frame, and the truth (contact inside its half-light line) was no longer
    what the image shows."""
    from synthetic.domain import sample_physical_specs

    rims = [s.camera.lit_rim_mm / s.camera.mm_per_px
            for s, _ in sample_physical_specs(60, seed=5) if s.camera.lit_shape != "full"]
    assert len(rims) >= 30  # three quarters of the draws have a lit zone
    assert min(rims) >= 0.3 / 0.08 * (1 - 1e-9) and max(rims) <= 3.0 / 0.03 * (1 + 1e-9), (
        min(rims), max(rims))


def test_physical_ice_holds_the_flaws_of_the_thesis_ice_per_area():
    """The physical world's views (0.6-38 mm wide) hold the ice's flaws drawn for the thesis's
    64 x 25.6 mm field as densities: bubbles by area, scratches (3-20 mm) by the ones that
    cross the view (Buffon: starts over the view and a margin of its perimeter times the mean
    length over pi), none of them bubbles on glass; Poisson counts from the clip's seed.
    Independent truth: the means of those laws over 4000 seeds, within 5 standard errors
    of a Poisson mean (never reached by chance: a failure is a broken law)."""
    from synthetic._render_tir import THESIS_FIELD_MM
    from synthetic.domain import _ice_flaws_in_view

    field_w, field_h = THESIS_FIELD_MM
    # the thesis's field itself: the counts as drawn
    full = {"width_px": 640, "height_px": 256, "mm_per_px": field_w / 640,
            "n_bubbles": 40, "n_scratches": 10}
    # a 2 x 1.5 mm micro view: 40 bubbles per field are 0.073 here
    micro = {**full, "width_px": 200, "height_px": 150, "mm_per_px": 0.01}
    crossing = (2.0 * 1.5 + 2 * 3.5 * 11.5 / math.pi) / (
        field_w * field_h + 2 * (field_w + field_h) * 11.5 / math.pi)
    n = 4000
    for cam, bubbles, scratches in ((full, 40.0, 10.0),
                                    (micro, 40 * 3.0 / (field_w * field_h), 10 * crossing)):
        got = [_ice_flaws_in_view(cam, seed, glass=False) for seed in range(n)]
        for key, mean in (("n_bubbles", bubbles), ("n_scratches", scratches)):
            values = np.array([g[key] for g in got])
            assert abs(values.mean() - mean) < 5 * math.sqrt(mean / n), (key, values.mean(), mean)
    assert all(_ice_flaws_in_view(full, s, glass=True)["n_bubbles"] == 0 for s in range(50))
    # the same clip seed, the same flaws
    assert _ice_flaws_in_view(micro, 3, glass=False) == _ice_flaws_in_view(micro, 3, glass=False)


def test_physical_draws_keep_their_other_fields_and_scale_their_flaws(monkeypatch):
    """The flaws come from a generator of their own: every other field of every draw is the
    one the sampler gives with the domain's counts left in place (the law replaced by one
    that keeps them), and a static scene's micro view holds far fewer than the 0-40
    bubbles drawn for the domain's view."""
    import synthetic.domain as domain

    specs = domain.sample_physical_specs(40, seed=2)
    static = [s for s, _ in specs if s.is_static]
    assert static
    # the domain draws 20 on average per view; a static view of at most 10 x 10 mm holds
    # under 20 * 100 / 1638 = 1.2 on average
    mean_bubbles = np.mean([s.camera.n_bubbles for s in static])
    assert mean_bubbles < 1.2, mean_bubbles
    assert all(s.camera.n_bubbles == 0 for s, _ in specs if s.substrate == "glass")
    monkeypatch.setattr(domain, "_ice_flaws_in_view", lambda cam, seed, glass: {
        "n_bubbles": cam["n_bubbles"], "n_scratches": cam["n_scratches"]})
    kept = domain.sample_physical_specs(40, seed=2)
    flaws = {"n_bubbles", "n_scratches"}
    assert any(s.camera.n_bubbles != k.camera.n_bubbles
               for (s, _), (k, _) in zip(specs, kept, strict=True))
    for (s, case), (k, case_k) in zip(specs, kept, strict=True):
        assert case == case_k
        a, b = s.to_dict(), k.to_dict()
        cam_a, cam_b = a.pop("camera"), b.pop("camera")
        assert a == b
        assert {x: v for x, v in cam_a.items() if x not in flaws} == {
            x: v for x, v in cam_b.items() if x not in flaws}
