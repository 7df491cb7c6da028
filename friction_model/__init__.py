"""Rubber-ice friction: the dry run-in / wet model, friction laws and test-rig evaluation.

This package knows no images (it imports only :mod:`tir_common`); it is laid out in rooms,
one per question, each with an ``__init__`` that lists its public names:

:mod:`friction_model.contact` -- what happens in the contact (section 4.5)
    The dry run-in / wet model (``drywet``, its march along the block in ``_march``), Blok's
    flash temperature (``flash_temperature``, Eq. 4.6 and 4.7), the initial water layer
    (``water_layer``), the switchable effects (``effects``), the model as a friction law
    (``drywet_law``) and the empirical friction laws with their fits (``laws``).
:mod:`friction_model.rig` -- the linear test rig (sections 4.2.4 and 4.4)
    Reading a run (``_io``), finding its constant-velocity window (``signals``,
    ``plateaus``), evaluating steady and instationary runs (``steady``, ``instationary``),
    averaging repeats (``aggregate``), the batch (``files``, ``batch``) and its outputs
    (``figures``, ``write``); parameters and results in ``params`` and ``results``.
:mod:`friction_model.identification` -- from measurements to parameters (section 5.4)
    Measured contact and lever arm (``coupling``), element identification (``identify``),
    the calibration to Table 4.6 (``table_4_6``).
:mod:`friction_model.dynamics` -- the tread block in motion (chapter 5)
    Rigid, Euler-Bernoulli and Timoshenko models, stick-slip, the velocity-step element.
:mod:`friction_model.discrepancy` -- where model and measurement disagree
    The discrepancy workflow (steady, transient, stick-slip).

At the top level stay what every room uses: the material constants (``constants``), the
physical effects, one registry entry each (``effect_registry``), the
rubber compound (``compound``), the conditions (``conditions``), the block geometry
(``geometry``), the calibrated-parameter file (``params_file``), the Table 4.6 figures
(``plots``), model selection criteria (``model_selection``) and two private helpers, the
table reader (``_table_io``) and the least-squares helpers (``_fitting``).

Public API
----------
Model inputs
    :class:`BlockGeometry`, :func:`reference_block`, :class:`Conditions`,
    :class:`DryWetParameters`, :class:`Effects`, :class:`IceProperties`,
    :class:`WaterProperties`.
Physical effects (:mod:`friction_model.effect_registry`)
    :class:`PhysicalEffect`, :func:`register_effect`, :func:`unregister_effect`,
    :func:`physical_effects`, :func:`effect_names`.
Dry/wet model (section 4.5.1), in :mod:`friction_model.contact`
    :func:`dry_run_in_length` (Eq. 4.7), :func:`flash_temperature_rise` (Eq. 4.6),
    :func:`simulate_block`, :func:`friction_table`, :func:`element_friction_table`,
    :class:`DryWetLaw` (the model as a friction law), :func:`real_contact_fraction`,
    :func:`initial_water_layer_m`, :func:`freezing_point_depression_K`.
Friction laws (Eq. 2.4, 4.8, 4.9, 5.4, 5.7, 5.24) and relaxation (Eq. 5.12)
    :class:`FrictionLaw`, :class:`ConstantLaw`, :class:`DecreasingSqrtLaw`,
    :class:`IncreasingSqrtLaw`, :class:`ExponentialLaw`, :class:`ArctanExponentialLaw`,
    :class:`VenkateshLaw`, :class:`RelaxedFriction`, :func:`fit_law`, :class:`FitResult`.
Test-rig evaluation (section 4.2.4 and 4.4), all of it in :mod:`friction_model.rig`
    :func:`read_run`, :func:`evaluate_steady_run`, :func:`evaluate_instationary_run`,
    :func:`evaluate_runs`, :func:`evaluate_folder`, :func:`write_outputs`,
    :func:`find_constant_velocity_window`, :func:`mean_friction_coefficients`,
    :class:`RunFormatError`, :class:`EvaluationResult`.
Calibration (Table 4.6)
    :func:`calibrate_table_4_6`, :func:`table_4_6_targets`, :func:`evaluate_on_table_4_6`.
Coupling and identification (section 5.4), in :mod:`friction_model.identification` and
:mod:`friction_model.params_file`
    :func:`contact_from_pipeline`, :class:`MeasuredContact`, :func:`drywet_inputs`,
    :func:`lever_arm_observations`, :func:`fit_lever_arm`, :class:`LeverArmFit`,
    :func:`identify_parameters`, :class:`IdentificationResult`, :class:`DeflectionSeries`,
    :class:`SteadyCharacteristic`, :func:`linear_element_response`,
    :func:`read_characteristic`, :func:`read_parameters`, :func:`write_parameters`,
    :class:`ParameterFileError`.
Calibration from measured results and running the calibrated model,
:mod:`friction_model.identification.workflow`, :mod:`friction_model.calibrated_model`
    :func:`calibrate_from_results`, :class:`CalibratedParameters`,
    :func:`simulate_calibrated`, :class:`CalibratedRun`.
Velocity-step element model (Eq. 5.8 linearised, Eq. 5.12),
:mod:`friction_model.dynamics.element_step`
    :func:`step_response`, :func:`step_element`, :class:`StepElement`.
Discrepancy workflow: :mod:`friction_model.discrepancy`.
"""

