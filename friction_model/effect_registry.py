"""The physical effects of the toolkit: one registry entry per effect.

Every physical effect that the base model (the dry run-in / wet model of section 4.5.1 and the
linearised element of Eq. 5.8 with the constant modulus E0) lacks, and that the discrepancy
workflow looks for, is one :class:`PhysicalEffect` here: its name, where it shows (``kind``),
its fitted parameter with its null and bounds, a plausible cap on that parameter, how it
changes the model and how the synthetic generators hide it. Everything that lists effects
derives from this table:

* the names of :mod:`friction_model.contact.effects` (``EFFECT_NAMES``, ``DRY_WET_EFFECTS``);
* the discrepancy workflow's candidates (:func:`friction_model.discrepancy.candidates`);
* the synthetic generators (``synthetic.measurements.EffectSpec``, ``make_steady_table``)
  and effect sizes (``synthetic.effect_size``);
* the choices of ``tir-contact synth measurements --effect`` and of
  ``tir-contact discrepancy --effects``.

The six library effects are built into the model (their physics lives where it acts,
``acts_in``). A new effect is one :func:`register_effect` call with an entry whose
``physics`` function says how it changes the friction coefficient of a steady table::

    def grit(conditions, mu, value):              # the physics, with its equation cited
        return mu * (1.0 + value * conditions["pressure_bar"].to_numpy() / 5.0)

    register_effect(PhysicalEffect(
        "ice_grit", "steady", ParameterSpec("strength", "1", 0.0, 0.0, 1.0),
        plausible_max=0.5, description="...", distinguishing_measurement="...",
        problems={"steady"}, hidden_in={"steady"}, hiding="...", physics=grit))

From then on the workflow fits it, ``make_steady_table(effects={"ice_grit": 0.2})`` hides it
in a table and the CLI offers it (docs/architecture.md, "Where to add ...").

Notes
-----
``kind`` says where an effect first shows: ``"steady"`` (it changes steady friction),
``"transient"`` (the path through a velocity step) or ``"stick-slip"`` (the element's
ringing and stick-slip frequency). ``problems`` are the discrepancy problem kinds
(``"steady"``, ``"transient"``) whose data can reveal it; ``hidden_in`` the synthetic data
kinds (``"steady"``, ``"transient"``, ``"raw"``) that carry it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from friction_model.compound import REFERENCE_COMPOUND, Compound

__all__ = [
    "DATA_KINDS",
    "EFFECT_KINDS",
    "LIBRARY_EFFECTS",
    "PLAUSIBLE_LOSS_FACTOR_MAX",
    "PROBLEM_KINDS",
    "ParameterSpec",
    "PhysicalEffect",
    "Physics",
    "effect_names",
    "extra_modulus_strength",
    "get_effect",
    "physical_effects",
    "register_effect",
    "unregister_effect",
]

#: Where an effect first shows.
EFFECT_KINDS: tuple[str, ...] = ("steady", "transient", "stick-slip")
#: Discrepancy problem kinds.
PROBLEM_KINDS: tuple[str, ...] = ("steady", "transient")
#: Synthetic data kinds (``synthetic.measurements.KINDS``).
DATA_KINDS: tuple[str, ...] = ("steady", "transient", "raw")

#: ``physics(conditions, mu, value) -> mu``: how a registered effect changes the friction
#: coefficient ``mu`` of the rows ``conditions`` (columns ``velocity_mps``, ``pressure_bar``,
#: ``temperature_C``, ``humidity_pct``, ``salinity_pct``, ``n_sipes``) at parameter ``value``;
#: ``mu`` unchanged at the parameter's null.
Physics = Callable[[pd.DataFrame, np.ndarray, float], np.ndarray]


@dataclass(frozen=True)
class ParameterSpec:
    """One bounded, physically signed parameter of an effect.

    Parameters
    ----------
    name : str
        Parameter name (``strength``, ``tau_s``, ...).
    unit : str
        Unit (``"1"`` for dimensionless).
    null : float
        The value at which the effect reduces exactly to the model without it; inside
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
class PhysicalEffect:
    """One physical effect: what it is, its parameter, and how model and data carry it.

    Parameters
    ----------
    name : str
        Identifier (the key in effect mappings, the CLI's ``--effect NAME``).
    kind : {"steady", "transient", "stick-slip"}
        Where it first shows.
    parameter : ParameterSpec
        The parameter the discrepancy workflow fits, with its null (effect off) and bounds.
    plausible_max : float
        Largest physically plausible value of the parameter (a fit beyond it is reported as
        implausible); at most ``parameter.upper``.
    description : str
        How it changes the model, with the thesis equation or section.
    distinguishing_measurement : str
        The measurement that tells it apart from the other effects.
    problems : set of str
        Discrepancy problem kinds whose data can reveal it (``"steady"``, ``"transient"``).
    hidden_in : set of str
        Synthetic data kinds that carry it (``"steady"``, ``"transient"``, ``"raw"``).
    hiding : str
        How the synthetic generators put it in the data.
    physics : callable, optional
        :data:`Physics` of an effect added on top of the steady model; None for the library
        effects, which are built into the model (``acts_in``).
    acts_in : str
        Where the physics lives (a module and the part of it).

    Raises
    ------
    ValueError
        A name that is not an identifier, an unknown kind, a cap outside the parameter's
        range, a registered effect without ``physics`` or with a data kind other than
        ``"steady"`` (``physics`` acts on steady friction).
    """

    name: str
    kind: str
    parameter: ParameterSpec
    plausible_max: float
    description: str
    distinguishing_measurement: str
    problems: frozenset[str]
    hidden_in: frozenset[str]
    hiding: str
    physics: Physics | None = None
    acts_in: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise ValueError(f"effect name must be an identifier, got {self.name!r}")
        if self.kind not in EFFECT_KINDS:
            raise ValueError(f"effect {self.name}: kind must be one of {EFFECT_KINDS}, "
                             f"got {self.kind!r}")
        if not isinstance(self.parameter, ParameterSpec):
            raise TypeError(f"effect {self.name}: parameter must be a ParameterSpec")
        for label, allowed in (("problems", PROBLEM_KINDS), ("hidden_in", DATA_KINDS)):
            values = frozenset(getattr(self, label))
            if not values <= set(allowed):
                raise ValueError(f"effect {self.name}: {label} must be a subset of {allowed}, "
                                 f"got {sorted(values)}")
            object.__setattr__(self, label, values)
        cap = float(self.plausible_max)
        p = self.parameter
        if not (min(p.null, p.upper) <= cap <= p.upper):
            raise ValueError(f"effect {self.name}: plausible_max={cap} must lie in "
                             f"[{p.null}, {p.upper}]")
        object.__setattr__(self, "plausible_max", cap)
        if self.physics is not None and not callable(self.physics):
            raise TypeError(f"effect {self.name}: physics must be callable")

    @property
    def built_in(self) -> bool:
        """True for the library effects whose physics is part of the model itself."""
        return self.physics is None

    def to_dict(self) -> dict:
        """Plain dict (for JSON; the physics function by name)."""
        p = self.parameter
        return {
            "name": self.name,
            "kind": self.kind,
            "parameter": {"name": p.name, "unit": p.unit, "null": p.null, "lower": p.lower,
                          "upper": p.upper},
            "plausible_max": self.plausible_max,
            "description": self.description,
            "distinguishing_measurement": self.distinguishing_measurement,
            "problems": sorted(self.problems),
            "hidden_in": sorted(self.hidden_in),
            "hiding": self.hiding,
            "acts_in": self.acts_in or getattr(self.physics, "__qualname__", ""),
        }


