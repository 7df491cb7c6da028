"""Effect size of a hidden effect on a steady table, and the strength that gives a wanted size.

The *effect size* of a dry/wet effect at a strength is the root-mean-square relative change
of mu over the rows of a steady table that a recalibrated base model cannot absorb. The
base of the discrepancy workflow (:class:`friction_model.discrepancy.SteadyProblem`) fits
one factor on mu, so the part of an effect that only scales mu is invisible to any
workflow: with ``a = mu_base / mu_effect`` and the factor ``c`` that the base's relative
least squares would fit, ``c = sum(a) / sum(a^2)``, the size is
``sqrt(mean((1 - c a)^2))`` (``absorb="scale"``, the default). ``absorb="none"`` gives the
plain ``sqrt(mean((mu_effect / mu_base - 1)^2))``.

Why this matters: an effect that is 3x the noise in the plain sense but mostly a common
factor (viscous shear is about one third factor) leaves a base residual of only 2x the
noise, and the held-out RMSE cannot fall by the 1 - 1/sqrt(1 + 3^2) = 68 % that an effect
of 3x the noise allows. Tests of the discrepancy workflow ask for effects "0.5, 3 and 10
times the noise": :func:`strength_for_effect_size` finds the strength whose effect size is
``size * noise`` by root-finding (the effect size grows with the strength on the grids
used; the root is bracketed and checked).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd
import scipy.optimize

from friction_model._validate import check_positive
from friction_model.drywet import DryWetParameters, friction_table
from friction_model.effects import DRY_WET_EFFECTS, EFFECT_NAMES, Effects
from friction_model.geometry import BlockGeometry
from synthetic.measurements import DEFAULT_NOISE, SteadyGrid

__all__ = ["effect_size", "strength_for_effect_size"]

# largest strength tried by the bracket search (ice_preheating stops at 1)
_MAX_STRENGTH = 1.0e3


def _grid(grid: SteadyGrid | Mapping[str, Sequence[float]] | None) -> SteadyGrid:
    if grid is None:
        return SteadyGrid()
    if isinstance(grid, Mapping):
        return SteadyGrid(**grid)
    if isinstance(grid, SteadyGrid):
        return grid
    raise TypeError(f"grid must be a SteadyGrid, a mapping or None, got {type(grid).__name__}")


def _check_effect(effect: str) -> None:
    if effect in DRY_WET_EFFECTS:
        return
    if effect in EFFECT_NAMES:
        raise ValueError(
            f"{effect} leaves steady states unchanged: its effect size on a steady table is 0"
        )
    raise ValueError(f"unknown effect {effect!r}; steady effects are {', '.join(DRY_WET_EFFECTS)}")


def _mu(table: pd.DataFrame, params: DryWetParameters) -> np.ndarray:
    mu = np.empty(len(table))
    for n_sipes, rows in table.groupby("n_sipes", sort=True):
        t = friction_table(
            BlockGeometry(n_sipes=int(n_sipes)), rows.drop(columns="n_sipes"), params
        )
        mu[table.index.get_indexer(rows.index)] = t["mu"].to_numpy(float)
    return mu


def effect_size(
    effect: str,
    strength: float,
    *,
    grid: SteadyGrid | Mapping[str, Sequence[float]] | None = None,
    params: DryWetParameters | None = None,
    absorb: str = "scale",
) -> float:
    """RMS relative change of mu over a steady table when ``effect`` is on at ``strength``.

    Parameters
    ----------
    effect : str
        A dry/wet effect (:data:`friction_model.effects.DRY_WET_EFFECTS`).
    strength : float
        Its strength (>= 0).
    grid : SteadyGrid or mapping, optional
        Conditions of the table (the default grid of :func:`make_steady_table`).
    params : DryWetParameters, optional
        Model parameters (calibrated defaults); their effects are replaced.
    absorb : {"scale", "none"}
        ``"scale"``: the change left after the base's factor on mu (module notes);
        ``"none"``: the plain change.

    Returns
    -------
    float
        The RMS relative change over the rows.

    Examples
    --------
    >>> effect_size("viscous_shear", 0.0)
    0.0
    >>> 0.01 < effect_size("ice_preheating", 0.1) < 0.1
    True
    """
    _check_effect(effect)
    _check_absorb(absorb)
    table = _grid(grid).frame()
    base = (params or DryWetParameters()).with_(effects=Effects.none())
    return _size(effect, strength, table, base, _mu(table, base), absorb)


def _check_absorb(absorb: str) -> None:
    if absorb not in ("scale", "none"):
        raise ValueError(f"absorb must be 'scale' or 'none', got {absorb!r}")


def _size(
    effect: str,
    strength: float,
    table: pd.DataFrame,
    base: DryWetParameters,
    mu0: np.ndarray,
    absorb: str,
) -> float:
    strength = float(strength)
    if not math.isfinite(strength) or strength < 0:
        raise ValueError(f"strength must be a finite number >= 0, got {strength!r}")
    if strength == 0.0:
        return 0.0
    mu1 = _mu(table, base.with_(effects=Effects.only(**{effect: strength})))
    if absorb == "none":
        return float(np.sqrt(np.mean((mu1 / mu0 - 1.0) ** 2)))
    a = mu0 / mu1  # the base's fit: min over c of sum((1 - c a)^2), relative residuals
    c = float(a.sum() / (a @ a))
    return float(np.sqrt(np.mean((1.0 - c * a) ** 2)))


def strength_for_effect_size(
    effect: str,
    size: float,
    *,
    noise: float = DEFAULT_NOISE,
    grid: SteadyGrid | Mapping[str, Sequence[float]] | None = None,
    params: DryWetParameters | None = None,
    rtol: float = 1e-4,
    absorb: str = "scale",
) -> float:
    """Strength of ``effect`` whose effect size is ``size`` times the relative noise.

    Parameters
    ----------
    effect : str
        A dry/wet effect.
    size : float
        Wanted effect size as a multiple of ``noise`` (> 0), e.g. 0.5, 3 or 10.
    noise : float
        Relative noise of the table (0.05 = 5 %).
    grid, params, absorb
        As for :func:`effect_size`.
    rtol : float
        Relative tolerance on the effect size.

    Returns
    -------
    float
        The strength (found with Brent's method on the monotone effect size).

    Raises
    ------
    ValueError
        When the effect cannot reach the size on this grid (the message gives the largest
        size it reaches): ``ice_preheating`` stops at strength 1, ``salinity_melting_point``
        where the melting point reaches a temperature of the table.

    Examples
    --------
    >>> s = strength_for_effect_size("viscous_shear", 3.0, noise=0.05)
    >>> round(effect_size("viscous_shear", s) / 0.05, 3)
    3.0
    """
    _check_effect(effect)
    _check_absorb(absorb)
    check_positive("size", size)
    check_positive("noise", noise)
    target = float(size) * float(noise)
    table = _grid(grid).frame()
    base = (params or DryWetParameters()).with_(effects=Effects.none())
    mu0 = _mu(table, base)

    def size_at(s: float) -> float:
        try:
            return _size(effect, s, table, base, mu0, absorb)
        except ValueError:  # beyond the validity of the model (melting point above T)
            return math.nan

    hi = 1.0
    reached = size_at(hi)
    while math.isfinite(reached) and reached < target and hi < _MAX_STRENGTH:
        if effect == "ice_preheating":
            break
        hi *= 2.0
        reached = size_at(hi)
    if not math.isfinite(reached):  # shrink to the largest valid strength
        lo_ok, hi_bad = 0.0, hi
        for _ in range(30):
            mid = 0.5 * (lo_ok + hi_bad)
            lo_ok, hi_bad = (mid, hi_bad) if math.isfinite(size_at(mid)) else (lo_ok, mid)
        hi, reached = lo_ok, size_at(lo_ok)
    if reached < target:
        raise ValueError(
            f"{effect} cannot reach effect size {size:g} x noise {noise:g} = {target:.4g} on "
            f"this grid: at most {reached:.4g} (strength {hi:.4g})"
        )
    # the size is near-linear in the strength: a tolerance of rtol on the strength gives
    # about rtol on the size
    return float(
        scipy.optimize.brentq(lambda s: size_at(s) - target, 0.0, hi, rtol=rtol, xtol=1e-9)
    )
