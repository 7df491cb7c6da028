"""Where do model and measurement disagree? Residuals against covariates and in frequency.

For each covariate: the Spearman rank correlation of the normalised residuals with it and a
permutation p-value, and the levels (few distinct values) or quantile ranges (many) whose
mean residual differs significantly from zero. For transients: the residual spectrum.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import scipy.signal
import scipy.stats

__all__ = ["residual_spectrum", "where_analysis"]

_MAX_LEVELS = 10
_N_BINS = 6


def _ranks(values: np.ndarray) -> np.ndarray:
    r = scipy.stats.rankdata(values)
    r = r - r.mean()
    norm = math.sqrt(float(r @ r))
    return r / norm if norm > 0 else r


def _ranges(values: np.ndarray) -> list[tuple[float, float, np.ndarray]]:
    levels = np.unique(values)
    if levels.size <= _MAX_LEVELS:
        return [(float(v), float(v), values == v) for v in levels]
    edges = np.unique(np.quantile(values, np.linspace(0.0, 1.0, _N_BINS + 1)))
    out = []
    for i in range(edges.size - 1):
        last = i == edges.size - 2
        sel = (values >= edges[i]) & ((values <= edges[i + 1]) if last else (values < edges[i + 1]))
        if sel.any():
            out.append((float(edges[i]), float(edges[i + 1]), sel))
    return out


def where_analysis(
    residual: np.ndarray,
    covariates: pd.DataFrame,
    *,
    n_permutations: int = 999,
    alpha: float = 0.01,
    rng: int | np.random.Generator | None = None,
) -> dict:
    """Residual structure against every numeric covariate.

    Parameters
    ----------
    residual : (n,) ndarray
        Normalised residuals, ``(y - prediction) / sigma`` (held-out predictions).
    covariates : pandas.DataFrame
        n rows; non-numeric and constant columns are skipped.
    n_permutations : int
        Permutations of the residuals for the p-value of each rank correlation.
    alpha : float
        Family-wise significance level; Bonferroni over the covariates (correlations) and
        over all ranges of all covariates (range means).
    rng : int, Generator or None
        Seed of the permutations.

    Returns
    -------
    dict
        ``covariates``: one entry per covariate, strongest first, with ``name``,
        ``spearman_rho``, ``p_value``, ``significant`` and ``ranges`` (``lower``, ``upper``,
        ``n``, ``mean_residual``, ``z``, ``significant``); ``significant``: names of the
        covariates with a significant correlation or range; ``alpha``.

    Notes
    -----
    A range's ``z`` is its mean residual times sqrt(n) (residuals in units of sigma); rows
    of one group share model errors, so z overstates significance for structure within
    groups and the correlations carry the main weight.

    Examples
    --------
    >>> x = np.linspace(0, 1, 200)
    >>> out = where_analysis(3 * (x - 0.5), pd.DataFrame({"x": x}), rng=0)
    >>> out["significant"], out["covariates"][0]["spearman_rho"]
    (['x'], 1.0)
    """
    residual = np.asarray(residual, float)
    gen = np.random.default_rng(rng)
    names, columns = [], []
    for col in covariates.columns:
        values = pd.to_numeric(covariates[col], errors="coerce").to_numpy(float)
        if np.all(np.isfinite(values)) and np.ptp(values) > 0:
            names.append(str(col))
            columns.append(values)
    if not names:
        return {"covariates": [], "significant": [], "alpha": alpha}
    rr = _ranks(residual)
    cov_ranks = np.column_stack([_ranks(c) for c in columns])
    rho = rr @ cov_ranks
    perm = np.array([rr[gen.permutation(rr.size)] for _ in range(n_permutations)])
    rho_perm = perm @ cov_ranks
    exceed = (np.abs(rho_perm) >= np.abs(rho)[None, :] - 1e-12).sum(axis=0)
    p_value = (1.0 + exceed) / (n_permutations + 1.0)
    all_ranges = [_ranges(c) for c in columns]
    n_ranges = sum(len(r) for r in all_ranges)
    z_crit = float(scipy.stats.norm.isf(alpha / (2.0 * max(n_ranges, 1))))
    entries = []
    for j, name in enumerate(names):
        ranges = []
        for lo, hi, sel in all_ranges[j]:
            m = float(residual[sel].mean())
            z = m * math.sqrt(int(sel.sum()))
            ranges.append(
                {
                    "lower": lo,
                    "upper": hi,
                    "n": int(sel.sum()),
                    "mean_residual": m,
                    "z": z,
                    "significant": bool(abs(z) > z_crit),
                }
            )
        sig_corr = bool(p_value[j] <= alpha / len(names))
        entries.append(
            {
                "name": name,
                "spearman_rho": float(np.round(rho[j], 12)),
                "p_value": float(p_value[j]),
                "significant_correlation": sig_corr,
                "significant": sig_corr or any(r["significant"] for r in ranges),
                "ranges": ranges,
            }
        )
    entries.sort(key=lambda e: (-abs(e["spearman_rho"]), e["name"]))
    return {
        "covariates": entries,
        "significant": [e["name"] for e in entries if e["significant"]],
        "alpha": alpha,
    }


def residual_spectrum(residual: np.ndarray, time_s: np.ndarray, groups: np.ndarray) -> dict:
    """Mean periodogram of the residuals over the runs, its peak and Fisher's g-test.

    Parameters
    ----------
    residual : (n,) ndarray
        Normalised residuals.
    time_s : (n,) ndarray
        Time of each sample, s (uniformly sampled within a run).
    groups : (n,) ndarray
        Run of each sample.

    Returns
    -------
    dict
        ``frequency_Hz`` and ``power`` (lists, the mean periodogram on the frequencies of
        the longest run), ``peak_Hz``, ``peak_share`` (Fisher's g: the peak's share of the
        total power) and ``p_value`` (Fisher's test that the peak is white noise).

    Examples
    --------
    >>> t = np.arange(2000) / 1000.0
    >>> out = residual_spectrum(np.sin(2 * np.pi * 50 * t), t, np.zeros(2000))
    >>> round(out["peak_Hz"], 3), out["p_value"] < 1e-6
    (50.0, True)
    """
    residual = np.asarray(residual, float)
    time_s = np.asarray(time_s, float)
    groups = np.asarray(groups)
    runs = []
    for g in np.unique(groups):
        sel = groups == g
        order = np.argsort(time_s[sel])
        t, r = time_s[sel][order], residual[sel][order]
        if t.size >= 8:
            runs.append((t, r))
    if not runs:
        raise ValueError("residual_spectrum needs at least one run with 8 or more samples")
    t_ref, _ = max(runs, key=lambda tr: tr[0].size)
    fs = 1.0 / float(np.median(np.diff(t_ref)))
    freq, _ = scipy.signal.periodogram(np.zeros(t_ref.size), fs=fs)
    total = np.zeros(freq.size)
    for t, r in runs:
        f_run, p_run = scipy.signal.periodogram(r, fs=1.0 / float(np.median(np.diff(t))))
        total += np.interp(freq, f_run, p_run)
    power = total / len(runs)
    body = power[1:]
    i = int(np.argmax(body))
    g = float(body[i] / body.sum()) if body.sum() > 0 else 0.0
    m = body.size
    p = min(1.0, m * (1.0 - g) ** (m - 1)) if g > 0 else 1.0
    return {
        "frequency_Hz": freq.tolist(),
        "power": power.tolist(),
        "peak_Hz": float(freq[1:][i]),
        "peak_share": g,
        "p_value": float(p),
    }
