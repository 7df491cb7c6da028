"""The discrepancy workflow: find the disagreement, name the missing effect, show the gap shrink.

Steps: hold out whole groups (conditions or runs); say where model and data
disagree (:mod:`._where`); fit every candidate (multi-start, :mod:`._fit`) and score it on
held-out data (RSS, AICc, BIC); name a winner only when every criterion holds; add it and
repeat; report the held-out gap before and after.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import logging
import math
import multiprocessing
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import scipy.stats

from friction_model.discrepancy._fit import (
    Evaluator,
    ModelScores,
    parameter_bounds,
    score_model,
    score_trends,
)
from friction_model.discrepancy._problem import (
    Candidate,
    Problem,
    candidate_apply,
    get_candidate,
)
from friction_model.discrepancy._problem import (
    candidates as registered_candidates,
)
from friction_model.discrepancy._scoring import block_bootstrap_weights, group_folds
from friction_model.discrepancy._where import residual_spectrum, where_analysis
from friction_model.model_selection import aicc_known_sigma, bic_known_sigma

__all__ = [
    "ADEQUACY_LEVEL",
    "AICC_MARGIN",
    "BIC_IMPROVEMENT",
    "BOOTSTRAP_WIN_SHARE",
    "CONFIDENCE_LEVEL",
    "DiscrepancyResult",
    "run_discrepancy",
]

logger = logging.getLogger(__name__)

#: A winner must improve the held-out BIC of the current model by at least this much
#: ("very strong" evidence on the Kass-Raftery scale).
BIC_IMPROVEMENT = 10.0
#: ... and beat the runner-up (and every generic trend) by at least this held-out dAICc.
AICC_MARGIN = 2.0
#: ... and win at least this share of the block-bootstrap resamples.
BOOTSTRAP_WIN_SHARE = 0.8
#: Level of the bootstrap confidence interval that must exclude the null.
CONFIDENCE_LEVEL = 0.95
#: A further effect (after the first) is kept only if the model with every named effect
#: fits to the noise: its chi-square (sigma known, as in the criteria above) does not
#: exceed the (1 - ADEQUACY_LEVEL) quantile of chi2(n - k). At 0.01 a complete two-effect
#: explanation is turned down in 1 % of data sets (then reported as unexplained residual).
ADEQUACY_LEVEL = 0.01


@dataclass
class DiscrepancyResult:
    """Outcome of :func:`run_discrepancy`.

    Attributes
    ----------
    verdict : str
        One line: ``"missing effect: NAME"``, ``"missing effects: A, B"``,
        ``"ambiguous: A or B (measure X to tell them apart)"``, ``"no missing effect
        found"`` or ``"unexplained residual: structured residual against COVARIATE"``
        (after named effects, the last two parts are joined with ``"; "``).
    missing_effects : list of str
        Names in the order found (empty when none).
    gap_before, gap_after : float
        Held-out RMSE of the base model and of the model with the missing effects,
        weighted by 1/sigma^2 (:func:`weighted_rmse`; the plain RMSE is in ``gap``).
    where : dict
        Residual structure before and after (``before``, ``after``; ``spectrum_before``,
        ``spectrum_after`` for transients), see :func:`where_analysis`.
    candidates : list of dict
        Every model scored in every round with its parameters, intervals and scores.
    rounds : list of dict
        The decision of each round and the criteria behind it.
    gap : dict
        Reduced chi-square before/after and the gap per condition (group).
    fitted : dict
        Parameters of the missing effects with their intervals.
    """

    kind: str
    n: int
    verdict: str
    missing_effects: list[str]
    gap_before: float
    gap_after: float
    where: dict
    candidates: list[dict]
    rounds: list[dict]
    gap: dict
    fitted: dict
    not_revealable: list[str]
    giveaway: str | None
    y: np.ndarray = field(repr=False)
    sigma: np.ndarray = field(repr=False)
    groups: np.ndarray = field(repr=False)
    covariates: pd.DataFrame = field(repr=False)
    prediction_before: np.ndarray = field(repr=False)
    prediction_after: np.ndarray = field(repr=False)

    def to_dict(self) -> dict[str, Any]:
        """The JSON content of ``result.json``."""
        return {
            "verdict": self.verdict,
            "missing_effects": list(self.missing_effects),
            "gap_before": self.gap_before,
            "gap_after": self.gap_after,
            "where": self.where,
            "candidates": self.candidates,
            "kind": self.kind,
            "n": self.n,
            "rounds": self.rounds,
            "gap": self.gap,
            "fitted": self.fitted,
            "not_revealable": self.not_revealable,
            "giveaway_covariate": self.giveaway,
            "criteria": {
                "bic_improvement": BIC_IMPROVEMENT,
                "aicc_margin": AICC_MARGIN,
                "bootstrap_win_share": BOOTSTRAP_WIN_SHARE,
                "confidence_level": CONFIDENCE_LEVEL,
                "adequacy_level": ADEQUACY_LEVEL,
            },
        }


def _resolve(problem: Problem, chosen: Sequence[str | Candidate] | None) -> tuple[list, list]:
    """Candidates to fit and library effects this data cannot reveal."""
    native = set(problem.effect_names)
    if chosen is None:
        pool = [c for c in registered_candidates() if problem.kind in c.kinds or c.name in native]
    else:
        pool = [c if isinstance(c, Candidate) else get_candidate(str(c)) for c in chosen]
    usable, skipped = [], []
    for c in pool:
        if c.name in native or candidate_apply(c.name) is not None:
            usable.append(c)
        else:
            skipped.append(c.name)
    for c in registered_candidates():
        if c.name not in native and candidate_apply(c.name) is None and c.name not in skipped:
            skipped.append(c.name)
    return usable, skipped


def _check_problem(problem: Problem) -> None:
    y = np.asarray(problem.y, float)
    n = y.size
    for name in ("sigma", "groups"):
        arr = np.asarray(getattr(problem, name))
        if arr.shape != (n,):
            raise ValueError(f"problem.{name} must have shape ({n},), got {arr.shape}")
    sigma = np.asarray(problem.sigma, float)
    if not np.all(np.isfinite(y)):
        raise ValueError("problem.y must be finite")
    if not np.all(np.isfinite(sigma)) or np.any(sigma <= 0):
        raise ValueError("problem.sigma must be finite and > 0")
    if len(problem.covariates) != n:
        raise ValueError(f"problem.covariates must have {n} rows, got {len(problem.covariates)}")
    if np.unique(np.asarray(problem.groups)).size < 2:
        raise ValueError("problem.groups must hold at least two groups (hold-out by group)")


def _check_null(problem: Problem, cand: Candidate) -> None:
    apply = candidate_apply(cand.name)
    if apply is None or cand.name in problem.effect_names:
        return
    pred = np.asarray(problem.predict(problem.fit_base(np.ones(len(problem.y), bool), {}), {}))
    back = np.asarray(apply(problem, pred.copy(), cand.null), float)
    if not np.array_equal(back, pred):
        raise ValueError(
            f"candidate {cand.name!r} does not reduce to the model without it at its null "
            f"{cand.null} (largest change {np.max(np.abs(back - pred)):.3g})"
        )


_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


@contextlib.contextmanager
def _worker_pool(n: int):
    """Fresh (spawned) worker processes with one BLAS thread each.

    The march multiplies (rows x cells) matrices; with a multi-threaded BLAS in each of
    several processes the threads fight for the cores, which made two workers slower than
    one. Spawned workers read the thread limits from the environment when they start.
    """
    saved = {k: os.environ.get(k) for k in _THREAD_VARS}
    os.environ.update({k: "1" for k in _THREAD_VARS})
    try:
        ctx = multiprocessing.get_context("spawn")
        with concurrent.futures.ProcessPoolExecutor(max_workers=n, mp_context=ctx) as ex:
            yield ex
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _score_candidate_job(
    problem: Problem,
    accepted: dict,
    candidate: Candidate,
    k: int,
    folds: np.ndarray,
    boot: np.ndarray,
) -> ModelScores:
    """Top-level (picklable) job: score one problem-native candidate."""
    ev = Evaluator(problem, accepted, candidate, {})
    return score_model(ev, candidate.name, "candidate", k, folds, boot)


def _score_candidates(
    problem: Problem,
    accepted: dict,
    pool: list[Candidate],
    applies: dict,
    folds: np.ndarray,
    boot: np.ndarray,
    workers: int,
) -> list[ModelScores]:
    k_acc = problem.n_base + sum(len(p) for p in accepted.values())
    native_only = all(n in problem.effect_names for n in accepted)
    jobs = [c for c in pool if c.name in problem.effect_names and native_only]
    serial = [c for c in pool if c not in jobs]
    results: dict[str, ModelScores] = {}

    def run_serial(todo: list[Candidate]) -> None:
        for c in todo:
            ev = Evaluator(problem, accepted, c, applies)
            results[c.name] = score_model(
                ev, c.name, "candidate", k_acc + len(c.parameters), folds, boot
            )

    if workers > 1 and len(jobs) > 1:
        with _worker_pool(min(workers, len(jobs))) as ex:
            futures = {
                c.name: ex.submit(
                    _score_candidate_job,
                    problem,
                    accepted,
                    c,
                    k_acc + len(c.parameters),
                    folds,
                    boot,
                )
                for c in jobs
            }
            run_serial(serial)  # user candidates in this process meanwhile
            for name, fut in futures.items():
                results[name] = fut.result()
    else:
        run_serial(pool)
    return [results[c.name] for c in pool]


def _interval(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    tail = (1.0 - CONFIDENCE_LEVEL) / 2.0 * 100.0
    return np.percentile(theta, tail, axis=0), np.percentile(theta, 100.0 - tail, axis=0)


def _measure_text(a: Candidate, b: Candidate) -> str:
    return (
        f"measure {a.distinguishing_measurement}, and {b.distinguishing_measurement}, "
        "to tell them apart"
    )


def _decide(
    problem: Problem,
    current: ModelScores,
    fits: list[ModelScores],
    trends: list[ModelScores],
    pool: dict[str, Candidate],
    round_no: int,
) -> tuple[dict, list[dict]]:
    """Score table of one round and its decision."""
    rows = _score_rows(problem, current, [current, *fits, *trends], pool, round_no)
    phys = sorted([r for r in rows if r["kind"] == "candidate"], key=lambda r: r["aicc"])
    best_trend = _best_trend(rows)
    nothing = _nothing_named(best_trend)
    if not phys:
        return nothing, rows
    best = phys[0]
    runner = phys[1] if len(phys) > 1 else None
    criteria = _criteria(best, runner, best_trend)
    best["criteria"] = criteria
    decision: dict[str, Any] = {"best": best["name"], "criteria": criteria}
    if not criteria["bic_improvement"]:
        decision.update(nothing)
    elif best_trend is not None and best_trend["aicc"] <= best["aicc"] - AICC_MARGIN:
        decision.update(nothing)
    elif not criteria["beats_runner_up"]:
        decision.update(_ambiguous(best["name"], runner["name"], pool))
    elif not criteria["beats_trends"]:
        decision.update(nothing)
    elif not criteria["bootstrap_wins"]:
        others = {r["name"]: r["bootstrap_wins"] for r in phys[1:]}
        other = max(others, key=others.get) if others else None
        if other is not None and best["bootstrap_wins"] + others[other] >= BOOTSTRAP_WIN_SHARE:
            decision.update(_ambiguous(best["name"], other, pool))
        else:
            decision.update(nothing)
    elif not (criteria["inside_bounds"] and criteria["interval_excludes_null"]):
        decision.update(nothing)
    else:
        decision.update({"outcome": "named", "text": f"missing effect: {best['name']}"})
    return decision, rows


def _score_rows(
    problem: Problem,
    current: ModelScores,
    models: list[ModelScores],
    pool: dict[str, Candidate],
    round_no: int,
) -> list[dict]:
    """One row per model: held-out RSS, chi-square, AICc, BIC, their gains over the current
    model, the share of bootstrap resamples it wins and (candidates) its parameters."""
    n = len(problem.y)
    y = np.asarray(problem.y, float)
    crit = {
        m.name: (aicc_known_sigma(m.chi2_cv, m.k, n), bic_known_sigma(m.chi2_cv, m.k, n))
        for m in models
    }
    base_aicc, base_bic = crit[current.name]
    # bootstrap: the model with the lowest in-sample BIC of each resample wins it
    boot_bic = np.column_stack([m.boot_chi2 + m.k * math.log(n) for m in models])
    winners = np.argmin(boot_bic, axis=1)
    wins = {m.name: float(np.mean(winners == i)) for i, m in enumerate(models)}
    rows = []
    for m in models:
        a, b = crit[m.name]
        entry: dict[str, Any] = {
            "round": round_no,
            "name": m.name,
            "kind": m.kind,
            "k": m.k,
            "rss_heldout": float(np.sum((y - m.cv_prediction) ** 2)),
            "chi2_heldout": m.chi2_cv,
            "chi2_fit": m.full.chi2,
            "aicc": a,
            "bic": b,
            "delta_bic": base_bic - b,
            "delta_aicc": base_aicc - a,
            "bootstrap_wins": wins[m.name],
            "parameters": [],
        }
        if m.kind == "candidate":
            entry["parameters"] = _parameter_rows(problem, pool[m.name], m)
        if m.kind == "trend":
            entry["covariate"] = m.extra["covariate"]
        rows.append(entry)
    return rows


def _parameter_rows(problem: Problem, cand: Candidate, scores: ModelScores) -> list[dict]:
    """Fitted value, bootstrap interval, null and bounds of each parameter of a candidate."""
    lo, hi = _interval(scores.boot_theta)
    bounds = parameter_bounds(problem, cand)
    return [
        {
            "name": spec.name,
            "unit": spec.unit,
            "value": scores.full.theta[j],
            "ci_lower": float(lo[j]),
            "ci_upper": float(hi[j]),
            "null": spec.null,
            "lower": bounds[j][0],
            "upper": bounds[j][1],
        }
        for j, spec in enumerate(cand.parameters)
    ]


def _criteria(best: dict, runner: dict | None, best_trend: dict | None) -> dict[str, bool]:
    """The criteria a candidate must meet to be named (see :func:`run_discrepancy`)."""
    return {
        "bic_improvement": best["delta_bic"] >= BIC_IMPROVEMENT,
        "beats_runner_up": runner is None or runner["aicc"] - best["aicc"] >= AICC_MARGIN,
        "beats_trends": best_trend is None or best_trend["aicc"] - best["aicc"] >= AICC_MARGIN,
        "inside_bounds": all(
            p["lower"] + 1e-3 * (p["upper"] - p["lower"])
            < p["value"]
            < p["upper"] - 1e-3 * (p["upper"] - p["lower"])
            for p in best["parameters"]
        ),
        "interval_excludes_null": any(
            not p["ci_lower"] <= p["null"] <= p["ci_upper"] for p in best["parameters"]
        ),
        "bootstrap_wins": best["bootstrap_wins"] >= BOOTSTRAP_WIN_SHARE,
    }


def _nothing_named(best_trend: dict | None) -> dict:
    """Outcome when no candidate is named: a structured residual (the best generic trend
    improves the BIC by :data:`BIC_IMPROVEMENT`) or nothing missing."""
    if best_trend is not None and best_trend["delta_bic"] >= BIC_IMPROVEMENT:
        return {
            "outcome": "unexplained",
            "covariate": best_trend["covariate"],
            "text": f"unexplained residual: structured residual against {best_trend['covariate']}",
        }
    return {"outcome": "none", "text": "no missing effect found"}


def _fits_the_noise(problem: Problem, scores: ModelScores, perm_seed: int) -> dict:
    """Whether a model fits the data to the noise, at :data:`ADEQUACY_LEVEL`.

    Sigma known (as in every criterion of the workflow): a model that holds every effect
    in the data has chi-square ~ chi2(n - k) and held-out residuals with no structure
    against any covariate (:func:`where_analysis`, family-wise at the same level).
    """
    y = np.asarray(problem.y, float)
    sigma = np.asarray(problem.sigma, float)
    chi2 = float(scores.full.chi2)
    limit = float(scipy.stats.chi2.isf(ADEQUACY_LEVEL, y.size - scores.k))
    structure = where_analysis(
        (y - scores.cv_prediction) / sigma,
        problem.covariates,
        alpha=ADEQUACY_LEVEL,
        rng=perm_seed,
    )["significant"]
    return {
        "model": scores.name,
        "chi2": chi2,
        "dof": y.size - scores.k,
        "chi2_limit": limit,
        "structured_against": structure,
        "fits": bool(chi2 <= limit and not structure),
    }


def _best_trend(rows: list[dict]) -> dict | None:
    """The generic trend of a round's score rows with the lowest held-out AICc."""
    trends = [r for r in rows if r["kind"] == "trend"]
    return min(trends, key=lambda r: r["aicc"]) if trends else None


