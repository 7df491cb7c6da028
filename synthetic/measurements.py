"""Synthetic test-rig measurement data with switchable, unannounced physical effects.

Three kinds of data, each made from the friction model with a chosen set of named effects
(the entries of :mod:`friction_model.effect_registry`; each entry's ``hiding`` says how these
generators put it in the data) switched on at a chosen strength, so that a
data set can contain an effect without saying so:

* ``steady``: a steady friction characteristic table over a grid of velocity, pressure,
  temperature, humidity, salinity and number of sipes (:func:`make_steady_table`);
* ``transient``: the deflection angle of a tread-block element through a velocity step
  (thesis section 5.1.2, Fig. 5.7) (:func:`make_transient_table`);
* ``raw``: raw runs of the linear test rig in the evaluation CSV format, with the climate
  chamber drifting as in Fig. 4.6 (:func:`make_raw_runs`).

The transient model (the linearised element of Eq. 5.8, Eq. 5.12, the modulus effect and
their constants ``TAU_REF_S``, ``MODULUS_ALPHA``, ``MODULUS_F0_HZ``) lives in
:mod:`friction_model.dynamics.element_step`; its public names are re-exported here.

The files hold the data only; :func:`write_measurements` writes the truth (effects and
strengths, seed, noise, derived constants) to a separate ``<out>.truth.json`` only when asked
(``reveal=True``). Same seed, same options: the same bytes.

Effects and their strengths (0 = off, exactly the base model; 1 = the calibrated physics):

``humidity_water_layer``, ``salinity_melting_point``, ``ice_preheating``, ``viscous_shear``
    Strengths of :class:`friction_model.contact.effects.Effects` in the dry/wet model on top of the
    base model ``Effects.none()``. They change mu(v) and therefore every kind of data.
``friction_relaxation``
    Eq. 5.12: mu lags mu_ss(v) with time constant ``tau = strength * TAU_REF_S``. It changes
    the transient table and the accelerating/decelerating phases of raw runs; a steady table
    holds steady states and is unchanged by it.
``frequency_dependent_modulus``
    Rubber modulus ``E(f) = E0 (1 + strength * MODULUS_ALPHA * log10(f / MODULUS_F0_HZ))``
    for f >= f0 (E0 below), realised in the transient model as Maxwell arms on the element's
    spring (:func:`arm_storage_ratio`). It changes the transient table (the natural frequency
    rises to the fixed point f = f_n(E(f)), the first swing after the step shrinks, the angle
    then creeps to its static value, which E0 sets) and the stick-slip frequency
    (:func:`modulus_scaled_frequency_Hz`); steady and raw data are unchanged by it.

Notes
-----
Units: velocity m/s, pressure bar (tables) or Pa (model), temperature degC, relative humidity
%, salinity % (mass), time s, angle degrees, force N, frequency Hz, modulus Pa. Times of the
transient table start at 0 s with the element in steady sliding at the first velocity.
"""

from __future__ import annotations

import itertools
import json
import logging
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd
import scipy.signal

from friction_model.contact.drywet import DryWetParameters, friction_table
from friction_model.contact.effects import DRY_WET_EFFECTS, Effects
from friction_model.dynamics import velocity_step
from friction_model.dynamics.element_step import (
    MODULUS_ALPHA,
    MODULUS_F0_HZ,
    TAU_REF_S,
    arm_storage_ratio,
    element_natural_frequency_Hz,
    linear_step_states,
    modulus_ratio,
    modulus_scaled_frequency_Hz,
    sipe_block,
    step_element,
)
from friction_model.dynamics.rigid import (
    REFERENCE_LOSS_FACTOR,
    REFERENCE_YOUNGS_MODULUS_PA,
)
from friction_model.effect_registry import effect_names, get_effect
from friction_model.geometry import REFERENCE_SAMPLES
from synthetic.rig import make_raw_run, write_run_csv
from tir_common.atomic import json_safe
from tir_common.validate import check_nonnegative, check_positive

__all__ = [
    "DEFAULT_NOISE",
    "FLOAT_FORMAT",
    "KINDS",
    "MODULUS_ALPHA",
    "MODULUS_F0_HZ",
    "N_REPEATS",
    "RUN_INTERVAL_S",
    "STEADY_COLUMNS",
    "TAU_REF_S",
    "TRANSIENT_COLUMNS",
    "EffectSpec",
    "MeasurementOutput",
    "SteadyGrid",
    "arm_storage_ratio",
    "element_natural_frequency_Hz",
    "make_raw_runs",
    "make_steady_table",
    "make_transient_table",
    "modulus_ratio",
    "modulus_scaled_frequency_Hz",
    "truth_path",
    "write_measurements",
    "write_raw_runs",
    "write_table",
    "write_truth",
]

logger = logging.getLogger(__name__)

#: The kinds of data :func:`write_measurements` makes.
KINDS: tuple[str, ...] = ("steady", "transient", "raw")
#: Columns of the steady table, in order.
STEADY_COLUMNS: tuple[str, ...] = (
    "velocity_mps",
    "pressure_bar",
    "temperature_C",
    "humidity_pct",
    "salinity_pct",
    "n_sipes",
    "mu",
    "mu_std",
)
#: Columns of the transient table, in order.
TRANSIENT_COLUMNS: tuple[str, ...] = ("time_s", "velocity_mps", "angle_deg")
#: printf format of every number written (10 significant digits, fixed so that the same seed
#: gives the same bytes).
FLOAT_FORMAT = "%.10g"

#: Relative noise of mu when not given: 5 %, the relative RMSE of the calibrated model
#: against the Table 4.6 measurements (0.005-0.007 on mu of about 0.1-0.15), i.e. the size of
#: the scatter those measurements show.
DEFAULT_NOISE = 0.05
#: Repeated runs behind one steady value and its std ("every sample is measured for ten
#: times", section 4.2.3).
N_REPEATS = 10
#: Time between the starts of two raw runs, s: four specimens measured ten times each in the
#: roughly 45 min of Fig. 4.6 (section 4.2.3, Table 4.2), 45 * 60 / 40.
RUN_INTERVAL_S = 45.0 * 60.0 / 40.0

