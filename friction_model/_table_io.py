"""Reading user CSV tables: delimiter and decimal mark detected, errors that say where.

Every CSV table a user hands to ``friction_model`` (test-rig runs, steady and transient
tables, characteristic tables, pipeline outputs) is read here, so that all of them accept
the same files and describe a bad file the same way:

* the **delimiter** is ``,``, ``;`` or a tab, and the **decimal mark** ``.`` or ``,``
  (``,`` only with ``;`` or tab delimiters), both detected from the column header and the
  first data lines (:func:`sniff_dialect`); a UTF-8 byte-order mark and CRLF line ends are
  accepted;
* blank lines and lines starting with ``#`` before the column header are skipped (the
  test-rig format keeps its ``# key: value`` metadata there);
* error messages name the file, the column, the row and what was expected. Rows are
  counted as the *data row* (1-based, the first row after the column header is data row 1)
  and the *file line* (1-based, counting every line of the file), e.g.
  ``steady.csv: column 'mu', data row 4 (file line 5): expected a finite number, got 'x'``.
  Where the detected dialect matters (a missing column, a field that is not a number, a row
  with the wrong number of fields) the message says which delimiter and decimal mark were
  found.
"""

from __future__ import annotations

import csv
import os
import re
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from itertools import islice
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

#: Major version of pandas (its CSV parser's float rounding changed in 3.0).
_PANDAS_MAJOR = int(pd.__version__.split(".")[0])

__all__ = [
    "CsvDialect",
    "TableFormatError",
    "TableHead",
    "TableSource",
    "read_columns",
    "read_head",
    "read_table",
    "sniff_dialect",
]

#: Delimiters recognised, in order of preference when several fit.
DELIMITERS = (",", ";", "\t")
# data lines used to choose the delimiter; the decimal mark is looked for in at least
# _DECIMAL_ROWS data lines and, while none shows a decimal mark, up to _DECIMAL_MAX_ROWS
_DELIMITER_ROWS = 20
_DECIMAL_ROWS = 100
_DECIMAL_MAX_ROWS = 100_000
_ENCODING = "utf-8-sig"
# a number with exactly one decimal mark and no other separator
_NUMBER = {
    ".": re.compile(r"[+-]?(\d+\.\d*|\.\d+)([eE][+-]?\d+)?"),
    ",": re.compile(r"[+-]?(\d+,\d*|,\d+)([eE][+-]?\d+)?"),
}


class TableFormatError(ValueError):
    """A CSV table that cannot be read as expected.

    The message is ``"<file>: <detail>"``; the detail names the column, the row and what
    was expected.

    Parameters
    ----------
    file : str or path-like
        The offending file (or a label such as ``"steady table"`` for an in-memory table).
    detail : str
        What is wrong, where, and what was expected (without the file name).
    column : str, optional
        The column (or metadata key) concerned.
    row : int, optional
        1-based data row concerned (the first row after the column header is row 1).
    line : int, optional
        1-based line of the file concerned.

    Attributes
    ----------
    file, detail, column, row, line
        As given.
    """

    def __init__(
        self,
        file: str | os.PathLike[str],
        detail: str,
        *,
        column: str | None = None,
        row: int | None = None,
        line: int | None = None,
    ) -> None:
        self.file = str(file)
        self.detail = detail
        self.column = column
        self.row = row
        self.line = line
        super().__init__(f"{self.file}: {detail}")


@dataclass(frozen=True)
class CsvDialect:
    """Delimiter and decimal mark of a CSV table.

    Attributes
    ----------
    delimiter : {",", ";", "\\t"}
        Field delimiter.
    decimal : {".", ","}
        Decimal mark of the numbers.

    Examples
    --------
    >>> CsvDialect(";", ",").describe()
    "delimiter ';', decimal mark ','"
    """

    delimiter: str = ","
    decimal: str = "."

    def describe(self) -> str:
        """``"delimiter ';', decimal mark ','"`` (a tab is written ``tab``)."""
        name = "tab" if self.delimiter == "\t" else repr(self.delimiter)
        return f"delimiter {name}, decimal mark {self.decimal!r}"


def _split(line: str, delimiter: str) -> list[str]:
    """Fields of one line (quotes as in CSV), surrounding blanks removed."""
    fields = next(csv.reader([line], delimiter=delimiter), [])
    return [f.strip() for f in fields]


