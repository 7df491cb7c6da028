"""Rigid-body tread-block models (section 5.1): SDOF element and siped block.

Independent truths: the thesis's own equations (Eq. 5.8, Eq. 5.10-5.11) coded here by hand,
closed-form frequencies and static moment balances, energy conservation, mirror symmetry;
and the thesis's qualitative results (Fig. 5.4-5.7) in a stated scenario.
"""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from friction_model.contact.laws import (
    ArctanExponentialLaw,
    ConstantLaw,
    DecreasingSqrtLaw,
    ExponentialLaw,
    RelaxedFriction,
    fit_law,
)
from friction_model.dynamics import SolverOptions
from friction_model.dynamics import _rigid_eom as eom
from friction_model.dynamics._common import SimulationError, velocity_step
from friction_model.dynamics.rigid import (
    BlockParams,
    SdofParams,
    element_surface_profiles,
    gent_youngs_modulus,
    simulate_block_dynamics,
    simulate_sdof,
)

L_G3 = 4.55e-3  # element length of the reference sample G3, m
H = 6e-3  # element height (sipe depth) of chapter 5, m

# Scenario for the thesis's qualitative results (section 5.1.2.2-3). G3 elements with the
# "face" contact (penalty springs spread over the bottom face). Penalty stiffness 5e4 N/m:
# the thesis preloads y0 = 5.1 / 4.6 mm then load an element with 45 / 70 N (1.2 / 1.9 bar,
# the HiLiTe range); with the default E l w / d = 2.2e5 N/m they load it close to the
# buckling load of the rigid chain (F_N d ~ c_phi) and it oscillates. Loss factor 0.4:
# tan(delta) of a winter compound at the elements' ~1 kHz and -5 degC; with 0.2 the
# decreasing law makes steady sliding at 1 m/s unstable (stick-slip).
FACE = {
    "contact_model": "face",
    "contact_stiffness_N_m": 5e4,
    "loss_factor": 0.4,
    "element_length_m": L_G3,
}
# Decreasing characteristic of Eq. 5.7: mu(1 m/s) = 0.31, mu(5 m/s) = 0.23.
LAW = ExponentialLaw(a1=0.2, a2=0.15, a3=-0.3)
# The thesis's "edge" contact (Fig. 5.3, Eq. 5.10-5.11) deflects backwards only when the
# friction moment beats the moment of the normal force at the leading edge (mu d >~ l/2 for
# G3); a high-friction characteristic (cold, polished ice: Roberts measured mu = 1.8) and
# a light preload keep it on that branch.
EDGE = {"contact_stiffness_N_m": 2e4, "loss_factor": 0.4, "element_length_m": L_G3}
HIGH_LAW = ExponentialLaw(a1=0.8, a2=0.3, a3=-0.3)  # mu(1) = 1.02, mu(5) = 0.87


def steady(result, column="angle_deg", since=None):
    d = result.data
    if since is not None:
        d = d[d.time_s >= since]
    return d.groupby("element")[column].mean().to_numpy()