def _ambiguous(first: str, second: str, pool: dict[str, Candidate]) -> dict:
    """Outcome of two candidates the data cannot tell apart, with what to measure."""
    return {
        "outcome": "ambiguous",
        "pair": [first, second],
        "text": f"ambiguous: {first} or {second} ({_measure_text(pool[first], pool[second])})",
    }


def weighted_rmse(y: np.ndarray, prediction: np.ndarray, sigma: np.ndarray) -> float:
    """RMSE with the weights of the fit, in units of y: ``sqrt(sum(r^2/s^2) / sum(1/s^2))``.

    Equals the plain RMSE when sigma is the same for every row; with relative noise it
    keeps the rows with the largest values (and largest scatter) from swamping it.
    """
    w = 1.0 / np.asarray(sigma, float) ** 2
    r = np.asarray(y, float) - np.asarray(prediction, float)
    return float(np.sqrt(np.sum(w * r * r) / np.sum(w)))


def _condition_labels(covariates: pd.DataFrame, groups: np.ndarray) -> dict:
    labels = {}
    for g in np.unique(groups):
        sub = covariates[groups == g]
        const = {c: sub[c].iloc[0] for c in sub.columns if sub[c].nunique() == 1}
        labels[g] = ", ".join(
            f"{c}={v:g}" if isinstance(v, int | float | np.number) else f"{c}={v}"
            for c, v in const.items()
        ) or str(g)
    return labels


