"""``tir-contact calibrate``: measured contact, deflection and friction in, a parameter file out.

Usage::

    tir-contact calibrate [--footage PATH...] [--characteristic CSV] [--transient CSV...]
        --out params.json [--preset G3] [--pressure-bar P] [--velocity V]
        [--sliding-direction left|right] [--law auto|ConstantLaw|DecreasingSqrtLaw|...]
        [--select KEY=VALUE]... [--lever-arm-from front_peak|contact_centroid]
        [--level 0.95] [--ci profile|jacobian|bootstrap] [--no-tip-feedback]

``--footage`` takes output folders of the contact pipeline (``frames.csv`` and
``elements.csv``; a path to either file means its folder). TIR results give the real contact
fraction, area and local pressure (:func:`friction_model.contact_from_pipeline`) and,
with deflection angles, the lever arm e(phi) of Eq. 5.21
(:func:`~friction_model.fit_lever_arm`); side-view results give the
deflection time series of element 0. A
``meta.json`` in the folder (or its parent), else the metadata ``tir-contact analyze`` recorded
in ``summary.json``, supplies the block, pressure, velocity and sliding
direction; the options override it. ``--characteristic`` is a steady table or the
evaluation's ``steady_characteristic.csv`` (mu(v) of its repeated runs where it has them,
fitted with ``--law``; ``auto`` leaves out the laws the replicate noise contradicts and
ranks the rest by AICc, and when the data cannot tell them apart it says so, names the
laws still in play and exits with code 2 asking for ``--law``; rows of more than one
``specimen`` are refused until ``--select specimen=NAME`` picks one). Every fit reports its
reduced chi-square against the noise; a misfit is warned about and its intervals widened.
``--transient`` takes transient tables (``time_s, velocity_mps, angle_deg``). The element
(E, loss factor) is identified together with the law
(:func:`friction_model.identify_parameters`) when a deflection series holds a velocity
change. The work is :func:`friction_model.calibrate_from_results`. Writes the parameter
file (docs/formats.md "Parameter file") and prints one summary line. Exit codes:
0 success, 1 when the data cannot be used (message on stderr), 2 for bad arguments or a
law that ``auto`` cannot decide.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from tir_contact.commands._types import UsageError, output_file, positive_number

__all__ = ["DESCRIPTION", "LAW_CHOICES", "add_arguments", "run"]

PROG = "tir-contact calibrate"
DESCRIPTION = (
    "Identify the real contact fraction, the lever arm e(phi) (Eq. 5.21), the rubber "
    "modulus and damping and a friction law mu(v) from contact-pipeline results, "
    "deflection time series and a steady characteristic; write a JSON parameter file."
)
#: Friction laws ``--law`` accepts (``auto``: one of the first four,
#: :data:`friction_model.identification.workflow.AUTO_LAWS`, chosen by
#: :func:`friction_model.identification.law_choice.choose_law`).
LAW_CHOICES = (
    "auto",
    "ConstantLaw",
    "DecreasingSqrtLaw",
    "IncreasingSqrtLaw",
    "ExponentialLaw",
    "ArctanExponentialLaw",
)


def _level(text: str) -> float:
    value = positive_number(text)
    if not value < 1:
        raise argparse.ArgumentTypeError(f"expected a number in (0, 1), got {text!r}")
    return value


def _select(text: str) -> tuple[str, Any]:
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    try:
        parsed: Any = float(value)
    except ValueError:
        parsed = value.strip()
    return key.strip(), parsed


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``tir-contact calibrate``: inputs, then how to fit them."""
    _add_inputs(parser)
    _add_fit_options(parser)


def _add_inputs(parser: argparse.ArgumentParser) -> None:
    """Result folders and tables in, the parameter file out, and the conditions."""
    parser.add_argument("--footage", nargs="+", default=[], metavar="PATH",
                        help="pipeline output folders (frames.csv + elements.csv) or those files")
    parser.add_argument("--characteristic", metavar="CSV",
                        help="steady table or steady_characteristic.csv")
    parser.add_argument("--transient", nargs="+", default=[], metavar="CSV",
                        help="transient tables (time_s, velocity_mps, angle_deg)")
    parser.add_argument("--out", type=output_file, required=True, metavar="FILE",
                        help="parameter file to write")
    parser.add_argument("--preset", default=None, metavar="NAME",
                        help="reference block G0/G3/G5/G6/G7 (default: meta.json, else G3)")
    parser.add_argument("--pressure-bar", type=positive_number, default=None, metavar="P",
                        help="nominal pressure F_N / (L w), bar (default: meta.json)")
    parser.add_argument("--velocity", type=positive_number, default=None, metavar="V",
                        help="sliding velocity of the footage, m/s (default: meta.json)")
    parser.add_argument("--sliding-direction", choices=("left", "right"), default=None,
                        help="direction the block moves in the image (default: meta.json)")


