"""The calibrated-parameter file: JSON written by ``tir-contact calibrate``, read by
``tir-contact simulate`` and the discrepancy workflow.

One UTF-8 JSON object with a schema name and version, a provenance record and up to five
sections, each optional (a calibration fills what its inputs determine)::

    {"schema": "tir-contact/parameters", "schema_version": 1,
     "provenance": {...}, "geometry": {...}, "contact": {...}, "lever_arm": {...},
     "friction_law": {...}, "element": {...}}

Units are in the key names (SI unless the name says ``_mm``, ``_mm2``, ``_deg``, ``_pct``).
Every value is checked on writing and on reading; a bad file gives a
:class:`ParameterFileError` whose one-line message names the file and the key. Files are
written atomically (a temporary file beside the target, then :func:`os.replace`).
"""

from __future__ import annotations

import datetime as _dt
import json
import os
from collections.abc import Mapping
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

from friction_model.contact import laws
from friction_model.dynamics.rigid import SdofParams
from tir_common.atomic import atomic_write, json_safe
from tir_common.schema import Field, FieldError, Schema

__all__ = [
    "SCHEMA",
    "SCHEMA_VERSION",
    "SECTIONS",
    "ParameterFileError",
    "friction_law_from",
    "lever_arm_kwargs_from",
    "read_parameters",
    "sdof_params_from",
    "write_parameters",
]

#: Value of the top-level ``schema`` key.
SCHEMA = "tir-contact/parameters"
#: Version of the layout below; readers refuse newer versions.
SCHEMA_VERSION = 1

# Shorthand of the rules below: "number>0", "number>=0", "fraction" (a number in [0, 1]),
# "int>=0", "number" (finite), "text", "bool", "numbers" (list of numbers), "mapping"
# (name -> number or null).
_RULES: dict[str, dict[str, Any]] = {
    "number>0": {"kind": "number", "low": 0.0, "low_open": True},
    "number>=0": {"kind": "number", "low": 0.0},
    "fraction": {"kind": "number", "low": 0.0, "high": 1.0},
    "int>=0": {"kind": "integer", "low": 0},
    "number": {"kind": "number"},
    "text": {"kind": "text"},
    "bool": {"kind": "bool"},
    "numbers": {"kind": "numbers"},
    "mapping": {"kind": "mapping"},
}


def _field(key: str, rule: str, required: bool, description: str = "") -> Field:
    """A :class:`~tir_common.schema.Field` from the shorthand ``rule``; the unit is in ``key``."""
    return Field(key, required=required, description=description, **_RULES[rule])


#: The sections of the file: every key with its rule and whether it is required.
_SPEC: dict[str, Schema] = {
    "geometry": Schema(
        "geometry",
        (
            _field("length_mm", "number>0", True),
            _field("width_mm", "number>0", True),
            _field("n_sipes", "int>=0", True),
            _field("sipe_width_mm", "number>=0", True),
            _field("height_mm", "number>0", True),
            _field("element_lengths_mm", "numbers", False),
        ),
    ),
    "contact": Schema(
        "contact",
        (
            _field("contact_fraction", "fraction", True),
            _field("contact_fraction_std", "number>=0", False),
            _field("contact_fraction_per_element", "numbers", False),
            _field("contact_ratio", "fraction", False),
            _field("real_contact_area_mm2", "number>0", False),
            _field("normal_force_N", "number>0", False),
            _field("nominal_pressure_Pa", "number>0", False),
            _field("pressure_local_Pa", "number>0", False),
            _field("n_frames", "int>=0", False),
        ),
    ),
    "lever_arm": Schema(
        "lever_arm",
        (
            _field("e1", "number", True),
            _field("e2_per_rad", "number>=0", True),
            _field("e3_m", "number", True),
            _field("e4_m", "number", True),
            _field("element_length_m", "number>0", True),
            _field("observation", "text", False),
            _field("stderr", "mapping", False),
            _field("ci_low", "mapping", False),
            _field("ci_high", "mapping", False),
            _field("confidence_level", "fraction", False),
            _field("rmse_m", "number>=0", False),
            _field("n_points", "int>=0", False),
        ),
    ),
    "friction_law": Schema(
        "friction_law",
        (
            _field("law", "text", True),
            _field("params", "mapping", True),
            _field("equation", "text", False),
            _field("stderr", "mapping", False),
            _field("ci_low", "mapping", False),
            _field("ci_high", "mapping", False),
            _field("confidence_level", "fraction", False),
            _field("rmse", "number>=0", False),
            _field("n_points", "int>=0", False),
            _field("velocity_range_mps", "numbers", False),
            _field("noise_source", "text", False,
                   "where the noise came from: replicates, given (mu_std) or residuals"),
            _field("noise_sigma", "number>0", False, "noise of one point"),
            _field("noise_dof", "int>=0", False, "degrees of freedom of the noise estimate"),
            _field("reduced_chi2", "number>=0", False,
                   "chi2 / (n - k) against the noise (absent when untestable)"),
            _field("misfit_p_value", "fraction", False,
                   "chi-square tail probability of the residuals under the noise"),
            _field("interval_scale", "number>0", False,
                   "factor on the standard errors, sqrt(max(1, reduced_chi2))"),
            _field("selection", "text", False, "why this law (auto) or 'named (--law)'"),
            _field("aicc", "mapping", False, "AICc of each candidate law (null: undefined)"),
        ),
    ),
    "element": Schema(
        "element",
        (
            _field("youngs_modulus_Pa", "number>0", True),
            _field("loss_factor", "number>=0", True),
            _field("density_kg_m3", "number>0", True),
            _field("height_m", "number>0", True),
            _field("element_length_m", "number>0", True),
            _field("width_m", "number>0", True),
            _field("normal_force_N", "number>=0", False),
            _field("relaxation_time_s", "number>=0", False),
            _field("tip_velocity_feedback", "bool", False),
            _field("natural_frequency_Hz", "number>0", False),
            _field("stderr", "mapping", False),
            _field("ci_low", "mapping", False),
            _field("ci_high", "mapping", False),
            _field("ci_method", "text", False),
            _field("confidence_level", "fraction", False),
            _field("rmse_deg", "number>=0", False),
            _field("n_points", "int>=0", False),
        ),
    ),
}
#: The optional sections of the file and their keys.
SECTIONS = tuple(_SPEC)
_PROVENANCE = Field("provenance", "object", "who wrote the file, when, from which inputs")


