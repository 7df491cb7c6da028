"""Friction characteristics mu(v) of rubber on ice, their least-squares fits and relaxation.

Every law is a frozen dataclass holding its parameters and deriving from :class:`FrictionLaw`:
it is called as ``law(v_rel_mps, pressure_Pa=..., temperature_C=...)`` (numpy-vectorised over
the sliding velocity) and fitted with :func:`fit_law` or ``LawClass.fit``, which return a
:class:`FitResult` with the fitted law, standard errors and covariance. :class:`RelaxedFriction`
adds the first-order time lag of Eq. 5.12 to any law.

- :class:`ConstantLaw`, Eq. 5.4: mu = mu0 (Coulomb, F_F = mu F_N)
- :class:`DecreasingSqrtLaw`, Eq. 4.8: mu = A_D |v|^-0.5 + B_D
- :class:`IncreasingSqrtLaw`, Eq. 4.9: mu = A_I |v|^0.5 + B_I
- :class:`ExponentialLaw`, Eq. 5.7: mu = a1 + a2 exp(a3 |v|)
- :class:`ArctanExponentialLaw`, Eq. 5.24: mu = (k1 + k2 exp(k3 |v|)) (2/pi) arctan(k4 v)
- :class:`VenkateshLaw`, Eq. 2.4: 1/mu = A (1 + B p / E0)

Notes
-----
Units: velocities in m/s, pressures in Pa, temperatures in degrees Celsius, times in s; the
friction coefficient is dimensionless. Equation numbers refer to the thesis this project
implements (rubber-ice friction of winter-tyre tread blocks).

Sign convention: Eq. 5.24 is odd in v and gives a signed coefficient, so it serves negative
sliding velocities and stick-slip. All other laws give the magnitude of the coefficient as a
function of the sliding speed |v| (they are even in v; Eq. 4.8, 4.9 and 5.7 are written in the
thesis for v >= 0, where |v| = v); the direction of the friction force is left to the caller.
"""

from __future__ import annotations

import abc
import inspect
import logging
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from friction_model._fitting import (
    as_float_array,
    covariance_from_jacobian,
    grid_local_minima,
    refine_nonlinear,
    weighted_lstsq_batched,
)
from tir_common.validate import check_real

logger = logging.getLogger(__name__)

__all__ = [
    "ArctanExponentialLaw",
    "ConstantLaw",
    "DecreasingSqrtLaw",
    "ExponentialLaw",
    "FitResult",
    "FrictionLaw",
    "IncreasingSqrtLaw",
    "RelaxedFriction",
    "VenkateshLaw",
    "fit_law",
]

#: Data points used for the grid search of starting values (the refinement uses all points).
_N_START = 512
#: Local minima of the starting-value grid refined by Levenberg-Marquardt; the best fit wins.
_N_STARTS = 3


def _velocity_scale(v: np.ndarray) -> float:
    """Largest sliding speed in ``v`` (m/s), or 1 when all are zero; sets the grid scales."""
    vmax = float(np.max(np.abs(v))) if v.size else 0.0
    return vmax if vmax > 0 else 1.0


