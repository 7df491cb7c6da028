"""The dry run-in / wet friction model (section 4.5.1) against independent truths."""

import math
import warnings

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from friction_model import (
    ICE,
    BlockGeometry,
    Conditions,
    DryWetParameters,
    Effects,
    dry_run_in_length,
    friction_table,
    reference_block,
    simulate_block,
)

G3 = reference_block("G3")
COLD_DRY = Conditions.from_bar(1.0, 2.5, -5.0, humidity_pct=40.0)
WARM_HUMID = Conditions.from_bar(7.0, 2.5, -1.0, humidity_pct=95.0)


def mu_of(geometry=G3, params=None, **kw):
    base = {"velocity_mps": 1.0, "pressure_bar": 2.5, "temperature_C": -5.0, "humidity_pct": 40.0}
    base.update(kw)
    return float(friction_table(geometry, pd.DataFrame([base]), params)["mu"].iloc[0])


# --- the physics inside the model against closed forms -------------------------------------


@pytest.mark.parametrize("v", [0.5, 1.0, 3.0, 7.0])
@pytest.mark.parametrize("T", [-8.0, -5.0, -2.0])
def test_first_element_heating_length_is_eq_4_7(v, T):
    # Element 0 meets virgin ice: the length after which the surface melts is Eq. 4.7 with
    # the local pressure and the model's heat fraction K. The march solves the exact
    # superposition by bisection (40 halvings of a cell): rtol 1e-6.
    params = DryWetParameters()
    r = simulate_block(G3, Conditions.from_bar(v, 2.5, T), params)
    expected = dry_run_in_length(
        -T, r.block["pressure_local_Pa"], params.mu_dry, v, params.heat_fraction
    )
    assert_allclose(r.elements["heating_length_mm"].iloc[0], expected * 1e3, rtol=1e-6)


def test_sipe_cooling_matches_pulse_solution():
    # Very cold and slow: element 0 never melts, so it applies the constant flux
    # q = K mu_dry p v for l0 / v and nothing across the sipe. The surface temperature that
    # element 1 meets is the closed-form pulse solution
    # theta = 2 q / sqrt(pi lambda rho c) * (sqrt(t) - sqrt(t - t_c)).
    params = DryWetParameters()
    cond = Conditions.from_bar(0.05, 1.0, -40.0)
    r = simulate_block(G3, cond, params)
    assert r.elements["heating_length_mm"].iloc[0] == pytest.approx(G3.element_lengths[0])
    p = r.block["pressure_local_Pa"]
    q = params.heat_fraction * params.mu_dry * p * cond.velocity_mps
    l0 = G3.element_lengths[0] * 1e-3
    s = G3.sipe_width_mm * 1e-3
    t, t_c = (l0 + s) / cond.velocity_mps, l0 / cond.velocity_mps
    theta = 2 * q / math.sqrt(math.pi * ICE.thermal_inertia) * (math.sqrt(t) - math.sqrt(t - t_c))
    assert_allclose(r.elements["entry_temperature_C"].iloc[1], -40.0 + theta, rtol=1e-10)


def test_contact_split_and_force_sum():
    r = simulate_block(G3, COLD_DRY)
    el = r.elements
    phi = r.block["contact_fraction"]
    # Eq. 4.1: A = A_dry + A_wet = phi * l * w per element (exact bookkeeping)
    assert_allclose(el["dry_area_mm2"] + el["wet_area_mm2"], phi * el["length_mm"] * 80.0)
    # Eq. 4.2: F_F = F_dry + F_viscous (+ boundary part of the wet zone)
    assert_allclose(
        el["friction_force_N"], el["dry_force_N"] + el["viscous_force_N"] + el["boundary_force_N"]
    )
    # Eq. 4.5 in coefficient form: mu = (eps/l) mu_dry + (1 - eps/l) mu_wet per element
    frac = el["dry_length_mm"] / el["length_mm"]
    assert_allclose(el["mu"], frac * 1.5 + (1 - frac) * el["mu_wet"], rtol=1e-10)
    # block: total friction over total normal force = nominal pressure * nominal area
    assert_allclose(r.block["normal_force_N"], 2.5e5 * 20e-3 * 80e-3, rtol=1e-12)
    assert_allclose(r.mu, el["friction_force_N"].sum() / r.block["normal_force_N"], rtol=1e-12)


def test_measured_contact_fraction_sets_local_pressure():
    # p_local = F_N / A_real with A_real = phi * (rubber face area)
    cond = Conditions.from_bar(2.0, 2.5, -4.0, contact_fraction=0.4)
    r = simulate_block(G3, cond)
    F_N = 2.5e5 * G3.nominal_area_mm2 * 1e-6
    assert_allclose(r.block["pressure_local_Pa"], F_N / (0.4 * G3.rubber_area_mm2 * 1e-6))
    assert r.block["contact_fraction"] == 0.4


