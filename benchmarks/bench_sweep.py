"""A sweep of 200 Timoshenko simulations (velocity x normal force x modulus).

Prints, measured in this run: the wall time of the sweep in this process (serial, the
baseline), through a local process pool with all cores, and through a local
``dask.distributed`` cluster when dask is installed; the speed-up of each against serial;
and that all three give the same table. Each run: a G3 element, 0.05 s, 40 nodes.

Run: ``python benchmarks/bench_sweep.py`` (about a minute on 2 cores).
"""

import importlib.util
import os
import time

import numpy as np

from friction_model.dynamics.sweep import parameter_grid, run_sweep, timoshenko_point

if __name__ == "__main__":
    grid = parameter_grid(
        velocity_mps=[1.0, 2.0, 3.0, 5.0, 7.0],
        pressure_bar=[1.5, 2.0, 2.5, 3.5, 5.0],
        # around the one rubber's E0 = 3.61 MPa; under the constant normal force a softer
        # element nears its Haringx buckling load (E < ~2.8 MPa at 2.5 bar)
        E_MPa=list(np.round(np.linspace(3.6, 6.0, 8), 3)),
    )
    print(f"{len(grid)} parameter sets, {os.cpu_count()} cores")
    timings = {}
    tables = {}
    for scheduler in ("serial", "processes", "dask"):
        if scheduler == "dask" and importlib.util.find_spec("distributed") is None:
            print("dask.distributed not installed: skipped")
            continue
        t0 = time.perf_counter()
        tables[scheduler] = run_sweep(timoshenko_point, grid, scheduler=scheduler, progress=False)
        timings[scheduler] = time.perf_counter() - t0
    for scheduler, seconds in timings.items():
        failed = int((tables[scheduler]["error"] != "").sum())
        print(
            f"  {scheduler:10s} {seconds:7.1f} s  ({seconds / len(grid) * 1e3:6.1f} ms per run, "
            f"speed-up vs serial {timings['serial'] / seconds:4.2f}x, {failed} failed)"
        )
    ref = tables["serial"]["tip_deflection_mm"].to_numpy()
    for scheduler, table in tables.items():
        diff = np.nanmax(np.abs(table["tip_deflection_mm"].to_numpy() - ref))
        print(f"  max |tip deflection - serial| ({scheduler}): {diff:.2e} mm")
    t = tables["serial"]
    print("\nsteady tip deflection (mm), E = 3.6 MPa, rows v (m/s), columns p (bar):")
    sub = t[np.isclose(t["E_MPa"], 3.6)]
    print(sub.pivot(index="velocity_mps", columns="pressure_bar", values="tip_deflection_mm")
          .round(3).to_string())
