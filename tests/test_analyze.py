"""Per-video analysis and the batch CLI: outputs, ground truth, broken input, resume.

Truth: the synthetic renderer's ``ground_truth.csv`` (exact model geometry before any camera
effect). Clips are small (0.2 mm/px, 320 x 128 px) so the module renders in a few seconds.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
import pytest

from tir_contact.analyze import ELEMENT_COLUMNS, FRAME_COLUMNS, AnalysisOptions, analyze_video
from tir_contact.batch import analyze_batch, find_footage, is_current

ISSUE_FRAME_COLUMNS = [
    "frame", "time_s", "block_in_view", "block_front_x_mm", "contact_area_mm2",
    "contact_ratio", "n_elements_in_contact", "front_peak_x_mm", "front_peak_contrast",
]
ISSUE_ELEMENT_COLUMNS = [
    "frame", "time_s", "element", "contact_area_mm2", "contact_length_mm", "front_edge_x_mm",
    "front_peak_x_mm", "front_peak_contrast", "liftoff_mm", "deflection_angle_deg",
]
# the full lists docs/formats.md publishes (TIR clip), in order
DOC_FRAME_COLUMNS = [*ISSUE_FRAME_COLUMNS, "block_fully_in_view", "n_regions",
                     "deflection_angle_deg", "tip_deflection_mm", "contact_at_lit_rim",
                     "contact_area_low_mm2", "contact_area_high_mm2"]
DOC_ELEMENT_COLUMNS = [*ISSUE_ELEMENT_COLUMNS, "front_peak_width_mm", "tip_deflection_mm"]
FAST = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0, parquet=False)


@pytest.fixture(scope="module")
def clip(render_clip, tmp_path_factory) -> Path:
    return render_clip(tmp_path_factory.mktemp("clips") / "G3_3mps")


@pytest.fixture(scope="module")
def analysed(run_cli, clip, tmp_path_factory) -> tuple[Path, Path]:
    out = tmp_path_factory.mktemp("out")
    code = run_cli(["analyze", clip, "--out", out, "--workers", "1", "--no-progress",
                 "--plots", "--overlay-video"])
    assert code == 0
    return clip, out / clip.name


def test_default_outputs_are_the_cheap_ones(run_cli, clip, tmp_path):
    out = tmp_path / "out"
    assert run_cli(["analyze", clip, "--out", out, "--workers", "1", "-q"]) == 0
    files = sorted(p.name for p in (out / clip.name).iterdir())
    # tables, summary, the lit mask and a few overlay images; no plots, no overlay video
    # unless asked
    assert "overlay.avi" not in files
    assert [f for f in files if f.endswith(".png")] == ["lit_mask.png"]
    assert {"frames.csv", "elements.csv", "summary.json", "overlays"} <= set(files)


def test_outputs_have_the_issue_columns_and_files(analysed):
    _, res = analysed
    frames = pd.read_csv(res / "frames.csv")
    elements = pd.read_csv(res / "elements.csv")
    # exact lists, in order: a reordered, renamed, missing or extra column fails
    assert list(frames.columns) == DOC_FRAME_COLUMNS
    assert list(elements.columns) == DOC_ELEMENT_COLUMNS
    assert FRAME_COLUMNS == DOC_FRAME_COLUMNS and ELEMENT_COLUMNS == DOC_ELEMENT_COLUMNS
    assert not (res / "regions.csv").exists()  # with block geometry only on request
    for name in ("summary.json", "contact.png", "elements.png", "overlay.avi"):
        assert (res / name).is_file(), name
    assert len(list((res / "overlays").glob("frame_*.png"))) >= 3
    summary = json.loads((res / "summary.json").read_text())
    assert summary["complete"] is True and summary["skipped_frames"] == []
    assert summary["reference"]["method"] == "percentile"
    assert summary["steady"]["n_frames"] == summary["frames_with_whole_block"] > 0
    # no staging folders left behind
    assert not [p for p in res.parent.iterdir() if p.name.startswith(".")]


def test_parquet_copies_hold_the_csv_tables(analysed):
    """The `parquet` extra's output: frames/elements.parquet, the same rows and columns as the
    CSV tables (CI installs the extra, tests/test_ci_extras.py; skips only without pyarrow)."""
    pytest.importorskip("pyarrow", reason="needs the parquet extra")
    _, res = analysed
    for stem, columns in (("frames", DOC_FRAME_COLUMNS), ("elements", DOC_ELEMENT_COLUMNS)):
        pq = pd.read_parquet(res / f"{stem}.parquet")
        csv = pd.read_csv(res / f"{stem}.csv")
        assert list(pq.columns) == columns
        assert len(pq) == len(csv) > 0
        # the CSV keeps 6 significant digits (%.6g): rtol 1e-5 covers it; dtypes may differ
        pd.testing.assert_frame_equal(pq, csv, check_dtype=False)


def test_area_against_ground_truth(analysed):
    """Median relative error of the block contact area <= 2 % (required)."""
    clip, res = analysed
    frames = pd.read_csv(res / "frames.csv").set_index("frame")
    truth = pd.read_csv(clip / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame")
    inside = block.index[block.in_view & (block.contact_area_mm2 > 20)]
    rel = (frames.loc[inside, "contact_area_mm2"] - block.loc[inside, "contact_area_mm2"]).abs()
    rel /= block.loc[inside, "contact_area_mm2"]
    assert rel.median() <= 0.02
    # frames without the block are reported as such
    empty = block.index[~block.in_view]
    assert len(empty) > 5
    assert not frames.loc[empty, "block_in_view"].astype(bool).any()
    assert (frames.loc[empty, "contact_area_mm2"] == 0).all()


def test_steady_summary_matches_truth(analysed):
    clip, res = analysed
    summary = json.loads((res / "summary.json").read_text())
    truth = pd.read_csv(clip / "ground_truth.csv")
    frames = pd.read_csv(res / "frames.csv")
    full = frames.loc[frames.block_fully_in_view.astype(bool), "frame"]
    t = truth[(truth.element == -1) & truth.frame.isin(full)]
    mean = summary["steady"]["contact_area_mm2"]["mean"]
    assert mean == pytest.approx(t.contact_area_mm2.mean(), rel=0.02)


def _said(folder: Path, needle: str, out: Path | None = None, **overrides) -> list[str]:
    """The warnings holding `needle` of `folder` analysed with the meta.json `overrides`."""
    res = analyze_video(folder, out, overrides=overrides or None, options=FAST)
    return [w for w in res.summary["warnings"] if needle in w]


def _directions(folder: Path) -> tuple[str, str]:
    """The clip's own sliding direction (its meta.json) and the other one."""
    given = json.loads((folder / "meta.json").read_text())["sliding_direction"]
    return given, "right" if given == "left" else "left"