# -- the equations of motion ------------------------------------------------------------------
def test_general_eom_is_eq_5_10_and_5_11_for_four_elements():
    # Truth: Eq. 5.10-5.11 as printed, for bars 3 and 4 (thesis element 2). The thesis numbers
    # elements from the trailing one; here element 0 leads, so thesis elements 1, 2, 3 are
    # elements 3, 2, 1. S_1, S_2 act at the trailing bottom corners of bars 3, 4; S_3, S_4 at
    # those of bars 5, 6, pressing on the leading face of bars 3, 4 at the corner's depth.
    # Agreement to rounding (1e-12) for random states and forces.
    n, d, ell, m, g = 4, 3e-3, 4.55e-3, 1.2e-3, 9.81
    masses = np.full((n, 2), m)
    inertia_c = m * (d**2 + ell**2) / 12 * np.ones((n, 2))
    L, grav = eom.bar_inertia_constants(masses, inertia_c, np.array([d, d]), g)
    rng = np.random.default_rng(1)
    springs, dampers = rng.uniform(0.5, 1.0, (n, 2)), rng.uniform(1e-4, 2e-4, (n, 2))
    model = eom.ChainModel(
        bar_length=np.array([d, d]),
        L=L,
        gravity=grav,
        spring=springs,
        damper=dampers,
        elem_length=np.full(n, ell),
        width=0.08,
        root_x=-np.arange(n) * (ell + 0.6e-3),
        ground_stiffness=np.full(n, 1e5),
        free_length=0.0,
        contact_model="edge",
        contact_offset=np.full(n, ell / 2),
        sipe_stiffness=np.full(n - 1, 1e5),
    )
    sin, cos, tan = np.sin, np.cos, np.tan
    for _ in range(5):
        phi = rng.uniform(-0.4, 0.4, (n, 2))
        dphi = rng.uniform(-80, 80, (n, 2))
        p3, p4 = phi[2]
        p5, p6 = phi[1]
        dp3, dp4 = dphi[2]
        c3, c4 = springs[2]
        d3, d4 = dampers[2]
        s1, s2, s3, s4, r1, r2, r3, r4, fn, ff = rng.uniform(1, 10, 10)
        j_b = m * d**2 / 3 + m * ell**2 / 12  # Eq. 5.9 for bar 3 about its joint B
        j_c2 = m * (d**2 + ell**2) / 12
        mass = eom.mass_matrix(model, phi)[2]
        c34 = cos(p3 - p4)
        assert_allclose(
            mass, [[j_b + m * d**2, m * d**2 / 2 * c34], [m * d**2 / 2 * c34, j_c2 + m * d**2 / 4]]
        )
        h3 = d * cos(p5) - ell / 2 * sin(p5)
        rhs3 = (
            -(d3 + d4) * dp3 + d4 * dp4 - (c3 + c4) * p3 + c4 * p4
            + m * d**2 / 2 * sin(p4 - p3) * dp4**2 - 1.5 * m * g * d * sin(p3)
            - (d * cos(p3) - ell / 2 * sin(p3)) * s1 + h3 * s3
            - (d * sin(p3) + ell / 2 * cos(p3)) * r1
            - (ell / (2 * cos(p3)) - h3 * tan(p3)) * r3
            - d * cos(p3) * s2 + d * cos(p3) * s4 - d * sin(p3) * r2
            + d * sin(p3) * r4 + d * sin(p3) * fn + d * cos(p3) * ff
        )  # fmt: skip
        h4 = d * cos(p5) + d * cos(p6) - ell / 2 * sin(p6) - d * cos(p3)
        rhs4 = (
            d4 * dp3 - d4 * dp4 + c4 * p3 - c4 * p4
            + m * d**2 / 2 * sin(p3 - p4) * dp3**2 - m * g * d / 2 * sin(p4)
            - (d * cos(p4) - ell / 2 * sin(p4)) * s2 + h4 * s4
            - (d * sin(p4) + ell / 2 * cos(p4)) * r2
            + (d / 2 * sin(p4) - ell / (2 * cos(p4))) * r4
            + (h4 - d / 2 * cos(p4)) * tan(p4) * r4
            + (d * sin(p4) - ell / 2 * cos(p4)) * fn + (ell / 2 * sin(p4) + d * cos(p4)) * ff
        )  # fmt: skip

        q = eom.internal_forces(model, phi, dphi) - eom.velocity_terms(model, phi, dphi)
        kin = eom.Kinematics(model, phi)
        full = np.full(n, d)
        # ground contact at the leading bottom edge: friction -x, normal force +y
        jx, jy = kin.jacobian(1, full, np.full(n, ell / 2))
        q = q + eom.generalized_force(jx, jy, np.full(n, -ff), np.full(n, fn))
        # own trailing corners (S_1, R_S1 on bar 3; S_2, R_S2 on bar 4): (+S, -R)
        for bar, (s, r) in enumerate([(s1, r1), (s2, r2)]):
            jx, jy = kin.jacobian(bar, full, np.full(n, -ell / 2))
            q[2] += s * jx[2] - r * jy[2]
        # the neighbour in front presses on the leading face at its corner's depth: (-S, +R)
        for bar, (s, r) in enumerate([(s3, r3), (s4, r4)]):
            _, yc = kin.point(bar, full, np.full(n, -ell / 2))
            sb = (-yc[1] + kin.jy[2, bar] - ell / 2 * sin(phi[2, bar])) / cos(phi[2, bar])
            jx, jy = kin.jacobian(bar, np.full(n, sb), np.full(n, ell / 2))
            q[2] += -s * jx[2] + r * jy[2]
        assert_allclose(q[2], [rhs3, rhs4], rtol=1e-12, atol=1e-15)


