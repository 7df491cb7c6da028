"""Parameter sweeps over simulations: serial, a local process pool, or dask.distributed.

A sweep maps a module-level function ``fn(**params) -> dict`` over many parameter sets and
returns one tidy DataFrame: the parameter columns, the result columns and an ``error``
column. A parameter set whose run fails keeps its row with the error message; the others are
not lost.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Iterable, Mapping
from concurrent.futures import ProcessPoolExecutor, as_completed
from itertools import product
from typing import Any

import pandas as pd

from friction_model.compound import REFERENCE_COMPOUND
from friction_model.conditions import Conditions
from friction_model.contact.drywet import friction_table
from friction_model.dynamics.stick_slip import table_4_6_eq_5_24
from friction_model.dynamics.timoshenko import TimoshenkoParams, simulate_timoshenko
from friction_model.geometry import reference_block
from tir_common.progress import progress_bar

logger = logging.getLogger(__name__)

__all__ = ["dry_wet_point", "parameter_grid", "run_sweep", "timoshenko_point"]


def timoshenko_point(
    *,
    velocity_mps: float,
    pressure_bar: float,
    E_MPa: float,
    t_end_s: float = 0.05,
    kelvin_voigt_s: float = 1e-3,
    n_nodes: int = 40,
) -> dict[str, Any]:
    """Steady state of one Timoshenko element (G3 element, Eq. 5.24 from Table 4.6).

    A picklable function for :func:`run_sweep`. The element carries the constant normal
    force ``pressure_bar`` times its face area (the default load, a soft loading spring);
    G = E/3, Haringx beam-column, density of the reference compound.

    Returns
    -------
    dict
        ``tip_deflection_mm, tip_slope_deg, bending_angle_deg, normal_force_N, mu,
        steps, wall_time_s`` (means over the last 20 % of the run).
    """
    E = E_MPa * 1e6
    params = TimoshenkoParams(
        E_Pa=E,
        density_kg_m3=REFERENCE_COMPOUND.density_kg_m3,
        kelvin_voigt_s=kelvin_voigt_s,
        contact_stiffness_N_m=1.0,  # unused: applied normal force
        n_nodes=n_nodes,
    )
    res = simulate_timoshenko(
        params,
        velocity=velocity_mps,
        normal_force=pressure_bar * 1e5 * params.area_m2,
        friction=table_4_6_eq_5_24(),
        t_end_s=t_end_s,
        n_output=201,
    )
    steady = res.data[res.data["time_s"] >= 0.8 * t_end_s].mean(numeric_only=True)
    return {
        "tip_deflection_mm": float(steady["tip_deflection_mm"]),
        "tip_slope_deg": float(steady["angle_deg"]),
        "bending_angle_deg": float(steady["bending_angle_deg"]),
        "normal_force_N": float(steady["normal_force_N"]),
        "mu": float(steady["mu"]),
        "steps": int(res.meta.get("n_steps", -1)),
        "wall_time_s": float(res.meta.get("wall_time_s", float("nan"))),
    }


def dry_wet_point(
    *,
    velocity_mps: float,
    temperature_C: float,
    pressure_bar: float = 2.5,
    humidity_pct: float = 50.0,
    salinity_pct: float = 0.0,
    sample: str = "G3",
) -> dict[str, Any]:
    """One point of a dry/wet friction-model sweep (a picklable function for :func:`run_sweep`).

    Returns
    -------
    dict
        ``mu``, ``regime``, ``run_in_length_first_mm``, ``run_in_length_last_mm``.
    """
    cond = Conditions.from_bar(
        velocity_mps,
        pressure_bar,
        temperature_C,
        humidity_pct=humidity_pct,
        salinity_pct=salinity_pct,
    )
    row = friction_table(reference_block(sample), [cond]).iloc[0]
    return {
        "mu": float(row["mu"]),
        "regime": str(row["regime"]),
        "run_in_length_first_mm": float(row["run_in_length_first_mm"]),
        "run_in_length_last_mm": float(row["run_in_length_last_mm"]),
    }


def parameter_grid(**axes: Iterable[Any]) -> pd.DataFrame:
    """Full factorial grid of the given axes.

    Examples
    --------
    >>> parameter_grid(velocity_mps=[1, 5], y0_mm=[4.6, 5.1]).shape
    (4, 2)
    """
    names = list(axes)
    return pd.DataFrame(list(product(*(list(v) for v in axes.values()))), columns=names)


def _call(fn: Callable[..., Mapping[str, Any]], index: int, params: dict[str, Any]):
    try:
        out = dict(fn(**params))
        return index, out, ""
    except Exception as exc:  # one failed set must not stop the sweep; it is reported
        return index, {}, f"{type(exc).__name__}: {exc}"


def run_sweep(
    fn: Callable[..., Mapping[str, Any]],
    param_sets: pd.DataFrame | Iterable[Mapping[str, Any]],
    *,
    scheduler: str | None = "processes",
    workers: int | None = None,
    progress: bool | None = None,
) -> pd.DataFrame:
    """Run ``fn(**params)`` for every parameter set and collect one tidy table.

    Parameters
    ----------
    fn : callable
        A module-level (picklable) function returning a mapping of scalar results.
    param_sets : pandas.DataFrame or iterable of mappings
        One parameter set per row/item.
    scheduler : str or None
        ``"serial"`` (in this process), ``"processes"`` (a local process pool, the default),
        ``"dask"`` (a local ``dask.distributed`` cluster) or the address of an existing
        ``dask.distributed`` scheduler (e.g. ``"tcp://10.0.0.5:8786"``).
    workers : int, optional
        Worker processes for ``"processes"`` and ``"dask"``; all cores by default.
    progress : bool, optional
        Show a progress bar (default: when attached to a terminal).

    Returns
    -------
    pandas.DataFrame
        The parameter columns, the result columns and ``error`` (empty string when the run
        succeeded), in the order of ``param_sets``.

    Examples
    --------
    >>> grid = parameter_grid(velocity_mps=[1.0, 5.0], temperature_C=[-5.0])
    >>> table = run_sweep(dry_wet_point, grid, scheduler="serial", progress=False)
    >>> bool(table["mu"].iloc[0] > table["mu"].iloc[1])
    True
    """
    rows = (
        param_sets.to_dict(orient="records")
        if isinstance(param_sets, pd.DataFrame)
        else [dict(p) for p in param_sets]
    )
    results: dict[int, tuple[dict[str, Any], str]] = {}
    n = len(rows)
    workers = workers or os.cpu_count() or 1
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got workers={workers!r}")
    if n == 0:
        return pd.DataFrame()
    bar = progress_bar(n, progress=progress, desc="sweep", unit="run")
    try:
        if scheduler == "serial" or (scheduler == "processes" and workers == 1):
            for i, p in enumerate(rows):
                _, out, err = _call(fn, i, p)
                results[i] = (out, err)
                bar.update()
        elif scheduler == "processes":
            with ProcessPoolExecutor(max_workers=workers) as pool:
                futures = [pool.submit(_call, fn, i, p) for i, p in enumerate(rows)]
                for fut in as_completed(futures):
                    i, out, err = fut.result()
                    results[i] = (out, err)
                    bar.update()
        elif scheduler is not None:
            _run_dask(fn, rows, scheduler, workers, results, bar)
        else:
            raise ValueError("scheduler must be 'serial', 'processes', 'dask' or an address")
    finally:
        bar.close()
    failed = sum(1 for _, err in results.values() if err)
    if failed:
        logger.warning("%d of %d parameter sets failed", failed, n)
    table = [{**rows[i], **results[i][0], "error": results[i][1]} for i in range(n)]
    return pd.DataFrame(table)


def _run_dask(fn, rows, scheduler: str, workers: int, results: dict, bar) -> None:
    try:
        from dask.distributed import Client, LocalCluster
        from dask.distributed import as_completed as dask_completed
    except ImportError:
        raise ImportError(
            "scheduler='dask' or a scheduler address needs dask.distributed; install the "
            "'dask' extra: python -m pip install 'tir-contact[dask]'"
        ) from None
    if scheduler == "dask":
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = Client(cluster)
    else:
        cluster = None
        client = Client(scheduler)
    try:
        futures = [client.submit(_call, fn, i, p, pure=False) for i, p in enumerate(rows)]
        for fut in dask_completed(futures):
            i, out, err = fut.result()
            results[i] = (out, err)
            bar.update()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