def test_a_block_moving_against_the_sliding_direction_is_warned_about(analysed, clip,
                                                                        tmp_path):
    """The clip's block moves the way its meta.json says: no warning. Told the other way
    (--sliding-direction), the analysis reads each element's back edge as its front, and
    the block's own travel across the fixed camera's view says so."""
    _, res = analysed
    summary = json.loads((res / "summary.json").read_text())
    assert not [w for w in summary["warnings"] if "sliding_direction" in w]
    given, other = _directions(clip)
    said = _said(clip, "sliding_direction", tmp_path / "out", sliding_direction=other)
    assert len(said) == 1 and f"the block moves {given}" in said[0], said
    assert f"sliding_direction is '{other}'" in said[0]


def test_a_short_pass_against_the_sliding_direction_is_warned_about(render_clip, tmp_path):
    """A 20-frame pass at 1 m/s moves the block 4.75 mm across a 64 mm view (the default
    camera): under the 10 % of the width the check needed before, so the wrong direction
    went without a word (helper-11). Its fitted travel is many standard errors (about
    0.005 mm) and 47 px from 0: told the other way, it is warned about; told its own way,
    not."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "short", n_frames=20, velocity_mps=1.0,
                         camera=CameraSettings(), seed=1)
    given, other = _directions(folder)
    assert not _said(folder, "sliding_direction is", sliding_direction=given)
    said = _said(folder, "sliding_direction is", sliding_direction=other)
    assert len(said) == 1, said
    assert f"the block moves {given}" in said[0]


def test_a_front_that_jumps_back_an_element_is_not_a_wrong_direction(render_clip, tmp_path):
    """The block's front is its leading element's in contact: as that element leaves the
    view the front jumps back an element pitch (4.55 + 0.6 mm), against the motion. A line
    through all frames of this 80-frame pass at 16000 fps (4.9 mm of travel) then sloped
    0.8 mm the other way with a small standard error, and the block's own direction was
    warned about (the review of the 5-sigma rule). Truth: the renderer's direction; no
    warning told it, one told the other."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "jump", n_frames=80, velocity_mps=1.0,
                         center_time_s=-0.0225, camera=CameraSettings(fps=16000.0), seed=1)
    given, other = _directions(folder)
    assert not _said(folder, "sliding_direction is", sliding_direction=given)
    assert len(_said(folder, "sliding_direction is", sliding_direction=other)) == 1