# Climate-chamber cycle of Fig. 4.6: +-1 degC and +-7 % relative humidity over about 45 min;
# at constant absolute humidity the relative humidity falls when the air warms, so the two
# move in opposite directions.
_CHAMBER_PERIOD_S = 45.0 * 60.0
_CHAMBER_TEMPERATURE_AMPLITUDE_C = 1.0
_CHAMBER_HUMIDITY_AMPLITUDE_PCT = 7.0
# Tabulation of mu(v) for the raw runs: from 0.01 m/s (below about 0.02 m/s the model sits at
# mu_dry, so lower speeds change nothing) to the highest run velocity, 64 points per run
# (spacing under 0.05 in log10(v) up to 7 m/s; the run velocities themselves are added, so
# the constant-velocity plateaus are exact).
_RAW_V_MIN_MPS = 0.01
_RAW_N_TABLE = 64
# Sensor noise of a raw run: the defaults of synthetic.rig.make_raw_run (2 N on 400 N).
_RIG_FORCE_NOISE_N = 2.0
_RIG_VELOCITY_NOISE_MPS = 0.002


# -- effects ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class EffectSpec:
    """Which named effects are on, and how strong.

    Parameters
    ----------
    strengths : mapping of str to float, optional
        Effect name -> strength (>= 0; 0 = off, 1 = calibrated physics). Names not given are
        off. Valid names: those of :mod:`friction_model.effect_registry`
        (:func:`~friction_model.effect_registry.effect_names`: the six library effects and any
        registered one, whose strength is the value of its parameter); ``ice_preheating`` must
        lie in [0, 1].

    Raises
    ------
    ValueError
        For an unknown name (the message lists the valid ones) or a bad strength.

    Examples
    --------
    >>> spec = EffectSpec({"friction_relaxation": 0.5, "viscous_shear": 1.0})
    >>> spec.relaxation_time_s
    0.01
    >>> spec.dry_wet.viscous_shear, spec.dry_wet.ice_preheating
    (1.0, 0.0)
    """

    strengths: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.strengths, Mapping):
            raise TypeError(
                "strengths must be a mapping of effect name to strength, "
                f"got {type(self.strengths).__name__}"
            )
        names = effect_names()
        unknown = sorted(str(k) for k in self.strengths if k not in names)
        if unknown:
            raise ValueError(
                f"unknown effect(s) {', '.join(unknown)}; valid effects are "
                f"{', '.join(names)}"
            )
        clean = {
            name: check_nonnegative(name, self.strengths[name])
            for name in names
            if name in self.strengths
        }
        # validates the dry/wet strengths (ice_preheating <= 1) with Effects' own message
        Effects.none().with_(**{k: v for k, v in clean.items() if k in DRY_WET_EFFECTS})
        object.__setattr__(self, "strengths", clean)

    @classmethod
    def coerce(cls, effects: EffectSpec | Mapping[str, float] | None) -> EffectSpec:
        """An :class:`EffectSpec` from None (base model), a mapping or an EffectSpec."""
        if effects is None:
            return cls()
        if isinstance(effects, EffectSpec):
            return effects
        if isinstance(effects, Mapping):
            return cls(effects)
        raise TypeError(
            "effects must be an EffectSpec, a mapping of effect name to strength or None, "
            f"got {type(effects).__name__}"
        )

    def strength(self, name: str) -> float:
        """Strength of effect ``name`` (0 when off)."""
        if name not in effect_names():
            raise ValueError(
                f"unknown effect {name!r}; valid effects are {', '.join(effect_names())}"
            )
        return float(self.strengths.get(name, 0.0))

    @property
    def dry_wet(self) -> Effects:
        """The dry/wet strengths as :class:`~friction_model.Effects` (base: all 0)."""
        return Effects.none().with_(
            **{k: v for k, v in self.strengths.items() if k in DRY_WET_EFFECTS}
        )

    @property
    def relaxation_time_s(self) -> float:
        """tau of Eq. 5.12, s: ``strength('friction_relaxation') * TAU_REF_S``."""
        return self.strength("friction_relaxation") * TAU_REF_S

    @property
    def modulus_strength(self) -> float:
        """Strength of ``frequency_dependent_modulus``."""
        return self.strength("frequency_dependent_modulus")

    def as_dict(self) -> dict[str, float]:
        """Every library effect and every effect switched on -> strength, 0 for those off
        (in registry order)."""
        return {name: self.strength(name) for name in effect_names()
                if name in self.strengths or get_effect(name).built_in}

    def check_carried(self, kind: str) -> None:
        """Refuse a switched-on registered effect that data of ``kind`` cannot carry (its
        entry's ``hidden_in``): it would be silently absent. (A library effect that leaves
        this kind unchanged, like the relaxation in a steady table, is documented there.)"""
        for name, value in self.strengths.items():
            effect = get_effect(name)
            if not effect.built_in and value != 0.0 and kind not in effect.hidden_in:
                raise ValueError(
                    f"effect {name} is not carried by {kind} data (its registry entry hides "
                    f"it in {', '.join(sorted(effect.hidden_in))} data only)"
                )

    def apply_physics(self, conditions: pd.DataFrame, mu: np.ndarray) -> np.ndarray:
        """``mu`` with the switched-on effects that have a physics function of their own
        (registered effects, :class:`~friction_model.effect_registry.PhysicalEffect`)
        applied in turn; the library effects are in the model already."""
        out = np.asarray(mu, dtype=float)
        for name, value in self.strengths.items():
            effect = get_effect(name)
            if effect.physics is not None and value != effect.parameter.null:
                out = np.asarray(effect.physics(conditions, out, value), dtype=float)
        return out


