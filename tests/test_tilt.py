"""The tilt of the element edges (tir_contact.tilt): a camera turned about its axis.

Truth: the renderer's ``CameraSettings.rotation_deg`` (the footage turned by it).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from synthetic.footage import CameraSettings
from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.tilt import MAX_TILT_DEG

SMALL_CAMERA = CameraSettings(mm_per_px=0.2, width_px=320, height_px=128)  # conftest's
FAST = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0, parquet=False)


@pytest.mark.parametrize("rotation_deg", [-3.0, 0.0, 3.0])
def test_a_turned_camera_is_measured_and_warned_about(render_clip, tmp_path, rotation_deg):
    """A G3 pass seen by a camera turned by `rotation_deg`: the edges' tilt is read within
    5 % of the turn plus 0.1 deg (the tensor reads 0.97 of it through the edges' pixel
    steps, module notes), and beyond MAX_TILT_DEG the deflection angles are said to drift
    (before: no word, while a 3 deg turn moved a G3 block's median angle error from 0.4 to
    1.7 deg)."""
    cam = dataclasses.replace(SMALL_CAMERA, rotation_deg=rotation_deg)
    folder = render_clip(tmp_path / "turned", n_frames=60, camera=cam, seed=3)
    res = analyze_video(folder, options=FAST)
    tilt = res.summary["edge_tilt"]
    assert tilt["coherence"] >= 0.9
    assert tilt["tilt_deg"] == pytest.approx(rotation_deg, abs=0.05 * abs(rotation_deg) + 0.1)
    said = [w for w in res.summary["warnings"] if "element edges are tilted" in w]
    assert len(said) == (abs(rotation_deg) > MAX_TILT_DEG), said
    assert np.isfinite(res.frames.deflection_angle_deg).any()  # what the warning is about


def test_round_static_contact_has_no_edge_direction(render_clip, tmp_path):
    """A static round pad: no straight edges dominate (coherence under 0.9), so nothing is
    said of a tilt whatever the tensor's angle."""
    folder = render_clip(tmp_path / "pad", scene="round_pad", n_frames=5)
    res = analyze_video(folder, options=FAST)
    assert res.summary["edge_tilt"]["coherence"] < 0.9
    assert not [w for w in res.summary["warnings"] if "tilted" in w]


def test_edges_along_the_rows_are_not_judged():
    """A long narrow contact (280 x 6 px) whose sides along the rows dominate: the tensor
    reads about 90 deg with high coherence; these are not the elements' front and back
    edges, and a "tilted 90 deg" warning would be nonsense (helper-15's review)."""
    from tir_contact.flatfield import Reference
    from tir_contact.tilt import edge_tilt, tilt_warning

    frame = np.full((100, 320), 200.0)
    frame[47:53, 20:300] = 20.0
    ref = Reference(np.full(frame.shape, 200.0), np.ones(frame.shape, bool), "file", 1)
    tilt = edge_tilt([frame], ref, 0.45)
    assert abs(tilt.tilt_deg) > 45 and tilt.straight
    assert tilt_warning(tilt, n_angles=10) is None
