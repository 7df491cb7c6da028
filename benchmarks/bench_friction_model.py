"""Speed and accuracy of the dry/wet friction model.

Prints, measured in this run:
* the time to evaluate the 28 Table 4.6 conditions at once (vectorised march) against
  evaluating them one by one (the baseline), and the ratio;
* the calibration on Table 4.6: its wall time and the RMSE of each curve.

Run: ``python benchmarks/bench_friction_model.py``.
"""

import time

from friction_model import (
    Conditions,
    DryWetParameters,
    calibrate_table_4_6,
    evaluate_on_table_4_6,
    friction_table,
    reference_block,
    table_4_6_targets,
)


def best_of(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


g3 = reference_block("G3")
targets = table_4_6_targets()
conds = [
    Conditions(r.velocity_mps, r.pressure_Pa, r.temperature_C, humidity_pct=r.humidity_pct)
    for r in targets.itertuples()
]
params = DryWetParameters()
t_vec = best_of(lambda: friction_table(g3, targets, params))
t_loop = best_of(lambda: [friction_table(g3, [c], params) for c in conds])
print(f"28 conditions, G3, {params.n_cells} cells/element:")
print(f"  vectorised march      {t_vec * 1e3:8.1f} ms")
print(f"  one by one (baseline) {t_loop * 1e3:8.1f} ms")
print(f"  speed-up              {t_loop / t_vec:8.1f} x")

_, rmse = evaluate_on_table_4_6(params)
print("\nShipped default parameters, RMSE of mu on Table 4.6:")
for name, value in rmse.items():
    print(f"  {name:22s} {value:.4f}")

t0 = time.perf_counter()
result = calibrate_table_4_6(n_starts=2, rng=5)
elapsed = time.perf_counter() - t0
print(f"\nCalibration (2 starts, {result.cost_evaluations} model evaluations): {elapsed:.1f} s")
for name, value in result.rmse.items():
    target = "<= 0.015" if name != "all" else ""
    print(f"  {name:22s} {value:.4f} {target}")
