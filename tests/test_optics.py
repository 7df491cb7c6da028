"""Full contact's darkness from the rig's optics (:mod:`tir_contact.optics`).

Independent truths: Fresnel's closed forms at normal incidence and at Brewster's angle,
total reflection past the critical angle; the renderer's physical scenes (frustrated TIR
through the gap field of a solved rough contact, :mod:`synthetic.ftir`), whose optical
contact is the image's darkness over that of full contact.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from _extras import needs_tamaas

from tir_contact._readers import FootageError
from tir_contact.meta import load_meta
from tir_contact.optics import SUBSTRATE_INDEX, contact_darkness, full_contact_from_meta


def test_normal_incidence_is_the_closed_form():
    for n1, n2 in [(1.31, 1.5), (1.52, 1.5), (1.0, 1.5)]:
        r = ((n1 - n2) / (n1 + n2)) ** 2
        assert contact_darkness(n1, 0.0, n2) == pytest.approx(1.0 - r, abs=1e-12)


def test_brewster_angle_leaves_only_the_s_wave():
    n1, n2 = 1.31, 1.5
    theta = math.atan(n2 / n1)
    ct, st = math.cos(theta), math.sin(theta)
    cos_t = math.sqrt(1 - (n1 * st / n2) ** 2)
    r_s = (n1 * ct - n2 * cos_t) / (n1 * ct + n2 * cos_t)
    assert contact_darkness(n1, math.degrees(theta), n2) == pytest.approx(1 - r_s ** 2 / 2,
                                                                         abs=1e-12)


def test_past_the_critical_angle_the_rubber_reflects_totally_too():
    # glass (1.52) on rubber of 1.3: critical angle 58.8 deg
    assert contact_darkness(1.52, 60.0, 1.3) == 0.0
    assert contact_darkness(1.52, 55.0, 1.3) > 0.0
    with pytest.raises(ValueError, match="incidence_deg"):
        contact_darkness(1.31, 90.0)


def test_meta_names_the_optics_and_a_wrong_substrate_is_a_clear_error(tmp_path):
    meta = {"view": "tir", "fps": 1000, "mm_per_px": 0.05, "sliding_direction": "left",
            "optics": {"substrate": "ice", "incidence_deg": 60}}
    c, how = full_contact_from_meta(meta)
    # rubber on ice at 60 deg returns 2.2 % of the light (the s wave 4.0 %, the p wave 0.4 %)
    assert c == pytest.approx(0.978, abs=5e-4) and "ice" in how and "Fresnel" in how
    assert full_contact_from_meta({"optics": {"rubber_index": 1.5}}) is None
    footage = tmp_path / "clip.tif"
    footage.write_bytes(b"")
    (tmp_path / "meta.json").write_text(
        '{"view": "tir", "fps": 1000, "mm_per_px": 0.05, "sliding_direction": "left", '
        '"optics": {"substrate": "sapphire", "incidence_deg": 60}}')
    with pytest.raises(FootageError, match=r"optics\.substrate") as err:
        load_meta(footage)
    assert "ice" in str(err.value) and "meta.json" in str(err.value)
    # a substrate without its angle, or an angle at which the rig shows no contact: the
    # analysis names the key (tir_contact.prepare adds the file)
    with pytest.raises(ValueError, match=r"'optics\.substrate' is given without"):
        full_contact_from_meta({"optics": {"substrate": "ice"}})
    with pytest.raises(ValueError, match=r"'optics\.incidence_deg' must lie between 49\.8"):
        full_contact_from_meta({"optics": {"substrate": "ice", "incidence_deg": 30}})
    with pytest.raises(ValueError, match=r"between 41\.1 deg .* and 80\.7 deg"):
        full_contact_from_meta({"optics": {"substrate": "glass", "incidence_deg": 85}})


def _junction_field(tmp_path, substrate: str, rubber_index: float | None, monkeypatch):
    """Seed 7's rough pad draw 4 (none of its junctions resolved: full contact's darkness
    cannot be read from the image), 4 frames, on `substrate`, analysed with its empty
    frame; the renderer's rubber index set to `rubber_index` (the analysis, not told it,
    takes 1.5)."""
    import cv2
    import pandas as pd

    from synthetic import footage as fp
    from synthetic.domain import sample_physical_specs
    from synthetic.ftir import FtirOptics
    from synthetic.table import empty_reference
    from tir_contact.analyze import AnalysisOptions, analyze_video

    spec, _ = sample_physical_specs(5, seed=7)[4]
    spec = dataclasses.replace(spec, n_frames=4, substrate=substrate)
    if rubber_index is not None:
        base = fp.FootageSpec.optics.fget
        monkeypatch.setattr(fp.FootageSpec, "optics", property(
            lambda s: dataclasses.replace(base(s), rubber_index=rubber_index)))
    folder = fp.render_footage(spec, tmp_path / "clip", progress=False)
    ref = tmp_path / "empty.png"  # the rig's empty frame: the free surface under the pad
    cv2.imwrite(str(ref), empty_reference(spec))
    res = analyze_video(folder, options=AnalysisOptions(
        overlay_video=False, plots=False, overlay_frames=0, parquet=False, reference=str(ref)))
    truth = pd.read_csv(folder / "ground_truth.csv")
    truth = truth[truth["element"] == -1].set_index("frame")
    optics = FtirOptics(substrate=substrate, rubber_index=rubber_index or 1.5)
    return res, truth, optics


@needs_tamaas
def test_junction_field_is_read_against_its_substrates_fresnel_contrast(tmp_path,
                                                                        monkeypatch):
    """On glass full contact takes 99.95 % of the light, not the 97 % assumed without the
    optics: read against 0.97 the pad would lie 3 % above its optical contact (the two
    contrasts' ratio); with meta.json's ``optics`` it reads 0.2-0.5 % below it (measured
    on the draw's ice at the thesis's flaw density; 0.0-0.2 % above on the crowded ice of
    the draws before). Tolerance 1 %: the pipeline's own error on this junction field with
    its empty frame (0.5 %) and the free surface's noise summed over it."""
    res, truth, _ = _junction_field(tmp_path, "glass", None, monkeypatch)
    assert res.summary["populations"]["contact"]["source"] == "assumed"
    assert any("on glass (n 1.52) at 60 deg, Fresnel" in w for w in res.summary["warnings"])
    frames = res.frames.set_index("frame").reindex(truth.index)
    np.testing.assert_allclose(frames["contact_area_mm2"], truth["optical_contact_area_mm2"],
                               rtol=0.01)


@needs_tamaas
def test_a_rubber_of_another_index_stays_inside_the_bar(tmp_path, monkeypatch):
    """The renderer's rubber at n = 1.6 on ice (full contact 0.962 dark) while the analysis
    takes 1.5 (0.978): the reading falls below the one of the same scene with a rubber of
    1.5 by the two contrasts' ratio (0.984; without the optics both would be read against
    the 0.97 assumed, and the ratio would be the same: what the optics change is the
    reading of the 1.5 rubber, above), and the bar, whose range of full contact (0.85-1)
    holds any rubber and stray light, still holds the optical contact in every frame."""
    res, truth, optics = _junction_field(tmp_path / "n16", "ice", 1.6, monkeypatch)
    monkeypatch.undo()
    same, same_truth, _ = _junction_field(tmp_path / "n15", "ice", None, monkeypatch)
    assert optics.contact_darkness == pytest.approx(0.962, abs=1e-3)
    frames = res.frames.set_index("frame").reindex(truth.index)
    frames_15 = same.frames.set_index("frame").reindex(same_truth.index)
    optical = truth["optical_contact_area_mm2"]
    expected = contact_darkness(SUBSTRATE_INDEX["ice"], 60.0, 1.6) / contact_darkness(
        SUBSTRATE_INDEX["ice"], 60.0)
    # frame by frame the two renders differ only in the rubber's index (the same junctions,
    # light, ice and noise): the pipeline's own error on the field (0.2-0.5 %) cancels in
    # their ratio, which is the contrasts' ratio to 0.03 % (measured) and to the 0.02 % by
    # which the two optical contacts differ. Tolerance 0.2 %: a tenth of the ratio's own
    # distance from 1 (a reading that ignored the index would give 1).
    ratio = (frames["contact_area_mm2"] / optical) / (
        frames_15["contact_area_mm2"] / same_truth["optical_contact_area_mm2"])
    np.testing.assert_allclose(ratio, expected, atol=0.002)
    assert any("on ice (n 1.31) at 60 deg, Fresnel" in w for w in res.summary["warnings"])
    assert (frames["contact_area_low_mm2"] <= optical).all()
    assert (optical <= frames["contact_area_high_mm2"]).all()


def test_optics_that_cannot_be_used_are_an_error_naming_the_metadata_file(render_clip,
                                                                          tmp_path):
    import json

    from tir_contact.analyze import AnalysisOptions, analyze_video

    folder = render_clip(tmp_path / "clip", n_frames=8)
    meta = json.loads((folder / "meta.json").read_text())
    meta["optics"] = {"substrate": "glass", "incidence_deg": 85.0}
    (folder / "meta.json").write_text(json.dumps(meta))
    with pytest.raises(FootageError, match=r"meta\.json: 'optics\.incidence_deg' must lie"):
        analyze_video(folder, options=AnalysisOptions(overlay_video=False, plots=False,
                                                      overlay_frames=0))