# -- validation helpers ----------------------------------------------------------------------
def _check_repeats(n_repeats: Any) -> int:
    if isinstance(n_repeats, bool) or int(n_repeats) != n_repeats or n_repeats < 2:
        raise ValueError(f"n_repeats must be an integer >= 2, got n_repeats={n_repeats!r}")
    return int(n_repeats)


def _values(name: str, values: Any, *, integer: bool = False) -> tuple:
    arr = np.atleast_1d(np.asarray(values, dtype=float))
    if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be a non-empty sequence of finite numbers, got {values!r}")
    if integer:
        if np.any(arr != np.round(arr)) or np.any(arr < 0):
            raise ValueError(f"{name} must hold integers >= 0, got {values!r}")
        return tuple(int(x) for x in arr)
    return tuple(float(x) for x in arr)


# -- steady table ----------------------------------------------------------------------------
@dataclass(frozen=True)
class SteadyGrid:
    """Grid of conditions of a steady characteristic table (every combination is a row).

    Parameters
    ----------
    velocities_mps : sequence of float
        Sliding velocities, m/s; default 1, 3, 5 (the HiLiTe series of section 4.2).
    pressures_bar : sequence of float
        Nominal pressures, bar; default 1, 2.5, 5 (section 4.2).
    temperatures_C : sequence of float
        Ice/ambient temperatures, degC; default -8, -4, -1 (section 4.2, Fig. 4.13).
    humidities_pct : sequence of float
        Relative humidities, %; default 40 and 90 (the low, rF < 50 %, and high, rF about
        90 %, states of Fig. 4.14).
    salinities_pct : sequence of float
        Salinity of the ice water, %; default 0 and 0.05 (Fig. 4.18).
    n_sipes : sequence of int
        Sipes per block; default 0 and 3 (G0 and G3, Fig. 4.18).

    Examples
    --------
    >>> len(SteadyGrid())
    216
    """

    velocities_mps: Sequence[float] = (1.0, 3.0, 5.0)
    pressures_bar: Sequence[float] = (1.0, 2.5, 5.0)
    temperatures_C: Sequence[float] = (-8.0, -4.0, -1.0)
    humidities_pct: Sequence[float] = (40.0, 90.0)
    salinities_pct: Sequence[float] = (0.0, 0.05)
    n_sipes: Sequence[int] = (0, 3)

    def __post_init__(self) -> None:
        for name in ("velocities_mps", "pressures_bar", "temperatures_C"):
            object.__setattr__(self, name, _values(name, getattr(self, name)))
        object.__setattr__(self, "humidities_pct", _values("humidities_pct", self.humidities_pct))
        object.__setattr__(self, "salinities_pct", _values("salinities_pct", self.salinities_pct))
        object.__setattr__(self, "n_sipes", _values("n_sipes", self.n_sipes, integer=True))
        for name in ("velocities_mps", "pressures_bar"):
            if min(getattr(self, name)) <= 0:
                raise ValueError(f"{name} must all be > 0, got {getattr(self, name)!r}")

    def __len__(self) -> int:
        return math.prod(len(getattr(self, name)) for name in self._fields())

    @staticmethod
    def _fields() -> tuple[str, ...]:
        return (
            "n_sipes",
            "pressures_bar",
            "temperatures_C",
            "humidities_pct",
            "salinities_pct",
            "velocities_mps",
        )

    def frame(self) -> pd.DataFrame:
        """All combinations as a table with the condition columns of :data:`STEADY_COLUMNS`.

        Rows are ordered by n_sipes, pressure, temperature, humidity, salinity, velocity
        (velocity fastest).
        """
        rows = list(itertools.product(*(getattr(self, name) for name in self._fields())))
        table = pd.DataFrame(
            rows,
            columns=[
                "n_sipes",
                "pressure_bar",
                "temperature_C",
                "humidity_pct",
                "salinity_pct",
                "velocity_mps",
            ],
        )
        return table[list(STEADY_COLUMNS[:6])]

    def to_dict(self) -> dict[str, list]:
        """Plain dict of the grid values (for the truth file)."""
        return {name: list(getattr(self, name)) for name in self._fields()}


def _params(effects: EffectSpec, params: DryWetParameters | None) -> DryWetParameters:
    return (params or DryWetParameters()).with_(effects=effects.dry_wet)


def _model_mu(conditions: pd.DataFrame, params: DryWetParameters) -> np.ndarray:
    """mu of the dry/wet model for a table with condition columns including n_sipes."""
    mu = np.empty(len(conditions))
    for n_sipes, rows in conditions.groupby("n_sipes", sort=True):
        table = friction_table(sipe_block(int(n_sipes)), rows.drop(columns="n_sipes"), params)
        mu[conditions.index.get_indexer(rows.index)] = table["mu"].to_numpy(float)
    return mu


