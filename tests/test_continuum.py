"""The continuum element (friction_model.continuum) against independent truths.

* a slender cantilever (depth / length 10) against the closed-form plane-strain Timoshenko
  beam (deflection within 2 %: the rigid clamp of the continuum stiffens the root by an
  amount O(l / d), 1.7 % at nu = 0.5 and d / l = 10, half that at 20) and its first
  frequencies against the beam's exact frequency equation (within 1 %);
* no volumetric locking: nu = 0.4999 gives the same deflection as nu = 0.5 and the same
  trend from nu = 0.45 as the beam's E / (1 - nu^2);
* a flat punch pressed into a block: the pressure follows P / (pi sqrt(a^2 - x^2));
* the neo-Hookean model at a small load is the linear model (an independent implementation);
* the lever arm of the element held flat on the ice is the guided beam's mu d / 2;
* mesh convergence of the G3 element on the ice (two refinements within 1 %; slow, in
  ``tests/test_continuum_slow.py``).
"""

from __future__ import annotations

import ast
import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("skfem")

import friction_model.continuum
from friction_model.continuum import (
    ElementSpec,
    build_mesh,
    element_outputs,
    modal_frequencies,
    section_profile,
    solve_element,
    solve_linear,
    solve_neo_hookean,
)
from friction_model.continuum.state import ElementState
from friction_model.dynamics.timoshenko import (
    TimoshenkoParams,
    cowper_shear_coefficient,
    natural_frequencies_timoshenko,
)

E = 3.6e6
MU_G3 = 0.2936  # Eq. 5.24 fitted to Table 4.6 at 1 m/s
N_G3 = 91.0


def _slender(nu: float, n_length: int = 8, ratio: float = 10.0) -> ElementSpec:
    return ElementSpec(height_m=ratio * 4e-3, length_m=4e-3, width_m=0.08,
                       youngs_modulus_Pa=E, poisson_ratio=nu, n_length=n_length)


def _tip(spec: ElementSpec, force: float = 1.0) -> float:
    em = build_mesh(spec)
    s = solve_linear(em, normal_force_N=0.0, face="free", tangential_force_N=force)
    return float(np.sum(em.face_weights_m * s.face_ux_m) / spec.length_m)


def _beam_plane_strain(spec: ElementSpec, force: float = 1.0) -> float:
    nu = spec.poisson_ratio
    Ep = E / (1 - nu**2)
    G = E / (2 * (1 + nu))
    inertia = spec.width_m * spec.length_m**3 / 12
    area = spec.width_m * spec.length_m
    d = spec.height_m
    return force * d**3 / (3 * Ep * inertia) + force * d / (cowper_shear_coefficient(nu) * G * area)


def test_scikit_fem_is_imported_only_when_a_model_is_built(monkeypatch):
    # no module of the room imports skfem at module level (friction_model imports without it)
    room = Path(friction_model.continuum.__file__).parent
    for path in room.glob("*.py"):
        for node in ast.parse(path.read_text()).body:
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            assert not any(n.split(".")[0] == "skfem" for n in names), path.name
    monkeypatch.setitem(sys.modules, "skfem", None)
    with pytest.raises(ImportError, match=r"tir-contact\[fem\]"):
        build_mesh(ElementSpec(n_length=2))


@pytest.mark.parametrize("nu", [0.3, 0.5])
def test_slender_cantilever_matches_the_plane_strain_timoshenko_beam(nu):
    spec = _slender(nu)
    assert _tip(spec) == pytest.approx(_beam_plane_strain(spec), rel=0.02)


def test_slender_cantilever_frequencies_match_the_beam_frequency_equation():
    nu = 0.3  # TimoshenkoParams keeps E / (2 G) - 1 <= 0.5; plane strain E' / (2 G) - 1 = 0.43
    spec = _slender(nu, n_length=4)
    em = build_mesh(spec)
    state = solve_linear(em, normal_force_N=0.0, face="free")
    fe = modal_frequencies(state, face="free", n_modes=3)
    beam = TimoshenkoParams(E_Pa=E / (1 - nu**2), G_Pa=E / (2 * (1 + nu)),
                            shear_coefficient=cowper_shear_coefficient(nu),
                            height_m=spec.height_m, length_m=spec.length_m,
                            width_m=spec.width_m, density_kg_m3=spec.density_kg_m3,
                            contact_stiffness_N_m=1.0)
    np.testing.assert_allclose(fe, natural_frequencies_timoshenko(beam, 3), rtol=0.01)


def test_no_volumetric_locking_near_incompressibility():
    tips = {nu: _tip(_slender(nu, n_length=4)) for nu in (0.45, 0.4999, 0.5)}
    beam = {nu: _beam_plane_strain(_slender(nu)) for nu in (0.45, 0.4999)}
    # locking would stiffen nu = 0.4999 by orders of magnitude on this coarse mesh
    assert tips[0.4999] == pytest.approx(tips[0.5], rel=1e-3)
    assert tips[0.4999] / tips[0.45] == pytest.approx(beam[0.4999] / beam[0.45], rel=0.01)