def _choose_delimiter(header: str, lines: Sequence[str]) -> str:
    """The delimiter that splits the header into > 1 field and every data line alike."""
    counts = {d: len(_split(header, d)) for d in DELIMITERS}
    fitting = [
        d
        for d in DELIMITERS
        if counts[d] > 1 and all(len(_split(s, d)) == counts[d] for s in lines)
    ]
    if fitting:
        return fitting[0]
    # no delimiter fits every line: the one that splits the header most (the parser then
    # reports the row that disagrees); a header without any delimiter is one column
    best = max(DELIMITERS, key=lambda d: counts[d])
    return best if counts[best] > 1 else ","


def sniff_dialect(
    header: str,
    lines: Iterable[str],
    *,
    file: str | os.PathLike[str] = "table",
    header_line: int = 1,
    error_type: type[TableFormatError] = TableFormatError,
) -> CsvDialect:
    """Detect the delimiter and the decimal mark of a CSV table.

    Parameters
    ----------
    header : str
        The column header line.
    lines : iterable of str
        The lines after the header (read lazily: the first 100, and more only while none
        of them shows a decimal mark).
    file : str or path-like
        Name used in error messages.
    header_line : int
        1-based file line of the header (for error messages).
    error_type : type
        :class:`TableFormatError` or a subclass, raised on mixed decimal marks.

    Returns
    -------
    CsvDialect
        The delimiter: the first of ``,``, ``;``, tab that splits the header into more than
        one field and every one of the first 20 data lines into as many (else the one
        giving the header the most fields; ``,`` for a one-column header). The decimal
        mark: ``,`` when a data field is a number written with a decimal comma (``0,5``,
        ``-1,2e-3``) and none with a decimal point, else ``.``; always ``.`` with the ``,``
        delimiter.

    Raises
    ------
    TableFormatError
        When data fields show both decimal marks (e.g. ``0.5`` and ``1,5``), naming both.

    Examples
    --------
    >>> sniff_dialect("time_s;mu", ["0,001;1,5", "0,002;1,25"])
    CsvDialect(delimiter=';', decimal=',')
    >>> sniff_dialect("time_s\\tmu", ["0.001\\t1.5"])
    CsvDialect(delimiter='\\t', decimal='.')
    >>> sniff_dialect("time_s,mu", ["0.001,1.5"])
    CsvDialect(delimiter=',', decimal='.')
    """
    rest: Iterator[str] = iter(lines)
    first = [s for s in islice(rest, _DELIMITER_ROWS)]
    sample = [s for s in first if s.strip()]
    delimiter = _choose_delimiter(header, sample)
    if delimiter == ",":
        return CsvDialect(",", ".")
    names = _split(header, delimiter)
    seen: dict[str, tuple[int, str, str]] = {}
    for k, line in enumerate([*first, *rest], start=1):
        if k > _DECIMAL_MAX_ROWS or (k > _DECIMAL_ROWS and seen):
            break
        for j, value in enumerate(_split(line, delimiter)):
            for mark, pattern in _NUMBER.items():
                if mark not in seen and pattern.fullmatch(value):
                    column = names[j] if j < len(names) else f"#{j + 1}"
                    seen[mark] = (k, column, value)
        if len(seen) == 2:
            break
    if len(seen) == 2:
        where = [
            f"{mark!r} in column '{column}', data row {k} (file line {header_line + k}): {value!r}"
            for mark, (k, column, value) in seen.items()
        ]
        name = "tab" if delimiter == "\t" else repr(delimiter)
        raise error_type(
            file,
            f"numbers with both decimal marks ({'; '.join(where)}) in a table with delimiter "
            f"{name}; expected one decimal mark throughout",
        )
    return CsvDialect(delimiter, "," if "," in seen else ".")


@dataclass(frozen=True)
class TableHead:
    """What precedes the data of a CSV file.

    Attributes
    ----------
    comments : list of (int, str)
        ``#`` lines before the column header: (1-based file line, stripped text).
    columns : list of str
        Column names (surrounding blanks and quotes removed).
    header_line : int
        1-based file line of the column header.
    dialect : CsvDialect
        Detected delimiter and decimal mark.
    """

    comments: list[tuple[int, str]]
    columns: list[str]
    header_line: int
    dialect: CsvDialect


