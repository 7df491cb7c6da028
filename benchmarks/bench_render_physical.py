"""Rendering cost of physical real contact against the solid block, one core, no disk.

Renders the G3 block crossing a 640 x 256 px view (400 frames, 0.1 mm/px, steady state)
with ``real_contact="solid"`` (the baseline, measured in the same run) and with
``real_contact="physical"`` (each element's rough face in the contact solved by tamaas at
its cell's pressure level, precomputed once and translated per frame), and prints the wall
time of each, the physical clip's one-time precompute (contact solves and row means) and
per-frame time, and the ratio physical / solid. Target: the physical clip under 30 s.

Run: ``python benchmarks/bench_render_physical.py [n_frames]`` (needs the contact extra).
"""

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys
import time

from synthetic import footage
from synthetic._physical import scene_contact_tile

N_FRAMES = int(sys.argv[1]) if len(sys.argv) > 1 else 400


def run(real_contact: str) -> tuple[float, float]:
    """Wall time of the whole clip and of its first frame (set-up included), s."""
    spec = footage.FootageSpec(
        preset="G3", real_contact=real_contact, dynamics="steady", settle_s=0.004,
        n_frames=N_FRAMES, seed=11,
    )
    footage._simulate.cache_clear()
    scene_contact_tile.cache_clear()
    t0 = time.perf_counter()
    frames = footage.iter_frames(spec)
    next(frames)
    first = time.perf_counter() - t0
    for _ in frames:
        pass
    return time.perf_counter() - t0, first


def main() -> None:
    solid, solid_first = run("solid")
    physical, physical_first = run("physical")
    per_frame = (physical - physical_first) / max(N_FRAMES - 1, 1)
    print(f"{N_FRAMES} frames 640 x 256, G3 steady, one core")
    print(f"  solid:    {solid:6.2f} s (first frame incl. model {solid_first:.2f} s)")
    print(
        f"  physical: {physical:6.2f} s (first frame incl. contact solves {physical_first:.2f} s,"
        f" then {1e3 * per_frame:.1f} ms/frame)"
    )
    print(f"  ratio physical / solid: {physical / solid:.1f}x; target physical < 30 s: "
          f"{'met' if physical < 30 else 'NOT met'}")


if __name__ == "__main__":
    main()
