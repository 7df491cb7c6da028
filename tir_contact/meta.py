"""Metadata of TIR footage: ``meta.json`` beside the footage, checked and overridable.

The file is the one written by ``tir-contact synth footage``::

    {"view": "tir", "fps": 5000.0, "mm_per_px": 0.05, "sliding_direction": "right",
     "contact_is": "dark",
     "block": {"length_mm": 20, "width_mm": 20, "n_sipes": 2, "sipe_width_mm": 0.4,
               "height_mm": 10},
     "conditions": {"velocity_mps": 0.1, "pressure_bar": 2.5, "temperature_C": -5,
                    "humidity_pct": 70, "salinity_pct": 0}}

Every known key is type-checked (:data:`META_FIELDS`, fields of :mod:`tir_common.schema`);
other keys are kept as they are.
Values given on the command line (dotted keys such as ``"block.n_sipes"``) override the file.

Notes
-----
Units are part of the key names: ``fps`` in Hz (frames per second), ``mm_per_px`` in
millimetres per pixel, ``_mm`` millimetres, ``_mps`` m/s, ``_bar`` bar, ``_C`` °C, ``_pct``
percent. ``sliding_direction`` is the direction in which the block moves relative to the ice
as seen in the image (``"right"``: towards increasing column index).
"""

from __future__ import annotations

import copy
import difflib
import json
import logging
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from tir_common.schema import Field, FieldError
from tir_contact._readers import FootageError
from tir_contact.optics import SUBSTRATE_INDEX

logger = logging.getLogger(__name__)

__all__ = [
    "DEFAULTS",
    "META_FIELDS",
    "META_FILENAME",
    "REQUIRED_KEYS",
    "check_overrides",
    "clip_footage",
    "find_meta",
    "load_meta",
    "option_flag",
    "read_meta_json",
]

#: Name of the metadata file beside the footage.
META_FILENAME = "meta.json"


def _fields(*fields: Field) -> dict[str, Field]:
    return {f.key: f for f in fields}


#: Known keys of ``meta.json`` (dotted for nested ones) and their types.
META_FIELDS: dict[str, Field] = _fields(
    Field("view", "choice", "camera view: TIR contact image or side view", choices=("tir", "side")),
    Field("fps", "number", "frame rate in Hz", unit="Hz", low=0, low_open=True),
    Field("container_fps", "number", "frame rate the video container's header states, where "
          "it cannot hold fps (an AVI written through FFmpeg holds at most 1000 frames/s)",
          unit="Hz", low=0, low_open=True),
    Field("mm_per_px", "number", "image scale in mm per pixel", unit="mm/px", low=0, low_open=True),
    Field(
        "sliding_direction",
        "choice",
        "direction the block slides relative to the ice, as seen in the image",
        choices=("left", "right"),
    ),
    Field("contact_is", "choice", "grey level of real contact", choices=("dark", "bright")),
    Field("block", "object", "tread-block geometry"),
    Field(
        "block.length_mm",
        "number",
        "block length in mm (sliding direction)",
        unit="mm",
        low=0,
        low_open=True,
    ),
    Field("block.width_mm", "number", "block width in mm", unit="mm", low=0, low_open=True),
    Field("block.n_sipes", "integer", "number of sipes", low=0),
    Field("block.sipe_width_mm", "number", "sipe width in mm", unit="mm", low=0),
    Field("block.height_mm", "number", "block height in mm", unit="mm", low=0, low_open=True),
    Field("conditions", "object", "test conditions"),
    Field("conditions.velocity_mps", "number", "sliding velocity in m/s", unit="m/s"),
    Field(
        "conditions.pressure_bar", "number", "nominal contact pressure in bar", unit="bar", low=0
    ),
    Field("conditions.temperature_C", "number", "ice or air temperature in °C", unit="degC"),
    Field(
        "conditions.humidity_pct",
        "number",
        "relative humidity in %",
        unit="%",
        low=0,
        high=100,
    ),
    Field(
        "conditions.salinity_pct",
        "number",
        "salinity of the ice in %",
        unit="%",
        low=0,
        high=100,
    ),
    Field("optics", "object", "the TIR rig's optics (full contact's darkness, Fresnel)"),
    Field(
        "optics.substrate",
        "choice",
        "what the rubber touches in the TIR image",
        choices=tuple(SUBSTRATE_INDEX),
    ),
    Field(
        "optics.incidence_deg",
        "number",
        "angle of the light in the substrate against its normal, deg",
        unit="deg",
        low=0,
        high=89.9,
    ),
    Field(
        "optics.rubber_index",
        "number",
        "refractive index of the rubber (default 1.5)",
        low=1.0,
        high=3.0,
    ),
)

