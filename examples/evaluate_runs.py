"""Evaluate a folder of synthetic test-rig runs like a day of measurements on the ice.

Synthesises, with a known friction law mu(v), three tread-block specimens (G0, G3, G5, as
in thesis Fig. 4.21) measured in alternation (section 4.2.3) five times each at two sliding
velocities, plus one instationary run (constant acceleration then deceleration, section
4.4), evaluates the folder and prints the steady characteristic and the ambient table
(Table 4.2 style). Outputs and plots go to ``examples/out/evaluate/`` (``--out DIR``).

Run with ``python examples/evaluate_runs.py [--out DIR]``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
from _common import example_arguments

from friction_model.rig import evaluate_folder
from synthetic.rig import make_raw_run, write_run_csv

SAMPLE_RATE_HZ = 10_000  # the rig records at 50 kHz; 10 kHz keeps the example quick
# friction level of each specimen: the three-siped block grips best (thesis Fig. 4.9)
LEVEL = {"G0": 1.00, "G3": 1.12, "G5": 1.05}


def mu_law(v: np.ndarray, level: float = 1.0) -> np.ndarray:
    """Friction decreasing with sliding velocity (chapter 4.3), scaled per specimen."""
    return level * (0.10 + 0.22 * np.exp(-np.asarray(v) / 1.5))


def synthesise(folder: Path, rng: np.random.Generator) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for old in folder.glob("*.csv"):
        old.unlink()
    chamber_T, chamber_rh = -3.9, 72.4  # Table 4.2 averages
    k = 0
    for velocity in (1.0, 3.0):
        for run in range(1, 6):
            for specimen, level in LEVEL.items():  # specimens measured one after another
                k += 1
                phase = 2 * np.pi * k / 23  # the chamber cycles slowly (Fig. 4.6)
                # run-to-run scatter of the friction level (ice surface, wear): 1.5 %
                scatter = 1.0 + 0.015 * rng.standard_normal()
                df = make_raw_run(
                    lambda v, level=level * scatter: mu_law(v, level),
                    velocity_mps=velocity,
                    accel_mps2=8.0,
                    decel_mps2=8.0,
                    plateau_s=0.6,
                    sample_rate_Hz=SAMPLE_RATE_HZ,
                    normal_force_N=400.0,
                    temperature_C=chamber_T + 0.8 * np.sin(phase),
                    humidity_pct=chamber_rh + 5.0 * np.sin(phase + 0.5),
                    rng=rng,
                    metadata={
                        "specimen": specimen,
                        "condition": "T=-4C p=0.25MPa",
                        "run": run,
                        "nominal_area_mm2": 1600,
                    },
                )
                write_run_csv(df, folder / f"{specimen}_v{velocity:g}_run{run:02d}.csv")
    df = make_raw_run(
        lambda v: mu_law(v, LEVEL["G3"]),
        kind="instationary",
        velocity_mps=4.0,
        accel_mps2=3.0,
        decel_mps2=3.0,
        sample_rate_Hz=SAMPLE_RATE_HZ,
        normal_force_N=400.0,
        inertial_mass_kg=12.5,
        rng=rng,
        metadata={"specimen": "G3", "condition": "T=-4C p=0.25MPa", "run": 1},
    )
    write_run_csv(df, folder / "G3_instationary.csv")


def main(argv: list[str] | None = None) -> int:
    out = example_arguments(argv, __doc__, "evaluate").out
    runs = out / "runs"
    synthesise(runs, np.random.default_rng(2011))
    result = evaluate_folder(runs, out, progress=False)
    with pd.option_context("display.width", 120, "display.max_columns", 12):
        steady = result.steady[result.steady["row_type"] == "aggregate"]
        print("Steady friction characteristic (mean and std over 5 runs):")
        print(
            steady[
                [
                    "specimen",
                    "velocity_mps",
                    "mu_mean_method1",
                    "mu_mean_method2",
                    "mu_std_runs",
                    "n_runs",
                    "normal_pressure_Pa",
                ]
            ].to_string(index=False, float_format="{:.4f}".format)
        )
        truth = mu_law(steady["velocity_mps"], steady["specimen"].map(LEVEL))
        deviation = np.max(np.abs(steady["mu_mean_method1"] - truth))
        print(f"largest deviation of a mean from the true law: {deviation:.2e}")
        print("\nAmbient averages (Table 4.2 style):")
        ambient = result.ambient.set_index("specimen")[["temperature_C", "humidity_pct"]]
        print(ambient.T.to_string(float_format="{:.2f}".format))
        inst = result.instationary
        near = (inst["velocity_mps"] - 1.0).abs().lt(0.13) | (inst["velocity_mps"] - 3.0).abs().lt(
            0.13
        )
        print(f"\nInstationary characteristic of G3 ({len(inst)} bins), near 1 and 3 m/s:")
        columns = ["velocity_mps", "branch", "mu", "mu_std", "n"]
        print(inst.loc[near, columns].to_string(index=False, float_format="{:.4f}".format))
    for failure in result.failures:
        print(f"{failure.file}: {failure.message}", file=sys.stderr)
    print(f"\nwrote {len(result.outputs)} files to {out}")
    return 0 if result.ok else 1


if __name__ == "__main__":
    sys.exit(main())
