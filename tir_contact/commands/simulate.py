"""``tir-contact simulate``: run the calibrated model of a parameter file.

Usage::

    tir-contact simulate --params params.json --out DIR [--velocity V ...]
        [--velocity-step V1,V2] [--normal-force-N F] [--no-plots]

Writes to DIR (created if needed):

* ``mu_v.csv`` / ``mu_v.png``: the steady characteristic mu(v) of the file's friction law at
  the velocities ``--velocity`` (default: 50 values over the calibrated velocity range, else
  0.5-8 m/s); with an ``element`` section also ``angle_deg``, the steady deflection angle of
  the loaded element (Eq. 5.8 linearised).
* ``step_response.csv`` / ``step_response.png`` (with an ``element`` section): the deflection
  angle through a velocity step V1 -> V2 (default: the smallest and largest velocity) from
  :func:`friction_model.identification.identify.linear_element_response`.
* ``lever_arm.csv`` / ``lever_arm.png`` (with a ``lever_arm`` section): e(phi) of Eq. 5.21.

The work is :func:`friction_model.simulate_calibrated`. Prints one summary line. Exit codes:
0 success, 1 when the parameter file cannot be used (message on stderr), 2 for bad arguments.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tir_contact.commands._types import (
    UsageError,
    output_folder,
    positive_number,
    positive_pair,
)

__all__ = ["DESCRIPTION", "add_arguments", "run"]

DESCRIPTION = (
    "Run the model calibrated by 'tir-contact calibrate': the steady friction "
    "characteristic, the element's deflection through a velocity step and the lever "
    "arm e(phi); CSV tables and PNG plots."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``tir-contact simulate``."""
    parser.add_argument("--params", required=True, metavar="FILE", help="parameter file (JSON)")
    parser.add_argument("--out", type=output_folder, required=True, metavar="DIR",
                        help="output folder")
    parser.add_argument("--velocity", type=positive_number, nargs="+", default=None,
                        metavar="V", help="sliding velocities of the steady characteristic, m/s")
    parser.add_argument("--velocity-step", type=positive_pair, default=None, metavar="V1,V2",
                        help="velocity step of the deflection simulation, m/s "
                        "(default: min,max velocity)")
    parser.add_argument("--normal-force-N", type=positive_number, default=None, metavar="F",
                        help="normal force on the element, N (default: the file's)")
    parser.add_argument("--no-plots", action="store_true", help="do not write PNG plots")


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact simulate``: :func:`simulate_calibrated`, then write its tables.

    Returns
    -------
    int
        0 on success (errors are raised: :class:`UsageError` for a missing parameter file,
        ValueError when it cannot be used).
    """
    # the model is imported when the command runs: 'tir-contact simulate --help' stays fast
    from friction_model.calibrated_model import simulate_calibrated

    if not Path(args.params).is_file():
        raise UsageError(f"{args.params}: does not exist")
    result = simulate_calibrated(
        args.params,
        velocities_mps=args.velocity,
        velocity_step_mps=args.velocity_step,
        normal_force_N=args.normal_force_N,
    )
    written = result.write(args.out, plots=not args.no_plots)
    print(f"simulated {args.params}: wrote {', '.join(written)} to {Path(args.out)}")
    # what the file cannot give, said rather than left out silently
    if result.step_response is None:
        unused = [flag for flag, value in (("--velocity-step", args.velocity_step),
                                           ("--normal-force-N", args.normal_force_N))
                  if value is not None]
        print(f"  no step_response: {args.params} has no 'element' section (calibrate "
              "identifies the element from side-view footage or --transient tables holding a "
              "velocity change)"
              + (f"; {', '.join(unused)} not used" if unused else ""))
    if result.lever_arm is None:
        print(f"  no lever_arm: {args.params} has no 'lever_arm' section")
    if result.extrapolated_mps:
        lo, hi = result.fitted_range_mps
        print(f"  extrapolated: mu at {', '.join(f'{v:g}' for v in result.extrapolated_mps)}"
              f" m/s (fitted {lo:g}-{hi:g} m/s), outside the velocities the law was fitted on")
    return 0
