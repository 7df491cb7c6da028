"""Segmentation of real contact in flat-field-normalised TIR frames.

Method: a pixel is contact where its darkness ``D`` (see :func:`tir_contact.calibrate.darkness`)
reaches half the contact contrast, the level at which a pixel on a contact edge is half
covered. The contrast is the median darkness of clearly dark pixels (``D > min_darkness``)
of the frame, or a value given by the user. Regions smaller than ``min_area_px`` are
dropped (noise, dust), and the rest are labelled as 8-connected regions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = ["FrameContact", "estimate_contrast", "segment_frame"]


def estimate_contrast(d: np.ndarray, *, min_darkness: float = 0.25) -> float:
    """Contact contrast of a frame: the median darkness of pixels darker than ``min_darkness``.

    Parameters
    ----------
    d : (M, N) ndarray of float
        Darkness (NaN for excluded pixels).
    min_darkness : float
        Darkness above which a pixel is surely contact, not noise (0.25 is well above the
        free-surface noise of a TIR image and well below the contact contrast).

    Returns
    -------
    float
        The contrast, or NaN when no pixel is that dark (no contact in the frame).

    Examples
    --------
    >>> round(estimate_contrast(np.array([[0.0, 0.8], [0.9, 0.02]])), 6)
    0.85
    """
    dark = d[np.isfinite(d) & (d > min_darkness)]
    return float(np.median(dark)) if dark.size else float("nan")


@dataclass(frozen=True)
class FrameContact:
    """Contact found in one frame.

    Attributes
    ----------
    mask : (M, N) ndarray of bool
        Contact pixels.
    labels : (M, N) ndarray of int32
        Region label per pixel (0 = no contact).
    regions : pandas.DataFrame
        One row per region: ``label, area_px, centroid_x_px, centroid_y_px, bbox_x0_px,
        bbox_y0_px, bbox_width_px, bbox_height_px, mean_darkness``.
    threshold : float
        Darkness threshold used (NaN when the frame has no contact).
    """

    mask: np.ndarray
    labels: np.ndarray
    regions: pd.DataFrame
    threshold: float

    @property
    def area_px(self) -> int:
        """Total contact area, px."""
        return int(self.mask.sum())


_REGION_COLUMNS = [
    "label",
    "area_px",
    "centroid_x_px",
    "centroid_y_px",
    "bbox_x0_px",
    "bbox_y0_px",
    "bbox_width_px",
    "bbox_height_px",
    "mean_darkness",
]


def segment_frame(
    d: np.ndarray,
    *,
    contrast: float | None = None,
    min_darkness: float = 0.25,
    min_area_px: int = 4,
) -> FrameContact:
    """Segment the real contact in one normalised frame.

    Parameters
    ----------
    d : (M, N) ndarray of float
        Darkness, 0 on the free surface (NaN where excluded).
    contrast : float, optional
        Contact contrast; estimated from the frame (:func:`estimate_contrast`) when
        omitted. The threshold is ``contrast / 2``.
    min_darkness : float
        See :func:`estimate_contrast`; also the lowest threshold used.
    min_area_px : int
        Regions smaller than this (px) are dropped.

    Returns
    -------
    FrameContact

    Notes
    -----
    Pixel coordinates: x to the right, y down, origin at the top-left pixel's centre.

    Examples
    --------
    >>> d = np.zeros((6, 8)); d[1:4, 2:6] = 0.8
    >>> segment_frame(d).area_px
    12
    """
    import cv2

    if d.ndim != 2:
        raise ValueError(f"d must be a 2-D image, got shape {d.shape}")
    if min_area_px < 1:
        raise ValueError(f"min_area_px must be >= 1, got min_area_px={min_area_px!r}")
    c = estimate_contrast(d, min_darkness=min_darkness) if contrast is None else float(contrast)
    empty = np.zeros(d.shape, bool)
    if not np.isfinite(c):
        return FrameContact(
            empty, np.zeros(d.shape, np.int32), pd.DataFrame(columns=_REGION_COLUMNS), np.nan
        )
    threshold = max(0.5 * c, 0.5 * min_darkness)
    raw = np.nan_to_num(d, nan=0.0) >= threshold
    n, labels, stats, centroids = cv2.connectedComponentsWithStats(
        raw.astype(np.uint8), connectivity=8
    )
    keep = np.zeros(n, bool)
    keep[1:] = stats[1:, cv2.CC_STAT_AREA] >= min_area_px
    remap = np.zeros(n, np.int32)
    remap[keep] = np.arange(1, keep.sum() + 1)
    labels = remap[labels]
    mask = labels > 0
    idx = np.flatnonzero(keep)
    sums = np.bincount(labels.ravel(), weights=np.nan_to_num(d, nan=0.0).ravel(),
                       minlength=len(idx) + 1)
    regions = pd.DataFrame(
        {
            "label": np.arange(1, len(idx) + 1),
            "area_px": stats[idx, cv2.CC_STAT_AREA],
            "centroid_x_px": centroids[idx, 0],
            "centroid_y_px": centroids[idx, 1],
            "bbox_x0_px": stats[idx, cv2.CC_STAT_LEFT],
            "bbox_y0_px": stats[idx, cv2.CC_STAT_TOP],
            "bbox_width_px": stats[idx, cv2.CC_STAT_WIDTH],
            "bbox_height_px": stats[idx, cv2.CC_STAT_HEIGHT],
            "mean_darkness": sums[1:] / np.maximum(stats[idx, cv2.CC_STAT_AREA], 1),
        },
        columns=_REGION_COLUMNS,
    )
    return FrameContact(mask, labels, regions, threshold)
