"""Synthetic raw runs of the linear friction test rig with exact ground truth.

A run is what the rig records while the carriage drags a tread-block sample over the ice
(thesis sections 4.2.3 and 4.4): sliding velocity, normal force, friction force, ambient
temperature and humidity, sampled at up to 50 kHz. :func:`make_raw_run` synthesises such a
run from a known friction law ``mu_of_v``; :func:`write_run_csv` writes it in the CSV format
read by :mod:`friction_model.rig` (see ``docs/formats.md``).

Notes
-----
Units are SI: time in s, velocity in m/s, acceleration in m/s^2, forces in N, mass in kg;
temperature in degC and relative humidity in percent. Time starts at 0 s with the sample at
rest on the ice; the carriage moves in the positive x direction, so velocity and the sliding
friction force are positive.
"""

from __future__ import annotations

import logging
import math
import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd

from tir_common.validate import check_nonnegative, check_positive

__all__ = ["RUN_COLUMNS", "make_raw_run", "write_run_csv"]

logger = logging.getLogger(__name__)

#: Column order of a raw run (the last two are optional in files read back).
RUN_COLUMNS = (
    "time_s",
    "velocity_mps",
    "normal_force_N",
    "friction_force_N",
    "temperature_C",
    "humidity_pct",
)

# Ambient drift of the climate chamber, thesis Fig. 4.6: about +-1 degC and +-7 % relative
# humidity over a cycle of roughly 45 min. The steepest slope of such a sine is
# 2*pi*amplitude/period; a run of a few seconds therefore only sees a small linear drift.
_AMBIENT_PERIOD_S = 45.0 * 60.0
_TEMPERATURE_AMPLITUDE_C = 1.0
_HUMIDITY_AMPLITUDE_PCT = 7.0
_TEMPERATURE_SENSOR_NOISE_C = 0.02
_HUMIDITY_SENSOR_NOISE_PCT = 0.1
# Wavelength of the ice-surface height variation that the preloaded coil spring turns into a
# normal-force ripple (m of track).
_SURFACE_WAVELENGTH_M = 0.5


