"""Photron camera information headers: ``.cih`` (text) and ``.cihx`` (XML) files.

Both describe the ``.mraw`` data file of the same name. They are read into one dictionary
keyed by the ``.cih`` names, so the reader does not care which one it got:

* ``.cih``: text lines ``Key : Value`` (``#`` lines are section titles); the camera
  information section ends at the first blank line, after which the viewer software
  appends version lists that are not read. A value is an int when it is an integer, a
  float when it parses as one, else the text (``"1/800000"``, ``"2.0.0.0"``).
* ``.cihx``: a binary preamble, then an XML document whose root element is ``<cih>``.
  Only the text from ``<cih>`` to ``</cih>`` is parsed (so no document type declaration
  or entity is ever read). The elements are mapped to the ``.cih`` keys, see
  :data:`CIHX_FIELDS`.

The element and key names are those written by Photron FASTCAM Viewer, as seen in the
pyMRAW project's sample files and its reader.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

__all__ = ["CIHX_FIELDS", "CihFormatError", "parse_cih_text", "parse_cihx_bytes", "read_cih"]

#: ``.cih`` key, the ``.cihx`` element path under ``<cih>``, whether the reader needs it
#: and the type of its value.
CIHX_FIELDS: tuple[tuple[str, str, bool, type], ...] = (
    ("Date", "fileInfo/date", False, str),
    ("Camera Type", "deviceInfo/deviceName", False, str),
    ("Record Rate(fps)", "recordInfo/recordRate", True, float),
    ("Total Frame", "frameInfo/totalFrame", True, int),
    ("Original Total Frame", "frameInfo/recordedFrame", False, int),
    ("Start Frame", "frameInfo/startFrame", False, int),
    ("Correct Trigger Frame", "frameInfo/correctTriggerFrame", False, int),
    ("Image Width", "imageDataInfo/resolution/width", True, int),
    ("Image Height", "imageDataInfo/resolution/height", True, int),
    ("Color Type", "imageDataInfo/colorInfo/type", False, str),
    ("Color Bit", "imageDataInfo/colorInfo/bit", True, int),
    ("File Format", "imageFileInfo/fileFormat", True, str),
    ("EffectiveBit Depth", "imageDataInfo/effectiveBit/depth", False, int),
    ("EffectiveBit Side", "imageDataInfo/effectiveBit/side", False, str),
    ("Comment Text", "basicInfo/comment", False, str),
)

_INTEGER = re.compile(r"[+-]?\d+")


class CihFormatError(ValueError):
    """The header file cannot be parsed; the message says what is missing or wrong."""


def _value(text: str) -> int | float | str:
    """A ``.cih`` value as int, float or text (see the module notes)."""
    if _INTEGER.fullmatch(text):
        return int(text)
    try:
        return float(text)
    except ValueError:
        return text


def parse_cih_text(text: str) -> dict[str, Any]:
    """Parse the camera information section of a ``.cih`` text.

    Parameters
    ----------
    text : str
        The file's text.

    Returns
    -------
    dict
        ``{key: value}`` of the lines before the first blank line.

    Raises
    ------
    CihFormatError
        When no ``Key : Value`` line is found.

    Examples
    --------
    >>> parse_cih_text("#Camera Information Header\\nRecord Rate(fps) : 20000\\n"
    ...                "Shutter Speed(s) : 1/800000\\n\\nPFV.exe : 3.6.3.0\\n")
    {'Record Rate(fps)': 20000, 'Shutter Speed(s)': '1/800000'}
    """
    cih: dict[str, Any] = {}
    for line in text.splitlines():
        if not line.strip():
            break  # end of the camera information section
        if line.startswith("#"):
            continue
        key, sep, value = line.partition(":")
        if sep and key.strip():
            cih[key.strip()] = _value(value.strip())
    if not cih:
        raise CihFormatError("no 'Key : Value' lines before the first blank line")
    return cih


def parse_cihx_bytes(data: bytes) -> dict[str, Any]:
    """Parse the XML part of a ``.cihx`` file into ``.cih`` keys.

    Parameters
    ----------
    data : bytes
        The whole file.

    Returns
    -------
    dict
        The keys of :data:`CIHX_FIELDS` whose elements are present.

    Raises
    ------
    CihFormatError
        When there is no ``<cih>`` element, the XML is malformed, a needed element is
        missing or a number is not a number.
    """
    start, end = data.find(b"<cih>"), data.rfind(b"</cih>")
    if start < 0 or end < start:
        raise CihFormatError("no <cih> ... </cih> XML element")
    try:
        root = ET.fromstring(data[start : end + len(b"</cih>")].decode("utf-8", "replace"))
    except ET.ParseError as exc:
        raise CihFormatError(f"malformed XML ({exc})") from exc
    cih: dict[str, Any] = {}
    for key, where, needed, kind in CIHX_FIELDS:
        element = root.find(where)
        if element is None:
            if needed:
                raise CihFormatError(f"element <{where}> missing")
            continue
        text = (element.text or "").strip()
        try:
            cih[key] = kind(text)
        except ValueError as exc:
            raise CihFormatError(f"element <{where}> is {text!r}, a number expected") from exc
    return cih


def read_cih(path: Path) -> dict[str, Any]:
    """Read a Photron ``.cih`` or ``.cihx`` header into a dictionary keyed by ``.cih`` names.

    Parameters
    ----------
    path : Path
        The header file; its suffix (any case) picks the format.

    Returns
    -------
    dict
        E.g. ``{"Record Rate(fps)": 50000.0, "Total Frame": 4, "Image Width": 1024, ...}``.

    Raises
    ------
    CihFormatError
        When the file cannot be parsed (see :func:`parse_cih_text`, :func:`parse_cihx_bytes`).
    OSError
        When the file cannot be read.
    """
    data = path.read_bytes()
    if path.suffix.lower() == ".cihx":
        return parse_cihx_bytes(data)
    return parse_cih_text(data.decode("utf-8", "replace"))
