"""Measured contact to model: real contact area, local pressure and the lever arm e(phi).

Couples the output of the contact pipeline (``frames.csv`` and ``elements.csv`` of
``tir-contact analyze``, one row per frame and per frame and element, element 0 leads) to the
friction model:

* :func:`contact_from_pipeline` averages the measured contact over the frames that show the
  whole block: the real contact fraction of the rubber face (``phi`` of the dry/wet model,
  :attr:`friction_model.conditions.Conditions.contact_fraction`), per element too, the real
  contact area and the local pressure ``p_local = F_N / A_real`` (section 4.5.1: the load is
  carried by the real contact). :func:`drywet_inputs` turns it into the inputs of
  :func:`~friction_model.contact.drywet.friction_table` /
  :func:`~friction_model.contact.drywet.simulate_block`.
* :func:`lever_arm_observations` converts measured front-peak positions (or contact lengths)
  into the eccentricity e of the normal force relative to the element's face centre, and
  :func:`fit_lever_arm` identifies e1..e4 of Eq. 5.21/5.22 from e against the deflection
  angle (least squares with standard errors and confidence intervals); the result plugs into
  :class:`~friction_model.dynamics.TimoshenkoParams`.

Conventions: image x in mm from the left image edge (docs/formats.md, "Coordinates");
``sliding_direction`` is the direction the block moves in the image, so its leading edge
faces that way. The lever arm is positive towards the leading edge (as in
:func:`friction_model.dynamics.lever_arm` and ``lever_arm_mm`` of ``ground_truth.csv``).
"""

from __future__ import annotations

import logging
import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from scipy import stats
from scipy.optimize import least_squares

from friction_model._fitting import covariance_with_stderr
from friction_model._table_io import read_table
from friction_model.geometry import BlockGeometry
from tir_common.validate import check_number, check_positive

logger = logging.getLogger(__name__)

__all__ = [
    "REQUIRED_ELEMENT_COLUMNS",
    "REQUIRED_FRAME_COLUMNS",
    "LeverArmFit",
    "MeasuredContact",
    "contact_from_pipeline",
    "drywet_inputs",
    "fit_lever_arm",
    "lever_arm_eq_5_21",
    "lever_arm_observations",
    "read_pipeline_tables",
]

#: The columns of the pipeline's ``frames.csv`` read here (the file has more).
REQUIRED_FRAME_COLUMNS = (
    "frame", "time_s", "block_in_view", "contact_area_mm2", "n_elements_in_contact",
)
#: The columns of the pipeline's ``elements.csv`` read here (the file has more).
REQUIRED_ELEMENT_COLUMNS = ("frame", "time_s", "element", "contact_area_mm2", "contact_length_mm")
#: Lever-arm parameter names of Eq. 5.21/5.22 in :class:`TimoshenkoParams` spelling.
LEVER_ARM_PARAMS = ("e1", "e2_per_rad", "e3_m", "e4_m")


# -- reading -------------------------------------------------------------------------------
def _as_table(name: str, table: pd.DataFrame | str | os.PathLike[str]) -> tuple[pd.DataFrame, str]:
    """A table and its name; files through the shared dialect-detecting CSV reader."""
    if isinstance(table, pd.DataFrame):
        return table, name
    path = os.fspath(table)
    if not os.path.isfile(path):
        raise ValueError(f"{path}: does not exist")
    return read_table(path)[0], path


def _require(table: pd.DataFrame, columns: tuple[str, ...], source: str) -> None:
    missing = [c for c in columns if c not in table.columns]
    if missing:
        raise ValueError(
            f"{source}: missing column(s) {missing}; expected the pipeline's columns "
            f"{list(columns)} (see docs/formats.md)"
        )


def _bool_column(values: pd.Series) -> np.ndarray:
    if values.dtype == bool:
        return values.to_numpy()
    text = values.astype(str).str.strip().str.lower()
    return text.isin(("true", "1", "1.0", "yes")).to_numpy()