def make_steady_table(
    grid: SteadyGrid | Mapping[str, Sequence[float]] | None = None,
    *,
    effects: EffectSpec | Mapping[str, float] | None = None,
    noise: float = DEFAULT_NOISE,
    rng: int | np.random.Generator | None = None,
    n_repeats: int = N_REPEATS,
    params: DryWetParameters | None = None,
) -> pd.DataFrame:
    """Steady friction characteristic over a grid of conditions, as a measurement reports it.

    Each value is the mean of ``n_repeats`` simulated repeated runs whose relative scatter is
    chosen so that the mean carries relative Gaussian noise ``noise``:
    ``mu = mu_model (1 + noise * e)``, e ~ N(0, 1). ``mu_std`` is what the repeats tell about
    that noise: their sample std over sqrt(n_repeats) (standard error of the mean), so it
    scatters about ``noise * mu_model``.

    Parameters
    ----------
    grid : SteadyGrid or mapping, optional
        Conditions (a mapping is passed to :class:`SteadyGrid`); the default grid when omitted.
    effects : EffectSpec or mapping, optional
        Effects switched on (None: the base model, every effect off).
    noise : float
        Relative standard deviation of mu, >= 0 (0.05 = 5 %).
    rng : int, numpy.random.Generator or None
        Seed or generator.
    n_repeats : int
        Repeated runs per value (>= 2).
    params : DryWetParameters, optional
        Model parameters (the calibrated defaults when omitted); their effects are replaced
        by ``effects``.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`STEADY_COLUMNS`: ``velocity_mps`` (m/s), ``pressure_bar`` (bar),
        ``temperature_C`` (degC), ``humidity_pct`` (%), ``salinity_pct`` (%), ``n_sipes``,
        ``mu``, ``mu_std`` (dimensionless). ``attrs["truth"]`` holds ``mu_model``, the
        noise-free values (a list).

    Notes
    -----
    ``friction_relaxation`` and ``frequency_dependent_modulus`` do not change steady states;
    with them alone the table equals the base model. A registered effect changes the
    model's mu through its ``physics`` function.

    Examples
    --------
    >>> t = make_steady_table({"velocities_mps": [1.0], "pressures_bar": [2.5],
    ...     "temperatures_C": [-5.0], "humidities_pct": [40.0], "salinities_pct": [0.0],
    ...     "n_sipes": [3]}, noise=0.0)
    >>> list(t.columns) == list(STEADY_COLUMNS), float(t.loc[0, "mu_std"])
    (True, 0.0)
    """
    spec = EffectSpec.coerce(effects)
    noise = check_nonnegative("noise", noise)
    n_repeats = _check_repeats(n_repeats)
    if grid is None:
        grid = SteadyGrid()
    elif isinstance(grid, Mapping):
        grid = SteadyGrid(**grid)
    elif not isinstance(grid, SteadyGrid):
        raise TypeError(f"grid must be a SteadyGrid, a mapping or None, got {type(grid).__name__}")
    gen = np.random.default_rng(rng)
    table = grid.frame()
    mu_model = spec.apply_physics(table, _model_mu(table, _params(spec, params)))
    # per-run relative scatter sqrt(n) * noise, so the mean of n runs has relative std noise
    eps = gen.standard_normal((len(table), n_repeats)) * (noise * math.sqrt(n_repeats))
    table["mu"] = mu_model * (1.0 + eps.mean(axis=1))
    negative = int((table["mu"] <= 0).sum())
    if negative:
        # the readers refuse mu <= 0 (steady tables): a table they cannot read is no data
        raise ValueError(
            f"noise={noise:g} puts mu <= 0 in {negative} of {len(table)} rows (a relative "
            "spread that wide reaches below zero), which the steady-table reader refuses; "
            "give a noise below 0.2 (a row then falls below zero with probability 3e-7)")
    table["mu_std"] = mu_model * eps.std(axis=1, ddof=1) / math.sqrt(n_repeats)
    table.attrs["truth"] = {"mu_model": mu_model.tolist()}
    logger.debug("steady table: %d rows, noise %g", len(table), noise)
    return table


