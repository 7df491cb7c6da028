"""Broken footage is never a silent wrong result: each case is built here and must be reported.

A container cut short is ``partial`` with the lost frames named; a frame folder with a gap in
its numbering keeps the gap (times follow the file numbers); black, saturated or contact-free
footage gets a warning in ``summary.json``, the batch report and on the console; temporaries
of a killed run go on the next run; workers never outlive the batch.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import tifffile

from tir_contact._outdir import remove_stale_temporaries, temporary_name
from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.io import open_footage

FAST = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0, parquet=False)
QUIET = ["--workers", "1", "--no-plots", "--overlay-frames", "0"]


@pytest.fixture(scope="module")
def clip(render_clip, tmp_path_factory) -> Path:
    """A small TIR clip (G3 at 3 m/s, 80 frames) with its ground truth."""
    return render_clip(tmp_path_factory.mktemp("clips") / "G3", n_frames=80)


@pytest.fixture
def stack(copy_meta):
    """``stack(clip, folder)``: the clip's first 40 frames as one uncompressed multi-page TIFF
    beside its meta.json; returns the file and the frames."""

    def write(clip: Path, folder: Path) -> tuple[Path, np.ndarray]:
        folder.mkdir()
        frames = np.stack([open_footage(clip / "frames").get_frame(i) for i in range(40)])
        tifffile.imwrite(folder / "clip.tif", frames)
        copy_meta(clip, folder, drop=["frame_pattern"])
        return folder / "clip.tif", frames

    return write


@pytest.mark.parametrize("keep", [0.99, 0.6])
def test_tiff_cut_short_reads_every_intact_frame_and_names_the_lost(
    run_cli, stack, clip, tmp_path, keep
):
    path, frames = stack(clip, tmp_path / "stack")
    size = path.stat().st_size
    with open(path, "r+b") as f:
        f.truncate(int(size * keep))
    # truth from the layout: tifffile writes the pixel data of all pages one after another
    # from the first page's data offset, the page directories after them
    with tifffile.TiffFile(tmp_path / "stack" / "clip.tif") as tif:
        offset = int(tif.series[0].dataoffset)
    intact = min(40, (int(size * keep) - offset) // frames[0].nbytes)
    with open_footage(path) as reader:
        assert len(reader) == intact
        assert reader.lost_frames == tuple(range(intact, 40))
        for i in (0, intact - 1):
            np.testing.assert_array_equal(reader.get_frame(i), frames[i])  # exact pixels
    out = tmp_path / "out"
    code = run_cli(["analyze", path, "--out", out, *QUIET])
    assert code == 1  # partial: a batch with lost frames is not ok
    report = pd.read_csv(out / "batch_report.csv")
    assert report.loc[0, "status"] == "partial"
    assert f"{40 - intact} frame(s) lost" in report.loc[0, "message"]
    summary = json.loads((out / "clip" / "summary.json").read_text())
    assert summary["lost_frames"] == list(range(intact, 40))
    assert any("cut short" in w for w in summary["warnings"])
    assert summary["n_frames_analysed"] == intact


def test_gap_in_the_frame_numbers_is_kept(copy_meta, clip, tmp_path):
    gap = tmp_path / "gap"
    gap.mkdir()
    fps = json.loads((clip / "meta.json").read_text())["fps"]
    for f in sorted((clip / "frames").glob("*.png")):
        number = int(f.stem.rsplit("_", 1)[1])
        if not 10 <= number <= 19:
            (gap / f.name).write_bytes(f.read_bytes())
    copy_meta(clip, gap, drop=["frame_pattern"])
    with open_footage(gap) as reader:
        assert reader.frame_numbers[9:11].tolist() == [9, 20]
    res = analyze_video(gap, tmp_path / "out", options=FAST)
    frames = res.frames.set_index("frame")
    assert 15 not in frames.index and 20 in frames.index
    # times from the file numbers: exact up to the float division
    np.testing.assert_allclose(frames["time_s"].to_numpy(), frames.index.to_numpy() / fps,
                               rtol=1e-12)
    assert res.summary["frame_gaps"] == [{"after": 9, "before": 20, "missing": 10}]
    assert any("10 frame number(s) missing" in w for w in res.summary["warnings"])
    # the deflection (which needs the true time of each frame) is as right as without a gap
    full = analyze_video(clip, tmp_path / "out_full", options=FAST)
    truth = pd.read_csv(clip / "ground_truth.csv")
    el = truth[(truth.element >= 0) & truth.in_view]

    def error(elements: pd.DataFrame) -> float:
        m = el.merge(elements, on=["frame", "element"], suffixes=("_t", ""))
        m = m[m.frame >= 20]
        return float((m.deflection_angle_deg - m.deflection_angle_deg_t).abs().median())

    # same frames and times after the gap; the reference is sampled from other frames, which
    # moves the threshold a little (0.0002 deg seen); numbering by position instead would put
    # frame 20 at the time of frame 10, 0.6 mm of carrier travel, many degrees off
    assert error(res.elements) <= error(full.elements) + 0.05


# black footage in the default run; saturated with -m slow (each a subprocess, about 2.5 s)
@pytest.mark.parametrize(("value", "words"), [
    (0, "no lit field"), pytest.param(255, "saturated", marks=pytest.mark.slow)])
def test_black_or_white_footage_is_warned_about(tmp_path, value, words):
    folder = tmp_path / "plain"
    folder.mkdir()
    tifffile.imwrite(folder / "clip.tif", np.full((20, 64, 96), value, np.uint8))
    (folder / "meta.json").write_text(json.dumps({"fps": 1000, "mm_per_px": 0.1,
                                                   "sliding_direction": "left"}))
    out = tmp_path / "out"
    # the console command in its own process: what a user's terminal shows
    done = subprocess.run([sys.executable, "-m", "tir_contact", "analyze",
                           str(folder / "clip.tif"), "--out", str(out), *QUIET],
                          capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr  # analysed, but not silently
    summary = json.loads((out / "clip" / "summary.json").read_text())
    assert any(words in w for w in summary["warnings"])
    assert any("no contact found in any of the 20 frames" in w for w in summary["warnings"])
    report = pd.read_csv(out / "batch_report.csv")
    assert words in report.loc[0, "warnings"]
    assert words in done.stderr and "Traceback" not in done.stderr


def _zone_mm2(res, width_px: int, height_px: int, mm_per_px: float) -> float:
    """The lit zone found, mm2 (summary.json: its share of the frame)."""
    return res.summary["lit_fraction"] * width_px * height_px * mm_per_px ** 2


def test_footage_without_contact_is_warned_about(render_clip, tmp_path):
    # the block passes the view centre 1 s after the clip: every frame is free ice
    folder = render_clip(tmp_path / "free", n_frames=12, center_time_s=1.0)
    truth = pd.read_csv(folder / "ground_truth.csv")
    assert not truth.in_view.any()
    res = analyze_video(folder, options=FAST)
    warnings = res.summary["warnings"]
    # the areas are then the darkness unmixed alone: the warning gives their medians
    med = res.frames[["contact_area_mm2", "contact_area_low_mm2",
                      "contact_area_high_mm2"]].median()
    assert warnings[-2] == (
        f"no contact found in any of the 12 frames analysed (reference: "
        f"{res.summary['reference']['method']}): contact_area_mm2 is the darkness unmixed "
        f"alone (median {med.iloc[0]:.3g} mm2, its bar 0-{med.iloc[2]:.3g} mm2)")
    # and that bar holds the truth, no contact
    assert med.iloc[1] == 0.0 and med.iloc[2] > med.iloc[0]
    # nothing moves: the free ice could as well be a contact over the whole lit zone
    # (test_static_contact_over_the_lit_zone_is_warned_about), and the warning says so
    assert res.summary["camera"] == "follows"
    assert warnings[-1].startswith("nothing moves and no contact is resolved")
    # and the measurement says what it assumed: no resolved contact, so any faint dark
    # spot is measured against an assumed full-contact darkness, its bar reaching zero
    assert len(warnings) == 3 and "assumed full-contact darkness" in warnings[0]
    assert (res.frames["contact_area_low_mm2"] == 0).all()
    # the bar spans both readings: no contact, and a contact over the whole lit zone found
    meta = json.loads((folder / "meta.json").read_text())
    zone_mm2 = _zone_mm2(res, meta["width_px"], meta["height_px"], meta["mm_per_px"])
    assert np.allclose(res.frames["contact_area_high_mm2"], zone_mm2, rtol=1e-6)


@pytest.mark.parametrize(("pad_radius_mm", "hint"), [(6.0, True), (1.0, False)])
def test_static_contact_over_the_lit_zone_is_warned_about(render_clip, tmp_path,
                                                          pad_radius_mm, hint):
    """A static pad larger than the lit disc leaves no free surface at the lit level in
    view: its contact, at a quarter of the light, is read as the free surface (or as the
    unlit outside), and nothing in one image tells them apart (the seed-3 domain draws
    34, 105: 100 % low, "no contact found"). The analysis cannot measure it, but it must
    not stay silent: it names the case and the two ways out. A pad inside the disc is
    found (within 5 %: the domain's static pads read 0.4 % in the median), with no such
    hint."""
    from synthetic.footage import CameraSettings

    # a 6.2 x 3.8 mm view, its lit disc 3.8 mm across (half the frame) with a soft rim
    cam = CameraSettings(mm_per_px=0.03, width_px=208, height_px=128, lit_shape="disc",
                         lit_fraction=0.5, lit_rim_mm=0.5)
    folder = render_clip(tmp_path / "pad", n_frames=8, scene="round_pad",
                         pad_radius_mm=pad_radius_mm, camera=cam)
    truth = pd.read_csv(folder / "ground_truth.csv")
    assert (truth[truth.element == -1].contact_area_mm2 > 0).all()
    res = analyze_video(folder, options=FAST)
    error = (res.frames["contact_area_mm2"].median()
             / truth[truth.element == -1].contact_area_mm2.median() - 1.0)
    said = [w for w in res.summary["warnings"] if w.startswith("nothing moves")]
    true_mm2 = truth[truth.element == -1].set_index("frame").contact_area_mm2
    frames = res.frames.set_index("frame").reindex(true_mm2.index)
    zone_mm2 = _zone_mm2(res, cam.width_px, cam.height_px, cam.mm_per_px)
    if hint:
        # read as free surface: a few dark specks at most (0.10 of 11.6 mm2 seen)
        assert error < -0.9 and len(said) == 1
        assert "--reference" in said[0] and "--lit-mask" in said[0]
        # the other reading the warning names, a contact over the whole lit zone found (and
        # the rim band past its edge, 2 px: the edge's tolerance), is the error bar's high
        # end: the truth (the pad over the lit disc, 12.0 mm2) lies in the bar in every
        # frame, where it lay 60 times above its high end (0.19 mm2) before
        assert "error bar reaches up to the whole lit zone" in said[0]
        assert (frames.contact_area_high_mm2 >= zone_mm2 - 1e-9).all()
        assert ((frames.contact_area_low_mm2 <= true_mm2)
                & (true_mm2 <= frames.contact_area_high_mm2)).all(), (frames, true_mm2)
    else:
        assert abs(error) < 0.05 and said == []
        # found contact keeps its own bar (well below the lit zone: the pad covers 2.6 % of
        # the frame, the disc half of it)
        assert (frames.contact_area_high_mm2 < 0.5 * zone_mm2).all()


def test_stale_temporaries_go_and_live_ones_stay(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    dead_pid = int(dead.stdout)
    stale = [out / f".G3.{dead_pid}-0123abcd.partial", out / ".G3.0123abcd.old",
             out / ".overlay-k2j4_x9z.avi", out / f".overlay.{dead_pid}-89abcdef.avi"]
    stale[0].mkdir()
    (stale[0] / "frames.csv").write_text("x")
    stale[1].mkdir()
    stale[2].write_bytes(b"\0" * 100)
    stale[3].write_bytes(b"\0" * 100)
    live = out / temporary_name("G7", ".partial")  # this process is alive
    live.mkdir()
    keep = [out / ".hidden_notes.txt", out / "G3"]
    keep[0].write_text("mine")
    keep[1].mkdir()
    removed = remove_stale_temporaries(out)
    assert sorted(removed) == sorted(stale)
    assert not any(p.exists() for p in stale)
    assert live.exists() and all(p.exists() for p in keep)


def test_the_next_run_removes_what_a_killed_run_left(run_cli, clip, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    leftover = out / ".overlay-abcd1234.avi"  # the name an older version gave it
    leftover.write_bytes(b"\0" * 1000)
    assert run_cli(["analyze", clip, "--out", out, *QUIET]) == 0
    assert not leftover.exists()
    assert sorted(p.name for p in out.iterdir()) == ["G3", "batch_report.csv",
                                                      "batch_report.json", "report.html",
                                                      "report_files"]


def _descendants(pid: int) -> set[int]:
    """Processes below `pid` (Linux /proc)."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(entry.name))
    out: set[int] = set()
    todo = [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.add(child)
            todo.append(child)
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc (Linux)")
# fork in the default run; the fork server (a parent with threads, about 3 s) with -m slow
@pytest.mark.parametrize("method", ["fork", pytest.param("forkserver", marks=pytest.mark.slow)])
def test_workers_die_with_the_batch(tmp_path, method):
    # the batch's own pool set-up (start method and initialiser), given work that would
    # last a minute; the parent is then killed with SIGKILL, as a user's kill -9 does.
    # A thread running in the parent makes the batch use a fork server instead of fork.
    thread = "threading.Thread(target=time.sleep, args=(300,), daemon=True).start()"
    script = textwrap.dedent(f"""
        import os, sys, threading, time
        from concurrent.futures import ProcessPoolExecutor
        from tir_contact import _workers
        {thread if method == "forkserver" else ""}
        context = _workers.context()
        assert context.get_start_method() == {method!r}, context.get_start_method()
        with ProcessPoolExecutor(2, mp_context=context,
                                 initializer=_workers.init_worker,
                                 initargs=(os.getpid(),)) as pool:
            futures = [pool.submit(time.sleep, 60) for _ in range(4)]
            print("ready", flush=True)
            time.sleep(120)
    """)
    parent = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                              text=True)
    try:
        assert parent.stdout.readline().strip() == "ready"
        deadline = time.monotonic() + 60
        while len(_descendants(parent.pid)) < 2 and time.monotonic() < deadline:
            time.sleep(0.1)  # two workers (and the fork server, where one is used)
        below = _descendants(parent.pid)
        assert len(below) >= 2
    finally:
        parent.send_signal(signal.SIGKILL)
        parent.wait()
    # the watch interval is 0.5 s; 20 s allows for a loaded machine
    deadline = time.monotonic() + 20
    while any(_alive(p) for p in below) and time.monotonic() < deadline:
        time.sleep(0.1)
    left = [p for p in below if _alive(p)]
    for p in left:  # do not leave them behind even when the test fails
        os.kill(p, signal.SIGKILL)
    assert not left


def test_clip_folder_with_a_broken_meta_json_names_the_json_error(run_cli, clip, tmp_path):
    broken = tmp_path / "broken"
    shutil.copytree(clip, broken)
    text = (broken / "meta.json").read_text()
    (broken / "meta.json").write_text(text.replace('"fps":', '"fps"', 1))  # a colon lost
    out = tmp_path / "out"
    assert run_cli(["analyze", broken, "--out", out, *QUIET]) == 1
    message = pd.read_csv(out / "batch_report.csv").loc[0, "message"]
    assert message.startswith("meta.json: not valid JSON (Expecting ':' delimiter at line")


def test_footage_too_noisy_to_measure_is_warned_about(render_clip, tmp_path):
    # read noise 6 DN at white level 0.3 (free surface about 76 DN): the darkness noise is
    # sqrt(36 + shot) / 76, about 0.085 (the renderer's figure; below), and 5 times it
    # passes the contact threshold on most of the zone. Before, 0 mm2 against a true
    # 100 mm2 without a word about noise (helper-11)
    from synthetic.footage import CameraSettings

    camera = CameraSettings(mm_per_px=0.2, width_px=320, height_px=128, read_noise_dn=6.0,
                            white_level=0.3)
    folder = render_clip(tmp_path / "noisy", n_frames=10, camera=camera)
    res = analyze_video(folder, options=FAST)
    lit = res.summary["lit_zone"]
    share = 1.0 - lit["measured_fraction"] / lit["fraction"]
    said = [w for w in res.summary["warnings"] if "too noisy to measure" in w]
    assert share > 0.5 and len(said) == 1
    assert said[0].startswith(f"{100 * share:.0f} % of the lit zone is too noisy")
    # the noise it states is the renderer's: read noise and shot noise (255 DN over a full
    # well of 16000 e-) at the free level, which the default light field (gradient 0.15,
    # vignetting 0.2) holds between 0.68 and 1 times the white level: the median between
    # the noise at the white level and at 0.65 of it
    level = camera.white_level * 255
    at_white = np.sqrt(6.0 ** 2 + level * 255 / camera.full_well_e) / level
    stated = float(said[0].split("darkness noise ")[1].split(",")[0])
    assert at_white <= stated <= at_white / 0.65


def test_a_clean_clip_says_nothing_of_noise(clip):
    res = analyze_video(clip, options=FAST)
    assert not any("too noisy" in w for w in res.summary["warnings"])