@settings(max_examples=25, deadline=None)
@given(
    v=st.floats(0.2, 10.0),
    p_bar=st.floats(0.5, 8.0),
    T=st.floats(-15.0, -0.3),
    rh=st.floats(0.0, 100.0),
    n=st.sampled_from([0, 3, 7]),
)
def test_limits_mu_wet_le_mu_le_mu_dry(v, p_bar, T, rh, n):
    # Section 4.5.1: mu_min = mu_wet (A = A_wet) <= mu <= mu_max = mu_dry (A = A_dry).
    r = simulate_block(reference_block(f"G{n}"), Conditions.from_bar(v, p_bar, T, humidity_pct=rh))
    el = r.elements
    assert np.all(el["mu"] <= 1.5 + 1e-12)
    assert np.all(el["mu_wet"] <= el["mu"] + 1e-12)
    assert r.block["mu_wet"] <= r.mu + 1e-12 <= 1.5 + 2e-12
    assert np.all(el["dry_length_mm"] <= el["length_mm"] + 1e-9)
    assert np.all(el["dry_length_mm"] >= 0)


def test_fully_dry_limit_gives_mu_dry():
    # Ice far below its melting point and a slow slide: nothing melts, mu = mu_dry exactly.
    r = simulate_block(G3, Conditions.from_bar(0.05, 1.0, -40.0))
    assert_allclose(r.mu, 1.5, rtol=1e-12)
    assert r.block["regime"] == "dry-dominated"


# --- Fig. 4.25: the siped block ------------------------------------------------------------


@pytest.mark.parametrize("name", ["G3", "G5", "G7"])
@pytest.mark.parametrize("cond", [COLD_DRY, WARM_HUMID, Conditions.from_bar(3.0, 5.0, -3.0)])
def test_dry_length_shrinks_front_to_back(name, cond):
    el = simulate_block(reference_block(name), cond).elements
    assert np.all(np.diff(el["heating_length_mm"]) <= 1e-12)
    assert np.all(np.diff(el["run_in_length_mm"]) <= 1e-12)
    assert el["run_in_length_mm"].iloc[-1] < el["run_in_length_mm"].iloc[0]


def test_without_preheating_all_elements_are_equal():
    # Symmetry: with the heat history switched off every element sees virgin ice and, being
    # equally long and loaded, gives the same result as the leading one.
    params = DryWetParameters(effects=Effects().with_(ice_preheating=0.0))
    el = simulate_block(G3, COLD_DRY, params).elements
    for col in ("heating_length_mm", "run_in_length_mm", "dry_length_mm", "mu"):
        assert_allclose(el[col], el[col].iloc[0], rtol=1e-12)


def test_wider_sipe_lets_ice_cool_more():
    # The sipe sets how much the ice cools between elements: a wider sipe means colder ice
    # at the second element and so a longer dry run-in there.
    run_in, entry = [], []
    for width in (0.2, 0.6, 2.0):
        g = BlockGeometry(n_sipes=3, sipe_width_mm=width)
        el = simulate_block(g, COLD_DRY).elements
        run_in.append(el["heating_length_mm"].iloc[1])
        entry.append(el["entry_temperature_C"].iloc[1])
    assert run_in[0] < run_in[1] < run_in[2]
    assert entry[0] > entry[1] > entry[2]


# --- the trends listed at the start of section 4.5.1 ---------------------------------------


# Sizes: the thesis's own numbers are Table 4.6's fits of G3 (Eq. 4.8 / 4.9). They are the
# calibration's fit targets (docs/friction_model.md): the checks below hold the model to what
# it was fitted to and to the shortfall the docs publish, they do not validate it. Tolerance:
# a difference of two fitted values may be off by twice the worst curve's RMSE (0.0074)
# plus a margin, 0.02.
def table_4_6_mu(v, *, cold_dry=True, bar=2.5):
    """Table 4.6: mu = A_D v^-0.5 + B_D (-5 degC, rH < 50 %) or A_I v^0.5 + B_I (-1 degC,
    rH > 90 %), G3 at 2.5 or 5 bar; numbers typed from the thesis."""
    if cold_dry:
        a, b = {2.5: (0.2, 0.095), 5.0: (0.125, 0.05)}[bar]
        return a / math.sqrt(v) + b
    a, b = {2.5: (0.03, 0.075), 5.0: (0.02, 0.04)}[bar]
    return a * math.sqrt(v) + b