def _gap(problem: Problem, before: np.ndarray, after: np.ndarray) -> dict:
    y = np.asarray(problem.y, float)
    sigma = np.asarray(problem.sigma, float)
    groups = np.asarray(problem.groups)
    labels = _condition_labels(problem.covariates, groups)
    per = []
    for g in np.unique(groups):
        sel = groups == g
        rb = (y[sel] - before[sel]) / sigma[sel]
        ra = (y[sel] - after[sel]) / sigma[sel]
        per.append(
            {
                "group": g.item() if isinstance(g, np.generic) else g,
                "condition": labels[g],
                "n": int(sel.sum()),
                "rmse_before": float(np.sqrt(np.mean((y[sel] - before[sel]) ** 2))),
                "rmse_after": float(np.sqrt(np.mean((y[sel] - after[sel]) ** 2))),
                "reduced_chi2_before": float(np.mean(rb * rb)),
                "reduced_chi2_after": float(np.mean(ra * ra)),
            }
        )
    rb = (y - before) / sigma
    ra = (y - after) / sigma
    return {
        "measure": "held-out RMSE weighted by 1/sigma^2, in units of the observation",
        "rmse_unweighted_before": float(np.sqrt(np.mean((y - before) ** 2))),
        "rmse_unweighted_after": float(np.sqrt(np.mean((y - after) ** 2))),
        "reduced_chi2_before": float(np.mean(rb * rb)),
        "reduced_chi2_after": float(np.mean(ra * ra)),
        "per_condition": per,
    }


