"""Scores and resampling by group: chi-square, AICc, BIC, folds and block bootstrap."""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "aicc",
    "bic",
    "block_bootstrap_weights",
    "chi_square",
    "group_folds",
    "reduced_chi_square",
]


def chi_square(
    y: np.ndarray, prediction: np.ndarray, sigma: np.ndarray, weights: np.ndarray | None = None
) -> float:
    """Weighted sum of squared normalised residuals, ``sum w ((y - f) / sigma)^2``.

    Examples
    --------
    >>> chi_square(np.array([1.0, 2.0]), np.array([0.0, 2.0]), np.array([0.5, 1.0]))
    4.0
    """
    r = (np.asarray(y, float) - np.asarray(prediction, float)) / np.asarray(sigma, float)
    if weights is None:
        return float(r @ r)
    return float(np.asarray(weights, float) @ (r * r))


def aicc(chi2: float, k: int, n: int) -> float:
    """Corrected Akaike criterion for Gaussian errors of known sigma.

    ``AICc = chi2 + 2 k + 2 k (k + 1) / (n - k - 1)`` (``-2 ln L = chi2`` up to a constant
    that cancels in every comparison on the same data).

    Examples
    --------
    >>> round(aicc(10.0, 2, 13), 12)
    15.2
    """
    if n - k - 1 <= 0:
        return math.inf
    return float(chi2 + 2.0 * k + 2.0 * k * (k + 1) / (n - k - 1))


def bic(chi2: float, k: int, n: int) -> float:
    """Bayesian information criterion for Gaussian errors of known sigma, ``chi2 + k ln n``.

    Examples
    --------
    >>> round(bic(10.0, 2, 100), 6)
    19.21034
    """
    return float(chi2 + k * math.log(n))


def reduced_chi_square(chi2: float, n: int, k: int = 0) -> float:
    """``chi2 / (n - k)`` (NaN when n <= k)."""
    return float(chi2 / (n - k)) if n > k else math.nan


def group_folds(groups: np.ndarray, n_folds: int, rng: np.random.Generator) -> np.ndarray:
    """Fold number (0..n_folds-1) of every row; whole groups go to one fold.

    Groups are shuffled and dealt out in turn, so folds differ by at most one group.

    Examples
    --------
    >>> f = group_folds(np.array([0, 0, 1, 1, 2, 2]), 3, np.random.default_rng(0))
    >>> sorted(set(f.tolist())), bool(f[0] == f[1])
    ([0, 1, 2], True)
    """
    labels, inverse = np.unique(np.asarray(groups), return_inverse=True)
    n_folds = int(min(n_folds, labels.size))
    if n_folds < 2:
        raise ValueError(f"hold-out needs at least 2 groups, got {labels.size}")
    order = rng.permutation(labels.size)
    fold_of_group = np.empty(labels.size, dtype=int)
    fold_of_group[order] = np.arange(labels.size) % n_folds
    return fold_of_group[inverse.ravel()]


def block_bootstrap_weights(
    groups: np.ndarray, n_resamples: int, rng: np.random.Generator
) -> np.ndarray:
    """Row weights of a block bootstrap: groups drawn with replacement, (B, n) counts.

    Each resample draws as many groups as there are, with replacement; a row's weight is
    how often its group was drawn (0 when not drawn).

    Examples
    --------
    >>> w = block_bootstrap_weights(np.array([0, 0, 1]), 4, np.random.default_rng(1))
    >>> w.shape, bool(np.all(w[:, 0] == w[:, 1]))
    ((4, 3), True)
    """
    labels, inverse = np.unique(np.asarray(groups), return_inverse=True)
    draws = rng.integers(0, labels.size, size=(n_resamples, labels.size))
    counts = np.zeros((n_resamples, labels.size))
    for b in range(n_resamples):
        counts[b] = np.bincount(draws[b], minlength=labels.size)
    return counts[:, inverse.ravel()]
