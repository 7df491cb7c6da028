"""Discrepancy problem for a steady friction characteristic table.

:class:`SteadyProblem` couples a steady table (``docs/formats.md``, "Steady table": one row
per condition with ``mu`` and ``mu_std``) with the dry/wet model of section 4.5.1
(:func:`friction_model.contact.drywet.friction_table`) so that
:func:`~friction_model.discrepancy.run_discrepancy` can name the effect it lacks.
"""

from __future__ import annotations

import hashlib
import logging
import math
import os
from collections import OrderedDict
from collections.abc import Mapping

import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from friction_model._table_io import TableSource, read_table
from friction_model.conditions import (
    HUMIDITY_RANGE_PCT,
    PRESSURE_RANGE_PA,
    SALINITY_RANGE_PCT,
    TEMPERATURE_RANGE_C,
)
from friction_model.contact.drywet import DryWetParameters
from friction_model.contact.effects import DRY_WET_EFFECTS, Effects
from friction_model.contact.water_layer import freezing_point_depression_K
from friction_model.discrepancy._problem import get_candidate
from friction_model.discrepancy._steady_curves import CONDITION_COLUMNS, steady_mu
from friction_model.geometry import BlockGeometry, reference_block
from friction_model.replicates import replicate_noise, value_levels, velocity_levels

__all__ = [
    "GROUP_COLUMNS",
    "MIN_RELATIVE_SIGMA",
    "SteadyProblem",
    "read_steady_table",
    "steady_table_from_characteristic",
]

logger = logging.getLogger(__name__)

#: A hold-out group is one condition of the rig: a whole velocity sweep at fixed pressure,
#: temperature, humidity, salinity and specimen.
GROUP_COLUMNS: tuple[str, ...] = (
    "pressure_bar",
    "temperature_C",
    "humidity_pct",
    "salinity_pct",
    "n_sipes",
)
#: Floor of the relative standard deviation of mu: 0.1 %, the accuracy of the interpolated
#: candidate curves (tested to < 1e-3 relative), so that noise-free tables stay usable.
MIN_RELATIVE_SIGMA = 1e-3

# knots of the strength grid per effect: (number, spacing); tested in
# tests/test_discrepancy_steady.py to interpolate within 1e-3 of mu (relative)
_KNOTS = {
    "humidity_water_layer": (16, "linear"),  # mu is almost linear in the bound layer
    "salinity_melting_point": (30, "chebyshev"),  # steep where the melting point nears T
    "ice_preheating": (16, "linear"),
    "viscous_shear": (32, "square"),  # strongest curvature near 0
}
# margin to the melting point (K) and to the critical film (share) of the bounds
_MELT_MARGIN_K = 0.1
_FILM_SHARE = 0.97
_CACHE: OrderedDict = OrderedDict()
_CACHE_SIZE = 64


def _knots(name: str, upper: float) -> np.ndarray:
    n, spacing = _KNOTS[name]
    u = np.linspace(0.0, 1.0, n)
    if spacing == "chebyshev":
        u = 0.5 * (1.0 - np.cos(np.pi * u))
    elif spacing == "square":
        u = u * u
    return upper * u


#: Set-point tolerance (relative, absolute) of the conditions a rig measures per run: runs
#: whose measured pressure, temperature or humidity differ by less belong to one condition.
#: The rig holds them far closer (demo runs: 0.003 bar, 0.0003 K, 0.002 %); the conditions
#: of a study differ by far more (Table 4.6: 2.5 and 5 bar, -5 and -1 degC, 40 and 95 %).
_SET_POINT_TOL = {
    "pressure_bar": (0.05, 0.0),
    "temperature_C": (0.0, 0.5),
    "humidity_pct": (0.0, 5.0),
}
#: Columns a steady table must have, and the fewest rows it needs.
_NEEDED = (*CONDITION_COLUMNS, "n_sipes", "mu")
_MIN_ROWS = 4
_EXPECTED = f"{', '.join(_NEEDED)}[, mu_std] (docs/formats.md, Steady table)"


