"""Instationary runs: ``mu(v)`` while accelerating and while decelerating (section 4.4).

The carriage accelerates and decelerates at constant rates (Fig. 4.22); the inertial force
``m a`` of carriage and sample is removed from the friction force and the corrected ``mu`` is
averaged in velocity bins, separately for the two branches.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from scipy.ndimage import maximum_filter1d

from friction_model.rig._io import RigRun, RunFormatError
from friction_model.rig.params import InstationaryParams
from friction_model.rig.results import INSTATIONARY_COLUMNS, InstationaryRunResult
from friction_model.rig.signals import (
    _decimate,
    _half_width,
    _moving_average,
    _mu_trace,
    _run_mean,
    _signals,
)
from tir_common.validate import check_nonnegative

__all__ = ["evaluate_instationary_run", "instationary_characteristic"]

logger = logging.getLogger(__name__)

_BRANCHES = ("accelerating", "decelerating")


@dataclass(frozen=True)
class _Instationary:
    """The binned characteristic and what the plots need of one instationary evaluation."""

    table: pd.DataFrame
    used: np.ndarray  # bool mask of evaluated samples
    branch_masks: dict[str, np.ndarray]
    mu_corrected: np.ndarray


def _evaluated_samples(v_ss: np.ndarray, half: int, min_velocity_mps: float) -> np.ndarray:
    """Samples whose filter support (``4 * half + 1`` samples) reaches no standstill sample.

    Samples within ``2 * half`` of an end of the record are dropped too: there the shrinking
    filter is no longer the same for all signals.
    """
    n = v_ss.shape[0]
    support = 2 * half
    still = (np.abs(v_ss) < min_velocity_mps).astype(np.uint8)
    # samples beyond the record count as moving (the support is clipped at the ends)
    near_still = maximum_filter1d(still, 2 * support + 1, mode="constant", cval=0) > 0
    idx = np.arange(n)
    return ~near_still & (idx >= support) & (idx < n - support)


def _bin_branch(
    branch: str, vb: np.ndarray, mub: np.ndarray, p: InstationaryParams
) -> pd.DataFrame | None:
    """Mean speed, mean and std of ``mu`` and count per velocity bin of one branch.

    Bins ``[k w, (k+1) w)`` of width ``w = p.bin_width_mps`` with fewer than
    ``p.min_samples`` samples are dropped; None when no bin is left.
    """
    bins = np.floor(vb / p.bin_width_mps).astype(np.int64)
    count = np.bincount(bins)
    keep = np.flatnonzero(count >= p.min_samples)
    if keep.size == 0:
        return None
    nz = np.maximum(count, 1)
    mean_mu = np.bincount(bins, weights=mub) / nz
    mean_v = np.bincount(bins, weights=vb) / nz
    sq = np.bincount(bins, weights=(mub - mean_mu[bins]) ** 2)
    std_mu = np.sqrt(sq / np.maximum(count - 1, 1))
    return pd.DataFrame(
        {
            "velocity_mps": mean_v[keep],
            "branch": branch,
            "mu": mean_mu[keep],
            "mu_std": std_mu[keep],
            "n": count[keep].astype(np.int64),
        }
    )


def _empty_characteristic() -> pd.DataFrame:
    """The characteristic without rows, with the dtypes of a filled one."""
    table = pd.DataFrame({c: pd.Series(dtype=float) for c in INSTATIONARY_COLUMNS})
    table["branch"] = table["branch"].astype(object)
    table["n"] = table["n"].astype(np.int64)
    return table


def _instationary(
    t: np.ndarray,
    v: np.ndarray,
    ff: np.ndarray,
    fn: np.ndarray,
    mass: float,
    p: InstationaryParams,
) -> _Instationary:
    """Filter, remove the inertial force, split into branches and bin (see the public API)."""
    half = _half_width(t, p.smoothing_s)

    def smooth(x: np.ndarray) -> np.ndarray:
        return _moving_average(_moving_average(x, half), half)

    # The acceleration (central differences of the velocity) and the forces pass through the
    # same linear filter, so the inertial part of F_F and m*a stay aligned through the kinks
    # of the velocity profile.
    v_ss = smooth(v)
    a_ss = smooth(np.gradient(v, t))
    ff_ss = smooth(ff)
    fn_ss = smooth(fn)
    used = _evaluated_samples(v_ss, half, p.min_velocity_mps)
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = (ff_ss - mass * a_ss) / fn_ss
    speed_up = a_ss * np.sign(v_ss)
    masks = {
        "accelerating": used & (speed_up >= p.min_accel_mps2),
        "decelerating": used & (speed_up <= -p.min_accel_mps2),
    }
    frames = []
    for branch in _BRANCHES:
        m = masks[branch]
        if m.any():
            frame = _bin_branch(branch, np.abs(v_ss[m]), mu[m], p)
            if frame is not None:
                frames.append(frame)
    table = pd.concat(frames, ignore_index=True) if frames else _empty_characteristic()
    return _Instationary(table, used, masks, mu)


def instationary_characteristic(
    time_s: np.ndarray,
    velocity_mps: np.ndarray,
    friction_force_N: np.ndarray,
    normal_force_N: np.ndarray,
    *,
    inertial_mass_kg: float,
    bin_width_mps: float = 0.25,
    smoothing_s: float = 0.01,
    min_velocity_mps: float = 0.05,
    min_accel_mps2: float = 0.2,
    min_samples: int = 20,
) -> pd.DataFrame:
    """Instationary friction characteristic ``mu(v)`` of a ramp-up / ramp-down run.

    Thesis section 4.4, Fig. 4.22: the carriage accelerates and decelerates at constant
    rates, the velocity is never constant. The inertial force of carriage and sample is
    removed from the friction force, ``mu = (F_F - m a) / F_N``, and ``mu`` is averaged in
    velocity bins, separately while accelerating and while decelerating.

    Parameters
    ----------
    time_s : (N,) array_like of float
        Sample times (s), strictly increasing, about uniformly spaced.
    velocity_mps : (N,) array_like of float
        Sliding velocity (m/s).
    friction_force_N, normal_force_N : (N,) array_like of float
        Friction force including the inertial force, and normal force (N).
    inertial_mass_kg : float
        Mass of carriage and sample seen by the friction force sensor (kg); 0 disables the
        inertia removal.
    bin_width_mps : float
        Width of the velocity bins ``[k w, (k+1) w)`` (m/s).
    smoothing_s : float
        Length of the centred moving average (s), applied twice. Velocity, forces and the
        acceleration ``a`` (central differences of the velocity) all pass this same filter,
        so the inertial part of ``F_F`` and ``m a`` stay aligned through the kinks of the
        velocity profile.
    min_velocity_mps : float
        Samples slower than this, and samples whose filter support reaches one or the end of
        the record, are left out (m/s); this removes standstill and the start and stop
        transients.
    min_accel_mps2 : float
        Samples whose speed grows at ``>= min_accel_mps2`` form the ``accelerating``
        branch, samples whose speed falls at ``>= min_accel_mps2`` the ``decelerating``
        branch (m/s^2).
    min_samples : int
        Bins with fewer samples are dropped.

    Returns
    -------
    pandas.DataFrame
        Columns ``velocity_mps`` (mean sliding speed of the samples in the bin, m/s),
        ``branch`` (``"accelerating"`` or ``"decelerating"``), ``mu`` (mean of the
        inertia-corrected, filtered ``mu`` of the bin), ``mu_std`` (sample standard deviation
        of those values) and ``n`` (number of samples); sorted by branch then velocity.
    """
    t, v, ff, fn = _signals(
        time_s=time_s,
        velocity_mps=velocity_mps,
        friction_force_N=friction_force_N,
        normal_force_N=normal_force_N,
        at_least=2,
    )
    check_nonnegative("inertial_mass_kg", inertial_mass_kg)
    params = InstationaryParams(
        bin_width_mps=bin_width_mps,
        smoothing_s=smoothing_s,
        min_velocity_mps=min_velocity_mps,
        min_accel_mps2=min_accel_mps2,
        min_samples=min_samples,
    )
    return _instationary(t, v, ff, fn, float(inertial_mass_kg), params).table


def evaluate_instationary_run(
    run: RigRun,
    *,
    inertial_mass_kg: float | None = None,
    params: InstationaryParams | None = None,
) -> InstationaryRunResult:
    """Evaluate one instationary run (see :func:`instationary_characteristic`).

    Parameters
    ----------
    run : RigRun
        The run, e.g. from :func:`read_run`.
    inertial_mass_kg : float, optional
        Mass of carriage and sample (kg); overrides the metadata key ``inertial_mass_kg``.
    params : InstationaryParams, optional
        Bin width and filter parameters; defaults of :class:`InstationaryParams` if omitted.

    Returns
    -------
    InstationaryRunResult
        The binned characteristic and the run's identity and ambient means.

    Raises
    ------
    RunFormatError
        When no mass is known, no accelerating or decelerating phase is found, or the normal
        force is ``<= 0`` at an evaluated sample.
    """
    p = params if params is not None else InstationaryParams()
    if inertial_mass_kg is None:
        inertial_mass_kg = run.metadata.get("inertial_mass_kg")
        if inertial_mass_kg is None:
            raise RunFormatError(
                run.path,
                f"metadata key 'inertial_mass_kg' missing from the header (file lines 1 to "
                f"{run.header_line - 1}); expected '# inertial_mass_kg: <kg>' or an inertial "
                "mass argument",
                column="inertial_mass_kg",
            )
    else:
        check_nonnegative("inertial_mass_kg", inertial_mass_kg)
    mass = float(inertial_mass_kg)
    t = run.time_s
    res = _instationary(t, run.velocity_mps, run.friction_force_N, run.normal_force_N, mass, p)
    used = np.flatnonzero(res.used)
    if used.size == 0 or res.table.empty:
        raise run.error(
            f"column 'velocity_mps': no accelerating or decelerating phase found in "
            f"{run.where(0)} to {run.where(len(run) - 1)}; expected samples moving at >= "
            f"{p.min_velocity_mps} m/s with |acceleration| >= {p.min_accel_mps2} m/s^2 filling "
            f"bins of {p.bin_width_mps} m/s with >= {p.min_samples} samples",
            column="velocity_mps",
        )
    bad = used[run.normal_force_N[used] <= 0.0]
    if bad.size:
        i = int(bad[0])
        raise run.error(
            f"column 'normal_force_N', {run.where(i)}: expected a normal force > 0 N at every "
            f"evaluated (moving) sample, got {float(run.normal_force_N[i])!r} N",
            column="normal_force_N",
            index=i,
        )
    spans = {}
    for branch, mask in res.branch_masks.items():
        idx = np.flatnonzero(mask)
        if idx.size:
            spans[branch] = (float(t[idx[0]]), float(t[idx[-1]]))
    reference = float(np.median(run.normal_force_N[used]))
    trace: dict[str, Any] = _mu_trace(run, reference)
    trace["mu_corrected"] = np.where(res.used, res.mu_corrected, np.nan)[_decimate(len(run))]
    trace["spans"] = spans
    logger.debug("%s: instationary, m = %.4g kg, %d bins", run.path, mass, len(res.table))
    return InstationaryRunResult(
        file=str(run.path),
        specimen=run.specimen,
        condition=run.condition,
        run=run.run_number,
        inertial_mass_kg=mass,
        table=res.table,
        temperature_C=_run_mean(run.temperature_C),
        humidity_pct=_run_mean(run.humidity_pct),
        metadata=dict(run.metadata),
        trace=trace,
    )