def read_pipeline_tables(folder: str | os.PathLike[str]) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Read ``frames.csv`` and ``elements.csv`` of one pipeline output folder.

    Parameters
    ----------
    folder : path-like
        Output folder of ``tir-contact analyze``.

    Returns
    -------
    frames, elements : pandas.DataFrame

    Raises
    ------
    ValueError
        If a file is missing or lacks a required column (the message names the file).
    """
    folder = os.fspath(folder)
    frames, fsrc = _as_table("frames", os.path.join(folder, "frames.csv"))
    elements, esrc = _as_table("elements", os.path.join(folder, "elements.csv"))
    _require(frames, ("frame", "time_s"), fsrc)
    _require(elements, ("frame", "time_s", "element"), esrc)
    return frames, elements


# -- contact -------------------------------------------------------------------------------
@dataclass(frozen=True)
class MeasuredContact:
    """Steady contact of a sliding block measured by TIR (averages over frames).

    Attributes
    ----------
    geometry : BlockGeometry
        The block the measurement belongs to.
    contact_fraction : float
        Real contact area over the rubber face area (sum of the element faces l_i w), the
        ``phi`` of the dry/wet model; the mean over the frames used.
    contact_fraction_std : float
        Sample standard deviation of the per-frame fraction (0 for one frame).
    contact_fraction_per_element : (n_elements,) ndarray
        Contact length over the element length l_i, element 0 first.
    contact_ratio : float
        Real contact area over the nominal area L w (sipes count as no contact, Fig. 4.21).
    visible_width_mm : float
        Width of the block seen in the image (contact area over contact length), mm.
    real_contact_area_mm2 : float
        ``contact_fraction`` times the full rubber face area, mm^2.
    normal_force_N : float or None
        Normal force on the block, N (given by the caller; None when unknown).
    nominal_pressure_Pa, pressure_local_Pa : float or None
        ``F_N / (L w)`` and ``F_N / A_real``, Pa (None without the normal force).
    n_frames : int
        Frames averaged.
    frames : tuple of int
        Their frame numbers.
    """

    geometry: BlockGeometry
    contact_fraction: float
    contact_fraction_std: float
    contact_fraction_per_element: np.ndarray
    contact_ratio: float
    visible_width_mm: float
    real_contact_area_mm2: float
    normal_force_N: float | None
    nominal_pressure_Pa: float | None
    pressure_local_Pa: float | None
    n_frames: int
    frames: tuple[int, ...] = field(repr=False, default=())

    def to_dict(self) -> dict[str, Any]:
        """The ``contact`` section of the parameter file (:mod:`friction_model.params_file`)."""
        out: dict[str, Any] = {
            "contact_fraction": self.contact_fraction,
            "contact_fraction_std": self.contact_fraction_std,
            "contact_fraction_per_element": [float(x) for x in self.contact_fraction_per_element],
            "contact_ratio": self.contact_ratio,
            "real_contact_area_mm2": self.real_contact_area_mm2,
            "n_frames": self.n_frames,
        }
        if self.normal_force_N is not None:
            out["normal_force_N"] = self.normal_force_N
            out["nominal_pressure_Pa"] = self.nominal_pressure_Pa
            out["pressure_local_Pa"] = self.pressure_local_Pa
        return out


def contact_from_pipeline(
    frames: pd.DataFrame | str | os.PathLike[str],
    elements: pd.DataFrame | str | os.PathLike[str],
    *,
    geometry: BlockGeometry,
    normal_force_N: float | None = None,
    visible_width_mm: float | None = None,
    image_width_mm: float | None = None,
    area_tolerance: float = 0.1,
    min_frames: int = 1,
) -> MeasuredContact:
    """Real contact fraction, area and local pressure from the pipeline's tables.

    Frames used: the block is in view, every element of ``geometry`` has a row with contact,
    the block lies inside the image (from ``block_front_x_mm``: its front and its rear, one
    block length behind, lie more than one frame's travel inside the image's x range, which
    is ``[0, image_width_mm]`` or else the range of front positions seen over the clip) and
    the block's contact area is at least ``1 - area_tolerance`` of the median over such
    frames (a frame whose first or last element is partly outside the image shows less).
    The contact fraction of frame k is ``sum_i L_c,i / sum_i l_i`` (contact lengths along
    the block centreline over the element lengths), which equals the visible contact area
    over the visible rubber area for contact strips across the width; the per-element
    fraction is ``L_c,i / l_i``. The local pressure follows section 4.5.1:
    ``p_local = F_N / (phi * sum_i l_i w)`` (the load is carried by the real contact).

    Parameters
    ----------
    frames, elements : pandas.DataFrame or path-like
        ``frames.csv`` and ``elements.csv`` of the pipeline (or the tables).
    geometry : BlockGeometry
        The block (element lengths, width, nominal area).
    normal_force_N : float, optional
        Normal force on the block, N; gives the nominal and local pressures.
    visible_width_mm : float, optional
        Width of the block in the image, mm; default the median of contact area over contact
        length of the element rows.
    image_width_mm : float, optional
        Image width in mm (``width_px * mm_per_px``); default the range of front positions.
    area_tolerance : float
        Fraction in [0, 1) below the median block contact area at which a frame counts as
        partly outside the image.
    min_frames : int
        Fewer usable frames is an error.

    Returns
    -------
    MeasuredContact

    Raises
    ------
    ValueError
        Missing columns (naming the file), fewer than ``min_frames`` frames with the whole
        block in view, or a non-positive normal force.
    """
    ftab, fsrc = _as_table("frames", frames)
    etab, esrc = _as_table("elements", elements)
    _require(ftab, REQUIRED_FRAME_COLUMNS, fsrc)
    _require(etab, REQUIRED_ELEMENT_COLUMNS, esrc)
    area_tolerance = check_number("area_tolerance", area_tolerance, low=0.0, high=1.0,
                                  high_open=True)
    if normal_force_N is not None:
        check_positive("normal_force_N", normal_force_N)
    lengths = geometry.element_lengths
    wide, el = _whole_block_frames(ftab, etab, geometry, image_width_mm, fsrc)
    wide = _drop_partly_outside(wide, ftab, area_tolerance)
    if len(wide) < min_frames:
        raise ValueError(
            f"{fsrc}: {len(wide)} frame(s) show the whole block, need min_frames={min_frames}"
        )
    if visible_width_mm is None:
        visible_width_mm = _visible_width(el[el["frame"].isin(wide.index)])
    if not (math.isfinite(visible_width_mm) and visible_width_mm > 0):
        raise ValueError(f"{esrc}: cannot derive the visible block width from the element rows")

    # a contact edge is found to a fraction of a pixel, so an element in full contact can
    # measure slightly longer than its nominal length; a contact fraction cannot exceed 1
    lc = np.minimum(wide.to_numpy(float), lengths[None, :])  # (n_frames, n_el), mm
    per_frame = lc.sum(axis=1) / lengths.sum()
    fraction = float(per_frame.mean())
    per_element = (lc / lengths[None, :]).mean(axis=0)
    face_area = geometry.rubber_area_mm2
    real_area = fraction * face_area
    nominal_p = local_p = None
    if normal_force_N is not None:
        nominal_p = normal_force_N / (geometry.nominal_area_mm2 * 1e-6)
        local_p = normal_force_N / (real_area * 1e-6)
    return MeasuredContact(
        geometry=geometry,
        contact_fraction=fraction,
        contact_fraction_std=float(per_frame.std(ddof=1)) if per_frame.size > 1 else 0.0,
        contact_fraction_per_element=per_element,
        contact_ratio=real_area / geometry.nominal_area_mm2,
        visible_width_mm=float(visible_width_mm),
        real_contact_area_mm2=float(real_area),
        normal_force_N=None if normal_force_N is None else float(normal_force_N),
        nominal_pressure_Pa=nominal_p,
        pressure_local_Pa=local_p,
        n_frames=len(wide),
        frames=tuple(int(f) for f in wide.index),
    )


def _whole_block_frames(
    ftab: pd.DataFrame,
    etab: pd.DataFrame,
    geometry: BlockGeometry,
    image_width_mm: float | None,
    fsrc: str,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Contact length per frame (rows) and element (columns) of the frames showing the block.

    A frame counts when the block is in view, every element has a row with contact and the
    block lies inside the image (:func:`_frames_inside`). Also returns the element rows of
    the candidate frames (contact length NaN read as 0).
    """
    n_el = geometry.n_elements
    in_view = _bool_column(ftab["block_in_view"])
    n_contact = pd.to_numeric(ftab["n_elements_in_contact"], errors="coerce").to_numpy()
    candidates = set(ftab.loc[in_view & (n_contact >= n_el), "frame"].astype(int))
    inside = _frames_inside(ftab, in_view, geometry.length_mm, image_width_mm)
    if inside is not None:
        candidates &= inside
    el = etab[etab["frame"].astype(int).isin(candidates)]
    el = el[(el["element"] >= 0) & (el["element"] < n_el)]
    length_c = pd.to_numeric(el["contact_length_mm"], errors="coerce")
    el = el.assign(contact_length_mm=length_c.fillna(0.0))
    wide = el.pivot_table(
        index="frame", columns="element", values="contact_length_mm", aggfunc="first"
    )
    wide = wide.reindex(columns=range(n_el))
    complete = wide.notna().all(axis=1) & (wide > 0).all(axis=1)
    wide = wide[complete]
    if len(wide) == 0:
        raise ValueError(
            f"{fsrc}: no frame shows the whole block ({n_el} elements with contact and "
            "block_in_view true); cannot average the contact"
        )
    return wide, el


