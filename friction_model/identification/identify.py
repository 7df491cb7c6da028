"""Parameter identification of the tread-block element (thesis section 5.4).

Fits the rubber's Young's modulus E, its loss factor tan(delta) (damping), optionally the
friction time constant of Eq. 5.12, and the parameters of a friction law mu(v) to measured
deflection-angle time series (the side-view pipeline's ``elements.csv``, a transient table)
and to a steady characteristic (mu against v), all at once, with confidence intervals.

Forward model: the rigid single-DOF element of Eq. 5.8 (:class:`~friction_model.dynamics.
SdofParams`: spring c_phi(E), inertia J_A of Eq. 5.9, damper d_phi = tan(delta) c_phi /
omega_0), linearised about phi = 0 with the normal force held at its preload::

    J phi'' + (d_phi + F_N d^2 mu'(v0)) phi' + (c_phi - F_N d + m g d/2) phi = F_N d mu(v0)

(Eq. 5.8 with sin phi = phi, cos phi = 1; the friction moment F_F d with
F_F = mu(v_rel) F_N and v_rel = v0 - d phi', Eq. 5.4-5.6, linearised in the tip velocity,
which adds the friction slope to the damping; gravity of the hanging bar as in
:func:`~friction_model.dynamics.simulate_sdof`). With Eq. 5.12 (``relaxation_time_s`` > 0)
the friction coefficient is a state: ``tau mu_R' + mu_R = mu(v0) - mu'(v0) d phi'``. The
carriage velocity is held between samples, so the response is exact per constant-velocity
segment (eigen-decomposition of the 2x2 or 3x3 system), costing well under a millisecond
for thousands of samples. This is the cheapest model that carries E (through the ringing
frequency and the static angle), the damping (through the decay) and mu(v) (through the
static angles); it holds for small angles (the moments are 2 % off at 20 deg) and a soft
normal-load path (the normal force is not modulated by the element's foreshortening).

Confidence intervals: the Jacobian (Gauss-Newton) covariance for every parameter, and for
the element parameters (E, tan(delta), tau), which enter nonlinearly, the profile
likelihood (``ci="profile"``) or a moving-block residual bootstrap (``ci="bootstrap"``).
Observation errors not given are estimated from the residuals of each data set (two
passes), so that a deflection series and a steady characteristic get their own weights.
"""

from __future__ import annotations

import logging
import math
import os
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from scipy import stats
from scipy.linalg import expm
from scipy.optimize import brentq, least_squares

from friction_model._fitting import covariance_with_stderr
from friction_model._table_io import TableSource, read_table
from friction_model.contact.laws import FrictionLaw, fit_law
from friction_model.dynamics.rigid import SdofParams
from friction_model.replicates import replicate_noise, velocity_levels

logger = logging.getLogger(__name__)

__all__ = [
    "ELEMENT_PARAMETERS",
    "DeflectionSeries",
    "Estimate",
    "IdentificationResult",
    "SteadyCharacteristic",
    "deflection_series_from_pipeline",
    "identify_parameters",
    "linear_element_response",
    "read_characteristic",
]

#: Element parameters that can be fitted, with their units and bounds.
ELEMENT_PARAMETERS: dict[str, tuple[str, float, float]] = {
    "youngs_modulus_Pa": ("Pa", 1e3, 1e12),
    "loss_factor": ("-", 0.0, 2.0),
    "relaxation_time_s": ("s", 0.0, 10.0),
}


# -- data ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class DeflectionSeries:
    """A measured deflection-angle time series of one element.

    Parameters
    ----------
    time_s : (N,) array_like
        Sample times, s, strictly increasing.
    angle_deg : (N,) array_like
        Deflection angle, degrees, > 0 when the tip trails (NaN samples are skipped).
    velocity_mps : (N,) array_like or float
        Carriage (sliding) velocity at each sample, m/s, held until the next sample.
    normal_force_N : float
        Normal force on the element, N (>= 0; 0 for a release test in air).
    sigma_deg : float, optional
        1-sigma error of the angle, degrees; estimated from the residuals when omitted.
    initial_angle_deg : float, optional
        Start at rest at this angle (release test, section 5.4); default: steady sliding
        at the first velocity.
    name : str
        Label in results and messages.
    """

    time_s: np.ndarray
    angle_deg: np.ndarray
    velocity_mps: np.ndarray | float
    normal_force_N: float
    sigma_deg: float | None = None
    initial_angle_deg: float | None = None
    name: str = "deflection"

    def __post_init__(self) -> None:
        t = np.asarray(self.time_s, dtype=float).ravel()
        a = np.asarray(self.angle_deg, dtype=float).ravel()
        v = np.broadcast_to(np.asarray(self.velocity_mps, dtype=float), t.shape).copy()
        if t.size != a.size:
            raise ValueError(
                f"{self.name}: time_s and angle_deg must have the same length, got "
                f"{t.size} and {a.size}"
            )
        if t.size < 4:
            raise ValueError(f"{self.name}: needs at least 4 samples, got {t.size}")
        if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise ValueError(f"{self.name}: time_s must be finite and strictly increasing")
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{self.name}: velocity_mps must be finite")
        if np.sum(np.isfinite(a)) < 4:
            raise ValueError(f"{self.name}: fewer than 4 finite angles")
        if not (math.isfinite(self.normal_force_N) and self.normal_force_N >= 0):
            raise ValueError(f"{self.name}: normal_force_N must be >= 0, got {self.normal_force_N}")
        if self.sigma_deg is not None and not (self.sigma_deg > 0):
            raise ValueError(f"{self.name}: sigma_deg must be > 0, got {self.sigma_deg}")
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "angle_deg", a)
        object.__setattr__(self, "velocity_mps", v)


