"""Benchmark of the discrepancy workflow.

Default: the whole workflow (base model, four steady library candidates plus two user
candidates = six, multi-start fits, 5-fold held-out scores, 100 block-bootstrap resamples,
where-analysis) on a 504-row steady table with one hidden effect, serial and with two
worker processes; prints both times and their ratio. Target: < 60 s on 2 cores.

``--full``: the confusion matrix over hidden effects (six + none) x noise (1, 5, 10 %) x
effect size (0.5, 3, 10) x seeds, and recovery rates. Transient effects need
``friction_model.discrepancy.transient``; without it they are reported as skipped.
Combinations an effect cannot reach on the grid, or only with a strength beyond the
candidate's upper bound (``SteadyProblem.parameter_bounds``: humidity's layer would pass
the critical film, a viscous shear many times that of water), are reported as unreachable
and not run.

Effect sizes: steady, :func:`synthetic.effect_size.strength_for_effect_size` (the RMS
change the base's factor on mu cannot absorb); transient,
:func:`synthetic.effect_size.strength_for_transient_effect_size` (the RMS change of the
angle the run's two levels cannot absorb, on a record of 0.2 s before and after the step).
A transient effect is capped well below 3 x 5 % noise (it acts over at most the step
height, in a window after the step); at each noise level where size 3 is out of reach the
benchmark adds a cell at the effect's cap (:func:`synthetic.effect_size.transient_size_cap`),
labelled with its size. Per cell the benchmark prints the outcomes, and for the runs that
named the right effect the median fall of the held-out RMSE (weighted, as
``gap_before``/``gap_after``, and plain) and the error of the fitted parameter.

Run: ``python benchmarks/bench_discrepancy.py [--full] [--seeds N] [--workers N]
[--effects NAME ...] [--no-timing]``.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import time
from collections import Counter

import numpy as np

from friction_model.contact.effects import DRY_WET_EFFECTS, EFFECT_NAMES
from friction_model.discrepancy import (
    Candidate,
    ParameterSpec,
    SteadyProblem,
    register_candidate,
    run_discrepancy,
    unregister_candidate,
)
from friction_model.discrepancy import steady as steady_module
from synthetic.effect_size import (
    strength_for_effect_size,
    strength_for_transient_effect_size,
    transient_size_cap,
)
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


# record of the transient cells: 0.2 s before and after the velocity step (Fig. 5.7); a fixed
# length, so that a slow lag is not diluted by a longer record
TRANSIENT_RECORD = {"duration_s": 0.2}


def steady_bound(effect: str) -> float:
    """Upper bound of the steady candidate's strength on GRID (SteadyProblem.parameter_bounds:
    the library bound, or the physical limit of the table, e.g. humidity's critical film)."""
    if effect not in _BOUNDS:
        problem = SteadyProblem(make_steady_table(GRID, rng=0))
        _BOUNDS.update({e: problem.parameter_bounds(e)[0][1] for e in DRY_WET_EFFECTS})
    return _BOUNDS[effect]


_BOUNDS: dict[str, float] = {}


def _one_run(args: tuple) -> dict:
    """One table with `effect` hidden at `strength`, through the workflow (a worker task)."""
    from friction_model.discrepancy import TransientProblem
    from synthetic.measurements import make_transient_table

    effect, strength, noise, seed, transient = args
    spec = {} if effect == "none" else {effect: strength}
    if transient:
        table = make_transient_table(effects=spec, noise=noise, rng=7000 + seed,
                                     **TRANSIENT_RECORD)
        problem = TransientProblem.from_tables([table])
    else:
        table = make_steady_table(GRID, effects=spec, noise=noise, rng=5000 + seed)
        problem = SteadyProblem(table)
    r = run_discrepancy(problem, seed=seed, max_effects=1)
    outcome = (r.missing_effects[0] if r.missing_effects else
               "ambiguous" if r.verdict.startswith("ambiguous") else
               "unexplained" if r.verdict.startswith("unexplained") else "none")
    out = {"outcome": outcome, "fall": 1.0 - r.gap_after / r.gap_before,
           "fall_plain": 1.0 - r.gap["rmse_unweighted_after"] / r.gap["rmse_unweighted_before"],
           "param_error": np.nan}
    if effect != "none" and outcome == effect:
        truth = strength
        if effect == "friction_relaxation":  # the candidate fits tau in s
            from synthetic.measurements import TAU_REF_S

            truth = strength * TAU_REF_S
        out["param_error"] = r.fitted[effect]["parameters"][0]["value"] / truth - 1.0
    return out