def eq_5_8_rhs(params, mu, v0, y0):
    """Eq. 5.8 with Eq. 5.1-5.6 (and gravity), coded from the thesis, v_rel = v0 - d cos dphi."""
    p = params
    d = p.length_m

    def f(t, y):
        phi, dphi = y
        fn = p.contact_stiffness_N_m * max(p.free_length_m + d * math.cos(phi) - y0, 0.0)
        v_rel = v0 - d * math.cos(phi) * dphi
        ff = mu * fn * math.tanh(v_rel / 1e-3)
        moment = (
            -p.damping_constant_Nms_rad * dphi
            - p.spring_constant_Nm_rad * phi
            + ff * d * math.cos(phi)
            + fn * d * math.sin(phi)
            - p.mass_kg * p.gravity_mps2 * d / 2 * math.sin(phi)
        )
        return [dphi, moment / p.inertia_kgm2]

    return f


def test_sdof_matches_eq_5_8_integrated_directly():
    # Truth: Eq. 5.8 integrated here with its own solver; agreement within the tolerances
    # of both integrations (rtol 1e-8): 1e-6 of the peak angle.
    params = SdofParams()
    y0, v0, mu = H - 0.05e-3, 3.0, 0.4
    res = simulate_sdof(
        params,
        velocity=v0,
        preload=y0,
        friction=ConstantLaw(mu),
        t_end_s=0.01,
        solver=SolverOptions(rtol=1e-10, atol=1e-13),
        output_step_s=1e-4,
    )
    t = res.data["time_s"].to_numpy()
    ref = solve_ivp(
        eq_5_8_rhs(params, mu, v0, y0), (0, 0.01), [0, 0], t_eval=t, rtol=1e-11, atol=1e-14,
        method="LSODA",
    )  # fmt: skip
    phi = np.radians(res.data["angle_deg"].to_numpy())
    assert_allclose(phi, ref.y[0], atol=1e-6 * np.abs(ref.y[0]).max())


def test_one_element_of_one_bar_is_the_sdof_model():
    # Truth: the SDOF model (Eq. 5.8/5.9). A block of one one-bar element with the contact on
    # the bar's axis (Fig. 5.1) derives the same mass, J_A (Eq. 5.9), spring, damper and
    # penalty stiffness from the rubber (to rounding), so both runs agree within the solver
    # tolerance (rtol 1e-10: 1e-7 of the peak angle).
    block = BlockParams(n_elements=1, n_bars=1, element_length_m=L_G3, contact_offset_m=0.0)
    chain = block.chain_model()
    sdof = SdofParams()
    assert_allclose(chain.L[0, 0, 0], sdof.inertia_kgm2, rtol=1e-14)
    assert_allclose(chain.spring[0, 0], sdof.spring_constant_Nm_rad, rtol=1e-14)
    assert_allclose(chain.damper[0, 0], sdof.damping_constant_Nms_rad, rtol=1e-12)
    kw = {"velocity": 2.0, "preload": H - 0.1e-3, "friction": LAW, "t_end_s": 0.005}
    kw.update(solver=SolverOptions(rtol=1e-10, atol=1e-13))
    a = simulate_block_dynamics(block, **kw).data["angle_deg"].to_numpy()
    b = simulate_sdof(sdof, **kw).data["angle_deg"].to_numpy()
    assert_allclose(a, b, atol=1e-7 * np.abs(b).max())


@pytest.mark.parametrize("gravity", [0.0, 9.80665])
def test_sdof_small_amplitude_frequency(gravity):
    # Truth: omega^2 = (c_phi + m g d/2) / J_A for the free, undamped, hanging bar (no ground
    # contact). Period from zero crossings over 20 cycles: error ~1e-6 (interpolation).
    params = SdofParams(damping_constant_Nms_rad=0.0, gravity_mps2=gravity)
    omega = math.sqrt(
        (params.spring_constant_Nm_rad + params.mass_kg * gravity * H / 2) / params.inertia_kgm2
    )
    period = 2 * math.pi / omega
    res = simulate_sdof(
        params,
        velocity=0.0,
        preload=2 * H,
        friction=ConstantLaw(0.3),
        t_end_s=20.2 * period,
        initial_angle_rad=1e-3,
        solver=SolverOptions(rtol=1e-10, atol=1e-14),
        output_step_s=period / 200,
    )
    t, a = res.data["time_s"].to_numpy(), res.data["angle_deg"].to_numpy()
    i = np.flatnonzero((a[:-1] > 0) & (a[1:] <= 0))
    crossings = t[i] + a[i] / (a[i] - a[i + 1]) * (t[i + 1] - t[i])
    measured = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    assert_allclose(measured, period, rtol=1e-5)
    f_undamped = math.sqrt(params.spring_constant_Nm_rad / params.inertia_kgm2) / (2 * math.pi)
    assert_allclose(params.natural_frequency_Hz, f_undamped, rtol=1e-15)