def read_head(
    path: str | os.PathLike[str],
    *,
    error_type: type[TableFormatError] = TableFormatError,
    expected_header: str = "a column header",
) -> TableHead:
    """Read the ``#`` lines and the column header of a CSV file and detect its dialect.

    Parameters
    ----------
    path : str or path-like
        UTF-8 CSV file (a byte-order mark is allowed).
    error_type : type
        :class:`TableFormatError` or a subclass to raise.
    expected_header : str
        What the header should be, for the message when there is none.

    Returns
    -------
    TableHead

    Raises
    ------
    TableFormatError
        When the file is not UTF-8 text, has no column header or mixes decimal marks.
    OSError
        When the file cannot be opened.
    """
    comments: list[tuple[int, str]] = []
    try:
        with open(path, encoding=_ENCODING, newline="") as fh:
            for lineno, raw in enumerate(fh, start=1):
                text = raw.strip()
                if not text:
                    continue
                if text.startswith("#"):
                    comments.append((lineno, text))
                    continue
                dialect = sniff_dialect(
                    text,
                    (s.rstrip("\r\n") for s in fh),
                    file=path,
                    header_line=lineno,
                    error_type=error_type,
                )
                columns = _split(text, dialect.delimiter)
                return TableHead(comments, columns, lineno, dialect)
    except UnicodeDecodeError as exc:
        raise error_type(path, f"not a UTF-8 text file ({exc.reason})") from None
    raise error_type(path, f"no column header found; expected {expected_header}")


@dataclass(frozen=True)
class TableSource:
    """Where a table came from, to say where a bad value is.

    Attributes
    ----------
    file : str
        File name, or a label such as ``"steady table"`` for an in-memory table.
    header_line : int or None
        1-based file line of the column header; None for an in-memory table (rows are then
        counted as data rows only).
    dialect : CsvDialect or None
        Delimiter and decimal mark the file was read with.
    error_type : type
        :class:`TableFormatError` or a subclass, raised by :meth:`error`.

    Examples
    --------
    >>> TableSource("steady.csv", header_line=1).where(3)
    'data row 4 (file line 5)'
    >>> TableSource("steady table").where(3)
    'data row 4'
    """

    file: str
    header_line: int | None = None
    dialect: CsvDialect | None = None
    error_type: type[TableFormatError] = field(default=TableFormatError, repr=False)

    def where(self, index: int) -> str:
        """Describe the row at 0-based position ``index`` as data row and file line."""
        row = int(index) + 1
        if self.header_line is None:
            return f"data row {row}"
        return f"data row {row} (file line {self.header_line + row})"

    def read_as(self) -> str:
        """``" (read with delimiter ';', decimal mark ',')"`` or ``""`` without a dialect."""
        return "" if self.dialect is None else f" (read with {self.dialect.describe()})"

    def error(
        self, detail: str, *, column: str | None = None, index: int | None = None
    ) -> TableFormatError:
        """Build an error for this file at the row at 0-based position ``index``."""
        row = None if index is None else int(index) + 1
        line = None if row is None or self.header_line is None else self.header_line + row
        return self.error_type(self.file, detail, column=column, row=row, line=line)

    def missing(
        self, columns: Sequence[str], found: Sequence[str], *, expected: str | None = None
    ) -> TableFormatError | None:
        """Error for the first of ``columns`` not in ``found`` (None when all are there)."""
        absent = [c for c in columns if c not in found]
        if not absent:
            return None
        where = "" if self.header_line is None else f" (file line {self.header_line})"
        return self.error_type(
            self.file,
            f"column '{absent[0]}' missing from the column header{where}; expected columns "
            f"{expected or ', '.join(columns)}, found {', '.join(map(str, found)) or 'none'}"
            f"{self.read_as()}",
            column=absent[0],
            line=self.header_line,
        )

    def numbers(self, table: pd.DataFrame, column: str, *, finite: bool = True) -> np.ndarray:
        """Column as float64, with an error at the first entry that is not a number.

        Parameters
        ----------
        table : pandas.DataFrame
            Table with ``column``; rows counted by position.
        column : str
            Column name.
        finite : bool
            Also refuse empty fields, NaN and infinite values.

        Returns
        -------
        (N,) ndarray of float

        Raises
        ------
        TableFormatError
            ``column 'mu', data row 4 (file line 5): expected a finite number, got 'x'``.
        """
        values = table[column]
        numeric = _to_float(values, "." if self.dialect is None else self.dialect.decimal)
        bad = ~np.isfinite(numeric) if finite else np.isnan(numeric) & values.notna().to_numpy()
        if not bad.any():
            return numeric
        i = int(np.flatnonzero(bad)[0])
        raw = values.iloc[i]
        if pd.isna(raw):
            got = "an empty field / NaN"
        elif isinstance(raw, str):
            got = repr(raw)
        else:
            got = repr(float(raw))
        # the dialect is said where a field is text that is not a number in it
        said = self.read_as() if isinstance(raw, str) and np.isnan(numeric[i]) else ""
        rule = "a finite number" if finite else "a number or an empty field"
        raise self.error(
            f"column '{column}', {self.where(i)}: expected {rule}, got {got}{said}",
            column=column,
            index=i,
        )


