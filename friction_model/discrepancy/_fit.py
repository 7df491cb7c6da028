"""Fitting candidates on weighted rows: multi-start profile fits, hold-out and bootstrap.

A *model* is the current model (the base plus the effects accepted so far) with at most one
more candidate. Its free parameters are the problem's base parameters (fitted by
:meth:`Problem.fit_base` for every trial value of the candidate's parameters: a profile
fit) and the candidate's one or two parameters (multi-start: a scan over the bounded range,
then a bounded local refinement from the best local minima of the scan). User candidates
that act on the prediction (``apply``) are fitted jointly with the base parameters by
bounded least squares, since ``fit_base`` does not know them.

Rows enter with weights: 0/1 for hold-out folds, counts for block-bootstrap resamples.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.optimize

from friction_model.discrepancy._problem import Apply, Candidate, Problem

__all__: list[str] = []

_SCAN_POINTS_1D = 24
_SCAN_POINTS_2D = 7
_N_STARTS = 2


def accepts_weights(problem: Problem) -> bool:
    """True when ``problem.fit_base`` takes a ``weights`` keyword (row weights)."""
    try:
        return "weights" in inspect.signature(problem.fit_base).parameters
    except (TypeError, ValueError):  # pragma: no cover - builtins without signature
        return False


def parameter_bounds(problem: Problem, candidate: Candidate) -> list[tuple[float, float]]:
    """Bounds of the candidate's parameters, narrowed by the problem where it says so.

    A problem may define ``parameter_bounds(name) -> sequence of (lower, upper)`` to narrow
    the library bounds to what its data allow (e.g. a melting point that stays above every
    temperature of the table); the null must stay inside.
    """
    bounds = [(p.lower, p.upper) for p in candidate.parameters]
    narrow = getattr(problem, "parameter_bounds", None)
    if callable(narrow):
        given = narrow(candidate.name)
        if given is not None:
            given = [(float(lo), float(hi)) for lo, hi in given]
            if len(given) != len(bounds):
                raise ValueError(
                    f"parameter_bounds({candidate.name!r}) gave {len(given)} ranges for "
                    f"{len(bounds)} parameters"
                )
            bounds = [
                (max(lo, glo), min(hi, ghi))
                for (lo, hi), (glo, ghi) in zip(bounds, given, strict=True)
            ]
    for (lo, hi), spec in zip(bounds, candidate.parameters, strict=True):
        if not lo <= spec.null <= hi or not lo < hi:
            raise ValueError(
                f"bounds [{lo}, {hi}] of {candidate.name}.{spec.name} must contain its null "
                f"{spec.null} and be non-empty"
            )
    return bounds


def scan_points(null: float, lower: float, upper: float, n: int) -> np.ndarray:
    """Trial values over [lower, upper], log-spaced away from the null when it is a bound.

    Examples
    --------
    >>> p = scan_points(0.0, 0.0, 1.0, 5)
    >>> float(p[0]), float(p[-1]), bool(np.all(np.diff(p) > 0))
    (0.0, 1.0, True)
    """
    span = upper - lower
    steps = np.concatenate([[0.0], np.geomspace(1e-3, 1.0, n - 1)])
    if null == lower:
        return lower + span * steps
    if null == upper:
        return (upper - span * steps)[::-1]
    return np.linspace(lower, upper, n)


@dataclass
class Fit:
    """One model fitted on one set of row weights."""

    theta: tuple[float, ...]
    beta: np.ndarray
    chi2: float
    prediction: np.ndarray


@dataclass
class ModelScores:
    """Everything the workflow needs about one model in one round."""

    name: str
    kind: str  # "current", "candidate" or "trend"
    k: int
    full: Fit
    cv_prediction: np.ndarray
    chi2_cv: float
    boot_chi2: np.ndarray
    boot_theta: np.ndarray
    fold_prediction: np.ndarray | None = None  # (n_folds, n), current model only
    boot_prediction: np.ndarray | None = None  # (B, n), current model only
    extra: dict = field(default_factory=dict)


class Evaluator:
    """Predictions and fits of the current model plus at most one candidate."""

    def __init__(
        self,
        problem: Problem,
        accepted: Mapping[str, tuple[float, ...]],
        candidate: Candidate | None,
        applies: Mapping[str, Apply],
    ) -> None:
        self.problem = problem
        self.accepted = dict(accepted)
        self.candidate = candidate
        self.applies = dict(applies)
        self.native = set(problem.effect_names)
        self.y = np.asarray(problem.y, float)
        self.sigma = np.asarray(problem.sigma, float)
        self.weighted = accepts_weights(problem)
        self.bounds = parameter_bounds(problem, candidate) if candidate else []
        names = [*self.accepted, *([candidate.name] if candidate else [])]
        self.joint = any(n not in self.native for n in names)
        for n in names:
            if n not in self.native and n not in self.applies:
                raise ValueError(
                    f"candidate {n!r} is not among the problem's effect_names "
                    f"{problem.effect_names} and has no apply function"
                )

    # -- model ---------------------------------------------------------------------------
    def _effects(self, theta: tuple[float, ...]) -> tuple[dict, list]:
        all_effects = dict(self.accepted)
        if self.candidate is not None:
            all_effects[self.candidate.name] = tuple(float(t) for t in theta)
        native = {n: p for n, p in all_effects.items() if n in self.native}
        user = [(n, p) for n, p in all_effects.items() if n not in self.native]
        return native, user

    def _base(self, w: np.ndarray, native: dict) -> np.ndarray:
        mask = w > 0
        if self.weighted:
            return np.asarray(self.problem.fit_base(mask, native, weights=w), float)
        return np.asarray(self.problem.fit_base(mask, native), float)

    def predict(self, beta: np.ndarray, theta: tuple[float, ...]) -> np.ndarray:
        native, user = self._effects(theta)
        pred = np.asarray(self.problem.predict(beta, native), float)
        for name, params in user:
            pred = np.asarray(self.applies[name](self.problem, pred, params), float)
        return pred

    def _chi2(self, pred: np.ndarray, w: np.ndarray) -> float:
        r = (self.y - pred) / self.sigma
        return float(w @ (r * r))

    def profile(self, theta: tuple[float, ...], w: np.ndarray) -> tuple[float, np.ndarray]:
        native, _ = self._effects(theta)
        beta = self._base(w, native)
        pred = self.predict(beta, theta)
        chi2 = self._chi2(pred, w)
        return (chi2 if math.isfinite(chi2) else math.inf), beta

    # -- fitting -------------------------------------------------------------------------
    def fit(self, w: np.ndarray, near: tuple[float, ...] | None = None) -> Fit:
        """Fit on row weights ``w``; ``near`` (a previous fit) makes the scan coarse.

        With ``near`` the scan has a third of the points, plus ``near`` itself; used for
        the bootstrap refits, whose optimum lies close to the fit on all rows.
        """
        if self.candidate is None:
            beta = self._base(w, self._effects(())[0])
            if self.joint and beta.size:
                beta = self._joint_beta(beta, w)
            pred = self.predict(beta, ())
            return Fit((), beta, self._chi2(pred, w), pred)
        starts = self._scan(w, near)
        if self.joint:
            return self._fit_joint(starts, w)
        if len(self.bounds) == 1:
            return self._refine_1d(starts, w)
        return self._refine_nd(starts, w)

    def _scan(
        self, w: np.ndarray, near: tuple[float, ...] | None = None
    ) -> list[tuple[float, ...]]:
        """Best local minima of the profile over a grid of trial values (the starts)."""
        specs = self.candidate.parameters
        if len(specs) == 1:
            lo, hi = self.bounds[0]
            n_scan = _SCAN_POINTS_1D if near is None else _SCAN_POINTS_1D // 3
            grid = scan_points(specs[0].null, lo, hi, n_scan)
            if near is not None:
                grid = np.unique(np.concatenate([grid, [np.clip(near[0], lo, hi)]]))
            values = np.array([self.profile((g,), w)[0] for g in grid])
            interior = (
                np.r_[True, values[1:] <= values[:-1]] & np.r_[values[:-1] <= values[1:], True]
            )
            order = [i for i in np.argsort(values) if interior[i]][:_N_STARTS]
            self._grid = grid
            return [(float(grid[i]),) for i in order]
        axes = [
            scan_points(s.null, lo, hi, _SCAN_POINTS_2D)
            for s, (lo, hi) in zip(specs, self.bounds, strict=True)
        ]
        mesh = np.array(np.meshgrid(*axes, indexing="ij")).reshape(len(axes), -1).T
        values = np.array([self.profile(tuple(m), w)[0] for m in mesh])
        return [tuple(float(v) for v in mesh[i]) for i in np.argsort(values)[: _N_STARTS + 1]]

    def _refine_1d(self, starts: list[tuple[float, ...]], w: np.ndarray) -> Fit:
        grid = self._grid
        lo_b, hi_b = self.bounds[0]
        best: tuple[float, float] | None = None
        for (x0,) in starts:
            i = int(np.searchsorted(grid, x0))
            a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
            res = scipy.optimize.minimize_scalar(
                lambda t: self.profile((t,), w)[0],
                bounds=(a, b),
                method="bounded",
                options={"xatol": 1e-6 * (hi_b - lo_b)},
            )
            for x, f in ((float(res.x), float(res.fun)), (x0, self.profile((x0,), w)[0])):
                if best is None or f < best[1]:
                    best = (x, f)
        x = best[0]
        chi2, beta = self.profile((x,), w)
        return Fit((x,), beta, chi2, self.predict(beta, (x,)))

    def _refine_nd(self, starts: list[tuple[float, ...]], w: np.ndarray) -> Fit:
        best: tuple[tuple[float, ...], float] | None = None
        for x0 in starts:
            res = scipy.optimize.minimize(
                lambda t: self.profile(tuple(t), w)[0],
                np.asarray(x0),
                method="Powell",
                bounds=self.bounds,
                options={"xtol": 1e-6, "ftol": 1e-10},
            )
            cand = (tuple(float(v) for v in np.clip(res.x, *np.array(self.bounds).T)), res.fun)
            if best is None or cand[1] < best[1]:
                best = cand
        theta = best[0]
        chi2, beta = self.profile(theta, w)
        return Fit(theta, beta, chi2, self.predict(beta, theta))

    def _residuals(self, x: np.ndarray, n_beta: int, w: np.ndarray) -> np.ndarray:
        pred = self.predict(x[:n_beta], tuple(x[n_beta:]))
        return np.sqrt(w) * (self.y - pred) / self.sigma

    def _joint_beta(self, beta: np.ndarray, w: np.ndarray) -> np.ndarray:
        res = scipy.optimize.least_squares(
            lambda b: np.sqrt(w) * (self.y - self.predict(b, ())) / self.sigma, beta
        )
        return res.x

    def _fit_joint(self, starts: list[tuple[float, ...]], w: np.ndarray) -> Fit:
        best: Fit | None = None
        lower = np.array([b[0] for b in self.bounds])
        upper = np.array([b[1] for b in self.bounds])
        for theta0 in starts:
            native, _ = self._effects(theta0)
            beta0 = self._base(w, native)
            nb = beta0.size
            x0 = np.concatenate([beta0, np.clip(theta0, lower, upper)])
            res = scipy.optimize.least_squares(
                self._residuals,
                x0,
                bounds=(
                    np.concatenate([np.full(nb, -np.inf), lower]),
                    np.concatenate([np.full(nb, np.inf), upper]),
                ),
                args=(nb, w),
            )
            theta = tuple(float(v) for v in res.x[nb:])
            pred = self.predict(res.x[:nb], theta)
            fit = Fit(theta, res.x[:nb], self._chi2(pred, w), pred)
            if best is None or fit.chi2 < best.chi2:
                best = fit
        return best


def score_model(
    evaluator: Evaluator,
    name: str,
    kind: str,
    k: int,
    folds: np.ndarray,
    boot_weights: np.ndarray,
    *,
    keep_predictions: bool = False,
) -> ModelScores:
    """Fit on all rows, on each hold-out fold's complement, and on each bootstrap resample."""
    n = evaluator.y.size
    full = evaluator.fit(np.ones(n))
    cv = np.empty(n)
    fold_pred = []
    for f in np.unique(folds):
        fit = evaluator.fit((folds != f).astype(float))
        held = folds == f
        cv[held] = fit.prediction[held]
        fold_pred.append(fit.prediction)
    r = (evaluator.y - cv) / evaluator.sigma
    n_par = len(full.theta)
    boot_chi2 = np.empty(len(boot_weights))
    boot_theta = np.empty((len(boot_weights), n_par))
    boot_pred = []
    for b, w in enumerate(boot_weights):
        fit = evaluator.fit(w, near=full.theta if n_par else None)
        boot_chi2[b] = fit.chi2
        boot_theta[b] = fit.theta
        if keep_predictions:
            boot_pred.append(fit.prediction)
    return ModelScores(
        name=name,
        kind=kind,
        k=k,
        full=full,
        cv_prediction=cv,
        chi2_cv=float(r @ r),
        boot_chi2=boot_chi2,
        boot_theta=boot_theta,
        fold_prediction=np.array(fold_pred) if keep_predictions else None,
        boot_prediction=np.array(boot_pred) if keep_predictions else None,
    )


