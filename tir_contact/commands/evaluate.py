"""``tir-contact evaluate``: friction coefficients from raw test-rig runs.

Usage::

    tir-contact evaluate PATH... --out DIR [--instationary] [--mass-kg M] [--bin-width 0.25]
                         [--no-plots] [--no-progress]

PATH is a run CSV file or a folder of them (all ``*.csv`` in natural sort order). Writes
``steady_characteristic.csv``, ``ambient.csv``, ``instationary_characteristic.csv`` (when
there are instationary runs), ``provenance.json``, PNG plots and ``report.html`` to DIR;
prints a summary to stdout and one ``file: message`` line per failed file to stderr. Exit
code 0 when every file was evaluated, 1 when any failed (everything that succeeded is still
written).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from tir_contact.commands._types import (
    UsageError,
    non_negative_number,
    output_folder,
    positive_number,
)

__all__ = ["DESCRIPTION", "add_arguments", "run"]

DESCRIPTION = (
    "Evaluate raw test-rig run CSVs: constant-velocity window, mean friction "
    "coefficient by both methods, mean and std over repeated runs, ambient averages, "
    "instationary mu(v) with the carriage inertia removed."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``tir-contact evaluate``."""
    parser.add_argument(
        "paths", nargs="+", metavar="PATH", help="run CSV files or folders of *.csv files"
    )
    parser.add_argument("--out", type=output_folder, required=True, metavar="DIR",
                        help="output folder")
    parser.add_argument(
        "--instationary",
        action="store_true",
        help="evaluate every run as instationary (default: per file, metadata 'kind')",
    )
    parser.add_argument(
        "--mass-kg",
        type=non_negative_number,
        default=None,
        metavar="M",
        help="inertial mass of carriage and sample in kg (default: metadata inertial_mass_kg)",
    )
    parser.add_argument(
        "--bin-width",
        type=positive_number,
        default=0.25,
        metavar="W",
        help="velocity bin width of the instationary characteristic in m/s (default: 0.25)",
    )
    parser.add_argument("--no-plots", action="store_true", help="do not write PNG plots")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact evaluate``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments of the parser :func:`add_arguments` filled.

    Returns
    -------
    int
        0 when every file was evaluated, 1 when any failed (or a folder held no ``*.csv``).
    """
    # the evaluation is imported when the command runs: 'tir-contact evaluate --help' stays fast
    from friction_model.rig import InstationaryParams, evaluate_folder

    missing = [str(path) for path in args.paths if not Path(path).exists()]
    if missing:  # as analyze: a usage error before any output is written
        raise UsageError(f"{', '.join(missing)}: does not exist")
    result = evaluate_folder(
        args.paths,
        args.out,
        instationary=args.instationary,
        inertial_mass_kg=args.mass_kg,
        instationary_params=InstationaryParams(bin_width_mps=args.bin_width),
        plots=not args.no_plots,
        progress=False if args.no_progress else None,
    )
    from tir_contact.report import write_evaluation_report

    write_evaluation_report(args.out)  # the tables and plots just written, to review
    n_steady, n_inst = len(result.steady_runs), len(result.instationary_runs)
    print(
        f"evaluated {n_steady} steady and {n_inst} instationary runs, "
        f"{len(result.failures)} failed; outputs in {args.out}"
    )
    if n_steady:
        agg = result.steady[result.steady["row_type"] == "aggregate"]
        summary = agg[["specimen", "condition"]].assign(
            **{
                "v [m/s]": agg["velocity_mps"].map("{:.3f}".format),
                "mu (method 1)": agg["mu_mean_method1"].map("{:.4f}".format),
                "mu (method 2)": agg["mu_mean_method2"].map("{:.4f}".format),
                "std over runs": agg["mu_std_runs"].map("{:.4f}".format),
                "runs": agg["n_runs"],
            }
        )
        print(summary.to_string(index=False))
    for r in result.instationary_runs:
        counts = r.table["branch"].value_counts()
        print(
            f"instationary {r.file}: m = {r.inertial_mass_kg:g} kg, "
            f"{counts.get('accelerating', 0)} accelerating and "
            f"{counts.get('decelerating', 0)} decelerating bins"
        )
    for failure in result.failures:
        print(f"{failure.file}: {failure.message}", file=sys.stderr)
    return 0 if result.ok and result.files else 1
