"""The ``tir-contact`` console command and its sub-commands.

The sub-commands are the table :data:`COMMANDS` (name, help line, which errors mean "the
data cannot be used"); each one's module in :mod:`tir_contact.commands` is imported only
when that command is given. Every error a command raises ends in :func:`main`, as one line
``tir-contact COMMAND: error: ...`` on stderr and an exit code.

Exit codes: 0 success; 1 some of the work failed (a video, a run file), reported at the end,
or (calibrate, simulate, discrepancy, synth) the data cannot be used; 2 a usage error (a bad
option, an input file that cannot be used, an output folder that cannot be written),
reported in one line naming the file and what was expected; 130 interrupted. No Python
traceback reaches the user unless ``-vv`` asks for it.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import logging
import signal
import sys
import traceback
import warnings
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from types import ModuleType

from tir_contact import __version__
from tir_contact._interrupt import one_interrupt
from tir_contact.commands._types import UsageError

#: Exit code of a usage error (argparse uses the same).
USAGE_ERROR = 2
#: Exit code when some of the work failed, or (for the commands that say so) the data
#: cannot be used.
FAILED = 1
#: Exit code of an interrupted run.
INTERRUPTED = 130
#: Errors that name an input or output the user can fix (exit code 2 unless the command
#: counts them as unusable data).
_USER_ERRORS: tuple[type[BaseException], ...] = (ValueError, OSError, KeyError)


@dataclass(frozen=True)
class Command:
    """A sub-command: its module under :mod:`tir_contact.commands` and how its errors end.

    The module provides ``DESCRIPTION``, ``add_arguments(parser)`` and ``run(args) -> int``
    and is imported only when the command is given (``tir-contact --help`` stays fast).

    Attributes
    ----------
    help : str
        One line in ``tir-contact --help``.
    data_errors : tuple of exception types
        Errors the command reports as "the data cannot be used" (exit code 1); other
        ValueError, OSError and KeyError are usage errors (exit code 2).
    module : str, optional
        The command's module when it is not ``tir_contact.commands.NAME`` (a plug-in).
    """

    help: str
    data_errors: tuple[type[BaseException], ...] = ()
    module: str | None = None


def _command_module(name: str) -> ModuleType:
    """The module of the sub-command `name` (imported only when the command is given)."""
    return importlib.import_module(COMMANDS[name].module or f"tir_contact.commands.{name}")


#: The sub-commands in the order of ``tir-contact --help``.
COMMANDS: dict[str, Command] = {
    "analyze": Command(
        "analyse TIR / side-view footage: contact area, elements, peaks, deflection"),
    "evaluate": Command(
        "evaluate raw test-rig runs (steady and instationary friction coefficients)"),
    "calibrate": Command(
        "calibrate the model on footage results and friction characteristics",
        data_errors=(ValueError, RuntimeError, OSError)),
    "simulate": Command(
        "run the calibrated model of a parameter file (mu(v), velocity step, e(phi))",
        data_errors=(ValueError, RuntimeError, OSError)),
    "discrepancy": Command(
        "find where model and measurement disagree and name the missing effect",
        data_errors=(ValueError, OSError, KeyError)),
    "report": Command("build report.html of an analyze or evaluate results folder"),
    "demo": Command("run the main job on synthetic data it makes itself"),
    "synth": Command(
        "make synthetic TIR footage or synthetic test-rig measurements",
        data_errors=(ValueError, OSError, ImportError)),
}


def build_parser(commands: Collection[str] | None = None) -> argparse.ArgumentParser:
    """Build the argument parser with every sub-command registered.

    Parameters
    ----------
    commands : collection of str, optional
        Give only these sub-commands their arguments (the others are listed by name and
        help; their modules are not imported); default all.

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
    for name, command in COMMANDS.items():
        if commands is not None and name not in commands:
            sub.add_parser(name, help=command.help)
            continue
        module = _command_module(name)
        leaf = sub.add_parser(name, help=command.help, description=module.DESCRIPTION)
        module.add_arguments(leaf)
        leaf.set_defaults(func=module.run)
        _add_output_options(leaf)
    return parser