#: Keys the contact analysis needs; ``view`` and ``contact_is`` have :data:`DEFAULTS`.
REQUIRED_KEYS: tuple[str, ...] = ("view", "fps", "mm_per_px", "sliding_direction", "contact_is")

#: Values used when neither ``meta.json`` nor the command line gives the key.
DEFAULTS: dict[str, Any] = {"view": "tir", "contact_is": "dark"}


def option_flag(key: str) -> str:
    """Command-line option that gives a metadata key.

    Parameters
    ----------
    key : str
        Dotted key, e.g. ``"block.n_sipes"``.

    Returns
    -------
    str
        The option, e.g. ``"--block-n-sipes"``.

    Examples
    --------
    >>> option_flag("mm_per_px")
    '--mm-per-px'
    """
    return "--" + key.replace(".", "-").replace("_", "-")


def find_meta(path: str | os.PathLike[str]) -> Path | None:
    """Locate the metadata file of some footage.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.json`` file (taken as it is), a folder (``folder/meta.json``, else the parent's
        ``meta.json`` when its ``frame_pattern`` points into this folder, as in a synthetic
        clip's ``frames/``) or a footage file (``<name>.meta.json`` beside it, as
        ``run1.tif.meta.json``, else ``<stem>.meta.json``, as ``run1.meta.json``, else
        ``meta.json`` beside it).

    Returns
    -------
    Path or None
        The metadata file, or None when there is none.
    """
    path = Path(path)
    if path.suffix.lower() == ".json":
        return path
    if path.is_dir():
        candidate = path / META_FILENAME
        if candidate.is_file():
            return candidate
        # frames/ inside a clip folder (synthetic layout)
        return path.parent / META_FILENAME if clip_footage(path.parent) == path else None
    for candidate in (path.with_name(path.name + ".meta.json"),
                      path.with_name(path.stem + ".meta.json"), path.with_name(META_FILENAME)):
        if candidate.is_file():
            return candidate
    return None


def clip_footage(folder: str | os.PathLike[str]) -> Path | None:
    """The footage a clip folder's ``meta.json`` names, if any.

    Parameters
    ----------
    folder : str or os.PathLike
        A folder that may hold a ``meta.json`` as written by ``tir-contact synth footage``.

    Returns
    -------
    Path or None
        ``folder/<video_file>``, or the sub-folder of ``frame_pattern`` (``folder/frames``);
        None when the folder has no readable ``meta.json`` naming either.
    """
    folder = Path(folder)
    meta = folder / META_FILENAME
    try:
        data = json.loads(meta.read_text(encoding="utf-8")) if meta.is_file() else None
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict):
        return None
    if isinstance(data.get("video_file"), str):
        return folder / data["video_file"]
    pattern = data.get("frame_pattern")
    if isinstance(pattern, str) and len(Path(pattern).parts) > 1:
        return folder / Path(pattern).parts[0]
    return None


def _meta_target(path: Path) -> Path:
    """Where a missing ``meta.json`` is expected, for messages."""
    if path.suffix.lower() == ".json":
        return path
    return (path if path.is_dir() else path.parent) / META_FILENAME


