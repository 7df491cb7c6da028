"""Private numerical helpers for :mod:`friction_model.contact.laws`.

The array check shared by the friction laws, batched weighted linear least squares (used for the
exact fit of laws that are linear in their parameters and for grid-based starting values of the
separable nonlinear laws), the Gauss-Newton covariance (and standard errors) of a least-squares
estimate and the
nonlinear refinement with :func:`scipy.optimize.least_squares`.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from scipy.optimize import least_squares

__all__ = [
    "Refined",
    "as_float_array",
    "covariance_from_jacobian",
    "covariance_with_stderr",
    "grid_local_minima",
    "refine_nonlinear",
    "weighted_lstsq_batched",
]


def as_float_array(name: str, value: object, *, finite: bool = True) -> np.ndarray:
    """Convert ``value`` to a float64 array, optionally rejecting NaN and infinity.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like
        Numbers to convert.
    finite : bool
        If True (default), raise when any element is NaN or infinite.

    Returns
    -------
    ndarray
        ``numpy.asarray(value, dtype=float)``.

    Raises
    ------
    TypeError
        If ``value`` cannot be converted to floats.
    ValueError
        If ``finite`` and an element is NaN or infinite.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be array_like of real numbers, got {value!r}") from exc
    if finite:
        bad = ~np.isfinite(arr)
        if bad.any():
            raise ValueError(
                f"{name} must be finite, got {int(bad.sum())} non-finite value(s) "
                f"(NaN or inf) out of {arr.size}"
            )
    return arr


