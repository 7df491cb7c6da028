"""Reading and validating raw test-rig run CSV files (the reader of :mod:`friction_model.rig`).

The format (``docs/formats.md``): ``# key: value`` metadata lines, then a column header with
at least ``time_s, velocity_mps, normal_force_N, friction_force_N`` (optionally
``temperature_C, humidity_pct``), then one row per sample.

Row numbers in error messages are given both as the 1-based data row (the first row after the
column header is data row 1) and as the 1-based line of the file.
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from friction_model._table_io import (
    TableFormatError,
    TableHead,
    TableSource,
    read_columns,
    read_head,
)
from tir_common.schema import Field, FieldError, Schema

__all__ = [
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "RigRun",
    "RunFormatError",
    "read_run",
]

logger = logging.getLogger(__name__)

REQUIRED_COLUMNS = ("time_s", "velocity_mps", "normal_force_N", "friction_force_N")
OPTIONAL_COLUMNS = ("temperature_C", "humidity_pct")
_RUN_KINDS = ("steady", "instationary")


class RunFormatError(TableFormatError):
    """A run file that cannot be evaluated.

    The message names the file, the column (or metadata key), the row and what was expected,
    e.g. ``run_03.csv: column 'time_s', data row 17 (file line 21): ...``.

    Parameters
    ----------
    file : str or path-like
        The offending file.
    detail : str
        What is wrong, where, and what was expected (without the file name).
    column : str, optional
        The column or metadata key concerned.
    row : int, optional
        1-based data row concerned (the first sample after the column header is row 1).
    line : int, optional
        1-based line of the file concerned.

    Attributes
    ----------
    file, detail, column, row, line
        As given.
    """


#: Metadata keys with a type; other keys are kept as the stripped text.
_METADATA = Schema(
    "metadata",
    (
        Field(
            "nominal_area_mm2",
            "number",
            "nominal contact area of the sample, gives the normal pressure",
            unit="mm^2",
            low=0,
            low_open=True,
        ),
        Field(
            "inertial_mass_kg",
            "number",
            "mass of carriage and sample, for the inertial force of instationary runs",
            unit="kg",
            low=0,
        ),
        Field("run", "integer", "number of the run among its repeats"),
        Field("kind", "choice", "how the run is evaluated", choices=_RUN_KINDS),
    ),
    closed=False,
)


@dataclass(frozen=True, eq=False)
class RigRun:
    """One raw test-rig run read from a CSV file.

    Attributes
    ----------
    path : pathlib.Path
        Source file.
    time_s : (N,) ndarray of float
        Sample time (s), strictly increasing.
    velocity_mps : (N,) ndarray of float
        Sliding velocity (m/s), positive in the sliding direction.
    normal_force_N : (N,) ndarray of float
        Normal force F_N (N).
    friction_force_N : (N,) ndarray of float
        Friction force F_F (N), positive against the motion of the sample; contains the
        inertial force ``m * a`` of carriage and sample while accelerating.
    temperature_C : (N,) ndarray of float or None
        Ambient temperature (degC) when recorded.
    humidity_pct : (N,) ndarray of float or None
        Relative humidity (%) when recorded.
    metadata : dict
        ``key: value`` metadata of the file header; ``run`` is an int, ``nominal_area_mm2``
        and ``inertial_mass_kg`` are floats, ``kind`` is lower case, every other value is the
        stripped string.
    header_line : int
        1-based file line of the column header; data row ``r`` (1-based) is file line
        ``header_line + r``.
    """

    path: Path
    time_s: np.ndarray
    velocity_mps: np.ndarray
    normal_force_N: np.ndarray
    friction_force_N: np.ndarray
    temperature_C: np.ndarray | None = None
    humidity_pct: np.ndarray | None = None
    metadata: dict[str, Any] = field(default_factory=dict)
    header_line: int = 1

    def __len__(self) -> int:
        return int(self.time_s.shape[0])

    @property
    def specimen(self) -> str:
        """Specimen name from the metadata key ``specimen`` (empty string when absent)."""
        return str(self.metadata.get("specimen", ""))

    @property
    def condition(self) -> str:
        """Grouping key from the metadata key ``condition`` (empty string when absent)."""
        return str(self.metadata.get("condition", ""))

    @property
    def run_number(self) -> int | None:
        """Run number from the metadata key ``run`` (None when absent)."""
        return self.metadata.get("run")

    @property
    def kind(self) -> str:
        """``"steady"`` or ``"instationary"`` from the metadata key ``kind`` (default steady)."""
        return str(self.metadata.get("kind", "steady"))

    def where(self, index: int) -> str:
        """Describe sample ``index`` (0-based) as data row and file line for messages."""
        row = int(index) + 1
        return f"data row {row} (file line {self.header_line + row})"

    def error(
        self, detail: str, *, column: str | None = None, index: int | None = None
    ) -> RunFormatError:
        """Build a :class:`RunFormatError` for this file at sample ``index`` (0-based)."""
        row = None if index is None else int(index) + 1
        line = None if row is None else self.header_line + row
        return RunFormatError(self.path, detail, column=column, row=row, line=line)


def _read_metadata(path: Path, head: TableHead) -> dict[str, Any]:
    """The ``# key: value`` metadata of the lines before the column header."""
    metadata: dict[str, Any] = {}
    for lineno, text in head.comments:
        body = text[1:].strip()
        if ":" not in body:
            continue  # free comment
        key, value = (s.strip() for s in body.split(":", 1))
        if not key:
            raise RunFormatError(
                path,
                f"metadata line, file line {lineno}: expected '# key: value', got {text!r}",
                line=lineno,
            )
        if key in _METADATA:
            try:
                metadata[key] = _METADATA[key].check(
                    value, from_text=True, decimal=head.dialect.decimal
                )
            except FieldError as exc:
                raise RunFormatError(
                    path,
                    f"metadata key '{key}', file line {lineno}: expected {exc.expected}, "
                    f"got {value!r}",
                    column=key,
                    line=lineno,
                ) from None
        else:
            metadata[key] = value
    return metadata


