"""Calibration from measured results: pipeline tables, deflection series and a characteristic.

:func:`calibrate_from_results` is the whole identification workflow behind
``tir-contact calibrate`` as a library function with plain arguments: it reads the output
folders of the contact pipeline (``frames.csv``, ``elements.csv`` and the footage metadata),
transient tables and a steady characteristic, and returns the sections of a parameter file
(docs/formats.md "Parameter file") as a :class:`CalibratedParameters`:

* ``geometry``: the block (:func:`block_geometry_from_meta`);
* ``contact``: the real contact fraction of the TIR results
  (:func:`~friction_model.identification.coupling.contact_from_pipeline`);
* ``lever_arm``: e(phi) of Eq. 5.21 fitted to the TIR results
  (:func:`~friction_model.identification.coupling.fit_lever_arm`);
* ``friction_law``: mu(v) fitted to the characteristic (its repeated runs where there are
  any), the law chosen by :func:`choose_friction_law`, with its reduced chi-square against
  the replicate noise and intervals widened by any misfit;
* ``element``: E and the loss factor identified together with the law from deflection
  series with a velocity change
  (:func:`~friction_model.identification.identify.identify_parameters`).
"""

from __future__ import annotations

import json
import math
import os
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from friction_model.contact import laws
from friction_model.discrepancy import read_transient_table
from friction_model.dynamics.rigid import SdofParams
from friction_model.geometry import BlockGeometry, reference_block
from friction_model.identification.coupling import (
    MeasuredContact,
    contact_from_pipeline,
    fit_lever_arm,
    lever_arm_observations,
    read_pipeline_tables,
)
from friction_model.identification.identify import (
    DeflectionSeries,
    SteadyCharacteristic,
    deflection_series_from_pipeline,
    identify_parameters,
    read_characteristic,
)
from friction_model.identification.law_choice import (
    AUTO_LAWS,
    LawChoice,
    LawUndecidable,
    choose_law,
    law_interval,
)
from friction_model.params_file import SECTIONS, ParameterFileError, write_parameters

__all__ = [
    "AUTO_LAWS",
    "CalibratedParameters",
    "LawUndecidable",
    "block_geometry_from_meta",
    "block_normal_force_N",
    "calibrate_from_results",
    "choose_friction_law",
    "footage_meta",
]

#: Starting parameters of each law when there is no characteristic to fit it to.
_DEFAULT_LAW_PARAMS: dict[str, dict[str, float]] = {
    "ConstantLaw": {"mu0": 0.15},
    "DecreasingSqrtLaw": {"A_D": 0.05, "B_D": 0.1},
    "IncreasingSqrtLaw": {"A_I": 0.01, "B_I": 0.1},
    "ExponentialLaw": {"a1": 0.1, "a2": 0.1, "a3": -0.5},
    "ArctanExponentialLaw": {"k1": 0.1, "k2": 0.1, "k3": -0.5, "k4": 100.0},
}
#: Sections of the parameter file, in the order of the summary.
_RESULT_SECTIONS = tuple(s for s in SECTIONS if s != "geometry")


