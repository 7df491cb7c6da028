"""Real contact ratio of the reference samples from the block dynamics (Fig. 4.21).

The rigid-body block model with face contact (:mod:`friction_model.dynamics.rigid`, penalty
springs spread over each element's bottom face) tilts each element under friction; a tilted
face touches the ice only over part of its length (lift-off at the back, line-wise contact
for thin, strongly inclined elements). The contact ratio of a sample is the contact area
over its nominal area L w (the sipes count as no contact), as in Fig. 4.21.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd

from friction_model.dynamics.rigid import BlockParams, simulate_block_dynamics
from friction_model.geometry import reference_block
from friction_model.laws import ExponentialLaw

__all__ = ["THESIS_CONTACT_RATIO", "reference_contact_ratios"]

#: Contact ratios measured by TIR (section 4.3.6, Fig. 4.21): about 70 % (G0), 25 % (G7).
THESIS_CONTACT_RATIO = {"G0": 0.70, "G7": 0.25}


def reference_contact_ratios(
    samples: Sequence[str] = ("G0", "G3", "G5", "G6", "G7"),
    *,
    velocity_mps: float = 1.0,
    pressure_bar: float = 2.5,
    friction: Any = None,
    loss_factor: float = 0.4,
    t_end_s: float = 0.03,
    steady_fraction: float = 0.3,
) -> pd.DataFrame:
    """Steady contact ratio of the reference samples sliding at ``velocity_mps``.

    Parameters
    ----------
    samples : sequence of str
        Reference samples (Table 4.4 / Fig. 4.21): 20 mm x 80 mm, 0..7 sipes.
    velocity_mps : float
        Sliding velocity, m/s.
    pressure_bar : float
        Nominal pressure F_N / (L w), bar; the preload distance is set so that the
        undeflected block carries it.
    friction : friction law, optional
        Default: Eq. 5.7 with a1 = 0.15, a2 = 0.25, a3 = -0.8 s/m (mu = 0.26 at 1 m/s).
    loss_factor : float
        Rubber loss factor (damping of the element springs).
    t_end_s : float
        Simulated time, s; the last ``steady_fraction`` of it is averaged.
    steady_fraction : float
        Fraction of the time span averaged as the steady state.

    Returns
    -------
    pandas.DataFrame
        One row per sample: ``sample, n_sipes, face_contact_fraction`` (contact over the
        element faces), ``contact_ratio`` (over the nominal area), ``angle_deg`` (mean steady
        deflection angle), ``thesis_contact_ratio`` (Fig. 4.21 where given, else NaN).
    """
    friction = friction or ExponentialLaw(a1=0.15, a2=0.25, a3=-0.8)
    rows = []
    for name in samples:
        geom = reference_block(name)
        params = BlockParams(
            n_elements=geom.n_elements,
            height_m=geom.height_mm * 1e-3,
            block_length_m=geom.length_mm * 1e-3,
            width_m=geom.width_mm * 1e-3,
            sipe_width_m=geom.sipe_width_mm * 1e-3,
            contact_model="face",
            loss_factor=loss_factor,
        )
        lengths = geom.element_lengths * 1e-3
        load_N = pressure_bar * 1e5 * geom.nominal_area_mm2 * 1e-6
        stiffness = params.youngs_modulus_Pa * lengths.sum() * params.width_m / params.height_m
        preload = params.height_m - load_N / stiffness
        res = simulate_block_dynamics(
            params, velocity=velocity_mps, preload=preload, friction=friction, t_end_s=t_end_s
        )
        data = res.data
        steady = data[data["time_s"] >= (1.0 - steady_fraction) * t_end_s]
        frac = steady.groupby("element")["contact_fraction"].mean().to_numpy()
        angle = steady.groupby("element")["angle_deg"].mean().to_numpy()
        rows.append(
            {
                "sample": name,
                "n_sipes": geom.n_sipes,
                "face_contact_fraction": float(np.sum(frac * lengths) / lengths.sum()),
                "contact_ratio": float(np.sum(frac * lengths) / (geom.length_mm * 1e-3)),
                "angle_deg": float(np.mean(angle)),
                "thesis_contact_ratio": THESIS_CONTACT_RATIO.get(name, np.nan),
            }
        )
    return pd.DataFrame(rows)
