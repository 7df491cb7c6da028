"""Tests of synthetic.measurements: effects switch the model as stated, noise has the stated
statistics, the dynamic effects shape the transient as stated, outputs are reproducible and
blind unless revealed."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from friction_model.contact.drywet import DryWetParameters, friction_table
from friction_model.contact.effects import DRY_WET_EFFECTS, EFFECT_NAMES, Effects
from friction_model.geometry import BlockGeometry
from friction_model.rig import evaluate_steady_run, read_run
from synthetic.measurements import (
    MODULUS_ALPHA,
    STEADY_COLUMNS,
    TAU_REF_S,
    TRANSIENT_COLUMNS,
    EffectSpec,
    SteadyGrid,
    arm_storage_ratio,
    element_natural_frequency_Hz,
    make_raw_runs,
    make_steady_table,
    make_transient_table,
    modulus_ratio,
    modulus_scaled_frequency_Hz,
    truth_path,
    write_measurements,
)

SMALL_GRID = {
    "velocities_mps": (1.0, 2.0, 3.0, 5.0, 7.0),
    "pressures_bar": (2.5,),
    "temperatures_C": (-5.0, -1.0),
    "humidities_pct": (40.0, 90.0),
    "salinities_pct": (0.0, 0.05),
    "n_sipes": (0, 3),
}
CONDITIONS = list(STEADY_COLUMNS[:6])


def model_table(effects: Effects, grid=SMALL_GRID) -> pd.DataFrame:
    """The friction model's mu on the grid, computed here independently per geometry."""
    rows = SteadyGrid(**grid).frame()
    parts = []
    for n, group in rows.groupby("n_sipes"):
        t = friction_table(
            BlockGeometry(n_sipes=int(n)),
            group.drop(columns="n_sipes"),
            DryWetParameters(effects=effects),
        )
        parts.append(group.assign(mu=t["mu"].to_numpy()))
    return pd.concat(parts)


def steady(effects=None, *, noise=0.0, grid=SMALL_GRID, rng=1) -> pd.DataFrame:
    return make_steady_table(grid, effects=effects, noise=noise, rng=rng)


# -- effect specification --------------------------------------------------------------------
def test_unknown_effect_lists_valid_names():
    with pytest.raises(ValueError, match=r"unknown effect.*bogus.*valid effects are humidity"):
        EffectSpec({"bogus": 1.0})
    with pytest.raises(ValueError, match="frequency_dependent_modulus"):
        make_steady_table(SMALL_GRID, effects={"friction_relax": 1.0})


@pytest.mark.parametrize(
    ("strengths", "match"),
    [
        ({"viscous_shear": -1.0}, "viscous_shear must be a finite number >= 0"),
        ({"friction_relaxation": math.nan}, "friction_relaxation"),
        ({"ice_preheating": 1.5}, r"ice_preheating must lie in \[0, 1\]"),
    ],
)
def test_bad_strength(strengths, match):
    with pytest.raises(ValueError, match=match):
        EffectSpec(strengths)


def test_effect_spec_maps_onto_model_strengths():
    spec = EffectSpec({"ice_preheating": 0.5, "friction_relaxation": 2.0})
    assert spec.dry_wet == Effects.only(ice_preheating=0.5)
    assert spec.relaxation_time_s == pytest.approx(2.0 * TAU_REF_S, rel=1e-15)
    assert spec.modulus_strength == 0.0
    assert list(spec.as_dict()) == list(EFFECT_NAMES)


# -- steady table ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "effects",
    [None, {"viscous_shear": 1.0}, {"salinity_melting_point": 0.5, "ice_preheating": 1.0}],
)
def test_noise_free_steady_equals_friction_table_exactly(effects):
    table = steady(effects)
    assert list(table.columns) == list(STEADY_COLUMNS)
    expected = model_table(EffectSpec.coerce(effects).dry_wet)
    merged = table.merge(expected, on=CONDITIONS, suffixes=("", "_model"), validate="1:1")
    assert len(merged) == len(table) == len(SteadyGrid(**SMALL_GRID))
    assert_array_equal(merged["mu"], merged["mu_model"])  # same model, same numbers
    assert_array_equal(table["mu_std"], 0.0)