def _drop_partly_outside(
    wide: pd.DataFrame, ftab: pd.DataFrame, area_tolerance: float
) -> pd.DataFrame:
    """Frames whose block contact area is at least ``1 - area_tolerance`` of the median."""
    area_block = (
        pd.to_numeric(ftab.set_index("frame")["contact_area_mm2"], errors="coerce")
        .groupby(level=0)
        .first()
        .reindex(wide.index)
    )
    keep = area_block >= (1.0 - area_tolerance) * float(area_block.median())
    return wide[keep.to_numpy()]


def _visible_width(used: pd.DataFrame) -> float:
    """Median contact area over contact length of the element rows, mm."""
    ratio = pd.to_numeric(used["contact_area_mm2"], errors="coerce") / used[
        "contact_length_mm"
    ].where(used["contact_length_mm"] > 0)
    return float(np.nanmedian(ratio.to_numpy(float)))


def _frames_inside(
    ftab: pd.DataFrame, in_view: np.ndarray, block_length_mm: float, image_width_mm: float | None
) -> set[int] | None:
    """Frames whose whole block lies inside the image, from the block's front position.

    None when the table cannot tell (no ``block_front_x_mm``, no motion, or no frame passes,
    e.g. a clip that never shows the block's entry and exit).
    """
    if "block_front_x_mm" not in ftab.columns:
        return None
    x = pd.to_numeric(ftab["block_front_x_mm"], errors="coerce").to_numpy(float)
    t = pd.to_numeric(ftab["time_s"], errors="coerce").to_numpy(float)
    ok = in_view & np.isfinite(x) & np.isfinite(t)
    if ok.sum() < 3 or np.ptp(t[ok]) <= 0:
        return None
    slope = float(np.polyfit(t[ok], x[ok], 1)[0])
    if slope == 0.0:
        return None
    lead = math.copysign(1.0, slope)
    margin = abs(slope) * float(np.median(np.diff(np.sort(t[ok]))))
    if image_width_mm is not None:
        lo, hi = 0.0, float(image_width_mm)
    else:
        lo, hi = float(np.min(x[ok])), float(np.max(x[ok]))
    rear = x - lead * block_length_mm
    full = ok & (np.minimum(x, rear) > lo + margin) & (np.maximum(x, rear) < hi - margin)
    if not full.any():
        return None
    return set(ftab.loc[full, "frame"].astype(int))


