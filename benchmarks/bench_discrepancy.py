"""Benchmark of the discrepancy workflow.

Default: the whole workflow (base model, four steady library candidates plus two user
candidates = six, multi-start fits, 5-fold held-out scores, 100 block-bootstrap resamples,
where-analysis) on a 504-row steady table with one hidden effect, serial and with two
worker processes; prints both times and their ratio. Target: < 60 s on 2 cores.

``--full``: the confusion matrix over hidden effects (six + none) x noise (1, 5, 10 %) x
effect size (0.5, 3, 10) x seeds, and recovery rates. Transient effects need
``friction_model.discrepancy.transient``; without it they are reported as skipped.
Combinations an effect cannot reach on the grid are reported as unreachable.

Run: ``python benchmarks/bench_discrepancy.py [--full] [--seeds N]``.
"""

from __future__ import annotations

import argparse
import importlib.util
import time
from collections import Counter

import numpy as np

from friction_model.discrepancy import (
    Candidate,
    ParameterSpec,
    SteadyProblem,
    register_candidate,
    run_discrepancy,
    unregister_candidate,
)
from friction_model.discrepancy import steady as steady_module
from friction_model.effects import DRY_WET_EFFECTS, EFFECT_NAMES
from synthetic.effect_size import strength_for_effect_size
from synthetic.measurements import SteadyGrid, make_steady_table

GRID_500 = SteadyGrid(
    velocities_mps=(0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0), temperatures_C=(-6.0, -3.0, -1.5)
)
GRID = SteadyGrid(temperatures_C=(-6.0, -3.0, -1.5))


def _user_candidates() -> list[str]:
    """Two user candidates (apply on the prediction), to fit six candidates in all."""
    specs = [
        (
            "pressure_softening",
            ParameterSpec("per_bar", "1/bar", 0.0, -0.1, 0.0),
            lambda pr, mu, p: mu * (1.0 + p[0] * (pr.covariates["pressure_bar"] - 2.5)),
        ),
        (
            "velocity_offset",
            ParameterSpec("mu_per_mps", "s/m", 0.0, -0.05, 0.05),
            lambda pr, mu, p: mu + p[0] * (pr.covariates["velocity_mps"] - 2.0),
        ),
    ]
    for name, spec, apply in specs:
        cand = Candidate(name, (spec,), "benchmark user candidate", frozenset({"steady"}), "-")
        register_candidate(cand, apply=apply, replace=True)
    return [s[0] for s in specs]


def timing() -> None:
    names = _user_candidates()
    try:
        s = strength_for_effect_size("ice_preheating", 3.0, noise=0.05, grid=GRID_500)
        table = make_steady_table(GRID_500, effects={"ice_preheating": s}, rng=1)
        times = {}
        for workers in (1, 2):
            steady_module._CACHE.clear()  # every run computes its candidate curves
            t0 = time.perf_counter()
            result = run_discrepancy(SteadyProblem(table), workers=workers, seed=0)
            times[workers] = time.perf_counter() - t0
            print(
                f"{len(table)} rows, 6 candidates, workers={workers}: "
                f"{times[workers]:.1f} s -> {result.verdict}"
            )
        print(f"serial / parallel: {times[1] / times[2]:.2f}x (target < 60 s)")
    finally:
        for name in names:
            unregister_candidate(name)


def transient_strength(effect: str, size: float, noise: float) -> float:
    """Strength whose RMS change of the angle is `size` x the noise (noise relative to the
    angle before the step, as in make_transient_table)."""
    from scipy.optimize import brentq

    from synthetic.measurements import make_transient_table

    base = make_transient_table(noise=0.0)
    scale = abs(float(base.angle_deg.iloc[0]))

    def excess(strength: float) -> float:
        eff = make_transient_table(effects={effect: strength}, noise=0.0)
        rms = float(np.sqrt(np.mean((eff.angle_deg - base.angle_deg) ** 2))) / scale
        return rms / noise - size

    return brentq(excess, 1e-4, 5.0, xtol=1e-4)