@pytest.mark.parametrize("name", EFFECT_NAMES)
def test_strength_zero_is_exactly_the_base_model(name):
    assert_array_equal(steady({name: 0.0})["mu"], steady(None)["mu"])
    base = make_transient_table(noise=0.0, sample_rate_Hz=2000.0)
    off = make_transient_table(effects={name: 0.0}, noise=0.0, sample_rate_Hz=2000.0)
    pd.testing.assert_frame_equal(off, base)


@pytest.mark.parametrize("name", ["friction_relaxation", "frequency_dependent_modulus"])
def test_dynamic_effects_leave_steady_states_alone(name):
    assert_array_equal(steady({name: 1.0})["mu"], steady(None)["mu"])


def relative_change(name: str) -> pd.DataFrame:
    base = steady(None).set_index(CONDITIONS)["mu"]
    on = steady({name: 1.0}).set_index(CONDITIONS)["mu"]
    return ((on - base) / base).rename("change").reset_index()


def test_humidity_water_layer_lowers_mu_more_in_humid_air():
    change = relative_change("humidity_water_layer")
    assert (change["change"] < 0).all()  # a thicker bound layer lubricates
    by_rh = change.groupby("humidity_pct")["change"].mean()
    assert by_rh[90.0] < by_rh[40.0]


def test_salinity_melting_point_lowers_mu_only_on_saline_ice():
    change = relative_change("salinity_melting_point")
    saline = change["salinity_pct"] > 0
    assert (change.loc[saline, "change"] < 0).all()  # ice closer to its melting point
    assert_array_equal(change.loc[~saline, "change"], 0.0)


def test_ice_preheating_lowers_mu_of_siped_blocks_only():
    change = relative_change("ice_preheating")
    siped = change["n_sipes"] > 0
    assert (change.loc[siped, "change"] < 0).all()  # warmer ice behind the first element
    assert_array_equal(change.loc[~siped, "change"], 0.0)  # G0: nothing ahead of it


def test_viscous_shear_makes_the_rise_at_minus_one():
    def curve(effects):
        t = steady(effects)
        sel = (t["temperature_C"] == -1.0) & (t["salinity_pct"] == 0.0)
        return t[sel].pivot_table(
            index=["n_sipes", "humidity_pct"], columns="velocity_mps", values="mu"
        )

    base, viscous = curve(None), curve({"viscous_shear": 1.0})
    assert (np.diff(base.to_numpy(), axis=1) < 0).all()  # no rise without viscous shear
    assert (viscous[7.0] > viscous[2.0]).all()  # the rise of Fig. 4.14 b at high speed


def test_noise_statistics_of_the_steady_table():
    grid = dict(SMALL_GRID, velocities_mps=tuple(np.arange(1.0, 9.0)), pressures_bar=(2.5, 5.0))
    noise = 0.05
    table = make_steady_table(grid, noise=noise, rng=7)
    mu_model = np.asarray(table.attrs["truth"]["mu_model"])
    n = len(table)
    assert n == 256
    residual = table["mu"].to_numpy() / mu_model - 1.0
    # sample std of n normal values: relative standard error 1/sqrt(2n) = 4.4 %; allow 3.4
    # standard errors
    assert abs(residual.std(ddof=1) / noise - 1.0) < 0.15
    assert abs(residual.mean()) < 4.0 * noise / math.sqrt(n)
    # mu_std estimates the noise from 10 repeats: E[sample std] = c4 sigma; the mean over n
    # rows has relative standard error ~ 0.24 / sqrt(n) = 1.5 %; allow 5 %
    r = 10
    c4 = math.sqrt(2.0 / (r - 1)) * math.gamma(r / 2) / math.gamma((r - 1) / 2)
    ratio = (table["mu_std"].to_numpy() / mu_model).mean() / (c4 * noise)
    assert abs(ratio - 1.0) < 0.05


