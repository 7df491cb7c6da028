"""Named, switchable physical effects of the friction model.

The effects themselves (parameters, bounds, caps, how the data hide them) are the entries of
:mod:`friction_model.effect_registry`; the names here derive from it.

The base model is the dry run-in / wet model of section 4.5.1 with every effect at strength
0; each effect is a named part on top of it with a strength (0 = off, reduces exactly to the
base model; 1 = the calibrated physics; other values scale it). The synthetic-data generator
and the discrepancy workflow switch them on and off by these names.

Effects of the dry/wet friction model (this package):

``humidity_water_layer``
    The initial (bound) water layer on the ice grows with relative humidity (section 4.5.1).
``salinity_melting_point``
    Salt lowers the melting point of the ice surface (section 4.5.2).
``ice_preheating``
    Each element heats the ice for the elements behind it; the sipe lets it cool (Fig. 4.25).
``viscous_shear``
    Viscous shear of the melt-water film, ``eta v / h`` (Eq. 4.3).

Effects of the tread-block dynamics (applied by the dynamics models):

``friction_relaxation``
    First-order lag of the friction coefficient, Eq. 5.12.
``frequency_dependent_modulus``
    Rubber stiffens with excitation frequency (end of section 5.3.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

from friction_model.effect_registry import LIBRARY_EFFECTS

__all__ = ["DRY_WET_EFFECTS", "EFFECT_NAMES", "Effects"]

#: The library's steady effects, built into the dry/wet model (a strength field of
#: :class:`Effects` each).
DRY_WET_EFFECTS: tuple[str, ...] = tuple(e.name for e in LIBRARY_EFFECTS if e.kind == "steady")
#: The six library effects (registered ones: ``effect_registry.effect_names()``).
EFFECT_NAMES: tuple[str, ...] = tuple(e.name for e in LIBRARY_EFFECTS)


@dataclass(frozen=True)
class Effects:
    """Strengths of the switchable effects of the dry/wet friction model.

    Parameters
    ----------
    humidity_water_layer, salinity_melting_point, ice_preheating, viscous_shear : float
        Strength of each effect, >= 0 (0 = off, 1 = full physics). ``ice_preheating`` must
        lie in [0, 1]: the factor on the whole heat history that each element meets (the
        heat of all elements ahead of it, scaled once, not compounded per element).

    Examples
    --------
    >>> Effects.none().viscous_shear
    0.0
    >>> Effects().with_(viscous_shear=0.0).ice_preheating
    1.0
    """

    humidity_water_layer: float = 1.0
    salinity_melting_point: float = 1.0
    ice_preheating: float = 1.0
    viscous_shear: float = 1.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = float(getattr(self, f.name))
            if not math.isfinite(value) or value < 0:
                raise ValueError(f"effect strength {f.name} must be >= 0, got {value!r}")
            object.__setattr__(self, f.name, value)
        if self.ice_preheating > 1.0:
            raise ValueError(
                f"effect strength ice_preheating must lie in [0, 1], got {self.ice_preheating!r}"
            )

    @classmethod
    def none(cls) -> Effects:
        """All effects off: the base model."""
        return cls(**{name: 0.0 for name in DRY_WET_EFFECTS})

    @classmethod
    def only(cls, **strengths: float) -> Effects:
        """The base model with only the named effects switched on."""
        unknown = set(strengths) - set(DRY_WET_EFFECTS)
        if unknown:
            raise ValueError(
                f"unknown effect(s) {sorted(unknown)}; dry/wet effects are {DRY_WET_EFFECTS}"
            )
        return replace(cls.none(), **strengths)

    def with_(self, **strengths: float) -> Effects:
        """A copy with some strengths changed (names checked)."""
        unknown = set(strengths) - set(DRY_WET_EFFECTS)
        if unknown:
            raise ValueError(
                f"unknown effect(s) {sorted(unknown)}; dry/wet effects are {DRY_WET_EFFECTS}"
            )
        return replace(self, **strengths)

    def as_dict(self) -> dict[str, float]:
        """Effect name -> strength."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


if tuple(f.name for f in fields(Effects)) != DRY_WET_EFFECTS:  # pragma: no cover - a new
    # steady library effect needs its strength field here and its physics in the march
    raise ImportError(
        f"Effects fields {[f.name for f in fields(Effects)]} differ from the registry's "
        f"steady library effects {DRY_WET_EFFECTS}"
    )
