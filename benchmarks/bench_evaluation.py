"""Benchmark: evaluating raw test-rig runs, friction_model.rig vs plain pandas.

Synthesises ten steady runs of 5 s at 50 kHz (250 000 rows each, like the rig records,
thesis section 4.2.3), writes them as CSV to a temporary folder, then times in the same
process

* ``friction_model.rig.evaluate_runs`` (C-engine read after the metadata lines,
  cumulative-sum filters, numpy plateau search), and
* a straightforward pandas implementation written below (``read_csv(comment="#")``, rolling
  means, ``groupby`` over contiguous spans, ``groupby`` aggregation),

and prints the time per run of both, their ratio and the largest difference of the friction
coefficients they find. Run with ``python benchmarks/bench_evaluation.py``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # running from a source checkout without installing
    sys.path.insert(0, str(ROOT))

from friction_model.rig import evaluate_runs  # noqa: E402
from synthetic.rig import make_raw_run, write_run_csv  # noqa: E402

# the same detection parameters as the defaults of friction_model.rig.WindowParams
SMOOTHING_S = 0.02
REL_TOL = 0.02
ABS_TOL_MPS = 0.01
MAX_ACCEL_MPS2 = 0.5
SETTLE_S = 0.05
MIN_VELOCITY_MPS = 0.02


def pandas_evaluate_file(path: Path) -> dict:
    """Evaluate one run the plain pandas way."""
    meta = {}
    with open(path) as fh:
        for line in fh:
            if not line.startswith("#"):
                break
            key, value = line[1:].split(":", 1)
            meta[key.strip()] = value.strip()
    df = pd.read_csv(path, comment="#")
    if df.isna().any().any():
        raise ValueError(f"{path}: NaN values")
    if not df["time_s"].is_monotonic_increasing:
        raise ValueError(f"{path}: time not increasing")
    dt = df["time_s"].diff().median()
    n = round(SMOOTHING_S / dt) // 2 * 2 + 1
    half = n // 2
    v_s = df["velocity_mps"].rolling(n, center=True, min_periods=1).mean()
    t = df["time_s"]
    a_s = (v_s.shift(-half) - v_s.shift(half)) / (t.shift(-half) - t.shift(half))
    quiet = (a_s.abs() <= MAX_ACCEL_MPS2) & (v_s.abs() >= MIN_VELOCITY_MPS)

    def longest_span(mask: pd.Series) -> pd.Index:
        span_id = (mask != mask.shift()).cumsum()
        sizes = mask[mask].groupby(span_id[mask]).size()
        return mask.index[span_id == sizes.idxmax()]

    v_p = v_s.loc[longest_span(quiet)].median()
    band = quiet & ((v_s - v_p).abs() <= max(REL_TOL * abs(v_p), ABS_TOL_MPS))
    span = longest_span(band)
    t0 = df.loc[span[0], "time_s"] + SETTLE_S
    t1 = df.loc[span[-1], "time_s"] - SETTLE_S
    win = df[(df["time_s"] >= t0) & (df["time_s"] <= t1)]
    if (win["normal_force_N"] <= 0).any():
        raise ValueError(f"{path}: normal force <= 0 in the window")
    mu = win["friction_force_N"] / win["normal_force_N"]
    return {
        "file": str(path),
        "specimen": meta.get("specimen", ""),
        "condition": meta.get("condition", ""),
        "velocity_mps": win["velocity_mps"].mean(),
        "mu_mean_method1": mu.mean(),
        "mu_mean_method2": win["friction_force_N"].mean() / win["normal_force_N"].mean(),
        "mu_std_t": mu.std(),
        "temperature_C": df["temperature_C"].mean(),
        "humidity_pct": df["humidity_pct"].mean(),
    }


def pandas_evaluate(paths: list[Path]) -> tuple[pd.DataFrame, pd.DataFrame]:
    runs = pd.DataFrame([pandas_evaluate_file(p) for p in paths])
    agg = runs.groupby(["specimen", "condition"]).agg(
        velocity_mps=("velocity_mps", "mean"),
        mu_mean=("mu_mean_method1", "mean"),
        mu_std_runs=("mu_mean_method1", "std"),
        n_runs=("mu_mean_method1", "size"),
    )
    return runs, agg


def make_runs(folder: Path, n_runs: int, seconds: float, rate: float) -> list[Path]:
    velocity, accel, rest, lift = 0.5, 5.0, 0.1, 0.05
    plateau = seconds - 2 * rest - 2 * velocity / accel - lift
    paths = []
    for i in range(n_runs):
        df = make_raw_run(
            lambda v, i=i: np.full_like(v, 0.2 + 0.005 * i),
            velocity_mps=velocity,
            accel_mps2=accel,
            decel_mps2=accel,
            plateau_s=plateau,
            sample_rate_Hz=rate,
            rest_s=rest,
            lift_off_s=lift,
            rng=i,
            metadata={"specimen": f"S{i % 2 + 1}", "condition": "bench", "run": i // 2 + 1},
        )
        path = folder / f"run_{i + 1:02d}.csv"
        write_run_csv(df, path)
        paths.append(path)
    return paths


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--rate", type=float, default=50_000)
    parser.add_argument("--repeat", type=int, default=3, help="timed repetitions (median)")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="bench_evaluation_") as tmp:
        t = time.perf_counter()
        paths = make_runs(Path(tmp), args.runs, args.seconds, args.rate)
        rows = len(pd.read_csv(paths[0], comment="#"))
        print(
            f"synthesised {len(paths)} runs x {rows} rows ({args.seconds:g} s at "
            f"{args.rate:g} Hz) in {time.perf_counter() - t:.1f} s"
        )
        ours, base = [], []
        for _ in range(args.repeat):
            t = time.perf_counter()
            result = evaluate_runs(paths, progress=False)
            ours.append(time.perf_counter() - t)
            t = time.perf_counter()
            runs, _ = pandas_evaluate(paths)
            base.append(time.perf_counter() - t)
        assert result.ok, result.failures
        ours_run = statistics.median(ours) / len(paths)
        base_run = statistics.median(base) / len(paths)
        mine = result.steady[result.steady["row_type"] == "run"]
        diff = np.max(np.abs(mine["mu_mean_method1"].to_numpy() - runs["mu_mean_method1"]))
        print(f"friction_model.rig           : {1e3 * ours_run:8.1f} ms per run")
        print(f"plain pandas             : {1e3 * base_run:8.1f} ms per run")
        print(f"speed-up (pandas / ours) : {base_run / ours_run:8.2f}x")
        print(f"largest |mu difference|  : {diff:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