def test_steady_grid_validation():
    with pytest.raises(ValueError, match="n_sipes must hold integers >= 0"):
        SteadyGrid(n_sipes=(1.5,))
    with pytest.raises(ValueError, match="velocities_mps must all be > 0"):
        SteadyGrid(velocities_mps=(0.0, 1.0))
    with pytest.raises(ValueError, match="noise must be a finite number >= 0"):
        make_steady_table(SMALL_GRID, noise=-0.1)


# -- transient table -------------------------------------------------------------------------
def t63_after_step(table: pd.DataFrame, truth: dict, t_step: float = 0.2) -> float:
    """Time after the step at which the angle first passes 63.2 % of its change."""
    t = table["time_s"].to_numpy()
    a = table["angle_deg"].to_numpy()
    a1, a2 = truth["angle_before_deg"], truth["angle_after_deg"]
    target = a1 + (1.0 - math.exp(-1.0)) * (a2 - a1)
    k = np.flatnonzero((t >= t_step) & ((a - target) * np.sign(a1 - a2) <= 0))[0]
    # linear interpolation between the samples around the crossing
    frac = (a[k - 1] - target) / (a[k - 1] - a[k])
    return t[k - 1] + frac * (t[k] - t[k - 1]) - t_step


def test_transient_columns_and_sampling():
    # (no timed assertion: speed depends on the machine, not on the code under test)
    table = make_transient_table(
        effects={"friction_relaxation": 1.0, "frequency_dependent_modulus": 1.0}, rng=3
    )
    assert list(table.columns) == list(TRANSIENT_COLUMNS)
    assert_allclose(np.diff(table["time_s"]), 1e-4, rtol=1e-9)
    v = table["velocity_mps"].to_numpy()
    assert_array_equal(v[table["time_s"] < 0.2], 1.0)
    assert_array_equal(v[table["time_s"] >= 0.2], 5.0)


@pytest.mark.parametrize("strength", [0.5, 1.0, 2.0])
def test_friction_relaxation_follows_the_first_order_lag(strength):
    table = make_transient_table(effects={"friction_relaxation": strength}, noise=0.0)
    truth = table.attrs["truth"]
    tau = strength * TAU_REF_S
    assert truth["tau_s"] == pytest.approx(tau, rel=1e-15)
    # the element answers within ~0.1 ms (d_phi / c_eff), so after 5 ms the angle is the
    # first-order response 1 - exp(-t / tau) of Eq. 5.12 (analytic) shifted by that lag:
    # difference below 1 % of the change
    t = table["time_s"].to_numpy() - 0.2
    a1, a2 = truth["angle_before_deg"], truth["angle_after_deg"]
    late = t >= 0.005
    first_order = a2 + (a1 - a2) * np.exp(-t[late] / tau)
    assert np.max(np.abs(table["angle_deg"].to_numpy()[late] - first_order)) < 0.01 * abs(a1 - a2)
    # 63 % time = tau of the first-order law, within the element lag and 3 %
    assert t63_after_step(table, truth) == pytest.approx(tau, rel=0.03, abs=5e-4)


def test_transient_lag_grows_with_relaxation_strength():
    t63 = [
        t63_after_step(tab, tab.attrs["truth"])
        for tab in (
            make_transient_table(effects={"friction_relaxation": s}, noise=0.0)
            for s in (0.0, 0.5, 1.0, 2.0)
        )
    ]
    assert t63[0] < 1e-3  # the element alone: a fraction of its ~1.7 ms period
    assert np.all(np.diff(t63) > 0)


def ringing_frequency(table: pd.DataFrame, t_step: float = 0.2, window: float = 0.01) -> float:
    """Mean frequency from the maxima of the angle during the first ``window`` s."""
    t = table["time_s"].to_numpy()
    a = table["angle_deg"].to_numpy()
    sel = (t > t_step) & (t < t_step + window)
    ts, av = t[sel], a[sel]
    peaks = np.flatnonzero((av[1:-1] > av[:-2]) & (av[1:-1] >= av[2:])) + 1
    assert peaks.size >= 3
    return (peaks.size - 1) / (ts[peaks[-1]] - ts[peaks[0]])


