"""What a beam model and the TIR pipeline can be checked against, from one solved element.

* the sections along the depth: deflection r(y) (the section's mean x displacement),
  rotation phi(y) of the deformed section (its least-squares line), slope alpha(y) of the
  deformed centre line, shear gamma = alpha - phi (the bending / shear split of Fig. 5.15);
* the face: contact pressure, contact length, rear lift-off (``l - contact length``, as the
  pipeline's ``liftoff_mm``), the pressure at the leading edge and the lever arm e of the
  normal resultant (positive in front of the deformed face centre, towards the leading
  edge, as e of Eq. 5.20-5.22).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd

from friction_model.continuum.state import ElementState

__all__ = ["ElementOutputs", "element_outputs", "face_contact", "section_profile"]

#: Depth of the band below the face over which the tip slope is taken, m (about what a
#: side-view camera resolves of the element's end).
SLOPE_BAND_M = 0.5e-3
#: Width of the leading band over which the front-edge pressure is averaged, m (about
#: the TIR camera's resolution of a peak; the corner pressure itself is singular).
FRONT_BAND_M = 0.5e-3


def section_profile(state: ElementState, *, n_sections: int = 61,
                    n_across: int = 21) -> pd.DataFrame:
    """Deflection, section rotation, centre-line slope and shear along the depth.

    Parameters
    ----------
    state : ElementState
    n_sections : int
        Heights from the root (y = 0) to the face (y = d).
    n_across : int
        Points across each section.

    Returns
    -------
    pandas.DataFrame
        ``y_m, deflection_m, rotation_rad, slope_rad, shear_rad, centre_x_m, centre_y_m``
        (the deformed centre of each section); positive rotation and slope lean the element
        towards +x (the beam's phi and alpha).
    """
    spec = state.mesh.spec
    half = 0.5 * spec.length_m * (1 - 1e-9)
    ys = np.linspace(0.0, spec.height_m * (1 - 1e-9), n_sections)
    xs = np.linspace(-half, half, n_across)
    X, Y = np.meshgrid(xs, ys)
    em = state.mesh
    # probe each component with the scalar P2 basis (its dofs are the components' dofs)
    P = em.basis_scalar.probes(np.vstack([X.ravel(), Y.ravel()]))
    ix, iy = em.basis_u.split_indices()
    ux = (P @ state.displacement[ix]).reshape(X.shape)
    uy = (P @ state.displacement[iy]).reshape(X.shape)
    xd, yd = X + ux, Y + uy
    r = ux.mean(axis=1)
    xc = xs - xs.mean()
    # the deformed section's direction (cov(x, x_def), cov(x, y_def)); the element leans +x
    # when the section turns clockwise (y_def falls with x)
    rotation = np.arctan2(-(yd - yd.mean(axis=1, keepdims=True)) @ xc,
                          (xd - xd.mean(axis=1, keepdims=True)) @ xc)
    dx = np.gradient(xd.mean(axis=1), ys, edge_order=2)
    dy = np.gradient(yd.mean(axis=1), ys, edge_order=2)
    slope = np.arctan2(dx, dy)
    return pd.DataFrame({"y_m": ys, "deflection_m": r, "rotation_rad": rotation,
                         "slope_rad": slope, "shear_rad": slope - rotation,
                         "centre_x_m": xd.mean(axis=1), "centre_y_m": yd.mean(axis=1)})


def _separation(x: np.ndarray, gap: np.ndarray, i: int, step: int) -> float:
    """Where the face leaves the ice beyond the last node ``i`` in contact, m.

    Near a smooth separation point x_e the gap opens as (x - x_e)^(3/2) (the elastic
    solution at a receding contact edge with zero pressure there); the two nodes after
    ``i`` give x_e from (g1 / g2)^(2/3) = (x1 - x_e) / (x2 - x_e), kept between ``x[i]``
    and ``x[i + step]``. A face corner in contact is the end itself.
    """
    j1, j2 = i + step, i + 2 * step
    if not 0 <= j1 < x.size:
        return float(x[i])
    if not 0 <= j2 < x.size or gap[j2] <= gap[j1] or gap[j1] <= 0:
        return float(0.5 * (x[i] + x[j1]))
    q = (gap[j1] / gap[j2]) ** (2.0 / 3.0)
    xe = (x[j1] - q * x[j2]) / (1.0 - q)
    lo, hi = sorted((float(x[i]), float(x[j1])))
    return float(np.clip(xe, lo, hi))


def face_contact(state: ElementState) -> dict[str, float]:
    """Contact length, lift-off, leading-edge pressure and lever arm of the face, SI units.

    The contact ends where the gap of the nodes off the ice extrapolates to zero
    (:func:`_separation`; the nodes' deformed x); the lever arm is the deformed face
    centre minus the point of action of the normal resultant.

    Returns
    -------
    dict
        ``contact_length_m, liftoff_m, front_lift_m, rear_lift_m, lever_arm_m,
        mean_pressure_Pa, front_pressure_Pa, front_pressure_ratio, peak_pressure_Pa``.
    """
    em = state.mesh
    x = em.face_x_m + state.face_ux_m
    w = em.face_weights_m
    lam = state.face_force_N_per_m
    act = np.flatnonzero(state.active)
    if act.size == 0:
        raise ValueError("the face is not in contact with the ice")
    gap = -(state.face_uy_m + state.indentation_m)  # distance from the ice, >= 0 off it
    lead = _separation(x, gap, int(act[0]), -1)
    trail = _separation(x, gap, int(act[-1]), +1)
    length = trail - lead
    centre = float(np.sum(w * state.face_ux_m) / em.spec.length_m)
    x_n = float(np.sum(lam * x) / lam.sum())
    p = state.face_pressure_Pa
    band = (x >= lead) & (x <= lead + FRONT_BAND_M)
    front = float(np.sum(lam[band]) / np.sum(w[band]))
    mean = float(lam.sum() / length)
    return {
        "contact_length_m": float(length),
        "liftoff_m": float(max(0.0, em.spec.length_m - length)),
        "front_lift_m": float(lead - x[0]),
        "rear_lift_m": float(x[-1] - trail),
        "lever_arm_m": centre - x_n,
        "mean_pressure_Pa": mean,
        "front_pressure_Pa": front,
        "front_pressure_ratio": front / mean,
        "peak_pressure_Pa": float(p.max()),
    }


@dataclass(frozen=True)
class ElementOutputs:
    """The numbers of one solved element (SI units; see :func:`element_outputs`)."""

    model: str
    normal_force_N: float
    mu: float
    tip_deflection_m: float
    tip_slope_rad: float
    bending_rad: float
    max_rotation_rad: float
    shear_rad: float
    indentation_m: float
    contact_length_m: float
    liftoff_m: float
    rear_lift_m: float
    lever_arm_m: float
    mean_pressure_Pa: float
    front_pressure_Pa: float
    front_pressure_ratio: float
    peak_pressure_Pa: float

    def as_row(self) -> dict[str, float | str]:
        """The table row in mm and deg (the names of ``continuum_vs_beam.csv``)."""
        return {
            "model": self.model,
            "tip_deflection_mm": self.tip_deflection_m * 1e3,
            "tip_slope_deg": math.degrees(self.tip_slope_rad),
            "bending_deg": math.degrees(self.bending_rad),
            "max_rotation_deg": math.degrees(self.max_rotation_rad),
            "lever_arm_mm": self.lever_arm_m * 1e3,
            "contact_length_mm": self.contact_length_m * 1e3,
            "liftoff_mm": self.liftoff_m * 1e3,
            "front_pressure_ratio": self.front_pressure_ratio,
        }

    def as_dict(self) -> dict[str, float | str]:
        """All fields."""
        return asdict(self)


def element_outputs(state: ElementState) -> ElementOutputs:
    """Tip deflection, slope, bending / shear, contact and lever arm of a solved element.

    The tip deflection is the face's mean x displacement (exact integral of the P2 trace);
    the tip slope is that of the deformed centre line over the last ``SLOPE_BAND_M`` below
    the face; bending angle (section rotation) and shear are those of the section at the
    face, as r(d), alpha(d), phi(d) and gamma(d) of the beam (Fig. 5.15).

    Parameters
    ----------
    state : ElementState
        A solution on the ice.

    Returns
    -------
    ElementOutputs
    """
    em = state.mesh
    prof = section_profile(state)
    tip = prof.iloc[-1]
    # the centre line's slope over the band below the face (its corner boundary layer
    # makes the slope at the face itself converge slowly under refinement)
    below = prof.iloc[int(np.argmin(np.abs(prof["y_m"] - (em.spec.height_m - SLOPE_BAND_M))))]
    tip_slope = math.atan2(tip["centre_x_m"] - below["centre_x_m"],
                           tip["centre_y_m"] - below["centre_y_m"])
    contact = face_contact(state)
    return ElementOutputs(
        model=state.model,
        normal_force_N=state.normal_force_N,
        mu=state.mu,
        tip_deflection_m=float(np.sum(em.face_weights_m * state.face_ux_m) / em.spec.length_m),
        tip_slope_rad=float(tip_slope),
        bending_rad=float(tip["rotation_rad"]),
        max_rotation_rad=float(prof["rotation_rad"].max()),
        shear_rad=float(tip["shear_rad"]),
        indentation_m=state.indentation_m,
        contact_length_m=contact["contact_length_m"],
        liftoff_m=contact["liftoff_m"],
        rear_lift_m=contact["rear_lift_m"],
        lever_arm_m=contact["lever_arm_m"],
        mean_pressure_Pa=contact["mean_pressure_Pa"],
        front_pressure_Pa=contact["front_pressure_Pa"],
        front_pressure_ratio=contact["front_pressure_ratio"],
        peak_pressure_Pa=contact["peak_pressure_Pa"],
    )
