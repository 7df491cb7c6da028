"""Which friction law a steady characteristic supports, and whether a fit fits.

A statistician's reading of a mu(v) characteristic, in three steps:

1. **Noise.** Repeated runs at one velocity (the ``run`` rows of
   ``steady_characteristic.csv``) give the noise independently of any law: the pooled
   replicate ("pure error") standard deviation :func:`replicate_noise`. Without repeats, a
   given ``mu_std`` serves; without either the noise is only known from a law's residuals.
2. **Quality of one fit** (:func:`fit_quality`). With an independent noise estimate, the
   weighted residual sum ``chi2`` of a correct law follows a chi-square distribution with
   ``n - k`` degrees of freedom; the reduced chi-square ``chi2 / (n - k)`` is about 1. A fit
   whose misfit has a tail probability below :data:`MISFIT_P` (the lack-of-fit F test with
   replicate noise, the chi-square test with a given one) is a misfit (the residual
   exceeds the noise by more than chance allows): it is warned about, and its covariance is
   scaled by the reduced chi-square (the Birge ratio squared), so that an interval is never
   narrower than the misfit it ignores.
3. **Choice** (:func:`choose_law`). Laws with more parameters than distinct velocities are
   not identifiable; laws that are misfits are contradicted by the data; the rest are
   ranked by AICc (:mod:`friction_model.model_selection`). When AICc cannot rank them
   (``n <= k + 1`` for one of them) the choice is undecidable; when several are within
   :data:`AICC_MARGIN` of the best, the one with the fewest parameters is taken if it is
   unique (parsimony), else the choice is undecidable. An undecidable choice raises
   :class:`LawUndecidable`, naming the laws still in play; it never falls back to a law by
   arithmetic accident.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import stats

from friction_model.contact import laws
from friction_model.model_selection import aicc_known_sigma, aicc_rss, reduced_chi_square
from friction_model.replicates import replicate_noise, velocity_levels

__all__ = [
    "AICC_MARGIN",
    "AUTO_LAWS",
    "MISFIT_P",
    "FitQuality",
    "LawChoice",
    "LawUndecidable",
    "choose_law",
    "fit_quality",
    "law_interval",
    "replicate_noise",
    "velocity_levels",
]

#: Laws ``law="auto"`` compares.
AUTO_LAWS = ("ConstantLaw", "DecreasingSqrtLaw", "IncreasingSqrtLaw", "ExponentialLaw")
#: A fit is a misfit when its chi-square, under the noise estimated without the law, has a
#: tail probability below this: one chance in a thousand that noise alone made it.
MISFIT_P = 1e-3
#: Laws within this AICc of the best are "in play" together (Burnham and Anderson: a
#: difference below 2 is substantial support for both).
AICC_MARGIN = 2.0
@dataclass(frozen=True)
class FitQuality:
    """Whether a law's fit agrees with the noise, and how much its intervals widen.

    Attributes
    ----------
    reduced_chi2 : float
        ``chi2 / (n - k)`` with the independent noise estimate; NaN when there is none or
        no degree of freedom is left (then the fit cannot be tested).
    p_value : float
        Tail probability of the misfit: the lack-of-fit F test with replicate noise, else
        ``chi2`` against the chi-square distribution with ``n - k`` degrees of freedom (NaN
        when untestable: no independent noise, or as many parameters as velocity levels).
    misfit : bool
        ``p_value < MISFIT_P``: the residual exceeds the noise by more than chance allows.
    interval_scale : float
        Factor on the standard errors: ``sqrt(max(1, reduced_chi2))`` for a fit with an
        independent noise estimate, 1 otherwise (the covariance of a fit without one is
        already scaled by its residuals).
    noise_source : str
        ``"replicates"``, ``"given"`` (``mu_std`` of the table) or ``"residuals"``.
    noise_sigma : float
        The noise standard deviation of one point (root-mean-square over the points).
    noise_dof : int or None
        Degrees of freedom of the noise estimate (None when unknown).
    """

    reduced_chi2: float
    p_value: float
    misfit: bool
    interval_scale: float
    noise_source: str
    noise_sigma: float
    noise_dof: int | None

    @property
    def testable(self) -> bool:
        """Whether the fit could be tested against the noise (a finite ``p_value``)."""
        return math.isfinite(self.p_value)

    def warning(self, law_name: str) -> str | None:
        """One line when the fit is a misfit, else None."""
        if not self.misfit:
            return None
        return (
            f"{law_name} does not fit: residuals {math.sqrt(self.reduced_chi2):.3g} times the "
            f"noise ({self.noise_source}, sigma {self.noise_sigma:.2g}; reduced chi-square "
            f"{self.reduced_chi2:.3g}, p = {self.p_value:.2g}); intervals widened by "
            f"{self.interval_scale:.3g}"
        )


def fit_quality(
    fit: laws.FitResult, *, noise_source: str, noise_sigma: float, noise_dof: int | None
) -> FitQuality:
    """The reduced chi-square of a fit, its misfit test and the interval scale.

    Parameters
    ----------
    fit : FitResult
        A fit by :func:`friction_model.contact.laws.fit_law`; with an independent noise
        estimate it was weighted by it (``absolute_sigma``).
    noise_source : {"replicates", "given", "residuals"}
        Where the noise came from; ``"residuals"`` means from this fit (untestable).
    noise_sigma : float
        Noise standard deviation of one point (for the message).
    noise_dof : int or None
        Degrees of freedom of the noise estimate.

    Returns
    -------
    FitQuality

    Examples
    --------
    >>> v = np.array([1.0, 1.0, 3.0, 3.0, 5.0, 5.0])
    >>> mu = np.array([0.25, 0.25, 0.18, 0.18, 0.17, 0.17]) + 1e-4 * np.array([1, -1] * 3)
    >>> fit = laws.fit_law(laws.ConstantLaw, v, mu, sigma=np.full(6, 1.4e-4))
    >>> q = fit_quality(fit, noise_source="replicates", noise_sigma=1.4e-4, noise_dof=3)
    >>> q.misfit, q.interval_scale > 100
    (True, True)
    """
    if noise_source == "residuals" or fit.dof <= 0 or not math.isfinite(fit.chi2):
        return FitQuality(math.nan, math.nan, False, 1.0, noise_source, noise_sigma, noise_dof)
    red = reduced_chi_square(fit.chi2, fit.n_points, fit.n_points - fit.dof)
    p = _misfit_p(fit.chi2, fit.dof, noise_source, noise_dof)
    return FitQuality(
        reduced_chi2=red,
        p_value=p,
        misfit=bool(p < MISFIT_P),
        interval_scale=math.sqrt(max(1.0, red)),
        noise_source=noise_source,
        noise_sigma=noise_sigma,
        noise_dof=noise_dof,
    )


def _misfit_p(chi2: float, dof: int, noise_source: str, noise_dof: int | None) -> float:
    """Tail probability of a fit's misfit under the noise (NaN when untestable).

    With replicate noise the chi-square splits into the pure error (``noise_dof`` exactly,
    the pooled sigma being made of it) and the lack of fit; the lack-of-fit F test
    ``F = ((chi2 - noise_dof) / (dof - noise_dof))``, F-distributed with
    ``(dof - noise_dof, noise_dof)`` degrees of freedom, accounts for the noise being
    estimated. A given sigma is taken as exact: ``chi2`` against chi-square(``dof``).
    """
    if noise_source == "replicates" and noise_dof:
        lof_dof = dof - noise_dof
        if lof_dof <= 0:  # as many parameters as replicate groups: no lack of fit to test
            return math.nan
        f_stat = max(chi2 - noise_dof, 0.0) / lof_dof
        return float(stats.f.sf(f_stat, lof_dof, noise_dof))
    return float(stats.chi2.sf(chi2, dof))


def law_interval(
    fit: laws.FitResult, quality: FitQuality, level: float
) -> dict[str, dict[str, float]]:
    """Standard errors and two-sided intervals of the free parameters, widened by misfit.

    The standard errors are the fit's times :attr:`FitQuality.interval_scale`. The quantile
    is Student's t: with the fit's ``n - k`` degrees of freedom when the noise came from
    its residuals or the covariance was scaled by the misfit, else with those of the noise
    estimate (normal when unknown).

    Returns
    -------
    dict
        ``stderr``, ``ci_low``, ``ci_high``: parameter name -> value.
    """
    scaled = quality.noise_source == "residuals" or quality.interval_scale > 1.0
    df = fit.dof if scaled else quality.noise_dof
    if df is None or df <= 0:
        q = float(stats.norm.ppf(0.5 + 0.5 * level)) if df is None else math.inf
    else:
        q = float(stats.t.ppf(0.5 + 0.5 * level, df))
    names = [k for k in fit.params if k not in fit.fixed]
    se = {k: fit.stderr[k] * quality.interval_scale for k in names}
    return {
        "stderr": se,
        "ci_low": {k: fit.params[k] - q * se[k] for k in names},
        "ci_high": {k: fit.params[k] + q * se[k] for k in names},
    }


class LawUndecidable(ValueError):
    """The data cannot tell the candidate laws apart.

    Attributes
    ----------
    in_play : tuple of str
        The laws still in play.
    reason : str
        Why they cannot be told apart.
    """

    def __init__(self, name: str, in_play: Sequence[str], reason: str) -> None:
        self.in_play = tuple(in_play)
        self.reason = reason
        super().__init__(
            f"{name}: cannot choose a friction law: {reason}; still in play: "
            f"{', '.join(self.in_play)}; name the law (law='NAME'; calibrate --law NAME)"
        )


@dataclass(frozen=True)
class LawChoice:
    """The outcome of :func:`choose_law`.

    Attributes
    ----------
    name : str
        The chosen law.
    fit : FitResult
        Its fit.
    quality : FitQuality
        Its fit quality.
    rule : str
        Why it was chosen, in one sentence.
    candidates : dict
        Per candidate law: ``k``, ``aicc`` (None when undefined), ``reduced_chi2``,
        ``status`` (``chosen``, ``in play``, ``contradicted``, ``not identifiable``,
        ``failed``).
    notes : tuple of str
        Warnings worth a line (misfit, a saturated law).
    """

    name: str
    fit: laws.FitResult
    quality: FitQuality
    rule: str
    candidates: dict[str, dict[str, Any]] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def law(self) -> laws.FrictionLaw:
        """The fitted law."""
        return self.fit.law


@dataclass
class _Candidate:
    name: str
    k: int
    fit: laws.FitResult | None = None
    quality: FitQuality | None = None
    aicc: float = math.nan
    status: str = "in play"


def _fit_candidate(name: str, steady: Any, noise: tuple[str, float, int | None]) -> _Candidate:
    """Fit one law; its status ``not identifiable``, ``failed``, ``contradicted`` or in play."""
    cls = getattr(laws, name)
    cand = _Candidate(name, len(cls.param_names))
    if cand.k > steady.n_velocities:
        cand.status = "not identifiable"
        return cand
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cand.fit = laws.fit_law(cls, steady.velocity_mps, steady.mu, sigma=steady.sigma)
    except (ValueError, RuntimeError):
        cand.status = "failed"
        return cand
    source, sigma, dof = noise
    cand.quality = fit_quality(cand.fit, noise_source=source, noise_sigma=sigma, noise_dof=dof)
    n = cand.fit.n_points
    if source == "residuals":
        cand.aicc = aicc_rss(cand.fit.chi2, cand.k, n)
    else:
        cand.aicc = aicc_known_sigma(cand.fit.chi2, cand.k, n)
    if cand.quality.misfit:
        cand.status = "contradicted"
    return cand


def _decide(cands: list[_Candidate], n: int) -> tuple[_Candidate | None, str, list[str]]:
    """The chosen candidate and the rule, or None with the reason and the laws in play."""
    fitted = [c for c in cands if c.fit is not None]
    ranked = [c for c in fitted if c.status == "in play"]
    prefix = ""
    if not ranked:
        ranked = fitted
        prefix = "every law contradicts the data; "
    if len(ranked) == 1:
        rule = "the only law the data do not contradict" if not prefix else "the only fit"
        return ranked[0], prefix + rule, []
    undefined = [c.name for c in ranked if not math.isfinite(c.aicc)]
    if undefined:
        reason = (
            f"{prefix}too few points (n = {n}) for AICc to rank {', '.join(undefined)} "
            "(it needs n > k + 1)"
        )
        return None, reason, [c.name for c in ranked]
    ranked.sort(key=lambda c: c.aicc)
    best = ranked[0]
    close = [c for c in ranked if c.aicc - best.aicc <= AICC_MARGIN]
    if len(close) == 1:
        gap = ranked[1].aicc - best.aicc
        return best, f"{prefix}lowest AICc, {gap:.1f} below {ranked[1].name}", []
    fewest = min(c.k for c in close)
    simplest = [c for c in close if c.k == fewest]
    names = ", ".join(c.name for c in close)
    if len(simplest) == 1:
        return simplest[0], (
            f"{prefix}{names} within {AICC_MARGIN:g} in AICc; the one with the fewest "
            "parameters taken"
        ), []
    return None, (
        f"{prefix}{names} within {AICC_MARGIN:g} in AICc, none with fewer parameters"
    ), [c.name for c in close]


def choose_law(
    steady: Any, name: str = "auto", candidates: Sequence[str] = AUTO_LAWS
) -> LawChoice:
    """Fit a named law, or choose one of ``candidates`` (``name="auto"``).

    Parameters
    ----------
    steady : SteadyCharacteristic
        The characteristic (:func:`~friction_model.identification.read_characteristic`):
        ``velocity_mps``, ``mu``, ``sigma`` (None: noise only from residuals),
        ``noise_source``, ``noise_dof``, ``n_velocities``.
    name : str
        A law's class name, or ``"auto"``.
    candidates : sequence of str
        The laws ``auto`` compares.

    Returns
    -------
    LawChoice

    Raises
    ------
    LawUndecidable
        ``auto`` when the data cannot tell the laws in play apart (see the module notes).
    ValueError
        A named law that cannot be fitted, or (``auto``) no law could be fitted.
    """
    sigma = steady.sigma
    noise_sigma = math.nan if sigma is None else float(np.sqrt(np.mean(np.square(sigma))))
    noise = (steady.noise_source, noise_sigma, steady.noise_dof)
    names = list(candidates) if name == "auto" else [name]
    cands = [_fit_candidate(c, steady, noise) for c in names]
    if name != "auto":
        cand = cands[0]
        if cand.fit is None:
            why = (f"{cand.k} parameters but {steady.n_velocities} distinct velocities"
                   if cand.status == "not identifiable" else "the fit failed")
            raise ValueError(f"{steady.name}: fitting {name} failed: {why}")
        chosen, rule = cand, "named (--law)"
    else:
        if not any(c.fit is not None for c in cands):
            raise ValueError(f"{steady.name}: no friction law could be fitted")
        found, rule, in_play = _decide(cands, steady.mu.size)
        if found is None:
            raise LawUndecidable(steady.name, in_play, rule)
        chosen = found
    chosen.status = "chosen"
    assert chosen.fit is not None and chosen.quality is not None
    notes = []
    warn = chosen.quality.warning(chosen.name)
    if warn:
        notes.append(warn)
    if chosen.k == steady.n_velocities:
        notes.append(
            f"{chosen.name} has as many parameters as distinct velocities ({chosen.k}): it "
            "passes through their means, its shape between and beyond them is not tested"
        )
    table = {
        c.name: {
            "k": c.k,
            "aicc": c.aicc if math.isfinite(c.aicc) else None,
            "reduced_chi2": None if c.quality is None or not math.isfinite(c.quality.reduced_chi2)
            else c.quality.reduced_chi2,
            "status": c.status,
        }
        for c in cands
    }
    return LawChoice(chosen.name, chosen.fit, chosen.quality, rule, table, tuple(notes))