def test_sdof_static_deflection_is_the_moment_balance_of_eq_5_8():
    # Truth: the rest state of Eq. 5.8, c phi = F_F d cos phi + F_N d sin phi - m g d/2 sin
    # phi with F_N = c_N (d cos phi - y0), F_F = mu F_N, solved by root finding. The
    # simulation settles to it (damped, 50 periods): 1e-7 rad.
    params = SdofParams()
    y0, mu = H - 0.1e-3, 0.35
    p = params

    def balance(phi):
        fn = p.contact_stiffness_N_m * (H * math.cos(phi) - y0)
        return (
            mu * fn * H * math.cos(phi)
            + fn * H * math.sin(phi)
            - p.mass_kg * p.gravity_mps2 * H / 2 * math.sin(phi)
            - p.spring_constant_Nm_rad * phi
        )

    expected = brentq(balance, 0.0, 0.5)
    res = simulate_sdof(
        params, velocity=4.0, preload=y0, friction=ConstantLaw(mu), t_end_s=0.03,
        solver=SolverOptions(rtol=1e-9, atol=1e-12),
    )  # fmt: skip
    final = math.radians(res.data["angle_deg"].iloc[-1])
    assert_allclose(final, expected, atol=1e-7)
    assert expected > 0.01  # a real deflection, not a trivial zero


def _swing(params, initial_rates_rad_s, solver, **options):
    """Elements started at `initial_rates_rad_s` on a block at rest (preload 5.7 mm, no ground
    friction), 2 ms; returns the result and the total energy (kinetic, springs, gravity,
    penalties) at each output step. `options` go to :func:`simulate_block_dynamics`."""
    y0 = 5.7e-3
    res = simulate_block_dynamics(
        params,
        velocity=0.0,
        preload=y0,
        friction=ConstantLaw(0.0),
        t_end_s=0.002,
        initial_rates_rad_s=initial_rates_rad_s,
        solver=solver,
        output_step_s=1e-5,
        **options,
    )
    phi, dphi = res.fields["phi_rad"], res.fields["dphi_rad_s"]
    energy = eom.energy(
        params.chain_model(), phi, dphi, np.full(phi.shape[:2], y0), np.ones(len(phi))
    )
    return res, energy


# the face contact (the footage's model) in the default run; the edge contact with -m slow
@pytest.mark.parametrize("contact_model", [pytest.param("edge", marks=pytest.mark.slow), "face"])
def test_energy_is_conserved_without_damping_and_friction(contact_model):
    # Truth: with no dampers and no friction, kinetic + spring + gravity + penalty energies
    # (ground and sipes, from their potentials) are constant. The elements are started
    # towards each other so that the sipes close; drift bounded by the tolerance: 1e-7.
    params = BlockParams(
        n_elements=3,
        element_length_m=L_G3,
        sipe_width_m=0.05e-3,
        contact_model=contact_model,
        damping_constants_Nms_rad=0.0,
    )
    res, energy = _swing(
        params,
        [[400.0, 600.0], [-300.0, -300.0], [-100.0, 50.0]],
        SolverOptions(rtol=1e-10, atol=1e-12),
    )
    assert res.data["sipe_force_N"].max() > 10.0  # the neighbours did collide
    assert res.data["contact"].mean() > 0.5  # ground contact, with lift-off of the edges
    phi, dphi = res.fields["phi_rad"], res.fields["dphi_rad_s"]
    chain = params.chain_model()
    # the kinetic energy checked independently from the centres of mass of the bars
    m_bar = params.density_kg_m3 * 0.08 * L_G3 * H / 2
    d = H / 2
    s, c = np.sin(phi), np.cos(phi)
    v1 = d / 2 * dphi[..., 0, None] * np.stack([-c[..., 0], s[..., 0]], -1)
    v2 = d * dphi[..., 0, None] * np.stack([-c[..., 0], s[..., 0]], -1) + d / 2 * dphi[
        ..., 1, None
    ] * np.stack([-c[..., 1], s[..., 1]], -1)
    j_c = m_bar * (d**2 + L_G3**2) / 12
    kinetic = 0.5 * m_bar * ((v1**2).sum(-1) + (v2**2).sum(-1)) + 0.5 * j_c * (dphi**2).sum(-1)
    ref_kin = 0.5 * np.einsum("...j,...jk,...k->...", dphi, eom.mass_matrix(chain, phi), dphi)
    assert_allclose(kinetic, ref_kin, rtol=1e-12)
    assert np.ptp(energy) / energy[0] < 1e-7


