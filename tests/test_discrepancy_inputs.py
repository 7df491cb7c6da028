"""Reading the discrepancy inputs: any dialect, exact values, errors that say where.

Each bad file is built here from a good table with one entry changed; the message must name
the file, the column, the data row (counted from 1, the first row after the header) with its
file line, and what was expected, the way ``tir-contact evaluate`` says it.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from friction_model.discrepancy import (
    SteadyProblem,
    read_elements_table,
    read_steady_table,
    read_transient_table,
)
from friction_model.identification.identify import read_characteristic

STEADY_COLUMNS = ["velocity_mps", "pressure_bar", "temperature_C", "humidity_pct",
                  "salinity_pct", "n_sipes", "mu", "mu_std"]


def steady_rows() -> list[list[str]]:
    """Eight rows of a steady table as text (shortest repr of each double)."""
    rng = np.random.default_rng(11)
    rows = []
    for k, (v, t) in enumerate([(1.0, -8.0), (3.0, -8.0), (1.0, -2.0), (3.0, -2.0)] * 2):
        mu = 0.1 + 0.05 * rng.random()
        rows.append([repr(v), "2.5", repr(t), "40.0" if k < 4 else "90.0", "0.0", "3",
                     repr(mu), repr(0.02 * mu)])
    return rows


def transient_rows(n: int = 40) -> list[list[str]]:
    t = np.arange(n) * 1e-3
    v = np.where(t < 0.02, 1.0, 5.0)
    angle = 3.0 + np.sin(t * 50.0)
    return [[repr(float(a)), repr(float(b)), repr(float(c))]
            for a, b, c in zip(t, v, angle, strict=True)]


def write(path, columns, rows, delimiter=",", decimal="."):
    lines = [delimiter.join(columns)]
    lines += [delimiter.join(f.replace(".", decimal) for f in row) for row in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("delimiter, decimal", [(";", ","), (";", "."), ("\t", ",")])
def test_steady_table_in_every_dialect_is_read_exactly(tmp_path, delimiter, decimal):
    rows = steady_rows()
    dots = read_steady_table(write(tmp_path / "dots.csv", STEADY_COLUMNS, rows))
    other = read_steady_table(
        write(tmp_path / "other.csv", STEADY_COLUMNS, rows, delimiter, decimal)
    )
    pd.testing.assert_frame_equal(dots, other, check_exact=True)
    assert dots["mu"].tolist() == [float(r[6]) for r in rows]  # the doubles written
    problem = SteadyProblem(other)
    np.testing.assert_array_equal(problem.y, [float(r[6]) for r in rows])


def test_transient_and_elements_tables_with_decimal_commas_are_read_exactly(tmp_path):
    rows = transient_rows()
    columns = ["time_s", "velocity_mps", "angle_deg"]
    dots = read_transient_table(write(tmp_path / "step.csv", columns, rows))
    semi = read_transient_table(write(tmp_path / "step_semi.csv", columns, rows, ";", ","))
    pd.testing.assert_frame_equal(dots, semi, check_exact=True)
    assert dots["angle_deg"].tolist() == [float(r[2]) for r in rows]
    el_rows = [[str(k), r[0], "0", r[2] if k % 5 else ""] for k, r in enumerate(rows)]
    el_cols = ["frame", "time_s", "element", "deflection_angle_deg"]
    a = read_elements_table(write(tmp_path / "elements.csv", el_cols, el_rows))
    b = read_elements_table(write(tmp_path / "elements_semi.csv", el_cols, el_rows, ";", ","))
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    assert a["deflection_angle_deg"].isna().sum() == 8  # out of view: kept as NaN


def test_a_row_without_friction_is_left_out_and_said(tmp_path, caplog):
    # before, the row went without a word: 7 points fitted from a file of 8 rows
    rows = steady_rows()
    rows[2][6] = ""
    with caplog.at_level("WARNING", logger="friction_model"):
        c = read_characteristic(write(tmp_path / "c.csv", STEADY_COLUMNS, rows))
    assert len(c.mu) == 7
    assert "c.csv: column 'mu': 1 row(s) without a finite friction coefficient left out " \
        "(data row 3 (file line 4))" in caplog.text


def test_characteristic_with_decimal_commas_is_read_exactly(tmp_path):
    rows = steady_rows()
    a = read_characteristic(write(tmp_path / "c.csv", STEADY_COLUMNS, rows),
                            select={"humidity_pct": 40.0})
    b = read_characteristic(write(tmp_path / "c_semi.csv", STEADY_COLUMNS, rows, ";", ","),
                            select={"humidity_pct": 40.0})
    np.testing.assert_array_equal(a.mu, b.mu)
    np.testing.assert_array_equal(a.velocity_mps, b.velocity_mps)
    np.testing.assert_array_equal(b.sigma, [float(r[7]) for r in rows[:4]])


# (column, 0-based row index, text, expected message tail)
STEADY_DEFECTS = [
    ("mu", 3, "", "expected a finite number, got an empty field / NaN"),
    ("pressure_bar", 0, "2.5 bar", "expected a finite number, got '2.5 bar' (read with "
     "delimiter ',', decimal mark '.')"),
    ("temperature_C", 6, "inf", "expected a finite number, got inf"),
    ("mu", 5, "-0.1", "expected a number > 0, got -0.1"),
    ("n_sipes", 7, "2.5", "expected an integer >= 0, got 2.5"),
    ("mu_std", 2, "-0.01", "expected a number >= 0, got -0.01"),
    # the model's conditions: a temperature in kelvin stopped at an effect's bound on the
    # salinity before, naming no row (helper-12)
    ("temperature_C", 4, "268.15", "expected a temperature in degC in [-60, 0] (ice below "
     "its melting point; kelvin?), got 268.15"),
    ("pressure_bar", 1, "250000", "expected a pressure in bar in [0.01, 1000], got 250000.0"),
    ("humidity_pct", 3, "140", "expected a relative humidity in % in [0, 100], got 140.0"),
    ("velocity_mps", 0, "0", "expected a number > 0, got 0.0"),
]


@pytest.mark.parametrize("column, index, text, expected", STEADY_DEFECTS)
def test_bad_steady_file_names_file_column_row_line(tmp_path, column, index, text, expected):
    rows = steady_rows()
    rows[index][STEADY_COLUMNS.index(column)] = text
    path = write(tmp_path / "steady.csv", STEADY_COLUMNS, rows)
    row = index + 1  # data row, counted from 1; the header is file line 1
    with pytest.raises(ValueError) as info:
        read_steady_table(path)
    assert str(info.value) == (
        f"{path}: column '{column}', data row {row} (file line {row + 1}): {expected}"
    )
    assert (info.value.column, info.value.row, info.value.line) == (column, row, row + 1)


def test_steady_file_without_a_column_or_rows(tmp_path):
    rows = steady_rows()
    path = write(tmp_path / "short.csv", STEADY_COLUMNS[:3] + STEADY_COLUMNS[4:], rows)
    with pytest.raises(
        ValueError, match=r"short\.csv: column 'humidity_pct' missing from the column header "
        r"\(file line 1\); expected columns velocity_mps, .*found velocity_mps, pressure_bar"
    ):
        read_steady_table(path)
    path = write(tmp_path / "three.csv", STEADY_COLUMNS, rows[:3], ";", ",")
    with pytest.raises(
        ValueError, match=r"three\.csv: expected at least 4 data rows after the column header "
        r"\(file line 1\), got 3$"
    ):
        read_steady_table(path)


def test_bad_transient_file_names_file_column_row_line(tmp_path):
    columns = ["time_s", "velocity_mps", "angle_deg"]
    rows = transient_rows()
    rows[12][0] = rows[11][0]  # a repeated time stamp
    path = write(tmp_path / "step.csv", columns, rows, ";", ",")
    t = float(rows[11][0])
    with pytest.raises(ValueError) as info:
        read_transient_table(path)
    assert str(info.value) == (
        f"{path}: column 'time_s', data row 13 (file line 14): time must increase strictly, "
        f"got {t!r} s after {t!r} s"
    )
    rows = transient_rows()
    rows[30][2] = "nan"
    with pytest.raises(
        ValueError, match=r"step2\.csv: column 'angle_deg', data row 31 \(file line 32\): "
        r"expected a finite number, got an empty field / NaN"
    ):
        read_transient_table(write(tmp_path / "step2.csv", columns, rows))


def test_bad_elements_file_names_row(tmp_path):
    rows = [[str(k), repr(k * 1e-3), "0" if k != 4 else "first", "1.5"] for k in range(10)]
    path = write(tmp_path / "elements.csv", ["frame", "time_s", "element",
                                             "deflection_angle_deg"], rows)
    with pytest.raises(
        ValueError, match=r"elements\.csv: column 'element', data row 5 \(file line 6\): "
        r"expected a finite number, got 'first'"
    ):
        read_elements_table(path)


def test_cli_discrepancy_bad_steady_file_is_one_line_naming_file_and_row(run_cli, tmp_path, capsys):
    rows = steady_rows()
    rows[3][6] = "0,125"  # a decimal comma in a comma-separated file: an extra field
    path = write(tmp_path / "steady.csv", STEADY_COLUMNS, rows)
    code = run_cli(["discrepancy", "--steady", path, "--out", tmp_path / "d"])
    assert code == 1  # the data cannot be used
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"tir-contact discrepancy: error: {path}: malformed CSV, data row 4 (file line 5): "
        "expected 8 fields like the column header (file line 1), got 9 (read with delimiter "
        "',', decimal mark '.')"
    ]
    assert not (tmp_path / "d" / "result.json").exists()


def test_cli_discrepancy_bad_transient_file_names_it(run_cli, tmp_path, capsys):
    good = write(tmp_path / "good.csv", ["time_s", "velocity_mps", "angle_deg"],
                 transient_rows())
    rows = transient_rows()
    rows[7][1] = "fast"
    bad = write(tmp_path / "bad.csv", ["time_s", "velocity_mps", "angle_deg"], rows, ";", ",")
    code = run_cli(["discrepancy", "--transient", good, bad, "--out",
                 str(tmp_path / "d")])
    assert code == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"tir-contact discrepancy: error: {bad}: column 'velocity_mps', data row 8 (file line 9): "
        "expected a finite number, got 'fast' (read with delimiter ';', decimal mark ',')"
    ]