class ParameterFileError(ValueError):
    """A parameter file that cannot be read or written; the message names file and key."""


def _fail(path: Path | str, key: str, what: str) -> ParameterFileError:
    return ParameterFileError(f"{path}: '{key}' {what}")


def _check_section(path: Path | str, name: str, section: Any) -> dict[str, Any]:
    try:
        out = _SPEC[name].check(section, prefix=f"{name}.")
    except FieldError as exc:
        raise ParameterFileError(f"{path}: {exc}") from None
    if name == "geometry":
        lengths = out.get("element_lengths_mm")
        if lengths is not None and len(lengths) != out["n_sipes"] + 1:
            raise _fail(
                path,
                "geometry.element_lengths_mm",
                f"must have n_sipes + 1 = {out['n_sipes'] + 1} entries, got {len(lengths)}",
            )
    if name == "friction_law":
        cls = getattr(laws, out["law"], None)
        if not (isinstance(cls, type) and issubclass(cls, laws.FrictionLaw)):
            known = sorted(
                n
                for n in laws.__all__
                if isinstance(getattr(laws, n), type)
                and issubclass(getattr(laws, n), laws.FrictionLaw)
                and n != "FrictionLaw"
            )
            raise _fail(
                path, "friction_law.law", f"must name a friction law {known}, got {out['law']!r}"
            )
        missing = [p for p in cls.param_names if out["params"].get(p) is None]
        if missing:
            raise _fail(path, f"friction_law.params.{missing[0]}", f"is missing (law {out['law']})")
    return out


def _validate(path: Path | str, doc: Any) -> dict[str, Any]:
    if not isinstance(doc, Mapping):
        raise ParameterFileError(
            f"{path}: expected a JSON object {{...}} at the top, got {type(doc).__name__}"
        )
    if doc.get("schema") != SCHEMA:
        raise _fail(path, "schema", f"must be {SCHEMA!r}, got {doc.get('schema')!r}")
    version = doc.get("schema_version")
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise _fail(path, "schema_version", f"must be an integer >= 1, got {version!r}")
    if version > SCHEMA_VERSION:
        raise _fail(
            path,
            "schema_version",
            f"is {version}, newer than this reader's {SCHEMA_VERSION}: update tir-contact",
        )
    out: dict[str, Any] = {"schema": SCHEMA, "schema_version": version}
    prov = doc.get("provenance", {})
    try:
        out["provenance"] = _PROVENANCE.check(prov)
    except FieldError as exc:
        raise ParameterFileError(f"{path}: {exc}") from None
    for name in SECTIONS:
        if doc.get(name) is not None:
            out[name] = _check_section(path, name, doc[name])
    unknown = sorted(set(doc) - {"schema", "schema_version", "provenance", *SECTIONS})
    if unknown:
        raise _fail(path, unknown[0], f"is not a known top-level key ({['provenance', *SECTIONS]})")
    if not any(name in out for name in SECTIONS):
        raise ParameterFileError(f"{path}: holds none of the sections {list(SECTIONS)}")
    return out


