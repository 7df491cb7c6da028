"""The dry/wet model's heat physics against an independent solver and energy conservation."""

import numpy as np
import pytest
from scipy.linalg import solve_banded

from friction_model import ICE, Conditions, DryWetParameters, reference_block
from friction_model.contact.drywet import _as_table, _run

G3 = reference_block("G3")


class _IceColumn:
    """Implicit (backward Euler) finite-volume heat conduction in the ice below one surface
    point, on a mesh graded from 20 nm at the surface to 3 mm depth (far end held at 0)."""

    def __init__(self) -> None:
        z, dz = [0.0], 2e-8
        while z[-1] < 3e-3:
            z.append(z[-1] + dz)
            dz *= 1.05
        h = np.diff(np.asarray(z))
        vol = np.zeros(len(z))
        vol[:-1] += h / 2
        vol[1:] += h / 2
        self.cap = ICE.density_kg_m3 * ICE.specific_heat_J_kgK * vol
        self.g = ICE.thermal_conductivity_W_mK / h
        self.T = np.zeros(len(z))  # temperature rise above the bulk, K

    def step(self, dt: float, *, flux: float | None = None, surface: float | None = None):
        n, g = len(self.T), self.g
        ab = np.zeros((3, n))
        diag = self.cap / dt
        diag[:-1] += g
        diag[1:] += g
        ab[1], ab[0, 1:], ab[2, :-1] = diag, -g, -g
        rhs = self.cap / dt * self.T
        ab[1, -1], ab[2, -2], rhs[-1] = 1.0, 0.0, 0.0
        if surface is None:
            rhs[0] += flux
        else:
            ab[1, 0], ab[0, 1], rhs[0] = 1.0, 0.0, surface
        self.T = solve_banded((1, 1), ab, rhs)


def fd_heating_length_of_second_element(cond: Conditions) -> tuple[float, float]:
    """Independent physics: element 0 heats with q_dry until the surface melts, then holds
    it at the melting point; nothing over the sipe; element 1 heats with q_dry again."""
    prep, res, _ = _run(G3, _as_table(cond), DryWetParameters())
    inp = prep.inp
    v, dT = inp.velocity[0], inp.delta_T[0]
    q = inp.heat_fraction * inp.mu_dry * inp.pressure_local[0] * v
    col = _IceColumn()
    x, dx, l0 = 0.0, 1e-9, G3.element_lengths[0] * 1e-3
    melted = False
    while x < l0:  # element 0
        step = min(dx, l0 - x)
        if melted:
            col.step(step / v, surface=dT)
        else:
            col.step(step / v, flux=q)
            melted = col.T[0] >= dT
        x += step
        dx = min(dx * 1.02, 2e-6)
    for _ in range(200):  # the sipe
        col.step(G3.sipe_width_mm * 1e-3 / v / 200, flux=0.0)
    x, dx = 0.0, 1e-10
    while True:  # element 1 until its surface melts (linear interpolation in the last step)
        before = col.T[0]
        col.step(dx / v, flux=q)
        if col.T[0] >= dT:
            return x + dx * (dT - before) / (col.T[0] - before), res.heating_length[0, 1]
        x += dx
        dx = min(dx * 1.02, 2e-6)


@pytest.mark.parametrize(
    "cond",
    [
        Conditions.from_bar(0.3, 2.5, -10.0, humidity_pct=40.0),
        Conditions.from_bar(1.0, 2.5, -5.0, humidity_pct=40.0),
    ],
)
def test_preheated_element_against_finite_differences(cond):
    # Tolerance 1 %: the FD solve is first order in time with micrometre steps; the review
    # of the model found agreement within 0.1-0.3 % for these conditions.
    fd, model = fd_heating_length_of_second_element(cond)
    assert model == pytest.approx(fd, rel=1e-2)


@pytest.mark.parametrize(
    "cond",
    [
        Conditions.from_bar(1.0, 2.5, -5.0, humidity_pct=40.0),
        Conditions.from_bar(7.0, 2.5, -1.0, humidity_pct=95.0),
        Conditions.from_bar(0.3, 2.5, -10.0),
        Conditions.from_bar(20.0, 2.5, -1.0),
        Conditions.from_bar(30.0, 0.2, -1.0),  # wet stress capped at mu_dry p
    ],
)
def test_energy_is_conserved_per_element(cond):
    # Frictional heat into the ice side = conduction into the ice + latent heat of the melt
    # carried off behind the element (per unit width and time). Exact up to round-off.
    params = DryWetParameters()
    prep, res, _ = _run(G3, _as_table(cond), params)
    dx, inp = prep.grid.dx, prep.inp
    v = inp.velocity[0]
    for s, e in zip(prep.grid.element_starts, prep.grid.element_ends, strict=True):
        friction = inp.heat_fraction * v * (res.tau[0, s:e] @ dx[s:e])
        conduction = res.flux[0, s:e] @ dx[s:e]
        melt = inp.melt_energy * v * (res.film[0, e - 1] - inp.h0[0])
        assert conduction + melt == pytest.approx(friction, rel=1e-9)


def test_run_in_length_converges_with_the_grid():
    cond = [Conditions.from_bar(0.3, 2.5, -10.0, humidity_pct=40.0)]
    coarse = _run(G3, _as_table(cond), DryWetParameters(n_cells=40))[2]["run_in_length_m"]
    fine = _run(G3, _as_table(cond), DryWetParameters(n_cells=320))[2]["run_in_length_m"]
    np.testing.assert_allclose(coarse, fine, rtol=5e-3)