def test_frequency_dependent_modulus_stiffens_the_transient():
    fs = 50_000.0  # 50 samples per period of the ~1 kHz ringing
    base = make_transient_table(noise=0.0, sample_rate_Hz=fs)
    stiff = make_transient_table(
        effects={"frequency_dependent_modulus": 1.0}, noise=0.0, sample_rate_Hz=fs
    )
    tb, ts = base.attrs["truth"], stiff.attrs["truth"]
    # base: the damped natural frequency of the linear SDOF, from its own constants
    zeta = tb["damping_constant_Nms_rad"] / (
        2.0 * math.sqrt(tb["inertia_kgm2"] * tb["effective_stiffness_Nm_rad"])
    )
    f_damped = tb["natural_frequency_Hz"] * math.sqrt(1.0 - zeta**2)
    assert ringing_frequency(base) == pytest.approx(f_damped, rel=0.02)  # 1 sample in 50
    # the modulus effect raises the frequency by the fixed point of f = f_n(E(f)); the arms
    # add some damping and fit E(f) to 0.3 %, so allow 5 %
    f0 = element_natural_frequency_Hz(modulus_strength=0.0)
    f1 = element_natural_frequency_Hz(modulus_strength=1.0)
    assert f1 > 1.3 * f0
    assert ringing_frequency(stiff) / ringing_frequency(base) == pytest.approx(f1 / f0, rel=0.05)
    # stiffer at the ringing frequency: the first swing after the step is smaller ...
    a_b, a_s = base["angle_deg"].to_numpy(), stiff["angle_deg"].to_numpy()
    after = base["time_s"].to_numpy() >= 0.2
    assert a_s[after].min() > a_b[after].min()
    # ... the static angles (E0) are the same, and it creeps towards the new one from above
    assert ts["angle_before_deg"] == tb["angle_before_deg"]
    assert_array_equal(a_s[~after], a_b[~after])
    assert a_s[-1] > ts["angle_after_deg"] > a_s[-1] - 0.1 * (a_s[0] - a_s[-1])


def test_modulus_law_and_its_time_domain_form():
    f = np.geomspace(10.0, 1e4, 200)
    for s in (0.5, 1.0, 2.0):
        exact = modulus_ratio(f, strength=s)
        # Prony series of the transient model against the stated law from 10 Hz to 10 kHz:
        # the fit's error is 0.0038 E0 per unit strength (0.27 % of E at strength 1)
        assert_allclose(arm_storage_ratio(f, strength=s), exact, rtol=0, atol=0.004 * s)
    assert modulus_ratio(1000.0, strength=1.0) == pytest.approx(1 + 3 * MODULUS_ALPHA, rel=1e-14)
    assert modulus_ratio(1000.0, strength=0.0) == 1.0
    # plausibility against section 5.3.2: 1111 Hz simulated with constant E, 1500 Hz measured
    assert modulus_scaled_frequency_Hz(1111.0, strength=1.0) == pytest.approx(1500.0, rel=0.05)


def test_transient_noise_is_relative_to_the_angle_before_the_step():
    noise = 0.02
    table = make_transient_table(noise=noise, rng=5)
    truth = table.attrs["truth"]
    residual = table["angle_deg"].to_numpy() - np.asarray(truth["angle_deg"])
    # 4001 samples: relative standard error of the std 1.1 %; allow 5 %
    assert residual.std(ddof=1) == pytest.approx(noise * truth["angle_before_deg"], rel=0.05)


def test_transient_rejects_a_buckling_element():
    with pytest.raises(ValueError, match=r"buckles.*lower pressure_bar"):
        make_transient_table(pressure_bar=4.0)