# with -m slow (about 3.5 s): the default run holds energy conservation without friction
# (face contact) and the dissipation of ground friction
@pytest.mark.slow
def test_sipe_friction_only_dissipates():
    # Truth: Coulomb friction in the sipes (R_S = mu S) opposes the relative sliding, so the
    # otherwise conservative system can only lose energy (solver noise: 1e-7 of E per output step).
    params = BlockParams(
        n_elements=2, element_length_m=L_G3, sipe_width_m=0.05e-3, damping_constants_Nms_rad=0.0
    )
    res, energy = _swing(
        params,
        [[400.0, 600.0], [-300.0, -300.0]],
        SolverOptions(rtol=1e-8, atol=1e-11),
        sipe_friction=ConstantLaw(0.8),
    )
    assert res.data["sipe_friction_N"].max() > 1.0
    assert np.all(np.diff(energy) <= 1e-7 * energy[0])
    assert energy[-1] < (1 - 1e-3) * energy[0]


def test_mirrored_velocity_mirrors_the_block():
    # Truth: mirror symmetry. Reversing v0 with an odd friction law (Eq. 5.24) mirrors the
    # block: element i at -v0 deflects as element N-1-i at +v0 with the opposite sign (the
    # leading edge moves to the other side). Same equations up to rounding: 1e-8 deg.
    params = BlockParams(n_elements=3, sipe_width_m=0.2e-3, **EDGE)
    law = ArctanExponentialLaw(k1=0.8, k2=0.3, k3=-0.3, k4=50.0)
    assert law(-2.0) == -law(2.0)
    kw = {"preload": 5.1e-3, "friction": law, "t_end_s": 0.004, "sipe_friction": ConstantLaw(0.3)}
    fwd = simulate_block_dynamics(params, velocity=3.0, **kw)
    bwd = simulate_block_dynamics(params, velocity=-3.0, **kw)
    a = fwd.data.pivot(index="time_s", columns="element", values="angle_deg").to_numpy()
    b = bwd.data.pivot(index="time_s", columns="element", values="angle_deg").to_numpy()
    assert np.abs(a).max() > 1.0
    assert_allclose(b, -a[:, ::-1], atol=1e-8)


@pytest.mark.parametrize(("n", "method"), [(3, "LSODA"), (16, "BDF")])
def test_identical_uncoupled_elements_behave_identically(n, method):
    # Truth: with gaps too wide to close, identical elements with one law each (a list) see
    # identical equations: identical to rounding. N = 16 with BDF takes the sparse Jacobian.
    params = BlockParams(n_elements=n, sipe_width_m=5e-3, **FACE)
    res = simulate_block_dynamics(
        params,
        velocity=5.0,
        preload=5.1e-3,
        friction=[LAW] * n,
        t_end_s=0.003,
        solver=SolverOptions(method=method),
    )
    a = res.data.pivot(index="time_s", columns="element", values="angle_deg").to_numpy()
    assert np.abs(a).max() > 1.0
    assert res.data["sipe_force_N"].max() == 0.0
    assert_allclose(a, a[:, [0] * n], rtol=1e-12, atol=1e-12)


