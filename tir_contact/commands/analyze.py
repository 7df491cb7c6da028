"""``tir-contact analyze``: contact analysis of TIR and side-view footage, one video or many.

Each PATH is a footage folder or video file, or with ``--recursive`` a tree searched for
them. Results go to ``OUT/<video name>/`` (``frames.csv``, ``elements.csv``, ``regions.csv``,
Parquet copies, ``summary.json`` and overlay images; with ``--plots`` PNG plots, with
``--overlay-video`` ``overlay.avi``), written atomically. A broken video is reported and
skipped; the exit code is 1 when anything failed, 2 for bad arguments.
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

from tir_contact.commands._types import input_file, output_folder, positive_int, positive_number
from tir_contact.meta import META_FIELDS, check_overrides, option_flag

logger = logging.getLogger(__name__)

__all__ = ["DESCRIPTION", "add_arguments", "run"]

DESCRIPTION = (
    "Analyse footage (frame folders, TIFF stacks, videos, Photron MRAW, Phantom CINE) "
    "with its meta.json. Writes OUT/<video>/frames.csv, elements.csv, regions.csv, "
    "summary.json, plots and overlays. Exit code 1 when any video failed or is partial, "
    "2 for options that cannot be used."
)


def _meta_option_keys() -> list[str]:
    # container_fps describes a file's header, not the footage: meta.json only
    return [k for k, f in META_FIELDS.items() if f.kind != "object" and k != "container_fps"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``tir-contact analyze``: inputs, the analysis, metadata overrides."""
    p.add_argument("paths", nargs="+", metavar="PATH", type=Path,
                   help="footage folder or file (a tree with --recursive)")
    p.add_argument("--out", type=output_folder, required=True, metavar="DIR",
                   help="output folder")
    p.add_argument("--recursive", action="store_true", help="search the PATHs for footage")
    p.add_argument("--workers", type=positive_int, default=None, metavar="N",
                   help="local worker processes (default: all cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on an existing dask.distributed scheduler (tcp://host:8786)")
    p.add_argument("--resume", action="store_true",
                   help="skip videos whose results are complete, current and made with "
                        "the same analysis and metadata options")
    p.add_argument("--no-progress", action="store_true", help="no progress bars")
    g = p.add_argument_group("analysis")
    g.add_argument("--reference", type=input_file, default=None, metavar="IMAGE",
                   help="free-surface image (no block); default: built from the footage")
    g.add_argument("--lit-mask", type=input_file, default=None, metavar="IMAGE",
                   help="image of the frame's size, non-zero where TIR light reaches "
                        "(default: found from the footage; lit_mask.png shows it)")
    g.add_argument("--camera", choices=("auto", "fixed", "follows"), default="auto",
                   help="fixed: the block passes the camera; follows: the contact stays in "
                        "view (camera following the block, static test, single image); "
                        "default auto: detected")
    g.add_argument("--contrast", type=positive_number, default=None,
                   help="contact darkness; threshold = half of it (default: estimated)")
    g.add_argument("--min-area-px", type=positive_int, default=4,
                   help="drop contact regions smaller than this (px, default 4)")
    g.add_argument("--peak-window-mm", type=positive_number, default=1.0, metavar="MM",
                   help="length behind an element's front edge searched for the front-edge "
                        "pressure peak (TIR; mm, default 1; at most half the contact)")
    g.add_argument("--overlay-frames", type=int, default=4, metavar="N",
                   help="overlay images per video (default 4, 0: none)")
    g.add_argument("--overlay-video", action=argparse.BooleanOptionalAction, default=False,
                   help="write overlay.avi, the footage with what was found drawn on it "
                        "(default: off; it costs about as much as the analysis)")
    g.add_argument("--plots", action=argparse.BooleanOptionalAction, default=False,
                   help="write PNG plots of each video's results over time (default: off)")
    m = p.add_argument_group(
        "metadata", "override or give meta.json values (see docs/formats.md)"
    )
    for key in _meta_option_keys():
        field = META_FIELDS[key]
        m.add_argument(option_flag(key), dest="meta__" + key.replace(".", "__"),
                       default=None, metavar="X",
                       help=f"{field.description} ({key})".replace("%", "%%"))


def run(args: argparse.Namespace) -> int:
    """Run the analysis; returns the exit code (1 when any video failed; options or
    footage that cannot be used are raised as errors, exit code 2)."""
    # the analysis is imported when the command runs: 'tir-contact analyze --help' stays fast
    from tir_contact.analyze import AnalysisOptions
    from tir_contact.batch import analyze_batch, find_footage

    # a metadata option that cannot be used is a usage error (exit 2), found before any
    # video is read, not one failure per video
    overrides = check_overrides({
        key: getattr(args, "meta__" + key.replace(".", "__"))
        for key in _meta_option_keys()
    })
    options = AnalysisOptions(
        reference=str(args.reference) if args.reference else None,
        lit_mask=str(args.lit_mask) if args.lit_mask else None,
        camera=args.camera,
        contrast=args.contrast,
        min_area_px=args.min_area_px,
        peak_window_mm=args.peak_window_mm,
        overlay_frames=max(0, args.overlay_frames),
        overlay_video=args.overlay_video,
        plots=args.plots,
    )
    footage = find_footage(args.paths, recursive=args.recursive)
    progress = False if args.no_progress else None
    report = analyze_batch(footage, args.out, overrides=overrides or None, options=options,
                           workers=args.workers, scheduler=args.scheduler,
                           resume=args.resume, progress=progress)
    counts: dict[str, int] = {}
    for v in report.videos:
        counts[v.status] = counts.get(v.status, 0) + 1
    # each failure and warning was printed once as the video finished (ERROR / WARNING)
    summary = ", ".join(f"{n} {s}" for s, n in sorted(counts.items()))
    warned = sum(1 for v in report.videos if v.warnings)
    if warned:
        summary += f"; {warned} with warnings (see above and batch_report.csv)"
    print(f"analysed {len(report.videos)} video(s) into {args.out}: {summary}")
    return 0 if report.ok else 1
