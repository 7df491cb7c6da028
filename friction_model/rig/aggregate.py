"""Aggregating steady runs: repeats per specimen, condition and velocity; ambient means.

Up to ten repeated runs per specimen, condition and velocity are averaged (mean and standard
deviation, section 4.2.4); the ambient temperature and humidity are averaged per specimen as
in Table 4.2.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd

from friction_model.rig.results import AMBIENT_COLUMNS, STEADY_COLUMNS, SteadyRunResult
from tir_common.naming import natural_key
from tir_common.validate import check_nonnegative, check_positive

__all__ = ["aggregate_runs", "ambient_table", "steady_characteristic"]


def _empty_steady() -> pd.DataFrame:
    """The steady characteristic without rows."""
    return pd.DataFrame({c: pd.Series(dtype=object) for c in STEADY_COLUMNS})


def aggregate_runs(
    runs: pd.DataFrame,
    *,
    velocity_rel_tol: float = 0.05,
    velocity_abs_tol_mps: float = 0.02,
) -> pd.DataFrame:
    """Aggregate repeated runs per specimen, condition and sliding velocity.

    Runs of one specimen and condition are grouped by velocity: sorted by velocity, a new
    group starts where the velocity exceeds the previous run's by more than
    ``max(velocity_rel_tol * v, velocity_abs_tol_mps)``.

    Parameters
    ----------
    runs : pandas.DataFrame
        Run rows with at least ``specimen``, ``condition``, ``velocity_mps``,
        ``mu_mean_method1``, ``mu_mean_method2`` (e.g. the ``run`` rows of
        :func:`steady_characteristic`).
    velocity_rel_tol : float
        Relative velocity difference that separates two groups.
    velocity_abs_tol_mps : float
        Absolute floor of that difference (m/s).

    Returns
    -------
    pandas.DataFrame
        One ``aggregate`` row per group, columns :data:`STEADY_COLUMNS`: means over the runs
        of velocity, ``mu_mean_method1``, ``mu_mean_method2``, ``mu_std_t``, forces,
        pressure, temperature and humidity; ``mu_std_runs`` the sample standard deviation
        (``ddof=1``) of ``mu_mean_method1`` over the runs (NaN for one run); ``n_runs``;
        ``n_samples`` the total. ``file``, ``run`` and the window times are empty.
    """
    check_nonnegative("velocity_rel_tol", velocity_rel_tol)
    check_positive("velocity_abs_tol_mps", velocity_abs_tol_mps)
    if runs.empty:
        return _empty_steady()
    rows = []
    keyed = runs.assign(
        specimen=runs["specimen"].fillna("").astype(str),
        condition=runs["condition"].fillna("").astype(str),
    )
    for (specimen, condition), group in keyed.groupby(["specimen", "condition"], sort=False):
        group = group.sort_values("velocity_mps", kind="stable")
        v = group["velocity_mps"].to_numpy(float)
        gaps = np.diff(v) > np.maximum(velocity_rel_tol * np.abs(v[:-1]), velocity_abs_tol_mps)
        cluster = np.concatenate(([0], np.cumsum(gaps)))
        for _, sub in group.groupby(cluster, sort=True):
            mu1 = sub["mu_mean_method1"].to_numpy(float)
            m1 = float(np.mean(mu1))
            m2 = float(sub["mu_mean_method2"].mean())

            def mean(col: str, sub: pd.DataFrame = sub) -> float:
                if col not in sub:
                    return math.nan
                values = pd.to_numeric(sub[col], errors="coerce")
                return float(values.mean()) if values.notna().any() else math.nan

            rows.append(
                {
                    "row_type": "aggregate",
                    "file": None,
                    "specimen": specimen,
                    "condition": condition,
                    "run": None,
                    "n_runs": len(sub),
                    "velocity_mps": mean("velocity_mps"),
                    "window_start_s": math.nan,
                    "window_end_s": math.nan,
                    "n_samples": int(sub["n_samples"].sum()) if "n_samples" in sub else None,
                    "mu_mean_method1": m1,
                    "mu_mean_method2": m2,
                    "method_rel_diff": abs(m1 - m2) / abs(m2) if m2 != 0 else math.nan,
                    "mu_std_t": mean("mu_std_t"),
                    "mu_std_runs": float(np.std(mu1, ddof=1)) if mu1.size > 1 else math.nan,
                    "normal_force_N": mean("normal_force_N"),
                    "friction_force_N": mean("friction_force_N"),
                    "normal_pressure_Pa": mean("normal_pressure_Pa"),
                    "temperature_C": mean("temperature_C"),
                    "humidity_pct": mean("humidity_pct"),
                }
            )
    out = pd.DataFrame(rows, columns=list(STEADY_COLUMNS))
    order = sorted(
        range(len(out)),
        key=lambda i: (
            natural_key(out.at[i, "specimen"]),
            natural_key(out.at[i, "condition"]),
            out.at[i, "velocity_mps"],
        ),
    )
    return out.iloc[order].reset_index(drop=True)


def steady_characteristic(
    results: Sequence[SteadyRunResult],
    *,
    velocity_rel_tol: float = 0.05,
    velocity_abs_tol_mps: float = 0.02,
) -> pd.DataFrame:
    """Steady friction characteristic: run rows followed by aggregate rows.

    Parameters
    ----------
    results : sequence of SteadyRunResult
        Evaluated steady runs.
    velocity_rel_tol, velocity_abs_tol_mps : float
        Velocity grouping of :func:`aggregate_runs` (dimensionless, m/s).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`STEADY_COLUMNS` then ``meta_<key>`` for the other metadata keys of
        the files; ``row_type`` is ``"run"`` or ``"aggregate"``.
    """
    if not results:
        return _empty_steady()
    runs = pd.DataFrame([r.as_row() for r in results])
    aggregates = aggregate_runs(
        runs, velocity_rel_tol=velocity_rel_tol, velocity_abs_tol_mps=velocity_abs_tol_mps
    )
    meta_cols = [c for c in runs.columns if c not in STEADY_COLUMNS]
    table = pd.concat([runs, aggregates], ignore_index=True)
    table = table[[*STEADY_COLUMNS, *meta_cols]]
    table["run"] = pd.array(table["run"].tolist(), dtype="Int64")
    table["n_runs"] = table["n_runs"].astype(np.int64)
    table["n_samples"] = table["n_samples"].astype(np.int64)
    return table


def ambient_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Ambient averages per specimen, like thesis Table 4.2.

    Parameters
    ----------
    runs : pandas.DataFrame
        One row per run with columns ``specimen``, ``temperature_C`` (degC) and
        ``humidity_pct`` (%); extra columns are ignored, NaN values skipped.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`AMBIENT_COLUMNS`. The first row, specimen ``"Average"``, averages over
        all runs; then one row per specimen in natural order with the mean and the sample
        standard deviation over its runs.
    """
    cols = list(AMBIENT_COLUMNS)
    if runs.empty:
        return pd.DataFrame({c: pd.Series(dtype=object) for c in cols})
    data = pd.DataFrame(
        {
            "specimen": runs["specimen"].fillna("").astype(str).to_numpy(),
            "temperature_C": pd.to_numeric(runs["temperature_C"], errors="coerce").to_numpy(),
            "humidity_pct": pd.to_numeric(runs["humidity_pct"], errors="coerce").to_numpy(),
        }
    )

    def summary(name: str, part: pd.DataFrame) -> dict[str, Any]:
        return {
            "specimen": name,
            "temperature_C": part["temperature_C"].mean(),
            "humidity_pct": part["humidity_pct"].mean(),
            "temperature_std_C": part["temperature_C"].std(ddof=1),
            "humidity_std_pct": part["humidity_pct"].std(ddof=1),
            "n_runs": len(part),
        }

    rows = [summary("Average", data)]
    for name in sorted(data["specimen"].unique(), key=natural_key):
        rows.append(summary(name, data[data["specimen"] == name]))
    return pd.DataFrame(rows, columns=cols)