def _check_table(table: pd.DataFrame, source: TableSource) -> dict[str, np.ndarray]:
    """Check a steady table; its needed columns (and ``mu_std``) as float arrays.

    Every message names the table (``source``: a file or ``"steady table"``), the column,
    the data row (1-based; with the file line for a file) and what was expected.
    """
    err = source.missing(_NEEDED, list(table.columns), expected=_EXPECTED)
    if err is not None:
        raise err
    if len(table) < _MIN_ROWS:
        where = "" if source.header_line is None else f" (file line {source.header_line})"
        raise source.error(
            f"expected at least {_MIN_ROWS} data rows after the column header{where}, got "
            f"{len(table)}"
        )
    table = table.reset_index(drop=True)
    numeric = {col: source.numbers(table, col) for col in _NEEDED}
    if "mu_std" in table:
        numeric["mu_std"] = source.numbers(table, "mu_std")
    def outside(col: str, low: float, high: float, what: str,
                hint: str = "") -> tuple[str, np.ndarray, str]:
        return (col, (numeric[col] < low) | (numeric[col] > high),
                f"{what} in [{low:g}, {high:g}]{hint}")

    rules = (
        ("mu", numeric["mu"] <= 0, "a number > 0"),
        ("velocity_mps", numeric["velocity_mps"] <= 0, "a number > 0"),
        # the model's conditions (friction_model.Conditions' ranges), checked where the
        # row is named: a table in kelvin stopped at an effect's bound on the salinity
        outside("pressure_bar", *(x / 1e5 for x in PRESSURE_RANGE_PA), "a pressure in bar"),
        outside("temperature_C", *TEMPERATURE_RANGE_C, "a temperature in degC",
                " (ice below its melting point; kelvin?)"),
        outside("humidity_pct", *HUMIDITY_RANGE_PCT, "a relative humidity in %"),
        outside("salinity_pct", *SALINITY_RANGE_PCT, "a salinity in %"),
        (
            "n_sipes",
            (numeric["n_sipes"] != np.round(numeric["n_sipes"])) | (numeric["n_sipes"] < 0),
            "an integer >= 0",
        ),
        (
            "mu_std",
            numeric["mu_std"] < 0 if "mu_std" in numeric else np.zeros(0, bool),
            "a number >= 0",
        ),
    )
    for col, bad, rule in rules:
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            got = float(numeric[col][i])
            raise source.error(
                f"column '{col}', {source.where(i)}: expected {rule}, got {got!r}",
                column=col,
                index=i,
            )
    return numeric


def read_steady_table(
    path: str | os.PathLike[str],
    *,
    salinity_pct: float | None = None,
    pressure_bar: float | None = None,
    n_sipes: int | None = None,
) -> pd.DataFrame:
    """Read and check a steady table CSV (docs/formats.md, "Steady table"), or the
    evaluation's ``steady_characteristic.csv`` (:func:`steady_table_from_characteristic`).

    Any delimiter and decimal mark of :mod:`friction_model._table_io` are read (``,`` with
    ``.``, ``;`` or tab with ``.`` or ``,``).

    Parameters
    ----------
    path : str or path-like
        CSV with the columns ``velocity_mps``, ``pressure_bar``, ``temperature_C``,
        ``humidity_pct``, ``salinity_pct``, ``n_sipes``, ``mu`` and optionally ``mu_std``;
        or a ``steady_characteristic.csv`` (``row_type``, ``mu_mean_method1``, ...).
    salinity_pct, pressure_bar, n_sipes : optional
        For a ``steady_characteristic.csv``: the conditions it does not record (see
        :func:`steady_table_from_characteristic`).

    Returns
    -------
    pandas.DataFrame
        The table, ready for :class:`SteadyProblem`.

    Raises
    ------
    ValueError
        Naming the file, the column, the data row and file line and what was expected: a
        missing column, fewer than 4 rows, an entry that is not a finite number, mu <= 0,
        n_sipes not an integer >= 0, mu_std < 0, a row's conditions outside the model's
        (velocity <= 0, pressure outside 0.01-1000 bar, temperature outside -60-0 degC,
        humidity outside 0-100 %, salinity outside 0-3.5 %).
    OSError
        When the file cannot be opened.
    """
    table, source = read_table(path)
    if "mu_mean_method1" in table.columns and "mu" not in table.columns:
        table = steady_table_from_characteristic(
            table, source, salinity_pct=salinity_pct, pressure_bar=pressure_bar,
            n_sipes=n_sipes,
        )
        source = TableSource(f"{source.file} (as a steady table)")
    else:
        err = source.missing(_NEEDED, list(table.columns), expected=_EXPECTED)
        if err is not None:
            raise err
        for col in (*_NEEDED, "mu_std"):
            if col in table.columns:
                table[col] = source.numbers(table, col)
    _check_table(table, source)
    return table


