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
evaluation's ``steady_characteristic.csv`` (mu(v), fitted with ``--law``; ``auto`` picks the
law with the lowest AICc). ``--transient`` takes transient tables (``time_s, velocity_mps,
angle_deg``). The element (E, loss factor) is identified together with the law
(:func:`friction_model.identify_parameters`) when a deflection series holds a
velocity change. Writes the parameter file (docs/formats.md "Parameter file") and prints one
summary line. Exit codes: 0 success, 1 when the data cannot be used (message on stderr),
2 for bad arguments.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import Any

from tir_contact.commands._types import output_file, positive_number

__all__ = ["LAW_CHOICES", "add_parser", "run"]

PROG = "tir-contact calibrate"
#: Friction laws ``--law`` accepts (``auto``: the lowest AICc of the first four).
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


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register the ``calibrate`` sub-command.

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
        "calibrate",
        help="calibrate the model on footage results and friction characteristics",
        description=(
            "Identify the real contact fraction, the lever arm e(phi) (Eq. 5.21), the rubber "
            "modulus and damping and a friction law mu(v) from contact-pipeline results, "
            "deflection time series and a steady characteristic; write a JSON parameter file."
        ),
    )
    parser.add_argument(
        "--footage",
        nargs="+",
        default=[],
        metavar="PATH",
        help="pipeline output folders (frames.csv + elements.csv) or those files",
    )
    parser.add_argument(
        "--characteristic", metavar="CSV", help="steady table or steady_characteristic.csv"
    )
    parser.add_argument(
        "--transient",
        nargs="+",
        default=[],
        metavar="CSV",
        help="transient tables (time_s, velocity_mps, angle_deg)",
    )
    parser.add_argument("--out", type=output_file, required=True, metavar="FILE",
                        help="parameter file to write")
    parser.add_argument(
        "--preset",
        default=None,
        metavar="NAME",
        help="reference block G0/G3/G5/G6/G7 (default: meta.json, else G3)",
    )
    parser.add_argument(
        "--pressure-bar",
        type=positive_number,
        default=None,
        metavar="P",
        help="nominal pressure F_N / (L w), bar (default: meta.json)",
    )
    parser.add_argument(
        "--velocity",
        type=positive_number,
        default=None,
        metavar="V",
        help="sliding velocity of the footage, m/s (default: meta.json)",
    )
    parser.add_argument(
        "--sliding-direction",
        choices=("left", "right"),
        default=None,
        help="direction the block moves in the image (default: meta.json)",
    )
    parser.add_argument(
        "--law", choices=LAW_CHOICES, default="auto", help="friction law (default: auto)"
    )
    parser.add_argument(
        "--select",
        type=_select,
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="use only characteristic rows with this column value (repeatable)",
    )
    parser.add_argument(
        "--lever-arm-from",
        choices=("front_peak", "contact_centroid"),
        default="front_peak",
        help="lever-arm observation from the TIR results (default: front_peak)",
    )
    parser.add_argument(
        "--level", type=_level, default=0.95, help="confidence level (default 0.95)"
    )
    parser.add_argument(
        "--ci",
        choices=("profile", "jacobian", "bootstrap"),
        default="profile",
        help="interval of the element parameters (default: profile likelihood)",
    )
    parser.add_argument(
        "--no-tip-feedback",
        action="store_true",
        help="friction follows the carriage velocity only, not the tip's motion "
        "(as in synthetic transient tables)",
    )
    parser.set_defaults(func=run)
    return parser


class _InputError(ValueError):
    """Bad command-line input (exit code 2)."""


def _footage_folders(paths: list[str]) -> list[Path]:
    folders: list[Path] = []
    for text in paths:
        p = Path(text)
        if p.is_file() and p.name in ("frames.csv", "elements.csv"):
            p = p.parent
        if not p.is_dir():
            raise _InputError(
                f"--footage {text}: not a pipeline output folder or its frames.csv/elements.csv"
            )
        for name in ("frames.csv", "elements.csv"):
            if not (p / name).is_file():
                raise _InputError(f"--footage {text}: {p / name} does not exist")
        if p not in folders:
            folders.append(p)
    return folders


def _meta(folder: Path) -> dict[str, Any]:
    """The footage metadata: ``meta.json`` beside the results, else the ``meta`` that
    ``tir-contact analyze`` recorded in ``summary.json``."""
    for candidate in (folder / "meta.json", folder.parent / "meta.json",
                      folder / "summary.json"):
        if candidate.is_file():
            try:
                doc = json.loads(candidate.read_text(encoding="utf-8"))
            except (OSError, json.JSONDecodeError) as exc:
                raise ValueError(f"{candidate}: not valid JSON ({exc})") from None
            if candidate.name == "summary.json" and isinstance(doc, dict):
                doc = doc.get("meta")
            if isinstance(doc, dict):
                return doc
    return {}