def weighted_lstsq_batched(
    X: np.ndarray, y: np.ndarray, sqrt_w: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Solve a stack of weighted linear least-squares problems.

    Parameters
    ----------
    X : (G, N, L) ndarray
        Design matrices, one per candidate ``G``.
    y : (G, N) or (N,) ndarray
        Targets.
    sqrt_w : (N,) ndarray
        Square roots of the weights (``1 / sigma``).

    Returns
    -------
    theta : (G, L) ndarray
        Minimum-norm solutions, so collinear columns are tolerated. A single problem (G = 1)
        is solved by SVD of the design (accurate to rounding); a stack of candidates through
        the pseudo-inverse of the normal matrices (fast, accurate enough to rank candidates).
    sse : (G,) ndarray
        Weighted sums of squared residuals; ``inf`` where the candidate gave non-finite values.
    """
    Xw = np.ascontiguousarray(np.moveaxis(X * sqrt_w[:, None], 2, 1))  # (G, L, N)
    yw = np.broadcast_to(y * sqrt_w, X.shape[:2])
    finite = np.isfinite(Xw).all(axis=(1, 2)) & np.isfinite(yw).all(axis=1)
    if not finite.all():
        Xw = np.where(finite[:, None, None], Xw, 0.0)
        yw = np.where(finite[:, None], yw, 0.0)
    if X.shape[2] == 0:
        theta = np.zeros((X.shape[0], 0))
    elif X.shape[0] == 1:
        theta = np.linalg.lstsq(Xw[0].T, yw[0], rcond=None)[0][None, :]
    else:
        gram = Xw @ np.swapaxes(Xw, 1, 2)
        theta = (np.linalg.pinv(gram) @ (Xw @ yw[:, :, None]))[:, :, 0]
    resid = yw - (theta[:, None, :] @ Xw)[:, 0, :]
    sse = np.sum(resid * resid, axis=1)
    return theta, np.where(finite, sse, np.inf)


def covariance_from_jacobian(J: np.ndarray, *, scale: float, names: tuple[str, ...]) -> np.ndarray:
    """Gauss-Newton covariance ``scale * (J^T J)^-1`` of a least-squares estimate.

    Parameters
    ----------
    J : (N, K) ndarray
        Jacobian of the weighted residuals with respect to the free parameters at the solution.
    scale : float
        Residual variance factor (``chi2 / dof``) or 1 for absolute sigma.
    names : tuple of str
        Free parameter names, for the warning message.

    Returns
    -------
    (K, K) ndarray
        The covariance; filled with ``inf`` (with a warning) when ``J`` is rank deficient,
        i.e. when the data cannot determine the parameters separately.
    """
    k = J.shape[1]
    _, s, vt = np.linalg.svd(J, full_matrices=False)
    threshold = np.finfo(float).eps * max(J.shape) * (s[0] if s.size else 0.0)
    if s.size < k or not np.all(s > threshold):
        warnings.warn(
            f"covariance of the fitted parameters {names} could not be estimated: the data do "
            "not determine them separately (rank-deficient Jacobian); stderr set to inf",
            UserWarning,
            stacklevel=3,
        )
        return np.full((k, k), np.inf)
    vs = vt.T / s
    return scale * (vs @ vs.T)


def covariance_with_stderr(
    J: np.ndarray, *, scale: float, names: tuple[str, ...], undetermined: str
) -> tuple[np.ndarray, np.ndarray]:
    """Covariance (:func:`covariance_from_jacobian`) and standard errors of an estimate.

    Parameters
    ----------
    J, scale, names
        As for :func:`covariance_from_jacobian`.
    undetermined : str
        The warning (``UserWarning``, attributed to the caller of the calling fit) given
        instead of the generic one when the data do not determine the parameters separately.

    Returns
    -------
    cov : (K, K) ndarray
        The covariance, ``inf`` throughout when undetermined.
    stderr : (K,) ndarray
        Square roots of its diagonal (negative round-off clipped to 0).
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cov = covariance_from_jacobian(J, scale=scale, names=names)
    if not np.all(np.isfinite(cov)):
        warnings.warn(undetermined, UserWarning, stacklevel=3)
    return cov, np.sqrt(np.clip(np.diag(cov), 0.0, np.inf))


class Refined(NamedTuple):
    """Outcome of :func:`refine_nonlinear`."""

    x: np.ndarray
    jac: np.ndarray
    cost: float
    converged: bool
    nfev: int


def refine_nonlinear(
    residuals: Callable[[np.ndarray], np.ndarray], x0: np.ndarray, *, law_name: str
) -> Refined:
    """Minimise ``sum(residuals(x)**2)`` by Levenberg-Marquardt from ``x0``.

    Parameters
    ----------
    residuals : callable
        Weighted residual vector as a function of the free parameters.
    x0 : (K,) ndarray
        Starting values.
    law_name : str
        For the error message.

    Returns
    -------
    Refined
        ``x`` the solution, ``jac`` the finite-difference Jacobian of ``residuals`` there,
        ``cost`` the sum of squared residuals, ``converged`` False when the optimiser stopped at
        its evaluation limit (typical of parameters the data hardly determine; ``x`` is then the
        last iterate), ``nfev`` the number of evaluations.

    Raises
    ------
    RuntimeError
        If the optimiser fails or returns non-finite values.
    """
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        res = least_squares(
            residuals, x0, method="lm", x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12
        )
    if res.status < 0 or not np.all(np.isfinite(res.x)) or not np.all(np.isfinite(res.fun)):
        raise RuntimeError(f"fit of {law_name} did not converge: {res.message}")
    return Refined(
        x=np.asarray(res.x, dtype=float),
        jac=np.asarray(res.jac, dtype=float),
        cost=float(np.sum(res.fun**2)),
        converged=res.status > 0,
        nfev=int(res.nfev),
    )


def grid_local_minima(sse: np.ndarray, *, limit: int) -> np.ndarray:
    """Flat indices of the local minima of a gridded objective, best first.

    Parameters
    ----------
    sse : ndarray
        Objective on a grid (one axis per parameter); ``inf`` marks invalid candidates.
    limit : int
        At most this many indices are returned.

    Returns
    -------
    (M,) ndarray of int
        Indices into ``sse.ravel()`` of the cells not larger than any axis neighbour, sorted by
        ``sse``; the global minimum is always first. Empty if every cell is ``inf``.
    """
    is_min = np.isfinite(sse)
    for axis in range(sse.ndim):
        pad = [(0, 0)] * sse.ndim
        pad[axis] = (1, 1)
        padded = np.pad(sse, pad, constant_values=np.inf)
        lower = np.take(padded, np.arange(0, sse.shape[axis]), axis=axis)
        upper = np.take(padded, np.arange(2, sse.shape[axis] + 2), axis=axis)
        is_min &= (sse <= lower) & (sse <= upper)
    flat = np.flatnonzero(is_min.ravel())
    return flat[np.argsort(sse.ravel()[flat], kind="stable")][:limit]