def make_raw_run(
    mu_of_v: Callable[[np.ndarray], np.ndarray],
    *,
    velocity_mps: float = 1.0,
    accel_mps2: float = 5.0,
    decel_mps2: float = 5.0,
    plateau_s: float = 1.0,
    sample_rate_Hz: float = 50_000,
    normal_force_N: float = 300.0,
    force_noise_N: float = 2.0,
    velocity_noise_mps: float = 0.002,
    normal_force_ripple: float = 0.01,
    inertial_mass_kg: float = 12.5,
    temperature_C: float = -3.9,
    humidity_pct: float = 72.4,
    rest_s: float = 0.1,
    lift_off_s: float = 0.05,
    kind: Literal["steady", "instationary"] = "steady",
    rng: int | np.random.Generator | None = None,
    metadata: Mapping[str, Any] | None = None,
) -> pd.DataFrame:
    """Synthesise one raw test-rig run with a known friction law.

    The velocity profile is: ``rest_s`` at rest with the sample set on the ice, constant
    acceleration ``accel_mps2`` up to ``velocity_mps``, (``kind="steady"`` only) a constant
    velocity phase of ``plateau_s``, constant deceleration ``decel_mps2`` to standstill,
    ``rest_s`` at rest, and finally ``lift_off_s`` with the sample lifted off the ice (normal
    force zero plus noise). For ``kind="instationary"`` (thesis section 4.4, Fig. 4.22) the
    carriage decelerates as soon as it reaches ``velocity_mps``, so the velocity is never
    constant.

    Parameters
    ----------
    mu_of_v : callable
        Friction law ``mu = mu_of_v(v)``, numpy-vectorised over sliding velocity ``v`` (m/s),
        evaluated only for ``v > 0``.
    velocity_mps : float
        Constant sliding velocity of a steady run, peak velocity of an instationary run (m/s).
    accel_mps2, decel_mps2 : float
        Magnitudes of the constant acceleration and of the braking deceleration (m/s^2).
    plateau_s : float
        Duration of the constant-velocity phase (s); ignored for ``kind="instationary"``.
    sample_rate_Hz : float
        Sample rate (Hz); the rig records at 50 kHz.
    normal_force_N : float
        Spring preload, the mean normal force while the sample is on the ice (N).
    force_noise_N : float
        Standard deviation of the white noise added to each force signal (N).
    velocity_noise_mps : float
        Standard deviation of the white noise on the velocity signal (m/s).
    normal_force_ripple : float
        Relative amplitude of the normal-force variation caused by the ice-surface height
        (wavelength 0.5 m of track) acting on the coil spring (dimensionless).
    inertial_mass_kg : float
        Mass of carriage plus sample whose inertia ``m * a`` appears in the friction force (kg).
    temperature_C, humidity_pct : float
        Mean ambient temperature (degC) and relative humidity (%) of the run. The signals
        drift linearly about these means at a random rate within the steepest slope of the
        chamber cycle of Fig. 4.6 (+-1 degC, +-7 % over 45 min), so the run mean is exact up
        to sensor noise (0.02 degC, 0.1 %).
    rest_s : float
        Time at rest before the start and after the stop (s).
    lift_off_s : float
        Time recorded after the sample is lifted off the ice (s); 0 for none.
    kind : {"steady", "instationary"}
        Velocity profile, see above.
    rng : int, numpy.random.Generator or None
        Seed or generator for the noise, passed to :func:`numpy.random.default_rng`.
    metadata : mapping, optional
        Extra ``key: value`` metadata (e.g. ``specimen``, ``run``, ``condition``,
        ``nominal_area_mm2``). It overrides the generated keys ``kind`` and
        ``inertial_mass_kg``.

    Returns
    -------
    pandas.DataFrame
        Columns ``time_s`` (s), ``velocity_mps`` (m/s), ``normal_force_N`` (N),
        ``friction_force_N`` (N), ``temperature_C`` (degC), ``humidity_pct`` (%).
        ``attrs["metadata"]`` holds the metadata dict to write with :func:`write_run_csv`;
        ``attrs["phases"]`` the exact phase boundaries (s): ``motion_start_s``,
        ``plateau_start_s``, ``plateau_end_s`` (both equal to the velocity peak for an
        instationary run), ``motion_end_s`` and ``lift_off_s``; ``attrs["truth"]`` the noise
        free ``velocity_mps``, ``acceleration_mps2``, ``normal_force_N`` and ``mu`` arrays.

    Notes
    -----
    The friction force is ``mu_of_v(v) * F_N + inertial_mass_kg * a + noise`` while sliding
    (``v > 0``) and ``m * a + noise`` otherwise, with ``a`` the exact piecewise-constant
    acceleration. Time is ``i / sample_rate_Hz``.
    """
    if kind not in ("steady", "instationary"):
        raise ValueError(f"kind must be 'steady' or 'instationary', got {kind=}")
    velocity_mps = check_positive("velocity_mps", velocity_mps)
    accel_mps2 = check_positive("accel_mps2", accel_mps2)
    decel_mps2 = check_positive("decel_mps2", decel_mps2)
    sample_rate_Hz = check_positive("sample_rate_Hz", sample_rate_Hz)
    normal_force_N = check_positive("normal_force_N", normal_force_N)
    plateau_s = check_nonnegative("plateau_s", plateau_s) if kind == "steady" else 0.0
    force_noise_N = check_nonnegative("force_noise_N", force_noise_N)
    velocity_noise_mps = check_nonnegative("velocity_noise_mps", velocity_noise_mps)
    normal_force_ripple = check_nonnegative("normal_force_ripple", normal_force_ripple)
    if normal_force_ripple >= 1.0:
        raise ValueError(f"normal_force_ripple must be < 1, got {normal_force_ripple=}")
    inertial_mass_kg = check_nonnegative("inertial_mass_kg", inertial_mass_kg)
    rest_s = check_nonnegative("rest_s", rest_s)
    lift_off_s = check_nonnegative("lift_off_s", lift_off_s)
    gen = np.random.default_rng(rng)

    phases, t, v, a = _timeline(
        rest_s=rest_s,
        velocity_mps=velocity_mps,
        accel_mps2=accel_mps2,
        decel_mps2=decel_mps2,
        plateau_s=plateau_s,
        lift_off_s=lift_off_s,
        sample_rate_Hz=sample_rate_Hz,
    )
    n = t.size
    x = np.cumsum(v) / sample_rate_Hz

    lifted = t >= phases["lift_off_s"]
    fn_true = _normal_force(x, lifted, normal_force_N, normal_force_ripple, gen)
    mu = _friction_coefficient(mu_of_v, v)
    ff_true = mu * fn_true + inertial_mass_kg * a

    normal = fn_true + force_noise_N * gen.standard_normal(n)
    friction = ff_true + force_noise_N * gen.standard_normal(n)
    velocity = v + velocity_noise_mps * gen.standard_normal(n)

    temperature, humidity = _ambient(t, temperature_C, humidity_pct, gen)

    df = pd.DataFrame(
        {
            "time_s": t,
            "velocity_mps": velocity,
            "normal_force_N": normal,
            "friction_force_N": friction,
            "temperature_C": temperature,
            "humidity_pct": humidity,
        }
    )
    df.attrs["metadata"] = {"kind": kind, "inertial_mass_kg": inertial_mass_kg, **(metadata or {})}
    df.attrs["phases"] = phases
    df.attrs["truth"] = {
        "velocity_mps": v,
        "acceleration_mps2": a,
        "normal_force_N": fn_true,
        "mu": mu,
    }
    logger.debug("synthesised %s run: %d samples, %.3f s", kind, n, t[-1])
    return df


