"""What the segmentation must do on the physical world: targets of issue 21 ("contact
area as a measurement"), all met now (they were strict xfails until it was).

Each case is a render of the kind the real images showed (the images themselves are not
ours to ship): dark micro-junctions of a rough elastomer on a bright, strongly textured
field, a static load series with no empty frame. The truth is the true contact area (gap 0)
from the rough-contact solver.
"""

from __future__ import annotations

import numpy as np
import pytest
from _extras import needs_tamaas

pytestmark = [needs_tamaas, pytest.mark.slow]  # four solves and four analyses: a minute

LOADS_BAR = (0.5, 1.0, 2.0, 4.0)


@pytest.fixture(scope="module")
def textured_series(tmp_path_factory):
    """Rough pad at four loads on a textured field (0.01 mm/px, no empty frame)."""
    from synthetic.footage import CameraSettings, FootageSpec, render_footage

    cam = CameraSettings(mm_per_px=0.01, width_px=200, height_px=200, optical_blur_mm=0.004)
    out = []
    for p in LOADS_BAR:
        spec = FootageSpec(
            scene="rough_pad", pad_radius_mm=0.8, pressure_bar=p, n_frames=3, camera=cam,
            texture=0.12, texture_mm=0.04, seed=4,
        )
        folder = render_footage(spec, tmp_path_factory.mktemp("series") / f"p{p:g}",
                                progress=False)
        out.append(_areas(folder))
    return out


def _areas(folder) -> tuple[float, float]:
    import pandas as pd

    from tir_contact import AnalysisOptions, analyze_video

    res = analyze_video(folder, options=AnalysisOptions(overlay_frames=0, parquet=False))
    truth = pd.read_csv(folder / "ground_truth.csv")
    true = float(truth.loc[truth["element"] == -1, "contact_area_mm2"].mean())
    f = res.frames
    return (float(f["contact_area_mm2"].mean()), true, float(f["contact_area_low_mm2"].mean()),
            float(f["contact_area_high_mm2"].mean()))


def test_textured_rough_load_series_area_within_25_percent(textured_series):
    """The measured area within 25 % of the truth at every load (measured: +16, +21, +3,
    +18 % at 0.5-4 bar; before issue 21's measurement +285, +158, +88, +56 %)."""
    measured, true, _, _ = zip(*textured_series, strict=True)
    # 25 %: the band the measured area is to carry for sub-pixel junctions
    assert np.allclose(measured, true, rtol=0.25)


def test_textured_rough_load_series_measured_area_grows_in_proportion(textured_series):
    measured = np.array([m[0] for m in textured_series])
    loads = np.array(LOADS_BAR)
    beta = np.polyfit(np.log(loads), np.log(np.maximum(measured, 1e-9)), 1)[0]
    # the truth grows as p^0.9-1 (test_physical_contact); 0.8 leaves room for the error bar
    assert beta > 0.8


def test_textured_rough_load_series_truth_inside_the_error_bar(textured_series):
    """The error bar (contact_area_low/high_mm2) holds the true area at every load."""
    for measured, true, low, high in textured_series:
        assert low <= true <= high, (measured, true, low, high)