# -- the thesis's results ---------------------------------------------------------------------
@pytest.mark.parametrize(("contact", "law"), [(FACE, LAW), (EDGE, HIGH_LAW)], ids=["face", "edge"])
def test_smaller_preload_distance_deflects_more(contact, law):
    # Fig. 5.4: y0 = 4.6 mm deflects the elements more than 5.1 mm (v = 5 m/s, d = 6 mm).
    params = BlockParams(n_elements=2, **contact)
    kw = {"velocity": 5.0, "friction": law, "t_end_s": 0.02, "output_step_s": 1e-4}
    near = steady(simulate_block_dynamics(params, preload=4.6e-3, **kw), since=0.015)
    far = steady(simulate_block_dynamics(params, preload=5.1e-3, **kw), since=0.015)
    assert np.all(far > 1.0)
    assert np.all(near > 1.5 * far)


def test_negative_initial_deflection_from_the_leading_edge_normal_force():
    # Fig. 5.4 b (arrow): the normal force at the leading edge (Fig. 5.3) tips the element
    # forwards while the friction still builds up (Eq. 5.12 from mu_R = 0 at the start of
    # sliding); then friction deflects it backwards.
    params = BlockParams(n_elements=1, **EDGE)
    res = simulate_block_dynamics(
        params,
        velocity=5.0,
        preload=5.1e-3,
        friction=RelaxedFriction(HIGH_LAW, tau_s=0.005),
        initial_mu=0.0,
        t_end_s=0.04,
        output_step_s=1e-4,
    )
    d = res.data
    early = d[d.time_s < 0.003]
    assert early["angle_deg"].min() < -2.0
    assert d["angle_deg"].iloc[-1] > 2.0
    # the face contact has no such offset: no negative excursion
    face = simulate_block_dynamics(
        BlockParams(n_elements=1, **FACE),
        velocity=5.0,
        preload=5.1e-3,
        friction=RelaxedFriction(LAW, tau_s=0.005),
        initial_mu=0.0,
        t_end_s=0.01,
    )
    assert face.data["angle_deg"].min() > -1e-3


def test_higher_velocity_smaller_and_faster_deflection():
    # Fig. 5.5 (y0 = 5.1 mm, decreasing Eq. 5.7): 5 m/s gives a smaller steady deflection
    # than 1 m/s, and reaches it sooner; at 1 m/s the tip first moves with the ground
    # (v_rel ~ 0, sticking), so the deflection rate is limited by v0.
    params = BlockParams(n_elements=2, **FACE)
    out = {}
    for v in (1.0, 5.0):
        res = simulate_block_dynamics(
            params, velocity=v, preload=5.1e-3, friction=LAW, t_end_s=0.04, output_step_s=2e-5
        )
        d = res.data[res.data.element == 0]
        ss = d[d.time_s > 0.035]["angle_deg"].mean()
        t90 = d.time_s[d.angle_deg >= 0.9 * ss].min()
        out[v] = (ss, t90, d[d.time_s < t90]["v_rel_mps"].min())
        assert d[d.time_s > 0.035]["angle_deg"].std() < 0.02  # steady sliding, no stick-slip
    assert out[5.0][0] < out[1.0][0] - 0.5
    assert out[5.0][1] < 0.7 * out[1.0][1]
    assert out[1.0][2] < 0.05 and out[5.0][2] > 1.0


# with -m slow (about 3.5 s): the default run holds the step and the relaxation lag through
# the renderer's truth (test_footage_step)
@pytest.mark.slow
def test_velocity_step_lowers_deflection_with_the_relaxation_lag():
    # Fig. 5.7: a step v1 -> v2 > v1 lowers the deflection (decreasing law); with Eq. 5.12
    # the change follows mu_R and reaches 63 % after about tau (the mechanics take < 1 ms);
    # without, it is immediate. 15 % on tau (the mechanical lag and output spacing).
    params = BlockParams(n_elements=2, **FACE)
    t_step, tau = 0.03, 0.02
    kw = {"velocity": velocity_step(1.0, 5.0, t_step), "preload": 5.1e-3, "t_end_s": 0.13}
    lags = {}
    for name, friction in (("steady", LAW), ("relaxed", RelaxedFriction(LAW, tau_s=tau))):
        res = simulate_block_dynamics(params, friction=friction, output_step_s=2e-4, **kw)
        d = res.data[res.data.element == 0]
        before = d[(d.time_s > t_step - 0.005) & (d.time_s < t_step)]["angle_deg"].mean()
        after = d[d.time_s > 0.125]["angle_deg"].mean()
        assert after < before - 0.5
        target = before + 0.632 * (after - before)
        later = d[d.time_s > t_step]
        lags[name] = later.time_s[later.angle_deg <= target].min() - t_step
    assert_allclose(lags["relaxed"], tau, rtol=0.15)
    assert lags["steady"] < tau / 10