def drywet_inputs(measured: MeasuredContact) -> dict[str, Any]:
    """Inputs of the dry/wet model set by a contact measurement.

    Parameters
    ----------
    measured : MeasuredContact

    Returns
    -------
    dict
        ``geometry`` (for :func:`~friction_model.contact.drywet.friction_table` /
        :func:`~friction_model.contact.drywet.simulate_block`) and the condition fields the
        measurement fixes: ``contact_fraction`` (the measured real contact fraction, used
        instead of the model's pressure law) and, with a known normal force,
        ``pressure_Pa`` (nominal). The model's local pressure
        ``p_nom L w / (phi sum l_i w)`` then equals the measured ``F_N / A_real``.

    Examples
    --------
    >>> from friction_model.geometry import reference_block
    >>> m = MeasuredContact(reference_block("G0"), 0.7, 0.0, np.array([0.7]), 0.7, 80.0,
    ...                     1120.0, 400.0, 2.5e5, 357142.9, 10)
    >>> sorted(drywet_inputs(m))
    ['contact_fraction', 'geometry', 'pressure_Pa']
    """
    out: dict[str, Any] = {
        "geometry": measured.geometry,
        "contact_fraction": float(min(max(measured.contact_fraction, 1e-6), 1.0)),
    }
    if measured.nominal_pressure_Pa is not None:
        out["pressure_Pa"] = float(measured.nominal_pressure_Pa)
    return out