class FrictionLaw(abc.ABC):
    """Base class of the friction characteristics mu(v).

    Subclasses are frozen dataclasses whose fields are the parameters listed in
    :attr:`param_names`; they are validated at construction.

    Attributes
    ----------
    param_names : tuple of str
        Parameter names, in the order of the dataclass fields.
    equation : str
        Equation number in the thesis, e.g. ``"Eq. 4.8"``.

    Notes
    -----
    A new law is a ``@dataclass(frozen=True)`` subclass with its parameters as fields, the class
    attributes ``param_names`` and ``equation``, and the classmethod
    ``_formula(v, theta, pressure)`` (the formula for parameter values ``theta`` in
    ``param_names`` order), which both :meth:`mu` and :func:`fit_law` use. Optional hooks:
    ``_rules`` (per-parameter "> 0" / ">= 0"), ``_check_v`` (undefined velocities),
    ``_needs_pressure``; for automatic starting values ``_linear`` with ``_basis`` (parameters
    entering linearly and their columns) and ``_grid`` (candidates of the others), or
    ``_start``; without them, fits need a full ``p0``.
    """

    param_names: ClassVar[tuple[str, ...]]
    equation: ClassVar[str]
    #: Parameters that enter mu linearly (for exact linear fits and separable start values).
    _linear: ClassVar[tuple[str, ...]] = ()
    #: Rule each parameter must obey besides being finite ("> 0" or ">= 0").
    _rules: ClassVar[Mapping[str, str]] = {}
    #: Parameters the data cannot determine; they must be passed in ``fixed`` when fitting.
    _must_fix: ClassVar[Mapping[str, str]] = {}
    #: Whether mu depends on pressure (then pressure_Pa is required).
    _needs_pressure: ClassVar[bool] = False

    def __post_init__(self) -> None:
        for name in self.param_names:
            value = check_real(name, getattr(self, name), rule=self._rules.get(name, "finite"))
            object.__setattr__(self, name, value)

    # -- evaluation -------------------------------------------------------------------------
    @classmethod
    @abc.abstractmethod
    def _formula(
        cls, v: np.ndarray, theta: Sequence[Any], pressure: np.ndarray | None
    ) -> np.ndarray:
        """The law's formula for parameter values ``theta`` (in ``param_names`` order)."""

    @classmethod
    def _check_v(cls, v: np.ndarray) -> None:
        """Raise ValueError if the law is undefined at a velocity in ``v`` (default: never)."""
        return None

    @classmethod
    def _pressure(cls, pressure_Pa: ArrayLike | None) -> np.ndarray | None:
        """Validated pressure array for pressure-dependent laws, None for the others."""
        if not cls._needs_pressure:
            return None
        if pressure_Pa is None:
            raise ValueError(
                f"{cls.__name__} needs pressure_Pa ({cls.equation} is pressure-dependent), "
                "got pressure_Pa=None"
            )
        p = as_float_array("pressure_Pa", pressure_Pa)
        if np.any(p < 0):
            raise ValueError(f"pressure_Pa must be >= 0, got min(pressure_Pa)={float(p.min()):g}")
        return p

    def mu(
        self,
        v_rel_mps: ArrayLike,
        *,
        pressure_Pa: ArrayLike | None = None,
        temperature_C: ArrayLike | None = None,
    ) -> np.ndarray | float:
        """Friction coefficient at the relative sliding velocity ``v_rel_mps``.

        Parameters
        ----------
        v_rel_mps : float or ndarray
            Relative sliding velocity, m/s. NaN propagates to the result.
        pressure_Pa : float or ndarray, optional
            Normal pressure, Pa (broadcast against ``v_rel_mps``); required by pressure-dependent
            laws (:class:`VenkateshLaw`), ignored by the others.
        temperature_C : float or ndarray, optional
            Temperature, degrees Celsius; accepted for a uniform interface and ignored by all
            laws in this module.

        Returns
        -------
        float or ndarray
            Friction coefficient (dimensionless); a float for scalar input, else an array of the
            broadcast shape.
        """
        v = as_float_array("v_rel_mps", v_rel_mps, finite=False)
        self._check_v(v)
        pressure = self._pressure(pressure_Pa)
        out = np.asarray(self._formula(v, self._values(), pressure), dtype=float)
        return float(out) if out.ndim == 0 else out

    def __call__(
        self,
        v_rel_mps: ArrayLike,
        *,
        pressure_Pa: ArrayLike | None = None,
        temperature_C: ArrayLike | None = None,
    ) -> np.ndarray | float:
        """Same as :meth:`mu`."""
        return self.mu(v_rel_mps, pressure_Pa=pressure_Pa, temperature_C=temperature_C)

    @property
    def params(self) -> dict[str, float]:
        """Parameter values by name, in :attr:`param_names` order."""
        return {name: getattr(self, name) for name in self.param_names}

    def _values(self) -> tuple[float, ...]:
        return tuple(getattr(self, name) for name in self.param_names)

    # -- fitting hooks ----------------------------------------------------------------------
    @classmethod
    def _basis(
        cls, v: np.ndarray, nonlinear: Mapping[str, Any], pressure: np.ndarray | None
    ) -> tuple[np.ndarray, ...]:
        """Columns multiplying the linear parameters ``_linear`` given the nonlinear ones.

        Only called for laws that declare ``_linear`` parameters; such a law must override it.
        """
        raise TypeError(
            f"{cls.__name__} declares linear parameters {cls._linear} but no _basis; "
            "override _basis or leave _linear empty"
        )

    @classmethod
    def _grid(cls, v: np.ndarray) -> dict[str, np.ndarray]:
        """Candidate values of the nonlinear parameters for the starting-value search."""
        return {}

    @classmethod
    def _start(
        cls,
        v: np.ndarray,
        mu: np.ndarray,
        sqrt_w: np.ndarray,
        pressure: np.ndarray | None,
        fixed: Mapping[str, float],
        *,
        n_starts: int = 1,
    ) -> list[dict[str, float]]:
        """Starting values of all parameters (exact least squares if the free ones are linear).

        For each candidate of the free nonlinear parameters (a grid from :meth:`_grid`) the
        linear ones are solved by weighted linear least squares (variable projection). Returns
        the candidates at the best ``n_starts`` local minima of the weighted residual over the
        grid, best first.
        """
        nonlinear_free = [n for n in cls.param_names if n not in cls._linear and n not in fixed]
        grid = cls._grid(v)
        missing = [n for n in nonlinear_free if n not in grid]
        if missing:
            raise ValueError(
                f"{cls.__name__} has no automatic starting values for {missing}; pass p0"
            )
        axes = np.meshgrid(*(grid[n] for n in nonlinear_free), indexing="ij")
        n_cand = axes[0].size if axes else 1
        nonlinear: dict[str, Any] = {
            n: fixed[n] for n in cls.param_names if n not in cls._linear and n in fixed
        }
        nonlinear.update({n: a.reshape(-1, 1) for n, a in zip(nonlinear_free, axes, strict=True)})
        with np.errstate(over="ignore", invalid="ignore"):
            cols = [
                np.broadcast_to(c, (n_cand, v.size)) for c in cls._basis(v, nonlinear, pressure)
            ]
        target = mu - sum(
            (fixed[n] * c for n, c in zip(cls._linear, cols, strict=True) if n in fixed),
            start=np.zeros(v.size),
        )
        free_idx = [i for i, n in enumerate(cls._linear) if n not in fixed]
        if free_idx:
            X = np.stack([cols[i] for i in free_idx], axis=-1)
        else:
            X = np.zeros((n_cand, v.size, 0))
        theta, sse = weighted_lstsq_batched(X, target, sqrt_w)
        grid_shape = tuple(len(grid[n]) for n in nonlinear_free)
        best = grid_local_minima(sse.reshape(grid_shape), limit=n_starts)
        if best.size == 0:
            raise RuntimeError(f"no finite starting values found for {cls.__name__}")
        starts = []
        for g in best:
            start = {n: float(fixed[n]) for n in fixed}
            start.update(
                {n: float(a.ravel()[g]) for n, a in zip(nonlinear_free, axes, strict=True)}
            )
            start.update({cls._linear[i]: float(theta[g, j]) for j, i in enumerate(free_idx)})
            starts.append(start)
        return starts

    @classmethod
    def fit(
        cls,
        v_rel_mps: ArrayLike,
        mu: ArrayLike,
        *,
        sigma: ArrayLike | None = None,
        p0: Mapping[str, float] | Sequence[float] | None = None,
        pressure_Pa: ArrayLike | None = None,
        fixed: Mapping[str, float] | None = None,
        absolute_sigma: bool | None = None,
    ) -> FitResult:
        """Fit this law to data; see :func:`fit_law` for the parameters."""
        return fit_law(
            cls,
            v_rel_mps,
            mu,
            sigma=sigma,
            p0=p0,
            pressure_Pa=pressure_Pa,
            fixed=fixed,
            absolute_sigma=absolute_sigma,
        )


