"""The comparison of issue 24: thesis | Timoshenko (Haringx) | FE linear | FE neo-Hookean.

For one preset, sliding speed and pressure (the thesis case: G3, 1 m/s, 2.5 bar) the
steady state of the beam (one rubber, E0, Haringx beam-column, Fig. 5.12 a lever arm) and
of the two continuum models, the first natural frequencies (at the modulus of their own
frequency) against the rig's 1500 Hz and the beam's stick-slip, and the beam run with the
lever-arm law of Eq. 5.21 refitted to the neo-Hookean continuum (a prediction: nothing of
the rig enters). The thesis row holds the chapter-5 numbers: the measured deflection
(Fig. 5.14) and stick-slip frequency, the thesis's simulated tip slope and bending angle
(Fig. 5.15) and its guessed lever arm (Fig. 5.12 a at that bending angle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from friction_model.compound import REFERENCE_COMPOUND, Compound
from friction_model.continuum.analysis import ElementAnalysis, analyse_element
from friction_model.continuum.lever_law import (
    beam_steady_state,
    fit_lever_arm_law,
    lever_arm_sweep,
)
from friction_model.continuum.model import ElementSpec

__all__ = ["THESIS_G3", "Comparison", "continuum_vs_beam"]

#: Chapter 5 numbers for G3 at 1 m/s, 2.5 bar: measured deflection (Fig. 5.14), the
#: thesis's simulated tip slope (Fig. 5.15, "good agreement" with the image) and bending
#: angle, the rig's stick-slip frequency (section 5.3.2).
THESIS_G3 = {"tip_deflection_mm": 1.6, "tip_slope_deg": 18.1, "bending_deg": 14.0,
             "stick_slip_Hz": 1500.0}
#: Friction coefficients of the lever-arm sweep (the tilt grows with mu).
SWEEP_MUS = (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5)


@dataclass(frozen=True)
class Comparison:
    """The result of :func:`continuum_vs_beam`.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per model: ``model, tip_deflection_mm, tip_slope_deg, bending_deg,
        lever_arm_mm, contact_length_mm, liftoff_mm, front_pressure_ratio,
        first_mode_sliding_Hz, first_mode_stuck_Hz, stick_slip_Hz, status``.
    linear, neo_hookean : ElementAnalysis
    sweep : pandas.DataFrame
        The neo-Hookean lever-arm sweep (:func:`lever_arm_sweep`).
    lever_law : dict
        e1..e4 of Eq. 5.21 fitted to the sweep, and its rms.
    mu : float
        Friction coefficient at the sliding speed.
    """

    table: pd.DataFrame
    linear: ElementAnalysis
    neo_hookean: ElementAnalysis
    sweep: pd.DataFrame
    lever_law: dict[str, float]
    mu: float


def _beam_rows(mu: float, N: float, length_m: float, law: dict[str, float],
               compound: Compound, stick_slip: dict[str, float] | None) -> list[dict[str, Any]]:
    """Timoshenko rows: Fig. 5.12 a law, refitted law, constant FE lever arm."""
    from friction_model.dynamics.stick_slip import loaded_mode_at_own_modulus_Hz
    from friction_model.dynamics.timoshenko import TimoshenkoParams

    fields = {"length_m": length_m}
    rows = []
    element = TimoshenkoParams(E_Pa=compound.E0_Pa, density_kg_m3=compound.density_kg_m3,
                               kelvin_voigt_s=0.0, contact_stiffness_N_m=1.0, **fields)
    f_mode = loaded_mode_at_own_modulus_Hz(element, N, compound.storage_modulus_Pa)
    fitted = {k: v for k, v in law.items() if k != "rms_m"}
    for name, extra in (("Timoshenko (Haringx), Fig. 5.12 a lever arm", {}),
                        ("Timoshenko (Haringx), Eq. 5.21 refitted to FE", fitted)):
        b = beam_steady_state(mu=mu, normal_force_N=N, compound=compound, **fields, **extra)
        rows.append({
            "model": name,
            "tip_deflection_mm": b["tip_deflection_m"] * 1e3,
            "tip_slope_deg": math.degrees(b["tip_slope_rad"]),
            "bending_deg": math.degrees(b["bending_angle_rad"]),
            "lever_arm_mm": b["lever_arm_m"] * 1e3,
            "contact_length_mm": b["contact_length_m"] * 1e3,
            "liftoff_mm": b["liftoff_m"] * 1e3,
            "first_mode_sliding_Hz": f_mode if not extra else np.nan,
            "stick_slip_Hz": (stick_slip or {}).get("frequency_Hz", np.nan) if not extra
            else np.nan,
            "status": "predicted (contact: Winkler from e)",
        })
    return rows


def _fe_row(a: ElementAnalysis, name: str) -> dict[str, Any]:
    row = a.outputs.as_row()
    row["model"] = name
    row["first_mode_sliding_Hz"] = a.first_sliding_own_modulus_Hz
    row["first_mode_stuck_Hz"] = a.first_stuck_own_modulus_Hz
    row["status"] = "predicted"
    return row


def continuum_vs_beam(
    preset: str = "G3",
    *,
    velocity_mps: float = 1.0,
    pressure_bar: float = 2.5,
    n_length: int = 16,
    n_length_sweep: int = 8,
    sweep_mus: tuple[float, ...] = SWEEP_MUS,
    compound: Compound = REFERENCE_COMPOUND,
    beam_stick_slip: bool = True,
) -> Comparison:
    """Thesis | Timoshenko (Haringx) | FE linear | FE neo-Hookean for one element.

    Parameters
    ----------
    preset, velocity_mps, pressure_bar : str, float, float
        The case (default the thesis's G3, 1 m/s, 2.5 bar).
    n_length : int
        Mesh density of the two continuum rows (elements across the length).
    n_length_sweep : int
        Mesh density of the lever-arm sweep.
    sweep_mus : tuple of float
        Friction coefficients of the sweep.
    compound : Compound
        The rubber.
    beam_stick_slip : bool
        Also run the beam's stick-slip limit cycle (G3, 1 m/s, 2.5 bar only; ~10 s).

    Returns
    -------
    Comparison
    """
    lin = analyse_element(preset, velocity_mps=velocity_mps, pressure_bar=pressure_bar,
                          model="linear", compound=compound, n_length=n_length)
    nh = analyse_element(preset, velocity_mps=velocity_mps, pressure_bar=pressure_bar,
                         model="neo-hookean", compound=compound, n_length=n_length)
    mu, N = lin.outputs.mu, lin.outputs.normal_force_N
    spec = ElementSpec.from_preset(preset, compound=compound, n_length=n_length_sweep)
    sweep = lever_arm_sweep(spec, normal_force_N=N, mus=sweep_mus, model="neo-hookean")
    law = fit_lever_arm_law(sweep["bending_rad"], sweep["lever_arm_m"], spec.length_m)
    thesis_case = (preset, velocity_mps, pressure_bar) == ("G3", 1.0, 2.5)
    stick = None
    if beam_stick_slip and thesis_case:
        from friction_model.dynamics.stick_slip import predict_stick_slip

        stick = predict_stick_slip(compound=compound)
    rows = []
    if thesis_case:
        from friction_model.dynamics.timoshenko import TimoshenkoParams, lever_arm

        e = lever_arm(TimoshenkoParams(contact_stiffness_N_m=1.0),
                      math.radians(THESIS_G3["bending_deg"]))
        rows.append({
            "model": "thesis (chapter 5)",
            **{k: THESIS_G3[k] for k in ("tip_deflection_mm", "tip_slope_deg", "bending_deg")},
            "lever_arm_mm": e * 1e3,
            "contact_length_mm": np.nan,  # not measured in chapter 5
            "stick_slip_Hz": THESIS_G3["stick_slip_Hz"],
            "status": "deflection, stick-slip measured; slope, bending simulated; e guessed",
        })
    rows += _beam_rows(mu, N, spec.length_m, law, compound, stick)[:1]
    rows += [_fe_row(lin, "FE linear"), _fe_row(nh, "FE neo-Hookean")]
    rows += _beam_rows(mu, N, spec.length_m, law, compound, None)[1:]
    table = pd.DataFrame(rows)
    table["liftoff_mm"] = spec.length_m * 1e3 - table["contact_length_mm"]
    return Comparison(table=table, linear=lin, neo_hookean=nh, sweep=sweep, lever_law=law, mu=mu)