def steady_table_from_characteristic(
    table: pd.DataFrame,
    source: TableSource | None = None,
    *,
    salinity_pct: float | None = None,
    pressure_bar: float | None = None,
    n_sipes: int | None = None,
) -> pd.DataFrame:
    """A steady table from the evaluation's ``steady_characteristic.csv``.

    The ``run`` rows where there are any (each repeat a measurement), else the ``aggregate``
    rows. ``mu`` is ``mu_mean_method1``; ``mu_std`` the pooled scatter of the repeats at
    one velocity (:func:`friction_model.replicates.replicate_noise`), or for aggregate rows
    the standard error of their mean, ``mu_std_runs / sqrt(n_runs)`` (absent without
    repeats: the problem then estimates it). The conditions the file does not record are
    derived from its own columns, else taken from the arguments:

    * ``pressure_bar``: the argument, else ``normal_pressure_Pa / 1e5``, else
      ``normal_force_N`` over the nominal area of the specimen's reference block
      (``specimen`` G0, G3, G5, G6 or G7);
    * the measured pressure, temperature and humidity of the runs are replaced by the mean
      of their set point (runs within 5 %, 0.5 K and 5 % of each other), so that the
      repeats of one condition form one condition;
    * ``n_sipes``: the argument, else the column or ``meta_n_sipes``, else each row's
      specimen's reference block (a file of G0 and G3 runs gives each row its own);
    * ``salinity_pct``: the argument, else the column or ``meta_salinity_pct`` (a
      ``# salinity_pct:`` line in the run files);
    * ``temperature_C``, ``humidity_pct``: the file's (the rig measures them).

    Raises
    ------
    ValueError
        One line naming the file, what is missing and the option that gives it.
    """
    src = source or TableSource("steady_characteristic.csv")
    if "row_type" in table.columns:
        kinds = table["row_type"].astype(str).str.strip()
        for kind in ("run", "aggregate"):
            if (kinds == kind).any():
                table = table[kinds == kind]
                break
    table = table.reset_index(drop=True)
    for col in ("temperature_C", "humidity_pct"):
        if col not in table.columns:
            raise src.error(f"column '{col}' missing: the rig's run files must record it",
                            column=col)
    out = pd.DataFrame({
        "velocity_mps": src.numbers(table, "velocity_mps"),
        "pressure_bar": _set_points(_characteristic_pressure(table, src, pressure_bar),
                                    *_SET_POINT_TOL["pressure_bar"]),
        "temperature_C": _set_points(src.numbers(table, "temperature_C"),
                                     *_SET_POINT_TOL["temperature_C"]),
        "humidity_pct": _set_points(src.numbers(table, "humidity_pct"),
                                    *_SET_POINT_TOL["humidity_pct"]),
        "salinity_pct": _characteristic_value(
            table, src, "salinity_pct", salinity_pct, "--salinity PCT (0 for fresh-water ice)"),
        "n_sipes": _characteristic_sipes(table, src, n_sipes),
        "mu": src.numbers(table, "mu_mean_method1"),
    })
    mu_std = _characteristic_mu_std(table, out)
    if mu_std is not None:
        out["mu_std"] = mu_std
    return out


def _set_points(values: np.ndarray, rel_tol: float, abs_tol: float) -> np.ndarray:
    """Each measured condition replaced by the mean of its level (its set point)."""
    levels = value_levels(values, rel_tol=rel_tol, abs_tol=abs_tol)
    means = np.bincount(levels, weights=values) / np.bincount(levels)
    return means[levels]


