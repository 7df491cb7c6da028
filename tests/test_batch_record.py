"""The batch record is always true (issue 22): each case is a defect seen once, built here.

Ctrl-C during a parallel batch stops it at once and the report lists what was written; a
container cut short is not ``complete``; each warning and failure is printed once; a CSV
parse error says where as "data row N (file line M)"; black footage does not grow the
free-surface closing to the whole image.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import tifffile

from synthetic.measurements import make_steady_table, write_table
from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.batch import find_footage, is_current
from tir_contact.io import open_footage
from tir_contact.reference import free_surface

QUIET = ["--no-plots", "--overlay-frames", "0"]
FAST = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0, parquet=False)


@pytest.fixture(scope="module")
def clip(render_clip, tmp_path_factory) -> Path:
    """A small TIR clip (G3 at 3 m/s, 80 frames)."""
    return render_clip(tmp_path_factory.mktemp("clips") / "G3", n_frames=80)


def _cli(*argv: str | Path, **kw) -> subprocess.Popen:
    """``tir-contact ARGV`` in its own process (and process group, as a shell job)."""
    return subprocess.Popen([sys.executable, "-m", "tir_contact", *map(str, argv)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, **kw)


def _result_folders(out: Path) -> set[str]:
    """The clips' result folders (not the report's ``report_files``)."""
    return {p.name for p in out.iterdir()
            if p.is_dir() and not p.name.startswith(".") and p.name != "report_files"}


# ten clips through a subprocess batch, interrupted (about 5 s each): with -m slow; the default
# run holds the batch's report and atomic writes (test_tiff_cut_short..., test_analyze)
@pytest.mark.slow
@pytest.mark.skipif(os.name != "posix", reason="sends SIGINT to a process group (POSIX)")
@pytest.mark.parametrize("target", ["group", "main"])
def test_ctrl_c_stops_at_once_and_the_report_lists_what_was_written(clip, tmp_path, target):
    # ten copies of the clip: each takes about as long as the interrupt takes to arrive
    tree = tmp_path / "clips"
    for i in range(10):
        shutil.copytree(clip, tree / f"c{i:02d}")
    out = tmp_path / "out"
    proc = _cli("analyze", tree, "--recursive", "--out", out, "--workers", "2", *QUIET)
    try:
        deadline = time.monotonic() + 120
        while not (out.is_dir() and _result_folders(out)) and time.monotonic() < deadline:
            time.sleep(0.02)
        at_signal = _result_folders(out)
        assert at_signal, "no clip finished in 120 s"
        # a terminal's Ctrl-C reaches the whole process group; kill -INT only the main one
        if target == "group":
            os.killpg(proc.pid, signal.SIGINT)
        else:
            os.kill(proc.pid, signal.SIGINT)
        time.sleep(0.05)
        os.kill(proc.pid, signal.SIGINT)  # an impatient second Ctrl-C: the clean-up goes on
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    written = _result_folders(out)
    time.sleep(1.5)  # nothing goes on writing once the command has returned
    assert _result_folders(out) == written
    # no new clip was started: at most the two in the workers' hands were finished
    assert len(written) <= len(at_signal) + 2
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]  # no temporaries
    report = pd.read_csv(out / "batch_report.csv")
    assert sorted(report["name"]) == [f"c{i:02d}" for i in range(10)]
    status = dict(zip(report["name"], report["status"], strict=True))
    assert {n for n, s in status.items() if s == "done"} == written
    assert {n for n, s in status.items() if s != "done"} == {
        n for n, s in status.items() if s == "interrupted"}
    assert len(written) < 10  # the interrupt came before the end
    assert json.loads((out / "batch_report.json").read_text())["ok"] is False
    page = (out / "report.html").read_text(encoding="utf-8")  # written on the way out too
    assert page.count(">interrupted</td>") == 10 - len(written)


@pytest.fixture
def cut_stack(clip, copy_meta, tmp_path) -> Path:
    """The clip's first 40 frames as a multi-page TIFF cut short after 60 % of its bytes."""
    folder = tmp_path / "stack"
    folder.mkdir()
    with open_footage(clip / "frames") as reader:
        frames = np.stack([reader.get_frame(i) for i in range(40)])
    tifffile.imwrite(folder / "clip.tif", frames)
    copy_meta(clip, folder, drop=["frame_pattern"])
    path = folder / "clip.tif"
    with open(path, "r+b") as f:
        f.truncate(int(path.stat().st_size * 0.6))
    return path


