"""Segmentation of real contact in flat-field-normalised TIR frames.

Method: a pixel is contact where its darkness ``D`` (see :func:`tir_contact.flatfield.darkness`)
reaches half the contact contrast, the level at which a pixel on a contact edge is half
covered. The contrast is the median darkness of clearly dark pixels (``D > min_darkness``)
of the frame, or a value given by the user. Regions smaller than ``min_area_px`` are
dropped (noise, dust), and the rest are labelled as 8-connected regions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import cv2
import numpy as np
import pandas as pd
from scipy import ndimage

__all__ = [
    "FrameContact",
    "contact_box",
    "estimate_contrast",
    "label_contact",
    "region_arrays",
    "region_table",
    "segment_frame",
]


def estimate_contrast(d: np.ndarray, *, min_darkness: float | np.ndarray = 0.25) -> float:
    """Contact contrast of a frame: the median darkness of pixels darker than ``min_darkness``.

    Parameters
    ----------
    d : (M, N) ndarray of float
        Darkness (NaN for excluded pixels).
    min_darkness : float or (M, N) ndarray
        Darkness above which a pixel is surely contact, not noise (0.25 is well above the
        free-surface noise of a TIR image and well below the contact contrast); per pixel
        where the noise varies over the image.

    Returns
    -------
    float
        The contrast, or NaN when no pixel is that dark (no contact in the frame).

    Examples
    --------
    >>> round(estimate_contrast(np.array([[0.0, 0.8], [0.9, 0.02]])), 6)
    0.85
    """
    with np.errstate(invalid="ignore"):
        dark = d[d > min_darkness]  # NaN compares False; only +inf is left to drop
    if dark.size and not math.isfinite(np.add.reduce(dark, dtype=np.float64)):
        dark = dark[np.isfinite(dark)]
    # `dark` is a fresh copy: the median may partition it in place (same order statistics)
    return float(np.median(dark, overwrite_input=True)) if dark.size else float("nan")


@dataclass(frozen=True)
class FrameContact:
    """Contact found in one frame.

    Attributes
    ----------
    shape : (int, int)
        Shape of the frame.
    threshold : float
        Darkness threshold used (NaN when the frame has no contact).
    n_regions : int
        Number of contact regions.
    darkness : (M, N) ndarray of float, optional
        The darkness the contact was segmented from (for the regions' mean darkness).
    box : (slice, slice) or None
        Rows and columns of the frame that hold all contact (None without contact).
    box_labels : ndarray of int32 or None
        Region labels inside `box` (0 = no contact), numbered 1..n_regions in scan order.
    known_counts : (ndarray, ndarray) or None
        :attr:`line_counts`, when known already.

    Notes
    -----
    The full-frame :attr:`mask` and :attr:`labels` and the per-region table
    :attr:`regions` are built on first access, so a pipeline that needs only the box, the
    per-column counts and the region count does not pay for them.
    """

    shape: tuple[int, int]
    threshold: float
    n_regions: int = 0
    darkness: np.ndarray | None = field(default=None, repr=False)
    box: tuple[slice, slice] | None = None
    box_labels: np.ndarray | None = field(default=None, repr=False)
    known_counts: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False,
                                                              compare=False)

    @cached_property
    def labels(self) -> np.ndarray:
        """(M, N) ndarray of int32: region label per pixel, 0 for no contact."""
        labels = np.zeros(self.shape, np.int32)
        if self.box is not None:
            labels[self.box] = self.box_labels
        return labels

    @cached_property
    def mask(self) -> np.ndarray:
        """(M, N) ndarray of bool: contact pixels."""
        mask = np.zeros(self.shape, bool)
        if self.box is not None:
            mask[self.box] = self.box_labels > 0
        return mask

    @cached_property
    def line_counts(self) -> tuple[np.ndarray, np.ndarray]:
        """Contact pixels per column, (N,) ndarray of int32, and per row, (M,) ndarray of int32.

        :func:`label_contact` gives them (``known_counts``) when it knows the counts of its
        input and drops no region; otherwise they are summed from :attr:`box_labels` on first
        access.
        """
        if self.known_counts is not None:
            return self.known_counts
        n_rows, n_cols = self.shape
        cols = np.zeros(n_cols, np.int32)
        rows = np.zeros(n_rows, np.int32)
        if self.box is None:
            return cols, rows
        r, c = self.box
        m8 = (self.box_labels > 0).view(np.uint8)
        cols[c] = cv2.reduce(m8, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
        rows[r] = cv2.reduce(m8, 1, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
        return cols, rows

    @property
    def area_px(self) -> int:
        """Total contact area, px."""
        return 0 if self.box is None else int(np.count_nonzero(self.box_labels))

    def region_arrays(self) -> dict[str, np.ndarray]:
        """The columns of :attr:`regions` as arrays (see :func:`region_arrays`)."""
        if self.box is None:
            return region_arrays(np.zeros((0, 0), np.int32), 0)
        rows, cols = self.box
        d = None if self.darkness is None else self.darkness[rows, cols]
        out = region_arrays(self.box_labels, self.n_regions, d)
        for key in ("centroid_x_px", "bbox_x0_px"):
            out[key] += cols.start
        for key in ("centroid_y_px", "bbox_y0_px"):
            out[key] += rows.start
        return out

    @cached_property
    def regions(self) -> pd.DataFrame:
        """One row per region: ``label, area_px, centroid_x_px, centroid_y_px, bbox_x0_px,
        bbox_y0_px, bbox_width_px, bbox_height_px, mean_darkness``."""
        return pd.DataFrame(self.region_arrays(), columns=_REGION_COLUMNS)


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


def region_arrays(
    labels: np.ndarray, n_regions: int, d: np.ndarray | None = None
) -> dict[str, np.ndarray]:
    """Columns of :func:`region_table` as arrays (no DataFrame is built).

    Examples
    --------
    >>> lab = np.zeros((4, 5), np.int32); lab[1:3, 1:4] = 1
    >>> region_arrays(lab, 1)["area_px"].tolist()
    [6.0]
    """
    if n_regions == 0:
        return {c: np.zeros(0) for c in _REGION_COLUMNS}
    flat = labels.ravel()
    on = np.flatnonzero(flat)
    lab = flat[on]
    ys, xs = np.divmod(on, labels.shape[1])
    m = n_regions + 1
    area = np.bincount(lab, minlength=m)[1:].astype(float)
    if d is not None:
        mean_d = np.bincount(lab, weights=d.ravel()[on], minlength=m)[1:] / area
    else:
        mean_d = np.full(n_regions, np.nan)
    boxes = ndimage.find_objects(labels, max_label=n_regions)
    return {
        "label": np.arange(1, n_regions + 1),
        "area_px": area,
        "centroid_x_px": np.bincount(lab, weights=xs, minlength=m)[1:] / area,
        "centroid_y_px": np.bincount(lab, weights=ys, minlength=m)[1:] / area,
        "bbox_x0_px": np.array([b[1].start for b in boxes], float),
        "bbox_y0_px": np.array([b[0].start for b in boxes], float),
        "bbox_width_px": np.array([b[1].stop - b[1].start for b in boxes], float),
        "bbox_height_px": np.array([b[0].stop - b[0].start for b in boxes], float),
        "mean_darkness": mean_d,
    }


def region_table(labels: np.ndarray, n_regions: int, d: np.ndarray | None = None) -> pd.DataFrame:
    """Area, centroid, bounding box and mean darkness of each labelled region.

    Parameters
    ----------
    labels : (M, N) ndarray of int
        Region labels 1..n_regions, 0 for background.
    n_regions : int
        Number of regions.
    d : (M, N) ndarray of float, optional
        Darkness, for ``mean_darkness`` (NaN without it).

    Returns
    -------
    pandas.DataFrame
        Columns ``label, area_px, centroid_x_px, centroid_y_px, bbox_x0_px, bbox_y0_px,
        bbox_width_px, bbox_height_px, mean_darkness``; pixel centres at integer
        coordinates.

    Examples
    --------
    >>> lab = np.zeros((4, 5), np.int32); lab[1:3, 1:4] = 1
    >>> region_table(lab, 1)[["area_px", "centroid_x_px", "bbox_width_px"]].values.tolist()
    [[6.0, 2.0, 3.0]]
    """
    return pd.DataFrame(region_arrays(labels, n_regions, d), columns=_REGION_COLUMNS)


def segment_frame(
    d: np.ndarray,
    *,
    contrast: float | None = None,
    min_darkness: float = 0.25,
    min_area_px: int = 4,
    threshold: float | None = None,
    raw: np.ndarray | None = None,
    box: tuple[slice, slice] | None = None,
    counts: tuple[np.ndarray, np.ndarray] | None = None,
) -> FrameContact:
    """Segment the real contact in one normalised frame (the analysis's step,
    :class:`tir_contact.tir_view.TirFrames`).

    Parameters
    ----------
    d : (M, N) ndarray of float
        Darkness, 0 on the free surface (NaN or 0 where excluded). The analysis passes the
        darkness computed only in the contact's box (NaN elsewhere).
    contrast : float, optional
        Contact contrast; estimated from the frame (:func:`estimate_contrast`) when
        omitted. The threshold is ``contrast / 2``.
    min_darkness : float
        See :func:`estimate_contrast`; also the lowest threshold used.
    min_area_px : int
        Regions smaller than this (px) are dropped.
    threshold : float, optional
        The darkness threshold of contact itself (the video's, as
        :meth:`tir_contact.tir_view.TirView.prepare` decides it); `contrast` and
        `min_darkness` are then not used.
    raw : (M, N) ndarray of bool, optional
        ``d >= threshold``, when already tested (the analysis tests the raw grey values,
        :class:`tir_contact._darkness.ContactTest`); needs `threshold`.
    box, counts : optional
        :func:`contact_box` of `raw` and its True pixels per column and per row, when known
        (see :func:`label_contact`).

    Returns
    -------
    FrameContact

    Notes
    -----
    Pixel coordinates: x to the right, y down, origin at the top-left pixel's centre.
    Connected components (8-connected) are labelled only inside the bounding box of the
    pixels above threshold; this is what makes the segmentation cheap on frames where the
    contact covers a small part of the image.

    Examples
    --------
    >>> d = np.zeros((6, 8)); d[1:4, 2:6] = 0.8
    >>> segment_frame(d).area_px, segment_frame(d, threshold=0.9).area_px
    (12, 0)
    """
    if d.ndim != 2:
        raise ValueError(f"d must be a 2-D image, got shape {d.shape}")
    if min_area_px < 1:
        raise ValueError(f"min_area_px must be >= 1, got min_area_px={min_area_px!r}")
    if threshold is None:
        if raw is not None:
            raise ValueError("raw needs the threshold it was tested with")
        c = estimate_contrast(d, min_darkness=min_darkness) if contrast is None else float(contrast)
        if not np.isfinite(c):
            return FrameContact(d.shape, np.nan, 0, d)
        threshold = max(0.5 * c, 0.5 * min_darkness)
    if raw is None:
        with np.errstate(invalid="ignore"):
            raw = d >= threshold  # NaN compares False: excluded pixels are never contact
    return label_contact(raw, threshold, d, min_area_px=min_area_px, box=box, counts=counts)


def contact_box(raw: np.ndarray) -> tuple[slice, slice] | None:
    """Bounding box (rows, columns) of the True pixels of `raw`, None when there is none.

    Examples
    --------
    >>> raw = np.zeros((5, 6), bool); raw[1:3, 2] = True; raw[2, 4] = True
    >>> contact_box(raw)
    (slice(1, 3, None), slice(2, 5, None))
    """
    return _box_and_counts(raw)[0]


def _box_and_counts(
    raw: np.ndarray,
) -> tuple[tuple[slice, slice] | None, tuple[np.ndarray, np.ndarray] | None]:
    """:func:`contact_box` of `raw` and its True pixels per column and per row (int32).

    The counts come from the same two sums that find the box (OpenCV's row and column
    reductions are several times faster than ``any`` along an axis); None without a box.
    """
    if raw.ndim != 2 or raw.size == 0:
        cols = raw.any(axis=0).nonzero()[0]
        if cols.size == 0:
            return None, None
        rows = raw[:, cols[0] : cols[-1] + 1].any(axis=1).nonzero()[0]
        return (slice(int(rows[0]), int(rows[-1]) + 1),
                slice(int(cols[0]), int(cols[-1]) + 1)), None
    u8 = raw.view(np.uint8) if raw.dtype == np.bool_ else (raw != 0).view(np.uint8)
    if u8.strides[1] != 1:
        u8 = np.ascontiguousarray(u8)
    col_counts = cv2.reduce(u8, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
    cols = col_counts.nonzero()[0]
    if cols.size == 0:
        return None, None
    c0, c1 = int(cols[0]), int(cols[-1]) + 1
    row_counts = cv2.reduce(u8[:, c0:c1], 1, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
    rows = row_counts.nonzero()[0]
    return (slice(int(rows[0]), int(rows[-1]) + 1), slice(c0, c1)), (col_counts, row_counts)


def _may_hold_small(sub: np.ndarray, min_area_px: int) -> bool:
    """False when no 8-connected region of the 0/1 image `sub` can be below `min_area_px`.

    Every pixel of a region of s pixels sees at most s set pixels in its 3 x 3
    neighbourhood (all of them belong to its region). So when every set pixel sees at
    least `min_area_px`, no region is smaller. A 3 x 3 box sum is about three times
    cheaper than counting the pixels of each label, and on contact images it settles
    almost every frame; otherwise the labels are counted.
    """
    if min_area_px <= 1:
        return False
    if min_area_px > 9:
        return True
    nb = cv2.boxFilter(sub, cv2.CV_8U, (3, 3), normalize=False, borderType=cv2.BORDER_CONSTANT)
    # set pixels (sub = 1) that see fewer than min_area_px, in place: 255 & 1 = 1
    _, few = cv2.threshold(nb, min_area_px - 1, 255, cv2.THRESH_BINARY_INV, dst=nb)  # nb < min
    return cv2.countNonZero(cv2.bitwise_and(few, sub, dst=few)) > 0


def label_contact(
    raw: np.ndarray,
    threshold: float,
    darkness: np.ndarray | None = None,
    *,
    min_area_px: int = 4,
    box: tuple[slice, slice] | None = None,
    counts: tuple[np.ndarray, np.ndarray] | None = None,
) -> FrameContact:
    """Drop small regions from a thresholded frame and label the rest (8-connected).

    Parameters
    ----------
    raw : (M, N) ndarray of bool
        Pixels at or above the threshold.
    threshold : float
        The darkness threshold `raw` was made with (kept in the result).
    darkness : (M, N) ndarray of float, optional
        The darkness (for the regions' mean darkness).
    min_area_px : int
        Regions smaller than this (px) are dropped.
    box : (slice, slice), optional
        :func:`contact_box` of `raw` when already known.
    counts : (ndarray, ndarray), optional
        With `box`: the True pixels of `raw` per column and per row (int32), as
        ``_box_and_counts`` gives them.

    Returns
    -------
    FrameContact

    Examples
    --------
    >>> raw = np.zeros((6, 8), bool); raw[1:4, 2:6] = True; raw[5, 7] = True
    >>> c = label_contact(raw, 0.4)
    >>> c.area_px, c.n_regions  # the single pixel is dropped
    (12, 1)
    """
    if min_area_px < 1:
        raise ValueError(f"min_area_px must be >= 1, got min_area_px={min_area_px!r}")
    if box is None:
        box, counts = _box_and_counts(raw)
    return _label_box(raw, threshold, darkness, min_area_px, box, counts)


def _label_box(
    raw: np.ndarray,
    threshold: float,
    darkness: np.ndarray | None,
    min_area_px: int,
    box: tuple[slice, slice] | None,
    counts: tuple[np.ndarray, np.ndarray] | None = None,
) -> FrameContact:
    """:func:`label_contact` with the box (and optionally the line counts of `raw`) known."""
    if box is None:
        return FrameContact(raw.shape, threshold, 0, darkness)
    sub = np.ascontiguousarray(raw[box]).view(np.uint8)
    n, lab = cv2.connectedComponents(sub, connectivity=8, ltype=cv2.CV_32S)
    n_regions = n - 1
    if n > 1 and _may_hold_small(sub, min_area_px):
        area = np.bincount(lab.ravel(), minlength=n)
        keep = area >= min_area_px
        keep[0] = False
        if not keep[1:].all():
            remap = np.zeros(n, np.int32)
            remap[keep] = np.arange(1, int(keep.sum()) + 1)
            lab = remap[lab]
            counts = None  # regions were dropped: the counts of `raw` no longer hold
        n_regions = int(keep.sum())
    if n_regions == 0:
        return FrameContact(raw.shape, threshold, 0, darkness)
    return FrameContact(raw.shape, threshold, n_regions, darkness, box, lab, counts)
