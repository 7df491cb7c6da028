"""What a user's ``tir-contact analyze`` over a folder costs: default outputs and workers.

Prints, for clips of 400 frames (640 x 256 px, 8-bit PNG frame folders, G3 at 1 m/s from the
synthetic renderer), each figure the median of ``--repeats`` runs of the console command in
a fresh process (start-up and imports included, as a user meets them), the runs of the
compared settings alternating so that both see the same machine load:

* the default run against the analysis-only run (``--no-plots --no-overlay-video
  --overlay-frames 0``) over 4 clips: target <= 1.3x;
* the cost of each optional output (``--plots``, ``--overlay-video``) against the default;
* ``--workers 2`` against ``--workers 1`` over 8 clips with the default outputs: target
  >= 1.6x on a 2-core machine.

Run: ``python benchmarks/bench_batch.py [--repeats 3] [--frames 400]``
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ANALYSIS_ONLY = ["--no-plots", "--no-overlay-video", "--overlay-frames", "0"]


def render_clips(root: Path, n_clips: int, n_frames: int) -> list[Path]:
    """One rendered clip, linked into `n_clips` clip folders (same frames, own names)."""
    from synthetic.footage import FootageSpec, render_footage

    first = root / "clip_0"
    spec = FootageSpec(preset="G3", velocity_mps=1.0, n_frames=n_frames, dynamics="steady")
    render_footage(spec, first, fmt="png", progress=False)
    clips = [first]
    for i in range(1, n_clips):
        clip = root / f"clip_{i}"
        shutil.copytree(first, clip, copy_function=os.link)
        clips.append(clip)
    return clips


def run(clips: list[Path], out: Path, extra: list[str]) -> float:
    """Wall-clock seconds of one ``tir-contact analyze`` in a fresh process."""
    shutil.rmtree(out, ignore_errors=True)
    cmd = [sys.executable, "-m", "tir_contact", "analyze", *map(str, clips), "--out", str(out),
           "-q", *extra]
    t0 = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True, check=False)
    elapsed = time.perf_counter() - t0
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{done.stderr}")
    return elapsed


def paired(clips: list[Path], out: Path, settings: dict[str, list[str]],
           repeats: int) -> dict[str, float]:
    """Median seconds of each setting, the settings alternating run by run."""
    times: dict[str, list[float]] = {name: [] for name in settings}
    for _ in range(repeats):
        for name, extra in settings.items():
            times[name].append(run(clips, out, extra))
    return {name: statistics.median(t) for name, t in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--frames", type=int, default=400)
    args = ap.parse_args()
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        print(f"rendering a {args.frames}-frame clip (G3, 1 m/s, 640x256 PNG) ... ", end="",
              flush=True)
        clips = render_clips(root, 8, args.frames)
        print("done")
        out = root / "out"
        four = paired(clips[:4], out, {
            "analysis only": ["--workers", "1", *ANALYSIS_ONLY],
            "default": ["--workers", "1"],
            "default + --plots": ["--workers", "1", "--plots"],
            "default + --overlay-video": ["--workers", "1", "--overlay-video"],
        }, args.repeats)
        base = four["analysis only"]
        print(f"\n4 clips x {args.frames} frames, one worker (median of {args.repeats} "
              "alternating runs, each a fresh process):")
        for name, seconds in four.items():
            print(f"  {name:28s} {seconds:6.2f} s  {seconds / base:5.2f}x analysis only")
        verdict = "met" if four["default"] <= 1.3 * base else "NOT met"
        print(f"  target: default <= 1.3x analysis only: {verdict}")
        eight = paired(clips, out, {"--workers 1": ["--workers", "1"],
                                    "--workers 2": ["--workers", "2"]}, args.repeats)
        speedup = eight["--workers 1"] / eight["--workers 2"]
        print(f"\n8 clips x {args.frames} frames, default outputs, {cores} cores:")
        for name, seconds in eight.items():
            print(f"  {name:28s} {seconds:6.2f} s")
        print(f"  --workers 2 is {speedup:.2f}x --workers 1 (target >= 1.6x: "
              f"{'met' if speedup >= 1.6 else 'NOT met'})")


if __name__ == "__main__":
    main()
