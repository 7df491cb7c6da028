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

Prints one summary line. Exit codes: 0 success, 1 when the parameter file cannot be used
(message on stderr), 2 for bad arguments.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

from tir_contact.commands._types import output_folder, positive_number, positive_pair

__all__ = ["add_parser", "run"]

PROG = "tir-contact simulate"


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register the ``simulate`` sub-command.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        From ``parser.add_subparsers()``.

    Returns
    -------
    argparse.ArgumentParser
        The sub-command's parser (its ``func`` default is :func:`run`).
    """
    parser = subparsers.add_parser(
        "simulate",
        help="run the calibrated model of a parameter file (mu(v), velocity step, e(phi))",
        description=(
            "Run the model calibrated by 'tir-contact calibrate': the steady friction "
            "characteristic, the element's deflection through a velocity step and the lever "
            "arm e(phi); CSV tables and PNG plots."
        ),
    )
    parser.add_argument("--params", required=True, metavar="FILE", help="parameter file (JSON)")
    parser.add_argument("--out", type=output_folder, required=True, metavar="DIR",
                        help="output folder")
    parser.add_argument(
        "--velocity",
        type=positive_number,
        nargs="+",
        default=None,
        metavar="V",
        help="sliding velocities of the steady characteristic, m/s",
    )
    parser.add_argument(
        "--velocity-step",
        type=positive_pair,
        default=None,
        metavar="V1,V2",
        help="velocity step of the deflection simulation, m/s (default: min,max velocity)",
    )
    parser.add_argument(
        "--normal-force-N",
        type=positive_number,
        default=None,
        metavar="F",
        help="normal force on the element, N (default: the file's)",
    )
    parser.add_argument("--no-plots", action="store_true", help="do not write PNG plots")
    parser.set_defaults(func=run)
    return parser


def _write_csv(table: Any, path: Path) -> None:
    from tir_common.atomic import atomic_write

    atomic_write(path, lambda tmp: table.to_csv(tmp, index=False, float_format="%.10g"))


def _save(fig: Any, path: Path) -> None:
    import matplotlib.pyplot as plt

    from tir_common.atomic import atomic_write

    try:
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=120))
    finally:
        plt.close(fig)


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact simulate``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments of the parser from :func:`add_parser`.

    Returns
    -------
    int
        0 on success, 1 when the parameter file cannot be used, 2 for bad arguments.
    """
    if not Path(args.params).is_file():
        print(f"{PROG}: error: {args.params}: does not exist", file=sys.stderr)
        return 2
    try:
        return _run(args)
    except (ValueError, RuntimeError, OSError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 1


def _run(args: argparse.Namespace) -> int:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    import pandas as pd

    from friction_model.identification.coupling import lever_arm_eq_5_21
    from friction_model.identification.identify import linear_element_response
    from friction_model.params_file import (
        friction_law_from,
        lever_arm_kwargs_from,
        read_parameters,
        sdof_params_from,
    )

    params = read_parameters(args.params)
    law = friction_law_from(params)
    sdof = sdof_params_from(params)
    lever = lever_arm_kwargs_from(params)
    if law is None and lever is None:
        raise ValueError(
            f"{args.params}: holds neither 'friction_law' nor 'lever_arm': nothing to simulate"
        )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    written: list[str] = []

    fn = args.normal_force_N
    if fn is None and params.get("element", {}).get("normal_force_N") is not None:
        fn = params["element"]["normal_force_N"]
    if fn is None and params.get("contact", {}).get("normal_force_N") is not None and sdof:
        n_el = params.get("geometry", {}).get("n_sipes", 0) + 1
        fn = params["contact"]["normal_force_N"] / n_el

    if law is not None:
        if args.velocity:
            v = np.sort(np.asarray(args.velocity, dtype=float))
        else:
            lo, hi = params["friction_law"].get("velocity_range_mps", [0.5, 8.0])
            v = np.geomspace(lo, hi, 50) if hi > lo else np.array([lo])
        table = pd.DataFrame({"velocity_mps": v, "mu": np.asarray(law(v), dtype=float)})
        if sdof is not None and fn:
            c_eff = sdof.spring_constant_Nm_rad - fn * sdof.length_m
            c_eff += sdof.mass_kg * sdof.gravity_mps2 * sdof.length_m / 2.0
            if c_eff > 0:
                table["angle_deg"] = np.degrees(fn * sdof.length_m * table["mu"] / c_eff)
        _write_csv(table, out / "mu_v.csv")
        written.append("mu_v.csv")
        if not args.no_plots:
            fig, ax = plt.subplots(figsize=(6, 4))
            ax.plot(table["velocity_mps"], table["mu"], "-", color="k")
            ax.set_xlabel("sliding velocity / (m/s)")
            ax.set_ylabel("friction coefficient mu")
            ax.set_title(f"{type(law).__name__} ({law.equation})")
            fig.tight_layout()
            _save(fig, out / "mu_v.png")
            written.append("mu_v.png")

        if sdof is not None and fn:
            v1, v2 = args.velocity_step or (float(v.min()), float(v.max()))
            tau = float(params["element"].get("relaxation_time_s") or 0.0)
            f_n = sdof.natural_frequency_Hz
            eta = max(sdof.loss_factor, 0.01)
            t_step = 5.0 / f_n
            t_end = t_step + max(0.02, 10.0 / (eta * math.pi * f_n) + 10.0 * tau)
            t = np.arange(0.0, t_end, 1.0 / (20.0 * f_n))
            vel = np.where(t >= t_step, v2, v1)
            phi = linear_element_response(
                sdof,
                time_s=t,
                velocity_mps=vel,
                friction=law,
                normal_force_N=fn,
                relaxation_time_s=tau,
                tip_velocity_feedback=params["element"].get("tip_velocity_feedback", True),
            )
            step = pd.DataFrame({"time_s": t, "velocity_mps": vel, "angle_deg": np.degrees(phi)})
            _write_csv(step, out / "step_response.csv")
            written.append("step_response.csv")
            if not args.no_plots:
                fig, ax = plt.subplots(figsize=(6, 4))
                ax.plot(step["time_s"] * 1e3, step["angle_deg"], color="k")
                ax.set_xlabel("time / ms")
                ax.set_ylabel("deflection angle / deg")
                ax.set_title(f"velocity step {v1:g} -> {v2:g} m/s, F_N = {fn:.3g} N")
                fig.tight_layout()
                _save(fig, out / "step_response.png")
                written.append("step_response.png")

    if lever is not None:
        phi_deg = np.linspace(0.0, 60.0, 121)
        e = lever_arm_eq_5_21(
            np.radians(phi_deg),
            length_m=lever["length_m"],
            e1=lever["e1"],
            e2_per_rad=lever["e2_per_rad"],
            e3_m=lever["e3_m"],
            e4_m=lever["e4_m"],
        )
        table = pd.DataFrame({"deflection_angle_deg": phi_deg, "lever_arm_mm": np.asarray(e) * 1e3})
        _write_csv(table, out / "lever_arm.csv")
        written.append("lever_arm.csv")
        if not args.no_plots:
            fig, ax = plt.subplots(figsize=(6, 4))
            ax.plot(table["deflection_angle_deg"], table["lever_arm_mm"], color="k")
            ax.set_xlabel("deflection angle / deg")
            ax.set_ylabel("lever arm e / mm")
            ax.set_title("Eq. 5.21")
            fig.tight_layout()
            _save(fig, out / "lever_arm.png")
            written.append("lever_arm.png")
    print(f"simulated {args.params}: wrote {', '.join(written)} to {out}")
    return 0