from friction_model.calibrated_model import CalibratedRun, simulate_calibrated
from friction_model.compound import REFERENCE_COMPOUND, Compound
from friction_model.conditions import Conditions
from friction_model.constants import ICE, WATER, IceProperties, WaterProperties
from friction_model.contact.drywet import (
    BlockFriction,
    DryWetParameters,
    element_friction_table,
    friction_table,
    real_contact_fraction,
    simulate_block,
)
from friction_model.contact.drywet_law import DryWetLaw
from friction_model.contact.effects import DRY_WET_EFFECTS, EFFECT_NAMES, Effects
from friction_model.contact.flash_temperature import dry_run_in_length, flash_temperature_rise
from friction_model.contact.laws import (
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
from friction_model.contact.water_layer import freezing_point_depression_K, initial_water_layer_m
from friction_model.dynamics.contact import element_real_contact_fractions
from friction_model.dynamics.element_step import StepElement, step_element, step_response
from friction_model.effect_registry import (
    PhysicalEffect,
    effect_names,
    physical_effects,
    register_effect,
    unregister_effect,
)
from friction_model.geometry import REFERENCE_SAMPLES, BlockGeometry, as_geometry, reference_block
from friction_model.identification.coupling import (
    LeverArmFit,
    MeasuredContact,
    contact_from_pipeline,
    drywet_inputs,
    fit_lever_arm,
    lever_arm_observations,
)
from friction_model.identification.identify import (
    DeflectionSeries,
    IdentificationResult,
    SteadyCharacteristic,
    identify_parameters,
    linear_element_response,
    read_characteristic,
)
from friction_model.identification.table_4_6 import (
    CalibrationResult,
    calibrate_table_4_6,
    evaluate_on_table_4_6,
    table_4_6_targets,
)
from friction_model.identification.workflow import CalibratedParameters, calibrate_from_results
from friction_model.params_file import ParameterFileError, read_parameters, write_parameters
from friction_model.rig import (
    EvaluationResult,
    RunFormatError,
    evaluate_folder,
    evaluate_instationary_run,
    evaluate_runs,
    evaluate_steady_run,
    find_constant_velocity_window,
    mean_friction_coefficients,
    read_run,
    write_outputs,
)

__all__ = [
    "DRY_WET_EFFECTS",
    "EFFECT_NAMES",
    "ICE",
    "REFERENCE_COMPOUND",
    "REFERENCE_SAMPLES",
    "WATER",
    "ArctanExponentialLaw",
    "BlockFriction",
    "BlockGeometry",
    "CalibratedParameters",
    "CalibratedRun",
    "CalibrationResult",
    "Compound",
    "Conditions",
    "ConstantLaw",
    "DecreasingSqrtLaw",
    "DeflectionSeries",
    "DryWetLaw",
    "DryWetParameters",
    "Effects",
    "EvaluationResult",
    "ExponentialLaw",
    "FitResult",
    "FrictionLaw",
    "IceProperties",
    "IdentificationResult",
    "IncreasingSqrtLaw",
    "LeverArmFit",
    "MeasuredContact",
    "ParameterFileError",
    "PhysicalEffect",
    "RelaxedFriction",
    "RunFormatError",
    "SteadyCharacteristic",
    "StepElement",
    "VenkateshLaw",
    "WaterProperties",
    "as_geometry",
    "calibrate_from_results",
    "calibrate_table_4_6",
    "contact_from_pipeline",
    "dry_run_in_length",
    "drywet_inputs",
    "effect_names",
    "element_friction_table",
    "element_real_contact_fractions",
    "evaluate_folder",
    "evaluate_instationary_run",
    "evaluate_on_table_4_6",
    "evaluate_runs",
    "evaluate_steady_run",
    "find_constant_velocity_window",
    "fit_law",
    "fit_lever_arm",
    "flash_temperature_rise",
    "freezing_point_depression_K",
    "friction_table",
    "identify_parameters",
    "initial_water_layer_m",
    "lever_arm_observations",
    "linear_element_response",
    "mean_friction_coefficients",
    "physical_effects",
    "read_characteristic",
    "read_parameters",
    "read_run",
    "real_contact_fraction",
    "reference_block",
    "register_effect",
    "simulate_block",
    "simulate_calibrated",
    "step_element",
    "step_response",
    "table_4_6_targets",
    "unregister_effect",
    "write_outputs",
    "write_parameters",
]