def _trend_regressor(column: pd.Series) -> np.ndarray | None:
    values = pd.to_numeric(column, errors="coerce").to_numpy(float)
    if not np.all(np.isfinite(values)) or np.ptp(values) == 0:
        return None
    return (values - values.mean()) / values.std()


def _trend_fit(
    y: np.ndarray, sigma: np.ndarray, p: np.ndarray, g: np.ndarray, w: np.ndarray
) -> np.ndarray:
    """Prediction ``p + a p + b g`` with a, b from weighted least squares (closed form)."""
    x = np.column_stack([p, g])
    ww = w / sigma**2
    a = x.T @ (ww[:, None] * x)
    rhs = x.T @ (ww * (y - p))
    coef = np.linalg.lstsq(a + 1e-12 * np.trace(a) * np.eye(2), rhs, rcond=None)[0]
    return p + x @ coef


def score_trends(
    problem: Problem, current: ModelScores, folds: np.ndarray, boot_weights: np.ndarray
) -> list[ModelScores]:
    """Generic trend models on top of the current model, one per covariate and form.

    Not physics: ``f = p (1 + a) + b g`` (additive) or ``f = p (1 + a + b g)`` (relative),
    with p the current model, g the standardised covariate, a a refit of the overall level
    and b the trend. They measure how much of the residual a plain trend against one
    covariate explains; a named effect must do better than all of them.
    """
    y = np.asarray(problem.y, float)
    sigma = np.asarray(problem.sigma, float)
    n = y.size
    out: list[ModelScores] = []
    fold_ids = np.unique(folds)
    for col in problem.covariates.columns:
        g0 = _trend_regressor(problem.covariates[col])
        if g0 is None:
            continue
        for form in ("additive", "relative"):

            def reg(p: np.ndarray, g0: np.ndarray = g0, form: str = form) -> np.ndarray:
                return g0 if form == "additive" else p * g0

            p = current.full.prediction
            full_pred = _trend_fit(y, sigma, p, reg(p), np.ones(n))
            cv = np.empty(n)
            for i, f in enumerate(fold_ids):
                pf = current.fold_prediction[i]
                train = (folds != f).astype(float)
                pred = _trend_fit(y, sigma, pf, reg(pf), train)
                cv[folds == f] = pred[folds == f]
            boot = np.empty(len(boot_weights))
            for b, w in enumerate(boot_weights):
                pb = current.boot_prediction[b]
                pred = _trend_fit(y, sigma, pb, reg(pb), w)
                rb = (y - pred) / sigma
                boot[b] = float(w @ (rb * rb))
            r_full = (y - full_pred) / sigma
            r_cv = (y - cv) / sigma
            out.append(
                ModelScores(
                    name=f"{col} trend ({form})",
                    kind="trend",
                    k=current.k + 1,
                    full=Fit((), np.empty(0), float(r_full @ r_full), full_pred),
                    cv_prediction=cv,
                    chi2_cv=float(r_cv @ r_cv),
                    boot_chi2=boot,
                    boot_theta=np.empty((len(boot_weights), 0)),
                    extra={"covariate": col, "form": form},
                )
            )
    return out