@dataclass(frozen=True)
class ConstantLaw(FrictionLaw):
    """Velocity-independent (Coulomb) friction coefficient, F_F = mu F_N (Eq. 5.4).

    Parameters
    ----------
    mu0 : float
        Friction coefficient, dimensionless, >= 0.

    Examples
    --------
    >>> ConstantLaw(0.3)([0.5, 2.0])
    array([0.3, 0.3])
    """

    mu0: float

    param_names: ClassVar[tuple[str, ...]] = ("mu0",)
    equation: ClassVar[str] = "Eq. 5.4"
    _linear: ClassVar[tuple[str, ...]] = ("mu0",)
    _rules: ClassVar[Mapping[str, str]] = {"mu0": ">= 0"}

    @classmethod
    def _formula(
        cls, v: np.ndarray, theta: Sequence[Any], pressure: np.ndarray | None
    ) -> np.ndarray:
        (mu0,) = theta
        return np.full_like(v, mu0, dtype=float)

    @classmethod
    def _basis(
        cls, v: np.ndarray, nonlinear: Mapping[str, Any], pressure: np.ndarray | None
    ) -> tuple[np.ndarray, ...]:
        return (np.ones_like(v),)


@dataclass(frozen=True)
class DecreasingSqrtLaw(FrictionLaw):
    """Decreasing square-root characteristic, mu = A_D |v|^-0.5 + B_D (Eq. 4.8).

    Fits the cold, dry characteristic (T = -5 degC, rF < 50 %) of Table 4.6.

    Parameters
    ----------
    A_D : float
        Coefficient of |v|^-0.5, (m/s)^0.5; A_D > 0 gives a decreasing characteristic.
    B_D : float
        Asymptotic friction coefficient at high speed, dimensionless.

    Notes
    -----
    Undefined at v = 0 (mu diverges): evaluating or fitting at v_rel_mps = 0 raises ValueError.
    The law is even in v (it uses the sliding speed |v|).

    Examples
    --------
    Table 4.6, G3 at p = 2.5 bar, T = -5 degC:

    >>> law = DecreasingSqrtLaw(A_D=0.2, B_D=0.095)
    >>> round(law(1.0), 12), round(law(4.0), 12)
    (0.295, 0.195)
    """

    A_D: float
    B_D: float

    param_names: ClassVar[tuple[str, ...]] = ("A_D", "B_D")
    equation: ClassVar[str] = "Eq. 4.8"
    _linear: ClassVar[tuple[str, ...]] = ("A_D", "B_D")

    @classmethod
    def _check_v(cls, v: np.ndarray) -> None:
        if np.any(v == 0):
            raise ValueError(
                "v_rel_mps must be non-zero for DecreasingSqrtLaw (Eq. 4.8: mu ~ |v|^-0.5 "
                f"diverges at v = 0), got {int(np.count_nonzero(v == 0))} zero value(s)"
            )

    @classmethod
    def _formula(
        cls, v: np.ndarray, theta: Sequence[Any], pressure: np.ndarray | None
    ) -> np.ndarray:
        a_d, b_d = theta
        return a_d / np.sqrt(np.abs(v)) + b_d

    @classmethod
    def _basis(
        cls, v: np.ndarray, nonlinear: Mapping[str, Any], pressure: np.ndarray | None
    ) -> tuple[np.ndarray, ...]:
        return (1.0 / np.sqrt(np.abs(v)), np.ones_like(v))


@dataclass(frozen=True)
class IncreasingSqrtLaw(FrictionLaw):
    """Increasing square-root characteristic, mu = A_I |v|^0.5 + B_I (Eq. 4.9).

    Fits the warm, humid characteristic (T = -1 degC, rF > 90 %) of Table 4.6.

    Parameters
    ----------
    A_I : float
        Coefficient of |v|^0.5, (m/s)^-0.5; A_I > 0 gives an increasing characteristic.
    B_I : float
        Friction coefficient at v = 0, dimensionless.

    Notes
    -----
    The law is even in v (it uses the sliding speed |v|).

    Examples
    --------
    Table 4.6, G3 at p = 2.5 bar, T = -1 degC:

    >>> law = IncreasingSqrtLaw(A_I=0.03, B_I=0.075)
    >>> round(law(4.0), 12)
    0.135
    """

    A_I: float
    B_I: float

    param_names: ClassVar[tuple[str, ...]] = ("A_I", "B_I")
    equation: ClassVar[str] = "Eq. 4.9"
    _linear: ClassVar[tuple[str, ...]] = ("A_I", "B_I")

    @classmethod
    def _formula(
        cls, v: np.ndarray, theta: Sequence[Any], pressure: np.ndarray | None
    ) -> np.ndarray:
        a_i, b_i = theta
        return a_i * np.sqrt(np.abs(v)) + b_i

    @classmethod
    def _basis(
        cls, v: np.ndarray, nonlinear: Mapping[str, Any], pressure: np.ndarray | None
    ) -> tuple[np.ndarray, ...]:
        return (np.sqrt(np.abs(v)), np.ones_like(v))


@dataclass(frozen=True)
class ExponentialLaw(FrictionLaw):
    """Exponential characteristic, mu = a1 + a2 exp(a3 |v|) (Eq. 5.7, after Ripka et al.).

    Parameters
    ----------
    a1 : float
        Friction coefficient approached at high speed when a3 < 0, dimensionless.
    a2 : float
        Amplitude of the exponential term, dimensionless (mu(0) = a1 + a2).
    a3 : float
        Rate, s/m; negative for a decreasing characteristic.

    Notes
    -----
    Eq. 5.7 is written for v_rel >= 0; this class uses |v| so that it is even in v.

    Examples
    --------
    >>> law = ExponentialLaw(a1=0.15, a2=0.25, a3=-0.8)
    >>> round(law(0.0), 12)
    0.4
    """

    a1: float
    a2: float
    a3: float

    param_names: ClassVar[tuple[str, ...]] = ("a1", "a2", "a3")
    equation: ClassVar[str] = "Eq. 5.7"
    _linear: ClassVar[tuple[str, ...]] = ("a1", "a2")

    @classmethod
    def _formula(
        cls, v: np.ndarray, theta: Sequence[Any], pressure: np.ndarray | None
    ) -> np.ndarray:
        a1, a2, a3 = theta
        return a1 + a2 * np.exp(a3 * np.abs(v))

    @classmethod
    def _basis(
        cls, v: np.ndarray, nonlinear: Mapping[str, Any], pressure: np.ndarray | None
    ) -> tuple[np.ndarray, ...]:
        return (np.ones_like(v), np.exp(nonlinear["a3"] * np.abs(v)))

    @classmethod
    def _grid(cls, v: np.ndarray) -> dict[str, np.ndarray]:
        rate = np.logspace(-2, 1.5, 40) / _velocity_scale(v)
        return {"a3": np.concatenate([-rate[::-1], rate])}


