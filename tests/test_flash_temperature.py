"""Eq. 4.6/4.7 (Blok): the thesis value and the analytic scaling of Fig. 4.26."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from friction_model import dry_run_in_length, flash_temperature_rise
from friction_model.constants import ICE


def test_thesis_example_value():
    # Section 4.5.1: dT = 8 K, p = 0.25 MPa, mu_dry = 1.5, v = 1 m/s -> 1.5 mm, i.e.
    # 1.51 mm. Tolerance: half a unit of the quoted last digit (0.005 mm).
    eps = dry_run_in_length(8.0, 0.25e6, 1.5, 1.0)
    assert abs(eps * 1e3 - 1.51) < 0.005


def test_closed_form_value():
    # Independent evaluation of Eq. 4.7 with the thesis constants, written out by hand.
    expected = (8.0 / (2 * 1.5 * 0.25e6)) ** 2 * np.pi * 2.2 * 917.0 * 2090.0 / 1.0
    assert_allclose(dry_run_in_length(8.0, 0.25e6, 1.5, 1.0), expected, rtol=1e-14)


@pytest.mark.parametrize(
    ("name", "factor", "expected_ratio"),
    [
        ("delta_T_K", 2.0, 4.0),  # ~ dT^2
        ("pressure_Pa", 2.0, 0.25),  # ~ 1/p^2
        ("mu_dry", 2.0, 0.25),  # ~ 1/mu^2
        ("velocity_mps", 2.0, 0.5),  # ~ 1/v
        ("delta_T_K", 0.1, 0.01),
        ("velocity_mps", 7.0, 1 / 7.0),
    ],
)
def test_scaling_fig_4_26(name, factor, expected_ratio):
    base = {"delta_T_K": 5.0, "pressure_Pa": 3e5, "mu_dry": 1.5, "velocity_mps": 2.0}
    scaled = dict(base, **{name: base[name] * factor})
    ratio = dry_run_in_length(**scaled) / dry_run_in_length(**base)
    assert_allclose(ratio, expected_ratio, rtol=1e-12)  # exact power laws


def test_heat_fraction_scaling():
    assert_allclose(
        dry_run_in_length(5.0, 3e5, 1.5, 2.0, heat_fraction=0.5)
        / dry_run_in_length(5.0, 3e5, 1.5, 2.0),
        4.0,
        rtol=1e-12,
    )


def test_eq_4_6_inverts_eq_4_7():
    dT = np.array([0.5, 2.0, 8.0, 20.0])
    v = np.array([0.5, 1.0, 3.0, 7.0])
    eps = dry_run_in_length(dT, 0.4e6, 1.2, v)
    assert_allclose(flash_temperature_rise(eps, 0.4e6, 1.2, v), dT, rtol=1e-12)


def test_vectorised_broadcast():
    v = np.linspace(1, 7, 7)
    eps = dry_run_in_length(8.0, 0.25e6, 1.5, v)
    assert eps.shape == (7,)
    assert_allclose(eps * v, eps[0] * v[0], rtol=1e-12)


def test_thermal_constants_are_thesis_values():
    assert (ICE.thermal_conductivity_W_mK, ICE.density_kg_m3) == (2.2, 917.0)
    assert (ICE.specific_heat_J_kgK, ICE.latent_heat_J_kg) == (2090.0, 334e3)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"velocity_mps": 0.0}, "velocity_mps"),
        ({"pressure_Pa": -1.0}, "pressure_Pa"),
        ({"mu_dry": 0.0}, "mu_dry"),
        ({"delta_T_K": -1.0}, "delta_T_K"),
        ({"delta_T_K": np.nan}, "delta_T_K"),
        ({"heat_fraction": 1.5}, "heat_fraction"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"delta_T_K": 8.0, "pressure_Pa": 0.25e6, "mu_dry": 1.5, "velocity_mps": 1.0}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        dry_run_in_length(**args)


@pytest.mark.parametrize(("call", "said"), [
    (lambda: dry_run_in_length(8.0, 0.25e6, 1.5, 0.0),
     "velocity_mps must be > 0, got velocity_mps=0"),
    (lambda: dry_run_in_length(8.0, [0.25e6, -1.0], 1.5, 1.0),
     "pressure_Pa must be > 0, got min(pressure_Pa)=-1"),
    (lambda: dry_run_in_length(-2.0, 0.25e6, 1.5, 1.0), "delta_T_K must be >= 0, got delta_T_K=-2"),
    (lambda: flash_temperature_rise(-1e-3, 0.25e6, 1.5, 1.0),
     "length_m must be >= 0, got length_m=-0.001"),
])
def test_a_bad_input_is_named_with_its_value_as_a_plain_number(call, said):
    # before: "got velocity_mps=array(0.)"
    with pytest.raises(ValueError) as info:
        call()
    assert str(info.value) == said