@pytest.mark.slow
def test_rough_surface_second_pass_deflects_more():
    # Fig. 5.6: a rough profile passed twice. The elements meet the bumps one after another;
    # on the first pass the friction is still building up (Eq. 5.12 from the start of
    # sliding), on the second the block arrives in steady sliding: every element deflects
    # more at the same bump the second time.
    params = BlockParams(**FACE)
    v0, tau = 5.0, 0.004
    s = np.linspace(0.0, 0.025, 501)  # one 25 mm pass of the profile
    bump = 0.15e-3 * np.exp(-0.5 * ((s - 0.004) / 0.5e-3) ** 2)
    heights = np.concatenate([bump, bump[1:]])
    positions = np.concatenate([s, s[1:] + 0.025])
    t_end = 0.0135
    profiles = element_surface_profiles(
        params, 5.1e-3, heights, positions, lambda t: v0, t_max_s=t_end
    )
    res = simulate_block_dynamics(
        params,
        velocity=v0,
        preload=profiles,
        friction=RelaxedFriction(LAW, tau_s=tau),
        initial_mu=0.0,
        t_end_s=t_end,
        solver=SolverOptions(max_step_s=3e-5),
        output_step_s=3e-5,
    )
    offsets = params.element_offsets_m
    for i, off in enumerate(offsets):
        d = res.data[res.data.element == i]
        t1 = (0.004 + off) / v0  # time element i is on the bump, first and second pass
        t2 = t1 + 0.025 / v0
        w = 1.5e-3
        first = d[(d.time_s > t1 - w) & (d.time_s < t1 + w)]["angle_deg"].max()
        window = d[(d.time_s > t2 - w) & (d.time_s < t2 + w)]["angle_deg"]
        second = window.max()
        assert second > first + 0.1, (i, first, second)
        assert second > window.iloc[0] + 0.1  # the bump does deflect the element


# -- parameters, inputs and errors ------------------------------------------------------------
def test_default_parameters_are_derived_from_the_rubber():
    # Gent's relation at Shore A 60 (REF, Table 4.3); c_N = E l w / d; J_A by Eq. 5.9.
    e_mod = gent_youngs_modulus(60.0)
    assert_allclose(e_mod, 3.605e6, rtol=1e-3)
    p = SdofParams()
    assert_allclose(p.contact_stiffness_N_m, e_mod * L_G3 * 0.08 / H, rtol=1e-12)
    m = 1150.0 * L_G3 * 0.08 * H
    assert_allclose(p.inertia_kgm2, m * H**2 / 3 + m * L_G3**2 / 12, rtol=1e-12)
    # the spring reproduces the tip compliance of a bending + shear cantilever
    ei = e_mod * 0.08 * L_G3**3 / 12
    kga = 6 / 7 * e_mod / 3 * 0.08 * L_G3
    assert_allclose(p.spring_constant_Nm_rad, H**2 / (H**3 / (3 * ei) + H / kga), rtol=1e-12)
    block = BlockParams()
    assert_allclose(block.element_lengths_m, L_G3, rtol=1e-12)
    assert_allclose(block.element_offsets_m, np.arange(4) * (L_G3 + 0.6e-3), atol=1e-15)