@dataclass(frozen=True)
class ArctanExponentialLaw(FrictionLaw):
    """Signed characteristic mu = (k1 + k2 exp(k3 |v|)) (2/pi) arctan(k4 v) (Eq. 5.24).

    Odd in v, so it covers negative sliding velocities and stick-slip; mu(0) = 0 (the thesis
    accepts this missing static-friction peak).

    Parameters
    ----------
    k1 : float
        Friction coefficient approached at high speed when k3 < 0, dimensionless.
    k2 : float
        Amplitude of the exponential term, dimensionless.
    k3 : float
        Rate of the exponential term, s/m.
    k4 : float
        Steepness of the zero crossing, s/m; must be > 0 so that mu has the sign of v.

    Examples
    --------
    >>> law = ArctanExponentialLaw(k1=0.15, k2=0.3, k3=-0.5, k4=20.0)
    >>> bool(law(-2.0) == -law(2.0))
    True
    """

    k1: float
    k2: float
    k3: float
    k4: float

    param_names: ClassVar[tuple[str, ...]] = ("k1", "k2", "k3", "k4")
    equation: ClassVar[str] = "Eq. 5.24"
    _linear: ClassVar[tuple[str, ...]] = ("k1", "k2")
    _rules: ClassVar[Mapping[str, str]] = {"k4": "> 0"}

    @classmethod
    def _formula(
        cls, v: np.ndarray, theta: Sequence[Any], pressure: np.ndarray | None
    ) -> np.ndarray:
        k1, k2, k3, k4 = theta
        return (k1 + k2 * np.exp(k3 * np.abs(v))) * (2.0 / math.pi) * np.arctan(k4 * v)

    @classmethod
    def _basis(
        cls, v: np.ndarray, nonlinear: Mapping[str, Any], pressure: np.ndarray | None
    ) -> tuple[np.ndarray, ...]:
        g = (2.0 / math.pi) * np.arctan(nonlinear["k4"] * v)
        return (g, np.exp(nonlinear["k3"] * np.abs(v)) * g)

    @classmethod
    def _grid(cls, v: np.ndarray) -> dict[str, np.ndarray]:
        scale = _velocity_scale(v)
        rate = np.logspace(-2, 1.5, 16) / scale
        return {
            "k3": np.concatenate([-rate[::-1], rate]),
            "k4": np.logspace(-1, 4, 21) / scale,
        }


@dataclass(frozen=True)
class VenkateshLaw(FrictionLaw):
    """Pressure-dependent friction after Venkatesh, 1/mu = A (1 + B p / E0) (Eq. 2.4).

    Independent of the sliding velocity; ``pressure_Pa`` is required.

    Parameters
    ----------
    A : float
        Rubber-dependent constant, > 0 (Venkatesh: 1...8), dimensionless.
    B : float
        Constant "almost the same for all rubber like materials", about 15, dimensionless.
    E0_Pa : float
        Compression modulus of the rubber, Pa, > 0.

    Notes
    -----
    Only the ratio B / E0_Pa is determined by friction data, so :func:`fit_law` needs
    ``fixed={"E0_Pa": ...}``. With B < 0 the law is undefined where 1 + B p / E0 <= 0 and
    evaluation there raises ValueError. The result broadcasts ``v_rel_mps`` against
    ``pressure_Pa``.

    Examples
    --------
    >>> law = VenkateshLaw(A=4.0, B=15.0, E0_Pa=5e6)
    >>> round(law(1.0, pressure_Pa=5e5), 12)
    0.1
    """

    A: float
    B: float
    E0_Pa: float

    param_names: ClassVar[tuple[str, ...]] = ("A", "B", "E0_Pa")
    equation: ClassVar[str] = "Eq. 2.4"
    _rules: ClassVar[Mapping[str, str]] = {"A": "> 0", "E0_Pa": "> 0"}
    _must_fix: ClassVar[Mapping[str, str]] = {"E0_Pa": "only B / E0_Pa is determined by the data"}
    _needs_pressure: ClassVar[bool] = True

    @classmethod
    def _formula(
        cls, v: np.ndarray, theta: Sequence[Any], pressure: np.ndarray | None
    ) -> np.ndarray:
        a, b, e0 = theta
        assert pressure is not None  # guaranteed by _pressure
        inv_mu = a * (1.0 + b * pressure / e0)
        return np.broadcast_to(1.0 / inv_mu, np.broadcast_shapes(v.shape, inv_mu.shape)).copy()

    def mu(
        self,
        v_rel_mps: ArrayLike,
        *,
        pressure_Pa: ArrayLike | None = None,
        temperature_C: ArrayLike | None = None,
    ) -> np.ndarray | float:
        """Friction coefficient at pressure ``pressure_Pa`` (Pa); see :meth:`FrictionLaw.mu`."""
        with np.errstate(divide="ignore"):
            out = super().mu(v_rel_mps, pressure_Pa=pressure_Pa, temperature_C=temperature_C)
        if np.any(np.asarray(out) <= 0) or np.any(np.isinf(out)):
            raise ValueError(
                f"1/mu = A (1 + B p / E0_Pa) must be > 0, but with B={self.B!r} it is <= 0 "
                f"for pressure_Pa >= {-self.E0_Pa / self.B!r}"
            )
        return out

    @classmethod
    def _start(
        cls,
        v: np.ndarray,
        mu: np.ndarray,
        sqrt_w: np.ndarray,
        pressure: np.ndarray | None,
        fixed: Mapping[str, float],
        *,
        n_starts: int = 1,
    ) -> list[dict[str, float]]:
        """Weighted linear least squares of 1/mu on p (weights mu^2 / sigma carry the errors).

        Returns a single start (``n_starts`` is accepted for the common interface).
        """
        assert pressure is not None
        ok = mu > 0
        if np.count_nonzero(ok) < 2:
            raise ValueError(
                "VenkateshLaw starting values need at least 2 points with mu > 0, got "
                f"{int(np.count_nonzero(ok))}"
            )
        y, p, w = 1.0 / mu[ok], pressure[ok], (sqrt_w * mu**2)[ok]
        e0 = fixed["E0_Pa"]
        if "A" in fixed and "B" in fixed:
            return [dict(fixed)]
        if "B" in fixed:  # 1/mu = A * (1 + B p / E0)
            x = (1.0 + fixed["B"] * p / e0)[None, :, None]
            a = weighted_lstsq_batched(x, y, w)[0][0, 0]
            return [{"A": float(a), **fixed}]
        if "A" in fixed:  # 1/mu - A = (A B / E0) p
            slope = weighted_lstsq_batched(p[None, :, None], y - fixed["A"], w)[0][0, 0]
            return [{"B": float(slope * e0 / fixed["A"]), **fixed}]
        X = np.stack([np.ones_like(p), p], axis=-1)[None]
        intercept, slope = weighted_lstsq_batched(X, y, w)[0][0]
        a = intercept if intercept > 0 else float(np.median(y))
        return [{"A": float(a), "B": float(slope * e0 / a), **fixed}]