def _check(value: Any, field: Field, where: str, *, from_text: bool) -> Any:
    """Check (and coerce) one value; `where` starts the message (file or option)."""
    try:
        return field.check(value, from_text=from_text)
    except FieldError as exc:
        raise FootageError(f"{where} {exc}") from None


def _check_tree(data: dict[str, Any], where: str, prefix: str = "") -> None:
    """Check every known key of `data` in place; JSON null means "not given"."""
    for name in list(data):
        key = prefix + name
        if data[name] is None:
            del data[name]
            continue
        field = META_FIELDS.get(key)
        if field is None:
            continue
        data[name] = _check(data[name], field, where, from_text=False)
        if field.kind == "object":
            _check_tree(data[name], where, prefix=key + ".")


def read_meta_json(meta_path: Path) -> dict[str, Any]:
    """Read ``meta.json`` as it is; every failure is a one-line :class:`FootageError`."""
    try:
        text = meta_path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FootageError(f"{meta_path}: file does not exist", meta_path) from None
    except UnicodeDecodeError as exc:
        raise FootageError(f"{meta_path}: not UTF-8 text ({exc.reason})", meta_path) from None
    except OSError as exc:
        raise FootageError(
            f"{meta_path}: cannot be read ({exc.strerror or exc})", meta_path
        ) from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise FootageError(
            f"{meta_path}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})",
            meta_path,
        ) from None
    if not isinstance(data, dict):
        raise FootageError(
            f"{meta_path}: expected a JSON object {{...}} at the top, got {type(data).__name__}",
            meta_path,
        )
    return data


def _set_dotted(data: dict[str, Any], key: str, value: Any, where: str) -> None:
    *parents, last = key.split(".")
    node = data
    walked = []
    for name in parents:
        walked.append(name)
        child = node.setdefault(name, {})
        if not isinstance(child, dict):
            raise FootageError(
                f"{where}: cannot set '{key}' because '{'.'.join(walked)}' is not an object"
            )
        node = child
    node[last] = value


def _get_dotted(data: Mapping[str, Any], key: str) -> Any:
    node: Any = data
    for name in key.split("."):
        if not isinstance(node, Mapping) or name not in node:
            return None
        node = node[name]
    return node


def _warn_if_misspelt(key: str) -> None:
    """Warn about an override key the analysis does not read that is close to one it does
    (``mm_per_pixel``, ``blok.length_mm``): kept as given, it would change nothing. Other
    unknown keys are the user's own (an operator, a run number) and kept without a word."""
    close = difflib.get_close_matches(key, list(META_FIELDS), n=1, cutoff=0.8)
    if close:
        logger.warning("metadata override '%s' is not a key the analysis reads (did you "
                       "mean '%s'?): kept as given, it changes nothing", key, close[0])


def check_overrides(overrides: Mapping[str, Any] | None) -> dict[str, Any]:
    """Command-line metadata values, parsed and checked before any footage is read.

    Parameters
    ----------
    overrides : mapping, optional
        Values by dotted key, as for :func:`load_meta`; ``None`` values are left out.

    Returns
    -------
    dict
        The values of the known keys coerced (numbers from text, choices in lower case),
        unknown keys as given (one close to a known key is warned about: a misspelling).

    Raises
    ------
    FootageError
        One line naming the option and what it expects: a usage error, the same for every
        video (``tir-contact analyze`` stops with exit code 2 before the batch).

    Examples
    --------
    >>> check_overrides({"mm_per_px": "0.05", "fps": None})
    {'mm_per_px': 0.05}
    >>> check_overrides({"mm_per_px": "0.1mm"})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    tir_contact._readers.FootageError: option --mm-per-px: ... got '0.1mm' (str)
    """
    checked: dict[str, Any] = {}
    for key, value in (overrides or {}).items():
        if value is None:
            continue
        field = META_FIELDS.get(key)
        where = f"option {option_flag(key)}:"
        if field is None:
            _warn_if_misspelt(key)
        if field is not None:
            value = _check(value, field, where, from_text=True)
            if field.kind == "object":
                value = copy.deepcopy(value)
                _check_tree(value, where, prefix=key + ".")
        checked[key] = value
    return checked