# -- transient table -------------------------------------------------------------------------
def make_transient_table(
    *,
    effects: EffectSpec | Mapping[str, float] | None = None,
    noise: float = DEFAULT_NOISE,
    rng: int | np.random.Generator | None = None,
    v1_mps: float = 1.0,
    v2_mps: float = 5.0,
    t_step_s: float = 0.2,
    duration_s: float | None = None,
    sample_rate_Hz: float = 10_000.0,
    n_sipes: int = 3,
    pressure_bar: float = 1.2,
    temperature_C: float = -3.9,
    humidity_pct: float = 72.4,
    salinity_pct: float = 0.0,
    params: DryWetParameters | None = None,
) -> pd.DataFrame:
    """Deflection angle of a tread-block element through a velocity step (Fig. 5.7).

    The element is the rigid bar on a torsional spring and damper of Eq. 5.8, linearised
    about phi = 0 with the normal force held at its preload value, driven by the friction
    moment ``F_N d mu_R(t)``, where mu_R follows Eq. 5.12 (``friction_relaxation``) towards
    the dry/wet model's steady mu at the carriage velocity::

        J phi'' + d_phi phi' + (c_phi - F_N d + m g d/2) phi + sum_k q_k = F_N d mu_R
        tau mu_R' + mu_R = mu_ss(v0(t))

    The q_k are the moments of Maxwell arms that make the spring's modulus follow
    E(f) (``frequency_dependent_modulus``, :func:`arm_storage_ratio`); they vanish at
    strength 0 and in steady states. The velocity steps from ``v1_mps`` to ``v2_mps`` at
    ``t_step_s``; before it the element slides steadily. The response is exact (matrix
    exponential), so it is fast (tens of ms).

    Parameters
    ----------
    effects : EffectSpec or mapping, optional
        Effects switched on (None: base model).
    noise : float
        Gaussian noise on the angle, relative to the steady angle before the step
        (std = noise * |angle before|), >= 0.
    rng : int, numpy.random.Generator or None
        Seed or generator.
    v1_mps, v2_mps : float
        Sliding velocity before and after the step, m/s (1 and 5 as in Fig. 5.5).
    t_step_s : float
        Time of the step, s (0.2 s as in Fig. 5.7).
    duration_s : float, optional
        Recorded time after the step, s; default max(0.2 s, 10 tau), so the lag settles to
        exp(-10) of the change.
    sample_rate_Hz : float
        Samples per second; 10 kHz resolves the element's ringing (about 600-1000 Hz) with
        more than 10 samples per period.
    n_sipes : int
        Sipes of the 20 mm x 80 mm block; the leading element is modelled (3: G3, the block
        of chapter 5).
    pressure_bar : float
        Nominal pressure, bar; 1.2 bar is 48 N per element of G3 (p L w / 4), near the
        45 N of the chapter 5 scenario's rigid model (``examples/velocity_step.py``).
    temperature_C, humidity_pct, salinity_pct : float
        Climate of the ice, degC, %, %; defaults the HiLiTe session of Table 4.2 (the rig
        that filmed Fig. 5.7).
    params : DryWetParameters, optional
        Dry/wet model parameters; effects replaced by ``effects``.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`TRANSIENT_COLUMNS`: ``time_s`` (s, from 0, step ``1 / sample_rate_Hz``),
        ``velocity_mps`` (m/s, the commanded carriage velocity, exact),
        ``angle_deg`` (degrees, > 0 when the tip trails). ``attrs["truth"]`` holds the
        noise-free angle and the model constants.

    Notes
    -----
    Linearisation: sin(phi) = phi and cos(phi) = 1; at 20 degrees this misstates the moments
    by 2 %, at 30 degrees by 4.5 %. The tip's own velocity d phi' is left out of the sliding
    velocity (the friction follows the carriage): with tau = 20 ms the friction answers the
    element's 1 kHz motion attenuated to below 1 %, and the omission keeps a falling mu(v)
    from undamping the element, so the model shows no stick-slip.

    What each dynamic effect does to the step response: ``friction_relaxation`` delays the
    change of the angle as 1 - exp(-t / tau) (63 % after about tau); ``frequency_dependent_
    modulus`` stiffens the element at its natural frequency (which rises to the fixed point
    f = f_n(E(f)), :func:`element_natural_frequency_Hz`), so it rings faster and first moves
    only part of the way, then creeps to the static angle, which is set by E0 and unchanged.

    Examples
    --------
    >>> t = make_transient_table(noise=0.0)
    >>> list(t.columns) == list(TRANSIENT_COLUMNS)
    True
    >>> bool(t["angle_deg"].iloc[0] > t["angle_deg"].iloc[-1])  # faster: less friction
    True
    """
    spec = EffectSpec.coerce(effects)
    spec.check_carried("transient")
    noise = check_nonnegative("noise", noise)
    for name, value in (("v1_mps", v1_mps), ("v2_mps", v2_mps), ("t_step_s", t_step_s)):
        check_positive(name, value)
    fs = check_positive("sample_rate_Hz", sample_rate_Hz)
    check_positive("pressure_bar", pressure_bar)
    tau = spec.relaxation_time_s
    if duration_s is None:
        duration_s = max(0.2, 10.0 * tau)
    duration_s = check_positive("duration_s", duration_s)
    gen = np.random.default_rng(rng)

    geometry = sipe_block(n_sipes)
    conditions = pd.DataFrame(
        {
            "velocity_mps": [float(v1_mps), float(v2_mps)],
            "pressure_bar": float(pressure_bar),
            "temperature_C": float(temperature_C),
            "humidity_pct": float(humidity_pct),
            "salinity_pct": float(salinity_pct),
        }
    )
    mu1, mu2 = friction_table(geometry, conditions, _params(spec, params))["mu"].to_numpy(float)
    el = step_element(
        geometry=geometry, pressure_bar=float(pressure_bar), modulus_strength=spec.modulus_strength
    )

    moment = el.normal_force_N * el.lever_m
    c_eff = el.stiffness_Nm_rad
    a, b = el.system(tau)
    n = round((t_step_s + duration_s) * fs) + 1
    t = np.arange(n) / fs
    states = linear_step_states(a, b, mu1, mu2, t, float(t_step_s), 1.0 / fs)
    angle_true = np.degrees(states[:, 0])
    angle_before = math.degrees(moment * mu1 / c_eff)
    angle = angle_true + noise * abs(angle_before) * gen.standard_normal(n)
    profile = velocity_step(v1_mps, v2_mps, t_step_s)
    velocity = np.fromiter((profile(ti) for ti in t), dtype=float, count=n)

    table = pd.DataFrame({"time_s": t, "velocity_mps": velocity, "angle_deg": angle})
    table.attrs["truth"] = {
        "angle_deg": angle_true.tolist(),
        "mu_before": float(mu1),
        "mu_after": float(mu2),
        "angle_before_deg": angle_before,
        "angle_after_deg": math.degrees(moment * mu2 / c_eff),
        "tau_s": tau,
        "youngs_modulus_static_Pa": REFERENCE_YOUNGS_MODULUS_PA,
        "youngs_modulus_dynamic_Pa": el.dynamic_modulus_Pa,
        "natural_frequency_Hz": el.natural_frequency_Hz,
        "spring_constant_Nm_rad": el.spring_Nm_rad,
        "damping_constant_Nms_rad": el.damper_Nms_rad,
        "effective_stiffness_Nm_rad": c_eff,
        "inertia_kgm2": el.inertia_kgm2,
        "normal_force_N": el.normal_force_N,
        "loss_factor": REFERENCE_LOSS_FACTOR,
    }
    logger.debug(
        "transient table: %d samples, tau %.4g s, f_n %.1f Hz", n, tau, el.natural_frequency_Hz
    )
    return table


# -- raw runs --------------------------------------------------------------------------------
def _specimen_name(n_sipes: int) -> str:
    for name, geometry in REFERENCE_SAMPLES.items():
        if geometry.n_sipes == n_sipes:
            return name
    return f"S{n_sipes}"


def _relax(mu_ss: np.ndarray, sliding: np.ndarray, tau: float, dt: float) -> np.ndarray:
    """Eq. 5.12 over the sliding samples, starting in equilibrium (exact for piecewise-linear
    mu_ss, the integrator of RelaxedFriction.simulate as a recursive filter)."""
    out = mu_ss.copy()
    idx = np.flatnonzero(sliding)
    if tau <= 0 or idx.size < 2:
        return out
    x = dt / tau
    e = math.exp(-x)
    c = 1.0 + math.expm1(-x) / x
    u = mu_ss[idx]
    zi = scipy.signal.lfiltic([c, 1.0 - e - c], [1.0, -e], y=[u[0]], x=[u[0]])
    out[idx], _ = scipy.signal.lfilter([c, 1.0 - e - c], [1.0, -e], u, zi=zi)
    return out