def test_half_the_scale_is_warned_about_by_the_elements_found(analysed, clip, tmp_path):
    """At the clip's own scale every element of the G3 block is found in contact: no
    warning. At half its mm_per_px the element template spans twice the block's length in
    the image and the contact fills only its first two elements: contact_ratio 0.48 (a
    patchy or G7 contact reads that low at the true scale), no word before (helper-11);
    the elements found say it now."""
    _, res = analysed
    summary = json.loads((res / "summary.json").read_text())
    assert not [w for w in summary["warnings"] if "elements but" in w]
    mm = json.loads((clip / "meta.json").read_text())["mm_per_px"]
    said = _said(clip, "elements but", tmp_path / "out", mm_per_px=0.5 * mm)
    assert len(said) == 1 and "block has 4 elements" in said[0], said
    assert f"mm_per_px {0.5 * mm:g}" in said[0]


def test_a_small_lit_zone_is_not_a_wrong_scale(render_clip, tmp_path):
    """A lit disc of a fifth of the frame shows only the elements inside it: at the true
    scale the frames with the whole block in the frame found 2 of 4 in contact, and the
    scale check warned (helper-15's review). Elements outside the lit zone say nothing of
    the scale: no such warning."""
    from synthetic.footage import CameraSettings

    cam = CameraSettings(mm_per_px=0.2, width_px=320, height_px=128, lit_shape="disc",
                         lit_fraction=0.2)
    folder = render_clip(tmp_path / "disc", n_frames=60, camera=cam, seed=3)
    assert not _said(folder, "elements but")


def test_contact_beyond_the_element_faces_is_warned_about(analysed, clip, tmp_path):
    """At the clip's own scale the contact lies on the element faces (contact_ratio at
    most 1: no warning); at three times its mm_per_px the faces the geometry gives are a
    third as long in pixels and the contact covers several times them, which says the
    scale or the geometry is wrong (before: areas nine times too large, no word)."""
    _, res = analysed
    summary = json.loads((res / "summary.json").read_text())
    assert not [w for w in summary["warnings"] if "element faces" in w]
    mm = json.loads((clip / "meta.json").read_text())["mm_per_px"]
    said = _said(clip, "element faces", tmp_path / "out", mm_per_px=3 * mm)
    assert len(said) == 1 and f"mm_per_px {3 * mm:g}" in said[0], said