def _specimen_blocks(table: pd.DataFrame) -> list[BlockGeometry] | None:
    """The reference block each row's ``specimen`` names (None unless every row names
    one: G0 and G3 runs evaluated together give each row its own block)."""
    if "specimen" not in table.columns:
        return None
    blocks: dict[str, BlockGeometry] = {}
    names = table["specimen"].astype(str).str.strip().tolist()
    for name in set(names):
        try:
            blocks[name] = reference_block(name)
        except ValueError:
            return None
    return [blocks[name] for name in names]


def _characteristic_value(
    table: pd.DataFrame, src: TableSource, column: str, given: float | None, option: str
) -> np.ndarray:
    """A condition: the argument, else the column or its ``meta_`` column."""
    if given is not None:
        return np.full(len(table), float(given))
    for col in (column, f"meta_{column}"):
        if col in table.columns:
            return src.numbers(table, col)
    raise src.error(f"no '{column}' (neither a column nor a '# {column}:' line in the run "
                    f"files); give {option}")


def _characteristic_sipes(
    table: pd.DataFrame, src: TableSource, given: int | None
) -> np.ndarray:
    """``n_sipes``: the argument, the column, or the specimen's reference block."""
    if given is None and not ({"n_sipes", "meta_n_sipes"} & set(table.columns)):
        blocks = _specimen_blocks(table)
        if blocks is not None:
            return np.array([b.n_sipes for b in blocks])
    return _characteristic_value(
        table, src, "n_sipes", given, "--n-sipes N (or name a reference block G0/G3/G5/G6/G7 "
        "as the runs' specimen)")


def _characteristic_pressure(
    table: pd.DataFrame, src: TableSource, given: float | None
) -> np.ndarray:
    """Nominal pressure, bar: the argument, the recorded pressure, or force over area."""
    if given is not None:
        return np.full(len(table), float(given))
    if "normal_pressure_Pa" in table.columns:
        p = src.numbers(table, "normal_pressure_Pa", finite=False)
        if np.all(np.isfinite(p)):
            return p / 1e5
    blocks = _specimen_blocks(table)
    if "normal_force_N" in table.columns and blocks is not None:
        force = src.numbers(table, "normal_force_N")
        area_m2 = np.array([b.nominal_area_mm2 for b in blocks]) * 1e-6
        return force / area_m2 / 1e5
    raise src.error("no nominal pressure (normal_pressure_Pa, or normal_force_N with a "
                    "reference block G0/G3/G5/G6/G7 as the specimen); give --pressure-bar P")


def _characteristic_mu_std(table: pd.DataFrame, out: pd.DataFrame) -> np.ndarray | None:
    """The noise of each mu: the repeats' pooled scatter, or an aggregate's standard error."""
    if {"mu_std_runs", "n_runs"} <= set(table.columns):
        sd = pd.to_numeric(table["mu_std_runs"], errors="coerce").to_numpy(float)
        n_runs = pd.to_numeric(table["n_runs"], errors="coerce").to_numpy(float)
        if np.all(np.isfinite(sd) & (sd > 0) & (n_runs >= 2)):
            return sd / np.sqrt(n_runs)
    keys = [str(x) for x in velocity_levels(out["velocity_mps"].to_numpy(float))]
    for col in ("specimen", "condition"):
        if col in table.columns:
            keys = [f"{k}|{x}" for k, x in zip(keys, table[col].astype(str), strict=True)]
    sigma, dof = replicate_noise(out["mu"].to_numpy(float), np.asarray(keys))
    return np.full(len(out), sigma) if dof > 0 and math.isfinite(sigma) else None