def _add_output_options(parser: argparse.ArgumentParser) -> None:
    """``-q`` and ``-v`` after the command too (``tir-contact analyze -q ...``); each leaf
    parser records its name (``tir-contact synth footage``) for messages."""
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
        leaf.set_defaults(command_prog=leaf.prog, command_parser=leaf)


def _command_in(argv: Sequence[str]) -> str | None:
    """The sub-command named in `argv` (the first word that is not an option), if known."""
    for word in argv:
        if not word.startswith("-"):
            return word if word in COMMANDS else None
    return None


def _report(prog: str, exc: BaseException, verbose: int, *, internal: bool = False) -> None:
    """One line on stderr naming the command and the error; the traceback with ``-vv``."""
    from tir_contact._readers import one_line  # not at startup: it loads the image libraries

    if verbose >= 2:
        traceback.print_exc()
    if internal:
        print(f"{prog}: internal error: {type(exc).__name__}: {one_line(exc, limit=None)} "
              "(run with -vv for the traceback)", file=sys.stderr)
    else:
        print(f"{prog}: error: {one_line(exc, limit=None)}", file=sys.stderr)


def _unrecognized(args: argparse.Namespace, extras: Sequence[str]) -> str:
    """The message for arguments the command does not know, with the nearest of its
    options for each that looks like an option (``--mm-px``: ``--mm-per-px``)."""
    import difflib

    leaf = getattr(args, "command_parser", None)
    known = [o for a in (leaf._actions if leaf else []) for o in a.option_strings]
    hints = []
    for word in extras:
        if word.startswith("--"):
            near = difflib.get_close_matches(word.split("=")[0], known, n=1, cutoff=0.6)
            if near:
                hints.append(f"{word}: did you mean {near[0]}?")
    text = f"unrecognized arguments: {' '.join(extras)}"
    return text + (f" ({'; '.join(hints)})" if hints else "")


def _setup_logging(verbose: int) -> None:
    level = {0: logging.WARNING, 1: logging.INFO}.get(verbose, logging.DEBUG)
    fmt = "%(levelname)s: %(message)s" if verbose == 0 else (
        "%(levelname)s %(name)s: %(message)s")
    logging.basicConfig(level=level, format=fmt)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI.

    Every error of a command ends here, as one line on stderr and an exit code:
    :class:`~tir_contact.commands._types.UsageError` 2; the command's ``data_errors`` 1;
    other ValueError, OSError and KeyError 2; anything else (a bug) 1, as an internal error.

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
    argv = sys.argv[1:] if argv is None else list(argv)
    command = _command_in(argv)
    parser = build_parser(commands=() if command is None else (command,))
    try:
        args, extras = parser.parse_known_args(argv)
        if extras:  # said by the command's own parser, with its usage line
            getattr(args, "command_parser", parser).error(_unrecognized(args, extras))
    except SystemExit as exc:  # --help, --version and argparse's usage errors
        return int(exc.code or 0) if isinstance(exc.code, int) else USAGE_ERROR
    _setup_logging(args.verbose)
    if args.quiet:
        args.no_progress = True
    prog = getattr(args, "command_prog", f"tir-contact {args.command}")
    data_errors = COMMANDS[args.command].data_errors
    try:
        with warnings.catch_warnings():
            if args.verbose < 2:
                # library warnings (matplotlib, pandas, numpy) are not the user's business;
                # our own conditions are logged as WARNING lines instead
                warnings.simplefilter("ignore")
            # the first Ctrl-C stops the command; a further one, until the process ends,
            # must not cut short the clean-up or change the exit code
            with one_interrupt(keep_ignoring=True):
                return int(args.func(args) or 0)
    except KeyboardInterrupt:
        with contextlib.suppress(ValueError):  # ValueError: not the main thread
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        print(f"{prog}: interrupted", file=sys.stderr)
        return INTERRUPTED
    except UsageError as exc:
        _report(prog, exc, args.verbose)
        return USAGE_ERROR
    except data_errors as exc:
        _report(prog, exc, args.verbose)
        return FAILED
    except _USER_ERRORS as exc:
        _report(prog, exc, args.verbose)
        return USAGE_ERROR
    except Exception as exc:  # a bug: one line, the traceback with -vv
        _report(prog, exc, args.verbose, internal=True)
        return FAILED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
