"""Real contact ratio of the reference samples from the block dynamics (Fig. 4.21).

The rigid-body block model with face contact (:mod:`friction_model.dynamics.rigid`, penalty
springs spread over each element's bottom face) tilts each element under friction; a tilted
face touches the ice only over part of its length (lift-off at the back, line-wise contact
for thin, strongly inclined elements). Inside the touching part of a face only the real
contact of the dry/wet model is in contact with the ice: the fraction
:func:`friction_model.contact.drywet.real_contact_fraction` of the local pressure (the same function
the synthetic renderer uses for its patchy contact), integrated over the linear (Winkler)
pressure profile of the face. The contact ratio of a sample is that real contact area over
its nominal area L w (the sipes count as no contact), as in Fig. 4.21.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache
from typing import Any

import numpy as np
import pandas as pd

from friction_model.contact.drywet import DryWetParameters, real_contact_fraction
from friction_model.contact.laws import ExponentialLaw
from friction_model.dynamics.rigid import BlockParams, simulate_block_dynamics
from friction_model.geometry import REFERENCE_SAMPLES, BlockGeometry, reference_block

__all__ = [
    "THESIS_CONTACT_RATIO",
    "element_real_contact_fractions",
    "face_real_contact_fraction",
    "reference_contact_ratios",
]

#: Midpoints of the quadrature over the touching length of a face.
_N_QUAD = 64


def face_real_contact_fraction(
    normal_force_N: np.ndarray | float,
    face_contact_fraction: np.ndarray | float,
    face_area_m2: np.ndarray | float,
    params: DryWetParameters | None = None,
) -> float | np.ndarray:
    """Real contact area over the face area of elements in (partial) face contact.

    A face touching over the fraction c of its length carries the normal force F with the
    linear Winkler pressure of the block model: uniform, F / A, in full contact (c = 1),
    triangular from the leading edge, p(s) = 2 p_mean s, when it has lifted off at the back
    (c < 1, p_mean = F / (c A)). The real contact at each point is
    :func:`friction_model.contact.drywet.real_contact_fraction` of the local pressure (Eq. 4.1-4.7
    model, ``contact_fraction_ref`` (p / p_ref)^gamma); integrated by the midpoint rule.

    Parameters
    ----------
    normal_force_N, face_contact_fraction, face_area_m2 : float or ndarray
        F (N), c in [0, 1], A = l w (m^2), broadcast together.
    params : DryWetParameters, optional
        Default: the package's one calibrated parameter set.

    Returns
    -------
    float or ndarray
        Real contact area / face area, in [0, 1] (a float for scalar inputs).
    """
    params = params or DryWetParameters()
    F, c, A = np.broadcast_arrays(
        np.atleast_1d(np.asarray(normal_force_N, float)),
        np.atleast_1d(np.asarray(face_contact_fraction, float)),
        np.atleast_1d(np.asarray(face_area_m2, float)),
    )
    scalar = np.ndim(normal_force_N) == np.ndim(face_contact_fraction) == np.ndim(face_area_m2) == 0
    out = np.zeros(F.shape)
    touching = (F > 0) & (c > 0)
    s = (np.arange(_N_QUAD) + 0.5) / _N_QUAD
    for idx in zip(*np.nonzero(touching), strict=True):
        f, cc, a = float(F[idx]), min(float(c[idx]), 1.0), float(A[idx])
        p_mean = f / (cc * a)
        p = np.full(_N_QUAD, p_mean) if cc >= 1.0 else 2.0 * p_mean * s
        out[idx] = cc * float(np.mean(real_contact_fraction(p, params)))
    return float(out[0]) if scalar else out


def _steady_block(
    name: str,
    velocity_mps: float,
    pressure_bar: float,
    friction: Any,
    t_end_s: float,
    steady_fraction: float,
) -> tuple[Any, np.ndarray, pd.DataFrame]:
    geom = reference_block(name)
    params = BlockParams(
        n_elements=geom.n_elements,
        height_m=geom.height_mm * 1e-3,
        block_length_m=geom.length_mm * 1e-3,
        width_m=geom.width_mm * 1e-3,
        sipe_width_m=geom.sipe_width_mm * 1e-3,
        contact_model="face",
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
    return geom, lengths, steady


@lru_cache(maxsize=64)
def _element_real_contact(preset: str, velocity_mps: float, pressure_bar: float) -> np.ndarray:
    geom, lengths, steady = _steady_block(
        preset, velocity_mps, pressure_bar, ExponentialLaw(a1=0.15, a2=0.25, a3=-0.8), 0.03, 0.3
    )
    g = steady.groupby("element")
    real = face_real_contact_fraction(
        g["normal_force_N"].mean().to_numpy(),
        g["contact_fraction"].mean().to_numpy(),
        lengths * geom.width_mm * 1e-3,
    )
    real.setflags(write=False)
    return real


def element_real_contact_fractions(
    preset: str | BlockGeometry, velocity_mps: float, pressure_bar: float
) -> np.ndarray:
    """Real contact fraction of each element face of a reference sample in steady sliding.

    The block model of :func:`reference_contact_ratios` (face contact, the one rubber, the
    default Eq. 5.7 friction) slides at ``velocity_mps`` under ``pressure_bar``; each
    element's steady face contact and normal force give its real contact fraction by
    :func:`face_real_contact_fraction` (the dry/wet model's
    :func:`~friction_model.contact.drywet.real_contact_fraction` with the default parameters).
    Cached: repeated calls with the same arguments cost nothing.

    Parameters
    ----------
    preset : str or BlockGeometry
        Reference sample ``"G0"`` .. ``"G7"`` (Table 4.4), or its block
        (``reference_block("G3")``); the block model is that of the reference samples.
    velocity_mps : float
        Sliding velocity, m/s.
    pressure_bar : float
        Nominal pressure F_N / (L w), bar.

    Returns
    -------
    (n_elements,) ndarray
        Real contact area over the element's face area l_i w, leading element first.
    """
    if isinstance(preset, BlockGeometry):
        names = [name for name, block in REFERENCE_SAMPLES.items() if block == preset]
        if not names:
            raise ValueError("preset must be a reference sample (its name or its block: "
                             f"{', '.join(sorted(REFERENCE_SAMPLES))}), got another block, "
                             f"{preset!r}")
        preset = names[0]
    elif not isinstance(preset, str):
        raise TypeError("preset must be a reference sample's name or block, got "
                        f"{type(preset).__name__}")
    return np.array(_element_real_contact(preset, float(velocity_mps), float(pressure_bar)))


#: Contact ratios measured by TIR (section 4.3.6, Fig. 4.21): about 70 % (G0), 25 % (G7).
THESIS_CONTACT_RATIO = {"G0": 0.70, "G7": 0.25}


def reference_contact_ratios(
    samples: Sequence[str] = ("G0", "G3", "G5", "G6", "G7"),
    *,
    velocity_mps: float = 1.0,
    pressure_bar: float = 2.5,
    friction: Any = None,
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
    t_end_s : float
        Simulated time, s; the last ``steady_fraction`` of it is averaged.
    steady_fraction : float
        Fraction of the time span averaged as the steady state.

    Returns
    -------
    pandas.DataFrame
        One row per sample: ``sample, n_sipes, face_contact_fraction`` (touching length
        over the element faces), ``apparent_contact_ratio`` (touching area over the nominal
        area), ``contact_ratio`` (real contact area over the nominal area, Fig. 4.21),
        ``angle_deg`` (mean steady deflection angle), ``thesis_contact_ratio`` (Fig. 4.21
        where given, else NaN).

    Notes
    -----
    The rubber is :data:`friction_model.compound.REFERENCE_COMPOUND` (the block model's
    defaults); the real contact uses the default :class:`DryWetParameters`.
    """
    friction = friction or ExponentialLaw(a1=0.15, a2=0.25, a3=-0.8)
    rows = []
    for name in samples:
        geom, lengths, steady = _steady_block(
            name, velocity_mps, pressure_bar, friction, t_end_s, steady_fraction
        )
        g = steady.groupby("element")
        frac = g["contact_fraction"].mean().to_numpy()
        angle = g["angle_deg"].mean().to_numpy()
        real = face_real_contact_fraction(
            g["normal_force_N"].mean().to_numpy(), frac, lengths * geom.width_mm * 1e-3
        )
        length_m = geom.length_mm * 1e-3
        rows.append(
            {
                "sample": name,
                "n_sipes": geom.n_sipes,
                "face_contact_fraction": float(np.sum(frac * lengths) / lengths.sum()),
                "apparent_contact_ratio": float(np.sum(frac * lengths) / length_m),
                "contact_ratio": float(np.sum(real * lengths) / length_m),
                "angle_deg": float(np.mean(angle)),
                "thesis_contact_ratio": THESIS_CONTACT_RATIO.get(name, np.nan),
            }
        )
    return pd.DataFrame(rows)
