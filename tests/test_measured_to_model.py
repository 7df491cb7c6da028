"""The measured-to-model path on the files the commands write (issue 26): rig runs ->
``evaluate`` -> ``calibrate`` -> ``simulate``, and ``evaluate`` -> ``discrepancy --steady``,
each command reading the previous one's output as it is."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from friction_model import Conditions, DryWetParameters, friction_table, reference_block
from synthetic.rig import make_raw_run, write_run_csv
from tir_contact.cli import main

VELOCITIES = (1.0, 3.0, 5.0)


def rig_runs(folder, *, salinity=True):
    """Three runs per velocity of G3 at 2.5 bar, -4 degC, 73 % (the demo's rig step), the
    friction of the dry/wet model as the known truth."""
    folder.mkdir()
    rng = np.random.default_rng(5)
    truth = {}
    for v in VELOCITIES:
        cond = Conditions.from_bar(v, 2.5, -4.0, humidity_pct=73.0)
        mu = float(friction_table(reference_block("G3"), [cond], DryWetParameters())["mu"][0])
        truth[v] = mu
        for k in range(3):
            meta = {"specimen": "G3", "run": k + 1, "condition": f"v{v:g}"}
            if salinity:
                meta["salinity_pct"] = 0.0
            df = make_raw_run(lambda vv, m=mu: np.full_like(np.asarray(vv, float), m),
                              velocity_mps=v, sample_rate_Hz=2000, normal_force_N=400.0,
                              temperature_C=-4.0, humidity_pct=73.0, rng=rng, metadata=meta)
            write_run_csv(df, folder / f"G3_v{v:g}_run{k + 1:02d}.csv", df.attrs["metadata"])
    return truth


@pytest.fixture(scope="module")
def evaluated(tmp_path_factory):
    root = tmp_path_factory.mktemp("m2m")
    truth = rig_runs(root / "runs")
    assert main(["evaluate", str(root / "runs"), "--out", str(root / "eval"), "--no-plots",
                 "-q"]) == 0
    return root, truth


def test_evaluate_calibrate_simulate_compose(evaluated, capsys):
    root, truth = evaluated
    char = root / "eval" / "steady_characteristic.csv"
    assert main(["calibrate", "--characteristic", str(char), "--out",
                 str(root / "params.json")]) == 0
    line = capsys.readouterr().out
    assert "over 9 points" in line and "reduced chi-square" in line
    law = json.loads((root / "params.json").read_text())["friction_law"]
    assert law["n_points"] == 9 and law["noise_source"] == "replicates"
    assert law["law"] != "ConstantLaw" and not law["reduced_chi2"] > 10
    assert main(["simulate", "--params", str(root / "params.json"), "--out",
                 str(root / "sim"), "--velocity", *map(str, VELOCITIES), "--no-plots",
                 "-q"]) == 0
    sim = pd.read_csv(next((root / "sim").glob("mu_v.csv")))
    mu_col = next(c for c in sim.columns if c.startswith("mu"))
    # the simulated characteristic is the calibrated law at the measured velocities: the
    # rig's truth within 5 noise sd of the evaluated means (noise ~ 1e-4)
    assert np.allclose(sim[mu_col], [truth[v] for v in VELOCITIES], atol=2e-3)


def test_evaluate_discrepancy_compose(evaluated, capsys):
    root, _ = evaluated
    char = root / "eval" / "steady_characteristic.csv"
    rc = main(["discrepancy", "--steady", str(char), "--out", str(root / "d"),
               "--bootstrap", "10", "--permutations", "49", "--max-effects", "1"])
    assert rc == 0
    result = json.loads((root / "d" / "result.json").read_text())
    assert result["verdict"] and "held-out gap" in capsys.readouterr().out


def test_a_characteristic_without_salinity_names_the_option(tmp_path, capsys):
    rig_runs(tmp_path / "runs", salinity=False)
    assert main(["evaluate", str(tmp_path / "runs"), "--out", str(tmp_path / "eval"),
                 "--no-plots", "-q"]) == 0
    char = tmp_path / "eval" / "steady_characteristic.csv"
    assert main(["discrepancy", "--steady", str(char), "--out", str(tmp_path / "d")]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "salinity_pct" in err[0] and "--salinity" in err[0]
    from friction_model.discrepancy import read_steady_table

    table = read_steady_table(char, salinity_pct=0.0)
    # pressure from the forces over G3's nominal area (20 mm x 80 mm): 400 N -> 2.5 bar
    assert np.allclose(table["pressure_bar"], 2.5, rtol=0.01)
    assert set(table["n_sipes"]) == {3} and len(table) == 9


def test_one_condition_is_held_out_by_velocity_level(evaluated):
    """The demo's sweep is one condition: hold-out groups are its velocity levels (repeats
    together), not nine single runs (measured conditions scatter per run) nor one group."""
    from friction_model.discrepancy import SteadyProblem, read_steady_table

    root, _ = evaluated
    table = read_steady_table(root / "eval" / "steady_characteristic.csv")
    assert table["pressure_bar"].nunique() == 1 and table["temperature_C"].nunique() == 1
    problem = SteadyProblem(table)
    assert problem.groups.tolist() == [0, 0, 0, 1, 1, 1, 2, 2, 2]


def test_calibrate_auto_that_cannot_decide_exits_2_naming_the_laws(tmp_path, capsys):
    path = tmp_path / "three.csv"
    pd.DataFrame({"velocity_mps": VELOCITIES, "mu": [0.2516, 0.1778, 0.1691]}).to_csv(
        path, index=False)
    assert main(["calibrate", "--characteristic", str(path), "--out",
                 str(tmp_path / "p.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot choose a friction law" in err[0]
    assert "still in play: ConstantLaw, DecreasingSqrtLaw" in err[0] and "--law" in err[0]
    assert not (tmp_path / "p.json").exists()


def test_the_generators_raw_runs_of_two_blocks_go_through_evaluate_to_discrepancy(tmp_path):
    # synth measurements --kind raw (G0 and G3 runs) -> evaluate -> the discrepancy's steady
    # table, nothing given by hand: each row's salinity from the run files, its sipes and
    # nominal pressure (force over area) from its own specimen's reference block (before:
    # no salinity_pct, and no n_sipes for a file of two specimens)
    from friction_model.discrepancy import read_steady_table

    assert main(["synth", "measurements", "--kind", "raw", "--velocities", "1,3",
                 "--repeats", "2", "--out", str(tmp_path / "raw")]) == 0
    assert main(["evaluate", str(tmp_path / "raw"), "--out", str(tmp_path / "ev"),
                 "--no-plots", "-q"]) == 0
    char = tmp_path / "ev" / "steady_characteristic.csv"
    table = read_steady_table(char)
    rows = pd.read_csv(char)
    rows = rows[rows.row_type == "run"] if "row_type" in rows else rows
    sipes = {"G0": 0, "G3": 3}
    assert sorted(table["n_sipes"]) == sorted(sipes[s] for s in rows.specimen)
    assert (table["salinity_pct"] == 0.0).all()
    # the generator's 2.5 bar (its normal force noise is about 1 N of 400 N)
    assert np.allclose(table["pressure_bar"], 2.5, rtol=0.01)
    # without the recorded pressure: each row's force over its own specimen's nominal area
    # (every reference block has 1600 mm2, so this checks the path, which refused a file
    # of two specimens before, not a difference between the areas)
    rows.drop(columns="normal_pressure_Pa").to_csv(tmp_path / "no_p.csv", index=False)
    forced = read_steady_table(tmp_path / "no_p.csv")
    assert np.allclose(forced["pressure_bar"], table["pressure_bar"], rtol=1e-9)