# -- lever arm -------------------------------------------------------------------------------
def lever_arm_eq_5_21(
    phi_rad: np.ndarray | float,
    *,
    length_m: float,
    e1: float,
    e2_per_rad: float,
    e3_m: float,
    e4_m: float,
) -> np.ndarray | float:
    """Lever arm e(phi) of Eq. 5.21 (phi >= 0) and Eq. 5.22 (phi < 0), m.

    ``e = sgn(phi) [l/4 - e3 + arctan(-e1 + e2 |phi|) (l/2 - e4) / pi]``; the exact form,
    without the smoothing of the sign switch that :func:`friction_model.dynamics.lever_arm`
    applies over ``lever_arm_smoothing_rad``.

    Parameters
    ----------
    phi_rad : float or ndarray
        Deflection angle, rad (positive: tip trailing, friction-driven).
    length_m : float
        Element length l in the sliding direction, m.
    e1, e2_per_rad, e3_m, e4_m : float
        Parameters of Eq. 5.21.

    Returns
    -------
    float or ndarray
        e, m, positive towards the leading edge.

    Examples
    --------
    >>> e = lever_arm_eq_5_21(np.radians([5.0, 60.0]), length_m=4.55e-3, e1=12.0,
    ...                       e2_per_rad=28.0, e3_m=2.133e-4, e4_m=3.234e-4)
    >>> np.round(e * 1e3, 2).tolist()  # Fig. 5.12 a: ~0 below 10 deg, ~1.9 mm beyond 40 deg
    [0.01, 1.86]
    """
    phi = np.asarray(phi_rad, dtype=float)
    mag = (
        0.25 * length_m
        - e3_m
        + np.arctan(-e1 + e2_per_rad * np.abs(phi)) / math.pi * (0.5 * length_m - e4_m)
    )
    out = np.where(phi < 0, -mag, mag)
    return float(out) if out.ndim == 0 else out