#: Upper end of a tread compound's loss factor near 0 degC (``friction_model.dynamics.rigid``:
#: typically 0.15-0.3).
PLAUSIBLE_LOSS_FACTOR_MAX = 0.3


def extra_modulus_strength(loss_factor: float, frequency_Hz: float = 1500.0) -> float:
    """Extra ``frequency_dependent_modulus`` strength that turns the reference compound's
    E(f) into that of a compound with ``loss_factor``, at ``frequency_Hz``.

    Both are causal constant-loss solids, E(f) ~ f^n with tan(delta) = tan(n pi / 2); the
    extra factor (f / f0)^(n - n_ref) is matched by 1 + s alpha log10(f / f0), with the
    effect's slope alpha = n_ref ln(10) per decade (``element_step.MODULUS_ALPHA``, end of
    section 5.3.2) and f0 the compound's reference frequency.

    Examples
    --------
    >>> round(extra_modulus_strength(0.3), 2)
    0.6
    >>> extra_modulus_strength(REFERENCE_COMPOUND.loss_factor)
    0.0
    """
    ref = REFERENCE_COMPOUND
    n_extra = Compound(loss_factor=loss_factor).modulus_exponent - ref.modulus_exponent
    f0 = ref.reference_frequency_Hz
    ratio = (frequency_Hz / f0) ** n_extra
    alpha = ref.modulus_exponent * math.log(10.0)
    return (ratio - 1.0) / (alpha * math.log10(frequency_Hz / f0))


