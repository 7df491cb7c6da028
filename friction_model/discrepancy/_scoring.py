"""Scores and resampling by group: chi-square, folds and block bootstrap.

The information criteria (AICc, BIC) are in :mod:`friction_model.model_selection`.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "block_bootstrap_weights",
    "chi_square",
    "group_folds",
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