def make_raw_runs(
    *,
    effects: EffectSpec | Mapping[str, float] | None = None,
    noise: float = DEFAULT_NOISE,
    rng: int | np.random.Generator | None = None,
    n_sipes: Sequence[int] = (0, 3),
    velocities_mps: Sequence[float] = (1.0, 3.0, 5.0),
    pressure_bar: float = 2.5,
    temperature_C: float = -3.9,
    humidity_pct: float = 72.4,
    salinity_pct: float = 0.0,
    n_repeats: int = 3,
    profile: Literal["steady", "instationary"] = "steady",
    sample_rate_Hz: float = 10_000.0,
    sensor_noise: bool = True,
    run_interval_s: float = RUN_INTERVAL_S,
    params: DryWetParameters | None = None,
) -> list[pd.DataFrame]:
    """Raw test-rig runs (evaluation CSV format) with mu(v) from the model and the effects.

    Runs are made in measurement order: for each velocity and repetition the specimens one
    after another (section 4.2.3), run k starting ``k * run_interval_s`` into the session.
    The chamber drifts as in Fig. 4.6: the mean temperature of run k is
    ``temperature_C + 1 degC sin(2 pi t_k / 45 min + phase)``, its humidity
    ``humidity_pct - 7 % sin(...)`` (clipped to 0-100 %), the phase random; within a run
    :func:`synthetic.rig.make_raw_run` adds a small linear drift and sensor noise. Each run's
    mu(v) is the dry/wet model at the run's own temperature and humidity, times a run factor
    ``1 + noise * e`` (e ~ N(0, 1)); ``friction_relaxation`` lags it by Eq. 5.12 over the
    sliding phase (starting in equilibrium when the sample starts to slide).

    Parameters
    ----------
    effects : EffectSpec or mapping, optional
        Effects switched on (None: base model).
    noise : float
        Relative run-to-run scatter of mu, >= 0.
    rng : int, numpy.random.Generator or None
        Seed or generator.
    n_sipes : sequence of int
        Specimens by their number of sipes (20 mm x 80 mm blocks; 0 and 3 are G0 and G3).
    velocities_mps : sequence of float
        Sliding velocities (peak velocities of instationary runs), m/s.
    pressure_bar : float
        Nominal pressure, bar; the normal force is p L w (400 N at 2.5 bar).
    temperature_C, humidity_pct : float
        Set-points of the chamber, degC and %; defaults the session of Table 4.2.
    salinity_pct : float
        Salinity of the ice water, %.
    n_repeats : int
        Repetitions per specimen and velocity (1-10; the thesis measures ten).
    profile : {"steady", "instationary"}
        Velocity profile, the ``kind`` of :func:`synthetic.rig.make_raw_run` (written to the
        file's ``kind`` metadata).
    sample_rate_Hz : float
        Sample rate, Hz, at most 50 kHz (the rig's rate).
    sensor_noise : bool
        Keep the rig's sensor noise (forces 2 N, velocity 0.002 m/s); False for none.
    run_interval_s : float
        Time between run starts, s.
    params : DryWetParameters, optional
        Dry/wet model parameters; effects replaced by ``effects``.

    Returns
    -------
    list of pandas.DataFrame
        One run each, as :func:`synthetic.rig.make_raw_run` returns it (``attrs["metadata"]``:
        ``specimen``, ``condition``, ``run``, ``nominal_area_mm2``, ``inertial_mass_kg``,
        ``kind``; ``attrs["truth"]`` arrays with the lagged ``mu``), plus
        ``attrs["run_truth"]``: ``session_time_s``, ``temperature_C``, ``humidity_pct``,
        ``mu_factor``, ``n_sipes`` of the run.

    Examples
    --------
    >>> runs = make_raw_runs(n_sipes=[3], velocities_mps=[1.0], n_repeats=1,
    ...                      sample_rate_Hz=1000.0, rng=1)
    >>> runs[0].attrs["metadata"]["specimen"], list(runs[0].columns)[:2]
    ('G3', ['time_s', 'velocity_mps'])
    """
    spec = EffectSpec.coerce(effects)
    spec.check_carried("raw")
    noise = check_nonnegative("noise", noise)
    sipes = _values("n_sipes", n_sipes, integer=True)
    velocities = _values("velocities_mps", velocities_mps)
    fs, interval = _check_raw_options(
        velocities_mps, velocities, n_repeats, sample_rate_Hz, pressure_bar, run_interval_s
    )
    if profile not in ("steady", "instationary"):
        raise ValueError(f"profile must be 'steady' or 'instationary', got profile={profile!r}")
    gen = np.random.default_rng(rng)
    model = _params(spec, params)
    tau = spec.relaxation_time_s

    order = [(v, rep, s) for v in velocities for rep in range(int(n_repeats)) for s in sipes]
    session, temps, hums, factors, seeds = _session_drift(
        len(order), gen, interval, float(temperature_C), float(humidity_pct), noise
    )
    v_low = min(_RAW_V_MIN_MPS, min(velocities))
    v_grid = np.union1d(np.geomspace(v_low, max(velocities), _RAW_N_TABLE), velocities)
    mu_tables = _run_mu_tables(
        [s for _, _, s in order], v_grid, temps, hums, float(pressure_bar), salinity_pct, model
    )
    log_grid = np.log(v_grid)
    condition = (
        f"p={pressure_bar:g}bar T={temperature_C:g}C rH={humidity_pct:g}% K={salinity_pct:g}%"
    )

    runs: list[pd.DataFrame] = []
    run_numbers: dict[tuple[float, int], int] = {}
    for k, (v, _rep, s) in enumerate(order):
        geometry = sipe_block(s)
        run_no = run_numbers[(v, s)] = run_numbers.get((v, s), 0) + 1
        table = mu_tables[k] * factors[k]

        def mu_of_v(vv: np.ndarray, table: np.ndarray = table) -> np.ndarray:
            return np.interp(np.log(np.maximum(vv, v_low)), log_grid, table)

        run = make_raw_run(
            mu_of_v,
            velocity_mps=v,
            kind=profile,
            sample_rate_Hz=fs,
            normal_force_N=float(pressure_bar) * 1e5 * geometry.nominal_area_mm2 * 1e-6,
            force_noise_N=_RIG_FORCE_NOISE_N if sensor_noise else 0.0,
            velocity_noise_mps=_RIG_VELOCITY_NOISE_MPS if sensor_noise else 0.0,
            temperature_C=float(temps[k]),
            humidity_pct=float(hums[k]),
            rng=int(seeds[k]),
            metadata={
                "specimen": _specimen_name(s),
                "condition": condition,
                "run": run_no,
                "nominal_area_mm2": geometry.nominal_area_mm2,
                # the discrepancy workflow's steady table needs it as its own key (the
                # condition text is free)
                "salinity_pct": float(salinity_pct),
            },
        )
        if tau > 0:
            _lag_friction(run, tau, 1.0 / fs)
        climate = (float(session[k]), float(temps[k]), float(hums[k]), float(factors[k]))
        run.attrs["run_truth"] = _run_truth(k + 1, int(s), float(v), *climate)
        runs.append(run)
    logger.debug("made %d raw runs (%s, %.0f Hz)", len(runs), profile, fs)
    return runs


