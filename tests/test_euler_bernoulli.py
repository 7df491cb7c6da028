"""Euler-Bernoulli modal beam of a tread-block element (section 5.2, Eq. 5.13)."""

import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import trapezoid

from friction_model.contact.laws import ConstantLaw, ExponentialLaw, RelaxedFriction
from friction_model.dynamics import SolverOptions
from friction_model.dynamics.euler_bernoulli import (
    EulerBernoulliParams,
    clamped_free_beta_d,
    eb_mode_shapes,
    eb_natural_frequencies,
    simulate_euler_bernoulli,
)

# Tabulated roots of 1 + cos(x) cosh(x) = 0 (the clamped-free beam, e.g. Blevins, Formulas
# for natural frequency and mode shape, Table 8-1), 10 digits.
BETA_D = [1.875104069, 4.694091133, 7.854757438, 10.99554073, 14.13716839]

# A slender strip (d/l = 20, Eq. 5.13 holds up to k = 4) of steel-like stiffness, so that
# the modal dynamics decay within milliseconds: E 210 GPa, rho 7850 kg/m^3, d 20 mm,
# l 1 mm, w 10 mm.
SLENDER = {
    "length_m": 20e-3,
    "element_length_m": 1e-3,
    "width_m": 10e-3,
    "youngs_modulus_Pa": 210e9,
    "density_kg_m3": 7850.0,
}


def test_roots_and_frequencies_match_the_tabulated_beta_values():
    # Truth: tabulated beta_k d (5 decimals) and f_k = (beta_k d)^2 / (2 pi d^2) sqrt(EI/rho A).
    assert_allclose(clamped_free_beta_d(5), BETA_D, rtol=1e-9)
    params = EulerBernoulliParams(**SLENDER)
    ei = 210e9 * 10e-3 * (1e-3) ** 3 / 12
    rho_a = 7850.0 * 10e-3 * 1e-3
    expected = np.array(BETA_D[:4]) ** 2 / (2 * math.pi * 0.02**2) * math.sqrt(ei / rho_a)
    assert_allclose(eb_natural_frequencies(params, 4), expected, rtol=1e-9)


def test_modes_are_orthonormal_with_tip_value_two():
    # Truth: int_0^d W_j W_k dx = d delta_jk and W_k(d) = 2 (-1)^(k+1) for the clamped-free
    # modes; also checks the overflow-free evaluation up to mode 20 (trapezoid rule on 40001
    # points: 1e-6) and W' against finite differences.
    params = EulerBernoulliParams(**SLENDER)
    x = np.linspace(0.0, 0.02, 40001)
    w, dw = eb_mode_shapes(params, 20, x)
    gram = trapezoid(w[:, None, :] * w[None, :, :], x, axis=-1) / 0.02
    assert_allclose(gram, np.eye(20), atol=1e-6)
    assert_allclose(w[:, -1], 2.0 * (-1.0) ** np.arange(20), rtol=1e-9)
    fd = np.gradient(w[:3], x, axis=1)
    assert_allclose(fd[:, 1:-1], dw[:3, 1:-1], atol=1e-5 * np.abs(dw[:3]).max())


def test_static_tip_deflection_converges_to_cantilever_formula():
    # Truth: P d^3 / (3 EI) for a tip load P. A constant friction force P = mu F_N (contact on
    # the axis, no axial-load effect, so F_N is constant) gives, at rest, the truncated modal
    # sum 4 P d^3 / EI sum_k 1 / (beta_k d)^4, which converges to it: the error falls with k
    # and is below 1e-3 with 4 modes. The simulation settles to the modal sum (1e-7).
    params = EulerBernoulliParams(
        **SLENDER, contact_offset_m=0.0, axial_load=False, loss_factor=1.0
    )
    ei = params.bending_stiffness_Nm2
    errors = []
    for k in (1, 2, 3, 4):
        res = simulate_euler_bernoulli(
            params, velocity=5.0, preload=0.02 - 2e-6, friction=ConstantLaw(0.5),
            t_end_s=0.05, n_modes=k, solver=SolverOptions(rtol=1e-9, atol=1e-15),
        )  # fmt: skip
        p = 0.5 * res.data["normal_force_N"].iloc[-1]
        tip = res.data["tip_deflection_mm"].iloc[-1] * 1e-3
        modal = 4 * p * 0.02**3 / ei * np.sum(1 / np.array(BETA_D[:k]) ** 4)
        assert_allclose(tip, modal, rtol=1e-7)
        errors.append(abs(tip / (p * 0.02**3 / (3 * ei)) - 1))
    assert np.all(np.diff(errors) < 0)
    assert errors[0] > 0.02 and errors[-1] < 1e-3  # tail 12 sum_{k>4} (beta_k d)^-4 = 6.3e-4


