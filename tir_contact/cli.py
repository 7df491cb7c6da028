"""The ``tir-contact`` console command and its sub-commands.

Exit codes: 0 success; 1 some of the work failed (a video, a run file), reported at the end;
2 a usage error (a bad option, an input file that cannot be used, an output folder that
cannot be written), reported in one line naming the file and what was expected; 130
interrupted. No Python traceback reaches the user unless ``-vv`` asks for it.
"""

from __future__ import annotations

import argparse
import logging
import sys
import traceback
import warnings
from collections.abc import Sequence

from tir_contact import __version__
from tir_contact._readers import FootageError
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

#: Exit code of a usage error (argparse uses the same).
USAGE_ERROR = 2


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
    noise = parser.add_mutually_exclusive_group()
    noise.add_argument(
        "-v", "--verbose", action="count", default=0,
        help="more log output (-v info, -vv debug and tracebacks)",
    )
    noise.add_argument(
        "-q", "--quiet", action="store_true",
        help="no progress bars or per-item lines: only errors, warnings and the result",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for module in _COMMANDS:
        module.add_parser(sub)
    for command in sub.choices.values():
        _add_output_options(command)
    return parser


def _add_output_options(parser: argparse.ArgumentParser) -> None:
    """``-q`` and ``-v`` after the command too (``tir-contact analyze -q ...``)."""
    leaves = [parser]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            leaves = list(action.choices.values())
    for leaf in leaves:
        group = leaf.add_argument_group("output")
        group.add_argument("-v", "--verbose", action="count", default=argparse.SUPPRESS,
                           help="more log output (-v info, -vv debug and tracebacks)")
        group.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                           help="no progress bars or per-item lines")


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name; ``sys.argv[1:]`` when omitted.

    Returns
    -------
    int
        Process exit code: 0 on success, 1 when some of the work failed, 2 for a usage
        error (bad option, unusable input file or output folder), 130 when interrupted.
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version and argparse's usage errors
        return int(exc.code or 0) if isinstance(exc.code, int) else USAGE_ERROR
    level = {0: logging.WARNING, 1: logging.INFO}.get(args.verbose, logging.DEBUG)
    fmt = "%(levelname)s: %(message)s" if args.verbose == 0 else (
        "%(levelname)s %(name)s: %(message)s")
    logging.basicConfig(level=level, format=fmt)
    if args.quiet:
        args.no_progress = True
    prog = f"tir-contact {args.command}"
    try:
        with warnings.catch_warnings():
            if args.verbose < 2:
                # library warnings (matplotlib, pandas, numpy) are not the user's business;
                # our own conditions are logged as WARNING lines instead
                warnings.simplefilter("ignore")
            return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except (FootageError, ValueError, OSError, KeyError) as exc:
        if args.verbose >= 2:
            traceback.print_exc()
        print(f"{prog}: error: {_one_line(exc)}", file=sys.stderr)
        return USAGE_ERROR
    except Exception as exc:  # a bug: one line, the traceback with -vv
        if args.verbose >= 2:
            traceback.print_exc()
        print(f"{prog}: internal error: {type(exc).__name__}: {_one_line(exc)} "
              "(run with -vv for the traceback)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
