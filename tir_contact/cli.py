"""The ``tir-contact`` console command and its sub-commands."""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Sequence

from tir_contact import __version__
from tir_contact.commands import (
    analyze,
    calibrate,
    demo,
    discrepancy,
    evaluate,
    simulate,
    synth,
)

_COMMANDS = (analyze, evaluate, calibrate, simulate, discrepancy, demo, synth)


def build_parser() -> argparse.ArgumentParser:
    """Build the argument parser with every sub-command registered.

    Returns
    -------
    argparse.ArgumentParser
        The top-level parser of ``tir-contact``.
    """
    parser = argparse.ArgumentParser(
        prog="tir-contact",
        description=(
            "Tread-block friction on ice: evaluate test-rig runs, model dry/wet friction, "
            "analyse TIR contact footage."
        ),
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument(
        "-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for module in _COMMANDS:
        module.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name; ``sys.argv[1:]`` when omitted.

    Returns
    -------
    int
        Process exit code: 0 on success, non-zero when anything failed.
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    level = {0: logging.WARNING, 1: logging.INFO}.get(args.verbose, logging.DEBUG)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    return int(args.func(args) or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