def load_meta(
    path_or_folder: str | os.PathLike[str],
    overrides: Mapping[str, Any] | None = None,
    *,
    frame_rate: float | None = None,
    required: Sequence[str] = REQUIRED_KEYS,
) -> dict[str, Any]:
    """Read, check and complete the metadata of some footage.

    Parameters
    ----------
    path_or_folder : str or os.PathLike
        The footage (frame folder or file) or the metadata ``.json`` itself; see
        :func:`find_meta`. A footage without a metadata file is fine as long as `overrides`,
        `frame_rate` and :data:`DEFAULTS` give every `required` key.
    overrides : mapping, optional
        Values from the command line by dotted key (``{"fps": 5000, "block.n_sipes": 3}``);
        they win over the file. ``None`` values are ignored (options not given); strings are
        parsed for numeric keys.
    frame_rate : float, optional
        Frame rate from the footage header in Hz (``reader.frame_rate``): the ``fps`` when
        neither the file nor `overrides` gives one.
    required : sequence of str
        Keys that must end up with a value (default :data:`REQUIRED_KEYS`).

    Returns
    -------
    dict
        The nested metadata, as in ``meta.json``, with numbers as float (int for
        ``block.n_sipes``), choices in lower case and defaults filled in.

    Raises
    ------
    FootageError
        One line naming the file (or option) and the key: the file is not JSON, a value has
        the wrong type or range, or a required key is missing (saying how to give it).

    Notes
    -----
    Precedence per key: `overrides`, then ``meta.json``, then `frame_rate` (``fps`` only), then
    :data:`DEFAULTS`. A header frame rate that differs from ``meta.json`` is logged as a
    warning and the file's value is used (no warning where the file's ``container_fps``
    states the header's rate).
    """
    path = Path(path_or_folder)
    meta_path = find_meta(path)
    data: dict[str, Any] = {}
    if meta_path is not None:
        data = read_meta_json(meta_path)
        _check_tree(data, f"{meta_path}:")
    file_fps = data.get("fps")

    for key, value in check_overrides(overrides).items():
        _set_dotted(data, key, value, f"option {option_flag(key)}:")

    if frame_rate is not None and frame_rate > 0:
        if "fps" not in data:
            data["fps"] = float(frame_rate)
        elif file_fps is not None and data["fps"] == file_fps:
            # a header the file itself says cannot hold the rate (container_fps) is no news
            header = data.get("container_fps")
            known = header is not None and math.isclose(header, frame_rate, rel_tol=1e-6)
            if not known and not math.isclose(file_fps, frame_rate, rel_tol=1e-6):
                logger.warning(
                    "%s gives fps %g, the footage header %g Hz: using %g",
                    meta_path,
                    file_fps,
                    frame_rate,
                    file_fps,
                )
    for key, value in DEFAULTS.items():
        data.setdefault(key, value)

    missing = [key for key in required if _get_dotted(data, key) is None]
    if missing:
        raise FootageError(_missing_message(path, meta_path, missing), meta_path or path)
    return data


def _missing_message(path: Path, meta_path: Path | None, missing: list[str]) -> str:
    """One line naming every required key that neither the metadata file nor the options
    give, and how to give each (all at once: a user should not find them one run at a
    time)."""
    keys = ", ".join(f"'{k}'" for k in missing)
    how = "pass " + ", ".join(option_flag(k) for k in missing)
    if "fps" in missing:
        how += " (the footage header gives no frame rate)"
    it = "it" if len(missing) == 1 else "them"
    if meta_path is not None:
        return f"{meta_path} has no {keys}: add {it} to {meta_path.name} or {how}"
    target = str(_meta_target(path))
    if path.is_file() and path.suffix.lower() != ".json":  # one file's own metadata too
        target += f" (or {path.name}.meta.json for this file alone)"
    return (f"{path}: no {META_FILENAME} beside the footage gives {keys}: "
            f"add {it} to {target} or {how}")
