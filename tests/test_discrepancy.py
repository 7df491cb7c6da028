"""Framework of the discrepancy workflow on an analytic toy problem.

The toy: y = a + b x (+ c x^2 hidden) with known Gaussian noise; base parameters (a, b)
by weighted least squares; candidate ``quadratic`` adds c x^2 (c in [0, 5], null 0). Every
score can be recomputed by hand from numpy's own least squares.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping

import numpy as np
import pandas as pd
import pytest

from friction_model.contact.effects import EFFECT_NAMES
from friction_model.discrepancy import (
    Candidate,
    ParameterSpec,
    aicc_known_sigma,
    bic_known_sigma,
    block_bootstrap_weights,
    candidates,
    get_candidate,
    group_folds,
    register_candidate,
    run_discrepancy,
    unregister_candidate,
    where_analysis,
    write_result,
)
from friction_model.discrepancy._fit import scan_points

N_GROUPS = 20
PER_GROUP = 6
SIGMA = 0.1


class ToyProblem:
    """y = a + b x + effects; native candidates 'quadratic' (c x^2) and 'twin' (same)."""

    kind = "toy"
    n_base = 2

    def __init__(self, y: np.ndarray, x: np.ndarray, z: np.ndarray, names=("quadratic",)):
        self.x = x
        self.y = y
        self.sigma = np.full(y.size, SIGMA)
        self.groups = np.repeat(np.arange(N_GROUPS), PER_GROUP)
        self.covariates = pd.DataFrame({"x": x, "z": z})
        self.effect_names = tuple(names)

    def _extra(self, effects: Mapping[str, tuple[float, ...]]) -> np.ndarray:
        return sum((float(p[0]) * self.x**2 for p in effects.values()), np.zeros(self.y.size))

    def fit_base(self, train, effects):
        design = np.column_stack([np.ones(self.y.size), self.x])[train]
        return np.linalg.lstsq(design, (self.y - self._extra(effects))[train], rcond=None)[0]

    def predict(self, base, effects):
        return base[0] + base[1] * self.x + self._extra(effects)


_QUAD = Candidate(
    "quadratic",
    (ParameterSpec("c", "1", 0.0, 0.0, 5.0),),
    "c x^2",
    frozenset({"toy"}),
    "y at large x",
)
_TWIN = Candidate(
    "twin",
    (ParameterSpec("c", "1", 0.0, 0.0, 5.0),),
    "the same c x^2 under another name",
    frozenset({"toy"}),
    "nothing: it is the same physics",
)


@pytest.fixture(autouse=True)
def _toy_candidates():
    register_candidate(_QUAD, replace=True)
    register_candidate(_TWIN, replace=True)
    yield
    for name in ("quadratic", "twin"):
        unregister_candidate(name)


def _data(c: float, seed: int, *, z_step: float = 0.0):
    gen = np.random.default_rng(seed)
    x = np.repeat(np.linspace(-1.0, 1.0, N_GROUPS), PER_GROUP) + gen.uniform(
        -0.02, 0.02, N_GROUPS * PER_GROUP
    )
    z = gen.uniform(-1.0, 1.0, x.size)
    y = 1.0 + 0.5 * x + c * x**2 + z_step * np.sign(z) + gen.normal(0.0, SIGMA, x.size)
    return x, z, y


def test_scores_by_hand():
    # AICc and BIC of Gaussian errors with known sigma, from the textbook formulas
    assert aicc_known_sigma(10.0, 2, 13) == pytest.approx(10.0 + 4.0 + 12.0 / 10.0, abs=1e-12)
    assert bic_known_sigma(10.0, 2, 100) == pytest.approx(10.0 + 2.0 * math.log(100.0), abs=1e-12)
    assert aicc_known_sigma(1.0, 5, 6) == math.inf


def test_heldout_scores_match_an_independent_refit():
    x, z, y = _data(0.0, 1)
    problem = ToyProblem(y, x, z)
    result = run_discrepancy(problem, candidates=["quadratic"], n_bootstrap=20, seed=5)
    # the folds the workflow uses: the first draw of its generator
    folds = group_folds(problem.groups, 5, np.random.default_rng(5))
    cv = np.empty(y.size)
    for f in range(5):
        train = folds != f
        coef = np.polyfit(x[train], y[train], 1)
        cv[~train] = np.polyval(coef, x[~train])
    chi2 = float(np.sum(((y - cv) / SIGMA) ** 2))
    base = next(c for c in result.candidates if c["kind"] == "current")
    n = y.size
    # the same least squares computed two ways: agreement to rounding
    assert base["chi2_heldout"] == pytest.approx(chi2, rel=1e-10)
    assert base["aicc"] == pytest.approx(chi2 + 4 + 12 / (n - 3), rel=1e-10)
    assert base["bic"] == pytest.approx(chi2 + 2 * math.log(n), rel=1e-10)
    assert base["rss_heldout"] == pytest.approx(float(np.sum((y - cv) ** 2)), rel=1e-10)


def test_hidden_quadratic_is_named_with_its_value():
    x, z, y = _data(0.8, 2)
    result = run_discrepancy(ToyProblem(y, x, z), candidates=["quadratic"], seed=0)
    assert result.verdict == "missing effect: quadratic"
    (param,) = result.fitted["quadratic"]["parameters"]
    # standard error of c with 120 points, sigma 0.1, x in [-1, 1]: about 0.03; 4 se
    assert param["value"] == pytest.approx(0.8, abs=0.12)
    # one seed's 95 % interval misses the truth for 5 % of random streams (not fixed across
    # numpy versions): the truth within twice the half-widths (~1e-4)
    v = param["value"]
    assert v - 2 * (v - param["ci_lower"]) < 0.8 < v + 2 * (param["ci_upper"] - v)
    assert result.gap_after < 0.5 * result.gap_before


def test_no_effect_names_nothing():
    for seed in range(3):
        x, z, y = _data(0.0, 10 + seed)
        result = run_discrepancy(
            ToyProblem(y, x, z), candidates=["quadratic"], seed=seed, n_bootstrap=40
        )
        assert result.verdict == "no missing effect found"
        assert result.missing_effects == []


def test_identical_candidates_are_ambiguous():
    x, z, y = _data(0.8, 3)
    problem = ToyProblem(y, x, z, names=("quadratic", "twin"))
    result = run_discrepancy(problem, seed=0, max_effects=1, n_bootstrap=40)
    assert result.verdict.startswith("ambiguous: ")
    assert {"quadratic", "twin"} <= set(result.verdict.replace(" or ", " ").split())
    assert "to tell them apart" in result.verdict
    assert result.missing_effects == []


def test_structure_outside_the_library_is_unexplained():
    x, z, y = _data(0.0, 4, z_step=0.3)
    result = run_discrepancy(ToyProblem(y, x, z), candidates=["quadratic"], seed=0, n_bootstrap=40)
    assert result.verdict == "unexplained residual: structured residual against z"
    assert result.missing_effects == []
    assert "z" in result.where["before"]["significant"]


def test_user_candidate_with_apply_is_fitted_and_named():
    x, z, y = _data(0.0, 5, z_step=0.3)
    step = Candidate(
        "z_step",
        (ParameterSpec("jump", "1", 0.0, 0.0, 1.0),),
        "a jump of y with the sign of z",
        frozenset({"toy"}),
        "y at z < 0 and z > 0",
    )
    register_candidate(
        step, apply=lambda problem, pred, p: pred + p[0] * np.sign(problem.covariates["z"])
    )
    try:
        result = run_discrepancy(ToyProblem(y, x, z), seed=0, n_bootstrap=40)
    finally:
        unregister_candidate("z_step")
    assert result.missing_effects == ["z_step"]
    (param,) = result.fitted["z_step"]["parameters"]
    # se of the jump: sigma / sqrt(n) ~ 0.01; 5 se
    assert param["value"] == pytest.approx(0.3, abs=0.05)


def test_apply_must_vanish_at_the_null():
    x, z, y = _data(0.0, 6)
    bad = Candidate(
        "offset_bug", (ParameterSpec("a", "1", 0.0, 0.0, 1.0),), "buggy", frozenset({"toy"}), "-"
    )
    register_candidate(bad, apply=lambda problem, pred, p: pred + 0.1 + p[0])
    try:
        with pytest.raises(ValueError, match="does not reduce to the model"):
            run_discrepancy(ToyProblem(y, x, z), n_bootstrap=10)
    finally:
        unregister_candidate("offset_bug")


def test_registry_rules():
    assert {c.name for c in candidates()} >= set(EFFECT_NAMES)
    with pytest.raises(ValueError, match="library effect"):
        register_candidate(get_candidate("viscous_shear"))
    with pytest.raises(ValueError, match="already registered"):
        register_candidate(_QUAD)
    with pytest.raises(KeyError, match="no candidate named"):
        get_candidate("nope")
    with pytest.raises(ValueError, match="null"):
        ParameterSpec("s", "1", null=2.0, lower=0.0, upper=1.0)
    with pytest.raises(ValueError, match="one or two"):
        Candidate("x", (), "", frozenset(), "")


def test_bad_problem_is_rejected():
    x, z, y = _data(0.0, 7)
    problem = ToyProblem(y, x, z)
    problem.sigma = np.zeros(y.size)
    with pytest.raises(ValueError, match="sigma must be finite and > 0"):
        run_discrepancy(problem)


def test_folds_and_bootstrap_keep_groups_whole():
    groups = np.repeat(np.arange(7), 3)
    folds = group_folds(groups, 3, np.random.default_rng(0))
    for g in range(7):
        assert np.unique(folds[groups == g]).size == 1
    assert np.bincount(np.bincount(folds) // 3).sum() == 3  # folds differ by <= one group
    w = block_bootstrap_weights(groups, 50, np.random.default_rng(0))
    assert np.all(w.sum(axis=1) == groups.size)  # 7 groups of 3 drawn per resample
    for g in range(7):
        assert np.all(w[:, groups == g] == w[:, groups == g][:, :1])


def test_where_analysis_finds_the_covariate_and_range():
    gen = np.random.default_rng(0)
    x = np.repeat(np.arange(5.0), 40)
    r = gen.normal(size=x.size) + np.where(x == 4.0, 2.0, 0.0)
    out = where_analysis(r, pd.DataFrame({"x": x, "noise": gen.normal(size=x.size)}), rng=1)
    assert out["covariates"][0]["name"] == "x"
    assert out["covariates"][0]["significant_correlation"]
    sig = [rng_["lower"] for rng_ in out["covariates"][0]["ranges"] if rng_["significant"]]
    assert sig == [4.0]
    noise = next(e for e in out["covariates"] if e["name"] == "noise")
    # under the null the permutation p-value (999 permutations) is uniform: > 0.01 fails for
    # 1 % of random streams (2 of 200 seeds), > 0.002 for 0.2 %; a seed's stream is not fixed
    # across numpy versions. The x range is found for all 200 seeds.
    assert noise["p_value"] > 0.002


def test_scan_points_respect_the_null_side():
    p = scan_points(1.0, -1.0, 1.0, 6)
    assert p[-1] == 1.0 and p[0] == -1.0 and np.all(np.diff(p) > 0)


def test_write_result_files(tmp_path):
    x, z, y = _data(0.8, 8)
    result = run_discrepancy(ToyProblem(y, x, z), candidates=["quadratic"], seed=0, n_bootstrap=20)
    out = write_result(result, tmp_path / "out")
    data = json.loads((out / "result.json").read_text())
    for key in ("missing_effects", "gap_before", "gap_after", "where", "candidates", "verdict"):
        assert key in data
    assert data["missing_effects"] == ["quadratic"]
    assert data["verdict"] == result.verdict
    assert "missing effect: quadratic" in (out / "report.md").read_text()
    for name in ("residuals.png", "measured_vs_simulated.png", "candidates.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]