@dataclass(frozen=True)
class CalibratedParameters:
    """The result of :func:`calibrate_from_results`: the sections of a parameter file.

    Attributes
    ----------
    sections : dict
        ``geometry`` always; ``contact``, ``lever_arm``, ``friction_law`` and ``element``
        where the data allowed (keys and units as in docs/formats.md "Parameter file").
    notes : tuple of str
        What was skipped and why (one line each).
    geometry : BlockGeometry
        The block the results were scaled with.
    provenance : dict
        Inputs and options, for the parameter file's ``provenance``.
    """

    sections: dict[str, Any]
    notes: tuple[str, ...]
    geometry: BlockGeometry
    provenance: dict[str, Any] = field(default_factory=dict)

    @property
    def identified(self) -> list[str]:
        """The sections identified from the data (``geometry`` not counted), in file order."""
        return [k for k in _RESULT_SECTIONS if k in self.sections]

    def summary(self) -> str:
        """The sections written and the friction law's parameters, in one line."""
        law_text = ""
        if "friction_law" in self.sections:
            fl = self.sections["friction_law"]
            law_text = f"; {fl['law']} " + ", ".join(
                f"{k}={v:.4g}" for k, v in fl["params"].items()
            )
            if "rmse" in fl and "n_points" in fl:
                law_text += f" (RMSE {fl['rmse']:.2g} over {fl['n_points']} points"
                if "reduced_chi2" in fl:
                    law_text += (f", noise {fl['noise_sigma']:.2g} from "
                                 f"{fl['noise_source']}, reduced chi-square "
                                 f"{fl['reduced_chi2']:.3g}")
                law_text += ")"
            if fl.get("selection") and fl["selection"] != "named (--law)":
                law_text += f"; chosen: {fl['selection']}"
        return f"{', '.join(['geometry', *self.identified])}{law_text}"

    def write(self, path: str | os.PathLike[str]) -> Path:
        """Write the parameter file (atomically).

        Raises
        ------
        ValueError
            A section the file format rejects, or a missing folder (the message names it).
        """
        try:
            return write_parameters(path, provenance=self.provenance, **self.sections)
        except ParameterFileError as exc:
            raise ValueError(str(exc)) from None


def footage_meta(folder: str | os.PathLike[str]) -> dict[str, Any]:
    """The metadata of a pipeline output folder.

    ``meta.json`` beside the results (or in their parent folder), else the ``meta`` that
    ``tir-contact analyze`` recorded in ``summary.json``; empty without either.

    Raises
    ------
    ValueError
        A metadata file that is not valid JSON (naming it).
    """
    folder = Path(folder)
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


def block_geometry_from_meta(
    meta: Mapping[str, Any], preset: str | None = None
) -> BlockGeometry:
    """The block of a footage: a preset, else the metadata's ``block``, else G3.

    The element lengths are :attr:`BlockGeometry.element_lengths` (the metadata's
    ``block.element_lengths_mm`` where given, else equal elements).

    Parameters
    ----------
    meta : mapping
        Footage metadata (:func:`footage_meta`); ``block.preset``, or all of
        ``block.length_mm, width_mm, n_sipes, sipe_width_mm, height_mm``.
    preset : str, optional
        Reference block G0/G3/G5/G6/G7, taking precedence over the metadata.

    Returns
    -------
    BlockGeometry

    Raises
    ------
    ValueError
        An unknown preset, or a block the geometry rejects.

    Examples
    --------
    >>> block_geometry_from_meta({}).n_elements
    4
    >>> block_geometry_from_meta({"block": {"preset": "G7"}}).n_sipes
    7
    """
    if preset is not None:
        return reference_block(preset)
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


def block_normal_force_N(pressure_bar: float, geometry: BlockGeometry) -> float:
    """Normal force on the block from the nominal pressure, ``F_N = p L w``, N.

    The nominal pressure acts on the footprint including the sipes
    (:attr:`BlockGeometry.nominal_area_mm2`), as the rig defines it.

    Examples
    --------
    >>> block_normal_force_N(0.5, reference_block("G3"))  # 0.5 bar on 20 mm x 80 mm
    80.0
    """
    return pressure_bar * 1e5 * geometry.nominal_area_mm2 * 1e-6


