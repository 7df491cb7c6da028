"""The Problem protocol, candidate effects and their registry.

A *problem* is measured data plus a base model that can be extended by named candidate
effects (:class:`Problem`). A *candidate* is a model extension with one or two bounded,
physically signed parameters that reduces exactly to the base model at its null value
(:class:`Candidate`, :class:`ParameterSpec`). The six effects of
:data:`friction_model.contact.effects.EFFECT_NAMES` form the library; users add their own with
:func:`register_candidate`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import pandas as pd

from friction_model.contact.effects import EFFECT_NAMES

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
class ParameterSpec:
    """One bounded, physically signed parameter of a candidate effect.

    Parameters
    ----------
    name : str
        Parameter name (``strength``, ``tau_s``, ...).
    unit : str
        Unit (``"1"`` for dimensionless).
    null : float
        The value at which the candidate reduces exactly to the model without it; inside
        ``[lower, upper]``, usually one of the bounds (the physical sign).
    lower, upper : float
        Bounds, ``lower < upper``.

    Examples
    --------
    >>> ParameterSpec("strength", "1", null=0.0, lower=0.0, upper=1.0).span
    1.0
    """

    name: str
    unit: str
    null: float
    lower: float
    upper: float

    def __post_init__(self) -> None:
        for label in ("null", "lower", "upper"):
            value = float(getattr(self, label))
            if not math.isfinite(value):
                raise ValueError(
                    f"ParameterSpec {self.name!r}: {label} must be finite, got {value}"
                )
            object.__setattr__(self, label, value)
        if not self.lower < self.upper:
            raise ValueError(
                f"ParameterSpec {self.name!r}: lower must be < upper, got "
                f"lower={self.lower}, upper={self.upper}"
            )
        if not self.lower <= self.null <= self.upper:
            raise ValueError(
                f"ParameterSpec {self.name!r}: null={self.null} must lie in "
                f"[{self.lower}, {self.upper}]"
            )

    @property
    def span(self) -> float:
        """``upper - lower``."""
        return self.upper - self.lower


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

_STRENGTH = "strength"
_LIBRARY: tuple[Candidate, ...] = (
    Candidate(
        "friction_relaxation",
        (ParameterSpec("tau_s", "s", 0.0, 0.0, 1.0),),
        "First-order lag of the friction coefficient after a velocity change, "
        "tau dmu/dt + mu = mu_ss(v) (Eq. 5.12); tau = 0 is the instantaneous law.",
        frozenset({"transient"}),
        "the deflection angle through a velocity step at a high frame rate (the lag of "
        "friction behind the step)",
    ),
    Candidate(
        "humidity_water_layer",
        (ParameterSpec(_STRENGTH, "1", 0.0, 0.0, 20.0),),
        "The bound water layer on the ice grows with relative humidity (section 4.5.1); "
        "strength scales the calibrated growth (1 = saturated air triples the layer).",
        frozenset({"steady", "transient"}),
        "mu at low and high relative humidity on the same ice at the same temperature",
    ),
    Candidate(
        "salinity_melting_point",
        (ParameterSpec(_STRENGTH, "1", 0.0, 0.0, 10.0),),
        "Salt lowers the melting point of the ice surface (section 4.5.2); strength scales "
        "the surface-brine enrichment.",
        frozenset({"steady", "transient"}),
        "mu on fresh-water ice against saline ice at the same temperature",
    ),
    Candidate(
        "ice_preheating",
        (ParameterSpec(_STRENGTH, "1", 0.0, 0.0, 1.0),),
        "Each element meets the heat history of the elements ahead of it; the sipe lets "
        "the ice cool (Fig. 4.25); strength is the share of that history, in [0, 1].",
        frozenset({"steady", "transient"}),
        "mu of blocks with and without sipes (G0 against G3) under the same conditions",
    ),
    Candidate(
        "viscous_shear",
        (ParameterSpec(_STRENGTH, "1", 0.0, 0.0, 20.0),),
        "Viscous shear of the melt-water film, eta v / h (Eq. 4.3); strength scales it.",
        frozenset({"steady", "transient"}),
        "mu over sliding velocity close to the melting point (e.g. -1 degC, 1-5 m/s)",
    ),
    Candidate(
        "frequency_dependent_modulus",
        (ParameterSpec(_STRENGTH, "1", 0.0, 0.0, 5.0),),
        "The rubber modulus rises with excitation frequency, E(f) = E0 (1 + strength alpha "
        "log10(f / f0)) (end of section 5.3.2).",
        frozenset({"transient"}),
        "the ringing or stick-slip frequency of the element against its simulated natural "
        "frequency",
    ),
)

_REGISTRY: dict[str, Candidate] = {c.name: c for c in _LIBRARY}
_APPLY: dict[str, Apply] = {}
_LIBRARY_NAMES = frozenset(c.name for c in _LIBRARY)
assert _LIBRARY_NAMES == set(EFFECT_NAMES)


def register_candidate(
    candidate: Candidate, *, apply: Apply | None = None, replace: bool = False
) -> Candidate:
    """Add a candidate effect to the library.

    Parameters
    ----------
    candidate : Candidate
        The effect. Its name must be new unless ``replace``; the six library names
        cannot be replaced.
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
    if name in _LIBRARY_NAMES:
        raise ValueError(f"candidate {name!r} is a library effect and cannot be replaced")
    if name in _REGISTRY and not replace:
        raise ValueError(f"candidate {name!r} is already registered; pass replace=True")
    _REGISTRY[name] = candidate
    if apply is None:
        _APPLY.pop(name, None)
    else:
        _APPLY[name] = apply
    return candidate


def unregister_candidate(name: str) -> None:
    """Remove a user candidate (library effects stay)."""
    if name in _LIBRARY_NAMES:
        raise ValueError(f"candidate {name!r} is a library effect and cannot be removed")
    if name not in _REGISTRY:
        raise KeyError(f"no candidate named {name!r}; registered: {sorted(_REGISTRY)}")
    del _REGISTRY[name]
    _APPLY.pop(name, None)


def get_candidate(name: str) -> Candidate:
    """The registered candidate ``name`` (KeyError listing the names otherwise)."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise KeyError(f"no candidate named {name!r}; registered: {sorted(_REGISTRY)}") from None


def candidate_apply(name: str) -> Apply | None:
    """The ``apply`` function of a user candidate (None for problem-native ones)."""
    return _APPLY.get(name)


def candidates(kind: str | None = None) -> tuple[Candidate, ...]:
    """The registered candidates (library first), optionally only those for ``kind``.

    Examples
    --------
    >>> [c.name for c in candidates("steady")][:2]
    ['humidity_water_layer', 'salinity_melting_point']
    """
    found: Iterable[Candidate] = _REGISTRY.values()
    if kind is not None:
        found = [c for c in found if kind in c.kinds]
    return tuple(found)