@dataclass(frozen=True)
class SteadyCharacteristic:
    """Steady friction coefficients against sliding velocity.

    Parameters
    ----------
    velocity_mps, mu : (N,) array_like
        Sliding velocities (m/s) and friction coefficients.
    sigma : (N,) array_like or float, optional
        1-sigma errors of mu; estimated from the residuals when omitted.
    name : str
        Label in results and messages.
    noise_source : {"given", "replicates", "residuals"}, optional
        Where ``sigma`` came from: ``"replicates"`` (the pooled scatter of repeated runs),
        ``"given"`` (a standard error in the table); default ``"given"`` with a sigma,
        ``"residuals"`` without.
    noise_dof : int, optional
        Degrees of freedom of the noise estimate (None: unknown, or taken as exact).
    """

    velocity_mps: np.ndarray
    mu: np.ndarray
    sigma: np.ndarray | float | None = None
    name: str = "steady"
    noise_source: str | None = None
    noise_dof: int | None = None

    def __post_init__(self) -> None:
        v = np.asarray(self.velocity_mps, dtype=float).ravel()
        mu = np.asarray(self.mu, dtype=float).ravel()
        if v.size != mu.size or v.size < 2:
            raise ValueError(
                f"{self.name}: velocity_mps and mu must have the same length >= 2, got "
                f"{v.size} and {mu.size}"
            )
        if not (np.all(np.isfinite(v)) and np.all(np.isfinite(mu))):
            raise ValueError(f"{self.name}: velocity_mps and mu must be finite")
        object.__setattr__(self, "velocity_mps", v)
        object.__setattr__(self, "mu", mu)
        if self.sigma is not None:
            s = np.broadcast_to(np.asarray(self.sigma, dtype=float), v.shape).copy()
            if not np.all(np.isfinite(s) & (s > 0)):
                raise ValueError(f"{self.name}: sigma must be finite and > 0")
            object.__setattr__(self, "sigma", s)
        source = self.noise_source or ("residuals" if self.sigma is None else "given")
        if source not in ("given", "replicates", "residuals") or (
            (source == "residuals") != (self.sigma is None)
        ):
            raise ValueError(
                f"{self.name}: noise_source must be 'residuals' without sigma and 'given' or "
                f"'replicates' with one, got {self.noise_source!r}"
            )
        object.__setattr__(self, "noise_source", source)

    @property
    def n_velocities(self) -> int:
        """Number of distinct velocity levels (repeats at one velocity counted once)."""
        return int(velocity_levels(self.velocity_mps).max()) + 1


def _read_csv(
    source: pd.DataFrame | str | os.PathLike[str],
) -> tuple[pd.DataFrame, TableSource]:
    """A table and where it came from; files through the shared dialect-detecting reader."""
    if isinstance(source, pd.DataFrame):
        return source.reset_index(drop=True), TableSource("table")
    path = os.fspath(source)
    if not os.path.isfile(path):
        raise ValueError(f"{path}: does not exist")
    return read_table(path)


def read_characteristic(
    source: pd.DataFrame | str | os.PathLike[str],
    *,
    select: Mapping[str, Any] | None = None,
) -> SteadyCharacteristic:
    """A steady characteristic from a steady table or ``steady_characteristic.csv``.

    Accepts the two steady formats of docs/formats.md: the synthetic "Steady table"
    (``velocity_mps, mu[, mu_std]``) and the evaluation's ``steady_characteristic.csv``
    (``row_type, velocity_mps, mu_mean_method1, mu_std_runs``). Of the evaluation's file
    the ``run`` rows are used where there are any (every repeat is a measurement: n = 9 for
    three runs at three velocities, not 3), else the ``aggregate`` rows.

    Parameters
    ----------
    source : pandas.DataFrame or path-like
    select : mapping, optional
        Keep only rows whose column equals the value (numbers compared with a relative
        tolerance of 1e-9), e.g. ``{"temperature_C": -4, "n_sipes": 3}``.

    Returns
    -------
    SteadyCharacteristic
        ``sigma``, the noise of one point: a steady table's ``mu_std`` where every selected
        row has a positive one; for ``aggregate`` rows the standard error of their mean,
        ``mu_std_runs / sqrt(n_runs)``; else, where points repeat a velocity (same
        ``specimen`` and ``condition``), the pooled replicate standard deviation
        (:func:`~friction_model.identification.law_choice.replicate_noise`,
        ``noise_source="replicates"``); else None (estimated from a fit's residuals).

    Raises
    ------
    ValueError
        Missing columns, unknown ``select`` columns, no rows left, or rows of more than one
        block (:data:`GROUP_COLUMNS`: ``specimen``, ``n_sipes``; naming the file).
    """
    table, src = _read_csv(source)
    evaluation = "mu_mean_method1" in table.columns and "mu" not in table.columns
    mu_col, sd_col = ("mu_mean_method1", "mu_std_runs") if evaluation else ("mu", "mu_std")
    err = src.missing(
        ("velocity_mps", mu_col),
        list(table.columns),
        expected="velocity_mps, mu[, mu_std] (a steady table) or velocity_mps, "
        "mu_mean_method1[, mu_std_runs] (steady_characteristic.csv)",
    )
    if err is not None:
        raise err
    # numbers checked on every row before any row is dropped, so that messages count the
    # rows of the file (the index stays the row position from here on)
    for col in ("velocity_mps", mu_col, sd_col, "n_runs"):
        if col in table.columns:
            table = table.assign(**{col: src.numbers(table, col, finite=False)})
    if evaluation and "row_type" in table.columns:
        kinds = table["row_type"].astype(str).str.strip()
        for kind in ("run", "aggregate"):
            if (kinds == kind).any():
                table = table[kinds == kind]
                break
    table = _select_rows(table, select, src)
    _one_group(table, src)
    finite = np.isfinite(table[mu_col].to_numpy(float))
    if not finite.all():
        # a row without a friction coefficient (an empty field: a run the evaluation could
        # not read) is left out, and said: the fit has fewer points than the file has rows
        left = table.index[~finite]
        shown = ", ".join(src.where(int(i)) for i in left[:3]) + (", ..." if len(left) > 3
                                                                  else "")
        logger.warning("%s: column '%s': %d row(s) without a finite friction coefficient "
                       "left out (%s)", src.file, mu_col, len(left), shown)
    table = table[finite]
    if len(table) < 2:
        raise src.error(
            f"column '{mu_col}': expected at least 2 rows with a friction coefficient (after "
            f"select), got {len(table)}",
            column=mu_col,
        )
    v = table["velocity_mps"].to_numpy(float)
    if not np.all(np.isfinite(v)):
        i = int(table.index[np.flatnonzero(~np.isfinite(v))[0]])
        raise src.error(
            f"column 'velocity_mps', {src.where(i)}: expected a finite number, got "
            f"an empty field / NaN",
            column="velocity_mps",
            index=i,
        )
    mu = table[mu_col].to_numpy(float)
    sigma, noise_source, noise_dof = _characteristic_noise(table, sd_col, v, mu)
    return SteadyCharacteristic(
        velocity_mps=v,
        mu=mu,
        sigma=sigma,
        name=os.path.basename(src.file),
        noise_source=noise_source,
        noise_dof=noise_dof,
    )