def _transient_counts(effect: str, noise: float, size: float, n_seeds: int) -> Counter:
    """Outcomes of the workflow on transient tables with `effect` hidden."""
    from friction_model.discrepancy import TransientProblem
    from synthetic.measurements import make_transient_table

    counts: Counter = Counter()
    try:
        strength = transient_strength(effect, size, noise)
    except ValueError:
        counts["unreachable"] += n_seeds
        return counts
    for seed in range(n_seeds):
        table = make_transient_table(effects={effect: strength}, noise=noise, rng=7000 + seed)
        r = run_discrepancy(TransientProblem.from_tables([table]), seed=seed, max_effects=1)
        key = (r.missing_effects[0] if r.missing_effects else
               "ambiguous" if r.verdict.startswith("ambiguous") else
               "unexplained" if r.verdict.startswith("unexplained") else "none")
        counts[key] += 1
    return counts


def full(n_seeds: int) -> None:
    transient = importlib.util.find_spec("friction_model.discrepancy.transient") is not None
    effects = ["none", *EFFECT_NAMES]
    confusion: dict[tuple, Counter] = {}
    for noise in (0.01, 0.05, 0.10):
        for size in (0.5, 3.0, 10.0):
            for effect in effects:
                if effect != "none" and effect not in DRY_WET_EFFECTS:
                    if not transient:
                        print(f"{effect}: skipped (friction_model.discrepancy.transient missing)")
                        continue
                    counts = _transient_counts(effect, noise, size, n_seeds)
                    confusion[(effect, noise, size)] = counts
                    print(f"{effect:24s} noise {noise:4.2f} size {size:4.1f}: right "
                          f"{counts[effect]}/{n_seeds}, outcomes {dict(counts)}", flush=True)
                    continue
                if effect == "none" and size != 3.0:
                    continue
                try:
                    spec = (
                        {}
                        if effect == "none"
                        else {
                            effect: strength_for_effect_size(effect, size, noise=noise, grid=GRID)
                        }
                    )
                except ValueError as exc:
                    print(f"{effect} noise {noise:g} size {size:g}: unreachable ({exc})")
                    continue
                counts = Counter()
                for seed in range(n_seeds):
                    table = make_steady_table(GRID, effects=spec, noise=noise, rng=5000 + seed)
                    r = run_discrepancy(SteadyProblem(table), seed=seed, max_effects=1)
                    if r.missing_effects:
                        counts[r.missing_effects[0]] += 1
                    elif r.verdict.startswith("ambiguous"):
                        counts["ambiguous"] += 1
                    elif r.verdict.startswith("unexplained"):
                        counts["unexplained"] += 1
                    else:
                        counts["none"] += 1
                confusion[(effect, noise, size)] = counts
                right = counts[effect] if effect != "none" else counts["none"]
                wrong = sum(v for k, v in counts.items() if k in EFFECT_NAMES and k != effect)
                print(
                    f"{effect:24s} noise {noise:4.2f} size {size:4.1f}: right {right}/{n_seeds}"
                    f", wrong name {wrong}, outcomes {dict(counts)}",
                    flush=True,
                )
    print("\nconfusion matrix at 5 % noise, size 3 (rows: hidden; columns: named)")
    cols = [*EFFECT_NAMES, "ambiguous", "unexplained", "none"]
    print(" " * 24 + " ".join(f"{c[:10]:>10s}" for c in cols))
    for effect in effects:
        counts = confusion.get((effect, 0.05, 3.0))
        if counts is None:
            continue
        print(f"{effect:24s}" + " ".join(f"{counts[c]:10d}" for c in cols))
    rates = [
        counts[e] / n_seeds
        for (e, noise, size), counts in confusion.items()
        if e != "none" and noise == 0.05 and size >= 3.0
    ]
    if rates:
        print(f"recovery at 5 % noise, size >= 3: mean {np.mean(rates):.2f}, min {min(rates):.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="confusion matrix over the grid")
    parser.add_argument("--seeds", type=int, default=20, help="seeds per cell with --full")
    args = parser.parse_args()
    timing()
    if args.full:
        full(args.seeds)


if __name__ == "__main__":
    main()
