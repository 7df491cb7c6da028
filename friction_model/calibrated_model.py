"""Running the calibrated model of a parameter file (``tir-contact simulate``).

:func:`simulate_calibrated` takes a parameter file (docs/formats.md "Parameter file", as
:func:`~friction_model.identification.calibrate_from_results` writes it) and returns the
model's tables as a :class:`CalibratedRun`:

* ``mu_v``: the steady characteristic mu(v) of the file's friction law; with an ``element``
  section also ``angle_deg``, the steady deflection angle of the loaded element (Eq. 5.8
  linearised);
* ``step_response`` (with an ``element`` section): the deflection angle through a velocity
  step from :func:`~friction_model.identification.identify.linear_element_response`;
* ``lever_arm`` (with a ``lever_arm`` section): e(phi) of Eq. 5.21.

:meth:`CalibratedRun.write` writes them as CSV tables and PNG plots.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from friction_model.dynamics.rigid import SdofParams
from friction_model.identification.coupling import lever_arm_eq_5_21
from friction_model.identification.identify import linear_element_response
from friction_model.params_file import (
    friction_law_from,
    lever_arm_kwargs_from,
    read_parameters,
    sdof_params_from,
)
from tir_common.atomic import atomic_write

__all__ = ["CalibratedRun", "simulate_calibrated"]

#: Velocity range of mu(v) when the file records none, m/s.
_DEFAULT_VELOCITY_RANGE_MPS = (0.5, 8.0)


@dataclass(frozen=True)
class CalibratedRun:
    """The tables of :func:`simulate_calibrated` (None where the file lacks the section).

    Attributes
    ----------
    mu_v : pandas.DataFrame or None
        ``velocity_mps, mu[, angle_deg]``.
    step_response : pandas.DataFrame or None
        ``time_s, velocity_mps, angle_deg``.
    lever_arm : pandas.DataFrame or None
        ``deflection_angle_deg, lever_arm_mm``.
    law_title : str
        The law's name and equation (plot title).
    velocity_step_mps : tuple of float or None
        The step V1 -> V2 of ``step_response``.
    normal_force_N : float or None
        Normal force on the element.
    extrapolated_mps : tuple of float
        The velocities asked for outside the law's fitted ``velocity_range_mps`` (empty
        when all lie inside, or the file records no range).
    fitted_range_mps : tuple of float or None
        That range, m/s.
    """

    mu_v: pd.DataFrame | None
    step_response: pd.DataFrame | None
    lever_arm: pd.DataFrame | None
    law_title: str = ""
    velocity_step_mps: tuple[float, float] | None = None
    normal_force_N: float | None = None
    extrapolated_mps: tuple[float, ...] = ()
    fitted_range_mps: tuple[float, float] | None = None

    def write(self, out_dir: str | os.PathLike[str], *, plots: bool = True) -> list[str]:
        """Write each table as CSV (and, with `plots`, PNG) into `out_dir` (created).

        Returns
        -------
        list of str
            The file names written, in order.
        """
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        written: list[str] = []
        for name, table in (("mu_v", self.mu_v), ("step_response", self.step_response),
                            ("lever_arm", self.lever_arm)):
            if table is None:
                continue
            _write_csv(table, out / f"{name}.csv")
            written.append(f"{name}.csv")
            if plots:
                _save_plot(*self._plot_spec(name), out / f"{name}.png")
                written.append(f"{name}.png")
        return written

    def _plot_spec(self, name: str) -> tuple[Any, Any, str, str, str]:
        """x, y, x label, y label and title of the plot of table `name`."""
        if name == "mu_v":
            t = self.mu_v
            return (t["velocity_mps"], t["mu"], "sliding velocity / (m/s)",
                    "friction coefficient mu", self.law_title)
        if name == "step_response":
            t = self.step_response
            v1, v2 = self.velocity_step_mps
            return (t["time_s"] * 1e3, t["angle_deg"], "time / ms", "deflection angle / deg",
                    f"velocity step {v1:g} -> {v2:g} m/s, F_N = {self.normal_force_N:.3g} N")
        t = self.lever_arm
        return (t["deflection_angle_deg"], t["lever_arm_mm"], "deflection angle / deg",
                "lever arm e / mm", "Eq. 5.21")


def _write_csv(table: pd.DataFrame, path: Path) -> None:
    """Write `table` atomically with 10 significant digits."""
    atomic_write(path, lambda tmp: table.to_csv(tmp, index=False, float_format="%.10g"))


def _save_plot(x: Any, y: Any, xlabel: str, ylabel: str, title: str, path: Path) -> None:
    """One black line, labelled, written atomically as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(x, y, "-", color="k")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    fig.tight_layout()
    try:
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=120))
    finally:
        plt.close(fig)