def _select_rows(
    table: pd.DataFrame, select: Mapping[str, Any] | None, src: TableSource
) -> pd.DataFrame:
    """The rows whose columns equal the values of ``select`` (numbers to 1e-9 relative)."""
    for key, value in (select or {}).items():
        if key not in table.columns:
            raise src.error(f"cannot select on {key!r}: no such column", column=key)
        col = table[key]
        if isinstance(value, int | float) and pd.api.types.is_numeric_dtype(col):
            mask = np.isclose(col.to_numpy(float), float(value), rtol=1e-9, atol=1e-12)
        else:
            mask = col.astype(str).to_numpy() == str(value)
        table = table[mask]
    return table


#: Columns of a characteristic that name what was measured: rows differing in one are
#: different characteristics (another tread block: the evaluation's ``specimen``, the
#: synthetic steady table's ``n_sipes``), not repeats. ``condition`` is not one: it is a
#: free grouping key, which a user may give per velocity level.
GROUP_COLUMNS = ("specimen", "n_sipes")


def _one_group(table: pd.DataFrame, src: TableSource) -> None:
    """Refuse rows of more than one block (:data:`GROUP_COLUMNS`): one friction law fitted
    to the characteristics of two blocks pooled is neither of them."""
    for col in GROUP_COLUMNS:
        if col not in table.columns:
            continue
        values = table[col].dropna().astype(str).str.strip()
        groups = sorted(set(values[values != ""]))
        if len(groups) > 1:
            shown = ", ".join(groups[:4]) + (", ..." if len(groups) > 4 else "")
            raise src.error(
                f"column '{col}': rows of {len(groups)} blocks ({shown}); a friction law is "
                f"fitted to one characteristic: choose one with select={{'{col}': "
                f"'{groups[0]}'}} (the CLI's --select {col}={groups[0]})",
                column=col,
            )


def _characteristic_noise(
    table: pd.DataFrame, sd_col: str, v: np.ndarray, mu: np.ndarray
) -> tuple[np.ndarray | None, str | None, int | None]:
    """The noise of each point of a characteristic: given, from repeats, or unknown."""
    if sd_col in table.columns:
        sd = table[sd_col].to_numpy(float)
        if np.all(np.isfinite(sd) & (sd > 0)):
            if "n_runs" not in table.columns:
                return sd, "given", None
            n_runs = table["n_runs"].to_numpy(float)
            if np.all(np.isfinite(n_runs) & (n_runs >= 2)):
                # an aggregate row is the mean of n_runs runs: its standard error
                return sd / np.sqrt(n_runs), "given", int(np.sum(n_runs - 1))
    keys = [str(x) for x in velocity_levels(v)]
    for col in ("specimen", "condition"):
        if col in table.columns:
            keys = [f"{k}|{x}" for k, x in zip(keys, table[col].astype(str), strict=True)]
    s, dof = replicate_noise(mu, np.asarray(keys))
    if dof > 0 and math.isfinite(s):
        return np.full(mu.size, s), "replicates", dof
    return None, None, None


def deflection_series_from_pipeline(
    elements: pd.DataFrame | str | os.PathLike[str],
    *,
    velocity_mps: float | Callable[[float], float] | np.ndarray,
    normal_force_N: float,
    element: int = 0,
    name: str | None = None,
) -> DeflectionSeries:
    """The deflection time series of one element from the side-view pipeline's output.

    Parameters
    ----------
    elements : pandas.DataFrame or path-like
        ``elements.csv`` (``frame, time_s, element, deflection_angle_deg``).
    velocity_mps : float, callable or array_like
        Sliding velocity: constant, a profile v0(t) (e.g.
        :func:`~friction_model.dynamics.velocity_step`) or one value per row of the element.
    normal_force_N : float
        Normal force on the element, N.
    element : int
        Element index (0 leads).
    name : str, optional
        Label; default the file name and element.

    Returns
    -------
    DeflectionSeries
    """
    table, src = _read_csv(elements)
    err = src.missing(
        ("time_s", "element", "deflection_angle_deg"),
        list(table.columns),
        expected="frame, time_s, element, deflection_angle_deg (side-view pipeline output)",
    )
    if err is not None:
        raise err
    rows = table[table["element"] == element].sort_values("time_s")
    if len(rows) < 4:
        raise src.error(
            f"column 'element': expected >= 4 rows of element {element}, got {len(rows)}",
            column="element",
        )
    t = rows["time_s"].to_numpy(float)
    if callable(velocity_mps):
        v = np.array([float(velocity_mps(ti)) for ti in t])
    else:
        v = np.broadcast_to(np.asarray(velocity_mps, dtype=float), t.shape)
    return DeflectionSeries(
        time_s=t,
        angle_deg=pd.to_numeric(rows["deflection_angle_deg"], errors="coerce").to_numpy(float),
        velocity_mps=v,
        normal_force_N=normal_force_N,
        name=name or f"{os.path.basename(src.file)}[element {element}]",
    )


# -- forward model ---------------------------------------------------------------------------
def _law_eval(law: Any, v: np.ndarray, pressure_Pa: float) -> np.ndarray:
    return np.asarray(law(v, pressure_Pa=pressure_Pa), dtype=float)


def _segment_starts(v: np.ndarray) -> np.ndarray:
    return np.concatenate([[0], np.flatnonzero(np.diff(v) != 0.0) + 1])