def _add_fit_options(parser: argparse.ArgumentParser) -> None:
    """The law, the rows of the characteristic, the lever-arm observation, the intervals."""
    parser.add_argument("--law", choices=LAW_CHOICES, default="auto",
                        help="friction law (default: auto)")
    parser.add_argument("--select", type=_select, action="append", default=[],
                        metavar="KEY=VALUE",
                        help="use only characteristic rows with this column value (repeatable)")
    parser.add_argument("--lever-arm-from", choices=("front_peak", "contact_centroid"),
                        default="front_peak",
                        help="lever-arm observation from the TIR results (default: front_peak)")
    parser.add_argument("--level", type=_level, default=0.95,
                        help="confidence level (default 0.95)")
    parser.add_argument("--ci", choices=("profile", "jacobian", "bootstrap"), default="profile",
                        help="interval of the element parameters (default: profile likelihood)")
    parser.add_argument("--no-tip-feedback", action="store_true",
                        help="friction follows the carriage velocity only, not the tip's motion "
                        "(as in synthetic transient tables)")


def _footage_folders(paths: list[str]) -> list[Path]:
    """The pipeline output folders of ``--footage`` (a frames.csv/elements.csv means its
    folder), each once."""
    folders: list[Path] = []
    for text in paths:
        p = Path(text)
        if p.is_file() and p.name in ("frames.csv", "elements.csv"):
            p = p.parent
        if not p.is_dir():
            raise UsageError(
                f"--footage {text}: not a pipeline output folder or its frames.csv/elements.csv"
            )
        for name in ("frames.csv", "elements.csv"):
            if not (p / name).is_file():
                raise UsageError(f"--footage {text}: {p / name} does not exist")
        if p not in folders:
            folders.append(p)
    return folders


def _check_usage(args: argparse.Namespace) -> None:
    """Options that do not fit together, and inputs that do not exist (exit code 2)."""
    if not (args.footage or args.characteristic or args.transient):
        raise UsageError("give at least one of --footage, --characteristic, --transient")
    out = Path(args.out)
    if not out.parent.is_dir():
        raise UsageError(f"--out {args.out}: folder {out.parent} does not exist")
    for path in [args.characteristic, *args.transient]:
        if path is not None and not Path(path).is_file():
            raise UsageError(f"{path}: does not exist")
    if args.preset is not None:
        from friction_model.geometry import reference_block

        try:
            reference_block(args.preset)
        except ValueError as exc:
            raise UsageError(f"--preset: {exc}") from None
    if args.transient and args.pressure_bar is None:
        raise UsageError(f"{args.transient[0]}: --pressure-bar is needed for a transient table")
    if args.select and not args.characteristic:
        raise UsageError("--select needs --characteristic")


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact calibrate``: :func:`calibrate_from_results`, then write the file.

    Returns
    -------
    int
        0 on success (errors are raised: :class:`UsageError` for bad arguments, ValueError
        when the data cannot be used).
    """
    # the model is imported when the command runs: 'tir-contact calibrate --help' stays fast
    from friction_model.identification.workflow import LawUndecidable, calibrate_from_results

    _check_usage(args)
    try:
        result = _calibrate(calibrate_from_results, args)
    except LawUndecidable as exc:
        raise UsageError(str(exc)) from None  # exit code 2: the user must name the law
    out = result.write(args.out)
    for note in result.notes:
        print(f"{PROG}: note: {note}", file=sys.stderr)
    print(f"wrote {out}: {result.summary()}")
    return 0


def _calibrate(calibrate_from_results: Any, args: argparse.Namespace) -> Any:
    """:func:`calibrate_from_results` with the command's arguments."""
    return calibrate_from_results(
        _footage_folders(args.footage),
        args.characteristic,
        args.transient,
        preset=args.preset,
        pressure_bar=args.pressure_bar,
        velocity_mps=args.velocity,
        sliding_direction=args.sliding_direction,
        law=args.law,
        select=dict(args.select),
        lever_arm_from=args.lever_arm_from,
        level=args.level,
        ci=args.ci,
        tip_velocity_feedback=not args.no_tip_feedback,
    )