def _blank_fitted(accepted: dict, pool: dict[str, Candidate]) -> dict:
    return {
        n: {"round": 0, "parameters": [{"name": p.name} for p in pool[n].parameters]}
        for n in accepted
    }


def _backfit(
    problem: Problem,
    accepted: dict,
    fitted: dict,
    pool: dict[str, Candidate],
    applies: dict,
    folds: np.ndarray,
    boot: np.ndarray,
    last: str,
    sweeps: int = 2,
) -> tuple[dict, dict, np.ndarray]:
    """Refit each accepted effect with the others fixed (back-fitting), a few sweeps.

    An effect named first absorbs part of the effects named after it; refitting each in
    turn with the others at their current values removes that bias. The held-out
    prediction after it is that of the last effect refitted per fold, the others fixed.
    """
    accepted = dict(accepted)
    fitted = {k: dict(v) for k, v in fitted.items()}
    order = [n for n in accepted if n != last] + [last]
    cv = None
    for _ in range(sweeps):
        for name in order:
            others = {n: p for n, p in accepted.items() if n != name}
            ev = Evaluator(problem, others, pool[name], applies)
            is_last = name == last
            k = problem.n_base + sum(len(p) for p in accepted.values())
            scores = score_model(ev, name, "candidate", k, folds, boot[:0])
            accepted = {**others, name: scores.full.theta}
            accepted = {n: accepted[n] for n in order if n in accepted}
            for j, p in enumerate(fitted[name]["parameters"]):
                p["value"] = scores.full.theta[j]
                p["refit_with_others"] = True
            if is_last:
                cv = scores.cv_prediction
    return accepted, fitted, cv


