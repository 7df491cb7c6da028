"""The Problem protocol, candidate effects and their registry.

A *problem* is measured data plus a base model that can be extended by named candidate
effects (:class:`Problem`). A *candidate* is a model extension with one or two bounded,
physically signed parameters that reduces exactly to the base model at its null value
(:class:`Candidate`, :class:`ParameterSpec`). Every physical effect of
:mod:`friction_model.effect_registry` is a candidate (the six library effects and any effect
registered there with its physics); a candidate that is no physical effect of the toolkit
(a trend, a data-specific correction) is added with :func:`register_candidate`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import pandas as pd

from friction_model.effect_registry import ParameterSpec, PhysicalEffect, physical_effects
from friction_model.effect_registry import get_effect as _get_effect

__all__ = [
    "Apply",
    "Candidate",
    "ParameterSpec",
    "Problem",
    "candidate_apply",
    "candidates",
    "get_candidate",
    "register_candidate",
    "unregister_candidate",
]


@runtime_checkable
class Problem(Protocol):
    """Measured data and a base model that named effects extend (steady or transient).

    Attributes
    ----------
    kind : str
        ``"steady"`` or ``"transient"``.
    y : (n,) ndarray
        Observations.
    sigma : (n,) ndarray
        Standard deviation of each observation, > 0 (estimated when the data has none).
    groups : (n,) ndarray
        Hold-out and block-bootstrap group of each observation: a whole condition or run,
        never a single point.
    covariates : pandas.DataFrame
        n rows of named covariates for the where-analysis (``velocity_mps``,
        ``pressure_bar``, ``temperature_C``, ``humidity_pct``, ``salinity_pct``, ``n_sipes``,
        ``element``, ``time_since_step_s``, ...).
    effect_names : tuple of str
        The candidate effects this data can reveal (the problem interprets their
        parameters in :meth:`predict`).
    n_base : int
        Number of base (nuisance) parameters that :meth:`fit_base` fits.
    """

    kind: str
    y: np.ndarray
    sigma: np.ndarray
    groups: np.ndarray
    covariates: pd.DataFrame
    effect_names: tuple[str, ...]
    n_base: int

    def fit_base(self, train: np.ndarray, effects: Mapping[str, tuple[float, ...]]) -> np.ndarray:
        """Fit the base parameters on the rows ``train`` (bool mask), effects held fixed."""
        ...

    def predict(self, base: np.ndarray, effects: Mapping[str, tuple[float, ...]]) -> np.ndarray:
        """Model prediction for all n rows."""
        ...


@dataclass(frozen=True)
class Candidate:
    """A named candidate effect: a model extension that is exactly off at its null.

    Parameters
    ----------
    name : str
        Effect name (the key of the effects mapping passed to :meth:`Problem.predict`).
    parameters : tuple of ParameterSpec
        One or two parameters.
    description : str
        What the effect is, with the physics it stands for.
    kinds : frozenset of str
        Problem kinds it applies to (``"steady"``, ``"transient"``).
    distinguishing_measurement : str
        The measurement that tells it apart from the other candidates (used in the
        ``ambiguous`` verdict).
    """

    name: str
    parameters: tuple[ParameterSpec, ...]
    description: str
    kinds: frozenset[str]
    distinguishing_measurement: str

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise ValueError(f"candidate name must be an identifier, got {self.name!r}")
        params = tuple(self.parameters)
        if not 1 <= len(params) <= 2 or not all(isinstance(p, ParameterSpec) for p in params):
            raise ValueError(
                f"candidate {self.name!r}: parameters must be one or two ParameterSpec, "
                f"got {self.parameters!r}"
            )
        object.__setattr__(self, "parameters", params)
        object.__setattr__(self, "kinds", frozenset(self.kinds))

    @property
    def null(self) -> tuple[float, ...]:
        """The parameter values that switch the effect off."""
        return tuple(p.null for p in self.parameters)

    def to_dict(self) -> dict:
        """Plain dict (for JSON)."""
        return {
            "name": self.name,
            "parameters": [
                {"name": p.name, "unit": p.unit, "null": p.null, "lower": p.lower, "upper": p.upper}
                for p in self.parameters
            ],
            "description": self.description,
            "kinds": sorted(self.kinds),
            "distinguishing_measurement": self.distinguishing_measurement,
        }


#: ``apply(problem, prediction, params) -> prediction``: how a user candidate changes the
#: prediction of the model without it (must return ``prediction`` unchanged at the null).
Apply = Callable[[Problem, np.ndarray, tuple[float, ...]], np.ndarray]

def _effect_candidate(effect: PhysicalEffect) -> Candidate:
    """The candidate of a registry entry."""
    return Candidate(effect.name, (effect.parameter,), effect.description, effect.problems,
                     effect.distinguishing_measurement)


def _effect_apply(effect: PhysicalEffect) -> Apply:
    """``apply`` of a registered effect: its physics on the problem's covariates."""
    physics = effect.physics
    assert physics is not None

    def apply(problem: Problem, prediction: np.ndarray, params: tuple[float, ...]) -> np.ndarray:
        return np.asarray(physics(problem.covariates, prediction, float(params[0])), float)

    return apply


