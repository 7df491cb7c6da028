"""Speed and accuracy of the Timoshenko element integration.

Prints, measured in this run:
* the time (best of 3) of one 0.3 s simulation with 40 nodes (the validation case of
  thesis's tuned validation case: G3 element, E = 1.1 MPa, k_i = 1 ms, 2.5 bar through a
  preload distance, v0 ramped to 1 m/s in 10 ms, the axial terms as printed in Eq. 5.26,
  ``beam_column="thesis_literal"``: under the default Haringx beam-column this soft an
  element is past its buckling load) by :func:`simulate_timoshenko` (BDF with the analytic
  sparse Jacobian). It measures the integrator, not the physics;
* the same problem (same right-hand side, tolerances and output grid) by plain scipy BDF
  (the ``solve_ivp`` integrator class, stepped here so that it can be stopped) estimating a
  dense Jacobian by finite differences without sparsity information: its time over the
  first 10 ms (the ramp), the time ratio there, how far it gets within ``CAP_S`` seconds of
  wall time on the whole 0.3 s, and the largest difference of the tip deflection between the
  two over the span it covered.

The finite-difference Jacobian is accurate to ~1e-4 of the stiffness entries, but the
discretised beam is stiff (eigenvalues from ~1e2 to ~1e9 1/s), so once the sliding is steady
and the steps grow, Newton's iteration with that Jacobian stops converging and the reference
crawls with tiny steps.

Run: ``python benchmarks/bench_timoshenko.py``.
"""

import time

import numpy as np
from scipy.integrate import BDF

from friction_model import ArctanExponentialLaw
from friction_model.dynamics import SolverOptions, velocity_ramp
from friction_model.dynamics.timoshenko import (
    TimoshenkoParams,
    _TimoshenkoProblem,
    preload_for_normal_force,
    simulate_timoshenko,
)

T_END, N_OUT, RTOL, ATOL = 0.3, 3001, 1e-5, 1e-7
E = 1.1e6
law = ArctanExponentialLaw(k1=0.1697, k2=0.2256, k3=-0.5692, k4=50.0)  # Table 4.6 fit
area, height = 4.55e-3 * 80e-3, 6e-3
p = TimoshenkoParams(
    E_Pa=E,
    density_kg_m3=1150.0,
    kelvin_voigt_s=1e-3,
    contact_stiffness_N_m=E * area / height,
    n_nodes=40,
    beam_column="thesis_literal",
)
y0 = preload_for_normal_force(p, 2.5e5 * p.area_m2)
v0 = velocity_ramp(0.0, 1.0, 0.0, 0.01)


def best_of(fn, repeat=3):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def ours():
    return simulate_timoshenko(
        p,
        velocity=v0,
        preload=y0,
        friction=law,
        t_end_s=T_END,
        n_output=N_OUT,
        solver=SolverOptions(rtol=RTOL, atol=ATOL),
    )


def reference(t_end: float, cap_s: float):
    """Plain BDF with a finite-difference dense Jacobian; stops after ``cap_s`` seconds."""
    prob = _TimoshenkoProblem(p, velocity=v0, preload=lambda t: y0, friction=law)
    m, d = prob.m, p.height_m
    scale = np.concatenate([np.full(m, d), np.ones(m), np.ones(m), np.full(m, 1.0 / d)])
    solver = BDF(prob.fun, 0.0, prob.y_init, t_end, rtol=RTOL, atol=ATOL * scale)
    t_eval = np.linspace(0.0, T_END, N_OUT)
    t_eval = t_eval[t_eval <= t_end]
    tip = np.full(t_eval.size, np.nan)
    tip[0] = 0.0
    k = 1
    t0 = time.perf_counter()
    while solver.status == "running" and time.perf_counter() - t0 < cap_s:
        solver.step()
        k_end = int(np.searchsorted(t_eval, solver.t, side="right"))
        if k_end > k:
            tip[k:k_end] = solver.dense_output()(t_eval[k:k_end])[m - 1] * 1e3
            k = k_end
    return time.perf_counter() - t0, solver, tip, prob


CAP_S = 60.0
RAMP_S = 0.01
t_ours, res = best_of(ours)
tip_ours = res.data["tip_deflection_mm"].to_numpy()
t_ramp_ref, _, tip_ramp, _ = reference(RAMP_S, np.inf)
t_ramp_ours, res_ramp = best_of(
    lambda: simulate_timoshenko(
        p,
        velocity=v0,
        preload=y0,
        friction=law,
        t_end_s=RAMP_S,
        n_output=101,
        solver=SolverOptions(rtol=RTOL, atol=ATOL),
    )
)
t_ref, solver, tip_ref, prob = reference(T_END, CAP_S)
done = ~np.isnan(tip_ref)
print(f"Timoshenko element, {p.n_nodes} nodes ({prob.dim} states), rtol {RTOL}, atol {ATOL}")
print(
    f"  simulate_timoshenko, {T_END} s: {t_ours * 1e3:8.1f} ms "
    f"({res.meta['n_steps']} steps, {res.meta['nfev']} f-evals, {res.meta['njev']} Jacobians)"
)
print(
    f"  first {RAMP_S * 1e3:.0f} ms (ramp): ours {t_ramp_ours * 1e3:.1f} ms, "
    f"FD-Jacobian BDF {t_ramp_ref * 1e3:.1f} ms, ratio {t_ramp_ref / t_ramp_ours:.1f}x"
)
status = "finished" if solver.status == "finished" else f"reached t = {solver.t * 1e3:.2f} ms"
print(
    f"  FD-Jacobian BDF, {T_END} s: {status} after {t_ref:.1f} s wall "
    f"({solver.nfev} f-evals, {solver.njev} Jacobians, {solver.nlu} LU)"
)
rate = t_ref / max(solver.t, 1e-12) * T_END
print(
    f"  ratio FD-Jacobian / ours for the {T_END} s run: "
    + (
        f"{t_ref / t_ours:.0f}x"
        if solver.status == "finished"
        else f">= {t_ref / t_ours:.0f}x (at its average pace, {rate / t_ours:.0f}x)"
    )
)
print(
    f"  max |tip deflection difference| over the {tip_ref[done].size} common output samples "
    f"(t <= {res.data['time_s'].to_numpy()[done].max() * 1e3:.2f} ms): "
    f"{np.max(np.abs(tip_ours[done] - tip_ref[done])) * 1e3:.3g} um; "
    f"steady deflection {tip_ours[-1]:.3f} mm"
)