def run_discrepancy(
    problem: Problem,
    *,
    candidates: Sequence[str | Candidate] | None = None,
    max_effects: int = 2,
    n_bootstrap: int = 100,
    n_folds: int = 5,
    n_permutations: int = 999,
    workers: int = 1,
    seed: int | None = 0,
) -> DiscrepancyResult:
    """Find where the model disagrees with the data, name the missing effect(s), close the gap.

    Parameters
    ----------
    problem : Problem
        Data and base model (:class:`~friction_model.discrepancy.SteadyProblem`, the
        transient problem, or any object that follows the :class:`Problem` protocol).
    candidates : sequence of str or Candidate, optional
        Candidates to try; by default every registered candidate the problem can evaluate
        (its ``effect_names`` and user candidates with ``apply`` for its kind).
    max_effects : int
        Most effects added one after the other (step 5).
    n_bootstrap : int
        Block-bootstrap resamples (groups drawn with replacement).
    n_folds : int
        Hold-out folds; whole groups go to one fold.
    n_permutations : int
        Permutations for the p-values of the where-analysis.
    workers : int
        Processes for fitting the candidates of a round in parallel (1 = serial).
    seed : int or None
        Seed of folds, resamples and permutations.

    Returns
    -------
    DiscrepancyResult

    Notes
    -----
    Every score is held out: each model is refitted with each fold left out and predicts
    that fold; RSS, chi-square, AICc and BIC use those predictions (k = base parameters
    plus effect parameters). A candidate is named only when it improves the BIC of the
    current model by >= 10, beats the runner-up and every generic trend model by dAICc
    >= 2, its fitted parameters lie inside their bounds with a 95 % block-bootstrap
    interval excluding the null, and it has the lowest BIC in >= 80 % of the resamples.
    The named effect is then held fixed at its fitted value and the search repeats. A
    further effect (and the better member of an ambiguous pair) must also leave a model
    that fits to the noise (chi-square within the chi2(n - k) quantile and no structured
    held-out residual, both at :data:`ADEQUACY_LEVEL`); otherwise what remains is reported
    as unexplained residual.
    """
    _check_problem(problem)
    if int(max_effects) != max_effects or max_effects < 0:
        raise ValueError(f"max_effects must be an integer >= 0, got {max_effects!r}")
    if int(n_bootstrap) != n_bootstrap or n_bootstrap < 10:
        raise ValueError(f"n_bootstrap must be an integer >= 10, got {n_bootstrap!r}")
    if int(workers) != workers or workers < 1:
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    pool_list, skipped = _resolve(problem, candidates)
    for cand in pool_list:
        _check_null(problem, cand)
    gen = np.random.default_rng(seed)
    groups = np.asarray(problem.groups)
    folds = group_folds(groups, n_folds, gen)
    boot = block_bootstrap_weights(groups, int(n_bootstrap), gen)
    perm_seed = int(gen.integers(2**31))
    y = np.asarray(problem.y, float)
    sigma = np.asarray(problem.sigma, float)
    search = _Search(
        problem, pool_list, folds, boot, workers=workers, max_effects=max_effects,
        perm_seed=perm_seed,
    )
    final = search.run()
    before, after = search.before, search.after
    names = list(search.accepted)
    if names:
        head = ("missing effect: " if len(names) == 1 else "missing effects: ") + ", ".join(names)
        verdict = head if final["outcome"] == "none" else f"{head}; {final['text']}"
    else:
        verdict = final["text"]
    where = _where(problem, (y - before) / sigma, (y - after) / sigma, n_permutations, perm_seed)
    if final["outcome"] == "unexplained":
        giveaway = final["covariate"]
    elif where["before"]["covariates"]:
        giveaway = where["before"]["covariates"][0]["name"]
    else:
        giveaway = None
    return DiscrepancyResult(
        kind=problem.kind,
        n=int(y.size),
        verdict=verdict,
        missing_effects=names,
        gap_before=weighted_rmse(y, before, sigma),
        gap_after=weighted_rmse(y, after, sigma),
        where=where,
        candidates=search.table,
        rounds=search.rounds,
        gap=_gap(problem, before, after),
        fitted=search.fitted,
        not_revealable=skipped,
        giveaway=giveaway,
        y=y,
        sigma=sigma,
        groups=groups,
        covariates=problem.covariates,
        prediction_before=before,
        prediction_after=after,
    )