def _element_normal_force_N(
    params: Mapping[str, Any], sdof: SdofParams | None, normal_force_N: float | None
) -> float | None:
    """The normal force on one element: given, else the file's element, else its contact
    force shared by the ``n_sipes + 1`` elements."""
    fn = normal_force_N
    if fn is None and params.get("element", {}).get("normal_force_N") is not None:
        fn = params["element"]["normal_force_N"]
    if fn is None and params.get("contact", {}).get("normal_force_N") is not None and sdof:
        n_el = params.get("geometry", {}).get("n_sipes", 0) + 1
        fn = params["contact"]["normal_force_N"] / n_el
    return fn


def _mu_v_table(
    params: Mapping[str, Any], law: Any, sdof: SdofParams | None, fn: float | None,
    velocities_mps: Sequence[float] | None,
) -> pd.DataFrame:
    """mu(v), and the steady angle ``F_N d mu / c_eff`` of Eq. 5.8 linearised."""
    if velocities_mps:
        v = np.sort(np.asarray(velocities_mps, dtype=float))
    else:
        lo, hi = params["friction_law"].get("velocity_range_mps", _DEFAULT_VELOCITY_RANGE_MPS)
        v = np.geomspace(lo, hi, 50) if hi > lo else np.array([lo])
    table = pd.DataFrame({"velocity_mps": v, "mu": np.asarray(law(v), dtype=float)})
    if sdof is not None and fn:
        c_eff = sdof.spring_constant_Nm_rad - fn * sdof.length_m
        c_eff += sdof.mass_kg * sdof.gravity_mps2 * sdof.length_m / 2.0
        if c_eff > 0:
            table["angle_deg"] = np.degrees(fn * sdof.length_m * table["mu"] / c_eff)
    return table


def _step_table(
    params: Mapping[str, Any], law: Any, sdof: SdofParams, fn: float, v1: float, v2: float
) -> pd.DataFrame:
    """The element's deflection through the step v1 -> v2 after 5 periods, until the
    ringing has decayed (10 decay times, and 10 friction relaxation times)."""
    tau = float(params["element"].get("relaxation_time_s") or 0.0)
    f_n = sdof.natural_frequency_Hz
    eta = max(sdof.loss_factor, 0.01)
    t_step = 5.0 / f_n
    t_end = t_step + max(0.02, 10.0 / (eta * math.pi * f_n) + 10.0 * tau)
    t = np.arange(0.0, t_end, 1.0 / (20.0 * f_n))
    vel = np.where(t >= t_step, v2, v1)
    phi = linear_element_response(
        sdof,
        time_s=t,
        velocity_mps=vel,
        friction=law,
        normal_force_N=fn,
        relaxation_time_s=tau,
        tip_velocity_feedback=params["element"].get("tip_velocity_feedback", True),
    )
    return pd.DataFrame({"time_s": t, "velocity_mps": vel, "angle_deg": np.degrees(phi)})