def choose_friction_law(
    name: str, steady: SteadyCharacteristic | None
) -> tuple[laws.FrictionLaw, LawChoice | None]:
    """A friction law fitted to the characteristic, or a default law without one.

    Parameters
    ----------
    name : str
        A law of :mod:`friction_model.contact.laws` (its class name), or ``"auto"``: the
        laws of :data:`AUTO_LAWS` are fitted and one is chosen by
        :func:`~friction_model.identification.law_choice.choose_law` (laws the data
        contradict are out; AICc ranks the rest; parsimony within
        :data:`~friction_model.identification.law_choice.AICC_MARGIN`).
    steady : SteadyCharacteristic or None
        The characteristic; None gives the law (``auto``: DecreasingSqrtLaw) with default
        starting parameters.

    Returns
    -------
    law : FrictionLaw
    choice : LawChoice or None
        The fit of the chosen law, its quality and why it was chosen (None without a
        characteristic).

    Raises
    ------
    LawUndecidable
        ``auto`` when the data cannot tell the laws in play apart (a ValueError naming them).
    ValueError
        The named law cannot be fitted, or (``auto``) none can.
    """
    if steady is None:
        cls = laws.DecreasingSqrtLaw if name == "auto" else getattr(laws, name)
        return cls(**_DEFAULT_LAW_PARAMS[cls.__name__]), None
    choice = choose_law(steady, name, AUTO_LAWS)
    return choice.fit.law, choice


@dataclass
class _Gathered:
    """What the footage folders and transient tables gave, before any fit."""

    contacts: list[MeasuredContact] = field(default_factory=list)
    observations: list[pd.DataFrame] = field(default_factory=list)
    series: list[DeflectionSeries] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class _Options:
    """The options of :func:`calibrate_from_results` that the steps share."""

    pressure_bar: float | None
    velocity_mps: float | None
    sliding_direction: str | None
    lever_arm_from: str
    level: float
    ci: str
    tip_velocity_feedback: bool


@dataclass(frozen=True)
class _Results:
    """One pipeline output folder: its tables, metadata and nominal pressure (bar)."""

    folder: Path
    frames: pd.DataFrame
    elements: pd.DataFrame
    meta: Mapping[str, Any]
    pressure_bar: float | None


def _has_contact(frames: pd.DataFrame, elements: pd.DataFrame, meta: Mapping[str, Any]) -> bool:
    """Whether a result folder holds TIR contact (contact lengths above zero)."""
    return bool(
        "contact_length_mm" in elements
        and "n_elements_in_contact" in frames
        and np.nanmax(
            pd.to_numeric(elements["contact_length_mm"], errors="coerce").to_numpy(float),
            initial=0.0,
        )
        > 0
        and str(meta.get("view", "tir")).lower() == "tir"
    )


def _gather_contact(
    res: _Results, geometry: BlockGeometry, opts: _Options, into: _Gathered
) -> None:
    """The measured contact of one TIR result folder and its lever-arm observations."""
    folder, elements, meta, p_bar = res.folder, res.elements, res.meta, res.pressure_bar
    fn_block = None if p_bar is None else block_normal_force_N(p_bar, geometry)
    try:
        width = None
        if meta.get("width_px") and meta.get("mm_per_px"):
            width = float(meta["width_px"]) * float(meta["mm_per_px"])
        measured = contact_from_pipeline(
            res.frames, elements, geometry=geometry, normal_force_N=fn_block, image_width_mm=width
        )
    except ValueError as exc:
        raise ValueError(f"{folder}: {exc}") from None
    into.contacts.append(measured)
    direction = opts.sliding_direction or meta.get("sliding_direction")
    if direction is None:
        into.notes.append(f"{folder}: no sliding direction, lever arm skipped")
        return
    into.observations.append(
        lever_arm_observations(
            elements,
            geometry=geometry,
            sliding_direction=str(direction).lower(),
            method=opts.lever_arm_from,
            frames=measured.frames,
        )
    )


def _gather_side_view(
    res: _Results, geometry: BlockGeometry, opts: _Options, into: _Gathered
) -> None:
    """The deflection series of element 0 of one side-view result folder."""
    folder, elements, meta, p_bar = res.folder, res.elements, res.meta, res.pressure_bar
    angles = pd.to_numeric(elements.get("deflection_angle_deg"), errors="coerce")
    if not (
        str(meta.get("view", "")).lower() == "side"
        and angles is not None
        and np.isfinite(angles).sum() >= 4
    ):
        return
    v = opts.velocity_mps or (meta.get("conditions") or {}).get("velocity_mps")
    if v is None or p_bar is None:
        into.notes.append(f"{folder}: side view without velocity or pressure, not used")
        return
    into.series.append(
        deflection_series_from_pipeline(
            elements,
            velocity_mps=float(v),
            normal_force_N=block_normal_force_N(p_bar, geometry) / geometry.n_elements,
            element=0,
            name=str(folder),
        )
    )


