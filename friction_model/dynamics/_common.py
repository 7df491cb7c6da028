"""Shared pieces of the tread-block dynamics: input profiles, results, friction evaluation.

Conventions for every model in :mod:`friction_model.dynamics`:

* SI units inside; time in s, lengths in m, angles in rad; result columns carry units in
  their names (``time_s``, ``angle_deg``, ``tip_deflection_mm``, ``normal_force_N``).
* Inputs are callables of time: the sliding velocity ``v0(t)`` in m/s
  (:func:`constant_velocity`, :func:`velocity_step`, :func:`velocity_ramp`) and the preload
  distance ``y0(t)`` in m (:func:`constant_preload`, :func:`surface_profile`).
* Friction: any object with ``mu(v_rel_mps, *, pressure_Pa=None, temperature_C=None)``
  (:mod:`friction_model.contact.laws`, :class:`friction_model.DryWetLaw`); a
  :class:`friction_model.contact.laws.RelaxedFriction` adds the state mu_R of Eq. 5.12.
* Every model returns a :class:`SimulationResult`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy.sparse import csc_matrix

__all__ = [
    "Profile",
    "SimulationError",
    "SimulationResult",
    "batched_fd_jacobian",
    "constant_preload",
    "constant_velocity",
    "finite_rhs",
    "output_times",
    "raise_if_failed",
    "surface_profile",
    "velocity_ramp",
    "velocity_step",
]

Profile = Callable[[float], float]


class SimulationError(RuntimeError):
    """An integration that diverged or failed; the message says at which time and why."""


def output_times(t_end_s: float, step_s: float) -> np.ndarray:
    """Output times 0, step, 2 step, ... up to and including ``t_end_s`` (s).

    Examples
    --------
    >>> output_times(0.01, 0.004).tolist()
    [0.0, 0.004, 0.008]
    """
    t = np.arange(0.0, t_end_s + 0.5 * step_s, step_s)
    return t[t <= t_end_s]


def finite_rhs(
    rhs_batch: Callable[[float, np.ndarray], np.ndarray], what: str, detail: str
) -> Callable[[float, np.ndarray], np.ndarray]:
    """Right-hand side ``f(t, y)`` from a batched one ``F(t, Y) -> (n_batch, n)``.

    A non-finite derivative raises :class:`SimulationError` saying ``what`` diverged, at
    which time, and ``detail`` (why), instead of letting NaNs into the solver.
    """

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        out = rhs_batch(t, y[None, :])[0]
        if not np.all(np.isfinite(out)):
            raise SimulationError(f"{what}: the integration diverged at t={t:.6g} s ({detail})")
        return out

    return rhs


def batched_fd_jacobian(
    rhs_batch: Callable[[float, np.ndarray], np.ndarray],
    floor: np.ndarray,
    what: str,
    *,
    pattern: np.ndarray | None = None,
) -> Callable[[float, np.ndarray], Any]:
    """Forward-difference Jacobian with all columns in one batched right-hand-side call.

    Parameters
    ----------
    rhs_batch : callable
        ``F(t, Y)`` evaluating the derivative for a stack of states ``Y`` (n_batch, n).
    floor : (n,) ndarray
        Smallest state magnitude used for the step (typical scale of each state).
    what : str
        Model name for the error message.
    pattern : (n, n) ndarray of bool, optional
        Sparsity pattern; when given the Jacobian is returned as a CSC matrix.
    """

    def jac(t: float, y: np.ndarray):
        h = 1.5e-8 * np.maximum(np.abs(y), floor)
        fs = rhs_batch(t, np.vstack([y, y + np.diag(h)]))
        jmat = ((fs[1:] - fs[0]) / h[:, None]).T
        if not np.all(np.isfinite(jmat)):
            raise SimulationError(f"{what}: non-finite Jacobian at t={t:.6g} s (diverged)")
        return jmat if pattern is None else csc_matrix(np.where(pattern, jmat, 0.0))

    return jac


def raise_if_failed(sol: Any, what: str) -> None:
    """Raise :class:`SimulationError` with the time and the solver's message if
    ``solve_ivp`` failed (status -1)."""
    if sol.status < 0:
        t_fail = float(sol.t[-1]) if sol.t.size else 0.0
        raise SimulationError(f"{what}: integration failed at t={t_fail:.6g} s: {sol.message}")


def constant_velocity(v_mps: float) -> Profile:
    """v0(t) = v_mps for all t.

    Examples
    --------
    >>> constant_velocity(2.0)(0.3)
    2.0
    """
    v = float(v_mps)
    return lambda t: v


def velocity_step(v1_mps: float, v2_mps: float, t_step_s: float, *, rise_s: float = 0.0) -> Profile:
    """v0 = v1 before ``t_step_s``, v2 after; a linear change over ``rise_s`` if > 0 (Fig. 5.7).

    Examples
    --------
    >>> f = velocity_step(1.0, 3.0, 0.2, rise_s=0.02)
    >>> f(0.1), round(f(0.21), 12), f(0.5)
    (1.0, 2.0, 3.0)
    """
    v1, v2, ts, rs = float(v1_mps), float(v2_mps), float(t_step_s), float(rise_s)

    def v0(t: float) -> float:
        if t < ts:
            return v1
        if rs <= 0.0 or t >= ts + rs:
            return v2
        return v1 + (v2 - v1) * (t - ts) / rs

    return v0


def velocity_ramp(v_start_mps: float, v_end_mps: float, t0_s: float, t1_s: float) -> Profile:
    """Linear ramp from v_start (before t0) to v_end (after t1).

    Examples
    --------
    >>> velocity_ramp(0.0, 2.0, 0.0, 1.0)(0.25)
    0.5
    """
    if t1_s <= t0_s:
        raise ValueError(f"t1_s must be > t0_s, got t0_s={t0_s!r}, t1_s={t1_s!r}")
    return velocity_step(v_start_mps, v_end_mps, t0_s, rise_s=t1_s - t0_s)


def constant_preload(y0_m: float) -> Profile:
    """y0(t) = y0_m for all t (the preload distance of Eq. 5.2)."""
    y0 = float(y0_m)
    return lambda t: y0


def surface_profile(
    y0_m: float,
    heights_m: ArrayLike,
    positions_m: ArrayLike,
    velocity: Profile,
    *,
    t_max_s: float,
    dt_s: float = 1e-5,
) -> Profile:
    """Preload distance over a rough surface: ``y0(t) = y0_m - z(s(t))``.

    ``z(s)`` is the surface height at travelled distance ``s(t) = int_0^t v0 dt`` (linear
    interpolation in the given samples, outside them 0); a bump (z > 0) pushes the element
    up, i.e. reduces the preload distance (Fig. 5.6).

    Parameters
    ----------
    y0_m : float
        Preload distance on a flat surface, m.
    heights_m, positions_m : array_like
        Surface height samples z (m) at distances s (m), s increasing.
    velocity : callable
        v0(t), m/s.
    t_max_s, dt_s : float
        Time span and step of the tabulated s(t).
    """
    s_pos = np.asarray(positions_m, dtype=float)
    z = np.asarray(heights_m, dtype=float)
    if s_pos.ndim != 1 or s_pos.shape != z.shape or np.any(np.diff(s_pos) <= 0):
        raise ValueError("positions_m must be 1-D, increasing and as long as heights_m")
    t = np.arange(0.0, t_max_s + 2 * dt_s, dt_s)
    v = np.array([velocity(ti) for ti in t])
    s = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * dt_s)])
    y0 = float(y0_m)

    def y0_of_t(tt: float) -> float:
        si = float(np.interp(tt, t, s))
        return y0 - float(np.interp(si, s_pos, z, left=0.0, right=0.0))

    return y0_of_t


@dataclass
class SimulationResult:
    """Outcome of a tread-block simulation.

    Attributes
    ----------
    data : pandas.DataFrame
        Tidy time series: one row per time and element with at least ``time_s``,
        ``element`` and ``angle_deg``; models add ``tip_deflection_mm``,
        ``normal_force_N``, ``friction_force_N``, ``v_rel_mps``, ``mu``, ...
    fields : dict of str to ndarray
        Field outputs (e.g. ``x_m`` (n_x,), ``r_m`` and ``phi_rad`` (n_t, n_x)).
    meta : dict
        Model name, parameters, solver statistics.
    """

    data: pd.DataFrame
    fields: dict[str, np.ndarray] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)

    def steady(self, column: str = "angle_deg", *, last_fraction: float = 0.2) -> pd.Series:
        """Mean of ``column`` per element over the last ``last_fraction`` of the time span."""
        t = self.data["time_s"]
        t_from = t.max() - last_fraction * (t.max() - t.min())
        return self.data[t >= t_from].groupby("element")[column].mean()

    def plot(self, column: str = "angle_deg", ax=None):
        """``column`` over time, one line per element (the usual deflection-angle figure).

        Returns
        -------
        matplotlib.figure.Figure
        """
        import matplotlib.pyplot as plt

        if ax is None:
            fig, ax = plt.subplots(figsize=(7, 3.8))
        else:
            fig = ax.figure
        for element, g in self.data.groupby("element"):
            ax.plot(g["time_s"], g[column], label=f"element {element}")
        ax.set_xlabel("time / s")
        ax.set_ylabel(column.replace("_", " "))
        if self.data["element"].nunique() > 1:
            ax.legend(fontsize=8)
        ax.set_title(str(self.meta.get("model", "")))
        fig.tight_layout()
        return fig

    def plot_shapes(self, times_s=None, ax=None):
        """Deformed shapes r(x) of a beam model at chosen times (needs ``fields`` with
        ``x_m``, ``t_s`` and ``r_m``, as the Timoshenko model returns).

        Parameters
        ----------
        times_s : sequence of float, optional
            Times to draw, s; six times spread over the run by default.
        ax : matplotlib Axes, optional

        Returns
        -------
        matplotlib.figure.Figure
        """
        import matplotlib.pyplot as plt

        for key in ("x_m", "t_s", "r_m"):
            if key not in self.fields:
                raise ValueError(
                    f"plot_shapes needs the field {key!r}; this result of "
                    f"{self.meta.get('model', 'a model')} has {sorted(self.fields)}"
                )
        x, t, r = self.fields["x_m"], self.fields["t_s"], self.fields["r_m"]
        if times_s is None:
            times_s = np.linspace(t[0], t[-1], 6)
        if ax is None:
            fig, ax = plt.subplots(figsize=(4.5, 4.5))
        else:
            fig = ax.figure
        for ti in times_s:
            i = int(np.argmin(np.abs(t - ti)))
            ax.plot(r[i] * 1e3, x * 1e3, label=f"{t[i] * 1e3:.1f} ms")
        ax.invert_yaxis()
        ax.set_xlabel("deflection r / mm")
        ax.set_ylabel("x from root / mm")
        ax.legend(fontsize=8)
        fig.tight_layout()
        return fig