def test_without_geometry_every_region_is_reported(copy_meta, clip, tmp_path):
    """Any TIR footage (no block): regions with area, centroid and box; no element table."""
    folder = tmp_path / "plain"
    shutil.copytree(clip / "frames", folder)
    copy_meta(clip, folder, drop=["block"])
    res = analyze_video(folder, tmp_path / "out", options=FAST)
    assert (tmp_path / "out" / "plain" / "regions.csv").is_file()
    assert res.elements.empty
    # typed as a full table (before, object columns: np.isfinite on them raised a TypeError
    # in the validation script)
    assert res.elements.dtypes["frame"] == np.int64
    assert np.isfinite(res.elements.contact_length_mm).sum() == 0
    truth = pd.read_csv(clip / "ground_truth.csv")
    el = truth[(truth.element >= 0) & truth.in_view].groupby("frame").size()
    regions = res.regions.groupby("frame").size()
    both = el.index.intersection(regions.index)
    # one region per element in contact (G3: up to 4 strips), in most frames
    assert (regions.loc[both] == el.loc[both]).mean() >= 0.9
    per_frame = res.regions.groupby("frame").area_mm2.sum()
    frames = res.frames.set_index("frame").loc[per_frame.index]
    # the regions are the pixels counted at half contrast, the frame's area the measurement
    # (tir_contact.measure: resolved contact's edges unmixed): both hold the true area, the
    # count to the edge's half pixel (2 %), the measurement within its bar in 90 % of frames
    true = truth[truth.element == -1].set_index("frame").loc[per_frame.index,
                                                               "contact_area_mm2"]
    big = true > 20.0
    assert (per_frame[big] / true[big] - 1).abs().median() < 0.02
    assert (frames["contact_area_mm2"][big] / true[big] - 1).abs().median() < 0.02
    inside = ((frames["contact_area_low_mm2"] <= true) & (true <= frames["contact_area_high_mm2"]))
    assert inside.mean() >= 0.9


def test_clip_folder_and_frames_folder_are_the_same_footage(clip, tmp_path):
    a = analyze_video(clip / "frames", options=FAST)
    items = find_footage([clip])
    assert items[0].path == clip / "frames" and items[0].name == clip.name
    b = analyze_video(items[0].path, options=FAST)
    pd.testing.assert_frame_equal(a.frames, b.frames)


def _broken_tree(root: Path, good: Path, copy_meta) -> dict[str, str]:
    """A tree with one good clip and one of each broken kind; returns name -> error words."""
    shutil.copytree(good, root / "good")
    (root / "empty").mkdir()  # a footage folder whose frames are missing
    copy_meta(good, root / "empty", drop=["frame_pattern"])
    # frames with a stray non-image file
    stray = root / "stray"
    shutil.copytree(good / "frames", stray)
    shutil.copy(good / "meta.json", stray / "meta.json")
    (stray / "notes.docx").write_bytes(b"x")
    # a truncated frame in the middle: the video finishes with that frame skipped
    trunc = root / "trunc"
    shutil.copytree(good / "frames", trunc)
    shutil.copy(good / "meta.json", trunc / "meta.json")
    f = sorted(trunc.glob("*.png"))[50]
    f.write_bytes(f.read_bytes()[:100])
    # mixed sizes
    mixed = root / "mixed"
    shutil.copytree(good / "frames", mixed)
    shutil.copy(good / "meta.json", mixed / "meta.json")
    cv2.imwrite(str(sorted(mixed.glob("*.png"))[10]), np.zeros((10, 10), np.uint8))
    # meta.json that is not JSON, and one with a wrong type
    shutil.copytree(good / "frames", root / "notjson")
    (root / "notjson" / "meta.json").write_text("{fps: 4000")
    shutil.copytree(good / "frames", root / "wrongtype")
    copy_meta(good, root / "wrongtype", fps="fast")
    # a video with zero frames
    zero = root / "zero"
    zero.mkdir()
    (zero / "clip.avi").write_bytes(b"")
    return {"empty": "no image files", "stray": "notes.docx", "trunc": "frame",
            "mixed": "differs", "notjson": "JSON", "wrongtype": "fps", "clip": "clip.avi"}