def _effect(name: str) -> PhysicalEffect | None:
    try:
        return _get_effect(name)
    except KeyError:
        return None


# candidates that are not physical effects of the registry (users' trends and corrections)
_REGISTRY: dict[str, Candidate] = {}
_APPLY: dict[str, Apply] = {}


def register_candidate(
    candidate: Candidate, *, apply: Apply | None = None, replace: bool = False
) -> Candidate:
    """Add a candidate effect to the library.

    Parameters
    ----------
    candidate : Candidate
        The effect. Its name must be new unless ``replace``; the names of physical effects
        (:func:`friction_model.effect_registry.effect_names`) cannot be replaced: a physical
        effect is added there, with its physics, and is then a candidate by itself.
    apply : callable, optional
        ``apply(problem, prediction, params) -> prediction``: how the effect changes the
        prediction of the model without it, for problems whose ``effect_names`` do not
        include it. It must return ``prediction`` unchanged at ``candidate.null``
        (:func:`~friction_model.discrepancy.run_discrepancy` checks this). Without
        ``apply`` the candidate is used only by problems that interpret it themselves.
    replace : bool
        Allow replacing a user candidate of the same name.

    Returns
    -------
    Candidate

    Examples
    --------
    A friction offset that grows with humidity, fitted on top of any steady problem:

    >>> from friction_model.discrepancy import (Candidate, ParameterSpec,
    ...     register_candidate, unregister_candidate, candidates)
    >>> wet_air = Candidate(
    ...     "humid_offset", (ParameterSpec("mu_per_pct", "1/%", 0.0, -0.01, 0.0),),
    ...     "mu falls linearly with relative humidity", frozenset({"steady"}),
    ...     "mu at two humidities")
    >>> _ = register_candidate(wet_air, apply=lambda problem, mu, p:
    ...     mu + p[0] * problem.covariates["humidity_pct"].to_numpy())
    >>> "humid_offset" in [c.name for c in candidates("steady")]
    True
    >>> unregister_candidate("humid_offset")
    """
    if not isinstance(candidate, Candidate):
        raise TypeError(f"candidate must be a Candidate, got {type(candidate).__name__}")
    if apply is not None and not callable(apply):
        raise TypeError(f"apply must be callable, got {type(apply).__name__}")
    name = candidate.name
    if _effect(name) is not None:
        raise ValueError(f"candidate {name!r} is a library effect (an entry of "
                         "friction_model.effect_registry) and cannot be replaced")
    if name in _REGISTRY and not replace:
        raise ValueError(f"candidate {name!r} is already registered; pass replace=True")
    _REGISTRY[name] = candidate
    if apply is None:
        _APPLY.pop(name, None)
    else:
        _APPLY[name] = apply
    return candidate


def unregister_candidate(name: str) -> None:
    """Remove a user candidate (physical effects stay: ``unregister_effect`` removes those)."""
    if _effect(name) is not None:
        raise ValueError(f"candidate {name!r} is a library effect (an entry of "
                         "friction_model.effect_registry) and cannot be removed here")
    if name not in _REGISTRY:
        raise KeyError(f"no candidate named {name!r}; registered: {sorted(_REGISTRY)}")
    del _REGISTRY[name]
    _APPLY.pop(name, None)


def get_candidate(name: str) -> Candidate:
    """The candidate ``name`` (KeyError listing the names otherwise)."""
    effect = _effect(name)
    if effect is not None:
        return _effect_candidate(effect)
    try:
        return _REGISTRY[name]
    except KeyError:
        names = [c.name for c in candidates()]
        raise KeyError(f"no candidate named {name!r}; registered: {sorted(names)}") from None


def candidate_apply(name: str) -> Apply | None:
    """The ``apply`` function of a user candidate or of a registered effect's physics (None
    for the library effects, which the problems evaluate natively)."""
    effect = _effect(name)
    if effect is not None:
        return None if effect.physics is None else _effect_apply(effect)
    return _APPLY.get(name)


def candidates(kind: str | None = None) -> tuple[Candidate, ...]:
    """The candidates (physical effects first, library first), optionally only for ``kind``.

    Examples
    --------
    >>> [c.name for c in candidates("steady")][:2]
    ['humidity_water_layer', 'salinity_melting_point']
    """
    found: Iterable[Candidate] = [
        *(_effect_candidate(e) for e in physical_effects()), *_REGISTRY.values()]
    if kind is not None:
        found = [c for c in found if kind in c.kinds]
    return tuple(found)