@dataclass(frozen=True, eq=False)
class FitResult:
    """Result of :func:`fit_law`.

    Attributes
    ----------
    law : FrictionLaw
        The fitted law.
    params : dict of str to float
        All parameter values (fitted and fixed), in ``param_names`` order.
    stderr : dict of str to float
        Standard errors; 0 for fixed parameters, inf when the data cannot determine them.
    cov : (P, P) ndarray
        Covariance of all parameters in ``param_names`` order (zero rows and columns for the
        fixed ones).
    rmse : float
        Root-mean-square (unweighted) residual of mu.
    n_points : int
        Number of data points.
    dof : int
        Degrees of freedom, ``n_points`` minus the number of free parameters.
    fixed : tuple of str
        Names of the parameters held fixed.
    absolute_sigma : bool
        Whether ``sigma`` was taken as absolute 1-sigma errors (cov not rescaled) or the
        covariance was scaled by the reduced chi-square.
    chi2 : float
        Weighted residual sum of squares, ``sum(((mu - law(v)) / sigma)^2)`` (``sigma`` = 1
        when not given): the RSS of an information criterion.
    """

    law: FrictionLaw
    params: dict[str, float]
    stderr: dict[str, float]
    cov: np.ndarray
    rmse: float
    n_points: int
    dof: int
    fixed: tuple[str, ...] = ()
    absolute_sigma: bool = False
    chi2: float = math.nan

    def to_frame(self) -> pd.DataFrame:
        """Tidy table of the parameters.

        Returns
        -------
        pandas.DataFrame
            Columns ``param``, ``value``, ``stderr`` and ``fixed``, one row per parameter.
        """
        return pd.DataFrame(
            {
                "param": list(self.params),
                "value": list(self.params.values()),
                "stderr": [self.stderr[n] for n in self.params],
                "fixed": [n in self.fixed for n in self.params],
            }
        )

    def summary(self) -> str:
        """Human-readable report: law, equation, fit statistics and the parameter table."""
        head = (
            f"{type(self.law).__name__} ({self.law.equation}): n_points={self.n_points}, "
            f"dof={self.dof}, rmse={self.rmse:.6g}, "
            f"{'absolute sigma' if self.absolute_sigma else 'cov scaled by chi2/dof'}"
        )
        return head + "\n" + self.to_frame().to_string(index=False)


def _resolve_p0(
    p0: Mapping[str, float] | Sequence[float] | None, free: tuple[str, ...], law_name: str
) -> dict[str, float]:
    if p0 is None:
        return {}
    if isinstance(p0, Mapping):
        unknown = sorted(set(p0) - set(free))
        if unknown:
            raise ValueError(
                f"p0 names must be free parameters of {law_name} {free}, got {unknown}"
            )
        return {n: check_real(f"p0[{n!r}]", p0[n]) for n in p0}
    values = list(p0)
    if len(values) != len(free):
        raise ValueError(
            f"p0 must give one value per free parameter {free}, got {len(values)} value(s)"
        )
    return {n: check_real(f"p0[{n!r}]", x) for n, x in zip(free, values, strict=True)}