def test_batch_survives_every_kind_of_broken_video(run_cli, copy_meta, clip, tmp_path, caplog):
    root = tmp_path / "tree"
    root.mkdir()
    expected = _broken_tree(root, clip, copy_meta)
    out = tmp_path / "out"
    code = run_cli(["analyze", root, "--recursive", "--out", out, "--workers", "2",
                 "--no-progress", "--no-overlay-video", "--overlay-frames", "0", "--no-plots"])
    assert code == 1
    report = pd.read_csv(out / "batch_report.csv").set_index("name")
    assert report.loc["good", "status"] == "done"
    assert (out / "good" / "frames.csv").is_file()
    assert report.loc["trunc", "status"] == "partial"  # results kept, frame 50 skipped
    trunc = pd.read_csv(out / "trunc" / "frames.csv")
    assert 50 not in set(trunc.frame) and len(trunc) == 159
    for name, words in expected.items():
        assert name in report.index, name
        message = report.loc[name, "message"]
        # the report names the video once, in its path column; the message says the rest
        path = report.loc[name, "path"]
        assert path not in message, (name, message)
        assert words.lower() in f"{path}: {message}".lower(), (name, message)
        assert "\n" not in message
        # a corrupt or odd-sized frame is skipped and named; the rest of the video is kept
        status = "partial" if name in ("trunc", "mixed") else "failed"
        assert report.loc[name, "status"] == status, name
    # the failure's ERROR line (on the console of a user; here in pytest's log capture)
    assert "notes.docx" in caplog.text
    # a partial video's skipped frame is said too, by its file: frame 50 of trunc
    skipped = [r.getMessage() for r in caplog.records
               if r.levelname == "WARNING" and "skipped, first:" in r.getMessage()]
    assert any(sorted((root / "trunc").glob("*.png"))[50].name in m for m in skipped), skipped


def test_empty_folder_given_directly_is_a_one_line_error(tmp_path):
    (tmp_path / "nothing").mkdir()
    # the console command in its own process: what a user's terminal shows, printed once
    done = subprocess.run([sys.executable, "-m", "tir_contact", "analyze",
                           str(tmp_path / "nothing"), "--out", str(tmp_path / "out"),
                           "--no-progress"], capture_output=True, text=True, timeout=300,
                          check=False)
    assert done.returncode == 1
    err = done.stderr.strip().splitlines()
    assert len(err) == 1 and "no image files" in err[0] and "nothing" in err[0]


def test_resume_skips_current_results_and_redoes_changed_ones(clip, tmp_path):
    src = tmp_path / "clip"
    shutil.copytree(clip, src)
    out = tmp_path / "out"
    items = find_footage([src])
    first = analyze_batch(items, out, options=FAST, workers=1, progress=False)
    assert first.ok and is_current(items[0], out)
    again = analyze_batch(items, out, options=FAST, workers=1, progress=False, resume=True)
    assert [v.status for v in again.videos] == ["resumed"]
    # the report of a resumed video keeps what its results hold
    assert again.videos[0].n_frames == first.videos[0].n_frames == 160
    (src / "meta.json").write_text((src / "meta.json").read_text() + " ")  # footage changed
    assert not is_current(items[0], out)
    third = analyze_batch(items, out, options=FAST, workers=1, progress=False, resume=True)
    assert [v.status for v in third.videos] == ["done"]
    # other analysis options or metadata values: analysed again with them, not resumed
    # (the old numbers were kept under the new options before)
    assert is_current(items[0], out, options=FAST, overrides={"mm_per_px": None})
    contrast = dataclasses.replace(FAST, contrast=0.5)
    assert not is_current(items[0], out, options=contrast)
    fourth = analyze_batch(items, out, options=contrast, workers=1, progress=False,
                           resume=True)
    assert [v.status for v in fourth.videos] == ["done"]
    summary = json.loads((out / items[0].name / "summary.json").read_text())
    assert summary["options"]["contrast"] == 0.5
    mm = summary["meta"]["mm_per_px"]
    assert is_current(items[0], out, options=contrast, overrides={"mm_per_px": mm})
    assert not is_current(items[0], out, options=contrast, overrides={"mm_per_px": 2 * mm})
    # results made under an override that is dropped now: not current either
    fifth = analyze_batch(items, out, options=contrast, overrides={"mm_per_px": 2 * mm},
                          workers=1, progress=False, resume=True)
    assert [v.status for v in fifth.videos] == ["done"]
    assert is_current(items[0], out, options=contrast, overrides={"mm_per_px": 2 * mm})
    assert not is_current(items[0], out, options=contrast)