def test_tiff_cut_short_is_not_complete_and_is_printed_once(cut_stack, tmp_path):
    out = tmp_path / "out"
    proc = _cli("analyze", cut_stack, "--out", out, "--workers", "1", *QUIET)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 1, err
    summary = json.loads((out / "clip" / "summary.json").read_text())
    assert summary["lost_frames"] and summary["complete"] is False
    assert not is_current(find_footage([cut_stack])[0], out)
    # the reader says it as it opens the file; nothing says it again
    assert sum("cut short" in line or "lost" in line for line in err.splitlines()) == 1, err


def test_skipped_frames_are_not_complete(clip, copy_meta, tmp_path):
    folder = tmp_path / "frames"
    shutil.copytree(clip / "frames", folder)
    copy_meta(clip, folder, drop=["frame_pattern"])
    bad = sorted(folder.glob("*.png"))[30]
    bad.write_bytes(bad.read_bytes()[:200])  # a PNG cut short: that frame is skipped
    result = analyze_video(folder, tmp_path / "out", options=FAST)
    summary = json.loads((result.out_dir / "summary.json").read_text())
    assert len(summary["skipped_frames"]) == 1 and summary["complete"] is False


def test_bad_meta_json_is_printed_once(clip, tmp_path):
    broken = tmp_path / "broken"
    shutil.copytree(clip, broken)
    text = (broken / "meta.json").read_text()
    (broken / "meta.json").write_text(text.replace('"fps":', '"fps"', 1))
    proc = _cli("analyze", broken, "--out", tmp_path / "out", "--workers", "1", *QUIET)
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 1
    assert (out + err).count("not valid JSON") == 1, out + err
    assert "1 failed" in out


def test_unclosed_quote_is_named_by_data_row_and_file_line(run_cli, tmp_path, capsys):
    grid = {"velocities_mps": [1, 3, 5], "pressures_bar": [1, 2.5],
            "temperatures_C": [-6, -3], "humidities_pct": [40],
            "salinities_pct": [0.0], "n_sipes": [0]}
    path = write_table(make_steady_table(grid, rng=1), tmp_path / "steady.csv")
    lines = path.read_text().splitlines()
    header = next(i for i, line in enumerate(lines) if line and not line.startswith("#"))
    row = 9  # data row 9: file line header + 1 + 9 (1-based)
    lines[header + row] = '"' + lines[header + row]  # a quote opened and never closed
    path.write_text("\n".join(lines) + "\n")
    code = run_cli(["discrepancy", "--steady", path, "--out", tmp_path / "d"])
    assert code == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert f"data row {row} (file line {header + 1 + row})" in err[0], err[0]
    assert "never closed" in err[0] and "EOF" not in err[0]


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_black_footage_keeps_the_starting_closing():
    # a black image has no light to lose: no contact candidate, so no reason to grow the
    # closing disc (before: every pixel a candidate, the disc grown to twice the image,
    # 30 times the time of a normal clip; benchmarks/bench_report.py times it); nor any
    # texture to measure (before: the median of no values, a RuntimeWarning and NaN)
    fs = free_surface(np.zeros((128, 320), np.float32), size_px=101)
    assert fs.size_px == 101
    assert not fs.candidates.any()
    assert np.all(fs.image == 0)
    assert fs.texture_sigma == 0.0 and fs.texture_corr_px == 1.0