def lever_arm_observations(
    elements: pd.DataFrame | str | os.PathLike[str],
    *,
    geometry: BlockGeometry,
    sliding_direction: str,
    method: str = "front_peak",
    frames: tuple[int, ...] | None = None,
) -> pd.DataFrame:
    """Measured lever arm e and deflection angle per frame and element.

    Parameters
    ----------
    elements : pandas.DataFrame or path-like
        ``elements.csv`` of the pipeline: ``frame, time_s, element, front_edge_x_mm,
        front_peak_x_mm, contact_length_mm, deflection_angle_deg``.
    geometry : BlockGeometry
        Element lengths l_i.
    sliding_direction : {"left", "right"}
        Direction the block moves in the image.
    method : {"front_peak", "contact_centroid"}
        ``"front_peak"``: e is the position of the front pressure peak relative to the face
        centre, ``e = l_i/2 - s (x_peak - x_front)`` with ``s`` the leading direction in x
        (the face centre lies ``l_i/2`` behind the leading edge of the face, where the
        contact starts). ``"contact_centroid"``: the centroid of a uniform pressure over the
        measured contact, ``e = (l_i - L_c) / 2``.
    frames : tuple of int, optional
        Use only these frames (e.g. :attr:`MeasuredContact.frames`).

    Returns
    -------
    pandas.DataFrame
        ``frame, element, phi_rad, lever_arm_m``; rows without contact or without a finite
        deflection angle are dropped.

    Raises
    ------
    ValueError
        Missing columns (naming the file) or an unknown ``sliding_direction``/``method``.
    """
    tab, src = _as_table("elements", elements)
    if sliding_direction not in ("left", "right"):
        raise ValueError(f"sliding_direction must be 'left' or 'right', got {sliding_direction!r}")
    need = {
        "front_peak": ("front_edge_x_mm", "front_peak_x_mm"),
        "contact_centroid": ("contact_length_mm",),
    }
    if method not in need:
        raise ValueError(f"method must be one of {sorted(need)}, got {method!r}")
    _require(tab, ("frame", "element", "deflection_angle_deg", *need[method]), src)
    tab = tab[(tab["element"] >= 0) & (tab["element"] < geometry.n_elements)]
    if frames is not None:
        tab = tab[tab["frame"].isin(frames)]
    ell = geometry.element_lengths[tab["element"].astype(int).to_numpy()]
    if method == "front_peak":
        lead = -1.0 if sliding_direction == "left" else 1.0
        behind = lead * (
            pd.to_numeric(tab["front_edge_x_mm"], errors="coerce")
            - pd.to_numeric(tab["front_peak_x_mm"], errors="coerce")
        )
        e_mm = 0.5 * ell - behind.to_numpy(float)
    else:
        lc = pd.to_numeric(tab["contact_length_mm"], errors="coerce").to_numpy(float)
        e_mm = np.where(lc > 0, 0.5 * (ell - lc), np.nan)
    phi = np.radians(pd.to_numeric(tab["deflection_angle_deg"], errors="coerce").to_numpy(float))
    out = pd.DataFrame(
        {
            "frame": tab["frame"].astype(int).to_numpy(),
            "element": tab["element"].astype(int).to_numpy(),
            "phi_rad": phi,
            "lever_arm_m": e_mm * 1e-3,
        }
    )
    return out[np.isfinite(out["phi_rad"]) & np.isfinite(out["lever_arm_m"])].reset_index(drop=True)


@dataclass(frozen=True)
class LeverArmFit:
    """Eq. 5.21/5.22 fitted to measured lever arms (:func:`fit_lever_arm`).

    Attributes
    ----------
    e1, e2_per_rad, e3_m, e4_m : float
        The parameters (dimensionless, 1/rad, m, m).
    element_length_m : float
        Element length l the parameters belong to, m.
    stderr, ci_low, ci_high : dict of str to float
        Standard errors and confidence limits (Jacobian covariance scaled by the residual
        variance, Student-t quantile); inf/-inf when the data do not determine a parameter.
    level : float
        Confidence level.
    cov : (4, 4) ndarray
        Covariance in the order e1, e2_per_rad, e3_m, e4_m.
    rmse_m : float
        Root-mean-square residual, m.
    n_points, dof : int
    """

    e1: float
    e2_per_rad: float
    e3_m: float
    e4_m: float
    element_length_m: float
    stderr: dict[str, float]
    ci_low: dict[str, float]
    ci_high: dict[str, float]
    level: float
    cov: np.ndarray = field(repr=False)
    rmse_m: float = 0.0
    n_points: int = 0
    dof: int = 0

    @property
    def params(self) -> dict[str, float]:
        """``e1, e2_per_rad, e3_m, e4_m``."""
        return {k: float(getattr(self, k)) for k in LEVER_ARM_PARAMS}

    def __call__(self, phi_rad: np.ndarray | float) -> np.ndarray | float:
        """e(phi) of the fit, m (Eq. 5.21/5.22)."""
        return lever_arm_eq_5_21(phi_rad, length_m=self.element_length_m, **self.params)

    def timoshenko_kwargs(self) -> dict[str, float]:
        """Keyword arguments of :class:`~friction_model.dynamics.TimoshenkoParams`.

        ``e1, e2_per_rad, e3_m, e4_m`` and ``length_m`` (the element length they belong to).
        """
        return {**self.params, "length_m": self.element_length_m}

    def to_dict(self, *, observation: str | None = None) -> dict[str, Any]:
        """The ``lever_arm`` section of the parameter file."""
        out: dict[str, Any] = {
            **self.params,
            "element_length_m": self.element_length_m,
            "stderr": dict(self.stderr),
            "ci_low": dict(self.ci_low),
            "ci_high": dict(self.ci_high),
            "confidence_level": self.level,
            "rmse_m": self.rmse_m,
            "n_points": self.n_points,
        }
        if observation is not None:
            out["observation"] = observation
        return out