def _run_truth(
    file_index: int,
    n_sipes: int,
    velocity_mps: float,
    session_time_s: float,
    temperature_C: float,
    humidity_pct: float,
    mu_factor: float,
) -> dict[str, Any]:
    """``attrs["run_truth"]`` of one raw run."""
    return {
        "file_index": file_index,
        "n_sipes": n_sipes,
        "velocity_mps": velocity_mps,
        "session_time_s": session_time_s,
        "temperature_C": temperature_C,
        "humidity_pct": humidity_pct,
        "mu_factor": mu_factor,
    }


def _run_mu_tables(
    sipes: list[int],
    v_grid: np.ndarray,
    temps: np.ndarray,
    hums: np.ndarray,
    pressure_bar: float,
    salinity_pct: float,
    model: DryWetParameters,
) -> np.ndarray:
    """mu of the dry/wet model on ``v_grid`` for each run's specimen and chamber climate,
    (n_runs, n_grid)."""
    conditions = pd.DataFrame(
        {
            "n_sipes": np.repeat(sipes, v_grid.size),
            "velocity_mps": np.tile(v_grid, len(sipes)),
            "pressure_bar": pressure_bar,
            "temperature_C": np.repeat(temps, v_grid.size),
            "humidity_pct": np.repeat(hums, v_grid.size),
            "salinity_pct": float(salinity_pct),
        }
    )
    return _model_mu(conditions, model).reshape(len(sipes), v_grid.size)


def _check_raw_options(
    velocities_mps: Any,
    velocities: tuple,
    n_repeats: Any,
    sample_rate_Hz: Any,
    pressure_bar: Any,
    run_interval_s: Any,
) -> tuple[float, float]:
    """Check the options of :func:`make_raw_runs`; the sample rate and run interval."""
    if min(velocities) <= 0:
        raise ValueError(f"velocities_mps must all be > 0, got {velocities_mps!r}")
    if isinstance(n_repeats, bool) or int(n_repeats) != n_repeats or not 1 <= n_repeats <= 10:
        raise ValueError(f"n_repeats must be an integer in 1..10, got n_repeats={n_repeats!r}")
    fs = check_positive("sample_rate_Hz", sample_rate_Hz)
    if fs > 50_000:
        raise ValueError(f"sample_rate_Hz must be <= 50000 (the rig's rate), got {fs!r}")
    check_positive("pressure_bar", pressure_bar)
    return fs, check_positive("run_interval_s", run_interval_s)


