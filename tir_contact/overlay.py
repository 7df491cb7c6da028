"""Overlay images: the analysis drawn over the frame, to check the segmentation at a glance.

TIR view: the lit zone's outline (cyan), contact contours (green), element labels (element
0 leads), the front-edge pressure peak of each element as a band (magenta, its measured
width) and the leading edge (yellow). Side view: each element's fitted centreline chord from
root to ice (green) with its angle, the ice line (cyan).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import cv2
import numpy as np
import pandas as pd

__all__ = ["draw_side_overlay", "draw_tir_overlay", "to_display"]

_GREEN = (60, 220, 60)
_MAGENTA = (220, 60, 220)
_YELLOW = (40, 220, 240)
_CYAN = (230, 200, 40)
_WHITE = (255, 255, 255)


def to_display(frame: np.ndarray, max_dn: float | None = None) -> np.ndarray:
    """Grey frame to an 8-bit BGR image, stretched to its bit depth.

    Parameters
    ----------
    frame : (M, N) ndarray
        Grey frame, uint8 or uint16.
    max_dn : float, optional
        Full-scale value; the frame's dtype maximum for uint8, else its largest value.

    Returns
    -------
    (M, N, 3) ndarray of uint8

    Examples
    --------
    >>> to_display(np.array([[0, 4095]], np.uint16), max_dn=4095)[0, :, 0].tolist()
    [0, 255]
    """
    if max_dn is None:
        max_dn = 255.0 if frame.dtype == np.uint8 else float(max(frame.max(), 1))
    grey = np.clip(frame.astype(np.float32) * (255.0 / max_dn), 0, 255).astype(np.uint8)
    return cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)


def _scale_up(img: np.ndarray, min_height: int = 256) -> tuple[np.ndarray, int]:
    k = max(1, int(np.ceil(min_height / img.shape[0])))
    if k > 1:
        img = cv2.resize(img, None, fx=k, fy=k, interpolation=cv2.INTER_NEAREST)
    return img, k


def draw_tir_overlay(
    frame: np.ndarray,
    mask: np.ndarray,
    elements: pd.DataFrame,
    frame_row: Mapping[str, Any],
    *,
    mm_per_px: float,
    max_dn: float | None = None,
    label: str = "",
    lit: np.ndarray | None = None,
) -> np.ndarray:
    """Draw a TIR frame's contact analysis over the frame.

    Parameters
    ----------
    frame : (M, N) ndarray
        The grey frame.
    mask : (M, N) ndarray of bool
        Contact pixels.
    elements : pandas.DataFrame
        The frame's element rows (``element, front_edge_x_mm, front_peak_x_mm,
        front_peak_width_mm``).
    frame_row : mapping
        The frame's row of ``frames.csv`` (``front_peak_x_mm``, ``contact_area_mm2`` and,
        written beside it, its error bar ``contact_area_low_mm2``-``_high_mm2``).
    mm_per_px : float
        Image scale, mm per pixel.
    max_dn : float, optional
        Full scale of the frame (see :func:`to_display`).
    label : str
        Text written in the top-left corner.
    lit : (M, N) ndarray of bool, optional
        The lit zone, outlined.

    Returns
    -------
    (M', N', 3) ndarray of uint8
        BGR image, enlarged by an integer factor to at least 256 rows.
    """
    img, k = _scale_up(to_display(frame, max_dn))
    h = img.shape[0]
    size = (img.shape[1], h)
    if lit is not None and not lit.all():
        big = cv2.resize(lit.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST)
        contours, _ = cv2.findContours(big, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        cv2.drawContours(img, contours, -1, _CYAN, 1)
    big = cv2.resize(mask.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST)
    contours, _ = cv2.findContours(big, cv2.RETR_LIST, cv2.CHAIN_APPROX_SIMPLE)
    cv2.drawContours(img, contours, -1, _GREEN, 1)
    for row in elements.itertuples(index=False):
        peak = getattr(row, "front_peak_x_mm", np.nan)
        width = getattr(row, "front_peak_width_mm", np.nan)
        edge = getattr(row, "front_edge_x_mm", np.nan)
        if np.isfinite(peak):
            half = 0.5 * (width if np.isfinite(width) else mm_per_px)
            x0 = round((peak - half) / mm_per_px * k)
            x1 = max(round((peak + half) / mm_per_px * k), x0 + 1)
            band = img[:, x0:x1]
            band[...] = (0.6 * band + 0.4 * np.array(_MAGENTA)).astype(np.uint8)
        if np.isfinite(edge):
            x = round(edge / mm_per_px * k)
            cv2.line(img, (x, 0), (x, h - 1), _YELLOW, 1)
            cv2.putText(
                img, str(int(row.element)), (x + 3, h - 8), cv2.FONT_HERSHEY_SIMPLEX, 0.5,
                _WHITE, 1, cv2.LINE_AA,
            )
    area = frame_row.get("contact_area_mm2", np.nan)
    low = frame_row.get("contact_area_low_mm2", np.nan)
    high = frame_row.get("contact_area_high_mm2", np.nan)
    text = f"{label}  area {area:.1f} mm2" if np.isfinite(area) else label
    if np.isfinite(area) and np.isfinite(low) and np.isfinite(high):
        text += f" ({low:.1f}-{high:.1f})"  # the error bar
    cv2.putText(img, text, (5, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.5, _WHITE, 1, cv2.LINE_AA)
    return img


def draw_side_overlay(
    frame: np.ndarray,
    elements: pd.DataFrame,
    lines: Mapping[int, tuple[tuple[float, float], tuple[float, float]]],
    *,
    ice_y_px: float | None = None,
    max_dn: float | None = None,
    label: str = "",
) -> np.ndarray:
    """Draw a side-view frame's element chords over the frame.

    Parameters
    ----------
    frame : (M, N) ndarray
        The grey frame.
    elements : pandas.DataFrame
        The frame's element rows (``element, deflection_angle_deg``).
    lines : mapping
        Element index to its chord ``((x_root, y_root), (x_tip, y_tip))`` in pixels.
    ice_y_px : float, optional
        Row of the ice surface line.
    max_dn : float, optional
        Full scale of the frame.
    label : str
        Text written in the top-left corner.

    Returns
    -------
    (M', N', 3) ndarray of uint8
    """
    img, k = _scale_up(to_display(frame, max_dn))
    if ice_y_px is not None and np.isfinite(ice_y_px):
        y = round((ice_y_px + 0.5) * k)
        cv2.line(img, (0, y), (img.shape[1] - 1, y), _CYAN, 1)
    angles = dict(zip(elements["element"], elements["deflection_angle_deg"], strict=False))
    for element, ((x0, y0), (x1, y1)) in lines.items():
        if not all(np.isfinite([x0, y0, x1, y1])):
            continue
        p0 = (round((x0 + 0.5) * k), round((y0 + 0.5) * k))
        p1 = (round((x1 + 0.5) * k), round((y1 + 0.5) * k))
        cv2.line(img, p0, p1, _GREEN, 1, cv2.LINE_AA)
        angle = angles.get(element, np.nan)
        text = f"{element}: {angle:.1f} deg" if np.isfinite(angle) else str(element)
        cv2.putText(img, text, (p1[0] + 3, p1[1] - 4), cv2.FONT_HERSHEY_SIMPLEX, 0.4, _WHITE, 1)
    cv2.putText(img, label, (5, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.5, _WHITE, 1, cv2.LINE_AA)
    return img