class SteadyProblem:
    """A steady characteristic table against the dry/wet model with ``Effects.none()``.

    Parameters
    ----------
    table : pandas.DataFrame
        Steady table: ``velocity_mps``, ``pressure_bar``, ``temperature_C``,
        ``humidity_pct``, ``salinity_pct``, ``n_sipes``, ``mu`` and optionally ``mu_std``
        (standard error of each mu). Any further numeric column (e.g. ``time_s``, when the
        rows were measured one after the other) becomes a covariate of the where-analysis.
    params : DryWetParameters, optional
        Calibrated model (e.g. from a parameter file); the calibrated defaults when omitted.
        Its effect strengths are replaced by ``Effects.none()``: the base model.
    sigma : {"pooled", "rows"}
        ``"pooled"`` (default): sigma = r * mu with r the root-mean-square of
        ``mu_std / mu`` over the table, because the rig's scatter is relative and each
        mu_std, from 10 repeats, itself scatters by about 24 %; ``"rows"``: mu_std as given.
        Without ``mu_std``, r is the relative RMS residual of the base model (which can only
        hide an effect, never invent one). r is at least :data:`MIN_RELATIVE_SIGMA`.

    Notes
    -----
    Hold-out groups (:attr:`groups`): one condition each (:data:`GROUP_COLUMNS`); a table
    of one condition is grouped by velocity level instead (repeats at one velocity
    together).

    Base (nuisance) parameter: one factor on mu (``n_base = 1``), fitted in closed form by
    weighted least squares. It stands for the overall level that a new ice batch or
    rubber run-in shifts (``mu_dry`` and the real-contact law act almost as a factor), and
    it is identifiable: every candidate changes mu differently across conditions, none as
    one factor. Other model parameters (``boundary_shear_Pa``, ``critical_film_m``) keep
    their calibrated values: each trades off with a candidate (tau_b with the viscous
    shear and the water layer, h_c with the humidity layer), so fitting them would make
    the candidates unidentifiable.

    Candidates: the four dry/wet effects of :data:`friction_model.contact.effects.DRY_WET_EFFECTS`,
    each with one parameter, its strength (null 0). ``friction_relaxation`` and
    ``frequency_dependent_modulus`` leave steady states exactly unchanged, so a steady
    table cannot reveal them; they are not in :attr:`effect_names`.

    Speed: mu of each candidate is computed exactly on a grid of strengths (one vectorised
    march per candidate) and interpolated with a cubic spline in between, within 1e-3 of
    mu (relative); single combinations (the current model) are computed exactly.

    Examples
    --------
    >>> import itertools
    >>> rows = list(itertools.product([1.0, 3.0], [2.5], [-8.0, -2.0], [40.0, 90.0], [0.0]))
    >>> table = pd.DataFrame(rows, columns=["velocity_mps", "pressure_bar", "temperature_C",
    ...     "humidity_pct", "salinity_pct"]).assign(n_sipes=0, mu=0.1)
    >>> problem = SteadyProblem(table)
    >>> problem.n_base, len(np.unique(problem.groups)), problem.effect_names[0]
    (1, 4, 'humidity_water_layer')
    """

    kind = "steady"
    n_base = 1
    effect_names: tuple[str, ...] = DRY_WET_EFFECTS

    def __init__(
        self,
        table: pd.DataFrame,
        params: DryWetParameters | None = None,
        *,
        sigma: str = "pooled",
    ) -> None:
        if not isinstance(table, pd.DataFrame):
            raise TypeError(f"table must be a pandas DataFrame, got {type(table).__name__}")
        if sigma not in ("pooled", "rows"):
            raise ValueError(f"sigma must be 'pooled' or 'rows', got {sigma!r}")
        numeric = _check_table(table, TableSource("steady table"))
        table = table.reset_index(drop=True)
        self.params = (params or DryWetParameters()).with_(effects=Effects.none())
        self.conditions = pd.DataFrame({c: numeric[c] for c in CONDITION_COLUMNS})
        self.conditions["n_sipes"] = numeric["n_sipes"].astype(int)
        self.y = numeric["mu"]
        extra = [
            c
            for c in table.columns
            if c not in (*CONDITION_COLUMNS, "n_sipes", "mu", "mu_std")
            and pd.api.types.is_numeric_dtype(table[c])
        ]
        self.covariates = pd.concat(
            [self.conditions, table[extra].astype(float)], axis=1
        ).reset_index(drop=True)
        keys = self.conditions[list(GROUP_COLUMNS)].round(9)
        self.groups = keys.groupby(list(GROUP_COLUMNS), sort=False).ngroup().to_numpy()
        if np.unique(self.groups).size < 2:
            # one condition (a velocity sweep of one specimen): hold out a whole velocity,
            # its repeats together, so that no repeat of a held-out point is trained on
            self.groups = velocity_levels(self.conditions["velocity_mps"].to_numpy())
        self._fingerprint = hashlib.sha1(
            self.conditions.to_numpy(float).tobytes() + repr(self.params).encode()
        ).hexdigest()
        self._exact: OrderedDict = OrderedDict()
        self._curves: dict = {}
        self._seen: dict = {}
        self._last: tuple | None = None
        self._bounds = {name: self._upper_bound(name) for name in self.effect_names}
        self.sigma = self._sigma(table, sigma)

    # -- noise ---------------------------------------------------------------------------
    def _sigma(self, table: pd.DataFrame, mode: str) -> np.ndarray:
        if "mu_std" in table:
            std = pd.to_numeric(table["mu_std"], errors="coerce").to_numpy(float)
            if mode == "rows":
                return np.maximum(std, MIN_RELATIVE_SIGMA * self.y)
            rel = math.sqrt(float(np.mean((std / self.y) ** 2)))
        else:
            base = self._mu({})
            scale = float(self.y @ base / (base @ base))
            rel = math.sqrt(float(np.mean((self.y / (scale * base) - 1.0) ** 2)))
        return max(rel, MIN_RELATIVE_SIGMA) * self.y

    # -- bounds --------------------------------------------------------------------------
    def _upper_bound(self, name: str) -> float:
        upper = get_candidate(name).parameters[0].upper
        p = self.params
        c = self.conditions
        if name == "salinity_melting_point":
            sal = c["salinity_pct"].to_numpy()
            allowed = -c["temperature_C"].to_numpy() - _MELT_MARGIN_K  # depression limit, K
            rows = sal > 0
            if rows.any() and p.salt_enrichment > 0:
                lo, hi = 0.0, upper
                for _ in range(60):  # bisection on the strength
                    mid = 0.5 * (lo + hi)
                    dep = freezing_point_depression_K(sal[rows], enrichment=p.salt_enrichment * mid)
                    lo, hi = (mid, hi) if np.all(dep <= allowed[rows]) else (lo, mid)
                upper = min(upper, lo)
        elif name == "humidity_water_layer":
            rh = c["humidity_pct"].to_numpy()
            d_t = np.maximum(p.ice.melting_point_C - c["temperature_C"].to_numpy(), 0.05)
            layer = p.qll_thickness_m * d_t ** (-1.0 / 3.0)
            rows = rh > 0
            if rows.any() and p.humidity_gain > 0:
                s_max = (
                    (_FILM_SHARE * p.critical_film_m / layer[rows] - 1.0)
                    * 100.0
                    / (p.humidity_gain * rh[rows])
                )
                upper = min(upper, float(np.min(s_max)))
        if upper <= 0:
            raise ValueError(
                f"the table leaves no room for {name}: at its conditions any strength > 0 "
                "takes the model outside its validity"
            )
        return float(upper)

    def parameter_bounds(self, name: str) -> list[tuple[float, float]] | None:
        """Bounds of ``name``'s strength that this table allows.

        ``salinity_melting_point``: the melting point stays at least 0.1 K above every
        temperature of the table. ``humidity_water_layer``: the bound layer stays below
        97 % of the critical film ``h_c`` (beyond it the contact would be wet from the
        leading edge, another regime). Others: the library bounds; None for a name that
        is not one of :attr:`effect_names` (user candidates keep their own bounds).
        """
        if name not in self._bounds:
            return None  # a user candidate: its own bounds
        return [(0.0, self._bounds[name])]

    # -- model ---------------------------------------------------------------------------
    def _strengths(self, effects: Mapping[str, tuple[float, ...]]) -> dict[str, float]:
        out = {}
        for name, params in effects.items():
            if name not in self.effect_names:
                raise ValueError(
                    f"unknown effect {name!r} for a steady table; effects: {self.effect_names}"
                )
            values = tuple(params)
            if len(values) != 1:
                raise ValueError(f"effect {name!r} takes one parameter (strength), got {values}")
            s = float(values[0])
            if s != 0.0:
                out[name] = s
        return out

    def _exact_mu(self, strengths: dict[str, float]) -> np.ndarray:
        key = tuple(sorted(strengths.items()))
        if key not in self._exact:
            params = self.params.with_(effects=Effects.none().with_(**strengths))
            self._exact[key] = steady_mu(self.conditions, params)
            if len(self._exact) > 256:
                self._exact.popitem(last=False)
        return self._exact[key]

    def _curve(self, name: str, context: tuple) -> CubicSpline:
        key = (name, context)
        if key in self._curves:
            return self._curves[key]
        upper = self._bounds[name]
        knots = _knots(name, upper)
        cache_key = (self._fingerprint, key, tuple(knots))
        if cache_key in _CACHE:
            _CACHE.move_to_end(cache_key)
            spline = _CACHE[cache_key]
        else:
            params = self.params.with_(effects=Effects.none().with_(**dict(context)))
            values = steady_mu(self.conditions, params, vary=name, strengths=knots)
            spline = CubicSpline(knots, values, axis=0)
            _CACHE[cache_key] = spline
            if len(_CACHE) > _CACHE_SIZE:
                _CACHE.popitem(last=False)
        self._curves[key] = spline
        return spline

    def _mu(self, strengths: dict[str, float]) -> np.ndarray:
        key = tuple(sorted(strengths.items()))
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        mu = self._mu_uncached(strengths, key)
        self._last = (key, mu)
        return mu

    def _mu_uncached(self, strengths: dict[str, float], key: tuple) -> np.ndarray:
        if not strengths:
            return self._exact_mu({})
        if key in self._exact:
            return self._exact[key]
        # a curve for one of the effects with the others as context
        for name in reversed(list(strengths)):
            context = tuple(sorted((n, s) for n, s in strengths.items() if n != name))
            s = strengths[name]
            if (name, context) in self._curves and s <= self._bounds[name]:
                return self._curves[(name, context)](s)
        # a second value of the last effect in the same context: it is being fitted,
        # build its curve once; a single combination is computed exactly
        name = list(strengths)[-1]
        s = strengths[name]
        context = tuple(sorted((n, v) for n, v in strengths.items() if n != name))
        seen = self._seen.setdefault((name, context), set())
        seen.add(s)
        if len(seen) > 1 and s <= self._bounds[name]:
            return self._curve(name, context)(s)
        return self._exact_mu(strengths)

    def fit_base(
        self,
        train: np.ndarray,
        effects: Mapping[str, tuple[float, ...]],
        weights: np.ndarray | None = None,
    ) -> np.ndarray:
        """Fit the factor on mu on the rows ``train`` with the effects fixed.

        Parameters
        ----------
        train : (n,) bool ndarray
            Rows to fit on.
        effects : mapping of str to tuple
            Effect name -> (strength,).
        weights : (n,) ndarray, optional
            Row weights (block-bootstrap counts); 1 for every train row when omitted.

        Returns
        -------
        ndarray, shape (1,)
            The factor ``c`` of ``mu = c mu_model`` (weighted least squares, closed form).
        """
        mu = self._mu(self._strengths(effects))
        w = np.asarray(train, bool).astype(float)
        if weights is not None:
            w = w * np.asarray(weights, float)
        ww = w / self.sigma**2
        den = float(ww @ (mu * mu))
        if den <= 0:
            raise ValueError("fit_base needs at least one training row")
        return np.array([float(ww @ (self.y * mu)) / den])

    def predict(self, base: np.ndarray, effects: Mapping[str, tuple[float, ...]]) -> np.ndarray:
        """mu of every row: ``base[0]`` times the dry/wet model with the given strengths."""
        return float(np.asarray(base, float)[0]) * self._mu(self._strengths(effects))