def read_run(path: str | os.PathLike[str]) -> RigRun:
    """Read and validate one raw test-rig run CSV.

    Parameters
    ----------
    path : str or path-like
        CSV file: ``# key: value`` metadata lines, a column header, one row per sample.

    Returns
    -------
    RigRun
        The arrays (SI units, see :class:`RigRun`) and the metadata.

    Raises
    ------
    RunFormatError
        For a missing required column, an empty or NaN or non-numeric value in a used
        column, time that does not increase strictly, a malformed metadata value or no data.
        The message names the file, the column and the row.
    OSError
        When the file cannot be opened.

    Notes
    -----
    Columns other than the six known ones are ignored. Trailing empty lines are allowed;
    an empty line between data rows is reported as missing values of that row.
    """
    path = Path(path)
    head = read_head(
        path,
        error_type=RunFormatError,
        expected_header=f"a line '{', '.join(REQUIRED_COLUMNS)}' after the '# key: value' "
        "metadata lines",
    )
    metadata = _read_metadata(path, head)
    columns, header_line = head.columns, head.header_line
    source = TableSource(str(path), header_line, head.dialect, RunFormatError)
    err = source.missing(
        REQUIRED_COLUMNS,
        columns,
        expected=f"{', '.join(REQUIRED_COLUMNS)} (optional {', '.join(OPTIONAL_COLUMNS)})",
    )
    if err is not None:
        raise err
    duplicates = sorted({c for c in columns if columns.count(c) > 1})
    if duplicates:
        raise RunFormatError(
            path,
            f"column '{duplicates[0]}' appears more than once in the column header (file line "
            f"{header_line}); expected unique column names",
            column=duplicates[0],
            line=header_line,
        )
    used = [c for c in (*REQUIRED_COLUMNS, *OPTIONAL_COLUMNS) if c in columns]
    frame = read_columns(path, head, source, floats=used, finite=used, usecols=used)
    if len(frame) < 2:
        raise RunFormatError(
            path,
            f"column '{REQUIRED_COLUMNS[0]}': expected at least 2 data rows after the column "
            f"header (file line {header_line}), got {len(frame)}",
            column=REQUIRED_COLUMNS[0],
            line=header_line,
        )
    arrays = {name: frame[name].to_numpy(dtype=np.float64) for name in used}
    t = arrays["time_s"]
    steps = np.diff(t)
    if not (steps > 0).all():
        i = int(np.flatnonzero(~(steps > 0))[0]) + 1
        row = i + 1
        raise RunFormatError(
            path,
            f"column 'time_s', data row {row} (file line {header_line + row}): time must "
            f"increase strictly, got {float(t[i])!r} s after {float(t[i - 1])!r} s",
            column="time_s",
            row=row,
            line=header_line + row,
        )
    logger.debug("read %s: %d samples, metadata %s", path, t.size, metadata)
    return RigRun(
        path=path,
        time_s=t,
        velocity_mps=arrays["velocity_mps"],
        normal_force_N=arrays["normal_force_N"],
        friction_force_N=arrays["friction_force_N"],
        temperature_C=arrays.get("temperature_C"),
        humidity_pct=arrays.get("humidity_pct"),
        metadata=metadata,
        header_line=header_line,
    )