def linear_element_response(
    sdof: SdofParams,
    *,
    time_s: np.ndarray,
    velocity_mps: np.ndarray | float,
    friction: Any,
    normal_force_N: float,
    relaxation_time_s: float = 0.0,
    initial_angle_rad: float | None = None,
    tip_velocity_feedback: bool = True,
) -> np.ndarray:
    """Deflection angle of the linearised single-DOF element (Eq. 5.8, 5.4-5.6, 5.12).

    ``J phi'' + (d_phi + F_N d^2 mu'(v0)) phi' + (c_phi - F_N d + m g d/2) phi = F_N d mu``
    with ``mu = mu(v0)``, or with Eq. 5.12 ``tau mu' + mu = mu(v0) - mu'(v0) d phi'``. The
    velocity is held from each sample to the next; each constant-velocity segment is solved
    exactly.

    Parameters
    ----------
    sdof : SdofParams
        The element: J_A, c_phi, d_phi, d, m and g.
    time_s : (N,) ndarray
        Output times, s, strictly increasing.
    velocity_mps : (N,) ndarray or float
        Sliding velocity v0 at the output times, m/s (>= 0).
    friction : friction law
        ``mu(v, pressure_Pa=...)`` (any law of :mod:`friction_model.contact.laws`); it gets the
        nominal pressure ``F_N / (l w)`` as :func:`~friction_model.dynamics.simulate_sdof` does.
    normal_force_N : float
        Normal force F_N, N (0: no contact and no friction).
    relaxation_time_s : float
        tau of Eq. 5.12, s (0: the friction follows the velocity at once).
    initial_angle_rad : float, optional
        Start at rest at this angle (friction state steady); default: steady sliding at the
        first velocity.
    tip_velocity_feedback : bool
        Include the tip velocity in the sliding velocity (Eq. 5.5/5.6, the ``mu'(v0)`` terms);
        False lets the friction follow the carriage velocity alone (as the synthetic
        transient table of :mod:`synthetic.measurements` does).

    Returns
    -------
    (N,) ndarray
        phi(t), rad.

    Raises
    ------
    ValueError
        If the loaded element has no positive stiffness (``F_N d >= c_phi + m g d/2``,
        buckling) or the inputs are inconsistent.

    Examples
    --------
    >>> from friction_model.contact.laws import ConstantLaw
    >>> p = SdofParams()
    >>> t = np.linspace(0.0, 0.01, 5)
    >>> phi = linear_element_response(p, time_s=t, velocity_mps=1.0, friction=ConstantLaw(0.2),
    ...                               normal_force_N=20.0)
    >>> c_eff = p.spring_constant_Nm_rad - 20.0 * p.length_m + p.mass_kg * 9.80665 * p.length_m / 2
    >>> bool(np.allclose(phi, 20.0 * p.length_m * 0.2 / c_eff))
    True
    """
    t = np.asarray(time_s, dtype=float).ravel()
    v = np.broadcast_to(np.asarray(velocity_mps, dtype=float), t.shape)
    d = sdof.length_m
    j = sdof.inertia_kgm2
    fn = float(normal_force_N)
    c_eff = sdof.spring_constant_Nm_rad - fn * d + sdof.mass_kg * sdof.gravity_mps2 * d / 2.0
    if c_eff <= 0:
        raise ValueError(
            f"the element buckles under F_N = {fn:.4g} N: F_N d = {fn * d:.4g} N m exceeds its "
            f"rotational stiffness {c_eff + fn * d:.4g} N m/rad (E = "
            f"{sdof.youngs_modulus_Pa:.4g} Pa); is the normal force, or the pressure it is "
            "made of, in its unit (N, bar)?"
        )
    tau = float(relaxation_time_s)
    relaxed = tau > 0
    starts = _segment_starts(v)
    seg_v = v[starts]
    if fn > 0:
        pressure = fn / (sdof.element_length_m * sdof.width_m)
        mu0 = _law_eval(friction, seg_v, pressure)
        h = 1e-6 * np.maximum(np.abs(seg_v), 1e-3)
        lo = np.maximum(seg_v - h, 0.5 * seg_v)
        slope = (_law_eval(friction, seg_v + h, pressure) - _law_eval(friction, lo, pressure)) / (
            seg_v + h - lo
        )
    else:
        mu0 = slope = np.zeros(seg_v.size)
    if not tip_velocity_feedback:
        slope = np.zeros(seg_v.size)
    moment = fn * d
    n_state = 3 if relaxed else 2
    out = np.empty(t.size)
    x = None
    for s, i0 in enumerate(starts):
        i1 = starts[s + 1] if s + 1 < starts.size else t.size
        a = np.zeros((n_state, n_state))
        b = np.zeros(n_state)
        a[0, 1] = 1.0
        a[1, 0] = -c_eff / j
        if relaxed:
            a[1, 1] = -sdof.damping_constant_Nms_rad / j
            a[1, 2] = moment / j
            a[2, 1] = -slope[s] * d / tau
            a[2, 2] = -1.0 / tau
            b[2] = mu0[s] / tau
        else:
            a[1, 1] = -(sdof.damping_constant_Nms_rad + moment * d * slope[s]) / j
            b[1] = moment * mu0[s] / j
        x_eq = -np.linalg.solve(a, b)
        if x is None:
            x = x_eq.copy()
            if initial_angle_rad is not None:
                x[0] = float(initial_angle_rad)
                x[1] = 0.0
        tt = t[i0:i1] - t[i0]
        t_next = (t[i1] - t[i0]) if i1 < t.size else None
        lam, vec = np.linalg.eig(a)
        dev = x - x_eq
        if np.linalg.cond(vec) < 1e8:
            coef = np.linalg.solve(vec, dev.astype(complex))
            out[i0:i1] = x_eq[0] + np.real(vec[0] @ (np.exp(np.outer(lam, tt)) * coef[:, None]))
            if t_next is not None:
                x = x_eq + np.real(vec @ (np.exp(lam * t_next) * coef))
        else:  # (nearly) defective: matrix exponential per sample
            for k, tk in enumerate(tt):
                out[i0 + k] = x_eq[0] + (expm(a * tk) @ dev)[0]
            if t_next is not None:
                x = x_eq + expm(a * t_next) @ dev
    return out