def _geometry(preset: str | None, meta: dict[str, Any]):
    from friction_model.geometry import BlockGeometry, reference_block

    if preset is not None:
        try:
            return reference_block(preset)
        except ValueError as exc:
            raise _InputError(f"--preset: {exc}") from None
    block = meta.get("block") or {}
    if block.get("preset"):
        return reference_block(str(block["preset"]))
    keys = ("length_mm", "width_mm", "n_sipes", "sipe_width_mm", "height_mm")
    if all(block.get(k) is not None for k in keys):
        lengths = block.get("element_lengths_mm")
        return BlockGeometry(
            length_mm=float(block["length_mm"]),
            width_mm=float(block["width_mm"]),
            n_sipes=int(block["n_sipes"]),
            sipe_width_mm=float(block["sipe_width_mm"]),
            height_mm=float(block["height_mm"]),
            element_lengths_mm=tuple(lengths) if lengths else None,
        )
    return reference_block("G3")


def _aicc(rss: float, n: int, k: int) -> float:
    if n - k - 1 <= 0 or rss <= 0:
        return math.inf
    return n * math.log(rss / n) + 2 * k + 2 * k * (k + 1) / (n - k - 1)


def _pick_law(name: str, steady: Any) -> Any:
    """A starting law: fitted to the characteristic (auto: lowest AICc), else a default."""
    import warnings

    import numpy as np

    from friction_model.contact import laws

    names = ("ConstantLaw", "DecreasingSqrtLaw", "IncreasingSqrtLaw", "ExponentialLaw")
    if steady is None:
        cls = laws.DecreasingSqrtLaw if name == "auto" else getattr(laws, name)
        defaults = {
            "ConstantLaw": {"mu0": 0.15},
            "DecreasingSqrtLaw": {"A_D": 0.05, "B_D": 0.1},
            "IncreasingSqrtLaw": {"A_I": 0.01, "B_I": 0.1},
            "ExponentialLaw": {"a1": 0.1, "a2": 0.1, "a3": -0.5},
            "ArctanExponentialLaw": {"k1": 0.1, "k2": 0.1, "k3": -0.5, "k4": 100.0},
        }
        return cls(**defaults[cls.__name__]), None
    candidates = names if name == "auto" else (name,)
    best = None
    for cand in candidates:
        cls = getattr(laws, cand)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fit = laws.fit_law(cls, steady.velocity_mps, steady.mu, sigma=steady.sigma)
        except (ValueError, RuntimeError) as exc:
            if name != "auto":
                raise ValueError(f"{steady.name}: fitting {cand} failed: {exc}") from None
            continue
        resid = steady.mu - np.asarray(fit.law(steady.velocity_mps))
        w = 1.0 if steady.sigma is None else 1.0 / np.asarray(steady.sigma)
        score = _aicc(float(np.sum((resid * w) ** 2)), steady.mu.size, len(cls.param_names))
        if best is None or score < best[0]:
            best = (score, fit)
    if best is None:
        raise ValueError(f"{steady.name}: no friction law could be fitted")
    return best[1].law, best[1]


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact calibrate``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments of the parser from :func:`add_parser`.

    Returns
    -------
    int
        0 on success, 1 when the data cannot be used, 2 for bad arguments.
    """
    try:
        return _run(args)
    except _InputError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    except (ValueError, RuntimeError, OSError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 1


def _run(args: argparse.Namespace) -> int:
    import warnings

    import numpy as np
    import pandas as pd
    from scipy import stats

    from friction_model.dynamics.rigid import SdofParams
    from friction_model.identification.coupling import (
        contact_from_pipeline,
        fit_lever_arm,
        lever_arm_observations,
        read_pipeline_tables,
    )
    from friction_model.identification.identify import (
        DeflectionSeries,
        identify_parameters,
        read_characteristic,
    )
    from friction_model.params_file import ParameterFileError, write_parameters

    if not (args.footage or args.characteristic or args.transient):
        raise _InputError("give at least one of --footage, --characteristic, --transient")
    out = Path(args.out)
    if not out.parent.is_dir():
        raise _InputError(f"--out {args.out}: folder {out.parent} does not exist")
    for path in [args.characteristic, *args.transient]:
        if path is not None and not Path(path).is_file():
            raise _InputError(f"{path}: does not exist")
    folders = _footage_folders(args.footage)
    metas = [_meta(f) for f in folders]
    geometry = _geometry(args.preset, metas[0] if metas else {})
    n_el = geometry.n_elements

    def pressure_of(meta: dict[str, Any]) -> float | None:
        if args.pressure_bar is not None:
            return args.pressure_bar
        p = (meta.get("conditions") or {}).get("pressure_bar")
        return None if p is None else float(p)

    def force_per_element(p_bar: float) -> float:
        return p_bar * 1e5 * geometry.nominal_area_mm2 * 1e-6 / n_el

    notes: list[str] = []
    contacts = []
    observations = []
    series: list[DeflectionSeries] = []
    for folder, meta in zip(folders, metas, strict=True):
        frames, elements = read_pipeline_tables(folder)
        p_bar = pressure_of(meta)
        has_contact = (
            "contact_length_mm" in elements
            and "n_elements_in_contact" in frames
            and np.nanmax(
                pd.to_numeric(elements["contact_length_mm"], errors="coerce").to_numpy(float),
                initial=0.0,
            )
            > 0
            and str(meta.get("view", "tir")).lower() == "tir"
        )
        if has_contact:
            fn_block = None if p_bar is None else p_bar * 1e5 * geometry.nominal_area_mm2 * 1e-6
            try:
                width = None
                if meta.get("width_px") and meta.get("mm_per_px"):
                    width = float(meta["width_px"]) * float(meta["mm_per_px"])
                measured = contact_from_pipeline(
                    frames,
                    elements,
                    geometry=geometry,
                    normal_force_N=fn_block,
                    image_width_mm=width,
                )
            except ValueError as exc:
                raise ValueError(f"{folder}: {exc}") from None
            contacts.append(measured)
            direction = args.sliding_direction or meta.get("sliding_direction")
            if direction is None:
                notes.append(f"{folder}: no sliding direction, lever arm skipped")
            else:
                obs = lever_arm_observations(
                    elements,
                    geometry=geometry,
                    sliding_direction=str(direction).lower(),
                    method=args.lever_arm_from,
                    frames=measured.frames,
                )
                observations.append(obs)
        angles = pd.to_numeric(elements.get("deflection_angle_deg"), errors="coerce")
        if (
            str(meta.get("view", "")).lower() == "side"
            and angles is not None
            and np.isfinite(angles).sum() >= 4
        ):
            v = args.velocity or (meta.get("conditions") or {}).get("velocity_mps")
            if v is None or p_bar is None:
                notes.append(f"{folder}: side view without velocity or pressure, not used")
            else:
                rows = elements[elements["element"] == 0].sort_values("time_s")
                series.append(
                    DeflectionSeries(
                        time_s=rows["time_s"].to_numpy(float),
                        angle_deg=pd.to_numeric(
                            rows["deflection_angle_deg"], errors="coerce"
                        ).to_numpy(float),
                        velocity_mps=float(v),
                        normal_force_N=force_per_element(p_bar),
                        name=str(folder),
                    )
                )
    for path in args.transient:
        from friction_model.discrepancy import read_transient_table

        table = read_transient_table(path)  # any CSV dialect; errors name file, column, row
        p_bar = args.pressure_bar
        if p_bar is None:
            raise _InputError(f"{path}: --pressure-bar is needed for a transient table")
        series.append(
            DeflectionSeries(
                time_s=table["time_s"].to_numpy(float),
                angle_deg=table["angle_deg"].to_numpy(float),
                velocity_mps=table["velocity_mps"].to_numpy(float),
                normal_force_N=force_per_element(p_bar),
                name=Path(path).name,
            )
        )

    steady = None
    if args.characteristic:
        steady = read_characteristic(args.characteristic, select=dict(args.select) or None)
    elif args.select:
        raise _InputError("--select needs --characteristic")

    sections: dict[str, Any] = {
        "geometry": {
            "length_mm": geometry.length_mm,
            "width_mm": geometry.width_mm,
            "n_sipes": geometry.n_sipes,
            "sipe_width_mm": geometry.sipe_width_mm,
            "height_mm": geometry.height_mm,
            "element_lengths_mm": geometry.element_lengths.tolist(),
        }
    }
    if contacts:
        weights = np.array([c.n_frames for c in contacts], dtype=float)
        frac = float(np.average([c.contact_fraction for c in contacts], weights=weights))
        section = (
            contacts[0].to_dict()
            if len(contacts) == 1
            else {
                "contact_fraction": frac,
                "contact_fraction_std": float(
                    np.std([c.contact_fraction for c in contacts], ddof=1)
                ),
                "contact_fraction_per_element": np.average(
                    [c.contact_fraction_per_element for c in contacts], axis=0, weights=weights
                ).tolist(),
                "contact_ratio": frac * geometry.rubber_area_mm2 / geometry.nominal_area_mm2,
                "real_contact_area_mm2": frac * geometry.rubber_area_mm2,
                "n_frames": int(weights.sum()),
            }
        )
        sections["contact"] = section
    if observations:
        obs = pd.concat(observations, ignore_index=True)
        if len(obs) >= 5 and np.ptp(obs["phi_rad"].to_numpy()) > 0:
            ell = float(np.mean(geometry.element_lengths)) * 1e-3
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fit = fit_lever_arm(
                    obs["phi_rad"].to_numpy(),
                    obs["lever_arm_m"].to_numpy(),
                    element_length_m=ell,
                    level=args.level,
                )
            sections["lever_arm"] = fit.to_dict(observation=args.lever_arm_from)
        else:
            notes.append("lever arm: too few frames with deflection angles, not fitted")

    law, law_fit = (None, None)
    if steady is not None or series:
        law, law_fit = _pick_law(args.law, steady)
    dynamic = [s for s in series if np.ptp(s.velocity_mps) > 0]
    if series and not dynamic:
        notes.append(
            "element: no deflection series with a velocity change, E and damping not identified"
        )
    if dynamic:
        base = SdofParams(
            length_m=geometry.height_mm * 1e-3,
            element_length_m=float(geometry.element_lengths[0]) * 1e-3,
            width_m=geometry.width_mm * 1e-3,
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = identify_parameters(
                dynamic,
                law=law,
                steady=steady,
                base=base,
                level=args.level,
                ci=args.ci,
                tip_velocity_feedback=not args.no_tip_feedback,
            )
        parts = result.to_sections(normal_force_N=dynamic[0].normal_force_N)
        sections["element"] = {
            **parts["element"],
            "tip_velocity_feedback": not args.no_tip_feedback,
        }
        sections["friction_law"] = parts["friction_law"]
        law = result.law
    elif law_fit is not None:
        q = float(stats.t.ppf(0.5 + 0.5 * args.level, max(law_fit.dof, 1)))
        names = [k for k in law_fit.params if k not in law_fit.fixed]
        sections["friction_law"] = {
            "law": type(law_fit.law).__name__,
            "equation": law_fit.law.equation,
            "params": law_fit.params,
            "stderr": {k: law_fit.stderr[k] for k in names},
            "ci_low": {k: law_fit.params[k] - q * law_fit.stderr[k] for k in names},
            "ci_high": {k: law_fit.params[k] + q * law_fit.stderr[k] for k in names},
            "confidence_level": args.level,
            "rmse": law_fit.rmse,
            "n_points": law_fit.n_points,
        }
    if "friction_law" in sections and steady is not None:
        sections["friction_law"]["velocity_range_mps"] = [
            float(steady.velocity_mps.min()),
            float(steady.velocity_mps.max()),
        ]
    provenance = {
        "command": "calibrate",
        "footage": [str(f) for f in folders],
        "characteristic": args.characteristic,
        "transient": list(args.transient),
        "options": {
            "preset": args.preset,
            "pressure_bar": args.pressure_bar,
            "velocity_mps": args.velocity,
            "sliding_direction": args.sliding_direction,
            "law": args.law,
            "select": {k: v for k, v in args.select},
            "lever_arm_from": args.lever_arm_from,
            "level": args.level,
            "ci": args.ci,
            "tip_velocity_feedback": not args.no_tip_feedback,
        },
        "notes": notes,
    }
    try:
        write_parameters(out, provenance=provenance, **sections)
    except ParameterFileError as exc:
        raise ValueError(str(exc)) from None
    for note in notes:
        print(f"{PROG}: note: {note}", file=sys.stderr)
    written = [k for k in ("contact", "lever_arm", "friction_law", "element") if k in sections]
    law_text = ""
    if "friction_law" in sections:
        fl = sections["friction_law"]
        law_text = f"; {fl['law']} " + ", ".join(f"{k}={v:.4g}" for k, v in fl["params"].items())
    print(f"wrote {out}: {', '.join(['geometry', *written])}{law_text}")
    return 0
