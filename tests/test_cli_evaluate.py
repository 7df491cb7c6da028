"""Tests of the ``tir-contact evaluate`` sub-command (through the console entry point)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from synthetic.rig import make_raw_run, write_run_csv

F_N = 300.0  # N, spring preload of the synthetic runs
MASS = 12.5  # kg, inertial mass written to the metadata


def make_folder(folder: Path, *, broken: bool = False, ramp=None) -> Path:
    """Six steady runs (G0, G3) in `folder`; with `broken` an unreadable G5 run, with `ramp`
    (the fixture ``write_ramp_run``) the instationary ramp run G0_ramp.csv."""
    folder.mkdir()
    for spec, mu in (("G0", 0.22), ("G3", 0.26)):
        for run in (1, 2, 3):
            df = make_raw_run(
                lambda v, mu=mu: np.full_like(v, mu),
                sample_rate_Hz=2000,
                normal_force_N=F_N,
                inertial_mass_kg=MASS,
                rng=10 * run + len(spec),
                metadata={"specimen": spec, "run": run, "condition": "T=-4C"},
            )
            write_run_csv(df, folder / f"{spec}_run{run}.csv")
    if broken:
        (folder / "G5_run1.csv").write_text(
            "# specimen: G5\ntime_s,velocity_mps,normal_force_N\n0,0,300\n0.001,0,300\n"
        )
    if ramp is not None:
        ramp(folder / "G0_ramp.csv", normal_force_ripple=0.0)
    return folder


def test_evaluate_folder_success(run_cli, tmp_path, capsys):
    runs = make_folder(tmp_path / "runs")
    out = tmp_path / "out"
    assert run_cli(["evaluate", runs, "--out", out, "--no-progress"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    assert "evaluated 6 steady and 0 instationary runs, 0 failed" in captured.out
    # summary: one line per specimen, mu printed with 4 decimals (noise se ~1.6e-4 per run)
    lines = {line.split()[0]: line.split() for line in captured.out.splitlines()[2:]}
    assert_allclose(float(lines["G0"][3]), 0.22, atol=1e-3)
    assert_allclose(float(lines["G3"][3]), 0.26, atol=1e-3)
    steady = pd.read_csv(out / "steady_characteristic.csv")
    assert (steady["row_type"] == "run").sum() == 6
    assert (steady["row_type"] == "aggregate").sum() == 2
    assert not (out / "instationary_characteristic.csv").exists()
    assert (out / "mu_v.png").is_file()
    assert len(list((out / "mu_t").glob("*.png"))) == 6


def test_broken_file_exit_code_and_stderr(run_cli, tmp_path, capsys):
    runs = make_folder(tmp_path / "runs", broken=True)
    out = tmp_path / "out"
    assert run_cli(["evaluate", runs, "--out", out, "--no-plots", "--no-progress"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    broken = runs / "G5_run1.csv"
    assert len(err) == 1
    assert err[0].startswith(f"{broken}: column 'friction_force_N' missing")
    assert "file line 2" in err[0]
    # the six good runs were still evaluated and written
    steady = pd.read_csv(out / "steady_characteristic.csv")
    assert (steady["row_type"] == "run").sum() == 6
    assert not (out / "mu_v.png").exists()


def test_instationary_run_in_folder_and_mass_override(
    run_cli, write_ramp_run, ramp_law, tmp_path, capsys
):
    runs = make_folder(tmp_path / "runs", ramp=write_ramp_run)
    out = tmp_path / "out"
    argv = ["evaluate", str(runs / "G0_ramp.csv"), "--out", str(out), "--no-plots"]
    assert run_cli([*argv, "--bin-width", "0.5"]) == 0
    assert "G0_ramp.csv: m = 12.5 kg, 6 accelerating and 6 decelerating bins" in (
        capsys.readouterr().out
    )
    inst = pd.read_csv(out / "instationary_characteristic.csv")
    assert_allclose(inst["inertial_mass_kg"], MASS, rtol=0)
    # bins of 0.5 m/s up to 3 m/s; law recovered after inertia removal (bin se ~1e-4, law
    # curvature over 0.5 m/s < 1e-3)
    assert_allclose(inst["mu"], ramp_law(inst["velocity_mps"]), atol=2e-3)
    # --mass-kg 0 keeps the inertial force: mu + m a / F_N while accelerating
    out0 = tmp_path / "out0"
    assert run_cli([*argv[:3], out0, "--no-plots", "--bin-width", "0.5", "--mass-kg", "0"]) == 0
    biased = pd.read_csv(out0 / "instationary_characteristic.csv")
    acc = (biased["branch"] == "accelerating") & (biased["velocity_mps"] < 2.5)
    assert_allclose(
        biased.loc[acc, "mu"] - inst.loc[acc, "mu"], MASS * 4.0 / F_N, atol=2e-3
    )


def test_forced_instationary_flag(run_cli, write_ramp_run, tmp_path):
    runs = make_folder(tmp_path / "runs", ramp=write_ramp_run)
    out = tmp_path / "out"
    # a steady run read as instationary: its ramps give both branches, the plateau none
    argv = ["evaluate", str(runs / "G0_run1.csv"), "--out", str(out), "--no-plots"]
    assert run_cli([*argv, "--instationary", "--bin-width", "0.25"]) == 0
    inst = pd.read_csv(out / "instationary_characteristic.csv")
    assert set(inst["branch"]) == {"accelerating", "decelerating"}
    # ramp at 5 m/s^2 to 1 m/s, bins below 1 m/s: mu = 0.22 after removing m a
    assert_allclose(inst["mu"], 0.22, atol=5e-3)
    assert math.isclose(inst["velocity_mps"].max(), 0.875, abs_tol=0.05)


@pytest.mark.parametrize("bad", [["--bin-width", "0"], ["--bin-width", "x"], ["--mass-kg", "-1"]])
def test_bad_option_values(run_cli, tmp_path, bad):
    assert run_cli(["evaluate", tmp_path, "--out", tmp_path / "o", *bad]) == 2


def test_empty_folder_fails(run_cli, tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    assert run_cli(["evaluate", tmp_path / "empty", "--out", tmp_path / "o"]) == 1
    assert "folder contains no *.csv files" in capsys.readouterr().err


def test_a_path_that_does_not_exist_is_a_usage_error(run_cli, tmp_path, capsys):
    # as analyze: exit 2 naming the path, nothing written (before: exit 1 and a full
    # output folder of empty tables and a report)
    runs = make_folder(tmp_path / "runs")
    out = tmp_path / "out"
    assert run_cli(["evaluate", runs, tmp_path / "nope", "--out", out]) == 2
    assert f"{tmp_path / 'nope'}: does not exist" in capsys.readouterr().err
    assert not out.exists()