def _to_float(values: pd.Series, decimal: str) -> np.ndarray:
    """Entries as float64, NaN where an entry is not a number written with ``decimal``."""
    if not pd.api.types.is_numeric_dtype(values) and decimal == ",":
        values = values.map(
            lambda v: v if not isinstance(v, str) else "x" if "." in v else v.replace(",", ".")
        )
    return pd.to_numeric(values, errors="coerce").to_numpy(dtype=np.float64)


def _drop_trailing_blank(frame: pd.DataFrame) -> pd.DataFrame:
    """Drop all-empty rows at the end (trailing empty lines of the file)."""
    empty = frame.isna().all(axis=1).to_numpy()
    if not empty.any() or not empty[-1]:
        return frame
    keep = len(empty) - int(np.argmin(empty[::-1])) if not empty.all() else 0
    return frame.iloc[:keep]


def read_columns(
    path: str | os.PathLike[str],
    head: TableHead,
    source: TableSource,
    *,
    floats: Sequence[str] = (),
    finite: Sequence[str] = (),
    usecols: Sequence[str] | None = None,
) -> pd.DataFrame:
    """Read the data rows of a CSV file whose head :func:`read_head` has read.

    Parameters
    ----------
    path : str or path-like
        The file.
    head : TableHead
        Its head (columns, header line, dialect).
    source : TableSource
        For error messages.
    floats : sequence of str
        Columns read as float64: a field that is not a number is an error naming its
        column and row. Empty fields become NaN.
    finite : sequence of str
        Columns (of ``floats``) whose every entry must be a finite number: an empty field,
        NaN or an infinite value is an error naming its column and row.
    usecols : sequence of str, optional
        Columns to keep (default all).

    Returns
    -------
    pandas.DataFrame
        One row per data line; trailing empty lines dropped, empty lines in between kept
        as rows of NaN (so data row ``r`` is file line ``header_line + r``).

    Raises
    ------
    TableFormatError
        For a field that is not a number, a non-finite entry of a ``finite`` column, a row
        with more fields than the header or text that is not UTF-8.
    """
    options: dict[str, Any] = {
        "skiprows": head.header_line - 1,
        "header": 0,
        "names": head.columns,
        "sep": head.dialect.delimiter,
        "decimal": head.dialect.decimal,
        "engine": "c",
        "skip_blank_lines": False,
        "encoding": _ENCODING,
    }
    if _PANDAS_MAJOR < 3:
        # correctly rounded doubles: pandas 2's default "high" parser can be one unit in the
        # last place off; pandas 3 rounds correctly by default (and deprecates the option)
        options["float_precision"] = "round_trip"
    # usecols (slower) only when the file has columns of its own
    if usecols is not None and len(usecols) < len(head.columns):
        options["usecols"] = list(usecols)
    kept = head.columns if usecols is None else list(usecols)
    floats = [c for c in floats if c in kept]
    finite = [c for c in finite if c in kept]
    try:
        try:
            frame = pd.read_csv(path, dtype=dict.fromkeys(floats, np.float64), **options)
        except ValueError as exc:
            if isinstance(exc, pd.errors.ParserError) or not floats:
                raise
            # a field that is not a number: read as text to find where it is
            text = _drop_trailing_blank(
                pd.read_csv(path, dtype=dict.fromkeys(floats, str), **options)
            )
            for name in floats:
                source.numbers(text, name, finite=name in finite)
            raise source.error(f"unreadable numbers ({exc}){source.read_as()}") from None
    except pd.errors.ParserError as exc:
        found = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", str(exc))
        where = _first_unparsable_row(path, head) if found is None else None
        if where is not None:  # pandas counts rows its own way: say where, as data row
            index, what = where
            raise source.error(f"malformed CSV, {source.where(index)}: {what}"
                               f"{source.read_as()}", index=index) from None
        if found is None:
            raise source.error(
                f"malformed CSV after the column header (file line {head.header_line}): {exc}"
                f"{source.read_as()}"
            ) from None
        expected, line, saw = (int(g) for g in found.groups())
        raise source.error(
            f"malformed CSV, {source.where(line - head.header_line - 1)}: expected {expected} "
            f"fields like the column header (file line {head.header_line}), got {saw}"
            f"{source.read_as()}",
            index=line - head.header_line - 1,
        ) from None
    except UnicodeDecodeError as exc:
        raise source.error(f"not a UTF-8 text file ({exc.reason})") from None
    frame = _drop_trailing_blank(frame)
    for name in finite:
        source.numbers(frame, name)
    return frame