def fit_law(
    law_cls: type[FrictionLaw],
    v_rel_mps: ArrayLike,
    mu: ArrayLike,
    *,
    sigma: ArrayLike | None = None,
    p0: Mapping[str, float] | Sequence[float] | None = None,
    pressure_Pa: ArrayLike | None = None,
    fixed: Mapping[str, float] | None = None,
    absolute_sigma: bool | None = None,
) -> FitResult:
    """Least-squares fit of a friction law to measured friction coefficients.

    Parameters
    ----------
    law_cls : type of FrictionLaw
        The law to fit, e.g. :class:`DecreasingSqrtLaw`.
    v_rel_mps : (N,) array_like
        Sliding velocities, m/s.
    mu : (N,) array_like
        Measured friction coefficients, same shape as ``v_rel_mps``.
    sigma : float or (N,) array_like, optional
        1-sigma errors of ``mu`` (> 0); residuals are weighted by ``1 / sigma``.
    p0 : mapping or sequence of float, optional
        Starting values for nonlinear fits: a mapping from (some) free parameter names to
        values, or one value per free parameter in ``param_names`` order. Missing ones are
        estimated automatically. Ignored (after validation) when the free parameters enter
        linearly, as the fit is then exact linear least squares.
    pressure_Pa : float or (N,) array_like, optional
        Normal pressure, Pa; required by :class:`VenkateshLaw`, ignored by the other laws.
    fixed : mapping of str to float, optional
        Parameters held at the given values. :class:`VenkateshLaw` needs ``E0_Pa`` here.
    absolute_sigma : bool, optional
        If True, ``sigma`` are absolute errors and the covariance is not rescaled; if False,
        the covariance is scaled by the reduced chi-square ``chi2 / dof``. Default: True when
        ``sigma`` is given, False otherwise (the residual variance then estimates the noise).

    Returns
    -------
    FitResult
        Fitted law, parameters, standard errors and covariance.

    Raises
    ------
    TypeError
        If ``law_cls`` is not a concrete :class:`FrictionLaw` subclass.
    ValueError
        On mismatched shapes, non-finite data, non-positive ``sigma``, too few points,
        unknown or missing fixed parameters, or fitted values the law rejects.
    RuntimeError
        If the nonlinear optimisation fails.

    Warns
    -----
    UserWarning
        If the covariance cannot be estimated (stderr set to inf) or the optimiser stops at its
        evaluation limit: both mean the data hardly determine the parameters. Also when
        there are more free parameters than distinct velocities (velocity and pressure
        pairs for a law that reads the pressure).

    Notes
    -----
    Laws whose free parameters enter linearly (Eq. 4.8, 4.9, Coulomb, Eq. 5.7 with ``a3``
    fixed, ...) are solved exactly by linear least squares. The others start from a grid search
    over the nonlinear parameters with the linear ones solved exactly for each candidate
    (Eq. 5.7, 5.24) or from a linear fit of 1/mu against p (Eq. 2.4); Levenberg-Marquardt on
    the residuals of mu then refines the best few local minima of that grid and keeps the
    best result. The covariance is the Gauss-Newton estimate
    ``(J^T W J)^-1``, times ``chi2 / dof`` unless ``absolute_sigma``; it is inf (with a
    warning) when the data cannot separate the parameters.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.linspace(1.0, 7.0, 13)
    >>> res = fit_law(DecreasingSqrtLaw, v, DecreasingSqrtLaw(0.2, 0.095)(v))
    >>> {k: round(x, 9) for k, x in res.params.items()}
    {'A_D': 0.2, 'B_D': 0.095}
    """
    if not (isinstance(law_cls, type) and issubclass(law_cls, FrictionLaw)) or inspect.isabstract(
        law_cls
    ):
        raise TypeError(f"law_cls must be a concrete FrictionLaw subclass, got {law_cls!r}")
    name = law_cls.__name__
    v, y, pressure = _fit_data(law_cls, v_rel_mps, mu, pressure_Pa)
    n = v.size
    sqrt_w, absolute = _fit_weights(sigma, absolute_sigma, n)
    fixed_vals, free = _fit_fixed(law_cls, fixed)
    need = len(free) + (0 if absolute else 1)
    if n < need:
        raise ValueError(
            f"too few points: fitting {len(free)} free parameter(s) {free} of {name} needs at "
            f"least {need} data points, got {n}"
        )
    _warn_if_undetermined(name, free, v, pressure)
    problem = _FitProblem(law_cls, v, y, sqrt_w, pressure, fixed_vals, free)
    start_given = _resolve_p0(p0, free, name)
    if all(k in law_cls._linear for k in free):
        params, J = _fit_linear(problem)
    else:
        params, J = _fit_nonlinear(problem, start_given)
    return _fit_result(problem, params, J, absolute)


def _warn_if_undetermined(name: str, free: tuple[str, ...], v: np.ndarray,
                          pressure: np.ndarray | None) -> None:
    """Warn when the law has more free parameters than the data have distinct conditions
    (velocities; velocity and pressure pairs for a law that reads the pressure): the data
    then fix at most that many combinations of them, whatever the standard errors say."""
    points = v if pressure is None else np.column_stack([v, np.broadcast_to(pressure, v.shape)])
    distinct = len(np.unique(points, axis=0))
    if len(free) > distinct:
        what = "velocities" if pressure is None else "velocity and pressure pairs"
        warnings.warn(
            f"{name}: {len(free)} free parameters {free} but {distinct} distinct {what}: "
            f"the data determine at most {distinct} combination{'s' if distinct > 1 else ''} "
            "of them (measure more "
            "velocities, or fix some with fixed=)", UserWarning, stacklevel=3)


@dataclass(frozen=True)
class _FitProblem:
    """What :func:`fit_law` fits: the law, the checked data and the fixed parameters."""

    law_cls: type[FrictionLaw]
    v: np.ndarray  # sliding velocities, m/s
    y: np.ndarray  # measured friction coefficients
    sqrt_w: np.ndarray  # residual weights 1 / sigma
    pressure: np.ndarray | None  # Pa, for pressure-dependent laws
    fixed_vals: dict[str, float]
    free: tuple[str, ...]

    def model(self, theta: Mapping[str, float]) -> np.ndarray:
        """The law's ``mu`` at the data for parameter values ``theta`` (all of them)."""
        names = self.law_cls.param_names
        return self.law_cls._formula(self.v, [theta[k] for k in names], self.pressure)