# -- raw runs --------------------------------------------------------------------------------
def test_raw_runs_evaluate_to_the_model_at_the_drifting_climate(tmp_path):
    out = write_measurements(
        "raw",
        tmp_path / "runs",
        effects={"viscous_shear": 1.0},
        noise=0.05,
        seed=11,
        reveal=True,
        n_sipes=(0, 3),
        velocities_mps=(1.0, 3.0),
        n_repeats=1,
        sample_rate_Hz=2000.0,
    )
    truth = json.loads(out.truth_file.read_text())["truth"]["runs"]
    assert len(out.files) == 4
    for file, rt in zip(out.files, truth, strict=True):
        result = evaluate_steady_run(read_run(file))
        model = friction_table(
            BlockGeometry(n_sipes=rt["n_sipes"]),
            pd.DataFrame(
                {
                    "velocity_mps": [rt["velocity_mps"]],
                    "pressure_bar": [2.5],
                    "temperature_C": [rt["temperature_C"]],
                    "humidity_pct": [rt["humidity_pct"]],
                }
            ),
            DryWetParameters(effects=Effects.only(viscous_shear=1.0)),
        )["mu"].iloc[0]
        # 2 N force noise on 400 N averaged over ~2000 samples: << 0.5 %
        assert result.mu_mean_method2 == pytest.approx(model * rt["mu_factor"], rel=5e-3)
        # the recorded temperature is the run's drifted mean (+- the small in-run drift)
        assert result.temperature_C == pytest.approx(rt["temperature_C"], abs=0.02)
        assert result.specimen == ("G0" if rt["n_sipes"] == 0 else "G3")


def test_raw_climate_drifts_as_in_fig_4_6():
    runs = make_raw_runs(
        n_sipes=(3,),
        velocities_mps=(1.0,),
        n_repeats=10,
        sample_rate_Hz=500.0,
        rng=2,
        run_interval_s=300.0,  # 10 runs over 45 min: one chamber cycle
    )
    temps = np.array([r.attrs["run_truth"]["temperature_C"] for r in runs])
    hums = np.array([r.attrs["run_truth"]["humidity_pct"] for r in runs])
    assert np.all(np.abs(temps + 3.9) <= 1.0) and np.ptp(temps) > 1.0
    assert np.all(np.abs(hums - 72.4) <= 7.0) and np.ptp(hums) > 7.0
    # warmer air, lower relative humidity (constant absolute humidity)
    assert np.corrcoef(temps, hums)[0, 1] == pytest.approx(-1.0, abs=1e-9)


def test_raw_relaxation_lags_only_while_the_speed_changes():
    kw = {
        "n_sipes": (0,),
        "velocities_mps": (3.0,),
        "n_repeats": 1,
        "sample_rate_Hz": 5000.0,
        "sensor_noise": False,
        "noise": 0.0,
        "rng": 4,
    }
    base = make_raw_runs(**kw)[0]
    lag = make_raw_runs(effects={"friction_relaxation": 1.0}, **kw)[0]
    phases = base.attrs["phases"]
    t = base["time_s"].to_numpy()
    diff = lag["friction_force_N"].to_numpy() - base["friction_force_N"].to_numpy()
    accel = (t > phases["motion_start_s"] + 0.02) & (t < phases["plateau_start_s"])
    settled = (t > phases["plateau_start_s"] + 10 * TAU_REF_S) & (t < phases["plateau_end_s"])
    # mu falls with speed at -3.9 degC, so the lagging mu stays above it while accelerating
    assert (diff[accel] > 0).all()
    assert np.max(np.abs(diff[settled])) < 1e-3  # N; exp(-10) of a ~100 N change is 5e-3 N
    assert_array_equal(lag["normal_force_N"], base["normal_force_N"])


def test_raw_run_validation():
    with pytest.raises(ValueError, match="sample_rate_Hz must be <= 50000"):
        make_raw_runs(sample_rate_Hz=60_000.0)
    with pytest.raises(ValueError, match=r"n_repeats must be an integer in 1\.\.10"):
        make_raw_runs(n_repeats=11)