# -- identification --------------------------------------------------------------------------
@dataclass(frozen=True)
class Estimate:
    """One identified parameter.

    Attributes
    ----------
    value, stderr : float
        Estimate and its standard error (Jacobian covariance; inf when undetermined).
    ci_low, ci_high : float
        Confidence limits at the result's level (method in ``IdentificationResult``).
    unit : str
    ci_method : str
        ``"jacobian"``, ``"profile"`` or ``"bootstrap"``.
    """

    value: float
    stderr: float
    ci_low: float
    ci_high: float
    unit: str
    ci_method: str

    def covers(self, truth: float) -> bool:
        """Whether ``truth`` lies inside the confidence interval."""
        return bool(self.ci_low <= truth <= self.ci_high)


@dataclass(frozen=True)
class IdentificationResult:
    """Outcome of :func:`identify_parameters`.

    Attributes
    ----------
    estimates : dict of str to Estimate
        Every free parameter: element parameters by their :data:`ELEMENT_PARAMETERS` names,
        friction-law parameters by the law's parameter names.
    sdof : SdofParams
        The element with the fitted E and loss factor.
    law : FrictionLaw
        The fitted friction law.
    relaxation_time_s : float
        tau of Eq. 5.12 (fitted or as given).
    level : float
        Confidence level.
    sigma : dict of str to float
        Observation error per data set (given or estimated): degrees for deflection series,
        mu for the steady characteristic.
    rmse : dict of str to float
        Root-mean-square residual per data set (same units).
    cov : pandas.DataFrame
        Covariance of the free parameters.
    fitted : dict of str to pandas.DataFrame
        Per data set the measured and fitted values (``time_s, velocity_mps, angle_deg,
        model_angle_deg`` or ``velocity_mps, mu, model_mu``).
    n_points : int
        Observations used.
    """

    estimates: dict[str, Estimate]
    sdof: SdofParams
    law: FrictionLaw
    relaxation_time_s: float
    level: float
    sigma: dict[str, float]
    rmse: dict[str, float]
    cov: pd.DataFrame = field(repr=False)
    fitted: dict[str, pd.DataFrame] = field(repr=False)
    n_points: int = 0

    def to_sections(self, *, normal_force_N: float | None = None) -> dict[str, dict[str, Any]]:
        """The ``element`` and ``friction_law`` sections of the parameter file."""
        el_names = [k for k in ELEMENT_PARAMETERS if k in self.estimates]
        law_names = [k for k in self.law.param_names if k in self.estimates]
        p = self.sdof
        element: dict[str, Any] = {
            "youngs_modulus_Pa": p.youngs_modulus_Pa,
            "loss_factor": p.loss_factor,
            "density_kg_m3": p.density_kg_m3,
            "height_m": p.length_m,
            "element_length_m": p.element_length_m,
            "width_m": p.width_m,
            "relaxation_time_s": self.relaxation_time_s,
            "natural_frequency_Hz": p.natural_frequency_Hz,
            "stderr": {k: self.estimates[k].stderr for k in el_names},
            "ci_low": {k: self.estimates[k].ci_low for k in el_names},
            "ci_high": {k: self.estimates[k].ci_high for k in el_names},
            "ci_method": ",".join(sorted({self.estimates[k].ci_method for k in el_names}))
            or "none",
            "confidence_level": self.level,
            "n_points": self.n_points,
        }
        degs = [
            v for k, v in self.rmse.items() if k in self.fitted and "angle_deg" in self.fitted[k]
        ]
        if degs:
            element["rmse_deg"] = float(np.sqrt(np.mean(np.square(degs))))
        if normal_force_N is not None:
            element["normal_force_N"] = float(normal_force_N)
        law = {
            "law": type(self.law).__name__,
            "equation": self.law.equation,
            "params": self.law.params,
            "stderr": {k: self.estimates[k].stderr for k in law_names},
            "ci_low": {k: self.estimates[k].ci_low for k in law_names},
            "ci_high": {k: self.estimates[k].ci_high for k in law_names},
            "confidence_level": self.level,
        }
        return {"element": element, "friction_law": law}


def _sdof_with(base: SdofParams, E: float, eta: float) -> SdofParams:
    return SdofParams(
        length_m=base.length_m,
        element_length_m=base.element_length_m,
        width_m=base.width_m,
        youngs_modulus_Pa=E,
        density_kg_m3=base.density_kg_m3,
        loss_factor=eta,
        free_length_m=base.free_length_m,
        gravity_mps2=base.gravity_mps2,
    )


def _law_bounds(law_cls: type[FrictionLaw], name: str) -> tuple[float, float]:
    rule = getattr(law_cls, "_rules", {}).get(name, "finite")
    if rule == "> 0":
        return 1e-12, np.inf
    if rule == ">= 0":
        return 0.0, np.inf
    return -np.inf, np.inf