def _lever_arm_table(lever: Mapping[str, float]) -> pd.DataFrame:
    """e(phi) of Eq. 5.21 over 0-60 degrees."""
    phi_deg = np.linspace(0.0, 60.0, 121)
    e = lever_arm_eq_5_21(
        np.radians(phi_deg),
        length_m=lever["length_m"],
        e1=lever["e1"],
        e2_per_rad=lever["e2_per_rad"],
        e3_m=lever["e3_m"],
        e4_m=lever["e4_m"],
    )
    return pd.DataFrame({"deflection_angle_deg": phi_deg, "lever_arm_mm": np.asarray(e) * 1e3})


def simulate_calibrated(
    parameters: Mapping[str, Any] | str | os.PathLike[str],
    *,
    velocities_mps: Sequence[float] | None = None,
    velocity_step_mps: tuple[float, float] | None = None,
    normal_force_N: float | None = None,
) -> CalibratedRun:
    """Run the calibrated model of a parameter file.

    Parameters
    ----------
    parameters : mapping or path-like
        A parameter file, or its contents as :func:`~friction_model.params_file.
        read_parameters` returns them.
    velocities_mps : sequence of float, optional
        Velocities of mu(v), m/s; default 50 values over the file's
        ``friction_law.velocity_range_mps``, else 0.5-8 m/s.
    velocity_step_mps : (float, float), optional
        The velocity step V1 -> V2, m/s; default the smallest and largest velocity of mu(v).
    normal_force_N : float, optional
        Normal force on the element, N; default the file's ``element.normal_force_N``, else
        its ``contact.normal_force_N`` shared by the elements.

    Returns
    -------
    CalibratedRun

    Raises
    ------
    ValueError
        A file that cannot be read, or one holding neither ``friction_law`` nor
        ``lever_arm`` (nothing to simulate).
    """
    if isinstance(parameters, Mapping):
        params, source = parameters, "parameters"
    else:
        params, source = read_parameters(parameters), os.fspath(parameters)
    law = friction_law_from(params)
    sdof = sdof_params_from(params)
    lever = lever_arm_kwargs_from(params)
    if law is None and lever is None:
        raise ValueError(
            f"{source}: holds neither 'friction_law' nor 'lever_arm': nothing to simulate"
        )
    fn = _element_normal_force_N(params, sdof, normal_force_N)
    mu_v = step = None
    v_step = None
    if law is not None:
        mu_v = _mu_v_table(params, law, sdof, fn, velocities_mps)
        if sdof is not None and fn:
            v = mu_v["velocity_mps"].to_numpy()
            v_step = velocity_step_mps or (float(v.min()), float(v.max()))
            step = _step_table(params, law, sdof, fn, *v_step)
    span = (params.get("friction_law") or {}).get("velocity_range_mps")
    fitted = None if span is None else (float(span[0]), float(span[1]))
    return CalibratedRun(
        mu_v=mu_v,
        step_response=step,
        lever_arm=None if lever is None else _lever_arm_table(lever),
        law_title="" if law is None else f"{type(law).__name__} ({law.equation})",
        velocity_step_mps=v_step,
        normal_force_N=fn,
        extrapolated_mps=_outside(velocities_mps, fitted),
        fitted_range_mps=fitted,
    )


def _outside(velocities_mps: Sequence[float] | None,
             fitted: tuple[float, float] | None) -> tuple[float, ...]:
    """The velocities outside the fitted range, with :data:`RANGE_SLACK` at its ends."""
    if not velocities_mps or fitted is None:
        return ()
    lo, hi = fitted
    return tuple(float(v) for v in velocities_mps
                 if v < lo * (1 - RANGE_SLACK) or v > hi * (1 + RANGE_SLACK))


#: Relative slack at the ends of a law's fitted velocity range: the ends are the runs'
#: measured mean velocities (4.99998 m/s for a 5 m/s setting), and a velocity within a
#: thousandth of one is the setting the runs were made at, not an extrapolation.
RANGE_SLACK = 1e-3
