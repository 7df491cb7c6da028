"""Tests of the test-rig evaluation (thesis sections 4.2.4 and 4.4) against synthetic truth."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from friction_model.rig import (
    AMBIENT_COLUMNS,
    INSTATIONARY_COLUMNS,
    STEADY_COLUMNS,
    InstationaryParams,
    RunFormatError,
    WindowParams,
    ambient_table,
    collect_run_files,
    evaluate_folder,
    evaluate_instationary_run,
    evaluate_runs,
    evaluate_steady_run,
    find_constant_velocity_window,
    friction_coefficient,
    instationary_characteristic,
    mean_friction_coefficients,
    read_run,
)
from synthetic.rig import make_raw_run, write_run_csv

F_N = 300.0  # N, spring preload of every synthetic run
NOISE = 2.0  # N, white noise on each force signal


def constant(mu: float):
    return lambda v: np.full_like(v, mu)


def law(v):
    """A decreasing friction law like the measured characteristics of chapter 4.3."""
    return 0.12 + 0.25 * np.exp(-np.asarray(v) / 1.5)


def write_run(path: Path, mu_of_v=None, *, rate: float = 2000, rng: int = 0, **kw) -> pd.DataFrame:
    mu_of_v = constant(0.2) if mu_of_v is None else mu_of_v
    kw.setdefault("normal_force_N", F_N)
    kw.setdefault("force_noise_N", NOISE)
    df = make_raw_run(mu_of_v, sample_rate_Hz=rate, rng=rng, **kw)
    write_run_csv(df, path)
    return df


def mu_noise_std(mu: float, noise_N: float = NOISE, fn: float = F_N) -> float:
    """Std of mu(t) = (mu F_N + e_F) / (F_N + e_N) to first order in the noise."""
    return math.sqrt(noise_N**2 + (mu * noise_N) ** 2) / fn


# --------------------------------------------------------------------------------------------
# steady runs


@pytest.mark.parametrize("mu", [0.05, 0.2, 0.6])
@pytest.mark.parametrize("rate", [2000, 5000])
def test_recovers_constant_mu(tmp_path, mu, rate):
    path = tmp_path / "run.csv"
    write_run(path, constant(mu), rate=rate, rng=int(mu * 100) + rate)
    res = evaluate_steady_run(read_run(path))
    n = res.window.stop - res.window.start
    # white noise only: the window mean has standard error std(mu(t)) / sqrt(n); 5 sigma
    tol = 5.0 * mu_noise_std(mu) / math.sqrt(n)
    assert_allclose(res.mu_mean_method1, mu, atol=tol)
    assert_allclose(res.mu_mean_method2, mu, atol=tol)
    # the measured velocity is the plateau velocity up to the velocity noise (2 mm/s white)
    assert_allclose(res.velocity_mps, 1.0, atol=5 * 0.002 / math.sqrt(n))
    assert_allclose(res.normal_force_N, F_N, rtol=0.011)  # surface ripple is +-1 %


@pytest.mark.parametrize(("flip", "said"), [
    (("velocity_mps", "friction_force_N"),
     "column 'velocity_mps'.*mean -1 m/s.*flip the signs of velocity_mps and friction_force_N"),
    (("friction_force_N",), "column 'friction_force_N'.*mean -.*flip the sign of "
                            "friction_force_N"),
    (("velocity_mps",), "column 'velocity_mps'.*mean -1 m/s.*flip the sign of velocity_mps"),
])
def test_a_run_of_the_other_sign_convention_is_refused(tmp_path, flip, said):
    # velocity positive in the sliding direction, friction positive against the motion
    # (docs/formats.md): a rig logging the other way gave mu -0.43 with exit 0 (helper-12)
    df = make_raw_run(constant(0.2), sample_rate_Hz=2000, rng=3, normal_force_N=F_N,
                      force_noise_N=NOISE)
    for col in flip:
        df[col] = -df[col]
    write_run_csv(df, tmp_path / "run.csv")
    with pytest.raises(RunFormatError, match=said):
        evaluate_steady_run(read_run(tmp_path / "run.csv"))


def test_methods_agree_within_footnote_7(tmp_path):
    # thesis footnote 7: both methods differ by less than 0.2 % on the evaluated measurements
    path = tmp_path / "clean.csv"
    write_run(path, law, rate=5000, force_noise_N=0.5, velocity_mps=2.0)
    res = evaluate_steady_run(read_run(path))
    rel = abs(res.mu_mean_method1 - res.mu_mean_method2) / res.mu_mean_method2
    assert rel < 2e-3
    assert_allclose(res.mu_mean_method1, law(2.0), atol=1e-3)


def test_methods_identical_without_noise(tmp_path):
    # F_F = mu F_N exactly: mu(t) == mu, so both averages are mu to rounding (9 digits in CSV)
    path = tmp_path / "exact.csv"
    write_run(path, constant(0.3), force_noise_N=0.0, velocity_noise_mps=0.0)
    res = evaluate_steady_run(read_run(path))
    assert_allclose([res.mu_mean_method1, res.mu_mean_method2], 0.3, rtol=1e-8)
    assert res.mu_std_t < 1e-8


@pytest.mark.parametrize(
    ("velocity", "accel", "plateau", "rate"),
    [(1.0, 5.0, 1.0, 2000), (0.1, 1.0, 0.8, 2000), (5.0, 10.0, 0.5, 5000), (3.0, 2.0, 1.2, 1000)],
)
def test_window_inside_true_constant_phase(tmp_path, velocity, accel, plateau, rate):
    path = tmp_path / "run.csv"
    df = write_run(
        path,
        velocity_mps=velocity,
        accel_mps2=accel,
        decel_mps2=accel,
        plateau_s=plateau,
        rate=rate,
    )
    ph = df.attrs["phases"]
    win = evaluate_steady_run(read_run(path)).window
    assert ph["plateau_start_s"] <= win.start_s < win.end_s <= ph["plateau_end_s"]
    # default settle_s = 0.05 s at each end plus at most one smoothing length (0.02 s) lost at
    # each corner of the velocity profile
    assert win.duration_s >= plateau - 2 * (0.05 + 0.02)
    assert_allclose(win.velocity_mps, velocity, rtol=1e-3)


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    velocity=st.floats(0.1, 8.0),
    accel=st.floats(1.0, 20.0),
    plateau=st.floats(0.3, 1.5),
    noise=st.floats(0.0, 0.01),  # up to 5x the generator's default velocity noise
    seed=st.integers(0, 2**16),
)
def test_window_inside_plateau_property(velocity, accel, plateau, noise, seed):
    df = make_raw_run(
        constant(0.2),
        velocity_mps=velocity,
        accel_mps2=accel,
        decel_mps2=accel,
        plateau_s=plateau,
        sample_rate_Hz=1000,
        velocity_noise_mps=noise,
        rng=seed,
    )
    ph = df.attrs["phases"]
    win = find_constant_velocity_window(df["time_s"], df["velocity_mps"])
    assert ph["plateau_start_s"] <= win.start_s < win.end_s <= ph["plateau_end_s"]
    assert win.duration_s >= plateau - 2 * (0.05 + 0.02)


def test_window_of_hand_made_profile():
    # 0.2 s rest, ramp 5 m/s^2 to 1 m/s at 0.4 s, plateau to 1.6 s, ramp down to 0 at 1.8 s.
    # smoothing 0.02 s = box of +-0.01 s, differentiated over +-0.01 s: a triangular kernel of
    # half-width 0.02 s; |a_s| <= 0.5 m/s^2 = a/10 once the kernel's tail weight on the ramp,
    # (x/0.02)^2/2, is <= 0.1, i.e. from 0.0111 s after the corner; then settle_s = 0.05 s.
    t = np.arange(0.0, 2.0, 1e-3)
    v = np.interp(t, [0, 0.2, 0.4, 1.6, 1.8, 2.0], [0, 0, 1, 1, 0, 0])
    win = find_constant_velocity_window(t, v)
    assert_allclose(win.start_s, 0.4 + 0.0111 + 0.05, atol=2e-3)  # one sample either way
    assert_allclose(win.end_s, 1.6 - 0.0111 - 0.05, atol=2e-3)
    assert_allclose(win.velocity_mps, 1.0, rtol=1e-12)  # cumulative-sum rounding only


def test_window_of_constant_velocity_everywhere():
    # a record that is all plateau: only the settle margins are trimmed, exactly to the sample
    t = np.arange(0.0, 1.0, 1e-3)
    win = find_constant_velocity_window(t, np.full_like(t, 2.0), settle_s=0.1)
    assert (win.start, win.stop) == (100, 900)
    assert_allclose([win.start_s, win.end_s], [0.1, 0.899], atol=1e-12)


@pytest.mark.parametrize(
    "v",
    [np.zeros(1000), np.linspace(0.0, 5.0, 1000), np.concatenate([np.zeros(500), np.ones(20)])],
    ids=["standstill", "ramp", "too_short"],
)
def test_window_not_found(v):
    t = np.arange(v.size) * 1e-3
    with pytest.raises(ValueError, match="no constant-velocity phase"):
        find_constant_velocity_window(t, v)


def test_window_parameters_validated():
    t = np.arange(100) * 1e-3
    with pytest.raises(ValueError, match="smoothing_s must be a finite number > 0"):
        find_constant_velocity_window(t, np.ones(100), smoothing_s=0.0)
    with pytest.raises(ValueError, match="bin_width_mps"):
        InstationaryParams(bin_width_mps=-0.1)


def test_friction_coefficient_and_both_methods_analytic():
    assert_allclose(friction_coefficient([1.0, 3.0], [2.0, 4.0]), [0.5, 0.75], rtol=1e-15)
    # trapezoid: method 1 = integral(F_F/F_N)/T, method 2 = integral(F_F)/integral(F_N)
    m1, m2 = mean_friction_coefficients([0.0, 1.0, 2.0], [1.0, 2.0, 3.0], [2.0, 2.0, 2.0])
    assert_allclose([m1, m2], [1.0, 1.0], rtol=1e-15)
    m1, m2 = mean_friction_coefficients([0.0, 1.0], [1.0, 1.0], [1.0, 2.0])
    assert_allclose([m1, m2], [0.75, 1.0 / 1.5], rtol=1e-15)


# --------------------------------------------------------------------------------------------
# repeated runs and ambient averages


def test_std_over_repeated_runs_matches_known_spread(tmp_path):
    gen = np.random.default_rng(42)
    mus = 0.2 + 0.01 * gen.standard_normal(10)  # known run-to-run scatter of the true mu
    for i, mu in enumerate(mus, start=1):
        write_run(
            tmp_path / f"G3_{i}.csv",
            constant(mu),
            rng=100 + i,
            metadata={"specimen": "G3", "condition": "T-3", "run": i},
        )
    res = evaluate_runs([tmp_path], progress=False)
    assert res.ok
    agg = res.steady[res.steady["row_type"] == "aggregate"]
    assert len(agg) == 1 and agg["n_runs"].iloc[0] == 10
    n = res.steady.loc[res.steady["row_type"] == "run", "n_samples"].min()
    se = mu_noise_std(0.2) / math.sqrt(n)  # standard error of one run's mean
    # per-run estimates are mu_i + e_i with |e_i| ~ se; the sample std moves by at most std(e)
    assert_allclose(agg["mu_mean_method1"].iloc[0], mus.mean(), atol=5 * se)
    assert_allclose(agg["mu_std_runs"].iloc[0], np.std(mus, ddof=1), atol=5 * se)
    # recovered per-run values in file order (natural sort: G3_2 before G3_10)
    runs = res.steady[res.steady["row_type"] == "run"]
    assert runs["run"].tolist() == list(range(1, 11))
    assert_allclose(runs["mu_mean_method1"], mus, atol=5 * se)


def test_std_over_time_matches_force_noise(tmp_path):
    path = tmp_path / "run.csv"
    write_run(path, constant(0.3), rate=5000, plateau_s=1.0, normal_force_ripple=0.0)
    res = evaluate_steady_run(read_run(path))
    n = res.window.stop - res.window.start
    # relative standard error of a sample std of n white samples is 1/sqrt(2(n-1)) ~ 1.1 %;
    # 5 % is > 4 sigma
    assert_allclose(res.mu_std_t, mu_noise_std(0.3), rtol=max(0.05, 4.5 / math.sqrt(2 * n)))


def test_ambient_averages_per_specimen(tmp_path):
    ambient = {
        ("Spec1", 1): (-3.9, 71.9),
        ("Spec1", 2): (-3.7, 72.1),
        ("Spec2", 1): (-3.8, 72.4),
        ("Spec2", 2): (-4.1, 73.0),
        ("Spec2", 3): (-3.6, 72.6),
    }
    for (spec, run), (temp, hum) in ambient.items():
        write_run(
            tmp_path / f"{spec}_{run}.csv",
            temperature_C=temp,
            humidity_pct=hum,
            rng=run,
            metadata={"specimen": spec, "run": run},
        )
    res = evaluate_runs([tmp_path], progress=False)
    table = res.ambient.set_index("specimen")
    assert list(res.ambient.columns) == list(AMBIENT_COLUMNS)
    assert list(table.index) == ["Average", "Spec1", "Spec2"]
    values = np.array(list(ambient.values()))
    # drift is linear about the run's middle (mean exact); sensor noise 0.02 degC / 0.1 % per
    # sample over ~3400 samples gives standard errors 3.4e-4 degC / 1.7e-3 %; 5 sigma
    cols = ["temperature_C", "humidity_pct"]
    for name, part in (("Average", values), ("Spec1", values[:2]), ("Spec2", values[2:])):
        got = table.loc[name, cols].to_numpy(float)
        assert np.all(np.abs(got - part.mean(0)) <= [2e-3, 9e-3])
    assert table["n_runs"].tolist() == [5, 2, 3]


def test_ambient_table_hand_made():
    runs = pd.DataFrame(
        {
            "specimen": ["B", "A", "B", "A10", "A2"],
            "temperature_C": [-4.0, -3.0, -2.0, np.nan, -5.0],
            "humidity_pct": [70.0, 72.0, 74.0, 80.0, np.nan],
        }
    )
    table = ambient_table(runs)
    assert table["specimen"].tolist() == ["Average", "A", "A2", "A10", "B"]  # natural order
    assert_allclose(table["temperature_C"], [-3.5, -3.0, -5.0, np.nan, -3.0], rtol=1e-15)
    assert_allclose(table["humidity_pct"], [74.0, 72.0, np.nan, 80.0, 72.0], rtol=1e-15)
    assert_allclose(table.loc[4, "temperature_std_C"], math.sqrt(2.0), rtol=1e-15)


def test_aggregates_group_by_velocity(tmp_path):
    for v in (1.0, 3.0):
        for i in (1, 2):
            write_run(
                tmp_path / f"v{v:g}_{i}.csv",
                law,
                velocity_mps=v,
                accel_mps2=10.0,
                decel_mps2=10.0,
                rng=i,
                metadata={"specimen": "G0", "run": i},
            )
    res = evaluate_runs([tmp_path], progress=False)
    agg = res.steady[res.steady["row_type"] == "aggregate"]
    assert agg["n_runs"].tolist() == [2, 2]
    # within-window noise se ~ 1.6e-4 per run; law changes by 0.1 between the velocities
    assert_allclose(agg["velocity_mps"], [1.0, 3.0], atol=1e-3)
    assert_allclose(agg["mu_mean_method1"], law(np.array([1.0, 3.0])), atol=1e-3)


# --------------------------------------------------------------------------------------------
# instationary runs


def instationary_run(tmp_path: Path, **kw) -> tuple[Path, pd.DataFrame]:
    path = tmp_path / "inst.csv"
    kw = {
        "kind": "instationary",
        "velocity_mps": 4.0,
        "accel_mps2": 4.0,
        "decel_mps2": 4.0,
        "inertial_mass_kg": 12.5,
        "force_noise_N": 1.0,
        "rate": 5000,
        "rng": 3,
        **kw,
    }
    return path, write_run(path, law, **kw)


def test_instationary_recovers_law_after_inertia_removal(tmp_path):
    path, _ = instationary_run(tmp_path)
    res = evaluate_instationary_run(read_run(path))  # mass from the metadata
    table = res.table
    assert list(table.columns) == list(INSTATIONARY_COLUMNS)
    assert set(table["branch"]) == {"accelerating", "decelerating"}
    assert table["velocity_mps"].max() > 3.7 and table["velocity_mps"].min() < 0.3
    # ~300 samples per bin, raw noise std(mu) ~ 3.5e-3 -> standard error 2e-4; the law's
    # curvature makes the bin mean differ from law(mean v) by < w^2 |mu''| / 24 < 3e-4
    assert_allclose(table["mu"], law(table["velocity_mps"]), atol=2e-3)
    assert (table["n"] >= 20).all()


def test_instationary_without_inertia_removal_is_biased(tmp_path):
    # with a constant normal force the inertial force adds exactly m a / F_N to mu
    path, _ = instationary_run(tmp_path, normal_force_ripple=0.0)
    run = read_run(path)
    biased = evaluate_instationary_run(run, inertial_mass_kg=0.0).table
    # the top bin holds the velocity peak, where the filtered acceleration changes sign
    biased = biased[biased["velocity_mps"] < 4.0 - 0.25]
    bias = np.where(biased["branch"] == "accelerating", 12.5 * 4.0, -12.5 * 4.0) / F_N
    assert_allclose(biased["mu"], law(biased["velocity_mps"]) + bias, atol=2e-3)
    assert np.all(np.abs(bias) > 50 * 2e-3)  # 0.167, far outside the tolerance above


def test_instationary_branches_match_steady_points(tmp_path):
    # Fig. 4.22 b: steady measurements hit the instationary curve
    path, _ = instationary_run(tmp_path)
    inst = evaluate_instationary_run(read_run(path), params=InstationaryParams(bin_width_mps=0.1))
    for v in (1.0, 2.5):
        steady_path = tmp_path / f"steady_{v}.csv"
        write_run(steady_path, law, velocity_mps=v, accel_mps2=10.0, decel_mps2=10.0, rate=5000)
        mu = evaluate_steady_run(read_run(steady_path)).mu_mean_method1
        for _, branch in inst.table.groupby("branch"):
            curve = np.interp(v, branch["velocity_mps"], branch["mu"])
            # both within ~1e-3 of the law; linear interpolation over 0.1 m/s adds < 2e-4
            assert_allclose(curve, mu, atol=2e-3)


def test_instationary_characteristic_arrays_and_bins():
    t = np.arange(0.0, 2.0, 1e-4)
    v = np.interp(t, [0, 0.1, 1.1, 2.0], [0, 0, 2.0, 2.0 - 0.9 * 2.0])
    a = np.gradient(v, t)
    fn = np.full_like(t, 200.0)
    ff = 0.25 * fn * (v > 0) + 10.0 * a
    table = instationary_characteristic(t, v, ff, fn, inertial_mass_kg=10.0, bin_width_mps=0.5)
    acc = table[table["branch"] == "accelerating"]
    # noise-free constant mu: exact after removing m a (away from the kinks excluded)
    assert_allclose(table["mu"], 0.25, atol=1e-9)
    # bins [0.5 k, 0.5 (k+1)): at constant acceleration the full bins (k = 1, 2) hold
    # 0.5 m/s / (2 m/s^2 * 1e-4 s) = 2500 samples spread evenly, centred on the bin centre
    full = acc.iloc[1:3]
    assert_allclose(full["velocity_mps"], [0.75, 1.25], atol=2e-4)  # one sample step
    assert np.all(np.abs(full["n"] - 2500) <= 1)


def test_instationary_missing_mass(tmp_path):
    path = tmp_path / "inst_nomass.csv"
    df = make_raw_run(law, kind="instationary", sample_rate_Hz=2000, velocity_mps=2.0, rng=1)
    meta = {k: v for k, v in df.attrs["metadata"].items() if k != "inertial_mass_kg"}
    write_run_csv(df, path, meta)
    match = r"inst_nomass\.csv.*'inertial_mass_kg'.*file lines 1 to 1"
    with pytest.raises(RunFormatError, match=match):
        evaluate_instationary_run(read_run(path))
    # an explicit mass needs no metadata
    assert not evaluate_instationary_run(read_run(path), inertial_mass_kg=12.5).table.empty


# --------------------------------------------------------------------------------------------
# reading and validation


def test_round_trip_write_read(tmp_path):
    path = tmp_path / "rt.csv"
    meta = {
        "specimen": "G5",
        "run": 7,
        "nominal_area_mm2": 1600,
        "condition": "T=-8 C",
        "ice": "clear",
    }
    df = write_run(path, metadata=meta, rate=1000)
    run = read_run(path)
    for col in ("time_s", "velocity_mps", "normal_force_N", "friction_force_N", "temperature_C"):
        assert_allclose(getattr(run, col), df[col], rtol=1e-8, atol=1e-12)  # 9 digits in CSV
    assert run.metadata["run"] == 7 and run.metadata["nominal_area_mm2"] == 1600.0
    assert run.specimen == "G5" and run.condition == "T=-8 C" and run.metadata["ice"] == "clear"
    assert run.kind == "steady" and run.metadata["inertial_mass_kg"] == 12.5
    assert run.header_line == 8
    res = evaluate_steady_run(run)
    assert_allclose(res.normal_pressure_Pa, res.normal_force_N / 1600e-6, rtol=1e-15)
    assert res.as_row()["meta_ice"] == "clear"


def test_reads_blanks_and_optional_columns(tmp_path):
    path = tmp_path / "min.csv"
    t = np.arange(0.0, 1.0, 1e-3)
    lines = ["# specimen: X", "# a free comment without key", ""]
    lines.append("time_s , velocity_mps, normal_force_N, friction_force_N, side_force_N")
    lines += [f"{x:.4f}, 1.0, 100, 20, 3" for x in t]
    path.write_text("\n".join(lines) + "\n\n\n")
    run = read_run(path)
    assert len(run) == t.size and run.temperature_C is None and run.humidity_pct is None
    assert run.header_line == 4
    res = evaluate_steady_run(run)
    assert_allclose(res.mu_mean_method1, 0.2, rtol=1e-12)
    assert math.isnan(res.temperature_C)


def _corrupt(path: Path, row: int, column: str, text: str) -> None:
    """Replace the value of ``column`` in 1-based data row ``row``."""
    lines = path.read_text().splitlines(keepends=True)
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    names = [c.strip() for c in lines[header].split(",")]
    fields = lines[header + row].rstrip("\n").split(",")
    fields[names.index(column)] = text
    lines[header + row] = ",".join(fields) + "\n"
    path.write_text("".join(lines))


@pytest.mark.parametrize(
    ("column", "row", "text", "expected"),
    [
        ("normal_force_N", 100, "nan", "expected a finite number, got an empty field / NaN"),
        ("velocity_mps", 57, "", "expected a finite number, got an empty field / NaN"),
        ("friction_force_N", 1234, "12,5", None),  # an extra field: malformed row
        ("friction_force_N", 200, "abc", "expected a finite number, got 'abc'"),
        ("temperature_C", 3, "inf", "expected a finite number, got inf"),
        ("time_s", 301, "0.1495", "time must increase strictly"),
    ],
)
def test_bad_values_name_file_column_row(tmp_path, column, row, text, expected):
    path = tmp_path / "bad_values.csv"
    write_run(path)  # 2 kHz: data row 301 has time 0.15 s, row 300 has 0.1495 s
    _corrupt(path, row, column, text)
    header_line = 3  # two metadata lines, then the column header
    with pytest.raises(RunFormatError) as info:
        read_run(path)
    err = info.value
    msg = str(err)
    assert "bad_values.csv" in msg
    if expected is None:  # an extra field: no single column is to blame
        assert f"malformed CSV, data row {row} (file line {header_line + row})" in msg
        assert "expected 6 fields like the column header (file line 3), got 7" in msg
        return
    assert expected in msg
    assert f"column '{column}'" in msg
    assert f"data row {row} (file line {header_line + row})" in msg
    assert (err.column, err.row, err.line) == (column, row, header_line + row)


def test_missing_column(tmp_path):
    path = tmp_path / "no_ff.csv"
    df = make_raw_run(constant(0.2), sample_rate_Hz=1000, rng=0).drop(columns="friction_force_N")
    write_run_csv(df, path)
    match = r"no_ff\.csv: column 'friction_force_N' missing .*file line 3"
    with pytest.raises(RunFormatError, match=match):
        read_run(path)


def test_normal_force_not_positive_in_window(tmp_path):
    path = tmp_path / "unloaded.csv"
    df = write_run(path)
    inside = int(np.searchsorted(df["time_s"], 0.8))  # plateau is 0.3 s to 1.3 s
    _corrupt(path, inside + 1, "normal_force_N", "-0.5")
    with pytest.raises(RunFormatError) as info:
        evaluate_steady_run(read_run(path))
    msg = str(info.value)
    assert "unloaded.csv" in msg and "column 'normal_force_N'" in msg
    assert f"data row {inside + 1} (file line {3 + inside + 1})" in msg
    assert "expected a normal force > 0 N" in msg and "got -0.5 N" in msg


def test_normal_force_outside_window_is_ignored(tmp_path):
    # the sample is lifted off at the end: F_N ~ 0 +- noise there, outside the window
    path = tmp_path / "lift.csv"
    df = write_run(path, lift_off_s=0.1)
    assert (df["normal_force_N"] <= 0).any()
    assert_allclose(evaluate_steady_run(read_run(path)).mu_mean_method1, 0.2, atol=1e-3)


def test_no_constant_velocity_phase(tmp_path):
    path = tmp_path / "ramp.csv"
    write_run(path, kind="instationary", velocity_mps=3.0)
    with pytest.raises(RunFormatError) as info:
        evaluate_steady_run(read_run(path))
    msg = str(info.value)
    assert "ramp.csv" in msg and "column 'velocity_mps'" in msg
    assert "no constant-velocity phase found" in msg and "data row" in msg and "file line" in msg
    assert info.value.column == "velocity_mps"


@pytest.mark.parametrize(
    ("header", "match"),
    [
        ("# run: three\n", r"metadata key 'run', file line 1: expected an integer, got 'three'"),
        (
            "# kind: wobbly\n",
            r"metadata key 'kind', file line 1: expected one of 'steady', 'instationary'",
        ),
        ("# nominal_area_mm2: -5\n", r"metadata key 'nominal_area_mm2', file line 1"),
    ],
)
def test_bad_metadata(tmp_path, header, match):
    path = tmp_path / "meta.csv"
    path.write_text(header + "time_s,velocity_mps,normal_force_N,friction_force_N\n0,0,1,0\n")
    with pytest.raises(RunFormatError, match=r"meta\.csv: " + match):
        read_run(path)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", "no column header found"),
        ("# specimen: A\n", "no column header found"),
        ("time_s,velocity_mps,normal_force_N,friction_force_N\n0,0,1,0\n", "at least 2 data rows"),
        (
            "time_s,time_s,velocity_mps,normal_force_N,friction_force_N\n",
            "column 'time_s' appears more than once .*file line 1",
        ),
    ],
)
def test_degenerate_files(tmp_path, text, match):
    path = tmp_path / "degenerate.csv"
    path.write_text(text)
    with pytest.raises(RunFormatError, match=match):
        read_run(path)


def test_run_format_error_is_value_error():
    err = RunFormatError("x.csv", "column 'a', data row 1 (file line 2): bad", column="a", row=1)
    assert isinstance(err, ValueError) and str(err).startswith("x.csv: column 'a'")


# --------------------------------------------------------------------------------------------
# batch and outputs


def test_batch_with_broken_file_writes_good_results(tmp_path):
    runs = tmp_path / "runs"
    runs.mkdir()
    for i in (1, 2, 3):
        meta = {"specimen": "G0", "run": i}
        write_run(runs / f"G0_{i}.csv", constant(0.25), rng=i, metadata=meta)
    broken = runs / "G0_broken.csv"
    write_run(broken, rng=9)
    _corrupt(broken, 10, "velocity_mps", "fast")
    instationary_run(runs)
    out = tmp_path / "out"
    res = evaluate_folder(runs, out, progress=False)
    assert not res.ok
    assert [f.file for f in res.failures] == [str(broken)]
    assert "column 'velocity_mps', data row 10" in res.failures[0].message
    steady = pd.read_csv(out / "steady_characteristic.csv")
    assert list(steady.columns[: len(STEADY_COLUMNS)]) == list(STEADY_COLUMNS)
    assert steady["row_type"].tolist() == ["run", "run", "run", "aggregate"]
    assert_allclose(steady["mu_mean_method1"], 0.25, atol=1e-3)
    inst = pd.read_csv(out / "instationary_characteristic.csv")
    assert set(inst["branch"]) == {"accelerating", "decelerating"}
    ambient = pd.read_csv(out / "ambient.csv", keep_default_na=False)
    assert ambient["specimen"].tolist() == ["Average", "", "G0"]  # inst.csv has no specimen
    assert ambient["n_runs"].tolist() == [4, 1, 3]
    assert (out / "mu_v.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in (out / "mu_t").iterdir()) == [
        "G0_1.png",
        "G0_2.png",
        "G0_3.png",
        "inst.png",
    ]
    prov = json.loads((out / "provenance.json").read_text())
    assert prov["failures"][0]["file"] == str(broken)
    assert prov["parameters"]["window"] == WindowParams().__dict__
    assert not [p for p in out.rglob("*") if p.name.endswith(".tmp")]  # atomic writes


def test_batch_reports_missing_file_and_empty_folder(tmp_path):
    (tmp_path / "empty").mkdir()
    good = tmp_path / "good.csv"
    write_run(good)
    res = evaluate_runs([tmp_path / "empty", tmp_path / "missing.csv", good], progress=False)
    assert [Path(f.file).name for f in res.failures] == ["empty", "missing.csv"]
    assert "no *.csv" in res.failures[0].message and "cannot read" in res.failures[1].message
    assert len(res.steady_runs) == 1


def test_forced_instationary_mode_and_mass_override(tmp_path):
    path, _ = instationary_run(tmp_path)
    meta_mass = evaluate_runs([path], progress=False).instationary
    override = evaluate_runs([path], instationary=True, inertial_mass_kg=0.0, progress=False)
    assert (override.instationary["inertial_mass_kg"] == 0.0).all()
    diff = override.instationary["mu"].to_numpy() - meta_mass["mu"].to_numpy()
    # +m a / F_N while accelerating (F_N ripple 1 %); not the top bin holding the peak
    acc = ((meta_mass["branch"] == "accelerating") & (meta_mass["velocity_mps"] < 3.75)).to_numpy()
    assert_allclose(diff[acc], 12.5 * 4.0 / F_N, rtol=0.02)


def test_collect_run_files_natural_order(tmp_path):
    for name in ("run_10.csv", "run_2.csv", "run_1.csv", "notes.txt"):
        (tmp_path / name).write_text("")
    files = collect_run_files([tmp_path, tmp_path / "run_2.csv"])
    assert [p.name for p in files] == ["run_1.csv", "run_2.csv", "run_10.csv"]


def test_generator_is_reproducible_and_exact():
    a = make_raw_run(law, sample_rate_Hz=1000, rng=5)
    b = make_raw_run(law, sample_rate_Hz=1000, rng=np.random.default_rng(5))
    pd.testing.assert_frame_equal(a, b)
    truth = a.attrs["truth"]
    moving = truth["velocity_mps"] > 0
    assert_allclose(truth["mu"][moving], law(truth["velocity_mps"][moving]), rtol=1e-15)
    with pytest.raises(ValueError, match="kind must be"):
        make_raw_run(law, kind="sideways")


# ---------------------------------------------------------------------------------------------
# the scipy.ndimage mask helpers equal a naive computation


def _naive_runs(mask):
    spans, i = [], 0
    while i < len(mask):
        if mask[i]:
            j = i
            while j < len(mask) and mask[j]:
                j += 1
            spans.append((i, j))
            i = j
        else:
            i += 1
    return spans


def _naive_close_gaps(mask, max_gap):
    out = mask.copy()
    for s, e in _naive_runs(~mask):
        if s > 0 and e < len(mask) and e - s <= max_gap:
            out[s:e] = True
    return out


def _naive_evaluated(v_ss, half, min_velocity):
    n, support = len(v_ss), 2 * half
    still = np.abs(v_ss) < min_velocity
    return np.array(
        [
            support <= i < n - support
            and not still[max(i - support, 0) : min(i + support + 1, n)].any()
            for i in range(n)
        ],
        dtype=bool,
    )


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.booleans(), min_size=0, max_size=60),
    st.integers(min_value=0, max_value=8),
)
def test_mask_helpers_equal_naive(bits, max_gap):
    from friction_model.rig.instationary import _evaluated_samples
    from friction_model.rig.plateaus import _close_gaps, _true_runs

    mask = np.array(bits, dtype=bool)
    starts, stops = _true_runs(mask)
    assert list(zip(starts.tolist(), stops.tolist(), strict=True)) == _naive_runs(mask)
    np.testing.assert_array_equal(_close_gaps(mask, max_gap), _naive_close_gaps(mask, max_gap))
    v = np.where(mask, 1.0, 0.0)
    half = max(max_gap // 2, 1)
    np.testing.assert_array_equal(
        _evaluated_samples(v, half, 0.5), _naive_evaluated(v, half, 0.5)
    )


@settings(max_examples=100, deadline=None)
@given(st.lists(st.booleans(), min_size=1, max_size=60), st.integers(min_value=1, max_value=8))
def test_close_gaps_is_the_morphological_closing(bits, max_gap):
    """The gap closing equals scipy.ndimage's closing of the False-padded mask."""
    from scipy import ndimage

    from friction_model.rig.plateaus import _close_gaps

    mask = np.array(bits, dtype=bool)
    size = max_gap + 1
    padded = np.pad(mask, size)
    closed = ndimage.binary_closing(padded, structure=np.ones(size, dtype=bool))[size:-size]
    np.testing.assert_array_equal(_close_gaps(mask, max_gap), closed)


def test_no_path_that_exists_is_an_error_and_writes_nothing(tmp_path):
    # before, evaluate_folder on a mistyped folder wrote empty tables and plots and said
    # so only at INFO level (the CLI refused it already); one missing among others stays
    # a failure of the result (test_batch_reports_missing_file_and_empty_folder)
    with pytest.raises(FileNotFoundError, match=r"nope: does not exist"):
        evaluate_folder(tmp_path / "nope", tmp_path / "out", progress=False)
    assert not (tmp_path / "out").exists()