class _Problem:
    """Stacked weighted residuals of all data sets as a function of the free parameters."""

    def __init__(
        self,
        series: Sequence[DeflectionSeries],
        steady: SteadyCharacteristic | None,
        base: SdofParams,
        law: FrictionLaw,
        relaxation_time_s: float,
        free: tuple[str, ...],
        tip_velocity_feedback: bool = True,
    ) -> None:
        self.feedback = bool(tip_velocity_feedback)
        self.series = list(series)
        self.steady = steady
        self.base = base
        self.law_cls = type(law)
        self.values: dict[str, float] = {
            "youngs_modulus_Pa": base.youngs_modulus_Pa,
            "loss_factor": base.loss_factor,
            "relaxation_time_s": float(relaxation_time_s),
            **law.params,
        }
        self.free = free
        self.masks = [np.isfinite(s.angle_deg) for s in self.series]
        self.sigma = [s.sigma_deg or 1.0 for s in self.series]
        self.sigma_steady: np.ndarray | float = (
            1.0 if steady is None or steady.sigma is None else steady.sigma
        )
        lo, hi = [], []
        for k in free:
            if k in ELEMENT_PARAMETERS:
                _, a, b = ELEMENT_PARAMETERS[k]
            else:
                a, b = _law_bounds(self.law_cls, k)
            lo.append(a)
            hi.append(b)
        self.lo, self.hi = np.array(lo), np.array(hi)

    def full(self, x: np.ndarray, fixed: Mapping[str, float] | None = None) -> dict[str, float]:
        vals = dict(self.values)
        vals.update(zip(self.free, (float(xi) for xi in x), strict=True))
        if fixed:
            vals.update(fixed)
        return vals

    def models(self, vals: Mapping[str, float]) -> tuple[list[np.ndarray], np.ndarray | None]:
        sdof = _sdof_with(self.base, vals["youngs_modulus_Pa"], vals["loss_factor"])
        law = self.law_cls(**{k: vals[k] for k in self.law_cls.param_names})
        angles = [
            np.degrees(
                linear_element_response(
                    sdof,
                    time_s=s.time_s,
                    velocity_mps=s.velocity_mps,
                    friction=law,
                    normal_force_N=s.normal_force_N,
                    relaxation_time_s=vals["relaxation_time_s"],
                    initial_angle_rad=None
                    if s.initial_angle_deg is None
                    else math.radians(s.initial_angle_deg),
                    tip_velocity_feedback=self.feedback,
                )
            )
            for s in self.series
        ]
        mu = None
        if self.steady is not None:
            mu = np.asarray(law(self.steady.velocity_mps), dtype=float)
        return angles, mu

    def parts(self, vals: Mapping[str, float]) -> list[np.ndarray]:
        """Unweighted residuals per data set (series first, then steady)."""
        angles, mu = self.models(vals)
        out = [
            (a - s.angle_deg)[m] for a, s, m in zip(angles, self.series, self.masks, strict=True)
        ]
        if self.steady is not None:
            out.append(mu - self.steady.mu)
        return out

    def weighted(self, vals: Mapping[str, float]) -> np.ndarray:
        parts = self.parts(vals)
        sig = [*self.sigma, self.sigma_steady] if self.steady is not None else self.sigma
        return np.concatenate([p / s for p, s in zip(parts, sig, strict=True)])

    def residuals(self, x: np.ndarray, fixed: Mapping[str, float] | None = None) -> np.ndarray:
        try:
            with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
                r = self.weighted(self.full(x, fixed))
        except (ValueError, ArithmeticError, np.linalg.LinAlgError):
            return np.full(self.n_obs, 1e6)
        return np.where(np.isfinite(r), r, 1e6)

    @property
    def n_obs(self) -> int:
        n = sum(int(m.sum()) for m in self.masks)
        return n + (0 if self.steady is None else self.steady.mu.size)


def _solve(
    prob: _Problem,
    x0: np.ndarray,
    *,
    idx: np.ndarray | None = None,
    fixed: Mapping[str, float] | None = None,
    max_nfev: int | None = None,
) -> Any:
    """Least squares over the free parameters ``idx`` (others of ``x0`` held)."""
    x0 = np.asarray(x0, dtype=float)
    if idx is None:
        idx = np.arange(x0.size)

    def fun(z: np.ndarray) -> np.ndarray:
        x = x0.copy()
        x[idx] = z
        return prob.residuals(x, fixed)

    lo, hi = prob.lo[idx], prob.hi[idx]
    z0 = np.clip(x0[idx], lo, hi)
    scale = np.maximum(np.abs(z0), 1e-3 * np.maximum(np.abs(z0).max(), 1.0))
    res = least_squares(
        fun,
        z0,
        bounds=(lo, hi),
        x_scale=scale,
        xtol=1e-10,
        ftol=1e-10,
        gtol=1e-10,
        max_nfev=max_nfev,
    )
    x = x0.copy()
    x[idx] = res.x
    return x, res


def _profile_interval(
    prob: _Problem, x_hat: np.ndarray, j: int, se: float, cost_min: float, delta: float
) -> tuple[float, float]:
    """Profile-likelihood interval of parameter j: chi2(theta_j) - chi2_min = delta."""
    others = np.array([i for i in range(x_hat.size) if i != j], dtype=int)
    lo_b, hi_b = prob.lo[j], prob.hi[j]

    def excess(val: float) -> float:
        x = x_hat.copy()
        x[j] = val
        if others.size:
            x, res = _solve(prob, x, idx=others, max_nfev=200)
            cost = float(np.sum(res.fun**2))
        else:
            cost = float(np.sum(prob.residuals(x) ** 2))
        return cost - cost_min - delta

    out = []
    step0 = se * math.sqrt(delta) if math.isfinite(se) and se > 0 else 0.1 * abs(x_hat[j]) + 1e-6
    for side in (-1.0, 1.0):
        bound = lo_b if side < 0 else hi_b
        a, fa = float(x_hat[j]), -delta
        step = step0
        found = None
        for _ in range(16):
            b = float(x_hat[j] + side * step)
            if (side < 0 and b <= bound) or (side > 0 and b >= bound):
                b = float(bound)
                fb = excess(b) if math.isfinite(b) else -1.0
                found = (a, b, fa, fb) if fb > 0 else ("bound", b)
                break
            fb = excess(b)
            if fb > 0:
                found = (a, b, fa, fb)
                break
            a, fa = b, fb
            step *= 2.0
        if found is None or found[0] == "bound":
            out.append(float(bound) if found is not None else side * math.inf)
            continue
        a, b, _, _ = found
        tol = 1e-4 * max(abs(x_hat[j]), se if math.isfinite(se) else 0.0, 1e-12)
        out.append(float(brentq(excess, a, b, xtol=tol)))
    return out[0], out[1]