_STEADY_DATA = frozenset({"steady", "transient", "raw"})
_HIDE_DRY_WET = (
    "switched on at the given strength in the dry/wet model (Effects) that makes mu of every "
    "steady row, the levels of a velocity step and the mu(v) of raw runs; the files name no "
    "effect (the truth goes to a separate file only with reveal)"
)

#: The six effects built into the model, in the order of ``EFFECT_NAMES``.
LIBRARY_EFFECTS: tuple[PhysicalEffect, ...] = (
    PhysicalEffect(
        "humidity_water_layer", "steady", ParameterSpec("strength", "1", 0.0, 0.0, 20.0),
        plausible_max=20.0,
        description="The bound water layer on the ice grows with relative humidity (section "
        "4.5.1); strength scales the calibrated growth (1 = saturated air triples the layer).",
        distinguishing_measurement="mu at low and high relative humidity on the same ice at "
        "the same temperature",
        problems={"steady", "transient"}, hidden_in=_STEADY_DATA, hiding=_HIDE_DRY_WET,
        acts_in="friction_model.contact.drywet (Effects.humidity_water_layer, the layer h0)",
    ),
    PhysicalEffect(
        "salinity_melting_point", "steady", ParameterSpec("strength", "1", 0.0, 0.0, 10.0),
        plausible_max=10.0,
        description="Salt lowers the melting point of the ice surface (section 4.5.2); "
        "strength scales the surface-brine enrichment.",
        distinguishing_measurement="mu on fresh-water ice against saline ice at the same "
        "temperature",
        problems={"steady", "transient"}, hidden_in=_STEADY_DATA, hiding=_HIDE_DRY_WET,
        acts_in="friction_model.contact.drywet (Effects.salinity_melting_point, the melting "
        "point)",
    ),
    PhysicalEffect(
        "ice_preheating", "steady", ParameterSpec("strength", "1", 0.0, 0.0, 1.0),
        plausible_max=1.0,
        description="Each element meets the heat history of the elements ahead of it; the "
        "sipe lets the ice cool (Fig. 4.25); strength is the share of that history, in [0, 1].",
        distinguishing_measurement="mu of blocks with and without sipes (G0 against G3) "
        "under the same conditions",
        problems={"steady", "transient"}, hidden_in=_STEADY_DATA, hiding=_HIDE_DRY_WET,
        acts_in="friction_model.contact._march (the heat history of the elements ahead)",
    ),
    PhysicalEffect(
        "viscous_shear", "steady", ParameterSpec("strength", "1", 0.0, 0.0, 20.0),
        plausible_max=20.0,
        description="Viscous shear of the melt-water film, eta v / h (Eq. 4.3); strength "
        "scales it.",
        distinguishing_measurement="mu over sliding velocity close to the melting point "
        "(e.g. -1 degC, 1-5 m/s)",
        problems={"steady", "transient"}, hidden_in=_STEADY_DATA, hiding=_HIDE_DRY_WET,
        acts_in="friction_model.contact._march (the shear stress of the film)",
    ),
    PhysicalEffect(
        "friction_relaxation", "transient", ParameterSpec("tau_s", "s", 0.0, 0.0, 1.0),
        # the longest lag a 0.2 s record after the step (Fig. 5.7) tells from a drift of
        # the level (discrepancy.transient.TAU_MAX_S)
        plausible_max=0.2,
        description="First-order lag of the friction coefficient after a velocity change, "
        "tau dmu/dt + mu = mu_ss(v) (Eq. 5.12); tau = 0 is the instantaneous law.",
        distinguishing_measurement="the deflection angle through a velocity step at a high "
        "frame rate (the lag of friction behind the step)",
        problems={"transient"}, hidden_in={"transient", "raw"},
        hiding="tau = strength x 20 ms in the element's friction through the step (transient "
        "tables) and in the accelerating and braking phases of raw runs; steady tables hold "
        "steady states and do not show it",
        acts_in="friction_model.dynamics.element_step (Eq. 5.12)",
    ),
    PhysicalEffect(
        "frequency_dependent_modulus", "stick-slip",
        ParameterSpec("strength", "1", 0.0, 0.0, 5.0),
        # a compound with tan(delta) = 0.3, the upper end for tread rubber, at the rig's 1.5 kHz
        plausible_max=extra_modulus_strength(PLAUSIBLE_LOSS_FACTOR_MAX),
        description="The rubber modulus rises with excitation frequency, E(f) = E0 (1 + "
        "strength alpha log10(f / f0)) (end of section 5.3.2).",
        distinguishing_measurement="the ringing or stick-slip frequency of the element "
        "against its simulated natural frequency",
        problems={"transient"}, hidden_in={"transient"},
        hiding="Maxwell arms on the element's spring in transient tables (the ringing "
        "frequency rises, the first swing shrinks, the angle creeps); steady and raw data "
        "do not show it",
        acts_in="friction_model.dynamics.element_step (modulus_ratio, arm_storage_ratio)",
    ),
)