def _where(
    problem: Problem,
    r_before: np.ndarray,
    r_after: np.ndarray,
    n_permutations: int,
    perm_seed: int,
) -> dict:
    """Structure of the held-out residuals / sigma before and after the missing effects
    (and their spectra for transients)."""
    where = {
        "residual": "held-out residual / sigma",
        "before": where_analysis(
            r_before, problem.covariates, n_permutations=n_permutations, rng=perm_seed
        ),
        "after": where_analysis(
            r_after, problem.covariates, n_permutations=n_permutations, rng=perm_seed
        ),
    }
    if problem.kind == "transient" and "time_s" in problem.covariates:
        t = problem.covariates["time_s"].to_numpy(float)
        groups = np.asarray(problem.groups)
        where["spectrum_before"] = residual_spectrum(r_before, t, groups)
        where["spectrum_after"] = residual_spectrum(r_after, t, groups)
    return where


class _Search:
    """The rounds of :func:`run_discrepancy`: score, decide, add the winner, repeat.

    Holds the fixed context (problem, candidates, folds, resamples) and the state carried
    from round to round: the accepted effects and their fits, the current model's scores,
    the held-out prediction with the accepted effects (``after``), the rounds and score
    rows so far, and a pending look-ahead on an ambiguous pair.
    """

    def __init__(
        self,
        problem: Problem,
        pool_list: list[Candidate],
        folds: np.ndarray,
        boot: np.ndarray,
        *,
        workers: int,
        max_effects: int,
        perm_seed: int = 0,
    ) -> None:
        self.problem = problem
        self.perm_seed = perm_seed
        self.pool_list = pool_list
        self.pool = {c.name: c for c in pool_list}
        self.applies = {
            c.name: candidate_apply(c.name) for c in pool_list if candidate_apply(c.name)
        }
        self.folds, self.boot = folds, boot
        self.workers, self.max_effects = workers, max_effects
        self.accepted: dict[str, tuple[float, ...]] = {}
        self.fitted: dict[str, dict] = {}
        self.rounds: list[dict] = []
        self.table: list[dict] = []
        self.pending: tuple | None = None  # state before a look-ahead on an ambiguous pair
        self.pending_decision: dict | None = None
        self.current = self.current_scores()
        self.before = self.current.cv_prediction
        self.after = self.before

    def current_scores(self) -> ModelScores:
        """Held-out scores of the base model with the accepted effects."""
        ev = Evaluator(self.problem, self.accepted, None, self.applies)
        k = self.problem.n_base + sum(len(p) for p in self.accepted.values())
        label = "base model" if not self.accepted else "base + " + " + ".join(self.accepted)
        return score_model(ev, label, "current", k, self.folds, self.boot, keep_predictions=True)

    def run(self) -> dict:
        """Rounds until one names no further effect; returns the final decision."""
        round_no = 0
        while True:
            round_no += 1
            fits, decision, rows = self._round(round_no)
            if decision["outcome"] == "ambiguous":
                self._check_pair(decision, fits, rows)
            self.rounds.append(decision)
            self.table.extend(rows)
            logger.info("round %d: %s", round_no, decision["text"])
            # two effects at once: the best candidate improves the fit strongly but a
            # runner-up or a generic trend competes with it, because neither single effect
            # explains both. Add the best tentatively; keep it only if the next round names
            # a further effect with every criterion met.
            tentative = (
                decision["outcome"] in ("ambiguous", "unexplained")
                and decision.get("criteria", {}).get("bic_improvement", False)
                and len(self.accepted) + 2 <= self.max_effects
                and self.pending is None
            )
            if decision["outcome"] != "named" and not tentative:
                return self._final(decision)
            saved = self._state()
            self._accept(decision, fits, rows, round_no, tentative=tentative)
            if self.accepted_fits_the_noise(decision):
                continue
            self._restore(saved)
            decision.update(_nothing_named(_best_trend(rows)))
            return self._final(decision)

    def accepted_fits_the_noise(self, decision: dict) -> bool:
        """Whether a further named effect completes the explanation (:data:`ADEQUACY_LEVEL`).

        The first effect is named against the base model; what it leaves is reported as
        unexplained residual. A second one is fitted to what the first leaves, and when
        part of that is the first one's error of form (an effect in the data that no
        candidate has), the second candidate gains support from carrying that error, not
        from its own physics. The two cases differ in what remains: two missing library
        effects, refitted together, fit the data to the noise (chi-square ~ chi2(n - k),
        sigma known as in every criterion here) and leave held-out residuals with no
        structure against any covariate (:func:`where_analysis` at the same level); an
        effect outside the library leaves a chi-square beyond the chi2(n - k) quantile or
        a structured residual, and then the further effect is not named. Tentative
        (look-ahead) additions are judged in the round that follows.
        """
        if decision.get("look_ahead") or len(self.accepted) < 2:
            return True
        check = _fits_the_noise(self.problem, self.current, self.perm_seed)
        decision["criteria"]["fits_the_noise"] = check["fits"]
        decision["with_every_effect"] = check
        return check["fits"]

    def _check_pair(self, decision: dict, fits: list[ModelScores], rows: list[dict]) -> None:
        """An ambiguous pair claims that either member carries what is missing: if the
        better one does not fit the noise (:func:`_fits_the_noise`), the pair competes only
        in how each approximates something no candidate has, and the round says
        "unexplained" instead (a look-ahead may still add it and find a second effect)."""
        best = next(f for f in fits if f.name == decision["best"])
        check = _fits_the_noise(self.problem, best, self.perm_seed)
        decision["criteria"]["fits_the_noise"] = check["fits"]
        decision["best_alone"] = check
        if not check["fits"]:
            decision.pop("pair", None)
            decision.update(_nothing_named(_best_trend(rows)))

    def _state(self) -> tuple:
        return (dict(self.accepted), dict(self.fitted), self.after, self.current,
                self.pending, self.pending_decision)

    def _restore(self, state: tuple) -> None:
        (self.accepted, self.fitted, self.after, self.current,
         self.pending, self.pending_decision) = state

    def _round(self, round_no: int) -> tuple[list[ModelScores], dict, list[dict]]:
        """Score the remaining candidates and the trends, and decide (after a look-ahead,
        refit the tentative effect together with the new best first)."""
        remaining = [c for c in self.pool_list if c.name not in self.accepted]
        if len(self.accepted) >= self.max_effects:
            remaining = []
        fits, decision, rows = self._score(remaining, round_no)
        if (
            self.pending is not None
            and decision["outcome"] != "named"
            and decision.get("criteria", {}).get("bic_improvement", False)
        ):
            self._refit_with(decision["best"], fits)
            fits, decision, rows = self._score(remaining, round_no)
            decision["refit_before_scoring"] = {n: list(p) for n, p in self.accepted.items()}
        decision["round"] = round_no
        decision["current_model"] = self.current.name
        return fits, decision, rows

    def _score(
        self, remaining: list[Candidate], round_no: int
    ) -> tuple[list[ModelScores], dict, list[dict]]:
        fits = _score_candidates(
            self.problem,
            self.accepted,
            remaining,
            self.applies,
            self.folds,
            self.boot,
            self.workers,
        )
        trends = score_trends(self.problem, self.current, self.folds, self.boot)
        decision, rows = _decide(self.problem, self.current, fits, trends, self.pool, round_no)
        return fits, decision, rows

    def _refit_with(self, best: str, fits: list[ModelScores]) -> None:
        """Look-ahead: the tentative effect was fitted alone and absorbed part of the
        second; refit both together (back-fitting) before the round is scored again."""
        trial = {**self.accepted, best: (0.0,) * len(self.pool[best].null)}
        trial[best] = next(f for f in fits if f.name == best).full.theta
        refit, _, _ = _backfit(
            self.problem,
            trial,
            _blank_fitted(trial, self.pool),
            self.pool,
            self.applies,
            self.folds,
            self.boot,
            best,
        )
        self.accepted = {n: refit[n] for n in self.accepted}
        self.current = self.current_scores()

    def _final(self, decision: dict) -> dict:
        """The last decision; a look-ahead that named nothing further is undone."""
        if self.pending is None:
            return decision
        self.accepted, self.fitted, self.after, self.current, self.rounds = self.pending
        final = self.pending_decision
        final["look_ahead_result"] = decision["text"]
        final["look_ahead_criteria"] = decision.get("criteria")
        return final

    def _accept(
        self,
        decision: dict,
        fits: list[ModelScores],
        rows: list[dict],
        round_no: int,
        *,
        tentative: bool,
    ) -> None:
        """Add the round's best candidate at its fitted value (tentatively for a pair)."""
        name = decision["best"]
        winner = next(f for f in fits if f.name == name)
        row = next(r for r in rows if r["name"] == name)
        if tentative:
            # two candidates explain the data about equally well: both may be missing.
            # Add the better one and see whether the next round names the other.
            self.pending = (
                dict(self.accepted),
                dict(self.fitted),
                self.after,
                self.current,
                list(self.rounds),
            )
            self.pending_decision = decision
            decision["look_ahead"] = f"added {name} to see whether a second effect is missing"
        else:
            self.pending = None
        self.accepted[name] = winner.full.theta
        self.fitted[name] = {"round": round_no, "parameters": row["parameters"]}
        self.after = winner.cv_prediction
        if len(self.accepted) > 1 and not tentative:
            self.accepted, self.fitted, self.after = _backfit(
                self.problem,
                self.accepted,
                self.fitted,
                self.pool,
                self.applies,
                self.folds,
                self.boot,
                name,
            )
        self.current = self.current_scores()