def identify_parameters(
    series: Sequence[DeflectionSeries] = (),
    *,
    law: FrictionLaw,
    steady: SteadyCharacteristic | None = None,
    base: SdofParams | None = None,
    free: Sequence[str] = ("youngs_modulus_Pa", "loss_factor"),
    law_free: Sequence[str] | None = None,
    relaxation_time_s: float = 0.0,
    level: float = 0.95,
    ci: str = "profile",
    n_bootstrap: int = 200,
    block_length: int | None = None,
    rng: int | np.random.Generator | None = None,
    tip_velocity_feedback: bool = True,
) -> IdentificationResult:
    """Fit E, the loss factor, tau and friction-law parameters to measurements (section 5.4).

    Weighted least squares over all data sets at once: deflection series through
    :func:`linear_element_response`, the steady characteristic through the law itself.
    Errors not given are estimated per data set from the residuals of a first fit, then the
    fit is repeated with those weights (the covariance is then taken with absolute sigma).

    Parameters
    ----------
    series : sequence of DeflectionSeries
        Deflection time series (velocity steps, release tests, ...).
    law : FrictionLaw
        The friction law; its values are the starting (or fixed) values of its parameters.
    steady : SteadyCharacteristic, optional
        Steady mu(v); when given, the law's free parameters start from
        :func:`~friction_model.contact.laws.fit_law` on it.
    base : SdofParams, optional
        Element geometry, density and the starting E and loss factor (default
        :class:`SdofParams`: G3 element, REF compound).
    free : sequence of str
        Element parameters to fit, from :data:`ELEMENT_PARAMETERS`.
    law_free : sequence of str, optional
        Law parameters to fit; default all of them.
    relaxation_time_s : float
        tau of Eq. 5.12, s; the starting value when ``"relaxation_time_s"`` is in ``free``.
    level : float
        Confidence level in (0, 1).
    ci : {"profile", "bootstrap", "jacobian"}
        Interval of the element parameters; law parameters always get the Jacobian interval
        (``"bootstrap"`` applies to all parameters).
    n_bootstrap : int
        Bootstrap resamples (``ci="bootstrap"``).
    block_length : int, optional
        Block length of the moving-block bootstrap, samples; default ``n^(1/3)`` per set.
    rng : int, Generator or None
        Randomness of the bootstrap.
    tip_velocity_feedback : bool
        Passed to :func:`linear_element_response` (False for data whose friction follows the
        carriage velocity only, e.g. synthetic transient tables).

    Returns
    -------
    IdentificationResult

    Raises
    ------
    ValueError
        Unknown parameter names, no data, or nothing to fit.

    Warns
    -----
    UserWarning
        When the data cannot determine a parameter (infinite standard error).
    """
    base = base or SdofParams()
    series = list(series)
    free, law_free = _check_request(series, steady, law, free, law_free, ci, level)
    all_free = free + law_free
    law = _law_start(law, steady, law_free)
    prob = _Problem(series, steady, base, law, relaxation_time_s, all_free, tip_velocity_feedback)
    x0 = np.array([prob.values[k] for k in all_free], dtype=float)
    x0 = np.clip(x0, prob.lo, prob.hi)
    if "youngs_modulus_Pa" in free:
        x0 = _modulus_search(prob, x0, all_free)
    x_hat, res = _fit_with_estimated_errors(prob, x0)
    cost_min = float(np.sum(res.fun**2))
    n_obs = prob.n_obs
    dof = max(n_obs - len(all_free), 1)
    cov, se = covariance_with_stderr(
        res.jac / 1.0,
        scale=1.0,
        names=all_free,
        undetermined=f"identify_parameters: the data do not determine {all_free} separately; "
        "standard errors set to inf",
    )
    q = float(stats.t.ppf(0.5 + 0.5 * level, dof))
    lows, highs, methods = x_hat - q * se, x_hat + q * se, ["jacobian"] * len(all_free)
    if ci == "profile":
        delta = float(stats.chi2.ppf(level, 1))
        for j, name in enumerate(all_free):
            if name in ELEMENT_PARAMETERS:
                lows[j], highs[j] = _profile_interval(prob, x_hat, j, se[j], cost_min, delta)
                methods[j] = "profile"
    elif ci == "bootstrap":
        lows, highs = _bootstrap(prob, x_hat, level, n_bootstrap, block_length, rng)
        methods = ["bootstrap"] * len(all_free)
    vals = prob.full(x_hat)
    units = {k: ELEMENT_PARAMETERS[k][0] if k in ELEMENT_PARAMETERS else "-" for k in all_free}
    estimates = {
        k: Estimate(
            value=float(x_hat[j]),
            stderr=float(se[j]),
            ci_low=float(lows[j]),
            ci_high=float(highs[j]),
            unit=units[k],
            ci_method=methods[j],
        )
        for j, k in enumerate(all_free)
    }
    fitted, sigma, rmse = _fitted_tables(prob, vals)
    logger.debug("identified %s", {k: e.value for k, e in estimates.items()})
    return IdentificationResult(
        estimates=estimates,
        sdof=_sdof_with(base, vals["youngs_modulus_Pa"], vals["loss_factor"]),
        law=prob.law_cls(**{k: vals[k] for k in prob.law_cls.param_names}),
        relaxation_time_s=float(vals["relaxation_time_s"]),
        level=float(level),
        sigma=sigma,
        rmse=rmse,
        cov=pd.DataFrame(cov, index=list(all_free), columns=list(all_free)),
        fitted=fitted,
        n_points=int(n_obs),
    )


