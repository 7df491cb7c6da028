"""Steady mu of the dry/wet model for many strengths of one effect in one vectorised march.

:func:`friction_model.contact.drywet.friction_table` takes one set of effect strengths per call and
costs about 0.1 s per call, most of it the march's loop over the cells of the block, nearly
independent of the number of conditions. The discrepancy workflow needs mu on a grid of 20-40
strengths of each candidate effect, so this module stacks the conditions once per strength
and marches them all together, with the strength given per row. The result equals
``friction_table`` exactly (``tests/test_discrepancy_steady.py`` checks every effect to 1e-12).

It uses the internals of :mod:`friction_model.contact.drywet` (``_prepare``, ``_element_tables``)
and :func:`friction_model.contact._march.march`, whose inputs broadcast over rows: the viscous
strength multiplies row arrays, the preheating factor multiplies the (rows, cells) heat
history, and the humidity and salinity effects act through the per-row bound layer ``h0``
and the melting point.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from friction_model.contact._march import march
from friction_model.contact.drywet import (
    DryWetParameters,
    _as_table,
    _element_tables,
    _prepare,
    _subcooling_K,
)
from friction_model.contact.effects import DRY_WET_EFFECTS
from friction_model.contact.water_layer import freezing_point_depression_K, initial_water_layer_m
from friction_model.geometry import BlockGeometry

__all__: list[str] = []

# the columns that describe a condition of a steady table (besides n_sipes)
CONDITION_COLUMNS = (
    "velocity_mps",
    "pressure_bar",
    "temperature_C",
    "humidity_pct",
    "salinity_pct",
)


def block_geometry(n_sipes: int) -> BlockGeometry:
    """The 20 mm x 80 mm rig sample with ``n_sipes`` sipes (G0, G3, ...)."""
    return BlockGeometry(n_sipes=int(n_sipes))


def _mu_one_geometry(
    geometry: BlockGeometry,
    conditions: pd.DataFrame,
    params: DryWetParameters,
    vary: str | None,
    strengths: np.ndarray,
) -> np.ndarray:
    """mu, shape (len(strengths), len(conditions)), for one block geometry."""
    n_s = len(strengths)
    n = len(conditions)
    if vary is None:
        n_s = 1
    stacked = pd.concat([conditions] * n_s, ignore_index=True)
    table = _as_table(stacked)
    base = params.with_(effects=params.effects.with_(**{vary: 0.0})) if vary else params
    prep = _prepare(geometry, table, base)
    inp = prep.inp
    if vary is not None:
        s_rows = np.repeat(np.asarray(strengths, dtype=float), n)
        eff = params.effects
        if vary == "viscous_shear":
            inp.viscous_strength = s_rows
        elif vary == "ice_preheating":
            inp.preheating = s_rows[:, None]
        elif vary == "humidity_water_layer":
            inp.h0 = initial_water_layer_m(
                inp.delta_T,
                table["humidity_pct"].to_numpy(float),
                qll_thickness_m=params.qll_thickness_m,
                humidity_gain=params.humidity_gain * eff.humidity_water_layer * 0.0
                + params.humidity_gain * s_rows,
            )
        elif vary == "salinity_melting_point":
            sal = table["salinity_pct"].to_numpy(float)
            temp = table["temperature_C"].to_numpy(float)
            t_melt = np.concatenate(
                [
                    params.ice.melting_point_C
                    - freezing_point_depression_K(
                        sal[k * n : (k + 1) * n], enrichment=params.salt_enrichment * float(s)
                    )
                    for k, s in enumerate(strengths)
                ]
            )
            d_t = _subcooling_K(temp, t_melt, sal, s_rows)
            inp.delta_T = d_t
            inp.h0 = initial_water_layer_m(
                d_t,
                table["humidity_pct"].to_numpy(float),
                qll_thickness_m=params.qll_thickness_m,
                humidity_gain=params.humidity_gain * eff.humidity_water_layer,
            )
        else:  # pragma: no cover - guarded by steady_mu
            raise ValueError(f"unknown dry/wet effect {vary!r}")
    res = march(prep.grid, inp)
    _, agg = _element_tables(geometry, prep, res)
    force = (agg["F_dry"] + agg["F_visc"] + agg["F_bnd"]).sum(axis=1)
    normal = prep.p_face * geometry.rubber_area_mm2 * 1e-6
    return (force / normal).reshape(n_s, n)


def steady_mu(
    conditions: pd.DataFrame,
    params: DryWetParameters,
    *,
    vary: str | None = None,
    strengths: Sequence[float] | np.ndarray = (),
) -> np.ndarray:
    """Block mu of the dry/wet model for every row, optionally on a grid of one strength.

    Parameters
    ----------
    conditions : pandas.DataFrame
        Columns :data:`CONDITION_COLUMNS` and ``n_sipes`` (one row per condition).
    params : DryWetParameters
        The model; its ``effects`` hold the strengths of the effects not varied.
    vary : str, optional
        A dry/wet effect whose strength takes each value of ``strengths`` in turn.
    strengths : sequence of float
        Strengths of ``vary`` (ignored without ``vary``).

    Returns
    -------
    ndarray
        Shape (len(conditions),) without ``vary``, else (len(strengths), len(conditions)).
    """
    if vary is not None and vary not in DRY_WET_EFFECTS:
        raise ValueError(f"vary must be one of {DRY_WET_EFFECTS}, got {vary!r}")
    strengths = np.atleast_1d(np.asarray(strengths, dtype=float))
    if vary is not None and strengths.size == 0:
        raise ValueError("strengths must not be empty when vary is given")
    n_s = 1 if vary is None else strengths.size
    out = np.empty((n_s, len(conditions)))
    sipes = conditions["n_sipes"].to_numpy()
    cond = conditions[list(CONDITION_COLUMNS)].reset_index(drop=True)
    for n_sipes in np.unique(sipes):
        rows = np.flatnonzero(sipes == n_sipes)
        out[:, rows] = _mu_one_geometry(
            block_geometry(int(n_sipes)), cond.iloc[rows], params, vary, strengths
        )
    return out[0] if vary is None else out
