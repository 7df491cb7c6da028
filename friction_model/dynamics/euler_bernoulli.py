"""Euler-Bernoulli modal beam of one tread-block element (section 5.2, Eq. 5.13).

The element is a clamped-free beam of length d (the sipe depth), clamped in the block base,
with the rectangular section l x w (bending about the axis along w). Its transverse
deflection w(x, t) (positive backwards, against the sliding direction, like the angle phi
of the rigid models) is the superposition of the first k analytic clamped-free modes::

    w(x, t) = sum_k W_k(x) q_k(t),
    W_k(x) = cosh(b x) - cos(b x) - s_k (sinh(b x) - sin(b x)),  b = beta_k,
    s_k = (cosh(b d) + cos(b d)) / (sinh(b d) + sin(b d)),  1 + cos(b d) cosh(b d) = 0,

so beta_k d = 1.8751, 4.6941, 7.8548, 10.9955, ... and the natural frequencies are
``omega_k = (beta_k d)^2 / d^2 sqrt(EI / (rho A))``. With ``int_0^d W_j W_k dx = d delta_jk``
the modal equations are ``rho A d (ddq_k + 2 zeta omega_k dq_k + omega_k^2 q_k) = Q_k``.

Loads at the free end (Fig. 5.8 b): the penalty normal force F_N = c_N max(u_N, 0) and the
friction force F_F = mu F_N act at the leading edge, a distance e (default l/2) ahead of the
neutral axis, as observed on HiLiTe (Fig. 5.8 c). Transferred to the axis, the friction
force loads the tip transversally and F_N adds the moment -e F_N (it tips the element
forwards) and, as an axial compression, the second-order (P-delta) stiffness
``-F_N int W_j' W_k' dx`` (``axial_load=True``). The contact point's depth is
``d - 1/2 int w'^2 dx + e w'(d)`` (foreshortening and tilt of the end face), so
``u_N = y_N + depth - y0`` (Eq. 5.2 for the beam) and the generalised forces follow by
virtual work. Sliding: ``v_rel = v0 - dw/dt(d)``, the same convention as
:mod:`friction_model.dynamics.rigid`.

Applicability (Eq. 5.13): the theory needs d / l > 5 k for the k-th mode; a
:class:`UserWarning` is emitted when d / l < 5 k for the highest mode used. Tread elements
(d / l about 4/3) violate it, which is the thesis's reason to move on to Timoshenko.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from friction_model.dynamics._common import (
    Profile,
    SimulationResult,
    batched_fd_jacobian,
    finite_rhs,
    output_times,
    raise_if_failed,
)
from friction_model.dynamics.rigid import (
    _G3_ELEMENT_LENGTH_M,
    _HEIGHT_M,
    _WIDTH_M,
    REFERENCE_DENSITY_KG_M3,
    REFERENCE_LOSS_FACTOR,
    REFERENCE_YOUNGS_MODULUS_PA,
    _as_profile,
    _FrictionSet,
    _sgn,
)
from friction_model.dynamics.solver import EULER_BERNOULLI_SOLVER, SolverOptions
from tir_common.validate import check_positive, check_range

logger = logging.getLogger(__name__)

__all__ = [
    "EulerBernoulliParams",
    "clamped_free_beta_d",
    "eb_mode_shapes",
    "eb_natural_frequencies",
    "simulate_euler_bernoulli",
]

#: Gauss-Legendre points for the geometric-stiffness integrals int W_j' W_k' dx.
_N_GAUSS = 64


@dataclass(frozen=True)
class EulerBernoulliParams:
    """Clamped-free Euler-Bernoulli beam of one tread-block element (section 5.2).

    Parameters
    ----------
    length_m : float
        Beam length d (sipe depth, element height), m; 6 mm.
    element_length_m : float
        Element length l in the sliding direction (section depth in bending), m; 4.55 mm
        (G3).
    width_m : float
        Element width w, m; 80 mm.
    youngs_modulus_Pa, density_kg_m3 : float
        Rubber of the reference compound (Shore A 60 by Gent's relation, 1150 kg/m^3).
    loss_factor : float
        tan(delta); every mode gets the damping ratio tan(delta) / 2.
    contact_stiffness_N_m : float, optional
        Penalty constant c_N; default E l w / d, the compression stiffness of the element.
    free_length_m : float
        Undeformed penalty-spring length y_N, m.
    contact_offset_m : float, optional
        Distance of the contact point ahead of the neutral axis, m; default l/2 (the
        leading edge, Fig. 5.8 b); 0 loads the axis.
    axial_load : bool
        Include the foreshortening of the beam and the second-order stiffness of the
        compressive normal force.
    """

    length_m: float = _HEIGHT_M
    element_length_m: float = _G3_ELEMENT_LENGTH_M
    width_m: float = _WIDTH_M
    youngs_modulus_Pa: float = REFERENCE_YOUNGS_MODULUS_PA
    density_kg_m3: float = REFERENCE_DENSITY_KG_M3
    loss_factor: float = REFERENCE_LOSS_FACTOR
    contact_stiffness_N_m: float | None = None
    free_length_m: float = 0.0
    contact_offset_m: float | None = None
    axial_load: bool = True

    def __post_init__(self) -> None:
        d = check_positive("length_m", self.length_m)
        ell = check_positive("element_length_m", self.element_length_m)
        w = check_positive("width_m", self.width_m)
        e_mod = check_positive("youngs_modulus_Pa", self.youngs_modulus_Pa)
        check_positive("density_kg_m3", self.density_kg_m3)
        check_range("loss_factor", self.loss_factor, 0.0, 2.0)
        check_range("free_length_m", self.free_length_m, 0.0, math.inf, unit="m")
        setv = object.__setattr__
        if self.contact_stiffness_N_m is None:
            setv(self, "contact_stiffness_N_m", e_mod * ell * w / d)
        check_positive("contact_stiffness_N_m", self.contact_stiffness_N_m)
        if self.contact_offset_m is None:
            setv(self, "contact_offset_m", ell / 2)
        check_range("contact_offset_m", self.contact_offset_m, 0.0, ell / 2, unit="m")
        setv(self, "axial_load", bool(self.axial_load))

    @property
    def bending_stiffness_Nm2(self) -> float:
        """EI = E w l^3 / 12, N m^2."""
        return self.youngs_modulus_Pa * self.width_m * self.element_length_m**3 / 12

    @property
    def mass_per_length_kg_m(self) -> float:
        """rho A = rho w l, kg/m."""
        return self.density_kg_m3 * self.width_m * self.element_length_m

    @property
    def slenderness(self) -> float:
        """d / l, the ratio of Eq. 5.13."""
        return self.length_m / self.element_length_m


def clamped_free_beta_d(n_modes: int) -> np.ndarray:
    """Roots beta_k d of 1 + cos(x) cosh(x) = 0 (clamped-free beam), k = 1..n_modes.

    Examples
    --------
    >>> clamped_free_beta_d(3).round(4)
    array([1.8751, 4.6941, 7.8548])
    """
    n = _check_modes(n_modes)

    def f(x: float) -> float:
        return math.cos(x) + 1.0 / math.cosh(x)

    return np.array(
        [brentq(f, (k - 1) * math.pi + 1e-9, k * math.pi, xtol=1e-15) for k in range(1, n + 1)]
    )


def _check_modes(n_modes: int) -> int:
    if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
        raise ValueError(f"n_modes must be an integer in [1, 60], got n_modes={n_modes!r}")
    if n_modes > 60:
        raise ValueError(f"n_modes must be an integer in [1, 60], got n_modes={n_modes!r}")
    return int(n_modes)


def _modes(beta_d: np.ndarray, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """W_k and d W_k / d(xi) at xi = x / d in [0, 1], (K, n_x) each (overflow-free form).

    ``cosh z - s sinh z = ((1 - s) e^z + (1 + s) e^-z) / 2`` with ``(1 - s) e^z`` written
    as ``2 e^(z - bd) (sin bd - cos bd - e^-bd) / (1 - e^(-2 bd) + 2 e^-bd sin bd)``.
    """
    b = beta_d[:, None]
    z = b * xi[None, :]
    eb = np.exp(-b)
    den = 1.0 - eb**2 + 2.0 * eb * np.sin(b)
    num = np.sin(b) - np.cos(b) - eb
    sigma = 1.0 - 2.0 * eb * num / den
    one_minus_s_exp = 2.0 * np.exp(z - b) * num / den  # (1 - s) e^z without overflow
    em = np.exp(-z)
    # cosh z - s sinh z and sinh z - s cosh z
    ch_s = 0.5 * (one_minus_s_exp + (1 + sigma) * em)
    sh_s = 0.5 * (one_minus_s_exp - (1 + sigma) * em)
    w = ch_s - np.cos(z) + sigma * np.sin(z)
    dw = b * (sh_s + np.sin(z) + sigma * np.cos(z))
    return w, dw


def eb_mode_shapes(
    params: EulerBernoulliParams, n_modes: int, x_m: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Mode shapes W_k(x) and slopes W_k'(x) (1/m) at positions ``x_m`` from the clamp.

    Normalised to ``int_0^d W_k^2 dx = d``, so that ``W_k(d) = 2 (-1)^(k+1)``.

    Returns
    -------
    W, dW : (n_modes, n_x) ndarray
    """
    x = np.asarray(x_m, dtype=float)
    d = params.length_m
    w, dw = _modes(clamped_free_beta_d(n_modes), x / d)
    return w, dw / d


def _warn_eq_5_13(params: EulerBernoulliParams, n_modes: int) -> None:
    """Eq. 5.13: Euler-Bernoulli needs d / l > 5 k for mode k (warn when d / l < 5 k)."""
    ratio = params.slenderness
    if ratio < 5 * n_modes:
        warnings.warn(
            f"Euler-Bernoulli beam outside its range (Eq. 5.13): d/l = {ratio:.3g} < 5 k = "
            f"{5 * n_modes} for the {n_modes} mode(s) used; shear and rotary inertia are not "
            "negligible (use the Timoshenko model)",
            UserWarning,
            stacklevel=3,
        )


def eb_natural_frequencies(params: EulerBernoulliParams, n_modes: int) -> np.ndarray:
    """Natural frequencies of the first ``n_modes`` clamped-free bending modes, Hz.

    ``f_k = (beta_k d)^2 / (2 pi d^2) sqrt(EI / (rho A))``.

    Warns
    -----
    UserWarning
        If d / l < 5 n_modes (Eq. 5.13).
    """
    n = _check_modes(n_modes)
    _warn_eq_5_13(params, n)
    return _omegas(params, n) / (2 * math.pi)


def _omegas(params: EulerBernoulliParams, n: int) -> np.ndarray:
    bd = clamped_free_beta_d(n)
    d = params.length_m
    return bd**2 / d**2 * math.sqrt(params.bending_stiffness_Nm2 / params.mass_per_length_kg_m)


def simulate_euler_bernoulli(
    params: EulerBernoulliParams,
    *,
    velocity: float | Profile,
    friction: Any,
    t_end_s: float,
    normal_force: float | Profile | None = None,
    preload: float | Profile | None = None,
    n_modes: int = 3,
    solver: SolverOptions | None = None,
    output_step_s: float | None = None,
    v_reg_mps: float = 1e-3,
    n_points: int = 25,
    initial_mu: float | None = None,
) -> SimulationResult:
    """Simulate the modal Euler-Bernoulli element sliding over the ground (section 5.2).

    Parameters
    ----------
    params : EulerBernoulliParams
    velocity : float or callable
        Sliding velocity v0 (m/s) or profile v0(t).
    normal_force : float or callable, optional
        Applied normal force F_N (N) or profile F_N(t): a constant force, the rig's soft
        loading spring (vertical, fixed in direction; its work on the foreshortening and the
        end-face tilt gives the same generalised forces as the penalty contact).
    preload : float or callable, optional
        Instead of ``normal_force``: the preload distance y0 from the clamp to the ground (m)
        or profile y0(t) (penalty contact, Eq. 5.2). Give exactly one of the two.
    friction : friction law or RelaxedFriction
        ``mu(v_rel_mps, *, pressure_Pa=None, temperature_C=None)``; RelaxedFriction adds the
        state of Eq. 5.12. The law gets the nominal pressure F_N / (l w).
    t_end_s : float
        Simulated time, s.
    n_modes : int
        Number k of modes superposed.
    solver : SolverOptions, optional
        Implicit solver (high modes make the system stiff), tolerances (modal coordinates
        in m) and largest step; unset fields take
        :data:`~friction_model.dynamics.solver.EULER_BERNOULLI_SOLVER` (LSODA, rtol 1e-6,
        atol 1e-12).
    output_step_s : float, optional
        Output spacing (default t_end_s / 1000), s.
    v_reg_mps : float
        Velocity over which the friction direction is regularised, m/s.
    n_points : int
        Points along the beam in ``fields["w_m"]``.
    initial_mu : float, optional
        Initial mu_R of a relaxed law; default the steady value at t = 0.

    Returns
    -------
    SimulationResult
        ``data``: time_s, element (0), tip_deflection_mm, angle_deg (slope of the end),
        normal_force_N, friction_force_N, v_rel_mps, mu, contact, v0_mps, preload_mm;
        ``fields``: x_m (n_points,), w_m (n_t, n_points), q_m (n_t, n_modes).

    Warns
    -----
    UserWarning
        If d / l < 5 n_modes (Eq. 5.13).

    Raises
    ------
    ValueError
        For out-of-range options (before any integration).
    SimulationError
        If the integration fails.
    """
    if not isinstance(params, EulerBernoulliParams):
        raise TypeError(f"params must be EulerBernoulliParams, got {type(params).__name__}")
    k = _check_modes(n_modes)
    t_end = check_range("t_end_s", t_end_s, 1e-9, 1e4, unit="s")
    opts = EULER_BERNOULLI_SOLVER.resolve(solver, t_end_s=t_end)
    out_step = t_end / 1000 if output_step_s is None else output_step_s
    check_range("output_step_s", out_step, 1e-12, t_end, unit="s")
    v_reg = check_range("v_reg_mps", v_reg_mps, 1e-9, 1.0, unit="m/s")
    if not isinstance(n_points, (int, np.integer)) or n_points < 2:
        raise ValueError(f"n_points must be an integer in [2, inf), got n_points={n_points!r}")
    _warn_eq_5_13(params, k)
    beam = _ModalBeam(params, k, velocity, friction, normal_force, preload, v_reg)
    y_init = beam.initial_state(initial_mu)
    start = time.perf_counter()
    sol = solve_ivp(
        beam.rhs,
        (0.0, t_end),
        y_init,
        t_eval=output_times(t_end, out_step),
        jac=beam.jacobian(),
        **opts.solve_ivp_options(),
    )
    runtime = time.perf_counter() - start
    raise_if_failed(sol, "Euler-Bernoulli beam")
    data, fields = beam.tidy(sol, int(n_points))
    meta = {
        "model": f"Euler-Bernoulli beam, {k} modes",
        "params": asdict(params),
        "n_modes": k,
        "natural_frequencies_Hz": beam.omega / (2 * math.pi),
        "method": opts.method,
        "rtol": opts.rtol,
        "atol": opts.atol,
        "nfev": int(sol.nfev),
        "runtime_s": runtime,
        "equations": "Eq. 5.1-5.4, 5.12, 5.13 with the clamped-free modes",
    }
    logger.debug("Euler-Bernoulli: %d rhs evaluations in %.2f s", sol.nfev, runtime)
    return SimulationResult(data=data, fields=fields, meta=meta)


class _ModalBeam:
    """The modal equations of :func:`simulate_euler_bernoulli` with their loads.

    State ``y = [q (k), dq/dt (k), (mu_R)]``: modal coordinates q_k (m), their rates and,
    for a :class:`~friction_model.contact.laws.RelaxedFriction`, mu_R (Eq. 5.12).
    """

    def __init__(
        self,
        params: EulerBernoulliParams,
        k: int,
        velocity: float | Profile,
        friction: Any,
        normal_force: float | Profile | None,
        preload: float | Profile | None,
        v_reg: float,
    ) -> None:
        if (preload is None) == (normal_force is None):
            raise ValueError(
                "give exactly one of normal_force (applied force, N) and preload (distance, m), "
                f"got normal_force={normal_force!r}, preload={preload!r}"
            )
        self.params, self.k, self.v_reg = params, k, v_reg
        self.vel = _as_profile("velocity", velocity)
        self.pre = (
            _as_profile("preload", preload) if preload is not None else (lambda t: float("nan"))
        )
        self.load = _as_profile("normal_force", normal_force) if normal_force is not None else None
        self.fr = _FrictionSet("friction", friction, 1, allow_relaxed=True)
        self.relaxed = bool(self.fr.index.size)
        d = params.length_m
        self.d = d
        self.omega = _omegas(params, k)
        self.zeta = params.loss_factor / 2
        self.modal_mass = params.mass_per_length_kg_m * d
        xg, wg = np.polynomial.legendre.leggauss(_N_GAUSS)
        xg = 0.5 * (xg + 1.0) * d
        _, dwg = eb_mode_shapes(params, k, xg)
        self.geo = (dwg * (0.5 * d * wg)) @ dwg.T if params.axial_load else np.zeros((k, k))
        self.w_tip, self.dw_tip = (a[:, 0] for a in eb_mode_shapes(params, k, np.array([d])))
        self.e = float(params.contact_offset_m)
        self.c_n = float(params.contact_stiffness_N_m)
        self.area = params.element_length_m * params.width_m
        self.rhs = finite_rhs(
            self.rhs_batch, "Euler-Bernoulli beam", "non-finite modal accelerations"
        )

    def forces(self, q: np.ndarray, dq: np.ndarray, t: float) -> dict[str, np.ndarray]:
        """Contact and friction for a batch of modal states q, dq (..., k)."""
        v0, y0 = float(self.vel(t)), float(self.pre(t))
        fore = 0.5 * np.einsum("...j,jk,...k->...", q, self.geo, q)
        depth = self.d - fore + self.e * (q @ self.dw_tip)
        if self.load is None:
            u = self.params.free_length_m + depth - y0
            fn = self.c_n * np.maximum(u, 0.0)
        else:
            fn = np.full(np.shape(depth), max(float(self.load(t)), 0.0))
        v_rel = v0 - dq @ self.w_tip
        pressure = fn / self.area
        mu = self.fr.steady(np.abs(v_rel)[..., None], pressure[..., None])[..., 0]
        return {"fn": fn, "v_rel": v_rel, "pressure": pressure, "mu": mu, "v0": v0, "y0": y0}

    def rhs_batch(self, t: float, ys: np.ndarray) -> np.ndarray:
        """Modal accelerations (and dmu_R/dt) for a batch of states ``ys`` (n_batch, n)."""
        k = self.k
        q, dq = ys[:, :k], ys[:, k : 2 * k]
        f = self.forces(q, dq, t)
        mu = ys[:, 2 * k] if self.relaxed else f["mu"]
        ff = mu * f["fn"] * _sgn(f["v_rel"], self.v_reg)
        gen = ff[:, None] * self.w_tip - f["fn"][:, None] * (self.e * self.dw_tip - q @ self.geo)
        omega = self.omega
        ddq = gen / self.modal_mass - 2 * self.zeta * omega * dq - omega**2 * q
        parts = [dq, ddq]
        if self.relaxed:
            rate = self.fr.relax_rate(
                ys[:, 2 * k : 2 * k + 1], np.abs(f["v_rel"])[:, None], f["pressure"][:, None]
            )
            parts.append(rate)
        return np.concatenate(parts, axis=1)

    def jacobian(self) -> Callable[[float, np.ndarray], Any]:
        """Batched forward-difference Jacobian scaled by the static deflection."""
        k = self.k
        if self.load is None:
            amp = max(abs(self.d - self.pre(0.0)), 1e-6)
        else:
            amp = max(float(self.load(0.0)) / self.c_n, 1e-6)
        floor = np.concatenate(
            [
                np.full(k, 1e-3 * amp),
                np.full(k, 1e-3 * amp * self.omega[0]),
                np.full(int(self.relaxed), 1e-3),
            ]
        )
        return batched_fd_jacobian(self.rhs_batch, floor, "Euler-Bernoulli beam")

    def initial_state(self, initial_mu: float | None) -> np.ndarray:
        """Rest, with mu_R at ``initial_mu`` or the steady value at t = 0."""
        k = self.k
        y_init = np.zeros(2 * k + int(self.relaxed))
        if self.relaxed:
            f0 = self.forces(y_init[None, :k], y_init[None, k : 2 * k], 0.0)
            y_init[-1] = (
                f0["mu"][0] if initial_mu is None else check_range("initial_mu", initial_mu, 0, 10)
            )
        return y_init

    def tidy(self, sol: Any, n_points: int) -> tuple[pd.DataFrame, dict[str, np.ndarray]]:
        """Result table and fields at the output times of ``sol``."""
        k = self.k
        q, dq = sol.y[:k].T, sol.y[k : 2 * k].T
        rows = [self.forces(q[i : i + 1], dq[i : i + 1], float(t)) for i, t in enumerate(sol.t)]
        fn = np.array([r["fn"][0] for r in rows])
        v_rel = np.array([r["v_rel"][0] for r in rows])
        mu = sol.y[2 * k] if self.relaxed else np.array([r["mu"][0] for r in rows])
        friction_force = mu * fn * _sgn(v_rel, self.v_reg)
        x = np.linspace(0.0, self.d, n_points)
        w_x, _ = eb_mode_shapes(self.params, k, x)
        data = pd.DataFrame(
            {
                "time_s": sol.t,
                "element": 0,
                "tip_deflection_mm": q @ self.w_tip * 1e3,
                "angle_deg": np.degrees(np.arctan(q @ self.dw_tip)),
                "normal_force_N": fn,
                "friction_force_N": friction_force,
                "v_rel_mps": v_rel,
                "mu": mu,
                "contact": fn > 0,
                "v0_mps": [r["v0"] for r in rows],
                "preload_mm": np.array([r["y0"] for r in rows]) * 1e3,
            }
        )
        fields = {"x_m": x, "w_m": q @ w_x, "q_m": q, "time_s": sol.t}
        return data, fields