TREND_TOL = 0.02


def test_velocity_cold_dry_decreasing_and_warm_humid_increasing():
    cold = [mu_of(velocity_mps=v) for v in (1, 2, 4, 7)]
    warm = [mu_of(velocity_mps=v, temperature_C=-1.0, humidity_pct=95.0) for v in (1, 2, 4, 7)]
    assert np.all(np.diff(cold) < 0)  # "most experiments: decreasing"
    # "sometimes an increasing friction": near the melting point and humid. The model is
    # flat between 1 and 2 m/s (within 0.001) and rises clearly above.
    assert np.all(np.diff(warm[1:]) > 0)
    assert warm[-1] > warm[0] + 0.02
    # size of the cold-dry fall from 1 to 7 m/s: Table 4.6 0.124 (model 0.114)
    fall = table_4_6_mu(1) - table_4_6_mu(7)
    assert cold[0] - cold[-1] == pytest.approx(fall, abs=TREND_TOL)
    # the warm-humid rise is the model's published shortfall: 56 % of Table 4.6's 0.049 at
    # 2.5 bar (docs/friction_model.md, "Warm-humid mechanism"; a strict xfail in
    # test_calibration holds the full target). 0.45-0.70 brackets 56 %: a rise that
    # vanishes, or one that overshoots the documented state, fails.
    rise = table_4_6_mu(7, cold_dry=False) - table_4_6_mu(1, cold_dry=False)
    assert 0.45 < (warm[-1] - warm[0]) / rise < 0.70


@pytest.mark.parametrize(("v", "T"), [(1, -5.0), (3, -5.0), (7, -5.0), (1, -1.0), (7, -1.0)])
def test_pressure_increase_lowers_friction(v, T):
    rh = 40.0 if T == -5.0 else 95.0  # Table 4.6's two climates
    values = [mu_of(velocity_mps=v, temperature_C=T, pressure_bar=p, humidity_pct=rh)
              for p in (1.0, 2.5, 5.0)]
    assert np.all(np.diff(values) < 0)
    # size from 2.5 to 5 bar: Table 4.6 (0.120 / 0.088 / 0.073 cold-dry at 1 / 3 / 7 m/s,
    # 0.045 / 0.061 warm-humid at 1 / 7 m/s)
    cold = T == -5.0
    drop = table_4_6_mu(v, cold_dry=cold) - table_4_6_mu(v, cold_dry=cold, bar=5.0)
    assert values[1] - values[2] == pytest.approx(drop, abs=TREND_TOL)


@pytest.mark.parametrize("v", [1.0, 3.0])
def test_colder_ice_gives_more_friction(v):
    values = [mu_of(velocity_mps=v, temperature_C=T) for T in (-10.0, -8.0, -4.0, -1.0)]
    assert np.all(np.diff(values) < 0)
    # size: Table 4.6 changes temperature only together with humidity; from -5 degC / 40 %
    # to -1 degC / 95 % mu falls by 0.190 at 1 m/s and 0.084 at 3 m/s (model 0.178 / 0.079)
    cold, warm = mu_of(velocity_mps=v), mu_of(velocity_mps=v, temperature_C=-1.0,
                                              humidity_pct=95.0)
    drop = table_4_6_mu(v) - table_4_6_mu(v, cold_dry=False)
    assert cold - warm == pytest.approx(drop, abs=TREND_TOL)


@pytest.mark.parametrize(("T", "published_pct"), [(-5.0, 1.1), (-3.0, 1.9), (-1.0, 4.7)])
def test_humidity_reduces_friction(T, published_pct):
    values = [mu_of(velocity_mps=1.0, temperature_C=T, humidity_pct=rh) for rh in (20, 60, 100)]
    assert np.all(np.diff(values) < 0)
    # size: the thesis gives no number for humidity alone (Fig. 4.14 only shows a clear
    # drop), so the published size is the docs' (docs/friction_model.md, "Bound initial water
    # layer": 20 -> 100 % lowers mu at 1 m/s by 1.1 / 1.9 / 4.7 %), to its rounding (+-0.1 %
    # point) plus 0.1 % point; a humidity term ten times too strong or too weak fails.
    drop_pct = 100.0 * (values[0] - values[-1]) / values[0]
    assert drop_pct == pytest.approx(published_pct, abs=0.2)


def test_humidity_effect_switch_is_exact():
    params = DryWetParameters(effects=Effects().with_(humidity_water_layer=0.0))
    assert mu_of(params=params, humidity_pct=10.0) == mu_of(params=params, humidity_pct=100.0)