def full(n_seeds: int, workers: int, only: list[str] | None = None) -> None:
    from concurrent.futures import ProcessPoolExecutor

    transient = importlib.util.find_spec("friction_model.discrepancy.transient") is not None
    effects = [e for e in ("none", "none (transient)", *EFFECT_NAMES)
               if not only or e.split()[0] in only]
    confusion: dict[tuple, Counter] = {}
    pool = ProcessPoolExecutor(workers) if workers > 1 else None
    t0 = time.perf_counter()
    try:
        # the cells the acceptance criteria name (5 % noise, size >= 3) first
        for noise in (0.05, 0.01, 0.10):
            for size in (3.0, 10.0, 0.5):
                for label in effects:
                    # "none" is the no-effect control on a steady table, "none (transient)"
                    # on a velocity-step record
                    effect = label.split()[0]
                    is_transient = label == "none (transient)" or (
                        effect in EFFECT_NAMES and effect not in DRY_WET_EFFECTS)
                    if effect == "none" and size != 3.0:
                        continue
                    if is_transient and not transient:
                        print(f"{effect}: skipped (friction_model.discrepancy.transient missing)")
                        continue
                    cell = size
                    try:
                        strength = (0.0 if effect == "none" else
                                    strength_for_transient_effect_size(
                                        effect, size, noise=noise, **TRANSIENT_RECORD)
                                    if is_transient else
                                    strength_for_effect_size(effect, size, noise=noise, grid=GRID))
                    except ValueError as exc:
                        print(f"{effect:24s} noise {noise:4.2f} size {size:4.1f}: unreachable "
                              f"({str(exc).split(': ')[-1]})", flush=True)
                        if not is_transient or size != 3.0:
                            continue
                        cap, strength = transient_size_cap(effect, **TRANSIENT_RECORD)
                        cell = round(cap / noise, 2)  # the cell at the effect's cap
                    if not is_transient and effect != "none" and strength > steady_bound(effect):
                        print(f"{label:24s} noise {noise:4.2f} size {size:4.1f}: unreachable "
                              f"within the candidate's bounds (needs strength {strength:.4g} > "
                              f"{steady_bound(effect):.4g})", flush=True)
                        continue
                    tasks = [(effect, strength, noise, seed, is_transient)
                             for seed in range(n_seeds)]
                    runs = list(pool.map(_one_run, tasks) if pool else map(_one_run, tasks))
                    counts = Counter(r["outcome"] for r in runs)
                    confusion[(label, noise, cell)] = counts
                    right = counts[effect]
                    wrong = sum(v for k, v in counts.items() if k in EFFECT_NAMES and k != effect)
                    named = [r for r in runs if r["outcome"] == effect]
                    extra = ""
                    if named and effect != "none":
                        fall = np.median([r["fall"] for r in named])
                        plain = np.median([r["fall_plain"] for r in named])
                        err = np.abs([r["param_error"] for r in named])
                        extra = (f"; when named: held-out RMSE falls {fall:.0%} (plain "
                                 f"{plain:.0%}), |param error| median {np.median(err):.1%} "
                                 f"max {np.max(err):.1%}")
                    print(f"{label:24s} noise {noise:4.2f} size {cell:4.2f} (strength "
                          f"{strength:.4g}): right {right}/{n_seeds}, wrong name {wrong}, "
                          f"outcomes {dict(counts)}{extra}", flush=True)
    finally:
        if pool:
            pool.shutdown()
    print(f"\n({time.perf_counter() - t0:.0f} s)")
    print("\nconfusion matrix at 5 % noise, size 3, transient effects at their cap "
          "(rows: hidden; columns: named)")
    cols = [*EFFECT_NAMES, "ambiguous", "unexplained", "none"]
    print(" " * 24 + " ".join(f"{c[:10]:>10s}" for c in cols))
    for effect in effects:
        counts = confusion.get((effect, 0.05, 3.0)) or next(
            (c for (e, n, _), c in confusion.items() if e == effect and n == 0.05), None)
        if counts is None:
            continue
        print(f"{effect:24s}" + " ".join(f"{counts[c]:10d}" for c in cols))
    rates = [
        counts[e] / n_seeds
        for (e, noise, size), counts in confusion.items()
        if not e.startswith("none") and noise == 0.05 and size >= 3.0
    ]
    wrong_total = sum(
        v for (e, _, _), counts in confusion.items() for k, v in counts.items()
        if k in EFFECT_NAMES and k != e
    )
    none_clean = all(c["none"] == n_seeds for (e, _, _), c in confusion.items()
                     if e.startswith("none"))
    if rates:
        print(f"recovery at 5 % noise, size >= 3: mean {np.mean(rates):.2f}, min {min(rates):.2f}"
              f" (target >= 0.95)")
    print(f"wrong names over the whole grid: {wrong_total} (target 0); no-effect control clean "
          f"at every noise: {none_clean}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="confusion matrix over the grid")
    parser.add_argument("--seeds", type=int, default=20, help="seeds per cell with --full")
    parser.add_argument("--workers", type=int, default=len(os.sched_getaffinity(0)),
                        help="processes for the seeds of a cell with --full")
    parser.add_argument("--no-timing", action="store_true", help="skip the timing part")
    parser.add_argument("--effects", nargs="+", choices=["none", *EFFECT_NAMES],
                        help="with --full: only these hidden effects (default: all)")
    args = parser.parse_args()
    if not args.no_timing:
        timing()
    if args.full:
        full(args.seeds, args.workers, args.effects)


if __name__ == "__main__":
    main()
