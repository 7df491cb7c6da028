"""What ``report.html`` costs on a large batch, and what black footage costs (issue 22).

Prints, each figure the median of ``--repeats`` runs:

* the report of ``--clips`` clips (default 200) built from scratch (thumbnails and plots
  made) and rebuilt (they are kept): target < 10 s from scratch; per clip against the
  analysis of one such clip in this run (the baseline);
* the page: its size, the thumbnails' total size, and with Debian's chromium and Selenium
  installed the time until the page is loaded (``loadEventEnd``, lazy images not counted:
  they load as they scroll into view);
* all-black footage against a normal clip of the same size and length (40 frames), the
  analysis alone: target <= 1.5x (it was 30x: the free-surface closing grew to twice the
  image, every black pixel taken for contact).

The 200 result folders are one analysed clip (400 frames, 640 x 256 px, the default camera;
four overlay images) copied with hard links, each under its own name.

Run: ``python benchmarks/bench_report.py [--clips 200] [--repeats 3]``
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import tifffile


def analysed_clip(root: Path, n_frames: int) -> tuple[Path, float]:
    """Render and analyse one clip; its result folder and the analysis's seconds."""
    from synthetic.footage import FootageSpec, render_footage
    from tir_contact.analyze import AnalysisOptions, analyze_video

    spec = FootageSpec(preset="G3", velocity_mps=1.0, n_frames=n_frames, dynamics="steady")
    render_footage(spec, root / "clip", fmt="png", progress=False)
    t0 = time.perf_counter()
    analyze_video(root / "clip", root / "one", options=AnalysisOptions())
    return root / "one" / "clip", time.perf_counter() - t0


def batch_folder(result: Path, out: Path, n: int) -> None:
    """`n` result folders, each a hard-linked copy of `result`, and a batch report."""
    out.mkdir()
    videos = []
    for i in range(n):
        shutil.copytree(result, out / f"clip_{i:03d}", copy_function=os.link)
        videos.append({"name": f"clip_{i:03d}", "path": f"clips/clip_{i:03d}",
                       "status": "done", "message": "", "n_frames": 400,
                       "skipped_frames": 0, "seconds": 1.0, "warnings": []})
    (out / "batch_report.json").write_text(json.dumps({"ok": True, "videos": videos}))


def load_time_s(page: Path) -> float | None:
    """Seconds until chromium fires the page's load event, None without a browser."""
    chromium, driver_path = shutil.which("chromium"), shutil.which("chromedriver")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.options import Options
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        return None
    if chromium is None or driver_path is None:
        return None
    options = Options()
    options.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1200,900"):
        options.add_argument(arg)
    driver = webdriver.Chrome(options=options, service=Service(driver_path))
    try:
        driver.get(page.as_uri())
        timing = driver.execute_script(
            "var t = performance.timing; return [t.navigationStart, t.loadEventEnd];")
        return (timing[1] - timing[0]) / 1e3
    finally:
        driver.quit()


def black_against_normal(root: Path, repeats: int) -> tuple[float, float]:
    """Median analysis seconds of a 40-frame black clip and of a normal one, alternating."""
    from synthetic.footage import FootageSpec, render_footage
    from tir_contact.analyze import AnalysisOptions, analyze_video
    from tir_contact.io import open_footage

    spec = FootageSpec(preset="G3", velocity_mps=1.0, n_frames=40, dynamics="steady")
    render_footage(spec, root / "normal", fmt="png", progress=False)
    with open_footage(root / "normal" / "frames") as reader:
        shape = reader.get_frame(0).shape
    black = root / "black"
    black.mkdir()
    tifffile.imwrite(black / "black.tif", np.zeros((40, *shape), np.uint8))
    meta = json.loads((root / "normal" / "meta.json").read_text())
    meta.pop("frame_pattern", None)
    (black / "meta.json").write_text(json.dumps(meta))
    fast = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0, parquet=False)
    times: dict[str, list[float]] = {"normal": [], "black": []}
    for _ in range(repeats):
        for name, path in (("normal", root / "normal"), ("black", black / "black.tif")):
            t0 = time.perf_counter()
            analyze_video(path, options=fast)
            times[name].append(time.perf_counter() - t0)
    return statistics.median(times["black"]), statistics.median(times["normal"])


def main() -> None:
    from tir_contact.report import write_report

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--clips", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--frames", type=int, default=400)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        result, analysis_s = analysed_clip(root, args.frames)
        fresh, again = [], []
        for k in range(args.repeats):
            out = root / f"batch_{k}"
            batch_folder(result, out, args.clips)
            t0 = time.perf_counter()
            page = write_report(out)
            fresh.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            write_report(out)
            again.append(time.perf_counter() - t0)
        build = statistics.median(fresh)
        thumbs = sum(p.stat().st_size for p in (out / "report_files").rglob("*.jpg"))
        print(f"report of {args.clips} clips: {build:.2f} s from scratch (target < 10 s), "
              f"{statistics.median(again):.2f} s rebuilt")
        print(f"  per clip {build / args.clips * 1e3:.1f} ms = "
              f"{build / args.clips / analysis_s:.3f}x the analysis of one clip "
              f"({analysis_s:.2f} s, {args.frames} frames, default outputs)")
        print(f"  page {page.stat().st_size / 1e3:.0f} kB, thumbnails {thumbs / 1e6:.1f} MB "
              f"({thumbs / 3 / args.clips / 1e3:.1f} kB each)")
        load = load_time_s(page)
        print("  chromium: " + (f"loaded in {load:.2f} s" if load is not None
                                else "not installed (apt-get install chromium "
                                     "chromium-driver; pip install selenium)"))
        black, normal = black_against_normal(root, args.repeats)
        print(f"black footage, 40 frames: {black:.2f} s against {normal:.2f} s for a normal "
              f"clip: {black / normal:.2f}x (target <= 1.5x)")


if __name__ == "__main__":
    main()