@pytest.mark.parametrize("n_modes", [1, 2, 3])
def test_eq_5_13_warning_exactly_when_too_stubby(n_modes):
    # d/l = 5k exactly (binary-exact lengths) is allowed; a hair below warns.
    ell = 2.0**-10
    at_limit = EulerBernoulliParams(length_m=5 * n_modes * ell, element_length_m=ell)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        eb_natural_frequencies(at_limit, n_modes)
    below = EulerBernoulliParams(length_m=5 * n_modes * ell * (1 - 1e-12), element_length_m=ell)
    with pytest.warns(UserWarning, match=r"Eq. 5.13"):
        eb_natural_frequencies(below, n_modes)


def test_tread_element_is_outside_the_theory_and_deflects_backwards():
    # The G3 element (d/l = 6/4.55 = 1.3, "in the order of 4/3") violates Eq. 5.13 for any k;
    # sliding with friction still bends it backwards, more with less preload distance.
    params = EulerBernoulliParams()
    kw = {"velocity": 5.0, "friction": ExponentialLaw(0.8, 0.3, -0.3), "t_end_s": 0.01}
    with pytest.warns(UserWarning, match=r"d/l = 1.32 < 5 k = 10"):
        near = simulate_euler_bernoulli(params, preload=5.95e-3, n_modes=2, **kw)
    with pytest.warns(UserWarning, match=r"Eq. 5.13"):
        far = simulate_euler_bernoulli(params, preload=5.97e-3, n_modes=2, **kw)
    a_near, a_far = near.data["tip_deflection_mm"].iloc[-1], far.data["tip_deflection_mm"].iloc[-1]
    assert 0 < a_far < a_near
    assert near.fields["w_m"].shape == (len(near.data), 25)


def test_lift_off_and_relaxation():
    # Lift-off: no contact without preload. Eq. 5.12: mu follows a step of mu_ss with tau.
    params = EulerBernoulliParams(**SLENDER, contact_offset_m=0.0, loss_factor=1.0)
    free = simulate_euler_bernoulli(
        params, velocity=1.0, preload=0.03, friction=ConstantLaw(0.3), t_end_s=1e-3, n_modes=2
    )
    assert not free.data["contact"].any()
    res = simulate_euler_bernoulli(
        params,
        velocity=2.0,
        preload=0.02 - 2e-6,
        friction=RelaxedFriction(ConstantLaw(0.4), tau_s=0.002),
        initial_mu=0.0,
        t_end_s=0.004,
        n_modes=2,
        solver=SolverOptions(rtol=1e-9),
    )
    d = res.data
    mu_tau = np.interp(0.002, d["time_s"], d["mu"])
    assert_allclose(mu_tau, 0.4 * (1 - math.exp(-1)), rtol=1e-5)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"length_m": -1.0}, r"length_m must be a finite number > 0"),
        ({"element_length_m": 0.0}, r"element_length_m must be a finite number > 0"),
        ({"youngs_modulus_Pa": -3e6}, r"youngs_modulus_Pa must be a finite number > 0"),
        ({"contact_offset_m": 1.0}, r"contact_offset_m must lie in \[0, "),
    ],
)
def test_params_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        EulerBernoulliParams(**kwargs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n_modes": 0}, r"n_modes must be an integer in \[1, 60\]"),
        ({"rtol": 0.5}, r"rtol must lie in"),
        ({"t_end_s": 0.0}, r"t_end_s must lie in"),
        ({"method": "RK45"}, r"method must be one of"),
    ],
)
def test_simulation_options_validation(kwargs, match):
    kw = {"velocity": 1.0, "preload": 0.0199, "friction": ConstantLaw(0.3), "t_end_s": 1e-3}
    kw.update(kwargs)
    solver = SolverOptions(**{k: kw.pop(k) for k in ("rtol", "method") if k in kw})
    with pytest.raises(ValueError, match=match):
        simulate_euler_bernoulli(EulerBernoulliParams(**SLENDER), solver=solver, **kw)