# -- files: reproducible, blind unless revealed ----------------------------------------------
KIND_OPTIONS = {
    "steady": {"grid": dict(SMALL_GRID, temperatures_C=(-5.0,))},
    "transient": {"sample_rate_Hz": 2000.0},
    "raw": {"n_sipes": (3,), "velocities_mps": (1.0,), "n_repeats": 2, "sample_rate_Hz": 1000.0},
}
ALL_ON = {name: (0.5 if name == "ice_preheating" else 1.0) for name in EFFECT_NAMES}


def written_bytes(kind: str, out: Path, seed: int, *, reveal: bool = False) -> dict[str, bytes]:
    result = write_measurements(
        kind, out, effects=ALL_ON, noise=0.05, seed=seed, reveal=reveal, **KIND_OPTIONS[kind]
    )
    return {f.name: f.read_bytes() for f in result.files}


@pytest.mark.parametrize("kind", ["steady", "transient", "raw"])
def test_same_seed_same_bytes_other_seed_other_bytes(kind, tmp_path):
    name = "out" if kind == "raw" else "out.csv"
    first = written_bytes(kind, tmp_path / "a" / name, seed=1)
    again = written_bytes(kind, tmp_path / "b" / name, seed=1)
    other = written_bytes(kind, tmp_path / "c" / name, seed=2)
    assert first == again
    assert first.keys() == other.keys()
    assert all(first[k] != other[k] for k in first)


@pytest.mark.parametrize("kind", ["steady", "transient", "raw"])
def test_files_name_no_effect_unless_revealed(kind, tmp_path):
    out = tmp_path / ("out" if kind == "raw" else "out.csv")
    for content in written_bytes(kind, out, seed=3).values():
        for name in (*EFFECT_NAMES, "effect", "strength", "tau"):
            assert name.encode() not in content
    assert not truth_path(out).exists()
    written_bytes(kind, out, seed=3, reveal=True)
    truth = json.loads(truth_path(out).read_text())
    assert truth["effects"] == ALL_ON
    assert (truth["seed"], truth["noise"], truth["kind"]) == (3, 0.05, kind)
    assert truth["reference"]["tau_ref_s"] == TAU_REF_S


def test_truth_path_sits_beside_the_output():
    assert truth_path("runs") == Path("runs.truth.json")
    assert truth_path(Path("a") / "t.csv") == Path("a") / "t.csv.truth.json"


def test_write_measurements_rejects_a_bad_kind(tmp_path):
    with pytest.raises(ValueError, match="kind must be one of steady, transient, raw"):
        write_measurements("video", tmp_path / "x.csv")


def test_dry_wet_effect_names_are_the_model_s():
    assert set(DRY_WET_EFFECTS) < set(EFFECT_NAMES)
    assert EffectSpec({n: 1.0 for n in DRY_WET_EFFECTS}).dry_wet == Effects()


def test_raw_output_refuses_a_folder_with_other_runs(tmp_path):
    opts = KIND_OPTIONS["raw"]
    write_measurements("raw", tmp_path / "runs", seed=1, **dict(opts, n_repeats=3))
    with pytest.raises(ValueError, match=r"holds run files.*run_003\.csv"):
        write_measurements("raw", tmp_path / "runs", seed=1, **opts)
    # rewriting the same set of files is fine (same names, replaced)
    write_measurements("raw", tmp_path / "runs", seed=1, **dict(opts, n_repeats=3))


def test_a_noise_that_makes_mu_negative_is_refused():
    # --noise 5 wrote 94 rows of mu <= 0 with exit 0, which discrepancy then refused
    # (helper-12); at 0.2 a row falls below zero with probability 3e-7 (5 sigma)
    with pytest.raises(ValueError, match=r"noise=5 puts mu <= 0 in \d+ of 216 rows"):
        make_steady_table(noise=5.0, rng=1)
    assert (make_steady_table(noise=0.2, rng=1)["mu"] > 0).all()
