"""The shared CSV reader: delimiter and decimal mark detected, exact values, clear errors.

Truth: every table is written here from known floats (``repr`` gives the shortest text that
reads back to the same double), then re-spelled with another delimiter and decimal mark; the
values read must equal the floats exactly, in every dialect.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from friction_model._table_io import (
    CsvDialect,
    TableFormatError,
    TableSource,
    read_table,
    sniff_dialect,
)

DIALECTS = [(",", "."), (";", ","), (";", "."), ("\t", "."), ("\t", ",")]


def spell(value: float, decimal: str) -> str:
    """A float as the shortest text that reads back exactly, with the given decimal mark."""
    return repr(float(value)).replace(".", decimal)


def write_table(path, columns, rows, delimiter=",", decimal=".", *, before="", end="\n"):
    """Write rows of floats (or ready-made strings) with a delimiter and decimal mark."""
    lines = [delimiter.join(columns)]
    for row in rows:
        lines.append(
            delimiter.join(v if isinstance(v, str) else spell(v, decimal) for v in row)
        )
    path.write_text(before + end.join(lines) + end, encoding="utf-8")
    return path


def known_values(n: int = 40) -> np.ndarray:
    """Floats over many decades, negative ones and exponents (``1e-05`` style) included."""
    rng = np.random.default_rng(7)
    return rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-7, 6, size=(n, 3))


@pytest.mark.parametrize("delimiter, decimal", DIALECTS)
def test_every_dialect_reads_the_same_values_exactly(tmp_path, delimiter, decimal):
    values = known_values()
    path = write_table(tmp_path / "t.csv", ["a", "b", "c"], values, delimiter, decimal)
    table, source = read_table(path, required=["a", "b", "c"], floats=["a", "b", "c"])
    assert source.dialect == CsvDialect(delimiter, decimal)
    assert source.header_line == 1
    # exact: the C parser reads the shortest repr of a double back to that double
    np.testing.assert_array_equal(table[["a", "b", "c"]].to_numpy(), values)


@pytest.mark.parametrize(
    "header, lines, expected",
    [
        ("time_s;F_N_N", ["0,001;1,5", "0,002;1,25"], CsvDialect(";", ",")),
        ("time_s;F_N_N", ["0.001;1.5"], CsvDialect(";", ".")),
        ("time_s,F_N_N", ["0.001,1.5"], CsvDialect(",", ".")),
        ("time_s\tF_N_N", ["0,001\t-1,5E-03"], CsvDialect("\t", ",")),
        ("time_s;F_N_N", ["0;1", "1;2"], CsvDialect(";", ".")),  # integers only
        ("time_s;F_N_N", [], CsvDialect(";", ".")),  # header only
        ("time_s", ["0.5"], CsvDialect(",", ".")),  # one column
        ('"time_s";"F_N_N"', ['"0,001";"1,5"'], CsvDialect(";", ",")),  # quoted
        # a text column with commas does not make ',' the delimiter
        ("time_s;note", ["0,5;a, b and c"], CsvDialect(";", ",")),
    ],
)
def test_sniff_dialect(header, lines, expected):
    assert sniff_dialect(header, lines) == expected


def test_decimal_mark_found_after_many_integer_rows(tmp_path):
    # the rig at rest writes whole numbers for a while; the first decimal comma decides
    rows = [[f"{k}", "0"] for k in range(150)] + [["150", "0,25"]]
    path = write_table(tmp_path / "t.csv", ["n", "x"], rows, ";")
    table, source = read_table(path, floats=["n", "x"])
    assert source.dialect == CsvDialect(";", ",")
    assert table["x"].iloc[-1] == 0.25 and len(table) == 151


def test_mixed_decimal_marks_are_named(tmp_path):
    path = write_table(tmp_path / "mixed.csv", ["a", "b"], [["0,5", "1"], ["2", "1.5"]], ";")
    with pytest.raises(
        TableFormatError,
        match=r"mixed\.csv: numbers with both decimal marks \(',' in column 'a', data row 1 "
        r"\(file line 2\): '0,5'; '\.' in column 'b', data row 2 \(file line 3\): '1\.5'\) in "
        r"a table with delimiter ';'; expected one decimal mark throughout",
    ):
        read_table(path)


def test_a_number_in_the_other_mark_later_names_row_and_dialect(tmp_path):
    # detection looks at the first rows; a later '.' number is reported with the dialect used
    rows = [[spell(0.5 + k, ","), "1,5"] for k in range(120)]
    rows[110][1] = "1.5"
    path = write_table(tmp_path / "late.csv", ["time_s", "mu"], rows, ";")
    with pytest.raises(
        TableFormatError,
        match=r"late\.csv: column 'mu', data row 111 \(file line 112\): expected a finite "
        r"number, got '1\.5' \(read with delimiter ';', decimal mark ','\)",
    ) as info:
        read_table(path, floats=["mu"], finite=["mu"])
    assert (info.value.column, info.value.row, info.value.line) == ("mu", 111, 112)


def test_unknown_delimiter_is_reported_with_what_was_found(tmp_path):
    path = write_table(tmp_path / "pipes.csv", ["time_s", "mu"], [["0.5", "1.5"]], "|")
    with pytest.raises(
        TableFormatError,
        match=r"pipes\.csv: column 'time_s' missing from the column header \(file line 1\); "
        r"expected columns time_s, mu, found time_s\|mu \(read with delimiter ',', decimal "
        r"mark '\.'\)",
    ):
        read_table(path, required=["time_s", "mu"])


def test_bom_crlf_comments_and_blank_lines_before_the_header(tmp_path):
    path = tmp_path / "excel.csv"
    text = "\ufeff# exported by the rig\r\n\r\ntime_s;mu\r\n0,5;0,125\r\n1;0,0625\r\n\r\n"
    path.write_bytes(text.encode("utf-8"))
    table, source = read_table(path, required=["time_s", "mu"], floats=["time_s", "mu"])
    assert source.header_line == 3 and source.dialect == CsvDialect(";", ",")
    assert table["time_s"].tolist() == [0.5, 1.0]  # trailing blank line dropped
    assert table["mu"].tolist() == [0.125, 0.0625]


def test_malformed_row_names_row_line_and_dialect(tmp_path):
    path = write_table(tmp_path / "short.csv", ["a", "b"], [["1,5", "2"], ["1", "2;3"]], ";")
    with pytest.raises(
        TableFormatError,
        match=r"short\.csv: malformed CSV, data row 2 \(file line 3\): expected 2 fields like "
        r"the column header \(file line 1\), got 3 \(read with delimiter ';', decimal mark ','\)",
    ):
        read_table(path, floats=["a", "b"])


def test_repeated_column_and_missing_header(tmp_path):
    path = write_table(tmp_path / "twice.csv", ["a", "a"], [["1", "2"]], ";")
    with pytest.raises(TableFormatError, match=r"twice\.csv: column 'a' appears more than once"):
        read_table(path)
    empty = tmp_path / "empty.csv"
    empty.write_text("# only a comment\n\n", encoding="utf-8")
    with pytest.raises(
        TableFormatError, match=r"empty\.csv: no column header found; expected a line of column "
        r"names \(time_s, mu\)"
    ):
        read_table(empty, required=["time_s", "mu"])


def test_in_memory_rows_are_counted_from_one():
    table = pd.DataFrame({"mu": [0.1, 0.2, np.inf]})
    with pytest.raises(
        TableFormatError, match=r"^steady table: column 'mu', data row 3: expected a finite "
        r"number, got inf$"
    ):
        TableSource("steady table").numbers(table, "mu")
    assert TableSource("f.csv", header_line=4).where(0) == "data row 1 (file line 5)"
