"""Test-rig runs exported with other delimiters and decimal marks evaluate exactly alike.

Truth: one synthetic run written in the documented format (``,`` and ``.``) and the same
text re-spelled as European lab software exports it (``;`` with decimal commas, ``;`` with
points, tabs). The re-spelling changes no digit, so every number read, and everything
evaluated from them, must be equal exactly (not within a tolerance).
"""

from __future__ import annotations

import json
import os
import re
import stat
import sys
from dataclasses import fields
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from friction_model.rig import (
    RunFormatError,
    evaluate_instationary_run,
    evaluate_steady_run,
    read_run,
)
from synthetic.rig import make_raw_run, write_run_csv

ARRAYS = ("time_s", "velocity_mps", "normal_force_N", "friction_force_N", "temperature_C",
          "humidity_pct")
_NUMBER = re.compile(r"^[+-]?[\d.]+([eE][+-]?\d+)?$")


def respell(text: str, delimiter: str, decimal: str) -> str:
    """The same file with another delimiter and decimal mark (numeric metadata included)."""
    out = []
    for line in text.splitlines(keepends=True):
        if line.startswith("#"):
            key, _, value = line.partition(":")
            if _NUMBER.match(value.strip()):
                value = value.replace(".", decimal)
            out.append(f"{key}:{value}")
        else:
            out.append(line.replace(",", delimiter).replace(".", decimal))
    return "".join(out)


def steady_run(path: Path, *, rng: int = 3, mass: float = 12.5) -> Path:
    df = make_raw_run(
        lambda v: np.full_like(v, 0.21),
        sample_rate_Hz=2000,
        normal_force_N=300.0,
        inertial_mass_kg=mass,
        rng=rng,
        metadata={"specimen": "G3", "condition": "T=-4C", "run": rng,
                  "nominal_area_mm2": 1600.5},
    )
    return write_run_csv(df, path)


def same_result(a, b) -> None:
    """Every field of two evaluation results equal exactly (NaN equal to NaN)."""
    for f in fields(a):
        if f.name == "file":
            continue
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, pd.DataFrame):
            pd.testing.assert_frame_equal(x, y, check_exact=True)
        elif isinstance(x, dict):
            assert x.keys() == y.keys(), f.name
            for k in x:
                np.testing.assert_array_equal(x[k], y[k], err_msg=f"{f.name}[{k}]")
        else:
            np.testing.assert_array_equal(x, y, err_msg=f.name)


@pytest.mark.parametrize("delimiter, decimal", [(";", ","), (";", "."), ("\t", "."),
                                                ("\t", ",")])
def test_respelled_run_reads_and_evaluates_exactly_alike(tmp_path, delimiter, decimal):
    dots = steady_run(tmp_path / "dots.csv")
    other = tmp_path / "other.csv"
    other.write_text(respell(dots.read_text(), delimiter, decimal), encoding="utf-8")
    if decimal == ",":
        assert "0,0005" in other.read_text() and "# nominal_area_mm2: 1600,5" in other.read_text()
    a, b = read_run(dots), read_run(other)
    for name in ARRAYS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.metadata == b.metadata
    assert b.metadata["nominal_area_mm2"] == 1600.5 and b.metadata["inertial_mass_kg"] == 12.5
    same_result(evaluate_steady_run(a), evaluate_steady_run(b))


def test_instationary_run_with_decimal_commas_evaluates_exactly_alike(write_ramp_run, tmp_path):
    dots = write_ramp_run(tmp_path / "ramp.csv")
    semi = tmp_path / "ramp_semi.csv"
    semi.write_text(respell(dots.read_text(), ";", ","), encoding="utf-8")
    a = evaluate_instationary_run(read_run(dots))
    b = evaluate_instationary_run(read_run(semi))
    same_result(a, b)


def test_missing_column_says_which_dialect_was_found(tmp_path):
    dots = steady_run(tmp_path / "dots.csv")
    piped = tmp_path / "piped.csv"
    piped.write_text(dots.read_text().replace(",", "|"), encoding="utf-8")
    with pytest.raises(
        RunFormatError,
        match=r"piped\.csv: column 'time_s' missing from the column header \(file line 7\); "
        r"expected columns time_s, velocity_mps, normal_force_N, friction_force_N \(optional "
        r"temperature_C, humidity_pct\), found time_s\|velocity_mps\|.*\(read with delimiter "
        r"',', decimal mark '\.'\)$",
    ):
        read_run(piped)


def test_decimal_comma_metadata_with_a_bad_value_names_key_and_line(tmp_path):
    semi = tmp_path / "semi.csv"
    text = respell(steady_run(tmp_path / "dots.csv").read_text(), ";", ",")
    semi.write_text(text.replace("# inertial_mass_kg: 12,5", "# inertial_mass_kg: 12,5 kg"),
                    encoding="utf-8")
    with pytest.raises(
        RunFormatError,
        match=r"semi\.csv: metadata key 'inertial_mass_kg', file line \d: expected a number "
        r">= 0, got '12,5 kg'",
    ):
        read_run(semi)


posix_only = pytest.mark.skipif(sys.platform == "win32", reason="POSIX permission bits")


@posix_only
def test_cli_evaluate_reads_a_semicolon_folder_like_the_comma_folder(run_cli, tmp_path, capsys):
    dots, semis = tmp_path / "dots", tmp_path / "semis"
    dots.mkdir()
    semis.mkdir()
    for run in (1, 2, 3):
        path = steady_run(dots / f"G3_run{run}.csv", rng=run)
        (semis / path.name).write_text(respell(path.read_text(), ";", ","), encoding="utf-8")
    saved = os.umask(0o022)
    try:
        for folder in (dots, semis):
            code = run_cli(["evaluate", folder, "--out", tmp_path / f"out_{folder.name}",
                         "--no-plots", "--no-progress"])
            assert code == 0
    finally:
        os.umask(saved)
    captured = capsys.readouterr()
    assert captured.err == ""
    a = pd.read_csv(tmp_path / "out_dots" / "steady_characteristic.csv")
    b = pd.read_csv(tmp_path / "out_semis" / "steady_characteristic.csv")
    assert a.loc[a["row_type"] == "aggregate", "n_runs"].tolist() == [3]
    paths = [c for c in a.columns if a[c].astype(str).str.contains("dots").any()]
    pd.testing.assert_frame_equal(a.drop(columns=paths), b.drop(columns=paths), check_exact=True)
    # the outputs get the permissions of any plain file under umask 022
    for name in ("steady_characteristic.csv", "ambient.csv", "provenance.json"):
        assert stat.S_IMODE((tmp_path / "out_semis" / name).stat().st_mode) == 0o644, name
    json.loads((tmp_path / "out_semis" / "provenance.json").read_text())
