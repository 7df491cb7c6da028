"""Rubber-ice friction: the dry run-in / wet model, friction laws and test-rig evaluation.

Public API
----------
Model inputs
    :class:`BlockGeometry`, :func:`reference_block`, :class:`Conditions`,
    :class:`DryWetParameters`, :class:`Effects`, :class:`IceProperties`,
    :class:`WaterProperties`.
Dry/wet model (section 4.5.1)
    :func:`dry_run_in_length` (Eq. 4.7), :func:`flash_temperature_rise` (Eq. 4.6),
    :func:`simulate_block`, :func:`friction_table`, :func:`real_contact_fraction`,
    :func:`initial_water_layer_m`, :func:`freezing_point_depression_K`.
Friction laws (Eq. 2.4, 4.8, 4.9, 5.4, 5.7, 5.24) and relaxation (Eq. 5.12)
    :class:`FrictionLaw`, :class:`ConstantLaw`, :class:`DecreasingSqrtLaw`,
    :class:`IncreasingSqrtLaw`, :class:`ExponentialLaw`, :class:`ArctanExponentialLaw`,
    :class:`VenkateshLaw`, :class:`RelaxedFriction`, :func:`fit_law`, :class:`FitResult`.
Calibration (Table 4.6)
    :func:`calibrate_table_4_6`, :func:`table_4_6_targets`, :func:`evaluate_on_table_4_6`.
"""

from friction_model.blok import dry_run_in_length, flash_temperature_rise
from friction_model.calibration import (
    CalibrationResult,
    calibrate_table_4_6,
    evaluate_on_table_4_6,
    table_4_6_targets,
)
from friction_model.conditions import Conditions
from friction_model.constants import ICE, WATER, IceProperties, WaterProperties
from friction_model.drywet import (
    BlockFriction,
    DryWetParameters,
    friction_table,
    real_contact_fraction,
    simulate_block,
)
from friction_model.effects import DRY_WET_EFFECTS, EFFECT_NAMES, Effects
from friction_model.geometry import REFERENCE_SAMPLES, BlockGeometry, reference_block
from friction_model.laws import (
    ArctanExponentialLaw,
    ConstantLaw,
    DecreasingSqrtLaw,
    ExponentialLaw,
    FitResult,
    FrictionLaw,
    IncreasingSqrtLaw,
    RelaxedFriction,
    VenkateshLaw,
    fit_law,
)
from friction_model.water_layer import freezing_point_depression_K, initial_water_layer_m

__all__ = [
    "DRY_WET_EFFECTS",
    "EFFECT_NAMES",
    "ICE",
    "REFERENCE_SAMPLES",
    "WATER",
    "ArctanExponentialLaw",
    "BlockFriction",
    "BlockGeometry",
    "CalibrationResult",
    "Conditions",
    "ConstantLaw",
    "DecreasingSqrtLaw",
    "DryWetParameters",
    "Effects",
    "ExponentialLaw",
    "FitResult",
    "FrictionLaw",
    "IceProperties",
    "IncreasingSqrtLaw",
    "RelaxedFriction",
    "VenkateshLaw",
    "WaterProperties",
    "calibrate_table_4_6",
    "dry_run_in_length",
    "evaluate_on_table_4_6",
    "fit_law",
    "flash_temperature_rise",
    "freezing_point_depression_K",
    "friction_table",
    "initial_water_layer_m",
    "real_contact_fraction",
    "reference_block",
    "simulate_block",
    "table_4_6_targets",
]