def _timeline(
    *,
    rest_s: float,
    velocity_mps: float,
    accel_mps2: float,
    decel_mps2: float,
    plateau_s: float,
    lift_off_s: float,
    sample_rate_Hz: float,
) -> tuple[dict[str, float], np.ndarray, np.ndarray, np.ndarray]:
    """Phase boundaries (s), sample times (s) and the exact piecewise-linear velocity (m/s)
    and piecewise-constant acceleration (m/s^2) of a run."""
    t_start = rest_s
    t_plateau = t_start + velocity_mps / accel_mps2
    t_brake = t_plateau + plateau_s
    t_stop = t_brake + velocity_mps / decel_mps2
    t_lift = t_stop + rest_s
    t_end = t_lift + lift_off_s
    n = math.floor(t_end * sample_rate_Hz) + 1
    t = np.arange(n) / sample_rate_Hz
    phases = {
        "motion_start_s": t_start,
        "plateau_start_s": t_plateau,
        "plateau_end_s": t_brake,
        "motion_end_s": t_stop,
        "lift_off_s": t_lift,
    }
    v = np.zeros(n)
    a = np.zeros(n)
    up = (t > t_start) & (t < t_plateau)
    flat = (t >= t_plateau) & (t <= t_brake)
    down = (t > t_brake) & (t < t_stop)
    v[up] = accel_mps2 * (t[up] - t_start)
    a[up] = accel_mps2
    v[flat] = velocity_mps
    v[down] = velocity_mps - decel_mps2 * (t[down] - t_brake)
    a[down] = -decel_mps2
    return phases, t, v, a


def _normal_force(
    x: np.ndarray, lifted: np.ndarray, mean_N: float, ripple: float, gen: np.random.Generator
) -> np.ndarray:
    """Normal force without noise, N: the spring preload with the ripple of the ice-surface
    height (wavelength 0.5 m of track, random phase) while on the ice, 0 once lifted."""
    phase = gen.uniform(0.0, 2.0 * np.pi)
    fn = mean_N * (1.0 + ripple * np.sin(2.0 * np.pi * x / _SURFACE_WAVELENGTH_M + phase))
    fn[lifted] = 0.0
    return fn


def _friction_coefficient(mu_of_v: Callable[[np.ndarray], np.ndarray], v: np.ndarray) -> np.ndarray:
    """mu_of_v(v) where the sample slides (v > 0), 0 at rest; ValueError if not finite."""
    sliding = v > 0.0
    mu = np.zeros(v.size)
    mu[sliding] = np.asarray(mu_of_v(v[sliding]), dtype=float)
    if not np.all(np.isfinite(mu[sliding])):
        raise ValueError("mu_of_v returned non-finite friction coefficients")
    return mu


def _ambient(
    t: np.ndarray, temperature_C: float, humidity_pct: float, gen: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Temperature (degC) and humidity (%) signals: a linear drift about the run means at a
    random rate within the steepest slope of the chamber cycle (Fig. 4.6), plus sensor noise.

    Random draws, in this order: the two rates, then the two noise series.
    """
    n = t.size
    t_mid = 0.5 * t[-1]
    slope = 2.0 * np.pi / _AMBIENT_PERIOD_S
    temp_rate = gen.uniform(-1.0, 1.0) * slope * _TEMPERATURE_AMPLITUDE_C
    hum_rate = gen.uniform(-1.0, 1.0) * slope * _HUMIDITY_AMPLITUDE_PCT
    temperature = (
        temperature_C
        + temp_rate * (t - t_mid)
        + _TEMPERATURE_SENSOR_NOISE_C * gen.standard_normal(n)
    )
    humidity = (
        humidity_pct + hum_rate * (t - t_mid) + _HUMIDITY_SENSOR_NOISE_PCT * gen.standard_normal(n)
    )
    return temperature, humidity


def write_run_csv(
    df: pd.DataFrame,
    path: str | os.PathLike[str],
    metadata: Mapping[str, Any] | None = None,
    *,
    float_format: str = "%.9g",
) -> Path:
    """Write a raw run in the test-rig CSV format.

    Parameters
    ----------
    df : pandas.DataFrame
        Run with at least ``time_s``, ``velocity_mps``, ``normal_force_N`` and
        ``friction_force_N``; other columns of :data:`RUN_COLUMNS` are written when present,
        in that order. Other columns are written after them.
    path : str or path-like
        Output file; its folder must exist.
    metadata : mapping, optional
        Written as ``# key: value`` lines before the column header; ``df.attrs["metadata"]``
        when omitted.
    float_format : str
        printf-style format of the numbers; the default keeps 9 significant digits.

    Returns
    -------
    pathlib.Path
        The written file.
    """
    if metadata is None:
        metadata = df.attrs.get("metadata", {})
    lines = []
    for key, value in metadata.items():
        key_s, value_s = str(key).strip(), str(value).strip()
        if not key_s or ":" in key_s or any(c in key_s + value_s for c in "\r\n"):
            raise ValueError(
                f"metadata keys must be non-empty without ':' or line breaks and values on one "
                f"line, got {key!r}: {value!r}"
            )
        lines.append(f"# {key_s}: {value_s}\n")
    ordered = [c for c in RUN_COLUMNS if c in df.columns]
    ordered += [c for c in df.columns if c not in ordered]
    path = Path(path)
    with open(path, "w", encoding="utf-8", newline="") as fh:
        fh.writelines(lines)
        df.to_csv(fh, columns=ordered, index=False, float_format=float_format, lineterminator="\n")
    return path