def write_parameters(
    path: str | os.PathLike[str],
    *,
    geometry: Mapping[str, Any] | None = None,
    contact: Mapping[str, Any] | None = None,
    lever_arm: Mapping[str, Any] | None = None,
    friction_law: Mapping[str, Any] | None = None,
    element: Mapping[str, Any] | None = None,
    provenance: Mapping[str, Any] | None = None,
) -> Path:
    """Write a parameter file atomically.

    Parameters
    ----------
    path : path-like
        Target ``.json`` file; its folder must exist.
    geometry, contact, lever_arm, friction_law, element : mapping, optional
        The sections (keys in :data:`SECTIONS`, see docs/formats.md "Parameter file");
        at least one. Numpy values are converted; non-finite numbers become ``null``.
    provenance : mapping, optional
        Free-form record of how the parameters were obtained (inputs, options); the
        package, its version and the UTC time are added.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ParameterFileError
        If a section is malformed (the message names the key) or the folder is missing.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "params.json"
    >>> _ = write_parameters(p, friction_law={"law": "ConstantLaw", "params": {"mu0": 0.12}})
    >>> read_parameters(p)["friction_law"]["params"]
    {'mu0': 0.12}
    """
    path = Path(path)
    try:
        pkg_version = version("tir-contact")
    except PackageNotFoundError:  # pragma: no cover - source tree without installation
        pkg_version = "unknown"
    prov = {
        "package": "tir-contact",
        "package_version": pkg_version,
        "created_utc": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        **json_safe(dict(provenance or {})),
    }
    doc: dict[str, Any] = {"schema": SCHEMA, "schema_version": SCHEMA_VERSION, "provenance": prov}
    for name, section in zip(SECTIONS, (geometry, contact, lever_arm, friction_law, element),
                             strict=True):
        if section is not None:
            doc[name] = {k: v for k, v in json_safe(dict(section)).items() if v is not None}
    _validate(path, doc)
    if not path.parent.is_dir():
        raise ParameterFileError(f"{path}: folder {path.parent} does not exist")
    text = json.dumps(doc, indent=2, sort_keys=False, allow_nan=False) + "\n"
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def read_parameters(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read and check a parameter file.

    Parameters
    ----------
    path : path-like
        The ``.json`` file written by :func:`write_parameters` (or by hand).

    Returns
    -------
    dict
        ``schema``, ``schema_version``, ``provenance`` and the sections present, with
        numbers as float (counts as int) and undetermined values (``null``) as None.

    Raises
    ------
    ParameterFileError
        Missing file, invalid JSON, wrong schema or version, a missing, unknown or
        out-of-range key; the one-line message names the file and the key.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ParameterFileError(f"{path}: does not exist") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ParameterFileError(f"{path}: cannot be read ({exc})") from None
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ParameterFileError(f"{path}: not valid JSON ({exc})") from None
    return _validate(path, doc)


def friction_law_from(parameters: Mapping[str, Any]):
    """The :class:`~friction_model.contact.laws.FrictionLaw` of a read parameter file.

    Parameters
    ----------
    parameters : mapping
        Output of :func:`read_parameters`.

    Returns
    -------
    FrictionLaw or None
        None when the file has no ``friction_law`` section.
    """
    section = parameters.get("friction_law")
    if section is None:
        return None
    cls = getattr(laws, section["law"])
    return cls(**{k: section["params"][k] for k in cls.param_names})


def sdof_params_from(parameters: Mapping[str, Any]) -> SdofParams | None:
    """The element as :class:`~friction_model.dynamics.SdofParams` (None without ``element``).

    Parameters
    ----------
    parameters : mapping
        Output of :func:`read_parameters`.

    Returns
    -------
    SdofParams or None
        Geometry, density, E and loss factor of the file; the derived constants follow
        from them as in :class:`~friction_model.dynamics.SdofParams`.
    """
    el = parameters.get("element")
    if el is None:
        return None
    return SdofParams(
        length_m=el["height_m"],
        element_length_m=el["element_length_m"],
        width_m=el["width_m"],
        youngs_modulus_Pa=el["youngs_modulus_Pa"],
        density_kg_m3=el["density_kg_m3"],
        loss_factor=el["loss_factor"],
    )


def lever_arm_kwargs_from(parameters: Mapping[str, Any]) -> dict[str, float] | None:
    """Keyword arguments of :class:`~friction_model.dynamics.TimoshenkoParams` for e(phi).

    Parameters
    ----------
    parameters : mapping
        Output of :func:`read_parameters`.

    Returns
    -------
    dict or None
        ``e1, e2_per_rad, e3_m, e4_m, length_m`` (Eq. 5.21/5.22); None without ``lever_arm``.
    """
    la = parameters.get("lever_arm")
    if la is None:
        return None
    return {
        "e1": la["e1"],
        "e2_per_rad": la["e2_per_rad"],
        "e3_m": la["e3_m"],
        "e4_m": la["e4_m"],
        "length_m": la["element_length_m"],
    }