def _check_request(
    series: list[DeflectionSeries],
    steady: SteadyCharacteristic | None,
    law: FrictionLaw,
    free: Sequence[str],
    law_free: Sequence[str] | None,
    ci: str,
    level: float,
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Check the request of :func:`identify_parameters`; the element and law parameters to fit.

    Without deflection series no element parameter is fitted (a steady characteristic alone
    says nothing about the element).
    """
    if not series and steady is None:
        raise ValueError(
            "identify_parameters needs deflection series, a steady characteristic or both"
        )
    if not isinstance(law, FrictionLaw):
        raise TypeError(f"law must be a FrictionLaw, got {type(law).__name__}")
    free = tuple(free)
    unknown = [k for k in free if k not in ELEMENT_PARAMETERS]
    if unknown:
        raise ValueError(
            f"free must name element parameters {list(ELEMENT_PARAMETERS)}, got {unknown}"
        )
    if not series and free:
        free = ()
    law_free = tuple(law.param_names if law_free is None else law_free)
    bad = [k for k in law_free if k not in law.param_names]
    if bad:
        raise ValueError(
            f"law_free must name parameters of {type(law).__name__} {law.param_names}, got {bad}"
        )
    if ci not in ("profile", "bootstrap", "jacobian"):
        raise ValueError(f"ci must be 'profile', 'bootstrap' or 'jacobian', got {ci!r}")
    if not 0.0 < level < 1.0:
        raise ValueError(f"level must lie in (0, 1), got {level=}")
    if not free + law_free:
        raise ValueError("nothing to fit: free and law_free are empty")
    return free, law_free


def _law_start(
    law: FrictionLaw, steady: SteadyCharacteristic | None, law_free: tuple[str, ...]
) -> FrictionLaw:
    """The law fitted to the steady characteristic (the free parameters' starting values)."""
    if steady is None or not law_free:
        return law
    fixed = {k: v for k, v in law.params.items() if k not in law_free}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = fit_law(
            type(law), steady.velocity_mps, steady.mu, sigma=steady.sigma, fixed=fixed or None
        )
    return start.law


def _modulus_search(prob: _Problem, x0: np.ndarray, all_free: tuple[str, ...]) -> np.ndarray:
    """Coarse search over E from 1/4 to 4 times its start, the others fitted briefly.

    The ringing frequency makes the cost multimodal in E.
    """
    jE = all_free.index("youngs_modulus_Pa")
    others = np.array([i for i in range(len(all_free)) if i != jE], dtype=int)
    best = (np.inf, x0)
    for f in np.geomspace(0.25, 4.0, 13):
        x = x0.copy()
        x[jE] = x0[jE] * f
        if others.size:
            x, res = _solve(prob, x, idx=others, max_nfev=30)
            cost = float(np.sum(res.fun**2))
        else:
            cost = float(np.sum(prob.residuals(x) ** 2))
        if cost < best[0]:
            best = (cost, x)
    return best[1]


def _fit_with_estimated_errors(prob: _Problem, x0: np.ndarray) -> tuple[np.ndarray, Any]:
    """Fit, estimate the errors not given per data set from the residuals, refit (twice)."""
    x_hat, res = _solve(prob, x0)
    n_sets = len(prob.series)
    for _ in range(2):
        parts = prob.parts(prob.full(x_hat))
        for i, s in enumerate(prob.series):
            if s.sigma_deg is None:
                prob.sigma[i] = max(float(np.sqrt(np.mean(parts[i] ** 2))), 1e-9)
        if prob.steady is not None and prob.steady.sigma is None:
            prob.sigma_steady = max(float(np.sqrt(np.mean(parts[n_sets] ** 2))), 1e-12)
        x_hat, res = _solve(prob, x_hat)
    return x_hat, res


def _fitted_tables(
    prob: _Problem, vals: Mapping[str, float]
) -> tuple[dict[str, pd.DataFrame], dict[str, float], dict[str, float]]:
    """Data against model per data set, with each set's error and RMS residual."""
    angles, mu = prob.models(vals)
    fitted: dict[str, pd.DataFrame] = {}
    sigma: dict[str, float] = {}
    rmse: dict[str, float] = {}
    for i, s in enumerate(prob.series):
        key = s.name if s.name not in fitted else f"{s.name}_{i}"
        fitted[key] = pd.DataFrame(
            {
                "time_s": s.time_s,
                "velocity_mps": s.velocity_mps,
                "angle_deg": s.angle_deg,
                "model_angle_deg": angles[i],
            }
        )
        m = prob.masks[i]
        rmse[key] = float(np.sqrt(np.mean((angles[i] - s.angle_deg)[m] ** 2)))
        sigma[key] = float(prob.sigma[i])
    steady = prob.steady
    if steady is not None and mu is not None:
        fitted[steady.name] = pd.DataFrame(
            {"velocity_mps": steady.velocity_mps, "mu": steady.mu, "model_mu": mu}
        )
        rmse[steady.name] = float(np.sqrt(np.mean((mu - steady.mu) ** 2)))
        sigma[steady.name] = float(np.sqrt(np.mean(np.square(prob.sigma_steady))))
    return fitted, sigma, rmse


def _bootstrap(
    prob: _Problem,
    x_hat: np.ndarray,
    level: float,
    n_bootstrap: int,
    block_length: int | None,
    rng: int | np.random.Generator | None,
) -> tuple[np.ndarray, np.ndarray]:
    """Percentile intervals from a moving-block bootstrap of each data set's residuals."""
    if int(n_bootstrap) < 10:
        raise ValueError(f"n_bootstrap must be >= 10, got {n_bootstrap=}")
    gen = np.random.default_rng(rng)
    vals = prob.full(x_hat)
    angles, mu = prob.models(vals)
    fits = [a[m] for a, m in zip(angles, prob.masks, strict=True)]
    parts = prob.parts(vals)
    if prob.steady is not None:
        fits.append(mu)
    orig_series, orig_steady = prob.series, prob.steady
    draws = []
    try:
        for _ in range(int(n_bootstrap)):
            new_parts = []
            for r in parts:
                n = r.size
                L = block_length or max(1, round(n ** (1.0 / 3.0)))
                n_blocks = math.ceil(n / L)
                starts = gen.integers(0, max(n - L + 1, 1), n_blocks)
                idx = (starts[:, None] + np.arange(L)[None, :]).ravel()[:n]
                new_parts.append(r[np.minimum(idx, n - 1)] - r.mean())
            boot_series = []
            for i, s in enumerate(orig_series):
                ang = np.full(s.angle_deg.shape, np.nan)
                ang[prob.masks[i]] = fits[i] - new_parts[i]
                boot_series.append(
                    DeflectionSeries(
                        time_s=s.time_s,
                        angle_deg=ang,
                        velocity_mps=s.velocity_mps,
                        normal_force_N=s.normal_force_N,
                        sigma_deg=s.sigma_deg,
                        initial_angle_deg=s.initial_angle_deg,
                        name=s.name,
                    )
                )
            prob.series = boot_series
            if orig_steady is not None:
                k = len(orig_series)
                prob.steady = SteadyCharacteristic(
                    orig_steady.velocity_mps, fits[k] - new_parts[k], orig_steady.sigma
                )
            x, _ = _solve(prob, x_hat, max_nfev=200)
            draws.append(x)
    finally:
        prob.series, prob.steady = orig_series, orig_steady
    arr = np.array(draws)
    alpha = 0.5 * (1.0 - level)
    return np.quantile(arr, alpha, axis=0), np.quantile(arr, 1.0 - alpha, axis=0)
