"""The TIR light's faults in the renderer (:mod:`synthetic.footage`): a darker fold across the
lit zone (``CameraSettings.fold_*``) and stray light (``CameraSettings.stray_light``), and the
renders of issue 21's table built on them (:mod:`synthetic.table`).

The truths are independent of the renderer's code: two renders of one seed, noise off and
16 bit, differ only by the fault, so their ratio (fold) or difference (stray light) is the
requested factor or offset, computed here from the stated geometry.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
import pytest

from synthetic.footage import CameraSettings, FootageSpec, iter_frames

CAM = CameraSettings(width_px=160, height_px=96, mm_per_px=0.1, bit_depth=16, white_level=0.7)


def _frame(spec: FootageSpec) -> tuple[np.ndarray, pd.DataFrame]:
    _, image, truth = next(iter(iter_frames(spec)))
    return image.astype(np.float64), truth


def _pad(**camera) -> FootageSpec:
    return FootageSpec(scene="round_pad", pad_radius_mm=2.0, n_frames=1, noise=False, seed=5,
                       camera=dataclasses.replace(CAM, **camera))


def test_fold_darkens_its_band_by_the_requested_factor_and_nothing_else():
    depth, x0, width, edge = 0.4, 2.0, 1.5, 0.5
    plain, truth = _frame(_pad())
    folded, truth_f = _frame(_pad(fold_depth=depth, fold_x_mm=x0, fold_width_mm=width,
                                  fold_edge_mm=edge))
    x = (np.arange(CAM.width_px) + 0.5) * CAM.mm_per_px - 0.5 * CAM.width_px * CAM.mm_per_px
    core = np.abs(x - x0) <= 0.5 * width
    clear = np.abs(x - x0) >= 0.5 * width + edge
    ratio = folded / plain
    # 16-bit grey ~ 0.7 * 65535 * light: rounding is < 2e-5 of the level, 1e-3 is ample
    assert np.mean(ratio[:, core]) == pytest.approx(1 - depth, abs=1e-3)
    assert np.abs(ratio[:, core] - (1 - depth)).max() < 2e-3
    assert np.abs(ratio[:, clear] - 1.0).max() < 1e-3
    # the documented raised cosine is point-symmetric about the edge's middle: the columns
    # at +-0.05 mm from it average to half the depth
    mid = 0.5 * width + 0.5 * edge
    pair = np.abs(np.abs(np.abs(x - x0) - mid) - 0.05) < 1e-6
    assert pair.sum() == 4  # two each side of the fold
    assert np.mean(ratio[:, pair]) == pytest.approx(1 - 0.5 * depth, abs=1e-3)
    inside_edge = ~core & ~clear
    assert np.all((ratio[:, inside_edge] > 1 - depth - 1e-3) & (ratio[:, inside_edge] < 1 + 1e-3))
    pd.testing.assert_frame_equal(truth, truth_f)  # light, not contact


def test_stray_light_raises_every_lit_grey_by_the_stated_amount():
    stray = 0.1
    plain, truth = _frame(_pad())
    lit, truth_s = _frame(_pad(stray_light=stray))
    # evenly lit frame ("full"): the offset is stray * white_level of full scale everywhere,
    # on the free surface and on the contact alike (rounding: +-1 DN)
    offset = stray * CAM.white_level * 65535
    assert np.abs(lit - plain - offset).max() <= 1.0
    pd.testing.assert_frame_equal(truth, truth_s)


def test_stray_light_scales_with_the_lit_zone():
    stray = 0.2
    cam = {"lit_shape": "disc", "lit_fraction": 0.5, "lit_rim_mm": 0.5, "outside_level": 0.1}
    plain, _ = _frame(_pad(**cam))
    lit, _ = _frame(_pad(stray_light=stray, **cam))
    diff = lit - plain
    full = stray * CAM.white_level * 65535
    # far outside the disc the light factor is outside_level, inside it 1
    assert diff[0, 0] == pytest.approx(0.1 * full, abs=1.0)
    assert diff[CAM.height_px // 2, CAM.width_px // 2] == pytest.approx(full, abs=1.0)


@pytest.mark.parametrize(("field", "value"), [
    ("fold_depth", 1.0), ("fold_depth", -0.1), ("fold_width_mm", -1.0), ("fold_edge_mm", -0.1),
    ("fold_x_mm", math.nan), ("stray_light", 1.0), ("stray_light", -0.01)])
def test_bad_light_fault_names_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        CameraSettings(**{field: value})


@pytest.mark.parametrize("field", ["fold_depth", "stray_light"])
def test_light_faults_are_tir_only(field):
    with pytest.raises(ValueError, match=f"camera.{field}"):
        FootageSpec(view="side", camera=CameraSettings(**{field: 0.2}))


def test_defaults_leave_the_spec_as_it_was():
    camera = FootageSpec().to_dict()["camera"]
    assert not any(k.startswith("fold_") or k == "stray_light" for k in camera)


# -- the renders of issue 21's table ------------------------------------------------------
# the full-size render (about 4 s): with -m slow, beside its measurement targets
# (tests/test_measurement_targets.py); the default run holds the fold's light
# (test_fold_darkens_its_band_by_the_requested_factor_and_nothing_else)
@pytest.mark.slow
def test_table_three_points_fold_truth_and_light():
    from synthetic.table import FOLD_DEPTH, table_specs

    spec = table_specs(n_frames=1)["three points, fold"]
    quiet = dataclasses.replace(spec, noise=False,
                                camera=dataclasses.replace(spec.camera, jpeg_quality=None))
    image, truth = _frame(quiet)
    total = float(truth.loc[truth.element == -1, "contact_area_mm2"].iloc[0])
    # three discs of 1.16 mm radius (12.7 mm2 nominal), patchy: issue 21's "about 8 mm2"
    assert 7.0 < total < 9.0
    assert (truth.element >= 0).sum() == 3
    unfolded, _ = _frame(dataclasses.replace(
        quiet, camera=dataclasses.replace(quiet.camera, fold_depth=0.0)))
    cam = spec.camera
    x = (np.arange(cam.width_px) + 0.5) * cam.mm_per_px - 0.5 * cam.width_px * cam.mm_per_px
    core = np.abs(x - cam.fold_x_mm) <= 0.5 * cam.fold_width_mm - cam.mm_per_px
    bright = unfolded[:, core] > 50  # the lit disc (8 bit, free surface ~100)
    ratio = image[:, core][bright] / unfolded[:, core][bright]
    # 8-bit rounding: +-0.5 DN at grey >= 50 is +-1 % of the ratio, averaged far below it
    assert np.mean(ratio) == pytest.approx(1 - FOLD_DEPTH, abs=0.01)


def test_table_smooth_sphere_covers_its_share():
    from synthetic.table import SPHERE_SHARE, table_specs

    spec = table_specs(n_frames=1)["smooth sphere on glass"]
    _, truth = _frame(spec)
    w, h = spec.camera.field_of_view_mm
    share = float(truth.loc[truth.element == -1, "contact_area_mm2"].iloc[0]) / (w * h)
    # supersampled disc: its area is exact to well under 1 % of 14 %
    assert share == pytest.approx(SPHERE_SHARE, rel=0.01)


# a full-size physical render (about 3.5 s): with -m slow; the rig's own empty frame is
# held in the default run by test_reference_fit and the fold render above
@pytest.mark.slow
def test_empty_reference_is_the_scene_without_contact_at_the_exposure():
    from synthetic.table import empty_reference, table_specs

    spec = table_specs(n_frames=1)["three points, fold"]
    quiet = dataclasses.replace(spec, noise=False,
                                camera=dataclasses.replace(spec.camera, jpeg_quality=None))
    ref = empty_reference(quiet, exposure=0.87, shift_px=(0.0, 0.0)).astype(float)
    image, _ = _frame(quiet)
    free = (image > 60) & (ref > 50)
    # far from the contacts the two differ by the exposure only (8-bit rounding averages out)
    assert np.median(image[free] / ref[free]) == pytest.approx(1 / 0.87, rel=0.01)
    with pytest.raises(ValueError, match="scene"):
        empty_reference(table_specs(n_frames=1)["round pad"])


def test_cli_light_fault_flags_reach_the_renderer(run_cli, tree_bytes, tmp_path, capsys):
    """``tir-contact synth footage`` with the fold and stray-light flags renders what the
    library renders for the same spec; a bad value is refused naming the field."""
    from synthetic.footage import render_footage

    out = tmp_path / "cli"
    argv = ["synth", "footage", "--out", str(out), "--frames", "2", "--scene", "round_pad",
            "--width", "96", "--height", "64", "--mm-per-px", "0.1", "--fold-depth", "0.3",
            "--fold-x", "1.5", "--fold-width", "1", "--fold-edge", "0.2", "--stray-light",
            "0.05"]
    assert run_cli(argv) == 0
    spec = FootageSpec(scene="round_pad", n_frames=2, seed=1, camera=CameraSettings(
        width_px=96, height_px=64, mm_per_px=0.1, fold_depth=0.3, fold_x_mm=1.5,
        fold_width_mm=1.0, fold_edge_mm=0.2, stray_light=0.05))
    ref = render_footage(spec, tmp_path / "lib", progress=False)
    assert tree_bytes(out / "frames") == tree_bytes(ref / "frames")
    capsys.readouterr()
    assert run_cli([*argv[:-2], "--stray-light", "1.5", "--out", str(tmp_path / "bad")]) != 0
    assert "stray_light" in capsys.readouterr().err


def test_stray_light_lifts_full_contact_of_a_physical_scene():
    """Rough pad (contact solver and FTIR optics): full contact is ~0.98 dark without stray
    light; with it every grey rises by stray * white_level of full scale, so the darkest
    contact is at most 1 / (1 + stray) as dark as before."""
    pytest.importorskip("tamaas", reason="the contact extra")
    stray = 0.15
    spec = FootageSpec(scene="rough_pad", pad_radius_mm=0.3, n_frames=1, noise=False, seed=2,
                       camera=CameraSettings(mm_per_px=0.01, width_px=96, height_px=96,
                                             bit_depth=16, white_level=0.7))
    plain, truth = _frame(spec)
    lit, truth_s = _frame(dataclasses.replace(
        spec, camera=dataclasses.replace(spec.camera, stray_light=stray)))
    assert np.abs(lit - plain - stray * 0.7 * 65535).max() <= 1.0
    free = np.median(plain)  # the pad covers a tenth of the frame
    assert 1 - plain.min() / free > 0.9  # the renderer's full contact: nearly black
    assert 1 - lit.min() / np.median(lit) < (1 - plain.min() / free) / (1 + stray) + 0.02
    pd.testing.assert_frame_equal(truth, truth_s)