def test_flat_punch_pressure_follows_the_half_space_solution():
    # a rigid flat punch of half-width a = 2 mm on an incompressible block 10 a long, 5 a
    # deep (frictionless; for nu = 0.5 friction does not change the normal pressure):
    # p = P / (pi sqrt(a^2 - x^2)). Finite block and nodal recovery: within 7 % inside 0.7 a
    a = 2e-3
    spec = ElementSpec(height_m=10e-3, length_m=20e-3, width_m=0.08, youngs_modulus_Pa=E,
                       poisson_ratio=0.5, n_length=80)
    em = build_mesh(spec)
    state = solve_linear(em, normal_force_N=10.0, contact_halfwidth_m=a)
    x = em.face_x_m
    inside = np.abs(x) <= 0.7 * a
    exact = 10.0 / 0.08 / (np.pi * np.sqrt(a**2 - x[inside] ** 2))
    np.testing.assert_allclose(state.face_pressure_Pa[inside], exact, rtol=0.07)
    assert not state.active[np.abs(x) > a * 1.001].any()
    assert state.active[np.abs(x) <= a].all()


def test_neo_hookean_at_a_small_load_is_the_linear_model():
    em = build_mesh(ElementSpec.from_preset("G3", n_length=4))
    small = solve_neo_hookean(em, normal_force_N=0.5, mu=MU_G3, n_steps=1)
    lin = solve_linear(em, normal_force_N=0.5, mu=MU_G3)
    # geometric nonlinearity scales with the strain (~1e-3 at 0.5 N)
    np.testing.assert_allclose(small.displacement, lin.displacement,
                               atol=5e-3 * np.abs(lin.displacement).max())


def test_lever_arm_of_the_face_held_flat_is_the_guided_beams():
    # full contact (mu = 0.1: no lift-off): the ice holds the face flat, the element bends
    # as a guided beam whose end moments are P d / 2, so e = mu d / 2 (linear, no N r term);
    # end effects of the continuum: 2 %
    spec = ElementSpec.from_preset("G3", n_length=8)
    out = element_outputs(solve_element(spec, normal_force_N=N_G3, mu=0.1))
    assert out.liftoff_m == 0.0
    assert out.lever_arm_m == pytest.approx(0.1 * spec.height_m / 2, rel=0.02)
    assert out.bending_rad == pytest.approx(0.0, abs=1e-6)


def test_section_profile_of_a_simple_shear_field():
    # u_x = g y, u_y = 0: deflection g y, slope atan(g), no section rotation, shear = slope
    em = build_mesh(ElementSpec(n_length=4))
    g = 0.1
    u = np.zeros(em.n_u)
    ix, _ = em.basis_u.split_indices()
    u[ix] = g * em.basis_u.doflocs[1, ix]
    st = ElementState(em, u, np.zeros(em.n_p), np.zeros(em.face_x.size),
                      np.zeros(em.face_x.size, dtype=bool), 0.0, 0.0, 0.0, "linear")
    prof = section_profile(st, n_sections=7)
    np.testing.assert_allclose(prof["deflection_m"], g * prof["y_m"], atol=1e-12)
    np.testing.assert_allclose(prof["slope_rad"], math.atan(g), atol=1e-9)
    np.testing.assert_allclose(prof["rotation_rad"], 0.0, atol=1e-12)


def test_rear_lifts_off_more_as_friction_grows_and_the_contact_set_settles():
    # mu = 0.5 puts the element near tipping (Newton fails beyond about 0.55): the
    # neo-Hookean contact set settles and lift-off and lever arm grow with mu
    spec = ElementSpec.from_preset("G3", n_length=4)
    outs = [element_outputs(solve_element(spec, normal_force_N=N_G3, mu=mu,
                                          model="neo-hookean")) for mu in (0.3, 0.5)]
    assert 0 < outs[0].liftoff_m < outs[1].liftoff_m < spec.length_m
    assert outs[0].lever_arm_m < outs[1].lever_arm_m < spec.length_m / 2


def test_base_layer_without_margin_is_a_taller_element():
    # a base layer as long as the element (no margin) is the element continued downwards:
    # the same mesh (shifted by t) as an element of height d + t: the same face to rounding
    common = {"length_m": 4e-3, "width_m": 0.08, "youngs_modulus_Pa": E, "n_length": 8}
    on_base = ElementSpec(height_m=6e-3, base_thickness_m=2e-3, base_margin_m=0.0, **common)
    taller = ElementSpec(height_m=8e-3, **common)
    a, b = (element_outputs(solve_element(s, normal_force_N=N_G3, mu=MU_G3))
            for s in (on_base, taller))
    for name in ("tip_deflection_m", "lever_arm_m", "contact_length_m"):
        assert getattr(a, name) == pytest.approx(getattr(b, name), rel=1e-7), name
    # a wider base is softer than the clamped root, and softer still when thicker
    clamped, thin, thick = (
        element_outputs(solve_element(ElementSpec(height_m=6e-3, base_thickness_m=t, **common),
                                      normal_force_N=N_G3, mu=MU_G3)).tip_deflection_m
        for t in (0.0, 1e-3, 4e-3))
    assert clamped < thin < thick