def _session_drift(
    n_runs: int,
    gen: np.random.Generator,
    interval_s: float,
    temperature_C: float,
    humidity_pct: float,
    noise: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Start time, chamber temperature and humidity (Fig. 4.6), mu factor and seed per run.

    Random draws, in this order: the phase of the chamber swing, the run factors
    ``1 + noise * e`` and the runs' seeds.
    """
    phase = gen.uniform(0.0, 2.0 * np.pi)
    session = np.arange(n_runs) * interval_s
    swing = np.sin(2.0 * np.pi * session / _CHAMBER_PERIOD_S + phase)
    temps = temperature_C + _CHAMBER_TEMPERATURE_AMPLITUDE_C * swing
    hums = np.clip(humidity_pct - _CHAMBER_HUMIDITY_AMPLITUDE_PCT * swing, 0.0, 100.0)
    factors = 1.0 + noise * gen.standard_normal(n_runs)
    seeds = gen.integers(0, 2**63 - 1, size=n_runs)
    return session, temps, hums, factors, seeds


def _lag_friction(run: pd.DataFrame, tau_s: float, dt_s: float) -> None:
    """Lag the run's friction behind mu(v) by Eq. 5.12 over its sliding phase (in place)."""
    truth = run.attrs["truth"]
    sliding = truth["velocity_mps"] > 0
    lagged = _relax(truth["mu"], sliding, tau_s, dt_s)
    run["friction_force_N"] = (
        run["friction_force_N"].to_numpy() + (lagged - truth["mu"]) * truth["normal_force_N"]
    )
    truth["mu"] = lagged


# -- writing ---------------------------------------------------------------------------------
def write_table(table: pd.DataFrame, path: str | os.PathLike[str]) -> Path:
    """Write a steady or transient table as CSV (fixed float format, ``\\n`` line ends).

    Parameters
    ----------
    table : pandas.DataFrame
        From :func:`make_steady_table` or :func:`make_transient_table`.
    path : str or path-like
        Output file; its folder is created.

    Returns
    -------
    pathlib.Path
        The written file.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", encoding="utf-8", newline="") as fh:
        table.to_csv(fh, index=False, float_format=FLOAT_FORMAT, lineterminator="\n")
    return path


def write_raw_runs(
    runs: Sequence[pd.DataFrame], out_dir: str | os.PathLike[str], *, prefix: str = "run"
) -> list[Path]:
    """Write raw runs as ``<out_dir>/<prefix>_001.csv``, ... in the test-rig CSV format.

    Parameters
    ----------
    runs : sequence of pandas.DataFrame
        From :func:`make_raw_runs`.
    out_dir : str or path-like
        Output folder (created).
    prefix : str
        File name prefix.

    Returns
    -------
    list of pathlib.Path
        The written files, in run order.

    Raises
    ------
    ValueError
        If the folder holds other ``<prefix>_*.csv`` files, which would mix with these.
    """
    out = Path(out_dir)
    width = max(3, len(str(len(runs))))
    names = {f"{prefix}_{k:0{width}d}.csv" for k in range(1, len(runs) + 1)}
    stale = sorted(p.name for p in out.glob(f"{prefix}_*.csv") if p.name not in names)
    if stale:
        raise ValueError(
            f"out_dir {out} holds run files this output would not replace ({', '.join(stale)}); "
            "use an empty or new folder"
        )
    out.mkdir(parents=True, exist_ok=True)
    return [
        write_run_csv(run, out / f"{prefix}_{k:0{width}d}.csv", float_format=FLOAT_FORMAT)
        for k, run in enumerate(runs, start=1)
    ]


def truth_path(out: str | os.PathLike[str]) -> Path:
    """The truth file beside an output: ``<out>.truth.json`` (a folder ``runs/`` gives
    ``runs.truth.json`` next to it).

    Examples
    --------
    >>> truth_path("data/steady.csv").as_posix()
    'data/steady.csv.truth.json'
    """
    out = Path(out)
    return out.with_name(out.name + ".truth.json")


def write_truth(out: str | os.PathLike[str], truth: Mapping[str, Any]) -> Path:
    """Write the truth of an output to :func:`truth_path` ``(out)`` as sorted, indented JSON."""
    path = truth_path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(json_safe(truth), indent=2, sort_keys=True)
    path.write_text(text + "\n", encoding="utf-8")
    return path


@dataclass(frozen=True)
class MeasurementOutput:
    """What :func:`write_measurements` wrote.

    Attributes
    ----------
    kind : str
        ``steady``, ``transient`` or ``raw``.
    files : list of pathlib.Path
        Data files written (one table, or the run CSVs).
    n_rows : int
        Rows of the table, or runs written for ``raw``.
    truth_file : pathlib.Path or None
        The truth file when revealed.
    """

    kind: str
    files: list[Path]
    n_rows: int
    truth_file: Path | None


def write_measurements(
    kind: str,
    out: str | os.PathLike[str],
    *,
    effects: EffectSpec | Mapping[str, float] | None = None,
    noise: float = DEFAULT_NOISE,
    seed: int | None = None,
    reveal: bool = False,
    **options: Any,
) -> MeasurementOutput:
    """Make one kind of synthetic measurement and write it, with the truth only if asked.

    Parameters
    ----------
    kind : {"steady", "transient", "raw"}
        What to make.
    out : str or path-like
        Output CSV file (``steady``, ``transient``) or folder of run CSVs (``raw``).
    effects : EffectSpec or mapping, optional
        Effects switched on (None: the base model).
    noise : float
        Relative noise (see the makers).
    seed : int, optional
        Random seed; the same seed and options give the same bytes.
    reveal : bool
        Also write ``<out>.truth.json`` (effects and strengths, seed, noise, reference
        constants, options and kind-specific truth).
    **options
        Passed to :func:`make_steady_table` (``grid``, ``n_repeats``, ``params``),
        :func:`make_transient_table` or :func:`make_raw_runs`.

    Returns
    -------
    MeasurementOutput
    """
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got kind={kind!r}")
    spec = EffectSpec.coerce(effects)
    out = Path(out)
    extra: dict[str, Any]
    if kind == "steady":
        table = make_steady_table(effects=spec, noise=noise, rng=seed, **options)
        files = [write_table(table, out)]
        n_rows = len(table)
        grid = options.get("grid")
        grid = SteadyGrid(**grid) if isinstance(grid, Mapping) else grid or SteadyGrid()
        extra = {"grid": grid.to_dict(), "mu_model": table.attrs["truth"]["mu_model"]}
    elif kind == "transient":
        table = make_transient_table(effects=spec, noise=noise, rng=seed, **options)
        files = [write_table(table, out)]
        n_rows = len(table)
        extra = dict(table.attrs["truth"])
        extra["angle_deg_noise_free"] = extra.pop("angle_deg")
    else:
        runs = make_raw_runs(effects=spec, noise=noise, rng=seed, **options)
        files = write_raw_runs(runs, out)
        n_rows = len(runs)
        extra = {
            "runs": [
                {"file": f.name, **run.attrs["run_truth"]}
                for f, run in zip(files, runs, strict=True)
            ],
            "relaxation_time_s": spec.relaxation_time_s,
        }
    truth_file = None
    if reveal:
        truth = {
            "generator": "synthetic.measurements",
            "kind": kind,
            "effects": spec.as_dict(),
            "seed": seed,
            "noise": float(noise),
            "reference": {
                "tau_ref_s": TAU_REF_S,
                "modulus_alpha": MODULUS_ALPHA,
                "modulus_f0_Hz": MODULUS_F0_HZ,
                "youngs_modulus_E0_Pa": REFERENCE_YOUNGS_MODULUS_PA,
            },
            "options": {k: v for k, v in options.items() if k not in ("grid", "params")},
            "truth": extra,
        }
        if options.get("params") is not None:
            truth["params"] = options["params"].to_dict()
        truth_file = write_truth(out, truth)
    elif truth_path(out).exists():
        logger.warning(
            "%s is left from an earlier revealed run and does not describe this output",
            truth_path(out),
        )
    return MeasurementOutput(kind=kind, files=files, n_rows=n_rows, truth_file=truth_file)