def _gather(
    folders: Sequence[Path],
    metas: Sequence[Mapping[str, Any]],
    transient: Sequence[Path],
    geometry: BlockGeometry,
    opts: _Options,
) -> _Gathered:
    """Contact, lever-arm observations and deflection series of every input."""
    got = _Gathered()
    for folder, meta in zip(folders, metas, strict=True):
        frames, elements = read_pipeline_tables(folder)
        p_bar = opts.pressure_bar
        if p_bar is None:
            p = (meta.get("conditions") or {}).get("pressure_bar")
            p_bar = None if p is None else float(p)
        res = _Results(folder, frames, elements, meta, p_bar)
        if _has_contact(frames, elements, meta):
            _gather_contact(res, geometry, opts, got)
        _gather_side_view(res, geometry, opts, got)
    if transient and opts.pressure_bar is None:  # before any table is read
        raise ValueError(f"{transient[0]}: a pressure (pressure_bar) is needed for a transient "
                         "table")
    for path in transient:
        table = read_transient_table(path)  # any CSV dialect; errors name file, column, row
        got.series.append(
            DeflectionSeries(
                time_s=table["time_s"].to_numpy(float),
                angle_deg=table["angle_deg"].to_numpy(float),
                velocity_mps=table["velocity_mps"].to_numpy(float),
                normal_force_N=block_normal_force_N(opts.pressure_bar, geometry)
                / geometry.n_elements,
                name=Path(path).name,
            )
        )
    return got


def _geometry_section(geometry: BlockGeometry) -> dict[str, Any]:
    """The ``geometry`` section of the parameter file."""
    return {
        "length_mm": geometry.length_mm,
        "width_mm": geometry.width_mm,
        "n_sipes": geometry.n_sipes,
        "sipe_width_mm": geometry.sipe_width_mm,
        "height_mm": geometry.height_mm,
        "element_lengths_mm": geometry.element_lengths.tolist(),
    }


def _contact_section(contacts: Sequence[MeasuredContact], geometry: BlockGeometry) -> dict:
    """The ``contact`` section: one result as it is, several weighted by their frames."""
    if len(contacts) == 1:
        return contacts[0].to_dict()
    weights = np.array([c.n_frames for c in contacts], dtype=float)
    frac = float(np.average([c.contact_fraction for c in contacts], weights=weights))
    return {
        "contact_fraction": frac,
        "contact_fraction_std": float(np.std([c.contact_fraction for c in contacts], ddof=1)),
        "contact_fraction_per_element": np.average(
            [c.contact_fraction_per_element for c in contacts], axis=0, weights=weights
        ).tolist(),
        "contact_ratio": frac * geometry.rubber_area_mm2 / geometry.nominal_area_mm2,
        "real_contact_area_mm2": frac * geometry.rubber_area_mm2,
        "n_frames": int(weights.sum()),
    }


def _lever_arm_section(
    observations: Sequence[pd.DataFrame], geometry: BlockGeometry, opts: _Options
) -> dict[str, Any] | None:
    """The ``lever_arm`` section (Eq. 5.21), None with too few varied observations."""
    obs = pd.concat(observations, ignore_index=True)
    if not (len(obs) >= 5 and np.ptp(obs["phi_rad"].to_numpy()) > 0):
        return None
    ell = float(np.mean(geometry.element_lengths)) * 1e-3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fit_lever_arm(
            obs["phi_rad"].to_numpy(),
            obs["lever_arm_m"].to_numpy(),
            element_length_m=ell,
            level=opts.level,
        )
    return fit.to_dict(observation=opts.lever_arm_from)


