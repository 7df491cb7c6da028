"""Side view with any holder above the block (issue 21, item 5), against the renderer's
ground truth (:mod:`synthetic.footage`, independent of the analysis).

The case of the issue: a holder plate spanning the whole frame width, the camera following
the block, elements that shear into parallelograms and change angle after a velocity step
(0.5 -> 3 m/s; the model's elements swing by up to 17 deg). Before, the elements' motion
made the automatic mode take the camera as fixed, and the percentile reference (which then
holds the block) left "no block found in any frame"; with ``--camera follows`` a block
over 80 % of the width was not found either (each row's background was its 75th
percentile, which is rubber then).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from synthetic.footage import CameraSettings, FootageSpec, iter_frames, render_footage
from tir_contact.analyze import analyze_video
from tir_contact.options import AnalysisOptions
from tir_contact.side import block_span_px

#: Frames of the stepped clips and the frame of the step (4000 frames/s).
N_FRAMES, STEP_FRAME = 24, 12


def _spec(mm_per_px: float, *, holder: str = "plate", preset: str = "G3",
          follow: bool = True) -> FootageSpec:
    step = dict(velocity_mps=0.5, velocity_step_to_mps=3.0, step_time_s=STEP_FRAME / 4000.0,
                dynamics="simulated", settle_s=0.01) if follow else dict(
                    velocity_mps=1.0, dynamics="steady", settle_s=0.004)
    return FootageSpec(view="side", preset=preset, holder=holder, follow_camera=follow,
                       n_frames=N_FRAMES if follow else 40,
                       camera=CameraSettings(width_px=640, height_px=256, mm_per_px=mm_per_px),
                       **step)


def _analyse(spec: FootageSpec, folder: Path, camera: str = "auto"):
    clip = render_footage(spec, folder, progress=False)
    result = analyze_video(clip, options=AnalysisOptions(camera=camera))
    truth = pd.read_csv(clip / "ground_truth.csv")
    truth = truth[truth["element"] >= 0]
    merged = truth.merge(result.elements, on=["frame", "element"], how="left",
                         suffixes=("_true", ""))
    return result, merged


# Measured (G3, holder plate, following camera, 0.5 -> 3 m/s step): 62 % of the width: all
# 96 angles, median error 0.005 deg, largest 0.035 deg; 89 %: the 90 elements wholly in
# view, median 0.002 deg, largest 0.012 deg. Before: no block in any frame (auto), and at
# 89 % none with --camera follows either.
@pytest.mark.parametrize("mm_per_px", [0.05, 0.035], ids=["block 62 %", "block 89 %"])
@pytest.mark.parametrize("camera", ["auto", "follows"])
def test_plate_across_the_frame_following_camera_velocity_step(tmp_path, mm_per_px, camera):
    spec = _spec(mm_per_px)
    result, el = _analyse(spec, tmp_path / "clip", camera)
    assert result.summary["camera"] == "follows"
    assert result.frames["block_in_view"].all()
    # G3's four angles in every frame when the block spans 62 % of the width; at 89 % the
    # trailing element touches the image border in some frames (listed with NaN, as
    # tir_contact.side says): 90 of 96 measured
    measured = el["deflection_angle_deg"].notna()
    assert len(el) == 4 * N_FRAMES
    assert measured.mean() >= (1.0 if mm_per_px == 0.05 else 0.9)
    err = (el["deflection_angle_deg"] - el["deflection_angle_deg_true"]).abs()[measured]
    tip = (el["tip_deflection_mm"] - el["tip_deflection_mm_true"]).abs()[measured]
    # 0.2 deg: the side view's stated accuracy is 0.5 deg (tests/test_side.py); the
    # chord's ends are placed to about 0.1 px, 0.1 deg over a 6 mm element at 0.05 mm/px
    assert err.max() <= 0.2 and err.median() <= 0.05
    assert tip.median() <= 0.01  # mm; 0.2 px at 0.05 mm/px
    # the elements do change angle after the step: the test sees the shear
    per_frame = el.groupby("frame")["deflection_angle_deg_true"].mean()
    assert np.ptp(per_frame.to_numpy()) > 10.0


@pytest.mark.slow  # 6 s: a second holder and a G5 model run
def test_carriage_above_the_holder(tmp_path):
    """The rig's carriage, as dark as the plate, fills the frame above the holder."""
    result, el = _analyse(_spec(0.05, holder="carriage", preset="G5"), tmp_path / "clip")
    assert result.summary["camera"] == "follows"
    assert el["deflection_angle_deg"].notna().all() and len(el) == 6 * N_FRAMES
    err = (el["deflection_angle_deg"] - el["deflection_angle_deg_true"]).abs()
    assert err.max() <= 0.2


def test_fixed_camera_with_a_plate_is_fixed(tmp_path):
    """A block passing a fixed camera under a plate across the frame: the block
    translates, so the camera is fixed; frames without the block give the reference."""
    spec = FootageSpec(view="side", preset="G3", holder="plate", n_frames=60,
                       dynamics="steady", settle_s=0.004, velocity_mps=3.0,
                       camera=CameraSettings(width_px=320, height_px=128, mm_per_px=0.2,
                                             fps=2000.0))
    result, el = _analyse(spec, tmp_path / "clip")
    assert result.summary["camera"] == "fixed"
    assert result.summary["reference"]["method"] == "percentile"
    measured = el["deflection_angle_deg"].notna()
    assert measured.sum() >= 40
    err = (el["deflection_angle_deg"] - el["deflection_angle_deg_true"]).abs()[measured]
    assert err.median() <= 0.5  # 0.2 mm/px: the side view's stated accuracy


def test_slow_block_that_never_leaves_a_fixed_camera(tmp_path):
    """The block moves by half its length past a fixed camera and never leaves the view: the
    camera is fixed (the block translates), but no frame shows the background behind it,
    so each frame is normalised by its own."""
    result, el = _analyse(_spec(0.035, follow=False), tmp_path / "clip")
    assert result.summary["camera"] == "fixed"
    assert "never leaves" in result.summary["reference"]["method"]
    measured = el["deflection_angle_deg"].notna()
    assert measured.mean() >= 0.7
    err = (el["deflection_angle_deg"] - el["deflection_angle_deg_true"]).abs()[measured]
    assert err.max() <= 0.2


def test_block_span_of_a_following_camera_stays_put():
    """The base of a block under a following camera stays within 1 % of its length while
    its elements swing by 17 deg (the decision rule's margin: a tenth of the length)."""
    spec = _spec(0.05)
    spans = np.array([block_span_px(img) for _, img, _ in iter_frames(spec)])
    length = float(np.median(spans[:, 1] - spans[:, 0]))
    assert np.ptp(spans, axis=0).max() < 0.02 * length


def test_no_block_span_in_an_empty_view_with_dust():
    """Dust on the lens darkens by up to about a third (a noisy, vignetted domain camera:
    sample_specs(80, seed=5)[3], the block far away): no block."""
    cam = CameraSettings(width_px=211, height_px=120, mm_per_px=0.1333, gain=2.894,
                         white_level=0.2975, vignetting=0.554, illumination_gradient=0.098,
                         n_bubbles=0, n_scratches=3, groove_depth=0.0188, n_dust=40)
    spec = FootageSpec(view="side", preset="G5", n_frames=1, dynamics="steady",
                       settle_s=0.004, center_time_s=10.0, seed=2138939200, camera=cam)
    image = next(iter_frames(spec))[1]
    assert block_span_px(image) is None
