"""``tir-contact demo``: the main job on data the toolkit makes itself.

The command parses its options, calls :func:`tir_contact.demo.run_demo` and prints the
result's report (the hidden-effect story first, then the model, the rig, the footage and the
stick-slip case). :func:`run_demo` and :class:`DemoResult` are re-exported here for code that
imported them from this module.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tir_contact.commands._types import output_folder
from tir_contact.demo import RUNS_RANGE, DemoResult, run_demo

__all__ = ["DESCRIPTION", "DemoResult", "add_arguments", "run", "run_demo"]

DESCRIPTION = (
    "Hide an effect the base model lacks in synthetic rig measurements and let the "
    "discrepancy workflow find it; then compute the friction model's Fig. 4.26 and Table 4.6 "
    "comparison, evaluate synthetic rig runs and footage against their truth and run the "
    "stick-slip case. Writes CSV, PNG and JSON files."
)


def _runs(text: str) -> int:
    """argparse type of ``--runs``: an integer in 1..10."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    lo, hi = RUNS_RANGE
    if not lo <= value <= hi:
        raise argparse.ArgumentTypeError(f"expected an integer in {lo}..{hi}, got {text!r}")
    return value


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``tir-contact demo``."""
    p.add_argument("--out", type=output_folder, default=Path("demo-out"),
                   help="output folder")
    p.add_argument("--seed", type=int, default=1,
                   help="random seed of the synthetic measurements, runs and footage")
    p.add_argument("--runs", type=_runs, default=3, help="repeated runs per velocity (1..10)")


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact demo``: :func:`run_demo`, then its report; 1 when anything failed."""
    result = run_demo(args.out, seed=args.seed, runs=args.runs)
    print(result.report())
    return 0 if result.ok else 1