def _lever_arm_data(
    phi_rad: np.ndarray, lever_arm_m: np.ndarray, sigma_m: np.ndarray | float | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Finite angle and lever-arm pairs, their weights ``1 / sigma``, and whether sigma is given.

    Raises ValueError for mismatched lengths, a bad ``sigma_m`` or fewer than 5 finite pairs.
    """
    phi = np.asarray(phi_rad, dtype=float).ravel()
    e = np.asarray(lever_arm_m, dtype=float).ravel()
    if phi.shape != e.shape:
        raise ValueError(
            f"phi_rad and lever_arm_m must have the same length, got {phi.size} and {e.size}"
        )
    ok = np.isfinite(phi) & np.isfinite(e)
    if sigma_m is None:
        w = np.ones_like(phi)
        absolute = False
    else:
        s = np.broadcast_to(np.asarray(sigma_m, dtype=float), phi.shape)
        if np.any(~np.isfinite(s[ok])) or np.any(s[ok] <= 0):
            raise ValueError("sigma_m must be finite and > 0")
        w = 1.0 / s
        absolute = True
    phi, e, w = phi[ok], e[ok], w[ok]
    if phi.size < 5:
        raise ValueError(f"fit_lever_arm needs at least 5 finite points, got {phi.size}")
    return phi, e, w, absolute


def _lever_arm_start(
    a_abs: np.ndarray, e_abs: np.ndarray, w: np.ndarray, ell: float
) -> tuple[np.ndarray, float]:
    """Starting e1..e4: a grid over (e1, e2) with (a, b) by weighted linear least squares.

    Returns the start and its e2 (which sets the scale of e2 in the refinement).
    """
    best = (np.inf, 0.0, 1.0, 0.0, 0.0)
    phi_max = max(float(a_abs.max()), 1e-3)
    for e2 in np.geomspace(0.3 / phi_max, 300.0 / phi_max, 41):
        for e1 in np.linspace(-5.0, 40.0, 46):
            g = np.arctan(-e1 + e2 * a_abs) / math.pi
            X = np.stack([np.ones_like(g), g], axis=1) * w[:, None]
            coef, *_ = np.linalg.lstsq(X, e_abs * w, rcond=None)
            sse = float(np.sum((X @ coef - e_abs * w) ** 2))
            if sse < best[0]:
                best = (sse, e1, e2, float(coef[0]), float(coef[1]))
    _, e1_0, e2_0, a0, b0 = best
    return np.array([e1_0, e2_0, 0.25 * ell - a0, 0.5 * ell - b0]), e2_0


def fit_lever_arm(
    phi_rad: np.ndarray,
    lever_arm_m: np.ndarray,
    *,
    element_length_m: float,
    sigma_m: np.ndarray | float | None = None,
    level: float = 0.95,
) -> LeverArmFit:
    """Identify e1..e4 of Eq. 5.21/5.22 from measured lever arms against deflection angle.

    Eq. 5.21 is linear in ``a = l/4 - e3`` and ``b = l/2 - e4`` for fixed e1, e2: a grid
    over (e1, e2) with (a, b) solved exactly gives the starting values, then
    trust-region least squares refines all four within the bounds of
    :class:`~friction_model.dynamics.TimoshenkoParams` (``e2 >= 0``,
    ``|e3|, |e4| <= l/2``). Observations at phi < 0 enter through Eq. 5.22 (odd
    symmetry). Standard errors from the Jacobian covariance ``s^2 (J^T J)^-1``
    (``s^2`` the residual variance unless ``sigma_m`` is given), intervals with the
    Student-t quantile of ``dof = n - 4``.

    Parameters
    ----------
    phi_rad : (N,) array_like
        Deflection angles, rad.
    lever_arm_m : (N,) array_like
        Measured lever arms, m (positive towards the leading edge).
    element_length_m : float
        Element length l, m.
    sigma_m : float or (N,) array_like, optional
        1-sigma errors of the lever arms, m (absolute); default: estimated from the residuals.
    level : float
        Confidence level of the intervals, in (0, 1).

    Returns
    -------
    LeverArmFit

    Raises
    ------
    ValueError
        Fewer than 5 finite points, mismatched shapes or bad options.

    Warns
    -----
    UserWarning
        When the data cannot determine the parameters separately (e.g. no angles in the
        transition of the arctan): their standard errors are inf.

    Examples
    --------
    >>> phi = np.radians(np.linspace(0.0, 60.0, 61))
    >>> true = dict(e1=12.0, e2_per_rad=28.0, e3_m=2.133e-4, e4_m=3.234e-4)
    >>> fit = fit_lever_arm(phi, lever_arm_eq_5_21(phi, length_m=4.55e-3, **true),
    ...                     element_length_m=4.55e-3)
    >>> round(fit.e1, 3), round(fit.e2_per_rad, 3)
    (12.0, 28.0)
    """
    if not (math.isfinite(element_length_m) and element_length_m > 0):
        raise ValueError(f"element_length_m must be a finite number > 0, got {element_length_m=}")
    if not 0.0 < level < 1.0:
        raise ValueError(f"level must lie in (0, 1), got {level=}")
    phi, e, w, absolute = _lever_arm_data(phi_rad, lever_arm_m, sigma_m)
    n = phi.size
    sgn = np.where(phi < 0, -1.0, 1.0)
    a_abs, e_abs = np.abs(phi), sgn * e  # Eq. 5.22: e(-phi) = -e(phi)
    ell = float(element_length_m)
    half = 0.5 * ell
    x0, e2_0 = _lever_arm_start(a_abs, e_abs, w, ell)
    lo = np.array([-1e3, 0.0, -half, -half])
    hi = np.array([1e3, 1e4, half, half])
    x0 = np.clip(x0, lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo))

    def resid(x: np.ndarray) -> np.ndarray:
        mag = 0.25 * ell - x[2] + np.arctan(-x[0] + x[1] * a_abs) / math.pi * (half - x[3])
        return w * (mag - e_abs)

    scale = np.array([1.0, max(e2_0, 1.0), ell, ell])
    res = least_squares(
        resid, x0, bounds=(lo, hi), x_scale=scale, xtol=1e-12, ftol=1e-12, gtol=1e-12
    )
    x = res.x
    r = resid(x)
    dof = n - 4
    chi2 = float(np.sum(r**2))
    scale_cov = 1.0 if absolute else chi2 / max(dof, 1)
    cov, se = covariance_with_stderr(
        res.jac,
        scale=scale_cov,
        names=LEVER_ARM_PARAMS,
        undetermined="fit_lever_arm: the data do not determine e1..e4 separately (angles should "
        "span the rise of the lever arm); standard errors set to inf",
    )
    q = float(stats.t.ppf(0.5 + 0.5 * level, max(dof, 1)))
    names = LEVER_ARM_PARAMS
    raw_e = r / w
    return LeverArmFit(
        e1=float(x[0]),
        e2_per_rad=float(x[1]),
        e3_m=float(x[2]),
        e4_m=float(x[3]),
        element_length_m=ell,
        stderr={k: float(s) for k, s in zip(names, se, strict=True)},
        ci_low={k: float(v - q * s) for k, v, s in zip(names, x, se, strict=True)},
        ci_high={k: float(v + q * s) for k, v, s in zip(names, x, se, strict=True)},
        level=float(level),
        cov=cov,
        rmse_m=float(np.sqrt(np.mean(raw_e**2))),
        n_points=int(n),
        dof=int(dof),
    )