def test_longer_block_at_constant_pressure_gives_less_friction():
    # Fig. 4.15: unsiped elements of 6, 10 and 12 mm at the same nominal pressure.
    values = [mu_of(BlockGeometry(length_mm=L), temperature_C=-4.0) for L in (6.0, 10.0, 12.0)]
    assert np.all(np.diff(values) < 0)


@pytest.mark.parametrize("v", [1.0, 5.0])
def test_salinity_lowers_friction(v):
    # Fig. 4.18: ice from water with K = 0.05 % salt gives less friction than purified ice.
    pure = mu_of(velocity_mps=v, temperature_C=-4.5)
    saline = mu_of(velocity_mps=v, temperature_C=-4.5, salinity_pct=0.05)
    assert saline < pure
    off = DryWetParameters(effects=Effects().with_(salinity_melting_point=0.0))
    assert mu_of(
        params=off, velocity_mps=v, temperature_C=-4.5, salinity_pct=0.05
    ) == mu_of(params=off, velocity_mps=v, temperature_C=-4.5)


def test_viscous_shear_switch_removes_viscous_force():
    params = DryWetParameters(effects=Effects().with_(viscous_shear=0.0))
    r = simulate_block(G3, WARM_HUMID, params)
    assert r.block["viscous_force_N"] == 0.0
    assert simulate_block(G3, WARM_HUMID).block["viscous_force_N"] > 0.0


def test_regimes():
    # cold and slow: the leading dry run-in areas carry most of the friction
    cold_slow = Conditions.from_bar(0.3, 2.5, -10.0, humidity_pct=40.0)
    assert simulate_block(G3, cold_slow).block["regime"] == "dry-dominated"
    warm = [Conditions.from_bar(v, 2.5, -1.0, humidity_pct=95.0) for v in (1.0, 7.0, 20.0)]
    table = friction_table(G3, warm)
    # near the melting point the viscous share grows with v until shear of the film dominates
    assert table["regime"].iloc[-1] == "viscous"
    assert np.all(np.diff(table["viscous_share"]) > 0)
    assert np.all(np.diff(table["run_in_share"]) < 0)


def test_grid_convergence():
    # The march is first order at worst; 40 cells per element agree with 160 within 0.5 %.
    conds = [COLD_DRY, WARM_HUMID, Conditions.from_bar(7.0, 5.0, -5.0, humidity_pct=40.0)]
    coarse = friction_table(G3, conds, DryWetParameters(n_cells=40))["mu"].to_numpy()
    fine = friction_table(G3, conds, DryWetParameters(n_cells=160))["mu"].to_numpy()
    assert_allclose(coarse, fine, rtol=5e-3)


def test_friction_table_equals_single_simulations():
    conds = [COLD_DRY, WARM_HUMID, Conditions.from_bar(2.0, 4.0, -3.0, humidity_pct=70.0)]
    table = friction_table(G3, conds)
    single = [simulate_block(G3, c).mu for c in conds]
    assert_allclose(table["mu"], single, rtol=1e-12)


# --- bad input -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"velocity_mps": -1.0}, "velocity_mps"),
        ({"temperature_C": 2.0}, "temperature_C"),
        ({"humidity_pct": 120.0}, "humidity_pct"),
        ({"contact_fraction": 1.5}, "contact_fraction"),
    ],
)
def test_bad_conditions(kwargs, match):
    base = {"velocity_mps": 1.0, "pressure_Pa": 2.5e5, "temperature_C": -5.0}
    base.update(kwargs)
    with pytest.raises(ValueError, match=match):
        Conditions(**base)


def test_bad_geometry_and_parameters():
    with pytest.raises(ValueError, match="n_sipes"):
        BlockGeometry(n_sipes=-1)
    with pytest.raises(ValueError, match="no rubber"):
        BlockGeometry(length_mm=2.0, n_sipes=5, sipe_width_mm=0.5)
    with pytest.raises(ValueError, match="element_lengths_mm"):
        BlockGeometry(n_sipes=1, element_lengths_mm=(5.0, 5.0))
    with pytest.raises(ValueError, match="n_cells"):
        DryWetParameters(n_cells=2)
    with pytest.raises(ValueError, match="ice_preheating"):
        Effects(ice_preheating=1.5)


def test_table_missing_column_and_bad_row():
    with pytest.raises(ValueError, match="temperature_C"):
        friction_table(G3, pd.DataFrame({"velocity_mps": [1.0], "pressure_bar": [2.5]}))
    bad = pd.DataFrame({"velocity_mps": [1.0, -2.0], "pressure_bar": 2.5, "temperature_C": -5.0})
    with pytest.raises(ValueError, match=r"row 1.*velocity_mps"):
        friction_table(G3, bad)