def test_eq_5_7_fits_the_table_4_6_characteristic():
    # The decreasing Eq. 5.7 stands in for Eq. 4.8 with Table 4.6 (G3, 2.5 bar, -5 degC):
    # the fit is close (rmse < 0.005) over 1-7 m/s, the range of the scenario.
    v = np.linspace(1.0, 7.0, 61)
    fit = fit_law(ExponentialLaw, v, DecreasingSqrtLaw(0.2, 0.095)(v))
    assert fit.rmse < 0.005
    assert fit.params["a3"] < 0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"height_m": -1e-3}, r"height_m must be a finite number > 0"),
        ({"n_elements": 0}, r"n_elements must be an integer in \[1, inf\)"),
        ({"n_bars": 0}, r"n_bars must be an integer"),
        ({"density_kg_m3": -5.0}, r"density_kg_m3 must be a finite number > 0"),
        (
            {"spring_constants_Nm_rad": [1.0, -1.0]},
            r"spring_constants_Nm_rad\[0, 1\] must be a finite number > 0",
        ),
        ({"contact_stiffness_N_m": 0.0}, r"contact_stiffness_N_m must be a finite number > 0"),
        ({"element_length_m": [1e-3, 2e-3]}, r"element_length_m must be a scalar or have 4"),
        ({"contact_model": "line"}, r"contact_model must be 'edge' or 'face'"),
        ({"loss_factor": 3.0}, r"loss_factor must lie in \[0, 2\]"),
        ({"sipe_width_m": -1e-3}, r"sipe_width_m must be a finite number >= 0"),
    ],
)
def test_block_params_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        BlockParams(**kwargs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"length_m": -6e-3}, r"length_m must be a finite number > 0, got length_m=-0.006"),
        ({"mass_kg": -1.0}, r"mass_kg must be a finite number > 0"),
        ({"spring_constant_Nm_rad": -1.0}, r"spring_constant_Nm_rad must be a finite number > 0"),
        ({"contact_offset_m": 1.0}, r"contact_offset_m must lie in \[0, 0.002275\]"),
    ],
)
def test_sdof_params_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        SdofParams(**kwargs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"rtol": 1.0}, r"rtol must lie in \[1e-13, 0.01\]"),
        ({"atol": -1.0}, r"atol must be a finite number > 0"),
        ({"t_end_s": -1.0}, r"t_end_s must lie in"),
        ({"method": "RK45"}, r"method must be one of \('Radau', 'BDF', 'LSODA'\)"),
        ({"max_angle_deg": 120.0}, r"max_angle_deg must lie in"),
        ({"preload": [5e-3, 5e-3]}, r"preload must be one value/profile or one per element"),
        ({"friction": [LAW]}, r"friction must be one law or one per element \(4\)"),
        ({"velocity": float("nan")}, r"velocity must be finite"),
    ],
)
def test_simulation_options_validated_before_integration(kwargs, match):
    kw = {"velocity": 5.0, "preload": 5.1e-3, "friction": LAW, "t_end_s": 0.01, **kwargs}
    solver = {k: kw.pop(k) for k in ("rtol", "atol", "method") if k in kw}
    with pytest.raises(ValueError, match=match):
        simulate_block_dynamics(BlockParams(), solver=SolverOptions(**solver), **kw)


def test_bad_friction_object_and_relaxed_sipe_law_are_type_errors():
    with pytest.raises(TypeError, match=r"friction must provide mu"):
        simulate_sdof(SdofParams(), velocity=1.0, preload=5e-3, friction=0.3, t_end_s=0.01)
    with pytest.raises(TypeError, match=r"sipe_friction\[0\] is a RelaxedFriction"):
        simulate_block_dynamics(
            BlockParams(n_elements=2),
            velocity=1.0,
            preload=5e-3,
            friction=LAW,
            sipe_friction=RelaxedFriction(LAW, 0.01),
            t_end_s=0.01,
        )


def test_buckling_raises_simulation_error_with_time():
    # A preload far beyond the buckling load (F_N d > c_phi) folds the bar past 80 deg.
    with pytest.raises(SimulationError, match=r"reached 80 deg at t=\d"):
        simulate_sdof(
            SdofParams(), velocity=1.0, preload=0.5e-3, friction=ConstantLaw(0.2), t_end_s=0.05
        )


def test_result_columns_and_lift_off():
    # Lift-off (Eq. 5.1-5.3): a preload distance beyond the element height gives no contact.
    res = simulate_block_dynamics(
        BlockParams(n_elements=2, **FACE), velocity=1.0, preload=7e-3, friction=LAW, t_end_s=1e-3
    )
    cols = {
        "time_s", "element", "angle_deg", "angle_upper_deg", "angle_lower_deg",
        "tip_deflection_mm", "normal_force_N", "friction_force_N", "v_rel_mps", "mu", "contact",
        "contact_fraction", "sipe_force_N", "sipe_friction_N", "v0_mps", "preload_mm",
    }  # fmt: skip
    assert cols <= set(res.data.columns)
    assert not res.data["contact"].any()
    assert (res.data["normal_force_N"] == 0).all() and (res.data["contact_fraction"] == 0).all()
    assert_allclose(res.data["angle_deg"], 0.0, atol=1e-6)  # only gravity, which is balanced
