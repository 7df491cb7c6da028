"""Tests of the Timoshenko tread-block element (thesis section 5.3).

Independent truths: the closed-form static deflection of a cantilever Timoshenko beam, its
exact clamped-free frequency equation (and the Euler-Bernoulli limit), quasi-static force
balance in steady sliding, and the exponential lag of Eq. 5.12. Tolerances follow the
method: round-off for closed forms, the grid order (h^2) for the finite differences, the
integration tolerances for time series.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from friction_model.contact.laws import (
    ArctanExponentialLaw,
    ConstantLaw,
    RelaxedFriction,
    VenkateshLaw,
)
from friction_model.dynamics import (
    SimulationError,
    SolverOptions,
    velocity_ramp,
    velocity_step,
)
from friction_model.dynamics.timoshenko import (
    TimoshenkoParams,
    _TimoshenkoProblem,
    cowper_shear_coefficient,
    fdm_natural_frequencies,
    fdm_static_deflection,
    lever_arm,
    natural_frequencies_timoshenko,
    preload_for_normal_force,
    simulate_timoshenko,
    static_tip_deflection,
)

E = 2e6  # Pa, soft tread rubber
BASE = dict(E_Pa=E, density_kg_m3=1150.0, kelvin_voigt_s=1e-3, contact_stiffness_N_m=1.2e5)
# Eq. 5.24 near the Table 4.6 cold/dry characteristic (decreasing for v > 0.1 m/s)
LAW = ArctanExponentialLaw(k1=0.17, k2=0.2256, k3=-0.569, k4=50.0)
N0 = 50.0  # N, initial contact force


def params(**kw) -> TimoshenkoParams:
    return TimoshenkoParams(**{**BASE, **kw})


def observed_order(h: np.ndarray, err: np.ndarray) -> float:
    """Slope of log|err| against log h (least squares)."""
    return float(np.polyfit(np.log(h), np.log(np.abs(err)), 1)[0])


# -- parameters -------------------------------------------------------------------------
def test_shear_coefficient_is_cowper_six_sevenths_for_rubber():
    p = params()
    assert p.shear_modulus_Pa == E / 3  # G = E/3 for nu = 0.5
    assert p.poisson_ratio == pytest.approx(0.5, abs=1e-15)
    assert p.kappa == pytest.approx(6 / 7, rel=1e-15)  # Eq. 5.19 value
    assert cowper_shear_coefficient(0.5) == pytest.approx(6 / 7, rel=1e-15)
    # Cowper (1966): 10 (1 + nu) / (12 + 11 nu); the printed "1 - nu" gives 5/17.5 at nu = 0.5
    assert cowper_shear_coefficient(0.3) == pytest.approx(13.0 / 15.3, rel=1e-15)
    assert cowper_shear_coefficient(0.0) == pytest.approx(10.0 / 12.0, rel=1e-15)


@pytest.mark.parametrize(
    ("kw", "exc", "match"),
    [
        ({"height_m": -6e-3}, ValueError, "height_m"),
        ({"height_m": 2e-3}, ValueError, r"height_m must be >= 0\.5 \* length_m"),
        ({"length_m": 0.0}, ValueError, "length_m"),
        ({"E_Pa": -1.0}, ValueError, "E_Pa"),
        ({"G_Pa": E / 4}, ValueError, "G_Pa"),
        ({"density_kg_m3": float("nan")}, ValueError, "density_kg_m3"),
        ({"kelvin_voigt_s": -1e-4}, ValueError, "kelvin_voigt_s"),
        ({"contact_stiffness_N_m": 0.0}, ValueError, "contact_stiffness_N_m"),
        ({"n_nodes": 2}, ValueError, "n_nodes"),
        ({"n_nodes": 3.5}, TypeError, "n_nodes"),
        ({"shear_coefficient": 1.5}, ValueError, "shear_coefficient"),
        ({"e3_m": 1e-4}, ValueError, "e3_m and e4_m"),
        ({"lever_arm_m": 3e-3}, ValueError, "lever_arm_m"),
        ({"length_m": 3e-3}, ValueError, "e3_m and e4_m or lever_arm_m"),
        ({"friction_smoothing_mps": 0.0}, ValueError, "friction_smoothing_mps"),
        ({"E_Pa": "3e6"}, TypeError, "E_Pa"),
    ],
)
def test_invalid_parameters_name_the_parameter(kw, exc, match):
    with pytest.raises(exc, match=match):
        params(**kw)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"rtol": 0.5}, "rtol"),
        ({"atol": 0.0}, "atol"),
        ({"t_end_s": -1.0}, "t_end_s"),
        ({"method": "RK45"}, "method"),
        ({"n_output": 1}, "n_output"),
        ({"velocity": float("inf")}, "velocity"),
    ],
)
def test_invalid_simulation_options_name_the_option(kw, match):
    p = params()
    opts = dict(velocity=1.0, preload=preload_for_normal_force(p, N0), friction=LAW, t_end_s=0.01)
    opts.update(kw)
    solver = {k: opts.pop(k) for k in ("rtol", "atol", "method") if k in opts}
    with pytest.raises(ValueError, match=match):
        simulate_timoshenko(p, solver=SolverOptions(**solver), **opts)


def test_lever_arm_follows_eq_5_21_and_fig_5_12():
    p = params()
    e_max = 1.9e-3  # Fig. 5.12 a
    assert lever_arm(p, 0.0) == 0.0
    assert abs(lever_arm(p, math.radians(10))) < 0.02 * e_max  # e ~ 0 up to 10 deg
    assert 0.95 * e_max < lever_arm(p, math.radians(40)) <= e_max  # ~1.9 mm beyond 40 deg
    phi = np.radians(np.linspace(-89, 89, 357))
    e = lever_arm(p, phi)
    assert_allclose(e, -lever_arm(p, -phi), atol=1e-18)  # odd: Eq. 5.22 mirrors Eq. 5.21
    assert np.all(np.abs(e) <= p.length_m / 2)  # inside the contact area
    # explicit e1..e4: Eq. 5.21 evaluated independently (away from the smoothed switch)
    q = params(e1=2.0, e2_per_rad=5.0, e3_m=2e-4, e4_m=5e-4)
    for ph in (0.1, 0.4, 1.0):
        ref = q.length_m / 4 - 2e-4 + math.atan(-2.0 + 5.0 * ph) / math.pi * (q.length_m / 2 - 5e-4)
        assert lever_arm(q, ph) == pytest.approx(ref, rel=1e-12)
        assert lever_arm(q, -ph) == pytest.approx(-ref, rel=1e-12)


# -- statics ----------------------------------------------------------------------------
@pytest.mark.parametrize("k_root", [None, 2.0])
@pytest.mark.parametrize("P, M", [(7.0, 0.0), (0.0, -0.02), (7.0, -0.02)])
def test_static_tip_deflection_by_castigliano(P, M, k_root):
    # Independent truth: Castigliano's theorem on the strain energy of the cantilever,
    # integrated numerically (quad): U = int M(x)^2 / (2 EI) + Q^2 / (2 kappa G A) dx
    # + M(0)^2 / (2 k). The tip deflection is dU/dP, with M(x) = M + P (d - x), Q = P;
    # a unit dummy force gives it for P = 0. Section from the raw inputs: I = w l^3 / 12
    # (bending across the 80 mm width), G = E / 3 (nu = 0.5), kappa = Cowper's 6/7 for nu = 0.5.
    from scipy.integrate import quad

    p = params(root_stiffness_Nm_per_rad=k_root)
    E, d, length, w = p.E_Pa, p.height_m, p.length_m, p.width_m
    EI, kGA = E * w * length**3 / 12, 6 / 7 * (E / 3) * w * length
    bend = quad(lambda x: (M + P * (d - x)) * (d - x) / EI, 0.0, d, epsabs=0, epsrel=1e-13)[0]
    shear = P * d / kGA
    root = 0.0 if k_root is None else (M + P * d) * d / k_root
    expected = bend + shear + root
    # quad's relative tolerance 1e-13 on a polynomial (exact to round-off)
    assert static_tip_deflection(p, P, moment_Nm=M) == pytest.approx(expected, rel=1e-12)
    if P:  # shear matters here (a third of the clamped deflection): dropping it fails
        assert shear / expected > 0.1


def test_fdm_static_deflection_converges_at_second_order():
    P = 7.0
    exact = static_tip_deflection(params(), P)
    nodes = np.array([9, 17, 33, 65])
    err = np.array([fdm_static_deflection(params(n_nodes=n), P)[1][-1] - exact for n in nodes])
    h = params().height_m / (nodes - 1)
    assert observed_order(h, err) == pytest.approx(2.0, abs=0.3)  # staggered scheme: O(h^2)
    assert abs(err[-1] / exact) < 1e-3


def test_fdm_tip_moment_is_exact():
    # a pure tip moment gives a linear rotation, integrated exactly by the scheme
    p = params(n_nodes=12)
    x, r, phi = fdm_static_deflection(p, 0.0, moment_Nm=-0.02)
    assert r[-1] == pytest.approx(static_tip_deflection(p, 0.0, moment_Nm=-0.02), rel=1e-10)
    assert_allclose(phi, -0.02 * x / p.EI, rtol=1e-10, atol=1e-15)


# -- natural frequencies ----------------------------------------------------------------
def test_frequency_equation_reaches_euler_bernoulli_limit():
    # slender beam: Timoshenko -> Euler-Bernoulli, beta_k L = 1.8751, 4.6941, 7.8548
    p = params(height_m=0.5, length_m=1e-3, lever_arm_m=0.0)
    scale = math.sqrt(p.EI / (p.rhoA * p.height_m**4)) / (2 * math.pi)
    eb = np.array([1.8751040687, 4.6940911330, 7.8547574382]) ** 2 * scale
    assert_allclose(natural_frequencies_timoshenko(p, 3), eb, rtol=1e-4)


def test_fdm_frequencies_converge_to_frequency_equation():
    exact = natural_frequencies_timoshenko(params(), 3)
    nodes = np.array([20, 40, 80])
    err = np.array([fdm_natural_frequencies(params(n_nodes=n), 3) - exact for n in nodes])
    h = params().height_m / (nodes - 1)
    for k in range(3):
        assert observed_order(h, err[:, k]) == pytest.approx(2.0, abs=0.3)
    # 40 nodes: O(h^2) error well below 0.1 % for the first three modes
    assert_allclose(fdm_natural_frequencies(params(), 3), exact, rtol=1e-3)


def test_free_vibration_after_release_rings_at_mode_one():
    # section 5.4: deflect, release, measure; no contact (ice 1 mm below the tip)
    p = params(kelvin_voigt_s=1e-6, E_Pa=3e6)
    f1 = natural_frequencies_timoshenko(p, 1)[0]
    res = simulate_timoshenko(
        p,
        velocity=0.0,
        preload=p.height_m + 1e-3,
        friction=LAW,
        t_end_s=0.01,
        n_output=4001,
        initial_tip_force_N=5.0,
        solver=SolverOptions(rtol=1e-6, atol=1e-9),
    )
    assert not res.data["contact"].any()
    t, x = res.data["time_s"].to_numpy(), res.data["tip_deflection_mm"].to_numpy()
    i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    f_sim = (tc.size - 1) / (tc[-1] - tc[0])
    # FDM (40 nodes) and time-integration errors are < 0.1 %; mode 2 is three times higher
    assert f_sim == pytest.approx(f1, rel=5e-3)


# -- sliding ----------------------------------------------------------------------------
def sliding(p, *, v=1.0, friction=LAW, t_end=0.1, **kw):
    return simulate_timoshenko(
        p,
        velocity=velocity_ramp(0.0, v, 0.0, 0.01) if v != 0 else 0.0,
        preload=preload_for_normal_force(p, N0),
        friction=friction,
        t_end_s=t_end,
        **kw,
    )


def test_steady_sliding_matches_static_force_balance():
    # without axial terms, foreshortening and lever arm the steady state is the static
    # beam under the tip force mu(v0) N0
    p = params(beam_column="none", foreshortening=False, lever_arm_m=0.0)
    res = sliding(p)
    last = res.data.iloc[-1]
    assert last["normal_force_N"] == pytest.approx(N0, rel=1e-12)
    assert last["v_rel_mps"] == pytest.approx(1.0, abs=1e-6)
    F = LAW.mu(1.0) * N0
    # O(h^2) grid error, relative (h/d)^2 / 4 ~ 2e-4 at 40 nodes
    assert last["tip_deflection_mm"] * 1e-3 == pytest.approx(static_tip_deflection(p, F), rel=1e-3)


def test_higher_velocity_gives_smaller_steady_deflection():
    p = params()
    steady = [sliding(p, v=v).steady("tip_deflection_mm").iloc[0] for v in (1.0, 3.0, 5.0)]
    assert steady[0] > steady[1] > steady[2] > 0  # decreasing mu(v) (Fig. 5.13)


def test_relative_velocity_uses_tip_deflection_velocity():
    # Eq. 5.23 corrected: v_rel = v0 - dr/dt(d), not v0 - dphi/dt(d)
    p = params()
    res = sliding(p, t_end=0.03, n_output=3001, solver=SolverOptions(rtol=1e-7, atol=1e-10))
    d = res.data
    t = d["time_s"].to_numpy()
    rdot = np.gradient(d["tip_deflection_mm"].to_numpy() * 1e-3, t)
    sel = slice(5, -5)
    err = d["v_rel_mps"].to_numpy()[sel] - (d["v0_mps"].to_numpy()[sel] - rdot[sel])
    # central differences on a 10 us grid of a ~1 kHz response: error << 1 mm/s
    assert np.max(np.abs(err)) < 2e-3
    assert np.max(np.abs(rdot)) > 0.05  # the tip did move, so the check has teeth


def test_offset_normal_force_deflects_tip_against_sliding_direction():
    # mu = 0 and a positive (front-edge) lever arm: static tip moment -e N (Eq. 5.20/5.28)
    e = 1e-3
    p = params(beam_column="none", foreshortening=False, lever_arm_m=e)
    res = sliding(p, friction=ConstantLaw(0.0), t_end=0.05)
    r_tip = res.data["tip_deflection_mm"].iloc[-1] * 1e-3
    assert r_tip < 0
    assert r_tip == pytest.approx(static_tip_deflection(p, 0.0, moment_Nm=-e * N0), rel=1e-6)


def test_negative_initial_deflection_before_friction_builds_up():
    # friction relaxing from mu = 0 (Eq. 5.12): the offset normal force acts first
    p = params(lever_arm_m=1e-3)
    res = sliding(p, friction=RelaxedFriction(LAW, 0.01), mu_initial=0.0, t_end=0.06)
    x = res.data["tip_deflection_mm"].to_numpy()
    t = res.data["time_s"].to_numpy()
    assert x[t <= 0.003].min() < 0
    assert x[-1] > 0


def test_lift_off_gives_zero_normal_force():
    p = params()
    y_contact = preload_for_normal_force(p, N0)

    def preload(t):
        return y_contact if t < 0.02 else p.height_m + 0.5e-3  # ice drops away at 20 ms

    res = simulate_timoshenko(p, velocity=1.0, preload=preload, friction=LAW, t_end_s=0.04)
    d = res.data
    before, after = d[d["time_s"] < 0.019], d[d["time_s"] > 0.021]
    assert before["contact"].all() and (before["normal_force_N"] > 0).all()
    assert not after["contact"].any()
    assert (after["normal_force_N"] == 0).all() and (after["friction_force_N"] == 0).all()


def test_relaxation_delays_velocity_step_response_by_tau():
    p = params()
    y0 = preload_for_normal_force(p, N0)

    def t63(friction):
        res = simulate_timoshenko(
            p,
            velocity=velocity_step(1.0, 3.0, 0.05),
            preload=y0,
            friction=friction,
            t_end_s=0.2,
            n_output=8001,
        )
        t, x = res.data["time_s"].to_numpy(), res.data["tip_deflection_mm"].to_numpy()
        a, b = x[np.searchsorted(t, 0.0499)], x[-1]
        frac = (x - a) / (b - a)
        return t[np.argmax((t > 0.05) & (frac >= 1 - math.exp(-1)))] - 0.05

    tau = 0.02
    # the beam itself answers within ~1 ms; with Eq. 5.12 the deflection follows mu(t),
    # which reaches 63 % of its step after tau
    assert t63(LAW) < 0.1 * tau
    assert t63(RelaxedFriction(LAW, tau)) == pytest.approx(tau, rel=0.15)


def test_relaxed_friction_with_zero_tau_is_the_law():
    p = params()
    a = sliding(p, t_end=0.03).data
    b = sliding(p, friction=RelaxedFriction(LAW, 0.0), t_end=0.03).data
    assert_allclose(a["tip_deflection_mm"], b["tip_deflection_mm"], rtol=0, atol=1e-12)


def test_reversed_sliding_mirrors_the_response():
    # odd friction law, odd lever arm, even foreshortening: v0 -> -v0 mirrors r and phi
    p = params()
    a = sliding(p, v=1.0, t_end=0.03).data
    b = sliding(p, v=-1.0, t_end=0.03).data
    assert_allclose(b["tip_deflection_mm"], -a["tip_deflection_mm"], atol=1e-6)
    assert_allclose(b["normal_force_N"], a["normal_force_N"], rtol=1e-6)


def test_even_and_pressure_dependent_laws_get_the_direction_of_v_rel():
    p = params()
    law = VenkateshLaw(A=3.0, B=15.0, E0_Pa=5e6)  # even in v, needs the pressure N / (l w)
    d = sliding(p, v=-1.0, friction=law, t_end=0.03).data.iloc[-1]
    assert d["friction_force_N"] < 0 and d["tip_deflection_mm"] < 0
    p_contact = d["normal_force_N"] / p.area_m2
    assert abs(d["mu"]) == pytest.approx(law.mu(1.0, pressure_Pa=p_contact), rel=1e-6)


def test_result_columns_and_fields():
    p = params(n_nodes=25)
    res = sliding(p, t_end=0.02, n_output=51)
    cols = {
        "time_s",
        "element",
        "angle_deg",
        "tip_deflection_mm",
        "bending_angle_deg",
        "shear_angle_deg",
        "normal_force_N",
        "friction_force_N",
        "v_rel_mps",
        "mu",
        "lever_arm_mm",
        "contact",
    }
    assert cols <= set(res.data.columns)
    assert len(res.data) == 51 and (res.data["element"] == 0).all()
    f = res.fields
    assert f["x_m"].shape == (25,) and f["t_s"].shape == (51,)
    assert f["r_m"].shape == (51, 25) and f["phi_rad"].shape == (51, 25)
    assert_allclose(f["r_m"][:, 0], 0.0)  # clamped root, Eq. 5.27
    assert_allclose(f["phi_rad"][:, 0], 0.0)
    assert_allclose(f["r_m"][:, -1] * 1e3, res.data["tip_deflection_mm"])
    d = res.data
    # alpha = atan(r'(d)), r'(d) = phi(d) + gamma(d)
    slope = np.tan(np.radians(d["angle_deg"]))
    assert_allclose(slope, np.radians(d["bending_angle_deg"] + d["shear_angle_deg"]), atol=1e-12)
    assert_allclose(d["friction_force_N"], d["mu"] * d["normal_force_N"], rtol=1e-12)


# -- numerics ---------------------------------------------------------------------------
@pytest.mark.parametrize("friction", [LAW, RelaxedFriction(VenkateshLaw(3.0, 15.0, 5e6), 0.01)])
def test_analytic_jacobian_matches_finite_differences(friction):
    p = params(n_nodes=8)
    prob = _TimoshenkoProblem(
        p,
        velocity=lambda t: 0.3,
        preload=lambda t: preload_for_normal_force(p, 80.0),
        friction=friction,
    )
    m = prob.m
    x = np.linspace(0, 1, m + 1)[1:]
    y = np.zeros(prob.dim)
    y[:m], y[m : 2 * m] = 5e-4 * x**2, 0.1 * x
    y[2 * m : 3 * m], y[3 * m : 4 * m] = 0.05 * x, 3 * x
    if prob.relaxed:
        y[-1] = 0.2
    J = prob.jac(0.1, y).toarray()
    Jn = np.empty_like(J)
    for j in range(prob.dim):
        dy = 1e-7 * max(abs(y[j]), 1e-3)
        yp, ym = y.copy(), y.copy()
        yp[j] += dy
        ym[j] -= dy
        Jn[:, j] = (prob.fun(0.1, yp) - prob.fun(0.1, ym)) / (2 * dy)
    # central differences: relative error ~1e-8 of each column's scale
    scale = np.maximum(np.abs(Jn).max(axis=0), 1e-30)
    assert np.max(np.abs(J - Jn) / scale) < 1e-5


def test_diverging_integration_raises_with_time():
    # contact load far above kappa G A: the -N gamma term of Eq. 5.26 destabilises the beam
    p = params()
    with pytest.raises(SimulationError, match=r"at t = [0-9.e-]+ s"):
        simulate_timoshenko(
            p,
            velocity=1.0,
            preload=preload_for_normal_force(p, 3000.0),
            friction=LAW,
            t_end_s=0.05,
        )


def test_non_finite_friction_raises_simulation_error():
    class BrokenLaw:
        def mu(self, v_rel_mps, *, pressure_Pa=None, temperature_C=None):
            v = np.asarray(v_rel_mps, dtype=float)
            return np.where(np.abs(v) >= 0.9, 0.3 * np.sign(v), np.nan)

    p = params()
    with pytest.raises(SimulationError, match="t = "):
        sliding(p, friction=BrokenLaw(), t_end=0.02)