def test_saline_ice_above_its_melting_point_is_an_error():
    with pytest.raises(ValueError, match="melting point"):
        simulate_block(G3, Conditions.from_bar(1.0, 2.5, -0.2, salinity_pct=0.5))


# --- the block given by name -----------------------------------------------------------------


def test_a_reference_block_may_be_given_by_its_name():
    # the name is the Table 4.4 marking: the same block, so the same numbers to the bit
    by_name = simulate_block("g3", COLD_DRY)
    assert by_name.geometry == G3
    assert by_name.block == simulate_block(G3, COLD_DRY).block
    assert friction_table("G3", [COLD_DRY]).equals(friction_table(G3, [COLD_DRY]))


def test_a_block_that_is_neither_a_geometry_nor_a_name_is_a_clear_error():
    with pytest.raises(ValueError, match=r"unknown reference sample 'G9'.*G0"):
        simulate_block("G9", COLD_DRY)
    with pytest.raises(TypeError, match=r"geometry must be a BlockGeometry or .*got int"):
        friction_table(3, [COLD_DRY])


# --- pressures in the other unit, and a table's columns -------------------------------------


@pytest.mark.parametrize(("make", "said"), [
    # 2.5 bar given as Pa: before, mu 1.5 (all dry) without a word (helper-12)
    (lambda: Conditions(1.0, 2.5, -5.0), r"got pressure_Pa=2\.5, which is 2\.5e-05 bar"),
    # 2.5e5 Pa given as bar: before, mu 4e-6
    (lambda: Conditions.from_bar(1.0, 2.5e5, -5.0), r"which is 250000 bar"),
])
def test_a_pressure_in_the_other_unit_is_refused(make, said):
    with pytest.raises(ValueError, match=said):
        make()


def test_the_pressure_range_takes_every_tread_block_load():
    # 0.5-10 bar, the tread blocks' range, and its limits 0.01 and 1000 bar
    for bar in (0.01, 0.5, 2.5, 10.0, 1000.0):
        assert Conditions.from_bar(1.0, bar, -5.0).pressure_bar == pytest.approx(bar)


def test_a_table_that_gives_the_pressure_twice_must_agree():
    row = {"velocity_mps": 1.0, "temperature_C": -5.0, "pressure_bar": 2.5}
    same = friction_table(G3, pd.DataFrame([{**row, "pressure_Pa": 2.5e5}]))
    assert same["mu"].iloc[0] == friction_table(G3, pd.DataFrame([row]))["mu"].iloc[0]
    # before: the Pa column was used and pressure_bar 2.5 shown beside it (helper-12)
    with pytest.raises(ValueError, match=r"row 0: 500000 Pa against 2\.5 bar"):
        friction_table(G3, pd.DataFrame([{**row, "pressure_Pa": 5e5}]))


def test_a_misspelt_condition_column_is_warned_about():
    row = {"velocity_mps": 1.0, "temperature_C": -5.0, "pressure_bar": 2.5, "humidity": 95.0}
    with pytest.warns(UserWarning, match="column 'humidity' is not read; did you mean "
                                         "'humidity_pct'"):
        friction_table(G3, pd.DataFrame([row]))


def test_a_column_beside_the_one_it_resembles_is_not_warned_about():
    # 'velocity_mps_std' next to 'velocity_mps' is the user's own column (the review of
    # 3824031); a bar value rounded to three figures agrees with its Pa within 1 %
    row = {"velocity_mps": 1.0, "velocity_mps_std": 0.01, "temperature_C": -5.0,
           "pressure_bar": 1.235, "pressure_Pa": 123456.0}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        friction_table(G3, pd.DataFrame([row]))


@pytest.mark.parametrize("humidity_pct", [140.0, -5.0, float("nan")])
def test_a_humidity_that_is_not_air_is_refused(humidity_pct):
    """A relative humidity beyond saturation (helper-12: 140 % grew the bound layer by the
    gain's 1.4x share without a word), below 0 or NaN is an error naming the field."""
    from friction_model.contact.water_layer import initial_water_layer_m

    with pytest.raises(ValueError, match=r"humidity_pct .*0\.\.100"):
        initial_water_layer_m(8.0, humidity_pct, qll_thickness_m=1e-7, humidity_gain=0.5)
    # both ends of the range are air: the law of the docstring, h0 (1 + gain rh / 100)
    h = initial_water_layer_m(8.0, np.array([0.0, 100.0]), qll_thickness_m=1e-7,
                              humidity_gain=0.5)
    assert_allclose(h, [5e-8, 7.5e-8], rtol=1e-12)