def _first_unparsable_row(path: str | os.PathLike[str],
                          head: TableHead) -> tuple[int, str] | None:
    """The 0-based data row where Python's strict CSV reader fails, and why, or None.

    Used for pandas parser errors that give no usable row (``EOF inside string starting at
    row 9`` counts rows its own way): an unclosed quote is reported at the row it opens in.
    """
    with open(path, encoding=_ENCODING, newline="") as f:
        for _ in range(head.header_line):
            f.readline()
        reader = csv.reader(f, delimiter=head.dialect.delimiter, strict=True)
        before = 0  # lines after the column header read before the row being read
        while True:
            try:
                next(reader)
            except StopIteration:
                return None
            except csv.Error as exc:
                text = str(exc)
                if "unexpected end of data" in text:
                    return before, "a quoted field opened in this row is never closed"
                return before, f"unreadable row ({text})"
            before = reader.line_num


def read_table(
    path: str | os.PathLike[str],
    *,
    required: Sequence[str] = (),
    floats: Sequence[str] = (),
    finite: Sequence[str] = (),
    expected: str | None = None,
) -> tuple[pd.DataFrame, TableSource]:
    """Read a CSV table (any supported dialect) and check its columns.

    Parameters
    ----------
    path : str or path-like
        UTF-8 CSV file; blank and ``#`` lines before the column header are skipped.
    required : sequence of str
        Columns that must be in the header.
    floats : sequence of str
        Columns read as float64 (an entry that is not a number is an error naming it).
    finite : sequence of str
        Columns (of ``floats``) whose every entry must be a finite number.
    expected : str, optional
        What the header should hold, for the missing-column message (default the
        ``required`` columns).

    Returns
    -------
    table : pandas.DataFrame
        All columns; ``floats`` as float64.
    source : TableSource
        The file, header line and dialect, for messages about later checks.

    Raises
    ------
    TableFormatError
        Missing or repeated column, a field that is not a number, an empty or non-finite
        entry of a ``finite`` column, a malformed row, mixed decimal marks, no header.
    OSError
        When the file cannot be opened.

    Examples
    --------
    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "t.csv"
    >>> _ = path.write_text("velocity_mps;mu\\n1;0,125\\n3;0,0625\\n", encoding="utf-8")
    >>> table, source = read_table(path, required=["velocity_mps", "mu"], floats=["mu"])
    >>> table["mu"].tolist(), source.dialect.describe()
    ([0.125, 0.0625], "delimiter ';', decimal mark ','")
    """
    path = Path(path)
    expected = expected or ", ".join(required)
    head = read_head(path, expected_header=f"a line of column names ({expected})")
    source = TableSource(str(path), head.header_line, head.dialect)
    err = source.missing(required, head.columns, expected=expected)
    if err is not None:
        raise err
    repeated = sorted({c for c in head.columns if head.columns.count(c) > 1})
    if repeated:
        raise source.error_type(
            source.file,
            f"column '{repeated[0]}' appears more than once in the column header (file line "
            f"{head.header_line}); expected unique column names",
            column=repeated[0],
            line=head.header_line,
        )
    table = read_columns(path, head, source, floats=floats, finite=finite)
    return table, source