def _fit_data(
    law_cls: type[FrictionLaw], v_rel_mps: ArrayLike, mu: ArrayLike, pressure_Pa: ArrayLike | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Checked, flattened velocities and coefficients, and the pressure broadcast to them."""
    v = as_float_array("v_rel_mps", v_rel_mps)
    y = as_float_array("mu", mu)
    if v.shape != y.shape:
        raise ValueError(f"v_rel_mps and mu must have the same shape, got {v.shape} and {y.shape}")
    v, y = v.ravel(), y.ravel()
    n = v.size
    law_cls._check_v(v)
    pressure = law_cls._pressure(pressure_Pa)
    if pressure is not None:
        try:
            pressure = np.broadcast_to(pressure, (n,))
        except ValueError:
            raise ValueError(
                "pressure_Pa must be a scalar or have the shape of v_rel_mps "
                f"{(n,)}, got shape {pressure.shape}"
            ) from None
    return v, y, pressure


def _fit_weights(
    sigma: ArrayLike | None, absolute_sigma: bool | None, n: int
) -> tuple[np.ndarray, bool]:
    """Residual weights ``1 / sigma`` (ones without sigma) and whether sigma is absolute."""
    if sigma is None:
        if absolute_sigma:
            raise ValueError("absolute_sigma=True needs sigma, got sigma=None")
        return np.ones(n), False
    s = as_float_array("sigma", sigma)
    try:
        s = np.broadcast_to(s, (n,))
    except ValueError:
        raise ValueError(
            f"sigma must be a scalar or have the shape of mu {(n,)}, got shape {s.shape}"
        ) from None
    if np.any(s <= 0):
        raise ValueError(f"sigma must be > 0, got min(sigma)={float(s.min()):g}")
    return 1.0 / s, True if absolute_sigma is None else bool(absolute_sigma)


def _fit_fixed(
    law_cls: type[FrictionLaw], fixed: Mapping[str, float] | None
) -> tuple[dict[str, float], tuple[str, ...]]:
    """Checked values of the fixed parameters, and the names of the free ones."""
    name = law_cls.__name__
    fixed_vals: dict[str, float] = {}
    for key, value in (fixed or {}).items():
        if key not in law_cls.param_names:
            raise ValueError(
                f"fixed names must be parameters of {name} {law_cls.param_names}, got {key!r}"
            )
        fixed_vals[key] = check_real(f"fixed[{key!r}]", value)
    for key, why in law_cls._must_fix.items():
        if key not in fixed_vals:
            raise ValueError(f"{name} needs fixed={{{key!r}: ...}} ({why}), got fixed={fixed!r}")
    free = tuple(k for k in law_cls.param_names if k not in fixed_vals)
    if not free:
        raise ValueError(f"nothing to fit: all parameters of {name} are fixed")
    return fixed_vals, free


def _fit_linear(fp: _FitProblem) -> tuple[dict[str, float], np.ndarray]:
    """Exact weighted linear least squares when every free parameter enters linearly.

    Returns the parameters and the weighted Jacobian of the model in the free parameters.
    """
    law_cls, n = fp.law_cls, fp.v.size
    (params,) = law_cls._start(fp.v, fp.y, fp.sqrt_w, fp.pressure, fp.fixed_vals)
    nonlinear = {k: fp.fixed_vals[k] for k in law_cls.param_names if k not in law_cls._linear}
    cols = dict(zip(law_cls._linear, law_cls._basis(fp.v, nonlinear, fp.pressure), strict=True))
    J = np.stack([np.broadcast_to(cols[k], (n,)) * fp.sqrt_w for k in fp.free], axis=-1)
    return params, J


def _nonlinear_starts(fp: _FitProblem, start_given: dict[str, float]) -> list[dict[str, float]]:
    """Starting values: the given ones when complete, else the law's grid search.

    The grid search sees at most ``_N_START`` points spread over the sorted velocities and
    returns the best ``_N_STARTS`` local minima; given values override theirs.
    """
    if len(start_given) == len(fp.free):
        return [{**fp.fixed_vals, **start_given}]
    n = fp.v.size
    sub = slice(None)
    if n > _N_START:
        sub = np.argsort(fp.v, kind="stable")[np.linspace(0, n - 1, _N_START).astype(int)]
    starts = fp.law_cls._start(
        fp.v[sub],
        fp.y[sub],
        fp.sqrt_w[sub],
        None if fp.pressure is None else fp.pressure[sub],
        fp.fixed_vals,
        n_starts=_N_STARTS,
    )
    return [{**start, **start_given} for start in starts]


def _fit_nonlinear(
    fp: _FitProblem, start_given: dict[str, float]
) -> tuple[dict[str, float], np.ndarray]:
    """Levenberg-Marquardt from each start; the lowest cost wins.

    Returns the parameters and the weighted Jacobian at the optimum.
    """
    name = fp.law_cls.__name__
    starts = _nonlinear_starts(fp, start_given)

    def residuals(x: np.ndarray) -> np.ndarray:
        theta = {**fp.fixed_vals, **dict(zip(fp.free, x, strict=True))}
        return fp.sqrt_w * (fp.model(theta) - fp.y)

    best = None
    for i, start in enumerate(starts):
        try:
            refined = refine_nonlinear(
                residuals, np.array([start[k] for k in fp.free]), law_name=name
            )
        except RuntimeError:
            if i == len(starts) - 1 and best is None:
                raise
            continue
        if best is None or refined.cost < best.cost:
            best = refined
    assert best is not None
    if not best.converged:
        warnings.warn(
            f"fit of {name} stopped at the evaluation limit ({best.nfev}) before "
            "converging; the data determine the parameters poorly (check stderr)",
            UserWarning,
            stacklevel=3,  # the caller of fit_law
        )
    params = {**fp.fixed_vals, **dict(zip(fp.free, (float(xi) for xi in best.x), strict=True))}
    return params, best.jac


def _fit_result(
    fp: _FitProblem, params: dict[str, float], J: np.ndarray, absolute: bool
) -> FitResult:
    """Residuals, covariance (scaled by ``chi2 / dof`` unless absolute) and the fitted law."""
    law_cls, free = fp.law_cls, fp.free
    name = law_cls.__name__
    n = fp.v.size
    params = {k: float(params[k]) for k in law_cls.param_names}
    resid = fp.y - fp.model(params)
    chi2 = float(np.sum((fp.sqrt_w * resid) ** 2))
    dof = n - len(free)
    scale = 1.0 if absolute else chi2 / dof
    cov_free = covariance_from_jacobian(J, scale=scale, names=free)
    idx = [law_cls.param_names.index(k) for k in free]
    cov = np.zeros((len(law_cls.param_names),) * 2)
    cov[np.ix_(idx, idx)] = cov_free
    stderr = {k: float(np.sqrt(cov[i, i])) for i, k in enumerate(law_cls.param_names)}
    try:
        law = law_cls(**params)
    except ValueError as exc:
        raise ValueError(f"fitted parameters {params} are invalid for {name}: {exc}") from exc
    logger.debug("fitted %s: %s +- %s", name, params, stderr)
    return FitResult(
        law=law,
        params=params,
        stderr=stderr,
        cov=cov,
        rmse=float(np.sqrt(np.mean(resid**2))),
        n_points=n,
        dof=dof,
        fixed=tuple(k for k in law_cls.param_names if k in fp.fixed_vals),
        absolute_sigma=absolute,
        chi2=chi2,
    )


@dataclass(frozen=True)
class RelaxedFriction:
    """First-order time lag of the friction coefficient (Eq. 5.12, after Lindner).

    The friction coefficient mu(t) relaxes towards the steady-state law mu_ss(v_rel(t)) with
    time constant ``tau_s``::

        tau * dmu/dt + mu = mu_ss(v_rel)

    Parameters
    ----------
    law : FrictionLaw
        Steady-state characteristic mu_ss.
    tau_s : float
        Relaxation time, s, >= 0; 0 reduces exactly to the steady law.

    Notes
    -----
    Eq. 5.12 is printed in the thesis as ``tau * mu_R + dmu_R/dt = mu(v_rel)``, a slip: it is
    dimensionally inconsistent (tau, in s, multiplies mu, while dmu/dt is in 1/s) and, read
    literally, relaxes to mu(v) / tau with time constant 1 / tau. This class implements the
    physical form above, the one Lindner uses: after a step in mu_ss, mu approaches the new
    value as exp(-t / tau), reaching 63 % of the change at t = tau.

    Examples
    --------
    >>> import numpy as np
    >>> relaxed = RelaxedFriction(ConstantLaw(0.2), tau_s=0.1)
    >>> mu = relaxed.simulate(np.array([0.0, 0.1]), 1.0, mu0=0.0)
    >>> bool(np.isclose(mu[1], 0.2 * (1 - np.exp(-1.0))))
    True
    """

    law: FrictionLaw
    tau_s: float

    equation: ClassVar[str] = "Eq. 5.12"

    def __post_init__(self) -> None:
        if not isinstance(self.law, FrictionLaw):
            raise TypeError(f"law must be a FrictionLaw, got {type(self.law).__name__}")
        object.__setattr__(self, "tau_s", check_real("tau_s", self.tau_s, rule=">= 0"))

    def steady(
        self,
        v_rel_mps: ArrayLike,
        *,
        pressure_Pa: ArrayLike | None = None,
        temperature_C: ArrayLike | None = None,
    ) -> np.ndarray | float:
        """Steady-state friction coefficient mu_ss(v), i.e. ``law.mu``."""
        return self.law.mu(v_rel_mps, pressure_Pa=pressure_Pa, temperature_C=temperature_C)

    def rhs(
        self,
        mu: ArrayLike,
        v_rel_mps: ArrayLike,
        *,
        pressure_Pa: ArrayLike | None = None,
        temperature_C: ArrayLike | None = None,
    ) -> np.ndarray | float:
        """Time derivative dmu/dt = (mu_ss(v) - mu) / tau, 1/s, for coupling into ODE solvers.

        Parameters
        ----------
        mu : float or ndarray
            Current friction coefficient (the ODE state).
        v_rel_mps : float or ndarray
            Current relative sliding velocity, m/s.
        pressure_Pa, temperature_C : float or ndarray, optional
            Passed to the law.

        Raises
        ------
        ValueError
            If ``tau_s`` is 0: mu is then algebraic (use :meth:`steady`), not an ODE state.
        """
        if self.tau_s == 0:
            raise ValueError(
                "rhs needs tau_s > 0, got tau_s=0.0; with no lag mu = steady(v) is algebraic"
            )
        mu_ss = self.steady(v_rel_mps, pressure_Pa=pressure_Pa, temperature_C=temperature_C)
        out = (np.asarray(mu_ss, dtype=float) - np.asarray(mu, dtype=float)) / self.tau_s
        return float(out) if out.ndim == 0 else out

    def simulate(
        self,
        t_s: ArrayLike,
        v_rel_mps: ArrayLike,
        *,
        mu0: float | None = None,
        pressure_Pa: ArrayLike | None = None,
        temperature_C: ArrayLike | None = None,
    ) -> np.ndarray:
        """Friction coefficient mu(t) for a sampled velocity history.

        Parameters
        ----------
        t_s : (N,) array_like
            Sample times, s, non-decreasing. A repeated time marks a jump of mu_ss (a step in
            velocity), integrated exactly.
        v_rel_mps : float or (N,) array_like
            Relative sliding velocity at the sample times, m/s.
        mu0 : float, optional
            mu at ``t_s[0]``; default the steady value there (start in equilibrium).
        pressure_Pa, temperature_C : float or (N,) array_like, optional
            Passed to the law at the sample times.

        Returns
        -------
        (N,) ndarray
            mu at the sample times; equal to mu_ss when ``tau_s`` is 0.

        Notes
        -----
        mu_ss(t) is taken piecewise linear between samples, for which the exponential
        integrator below is exact (up to rounding) for any step size: over a step h with
        x = h / tau, E = exp(-x) and c = 1 - (1 - E) / x,

            mu[k+1] = E mu[k] + (1 - E - c) mu_ss[k] + c mu_ss[k+1],

        a convex combination, so mu stays between the extremes of mu0 and mu_ss. O(N).
        """
        t = as_float_array("t_s", t_s)
        if t.ndim != 1 or t.size == 0:
            raise ValueError(f"t_s must be a non-empty 1-D array, got shape {t.shape}")
        h = np.diff(t)
        if np.any(h < 0):
            raise ValueError(
                f"t_s must be non-decreasing, got a decrease at index {int(np.argmax(h < 0)) + 1}"
            )
        v = as_float_array("v_rel_mps", v_rel_mps)
        try:
            v = np.broadcast_to(v, t.shape)
        except ValueError:
            raise ValueError(
                f"v_rel_mps must be a scalar or have the shape of t_s {t.shape}, "
                f"got shape {v.shape}"
            ) from None
        mu_ss = np.array(
            np.broadcast_to(
                self.steady(v, pressure_Pa=pressure_Pa, temperature_C=temperature_C), t.shape
            ),
            dtype=float,
        )
        start = mu_ss[0] if mu0 is None else check_real("mu0", mu0)
        if self.tau_s == 0:
            return mu_ss
        x = h / self.tau_s
        jump = x == 0
        x_safe = np.where(jump, 1.0, x)
        one_minus_e = -np.expm1(-x_safe)
        c = np.where(jump, 0.0, 1.0 - one_minus_e / x_safe)
        a = np.where(jump, 1.0, np.exp(-x_safe))
        b = np.where(jump, 0.0, one_minus_e - c)
        forcing = b * mu_ss[:-1] + c * mu_ss[1:]
        out = [start]
        m = start
        for ak, fk in zip(a.tolist(), forcing.tolist(), strict=True):
            m = ak * m + fk
            out.append(m)
        return np.asarray(out)