def _law_fit_section(choice: LawChoice, level: float) -> dict[str, Any]:
    """The ``friction_law`` section of a law fitted to the characteristic alone: the
    parameters, intervals widened by the misfit, the fit's quality and why the law."""
    fit, quality = choice.fit, choice.quality
    section: dict[str, Any] = {
        "law": choice.name,
        "equation": fit.law.equation,
        "params": fit.params,
        **law_interval(fit, quality, level),
        "confidence_level": level,
        "rmse": fit.rmse,
        "n_points": fit.n_points,
        "noise_source": quality.noise_source,
        "interval_scale": quality.interval_scale,
        "selection": choice.rule,
        "aicc": {k: c["aicc"] for k, c in choice.candidates.items()},
    }
    if math.isfinite(quality.noise_sigma):
        section["noise_sigma"] = quality.noise_sigma
    if quality.noise_dof is not None:
        section["noise_dof"] = quality.noise_dof
    if math.isfinite(quality.reduced_chi2):
        section["reduced_chi2"] = quality.reduced_chi2
    if quality.testable:
        section["misfit_p_value"] = quality.p_value
    return section


def _element_and_law_sections(
    law_name: str,
    steady: SteadyCharacteristic | None,
    series: Sequence[DeflectionSeries],
    geometry: BlockGeometry,
    opts: _Options,
    notes: list[str],
) -> dict[str, Any]:
    """The ``element`` and ``friction_law`` sections (section 5.4).

    The element (E, loss factor) is identified together with the law from the series with
    a velocity change; without one, the law is fitted to the characteristic alone.
    """
    if steady is None and not series:
        return {}
    law, law_fit = choose_friction_law(law_name, steady)
    if law_fit is not None:
        notes.extend(f"friction law: {note}" for note in law_fit.notes)
    dynamic = [s for s in series if np.ptp(s.velocity_mps) > 0]
    if series and not dynamic:
        notes.append(
            "element: no deflection series with a velocity change, E and damping not identified"
        )
    out: dict[str, Any] = {}
    if dynamic:
        base = SdofParams(
            length_m=geometry.height_mm * 1e-3,
            element_length_m=float(geometry.element_lengths[0]) * 1e-3,
            width_m=geometry.width_mm * 1e-3,
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = identify_parameters(
                dynamic, law=law, steady=steady, base=base, level=opts.level, ci=opts.ci,
                tip_velocity_feedback=opts.tip_velocity_feedback,
            )
        parts = result.to_sections(normal_force_N=dynamic[0].normal_force_N)
        out["element"] = {
            **parts["element"], "tip_velocity_feedback": opts.tip_velocity_feedback,
        }
        out["friction_law"] = parts["friction_law"]
    elif law_fit is not None:
        out["friction_law"] = _law_fit_section(law_fit, opts.level)
    # the velocities the law rests on: the characteristic's, else the velocity steps'
    # (a law from the steps alone is extrapolated beyond them as much as a fitted one)
    rests_on = ([steady.velocity_mps] if steady is not None
                else [np.asarray(s.velocity_mps, float) for s in dynamic])
    if "friction_law" in out and rests_on:
        out["friction_law"]["velocity_range_mps"] = [
            float(min(np.min(v) for v in rests_on)),
            float(max(np.max(v) for v in rests_on)),
        ]
    return out


def calibrate_from_results(
    folders: Sequence[str | os.PathLike[str]] = (),
    characteristic: str | os.PathLike[str] | None = None,
    transient: Sequence[str | os.PathLike[str]] = (),
    *,
    preset: str | None = None,
    pressure_bar: float | None = None,
    velocity_mps: float | None = None,
    sliding_direction: str | None = None,
    law: str = "auto",
    select: Mapping[str, Any] | None = None,
    lever_arm_from: str = "front_peak",
    level: float = 0.95,
    ci: str = "profile",
    tip_velocity_feedback: bool = True,
) -> CalibratedParameters:
    """Identify the model's parameters from measured results (section 5.4).

    TIR result folders give the real contact fraction, area and local pressure and, with
    deflection angles, the lever arm e(phi) of Eq. 5.21; side-view result folders give the
    deflection series of element 0; transient tables give deflection series; the steady
    characteristic gives mu(v). The element (E, loss factor) is identified together with
    the law when a deflection series holds a velocity change.

    Parameters
    ----------
    folders : sequence of path-like
        Output folders of the contact pipeline (``frames.csv`` and ``elements.csv``); the
        metadata from :func:`footage_meta`.
    characteristic : path-like, optional
        Steady table or the evaluation's ``steady_characteristic.csv``.
    transient : sequence of path-like
        Transient tables (``time_s, velocity_mps, angle_deg``); they need `pressure_bar`.
    preset : str, optional
        Reference block G0/G3/G5/G6/G7 (default: the first folder's metadata, else G3).
    pressure_bar : float, optional
        Nominal pressure F_N / (L w), bar (default: each folder's metadata).
    velocity_mps : float, optional
        Sliding velocity of the footage, m/s (default: the metadata).
    sliding_direction : {"left", "right"}, optional
        Direction the block moves in the image (default: the metadata).
    law : str
        A law's class name, or ``"auto"`` (:func:`choose_friction_law`).
    select : mapping, optional
        Use only characteristic rows with these column values.
    lever_arm_from : {"front_peak", "contact_centroid"}
        Lever-arm observation from the TIR results.
    level : float
        Confidence level of the intervals, in (0, 1).
    ci : {"profile", "jacobian", "bootstrap"}
        Interval of the element parameters.
    tip_velocity_feedback : bool
        Whether friction follows the tip's motion as well as the carriage velocity.

    Returns
    -------
    CalibratedParameters

    Raises
    ------
    ValueError
        No input, an input that cannot be used (the message names the file), or a fit
        that fails.
    """
    given_transient = [os.fspath(p) for p in transient]
    folders = [Path(f) for f in folders]
    transient = [Path(p) for p in transient]
    if not (folders or characteristic or transient):
        raise ValueError("give at least one of: footage folders, a characteristic, "
                         "transient tables")
    if select and not characteristic:
        raise ValueError("select needs a characteristic")
    opts = _Options(pressure_bar, velocity_mps, sliding_direction, lever_arm_from, level, ci,
                    tip_velocity_feedback)
    metas = [footage_meta(f) for f in folders]
    geometry = block_geometry_from_meta(metas[0] if metas else {}, preset)
    got = _gather(folders, metas, transient, geometry, opts)
    steady = None
    if characteristic:
        steady = read_characteristic(characteristic, select=dict(select or {}) or None)
    sections: dict[str, Any] = {"geometry": _geometry_section(geometry)}
    if got.contacts:
        sections["contact"] = _contact_section(got.contacts, geometry)
    if got.observations:
        lever = _lever_arm_section(got.observations, geometry, opts)
        if lever is None:
            got.notes.append("lever arm: too few frames with deflection angles, not fitted")
        else:
            sections["lever_arm"] = lever
    sections.update(
        _element_and_law_sections(law, steady, got.series, geometry, opts, got.notes)
    )
    provenance = {
        "command": "calibrate",
        "footage": [str(f) for f in folders],
        "characteristic": None if characteristic is None else os.fspath(characteristic),
        "transient": given_transient,
        "options": {
            "preset": preset,
            "pressure_bar": pressure_bar,
            "velocity_mps": velocity_mps,
            "sliding_direction": sliding_direction,
            "law": law,
            "select": dict(select or {}),
            "lever_arm_from": lever_arm_from,
            "level": level,
            "ci": ci,
            "tip_velocity_feedback": tip_velocity_feedback,
        },
        "notes": list(got.notes),
    }
    return CalibratedParameters(sections, tuple(got.notes), geometry, provenance)
