"""Repeated measurements of a characteristic: velocity levels and the replicate noise.

Repeated runs at one velocity measure the noise without any model: the pooled scatter of
the repeats about their own mean (the "pure error" of a lack-of-fit test). Both the law
choice of the calibration (:mod:`friction_model.identification.law_choice`) and the
discrepancy workflow's steady problem read a characteristic's noise from here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["replicate_noise", "value_levels", "velocity_levels"]

# velocity levels: a new level where v exceeds the previous by more than max(5 %, 0.02 m/s),
# the grouping of repeats that friction_model.rig.aggregate_runs uses
_LEVEL_REL_TOL = 0.05
_LEVEL_ABS_TOL_MPS = 0.02


def value_levels(
    values: Sequence[float] | np.ndarray, *, rel_tol: float, abs_tol: float
) -> np.ndarray:
    """Index of the level of every value: sorted, a new level starts where a value exceeds
    the previous one by more than ``max(rel_tol |x|, abs_tol)``.

    Examples
    --------
    >>> value_levels([-4.01, -1.0, -3.99, -4.0], rel_tol=0.0, abs_tol=0.5).tolist()
    [0, 1, 0, 0]
    """
    x = np.asarray(values, dtype=float).ravel()
    order = np.argsort(x, kind="stable")
    xs = x[order]
    step = np.diff(xs) > np.maximum(rel_tol * np.abs(xs[:-1]), abs_tol)
    levels = np.empty(x.size, dtype=int)
    levels[order] = np.concatenate([[0], np.cumsum(step)]) if x.size else []
    return levels


def velocity_levels(velocity_mps: Sequence[float] | np.ndarray) -> np.ndarray:
    """Index of the velocity level of every point (repeats at one velocity share it).

    Sorted by velocity, a new level starts where the velocity exceeds the previous point's
    by more than ``max(0.05 v, 0.02 m/s)`` (the grouping of
    :func:`friction_model.rig.aggregate_runs`).

    Examples
    --------
    >>> velocity_levels([3.0, 1.0, 1.001, 3.02, 5.0]).tolist()
    [1, 0, 0, 1, 2]
    """
    return value_levels(velocity_mps, rel_tol=_LEVEL_REL_TOL, abs_tol=_LEVEL_ABS_TOL_MPS)


def replicate_noise(mu: np.ndarray, groups: np.ndarray) -> tuple[float, int]:
    """Pooled replicate standard deviation of ``mu`` and its degrees of freedom.

    ``s^2 = sum_g sum_i (mu_gi - mean_g)^2 / (n - G)``: the scatter of repeated
    measurements about their own mean, which no friction law enters (the "pure error" of a
    lack-of-fit test).

    Parameters
    ----------
    mu : (n,) ndarray
        Friction coefficients.
    groups : (n,) ndarray
        Replicate group of each point (same specimen, condition and velocity).

    Returns
    -------
    sigma : float
        The pooled standard deviation (NaN without a repeat or when every repeat is equal).
    dof : int
        ``n - G``, 0 without a repeat.

    Examples
    --------
    >>> s, dof = replicate_noise(np.array([1.0, 3.0, 10.0, 12.0]), np.array([0, 0, 1, 1]))
    >>> round(s, 12), dof  # each pair scatters by sqrt(2) about its mean
    (1.414213562373, 2)
    """
    mu = np.asarray(mu, dtype=float)
    _, inverse = np.unique(np.asarray(groups), return_inverse=True)
    inverse = inverse.ravel()
    n_groups = int(inverse.max()) + 1 if inverse.size else 0
    dof = int(mu.size - n_groups)
    if dof <= 0:
        return math.nan, 0
    means = np.bincount(inverse, weights=mu, minlength=n_groups) / np.bincount(inverse)
    ss = float(np.sum((mu - means[inverse]) ** 2))
    return (math.sqrt(ss / dof) if ss > 0 else math.nan), dof
