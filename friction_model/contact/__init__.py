"""Contact physics of rubber sliding on ice (thesis section 4.5).

The dry run-in / wet model (:mod:`.drywet`, its time march in :mod:`._march`), Blok's flash
temperature (:mod:`.flash_temperature`, Eq. 4.6 and 4.7), the initial water layer and the
melting point of salty ice (:mod:`.water_layer`), the switchable physical effects
(:mod:`.effects`), the model as a callable friction law (:mod:`.drywet_law`) and the
empirical friction laws with their fits (:mod:`.laws`).
"""

from friction_model.contact.drywet import *  # noqa: F403
from friction_model.contact.drywet import __all__ as _drywet
from friction_model.contact.drywet_law import DryWetLaw
from friction_model.contact.effects import DRY_WET_EFFECTS, EFFECT_NAMES, Effects
from friction_model.contact.flash_temperature import dry_run_in_length, flash_temperature_rise
from friction_model.contact.laws import *  # noqa: F403
from friction_model.contact.laws import __all__ as _laws
from friction_model.contact.water_layer import freezing_point_depression_K, initial_water_layer_m

__all__ = [
    *_drywet,
    *_laws,
    "DRY_WET_EFFECTS",
    "EFFECT_NAMES",
    "DryWetLaw",
    "Effects",
    "dry_run_in_length",
    "flash_temperature_rise",
    "freezing_point_depression_K",
    "initial_water_layer_m",
]
