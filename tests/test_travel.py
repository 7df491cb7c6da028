"""The camera mode by the metadata's travel (tir_contact.travel): a passing block whose
contact is too faint for the samples alone to show it passing.

Truth: the renderer's geometry (the block passes a fixed camera at the spec's velocity, or
the camera follows it) and its ``ground_truth.csv``; for the unit tests, profiles shifted
by a known number of pixels.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tests._extras import needs_tamaas
from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.travel import MIN_TRAVEL_PX, carried, expected_travel_px

FAST = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0, parquet=False)


def _frames(shifts_px: list[int], *, seed: int = 0) -> tuple[list[np.ndarray], np.ndarray]:
    """A vignetted 120 x 400 px light field with a fine random pattern of dark junctions over
    a 200 px stretch (a rough block's real contact: a few % of it, none of it block-sized),
    shifted along the rows by each of `shifts_px`; and the field itself (the free surface)."""
    rng = np.random.default_rng(seed)
    xx = np.mgrid[:120, :400][1]
    light = 200.0 * (1.0 - 0.3 * ((xx - 200) / 200.0) ** 2)
    spots = (rng.random((120, 800)) < 0.04) & (np.arange(800) >= 300) & (np.arange(800) < 500)
    frames = []
    for s in shifts_px:
        dark = np.roll(spots, s, axis=1)[:, 200:600]
        noise = rng.normal(0.0, 2.0, light.shape)
        frames.append((light * (1.0 - 0.9 * dark) + noise).astype(np.float32))
    return frames, light.astype(np.float32)


def test_expected_travel_follows_the_metadata():
    """v dt / mm_per_px along the sliding direction: 2 m/s at 5000 fps and 0.05 mm/px is
    8 px per frame; none without a velocity."""
    meta = {"fps": 5000, "mm_per_px": 0.05, "sliding_direction": "right",
            "conditions": {"velocity_mps": 2.0}}
    np.testing.assert_allclose(expected_travel_px(meta, [10, 11, 15]), [0.0, 8.0, 40.0])
    assert expected_travel_px({**meta, "conditions": {}}, [0, 1]) is None


@pytest.mark.parametrize("shift", [-30, 30])
def test_contact_shifted_by_the_travel_is_carried(shift):
    """Junctions shifted by the expected travel: carried; the same junctions held in place
    while the metadata expects that travel: held; shifted as far against the sliding
    direction: carried too (a fixed camera whose sliding_direction is wrong, which the
    front's travel warns about)."""
    lit = np.ones((120, 400), bool)
    frames, free = _frames([0, shift // 2, shift])
    travel = [0.0, shift / 2, float(shift)]
    assert carried(frames, free, lit, travel) is True
    held, _ = _frames([0, 0, 0])
    assert carried(held, free, lit, travel) is False
    back, _ = _frames([0, -shift // 2, -shift])
    assert carried(back, free, lit, travel) is True


def test_a_travel_too_short_to_tell_decides_nothing():
    """Under MIN_TRAVEL_PX between the samples the lag cannot tell 0 from the travel."""
    lit = np.ones((120, 400), bool)
    frames, free = _frames([0, 3])
    assert carried(frames, free, lit, [0.0, 0.5 * MIN_TRAVEL_PX]) is None


def _area_error_pct(folder, res) -> float:
    truth = pd.read_csv(folder / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame").contact_area_mm2
    measured = res.frames.set_index("frame").contact_area_mm2
    return float(100 * (measured.sum() / block.reindex(measured.index).sum() - 1))


@needs_tamaas
@pytest.mark.parametrize("fields", [
    {"velocity_mps": 1.0},
    {"velocity_mps": 2.0, "sliding_direction": "right"},
], ids=["1 m/s left", "2 m/s right"])
def test_a_short_pass_of_faint_contact_is_a_fixed_camera(render_clip, tmp_path, fields):
    """A G3 block with physical real contact passing the default camera (0.1 mm/px, 640 px)
    in 10 frames covers most of the view in every sample, and its junctions are too faint
    for a block-sized region: the samples alone took it as held, and its area read -38.8 and
    -31.7 % (helper-11). Its travel between the samples (22.5 and 45 px) decides now.
    Required: camera "fixed" and the summed area within 8 %, issue 21's p95 target (-3.7 and
    -3.3 % measured)."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "clip", n_frames=10, real_contact="physical",
                         dynamics="steady", settle_s=0.004, seed=2, camera=CameraSettings(),
                         **fields)
    res = analyze_video(folder, options=FAST)
    assert res.summary["camera"] == "fixed"
    assert abs(_area_error_pct(folder, res)) <= 8.0


@needs_tamaas
def test_held_faint_contact_stays_held_with_a_velocity(render_clip, tmp_path):
    """The same block and velocity seen by a camera that follows it: the contact does not
    travel, and the metadata's velocity must not make it a fixed camera."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "clip", n_frames=10, real_contact="physical",
                         dynamics="steady", settle_s=0.004, seed=2, camera=CameraSettings(),
                         velocity_mps=1.0, follow_camera=True)
    res = analyze_video(folder, options=FAST)
    assert res.summary["camera"] == "follows"


@pytest.mark.parametrize("pitch_px", [20, 25, 35, 45])
@pytest.mark.parametrize("travel_px", [30.0, -30.0])
def test_a_held_periodic_tread_is_never_taken_for_a_passing_one(pitch_px, travel_px):
    """A held tread filling the view, 12 px elements every `pitch_px`, whose junctions
    renew from sample to sample (the ice slides under a block that a camera follows): its
    profile correlates about as well one pitch off as in place. Before, the best shift up
    to twice the travel that lay nearer the travel than 0 made it a passing block in 3 of
    these 8 cases (helper-14); it may be undecided (None: the samples' own answer stands),
    never carried."""
    h, w = 120, 400
    xx = np.mgrid[:h, :w][1]
    light = (200.0 * (1.0 - 0.3 * ((xx - 200) / 200.0) ** 2)).astype(np.float32)
    elements = ((np.arange(w) % pitch_px) < 12)[None, :]
    frames = []
    for k in range(3):
        rng = np.random.default_rng(k)
        dark = elements & (rng.random((h, w)) < 0.3)
        frames.append((light * (1 - 0.9 * dark) + rng.normal(0, 2, (h, w))).astype(np.float32))
    lit = np.ones((h, w), bool)
    assert carried(frames, light, lit, [0.0, travel_px / 2, travel_px]) is not True


def test_travel_must_be_one_finite_value_per_sample():
    frames, free = _frames([0, 10])
    lit = np.ones(free.shape, bool)
    with pytest.raises(ValueError, match=r"one finite displacement .* per sample"):
        carried(frames, free, lit, [0.0, float("nan")])
    with pytest.raises(ValueError, match=r"per sample \(2\)"):
        carried(frames, free, lit, [0.0, 10.0, 20.0])