_REGISTRY: dict[str, PhysicalEffect] = {e.name: e for e in LIBRARY_EFFECTS}
_LIBRARY_NAMES = frozenset(_REGISTRY)


def register_effect(effect: PhysicalEffect, *, replace: bool = False) -> PhysicalEffect:
    """Add a physical effect (its ``physics`` says how it changes steady friction).

    Parameters
    ----------
    effect : PhysicalEffect
        The entry; ``physics`` is required and ``hidden_in`` may hold only ``"steady"``.
    replace : bool
        Allow replacing a registered (not a library) effect of the same name.

    Returns
    -------
    PhysicalEffect

    Raises
    ------
    ValueError
        A library name, a name already registered (without ``replace``), no ``physics``.
    """
    if not isinstance(effect, PhysicalEffect):
        raise TypeError(f"effect must be a PhysicalEffect, got {type(effect).__name__}")
    if effect.name in _LIBRARY_NAMES:
        raise ValueError(f"effect {effect.name!r} is a library effect and cannot be replaced")
    if effect.name in _REGISTRY and not replace:
        raise ValueError(f"effect {effect.name!r} is already registered; pass replace=True")
    if effect.physics is None:
        raise ValueError(f"effect {effect.name!r}: a registered effect needs its physics "
                         "function (how it changes mu)")
    if not effect.hidden_in <= {"steady"} or not effect.problems <= {"steady"}:
        raise ValueError(f"effect {effect.name!r}: physics acts on steady friction, so "
                         "problems and hidden_in may hold only 'steady'")
    _REGISTRY[effect.name] = effect
    return effect


def unregister_effect(name: str) -> None:
    """Remove a registered effect (library effects stay)."""
    if name in _LIBRARY_NAMES:
        raise ValueError(f"effect {name!r} is a library effect and cannot be removed")
    if name not in _REGISTRY:
        raise KeyError(f"no effect named {name!r}; registered: {sorted(_REGISTRY)}")
    del _REGISTRY[name]


def get_effect(name: str) -> PhysicalEffect:
    """The effect ``name`` (KeyError listing the names otherwise)."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise KeyError(f"no effect named {name!r}; effects: {', '.join(_REGISTRY)}") from None


def physical_effects(
    *, kind: str | None = None, problem: str | None = None, data: str | None = None
) -> tuple[PhysicalEffect, ...]:
    """The effects (library first, then registered), optionally filtered.

    Parameters
    ----------
    kind : str, optional
        Only effects of this kind (``"steady"``, ``"transient"``, ``"stick-slip"``).
    problem : str, optional
        Only effects a problem of this kind can reveal.
    data : str, optional
        Only effects that synthetic data of this kind carries.

    Examples
    --------
    >>> [e.name for e in physical_effects(kind="transient")]
    ['friction_relaxation']
    >>> [e.name for e in physical_effects(data="raw")][-1]
    'friction_relaxation'
    """
    found: Iterable[PhysicalEffect] = _REGISTRY.values()
    if kind is not None:
        found = [e for e in found if e.kind == kind]
    if problem is not None:
        found = [e for e in found if problem in e.problems]
    if data is not None:
        found = [e for e in found if data in e.hidden_in]
    return tuple(found)


def effect_names() -> tuple[str, ...]:
    """Names of every effect now registered (the library's six first).

    Examples
    --------
    >>> effect_names()[:2]
    ('humidity_water_layer', 'salinity_melting_point')
    """
    return tuple(_REGISTRY)