def test_a_failure_while_writing_keeps_the_old_result(clip, tmp_path, monkeypatch):
    out = tmp_path / "out"
    analyze_video(clip, out, options=FAST)
    before = (out / clip.name / "frames.csv").read_bytes()

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr("tir_contact.plots.plot_video_results", boom)
    with pytest.raises(RuntimeError):
        analyze_video(clip, out, options=AnalysisOptions(plots=True, parquet=False))
    assert (out / clip.name / "frames.csv").read_bytes() == before
    assert [p.name for p in out.iterdir()] == [clip.name]


def test_block_that_never_leaves_gets_a_fitted_free_surface(render_clip, tmp_path):
    """A clip showing only the middle of the pass: the percentile image holds the block."""
    folder = render_clip(tmp_path / "stay", n_frames=12, center_time_s=0.0015)
    truth = pd.read_csv(folder / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame")
    assert block.in_view.all()
    res = analyze_video(folder, options=FAST)
    assert "fitted" in res.summary["reference"]["method"]
    rel = (res.frames.set_index("frame").contact_area_mm2 - block.contact_area_mm2).abs()
    # the fitted free surface is rougher than a clean reference: 5 % allowed
    assert (rel / block.contact_area_mm2).median() <= 0.05


def test_a_block_wider_than_its_pass_gets_a_fitted_free_surface(render_clip, tmp_path):
    """G0, one 20 mm element, passes 7.5 mm in 10 frames (3 m/s): its middle is covered in
    every sample, in the default view (0.1 mm/px) a band wider than the first closing
    disc, so the percentile image held it without a candidate and it was read as free
    surface (-71 %, no warning; helper-11). Truth: the renderer's area; required median
    error 2 % (the issue's target)."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "g0", preset="G0", n_frames=10, camera=CameraSettings())
    truth = pd.read_csv(folder / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame")
    assert block.in_view.all() and (block.contact_area_mm2 > 400).all()
    res = analyze_video(folder, options=FAST)
    assert "fitted" in res.summary["reference"]["method"]
    rel = res.frames.set_index("frame").contact_area_mm2 / block.contact_area_mm2 - 1
    assert rel.abs().median() <= 0.02


@pytest.mark.parametrize("darkness", [0.3, 0.5])
def test_a_static_dark_patch_wider_than_the_disc_stays_free_surface(render_clip, tmp_path,
                                                                    darkness):
    """A 12 mm (120 px) square that takes `darkness` of the light in every frame (a shadow,
    frost, a mark on the prism) while G3 passes at 3 m/s: the grown estimate finds it as it
    finds a held block, but no block holds it (the block sweeps over it), so it stays free
    surface. With every grown candidate replaced it read as contact in every frame, +19 %
    at 0.5 (the review of 4aafa86). Truth: the renderer's area; required median error 2 %."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "patch", n_frames=60, camera=CameraSettings())
    w = 120
    for png in sorted((folder / "frames").glob("*.png")):
        im = cv2.imread(str(png), cv2.IMREAD_UNCHANGED).astype(np.float32)
        y0, x0 = im.shape[0] // 2 - w // 2, im.shape[1] // 2 - w // 2
        im[y0:y0 + w, x0:x0 + w] *= 1.0 - darkness
        cv2.imwrite(str(png), np.clip(np.rint(im), 0, 255).astype(np.uint8))
    truth = pd.read_csv(folder / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame")
    res = analyze_video(folder, options=FAST)
    assert res.summary["reference"]["method"] == "percentile"
    inside = block.index[block.contact_area_mm2 > 100]
    rel = res.frames.set_index("frame").contact_area_mm2[inside] / block.contact_area_mm2[inside]
    assert (rel - 1).abs().median() <= 0.02


def test_a_following_camera_measures_the_angle_against_a_block_that_stays(render_clip,
                                                                          tmp_path):
    """A camera that follows the carrier keeps the undeformed block where it is at
    center_time_s: the angle is read against that place, not against a fixed camera's
    travel (before: 5.6 deg median error, 1.4 for 11.4 deg; helper-11). Truth: the
    renderer's angles; required median error one pixel's angle over the element height
    (0.1 mm over 6 mm: 0.95 deg), the resolution of the front edge."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "follow", n_frames=10, follow_camera=True,
                         velocity_mps=1.0, camera=CameraSettings())
    truth = pd.read_csv(folder / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame")
    res = analyze_video(folder, options=dataclasses.replace(FAST, camera="follows"))
    err = (res.frames.set_index("frame").deflection_angle_deg - block.deflection_angle_deg)
    assert err.notna().all() and err.abs().median() <= math.degrees(math.atan(0.1 / 6.0))


@pytest.mark.parametrize("center_time_s", [-0.003, 0.003])
def test_one_frame_of_a_fixed_camera_keeps_the_carriers_travel(render_clip, tmp_path,
                                                               center_time_s):
    """One frame 3 ms off center_time_s (the block 3 mm off the image centre): auto mode
    says "follows" without evidence of motion, and the angle must still be read against
    the carrier's travel (the review of c47cd8c: -19.6 and 32.8 deg for a true 7.8 while
    auto's guess pinned the block). Required: one pixel's angle (0.95 deg), as above."""
    from synthetic.footage import CameraSettings

    folder = render_clip(tmp_path / "one", n_frames=1, velocity_mps=1.0,
                         center_time_s=center_time_s, camera=CameraSettings())
    truth = pd.read_csv(folder / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame")
    res = analyze_video(folder, options=FAST)
    assert res.summary["camera"] == "follows"
    err = res.frames.set_index("frame").deflection_angle_deg - block.deflection_angle_deg
    assert err.notna().all() and err.abs().max() <= math.degrees(math.atan(0.1 / 6.0))


# with -m slow: test_side holds side-view angles to the truth and test_side_holder runs
# side views through analyze_video in the default run
@pytest.mark.slow
def test_side_view_deflection_against_ground_truth(render_clip, tmp_path):
    """Side view through the pipeline: median angle error <= 0.5 deg (required)."""
    folder = render_clip(tmp_path / "side", view="side", preset="G7")
    res = analyze_video(folder, tmp_path / "out", options=AnalysisOptions(
        overlay_video=True, overlay_frames=2, parquet=False, plots=True))
    truth = pd.read_csv(folder / "ground_truth.csv")
    el = truth[(truth.element >= 0) & truth.in_view]
    merged = el.merge(res.elements, on=["frame", "element"], suffixes=("_t", ""))
    err = (merged.deflection_angle_deg - merged.deflection_angle_deg_t).abs()
    assert err.median() <= 0.5
    assert merged.deflection_angle_deg.notna().mean() >= 0.8
    block = truth[truth.element == -1].set_index("frame")
    frames = res.frames.set_index("frame")
    empty = block.index[~block.in_view]
    assert not frames.loc[empty, "block_in_view"].astype(bool).any()
    out = tmp_path / "out" / "side"
    assert (out / "deflection.png").is_file() and (out / "overlay.avi").is_file()
    assert len(list((out / "overlays").glob("*.png"))) == 2


def test_calibrate_reads_the_analysis_output(run_cli, analysed, tmp_path):
    """`tir-contact calibrate` takes an analyze result folder as it is (meta from summary.json).

    Truth: the renderer's per-element contact_fraction over the frames with the whole block in
    view; the measured fraction must agree within 2 % (the area accuracy of the pipeline).
    """
    clip, res = analysed
    params = tmp_path / "params.json"
    code = run_cli(["calibrate", "--footage", res, "--out", params])
    assert code == 0
    doc = json.loads(params.read_text())
    frames = pd.read_csv(res / "frames.csv")
    full = frames.loc[frames.block_fully_in_view.astype(bool), "frame"]
    truth = pd.read_csv(clip / "ground_truth.csv")
    t = truth[(truth.element >= 0) & truth.frame.isin(full)]
    assert doc["contact"]["contact_fraction"] == pytest.approx(t.contact_fraction.mean(), rel=0.02)
    assert "lever_arm" in doc  # the sliding direction came from summary.json's meta


def test_side_view_with_a_camera_following_the_block(render_clip, tmp_path):
    """The block is in every frame: no clean reference; per-frame background instead."""
    folder = render_clip(tmp_path / "follow", view="side", preset="G3", n_frames=30,
                         follow_camera=True)
    res = analyze_video(folder, options=FAST)
    assert res.summary["reference"]["method"].startswith("per-frame")
    truth = pd.read_csv(folder / "ground_truth.csv")
    el = truth[(truth.element >= 0) & truth.in_view]
    merged = el.merge(res.elements, on=["frame", "element"], suffixes=("_t", ""))
    err = (merged.deflection_angle_deg - merged.deflection_angle_deg_t).abs()
    assert merged.deflection_angle_deg.notna().mean() >= 0.8
    assert err.median() <= 0.5  # the required side-view accuracy


def test_batch_on_a_dask_scheduler(clip, tmp_path):
    """--scheduler ADDRESS: the same results as a local run (needs the dask extra)."""
    distributed = pytest.importorskip("dask.distributed")
    items = find_footage([clip])
    local = analyze_batch(items, tmp_path / "local", options=FAST, workers=1, progress=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        report = analyze_batch(items, tmp_path / "dask", options=FAST,
                               scheduler=cluster.scheduler_address, progress=False)
    assert local.ok and report.ok
    a = pd.read_csv(tmp_path / "local" / clip.name / "frames.csv")
    b = pd.read_csv(tmp_path / "dask" / clip.name / "frames.csv")
    pd.testing.assert_frame_equal(a, b)


def test_a_short_pass_of_many_elements_is_measured(tmp_path):
    # G7's eight elements pass a fixed camera in 120 frames (the default view, 1 m/s).
    # Before, the noise model read the moving stripes between consecutive samples as noise
    # (42 DN for the sensor's 2.1): every pixel too noisy to measure, no contact found in
    # any frame, though the summary said the whole frame was lit. Truth: the renderer's
    # contact area; the required median error, 2 %
    from synthetic.footage import FootageSpec, render_footage

    clip = render_footage(FootageSpec(preset="G7", velocity_mps=1.0, n_frames=120),
                          tmp_path / "g7", fmt="png", progress=False)
    result = analyze_video(clip, tmp_path / "res", options=FAST)
    assert result.summary["reference"]["excluded_fraction"] < 0.01
    truth = pd.read_csv(clip / "ground_truth.csv")
    block = truth[truth.element == -1].set_index("frame")
    frames = result.frames.set_index("frame")
    inside = block.index[block.in_view & (block.contact_area_mm2 > 20)]
    assert len(inside) > 60
    rel = (frames.loc[inside, "contact_area_mm2"] / block.loc[inside, "contact_area_mm2"] - 1)
    assert rel.abs().median() <= 0.02


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"min_area_px": "4"}, "min_area_px must be an int, got '4' (str)"),
    ({"contrast": "0.9"}, "contrast must be a number or None, got '0.9' (str)"),
    ({"plots": 1}, "plots must be True or False, got 1 (int)"),
    ({"min_area_px": True}, "min_area_px must be an int, got True (bool)"),
])
def test_an_option_of_the_wrong_type_is_named(kwargs, message):
    # before: "'<' not supported between instances of 'str' and 'int'" (min_area_px), or
    # taken as it was (plots=1); numpy scalars are numbers as any
    with pytest.raises(TypeError, match=re.escape(message)):
        AnalysisOptions(**kwargs)
    AnalysisOptions(min_area_px=np.int64(4), contrast=np.float32(0.5), plots=np.bool_(True))


def test_options_as_a_dict_is_a_type_error_that_shows_the_call(tmp_path):
    # before: AttributeError: 'dict' object has no attribute 'reference_frames'
    with pytest.raises(TypeError, match=re.escape(
            "options must be an AnalysisOptions, e.g. AnalysisOptions(contrast=0.9), got dict")):
        analyze_video(tmp_path, options={"contrast": 0.9})
