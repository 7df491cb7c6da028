"""Cost of preparing a video (:func:`tir_contact.prepare_video`), one core.

Issue 21 item 8 asks for ``prepare_video`` under 0.2 s per video. Preparing samples frames
and finds the lit zone, the camera mode, the free surface, the noise and the area model.
In a static scene the free surface is estimated from the image, and its grey closing with
a disc wider than the contact was most of the time.

Renders (once, to a temporary folder):

* the thesis's G3 block passing a fixed 640 x 256 px camera (``bench_analyze``'s clip);
* the two imitations of real photographs (640 x 512 px, 8-bit JPEG, vignetted lit disc):
  a round pad and three points (:func:`synthetic.domain.real_photo_specs`);
* with the contact extra: the first physical draw (a block with physical real contact),
  whose free surface needs the widest closing.

Each is prepared 5 times with the package's closing and 5 times with OpenCV's grey
closing (``cv2.morphologyEx`` with the same elliptic disc: the baseline, the same values),
alternating; the best of each and their ratio are printed, and whether every clip meets
0.2 s.

Run: ``python benchmarks/bench_prepare.py``.
"""

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import tempfile
import time
import warnings
from pathlib import Path

from synthetic.domain import real_photo_specs
from synthetic.footage import FootageSpec, render_footage
from tir_contact import AnalysisOptions, _morphology
from tir_contact.io import open_footage
from tir_contact.prepare import prepare_video, resolve_footage

TARGET_S = 0.2
REPEATS = 5


def clips() -> dict[str, FootageSpec]:
    """The clips to prepare, by name."""
    out = {"G3 passing, 640 x 256": FootageSpec(preset="G3", n_frames=60, seed=3)}
    for name, spec in real_photo_specs(n_frames=8).items():
        out[f"{name}, 640 x 512 JPEG"] = spec
    try:
        from synthetic.domain import sample_physical_specs

        spec, case = sample_physical_specs(1, seed=0)[0]
        out[f"physical draw 0 ({case})"] = spec
    except ImportError:
        print("(no contact extra: the physical draw is left out)")
    return out


def best_prepare(folder: Path, opencv: bool) -> float:
    """Best wall time (s) of preparing the clip in `folder` (the reader opened each time)."""
    path, _ = resolve_footage(folder)
    opts = AnalysisOptions(overlay_frames=0, parquet=False, plots=False, overlay_video=False)
    keep = _morphology.ROWS_FROM_PX
    _morphology.ROWS_FROM_PX = 10**9 if opencv else keep
    try:
        best = float("inf")
        reader = open_footage(path)
        prepare_video(reader, path, None, opts)  # warm caches and imports
        for _ in range(REPEATS):
            t0 = time.perf_counter()
            prepare_video(reader, path, None, opts)
            best = min(best, time.perf_counter() - t0)
        return best
    finally:
        _morphology.ROWS_FROM_PX = keep


def main() -> None:
    warnings.filterwarnings("ignore")
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        print(f"{'clip':38s} {'prepare':>9s} {'OpenCV closing':>15s} {'ratio':>6s}")
        for name, spec in clips().items():
            folder = Path(tmp) / f"clip{abs(hash(name))}"
            render_footage(spec, folder, progress=False)
            ours = best_prepare(folder, opencv=False)
            base = best_prepare(folder, opencv=True)
            worst = max(worst, ours)
            print(f"{name:38s} {ours:8.3f}s {base:14.3f}s {base / ours:5.1f}x")
    print(f"slowest {worst:.3f} s; target < {TARGET_S} s per video: "
          f"{'met' if worst < TARGET_S else 'NOT met'}")


if __name__ == "__main__":
    main()
