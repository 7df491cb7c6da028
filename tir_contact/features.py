"""Per-frame features of a TIR contact: elements, front-edge peak, lift-off and deflection.

The input is one flat-field-normalised frame (darkness ``D``,
:func:`tir_contact.flatfield.darkness`) and its segmentation
(:func:`tir_contact.segment.segment_frame`). The block slides along the image x axis; its
elements are strips across the image (along y) separated by the sipes.

Method
------
Everything is computed from two 1-D profiles along x, so the cost hardly grows with the image:

* ``n(c)``, the number of contact pixels in column ``c`` (mask column sums), and
* ``p(c)``, the mean darkness of column ``c`` over the rows that hold contact (all of them, not
  only the contact pixels, so that an edge column carries its partial coverage).

The sliding direction is handled by mirroring both profiles so that the block always moves
towards smaller x (the leading side is on the left); positions are mirrored back at the end.

1. *Runs*: columns with ``n(c) >= n_max / 2`` (more than half the contact rows) form contact
   runs; for graded contact (``free`` given: a field of junctions below the pixel, which
   reaches half coverage only at each face's dark front), the columns whose mean darkness
   holds contact significantly (:mod:`tir_contact.graded`), their edges at that presence
   level and their areas the unmixed darkness. A run whose first (last) column
   is the view's first (last) column is *clipped*: its edge lies at or beyond the view's
   end. The view is the image or, with ``valid``,
   the columns whose valid pixels in the contact's rows could hold a run (at least
   ``n_max / 2``): where the lit zone ends or narrows past that, the view ends.
2. *Element numbering* (needs the geometry, :class:`BlockLayout`): the element footprint
   template (element ``i`` covers ``[x0 + P_i, x0 + P_i + l_i]``, ``P_i`` the undeformed front
   of element ``i`` behind the block front, ``l_i`` its length) is matched to the runs. The
   candidate offsets ``x0`` put any element's front on the front of the first run with an
   unclipped front edge, or any element's back on the back of the first run (and the
   carrier position when the trajectory is known). Each candidate is scored by its
   mismatch with the template *clipped to the view*: a contact column outside every element
   face costs 1, a face column without contact 1/4 (a face may lose more than half its
   contact to lift-off and must still beat no face at all); the lowest score wins. Because
   the template is clipped to the view, a shift by one element leaves either an empty
   element face inside the view or contact outside the faces, so entering and leaving blocks
   (leading or trailing elements outside the view) are numbered correctly. Each run goes to
   the element it overlaps most; a run spanning a closed sipe (overlapping two element
   templates by more than a quarter of their length each) is split at the sipe's centre.
3. *Edges and length*: the front and back edges of a run are where ``p`` crosses half of the
   run's median darkness, interpolated linearly between pixel centres (for a step edge the
   error is below 0.1 px; a binary mask edge would be off by up to 0.5 px). A clipped edge is
   the view's end (step 1). ``contact_length_mm`` is
   the summed length of the element's runs inside the view (the image: as in the ground
   truth); ``front_edge_x_mm`` is the leading edge of the first run (NaN when clipped).
   For full-height strips this is the row mean of the line-wise contact length, with
   sub-pixel edges.
4. *Front-edge pressure peak*: the maximum of ``p`` over the first ``peak_window_mm`` (at most
   half) of the element's contact, refined by the parabola through the maximum column and its
   neighbours. The *plateau* is the median of ``p`` behind that window (without the back edge
   column); ``front_peak_contrast`` is the maximum column darkness minus the plateau and
   ``front_peak_width_mm`` the full width of the band above ``plateau + contrast / 2``
   (linear interpolation; NaN unless the contrast is positive). NaN when the element's front
   is clipped or the contact is shorter than 4 px.
5. *Lift-off*: ``liftoff_mm = max(0, l_i - contact_length_mm)``: 0 in full contact, the lifted
   length otherwise. NaN when the element's template or run reaches beyond the view (the
   image, or the lit zone's ends as in step 3).
6. *Deflection* (needs ``velocity_mps``, ``center_time_s``, the frame time and the geometry):
   the carrier (undeformed block) moves as the renderer's convention says, the block centre
   passing the image centre at ``center_time_s``; the undeformed front of element ``i`` in
   image x is ``x_c - s v (t - t_c) - s L/2 + s P_i`` with ``s = +1`` sliding left, ``-1``
   right, ``x_c`` the image centre and ``L`` the block length; with a camera given as
   following the carrier (``--camera follows``) the travel term is 0. The trailing displacement of
   the element's leading bottom corner, ``tip_deflection_mm = s (x_front - x_undeformed)``,
   approximates the tip deflection, and ``deflection_angle_deg = atan(tip / height_mm)``.

Block values: the area is the total contact (every contact pixel); ``block_front_x_mm``,
``front_peak_x_mm`` and ``front_peak_contrast`` are those of the leading element in contact;
``deflection_angle_deg`` and ``tip_deflection_mm`` the mean over the elements with a value.

``contact_ratio`` is the contact area over the *nominal visible area*: the element faces of
the fitted template (the undeformed faces shifted to the measured position) clipped to the
image, times the rows the contact spans (first to last row holding contact; with ``valid``,
only valid pixels of that footprint count). NaN without geometry or contact.

Without geometry (``element_lengths_mm=None``, e.g. a finger or a tyre footprint) the whole
contact is one strip (``n_elements_in_contact`` NaN: no elements to count): area, number of
regions, ``block_in_view`` (any contact),
``block_front_x_mm`` (the leading boundary of the most leading contact column, ±0.5 px) and
the front peak of the mean darkness of the contact pixels of each column are reported; the
elements table is empty.

Limits
------
* The path must run along the image x axis (no ``rotation_deg``; element edges tilted
  beyond 1.5 deg are warned about where straight front and back edges dominate the
  contact, :mod:`tir_contact.tilt`); elements must span their
  rows (strips across the view), as in a block wider than the view or a block seen whole.
* Sipes must be resolved (a gap of >= 1 column below half coverage) or the template split
  is used, which puts the split at the template's sipe centre (no sub-pixel edge there).
* Blocks longer than the view with equal elements and no trajectory cannot be numbered
  uniquely: the first candidate (front-aligned, element 0 first) is taken.
* Lift-off does not tell which end is lifted; deflection assumes the leading corner touches
  (the usual state under friction, the trailing corner lifted). The leading corner of a
  tilted face is displaced ``l/2 (1 - cos(tilt))`` more than the bottom centre, and TIR does
  not show the tilt, so the tip deflection is overestimated by that much: 0.035 mm for G3
  (10 deg tilt at 1 m/s), 0.15 mm for G7 (33 deg). The angle uses the nominal element
  height, not the compressed height nor the bending shape of the ground truth's chord; on
  the synthetic footage it is within 0.05 deg (G0), 0.43 deg (G3) and 0.85 deg (G7).
* A dark static feature of the ice that survives the flat field can merge with the contact;
  the reference (``tir_contact.flatfield``) is responsible for removing it.

Notes
-----
Image x in mm from the left image edge: pixel column ``c`` covers ``[c, c + 1) * mm_per_px``, its
centre at ``(c + 0.5) * mm_per_px`` (the convention of :mod:`synthetic.footage`). Element 0
leads in the sliding direction.

Speed: about 0.1 ms per 640 x 256 frame for :func:`tir_frame_records` (column sums by
OpenCV, the per-column and per-row contact counts taken from the segmentation, the template
scored for all candidate offsets in one numpy array, a few dozen scalar operations per
element); :func:`tir_frame_features` adds the construction of the small elements DataFrame
(a further ~0.1 ms). Batch code should call :func:`tir_frame_records` and build one
DataFrame at the end.
"""

from __future__ import annotations

import functools
import itertools
import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, NamedTuple

import cv2
import numpy as np
import pandas as pd

from friction_model.geometry import BlockGeometry
from tir_common.validate import check_positive
from tir_contact._columns import ColumnSums, column_mean
from tir_contact.graded import FreeLevel, graded_runs
from tir_contact.segment import FrameContact

__all__ = [
    "ELEMENT_DTYPE",
    "ELEMENT_FIELDS",
    "FRAME_KEYS",
    "BlockLayout",
    "ElementRow",
    "FrameFeatures",
    "tir_frame_features",
    "tir_frame_records",
]

logger = logging.getLogger(__name__)

#: Keys of :attr:`FrameFeatures.frame`, in order (``frames.csv`` adds the frame, its time
#: and the video-level flags, :data:`tir_contact.outputs.FRAME_COLUMNS`).
FRAME_KEYS = [
    "block_in_view",
    "block_front_x_mm",
    "contact_area_mm2",
    "contact_ratio",
    "n_elements_in_contact",
    "front_peak_x_mm",
    "front_peak_contrast",
    "n_regions",
    "deflection_angle_deg",
    "tip_deflection_mm",
]


class ElementRow(NamedTuple):
    """Features of one element in contact in one frame (see the module notes for each)."""

    element: int
    contact_area_mm2: float
    contact_length_mm: float
    front_edge_x_mm: float
    front_peak_x_mm: float
    front_peak_contrast: float
    liftoff_mm: float
    deflection_angle_deg: float
    front_peak_width_mm: float
    tip_deflection_mm: float


#: Columns of :attr:`FrameFeatures.elements`, in order (``elements.csv`` puts the frame and
#: its time first, :data:`tir_contact.outputs.ELEMENT_COLUMNS`).
ELEMENT_FIELDS = list(ElementRow._fields)
#: Record type of the elements of :func:`tir_frame_records` (the element index as int64).
ELEMENT_DTYPE = np.dtype([("element", np.int64)] + [(c, np.float64) for c in ELEMENT_FIELDS[1:]])

#: Columns beyond the contact that the features read the darkness of (edge crossings); the
#: darkness is read only in the contact rows and these widened columns.
EDGE_MARGIN_PX = 3
_NAN = math.nan
#: Cost of a pixel of element face without contact relative to a contact pixel outside
#: every face, in the matching of the template (see :func:`_fit_offset`).
_EMPTY_FACE_WEIGHT = 0.25


@dataclass(frozen=True)
class BlockLayout:
    """What is known of the block and its motion in the image.

    Parameters
    ----------
    mm_per_px : float
        Image scale, mm per pixel (> 0).
    sliding_direction : {"left", "right"}
        Direction the block moves in the image (``"right"``: towards larger column index).
    element_lengths_mm : tuple of float, optional
        Element lengths l_i along the sliding direction, mm, element 0 (leading) first.
        None: no block geometry known (the contact is analysed as a whole).
    sipe_width_mm : float
        Width of each sipe, mm (>= 0).
    width_mm : float, optional
        Block width across the path, mm (caps the nominal visible width).
    height_mm : float, optional
        Element height, mm (needed for the deflection angle).
    velocity_mps : float, optional
        Carrier speed, m/s (>= 0); with `center_time_s` it gives the undeformed block
        position (deflection).
    center_time_s : float, optional
        Time at which the block centre passes the image centre, s.
    camera_follows : bool
        The camera moves with the carrier (given as ``camera="follows"``): the undeformed
        block stays where it is at `center_time_s`, the image centre.

    Examples
    --------
    >>> layout = BlockLayout.from_meta({"mm_per_px": 0.1, "sliding_direction": "left",
    ...     "block": {"length_mm": 20, "n_sipes": 3, "sipe_width_mm": 0.6}})
    >>> layout.element_lengths_mm
    (4.55, 4.55, 4.55, 4.55)
    >>> [round(p, 2) for p in layout.element_fronts_mm]
    [0.0, 5.15, 10.3, 15.45]
    """

    mm_per_px: float
    sliding_direction: str
    element_lengths_mm: tuple[float, ...] | None = None
    sipe_width_mm: float = 0.0
    width_mm: float | None = None
    height_mm: float | None = None
    velocity_mps: float | None = None
    center_time_s: float | None = None
    camera_follows: bool = False

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "mm_per_px", check_positive("mm_per_px", self.mm_per_px))
        if self.sliding_direction not in ("left", "right"):
            raise ValueError(
                "sliding_direction must be 'left' or 'right', got "
                f"sliding_direction={self.sliding_direction!r}"
            )
        if self.element_lengths_mm is not None:
            lengths = tuple(
                check_positive(f"element_lengths_mm[{i}]", v)
                for i, v in enumerate(self.element_lengths_mm)
            )
            if not lengths:
                raise ValueError("element_lengths_mm must hold at least one length, got ()")
            put(self, "element_lengths_mm", lengths)
        sw = float(self.sipe_width_mm)
        if not (math.isfinite(sw) and sw >= 0):
            raise ValueError(f"sipe_width_mm must be a finite number >= 0, got {sw!r}")
        put(self, "sipe_width_mm", sw)
        for name in ("width_mm", "height_mm"):
            if getattr(self, name) is not None:
                put(self, name, check_positive(name, getattr(self, name)))
        if self.velocity_mps is not None:
            v = float(self.velocity_mps)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"velocity_mps must be a finite number >= 0, got {v!r}")
            put(self, "velocity_mps", v)
        if self.center_time_s is not None:
            t = float(self.center_time_s)
            if not math.isfinite(t):
                raise ValueError(f"center_time_s must be finite, got {t!r}")
            put(self, "center_time_s", t)

    @classmethod
    def from_meta(cls, meta: Mapping[str, Any]) -> BlockLayout:
        """Layout from the metadata of a footage (``meta.json`` as :func:`load_meta` returns it).

        Parameters
        ----------
        meta : mapping
            Needs ``mm_per_px`` and ``sliding_direction``. Element lengths from
            ``block.element_lengths_mm``, else equal elements from ``block.length_mm``,
            ``block.n_sipes`` (default 0) and ``block.sipe_width_mm`` (default 0); without
            ``block.length_mm`` no geometry. ``block.width_mm``, ``block.height_mm``,
            ``conditions.velocity_mps`` and ``center_time_s`` when present.

        Returns
        -------
        BlockLayout

        Raises
        ------
        ValueError
            A missing required key, or a geometry that leaves no rubber for the elements.
        """
        for key in ("mm_per_px", "sliding_direction"):
            if meta.get(key) is None:
                raise ValueError(f"meta has no '{key}': it is needed for the TIR features")
        block = meta.get("block") or {}
        cond = meta.get("conditions") or {}
        sipe = float(block.get("sipe_width_mm") or 0.0)
        lengths: tuple[float, ...] | None = None
        if block.get("element_lengths_mm") is not None:
            lengths = tuple(float(v) for v in block["element_lengths_mm"])
        elif block.get("length_mm") is not None:  # equal elements, as the block model has them
            try:
                geometry = BlockGeometry(length_mm=float(block["length_mm"]),
                                         n_sipes=int(block.get("n_sipes") or 0),
                                         sipe_width_mm=sipe)
            except ValueError as exc:
                raise ValueError(f"meta 'block': {exc}") from None
            lengths = tuple(geometry.element_lengths.tolist())
        velocity = cond.get("velocity_mps")
        centre = meta.get("center_time_s")
        return cls(
            mm_per_px=float(meta["mm_per_px"]),
            sliding_direction=str(meta["sliding_direction"]).lower(),
            element_lengths_mm=lengths,
            sipe_width_mm=sipe,
            width_mm=block.get("width_mm"),
            height_mm=block.get("height_mm"),
            velocity_mps=None if velocity is None else abs(float(velocity)),
            center_time_s=None if centre is None else float(centre),
        )

    @property
    def n_elements(self) -> int:
        """Number of elements (0 without geometry)."""
        return 0 if self.element_lengths_mm is None else len(self.element_lengths_mm)

    @functools.cached_property
    def element_fronts_mm(self) -> tuple[float, ...]:
        """Undeformed front of each element behind the block front, mm (empty without geometry)."""
        if self.element_lengths_mm is None:
            return ()
        fronts, x = [], 0.0
        for ell in self.element_lengths_mm:
            fronts.append(x)
            x += ell + self.sipe_width_mm
        return tuple(fronts)

    @property
    def block_length_mm(self) -> float:
        """Length of the block face (elements and sipes), mm (NaN without geometry)."""
        if self.element_lengths_mm is None:
            return _NAN
        return float(sum(self.element_lengths_mm) + self.sipe_width_mm * (self.n_elements - 1))

    def undeformed_front_mm(self, time_s: float | None, image_width_mm: float) -> float:
        """Image x of the undeformed block front at `time_s`, mm (NaN when not known).

        The block centre passes the image centre at ``center_time_s`` with ``velocity_mps``
        along the sliding direction (the convention of :mod:`synthetic.footage`); a camera
        that follows the carrier keeps it there (`camera_follows`: before, the travel of a
        fixed camera was taken, and a following camera's angles read 1.4 for 11.4 deg and
        23.2 for 12.9 deg; helper-11).
        """
        if (
            time_s is None
            or self.velocity_mps is None
            or self.center_time_s is None
            or self.element_lengths_mm is None
        ):
            return _NAN
        s = 1.0 if self.sliding_direction == "left" else -1.0
        travel_mm = (0.0 if self.camera_follows
                     else self.velocity_mps * 1e3 * (float(time_s) - self.center_time_s))
        return 0.5 * image_width_mm - s * travel_mm - s * 0.5 * self.block_length_mm

    @functools.cached_property
    def _template_px(self) -> tuple[np.ndarray, np.ndarray]:
        """Element fronts and lengths in pixels (the footprint template)."""
        fronts = np.asarray(self.element_fronts_mm, dtype=float) / self.mm_per_px
        lengths = np.asarray(self.element_lengths_mm or (), dtype=float) / self.mm_per_px
        return fronts, lengths

    @functools.cached_property
    def _template_lists(self) -> tuple[list[float], list[float], list[float]]:
        """:attr:`_template_px` as lists, and a quarter of each length (the split limit)."""
        fronts, lengths = self._template_px
        return fronts.tolist(), lengths.tolist(), (0.25 * lengths).tolist()


@dataclass(frozen=True)
class FrameFeatures:
    """Features of one TIR frame.

    Attributes
    ----------
    frame : dict
        Keys :data:`FRAME_KEYS` (see the module notes).
    elements : pandas.DataFrame
        Columns :data:`ELEMENT_FIELDS`; one row per
        element in contact, element 0 leading; empty without geometry.
    """

    frame: dict[str, float | int | bool]
    elements: pd.DataFrame


# -- profiles ---------------------------------------------------------------------------------
def _tight_box(box: tuple[slice, slice] | None, counts: np.ndarray,
               row_counts: np.ndarray) -> tuple[int, int, int, int] | None:
    """(r0, r1, c0, c1) of `box` when its first and last rows and columns hold contact.

    The counts are zero outside the box, so such a box is the tight one; None otherwise
    (the caller then searches the counts).
    """
    if box is None:
        return None
    rows, cols = box
    r0, r1, c0, c1 = rows.start, rows.stop, cols.start, cols.stop
    if not (type(r0) is int and type(r1) is int and type(c0) is int and type(c1) is int
            and rows.step is None and cols.step is None
            and 0 <= r0 < r1 <= row_counts.size and 0 <= c0 < c1 <= counts.size):
        return None
    if counts[c0] and counts[c1 - 1] and row_counts[r0] and row_counts[r1 - 1]:
        return r0, r1, c0, c1
    return None


def _masked_column_mean(d: np.ndarray, mask: np.ndarray, counts: np.ndarray,
                        c0: int, c1: int) -> np.ndarray:
    """Mean darkness of the contact pixels of each column c0..c1-1 (0 without contact)."""
    sub = np.where(mask[:, c0:c1], d[:, c0:c1], 0.0)
    s = np.nansum(sub, axis=0, dtype=np.float64)
    return s / np.maximum(counts[c0:c1], 1)


def _half_runs(counts: np.ndarray, c_lo: int, c_hi: int) -> tuple[list[int], list[int]]:
    """First and last column of each run of ``counts >= max / 2`` (only c_lo..c_hi-1 hold
    counts)."""
    seg = counts[c_lo:c_hi]
    on = np.zeros(c_hi - c_lo + 2, np.bool_)  # padded with False at both ends
    # n >= max / 2 for integers n, max: n >= ceil(max / 2), compared in the counts' dtype
    np.greater_equal(seg, (int(np.maximum.reduce(seg)) + 1) // 2, out=on[1:-1])
    change = (np.not_equal(on[1:], on[:-1]).nonzero()[0] + c_lo).tolist()
    return change[0::2], [c - 1 for c in change[1::2]]


# -- edges and peak on a profile list ---------------------------------------------------------
def _front_edge(p: list[float], c0: int, c1: int, level: float) -> float:
    """Leading (left) crossing of `level` near column c0, px from the left border."""
    if c0 == 0:
        return 0.0
    j = c0
    for _ in range(2):
        if j > 0 and p[j - 1] >= level:
            j -= 1
    while j < c1 and p[j] < level:
        j += 1
    if j == 0:
        return 0.0
    lo, hi = p[j - 1], p[j]
    t = (level - lo) / (hi - lo) if hi > lo else 0.5
    t = 0.0 if t < 0.0 else t  # min(max(t, 0.0), 1.0), spelled out (no builtin calls)
    return j - 0.5 + (1.0 if t > 1.0 else t)


def _back_edge(p: list[float], c0: int, c1: int, level: float, n: int) -> float:
    """Trailing (right) crossing of `level` near column c1, px from the left border."""
    if c1 == n - 1:
        return float(n)
    j = c1
    for _ in range(2):
        if j < n - 1 and p[j + 1] >= level:
            j += 1
    while j > c0 and p[j] < level:
        j -= 1
    if j == n - 1:
        return float(n)
    hi, lo = p[j], p[j + 1]
    t = (hi - level) / (hi - lo) if hi > lo else 0.5
    t = 0.0 if t < 0.0 else t  # min(max(t, 0.0), 1.0), spelled out (no builtin calls)
    return j + 0.5 + (1.0 if t > 1.0 else t)


def _median(values: list[float]) -> float:
    v = sorted(values)
    k = len(v)
    return v[k // 2] if k % 2 else 0.5 * (v[k // 2 - 1] + v[k // 2])


def _front_peak(p: list[float], c0: int, c1: int, window_px: float) -> tuple[float, float, float]:
    """Peak position (px from the left border), width (px) and contrast of the front band.

    Run of columns c0..c1 (inclusive), leading edge on the left.
    """
    n_run = c1 - c0 + 1
    if n_run < 4:
        return _NAN, _NAN, _NAN
    w = max(2, min(math.ceil(window_px), n_run // 2))
    window = p[c0 : c0 + w]
    best = max(window)
    k = c0 + window.index(best)
    pos = k + 0.5
    if 0 < k < len(p) - 1:
        y0, y2 = p[k - 1], p[k + 1]
        den = y0 - 2.0 * best + y2
        if den < 0:
            shift = 0.5 * (y0 - y2) / den
            shift = -0.5 if shift < -0.5 else shift  # min(max(shift, -0.5), 0.5)
            pos += 0.5 if shift > 0.5 else shift
    behind = p[c0 + w : c1]  # without the back edge column
    if len(behind) < 2:
        return pos, _NAN, _NAN
    plateau = _median(behind)
    contrast = best - plateau
    if not contrast > 0:
        return pos, _NAN, contrast
    half = plateau + 0.5 * contrast
    i = k
    while i >= 0 and p[i] >= half:
        i -= 1
    left = i + 0.5 + (half - p[i]) / (p[i + 1] - p[i]) if i >= 0 else 0.0
    i = k
    n = len(p)
    while i < n and p[i] >= half:
        i += 1
    right = i - 0.5 + (p[i - 1] - half) / (p[i - 1] - p[i]) if i < n else float(n)
    return pos, right - left, contrast


# -- element numbering ------------------------------------------------------------------------
def _fit_offset(
    starts: list[int],
    ends: list[int],
    fronts: np.ndarray,
    lengths: np.ndarray,
    n_cols: int,
    x0_carrier: float,
    fronts_l: list[float] | None = None,
    lengths_l: list[float] | None = None,
    view: tuple[int, int] | None = None,
) -> float:
    """Block-front offset (px, mirrored frame) that best matches the runs to the template.

    Runs are columns ``starts[j] .. ends[j]`` (inclusive); a run starting at column 0 has no
    known front, one ending at the last column no known back. `fronts_l` and `lengths_l`
    are `fronts` and `lengths` as lists (made here when not given).
    """
    if fronts_l is None or lengths_l is None:
        fronts_l, lengths_l = fronts.tolist(), lengths.tolist()
    first, last = (0, n_cols - 1) if view is None else view
    x0_list: list[float] = []
    for c in starts:
        if c > first:
            x0_list += [c - f for f in fronts_l]
            break
    if ends[0] < last:
        e0 = ends[0] + 1.0
        x0_list += [e0 - f - n for f, n in zip(fronts_l, lengths_l, strict=True)]
    carrier = math.isfinite(x0_carrier)
    if carrier:
        x0_list.append(x0_carrier)
    if not x0_list:  # one run clipped at both borders: any element may fill the view
        return float(starts[0] - fronts_l[0])
    # (K, N) template clipped to the image, lo and hi in one array (np.minimum/maximum:
    # np.clip costs 5x more here); the element-wise steps round as ``x0 + fronts`` and
    # ``x0 + fronts + lengths`` do
    x0 = np.array(x0_list)
    lohi = np.empty((2, x0.size, len(fronts_l)))
    np.add(x0[:, None], fronts, out=lohi[0])
    np.add(lohi[0], lengths, out=lohi[1])
    np.maximum(lohi, float(first), out=lohi)
    np.minimum(lohi, last + 1.0, out=lohi)
    lo, hi = lohi
    ov = np.minimum(hi[:, :, None], np.array([c + 1.0 for c in ends]))  # (K, N, J)
    np.subtract(ov, np.maximum(lo[:, :, None], np.array(starts, float)), out=ov)
    # Contact outside every element face costs fully, face without contact (lift-off, or an
    # element template over an empty part of the view) a quarter: a face may lose more than
    # half its contact to lift-off and must still be preferred over no face at all.
    # (np.add.reduce is what ndarray.sum calls, without the wrapper)
    overlap = np.add.reduce(np.maximum(ov, 0.0, out=ov), axis=(1, 2)).tolist()
    face = np.add.reduce(hi - lo, axis=1).tolist()
    cost = [_EMPTY_FACE_WEIGHT * (f - o) - o for f, o in zip(face, overlap, strict=True)]
    best = min(cost) + 0.5
    tied = [x for x, c in zip(x0_list, cost, strict=True) if c <= best]
    if len(tied) > 1 and carrier:
        return min(tied, key=lambda x: abs(x - x0_carrier))  # first of equals, as argmin
    return tied[0]


class _Piece(NamedTuple):
    """A contact run (or the part of one between two sipes) and the element it belongs to."""

    element: int
    c0: int  # first column (mirrored frame)
    c1: int  # last column, inclusive
    split_front: bool  # the front is a cut at a sipe, not an edge
    split_back: bool  # the back is a cut at a sipe


@dataclass(slots=True)
class _Run:
    """One element's contact in one frame, in px of the mirrored frame (step 3)."""

    front_px: float  # leading edge of its first run
    length_px: float  # summed length of its runs
    area_px: float  # contact pixels of its runs (graded contact: unmixed area)
    c0: int  # first run's first column
    c1: int  # first run's last column (inclusive)
    front_clipped: bool  # the first run starts at the view's border (image or lit zone)
    back_clipped: bool  # its last run ends at the view's border


def _assign(
    starts: list[int],
    ends: list[int],
    x0: float,
    fronts: list[float],
    lengths: list[float],
    quarters: list[float],
    sipe_px: float,
) -> list[_Piece]:
    """The :class:`_Piece` of each (sub-)run.

    `quarters` holds ``0.25 * lengths``; plain floats, as the element-wise numpy operations
    would round them.
    """
    t_lo = [x0 + f for f in fronts]
    t_hi = [a + n for a, n in zip(t_lo, lengths, strict=True)]
    elements = range(len(fronts))
    out: list[_Piece] = []
    for c0, c1 in zip(starts, ends, strict=True):
        s, e = float(c0), float(c1) + 1.0
        ov = [(h if h < e else e) - (a if a > s else s) for a, h in zip(t_lo, t_hi, strict=True)]
        big = [i for i in elements if ov[i] > quarters[i]]
        if len(big) >= 2:  # a run across a closed sipe: split at the sipe centres
            cuts = [c0]
            for i in big[1:]:
                cut = round(t_lo[i] - 0.5 * sipe_px)
                cuts.append(min(max(cut, cuts[-1] + 1), c1 + 1))
            cuts.append(c1 + 1)
            for n_i, i in enumerate(big):
                lo_c, hi_c = cuts[n_i], cuts[n_i + 1] - 1
                if hi_c >= lo_c:
                    out.append(_Piece(i, lo_c, hi_c, n_i > 0, n_i < len(big) - 1))
            continue
        i = ov.index(max(ov))  # the first of equal overlaps, as argmax
        if ov[i] <= 0:  # no overlap at all: the nearest element
            mid = 0.5 * (c0 + c1 + 1)
            dist = [abs(0.5 * (a + h) - mid) for a, h in zip(t_lo, t_hi, strict=True)]
            i = dist.index(min(dist))
        out.append(_Piece(i, c0, c1, False, False))
    return out


def _nominal_px2(
    x0: float,
    fronts: list[float],
    lengths: list[float],
    n_cols: int,
    span: float,
    vcum: list[int] | None,
) -> float:
    """Nominal visible area of the template at `x0`, px^2 (see the module notes)."""
    lo, hi = [], []
    for f, n in zip(fronts, lengths, strict=True):  # min(max(x, 0.0), n_cols), spelled out
        t = x0 + f
        u = t + n
        t = 0.0 if t < 0.0 else t
        u = 0.0 if u < 0.0 else u
        lo.append(n_cols if n_cols < t else t)
        hi.append(n_cols if n_cols < u else u)
    if vcum is None:
        return span * sum(b - a for a, b in zip(lo, hi, strict=True))
    last = n_cols - 1

    def cum(x: float) -> float:  # valid pixels left of x (fractional columns pro rata)
        k = int(x)
        if k > last:
            k = last
        return vcum[k] + (x - k) * (vcum[k + 1] - vcum[k])

    return sum(cum(b) - cum(a) for a, b in zip(lo, hi, strict=True) if b > a)


class ValidCounts:
    """The last cumulative valid-pixel counts of one video's mask (:func:`_valid_cumsum`).

    A frame analyser keeps one: the reference's mask does not change within a video, and
    consecutive frames mostly share the rows of their contact.
    """

    __slots__ = ("columns", "key", "value")

    def __init__(self) -> None:
        self.key: tuple | None = None
        self.value: list[int] = []
        self.columns: np.ndarray = np.zeros(0, np.int32)


def _valid_cumsum(valid: np.ndarray, r0: int, r1: int, flip: bool,
                  cache: ValidCounts | None = None) -> tuple[list[int], np.ndarray]:
    """Cumulative valid pixels per column within rows r0..r1-1 (mirrored when `flip`), and
    the valid pixels of each column there.

    With `cache` (one per video and mask), the last result is reused for the same rows.
    """
    key = (valid.shape, r0, r1, flip)
    if cache is not None and cache.key == key:
        return cache.value, cache.columns
    v8 = valid[r0:r1]
    v8 = v8.view(np.uint8) if v8.dtype == np.bool_ else (v8 != 0).view(np.uint8)
    if not v8.flags.c_contiguous:
        v8 = np.ascontiguousarray(v8)
    vc = cv2.reduce(v8, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
    vc = vc[::-1] if flip else vc
    out = np.concatenate([[0], np.cumsum(vc)]).tolist()
    if cache is not None:
        cache.key, cache.value, cache.columns = key, out, vc
    return out, vc


def _view(valid: np.ndarray | None, span: tuple[int, int, int, int], flip: bool,
          counts: np.ndarray, valid_counts: ValidCounts | None, need: int | None = None
          ) -> tuple[list[int] | None, tuple[int, int]]:
    """The cumulative valid pixels per column in the contact's rows (None without `valid`)
    and the view's first and last column (mirrored frame): those whose valid pixels there
    could hold a run, at least half of the most contact pixels a column holds (a run's own
    rule, :func:`_half_runs`; `need` pixels where given); where the lit zone narrows past
    them, a run ends because the view ends. The image's ends without `valid`, or when no
    column can."""
    n_cols = counts.shape[0]
    if valid is None:
        return None, (0, n_cols - 1)
    vcum, columns = _valid_cumsum(valid, span[0], span[1], flip, valid_counts)
    if need is None:
        need = (int(counts.max()) + 1) // 2
    seen = np.flatnonzero(columns >= need)
    return vcum, ((int(seen[0]), int(seen[-1])) if seen.size else (0, n_cols - 1))


# -- the frame --------------------------------------------------------------------------------
def _empty_frame(n_regions: int, area_mm2: float = 0.0) -> dict[str, float | int | bool]:
    return {
        "block_in_view": False,
        "block_front_x_mm": _NAN,
        "contact_area_mm2": area_mm2,
        "contact_ratio": _NAN,
        "n_elements_in_contact": 0,
        "front_peak_x_mm": _NAN,
        "front_peak_contrast": _NAN,
        "n_regions": n_regions,
        "deflection_angle_deg": _NAN,
        "tip_deflection_mm": _NAN,
    }


def tir_frame_records(
    d: np.ndarray,
    contact: FrameContact,
    layout: BlockLayout,
    *,
    valid: np.ndarray | None = None,
    time_s: float | None = None,
    peak_window_mm: float = 1.0,
    free: FreeLevel | None = None,
) -> tuple[dict[str, float | int | bool], np.ndarray]:
    """Features of one TIR frame as a dict and a record array (the fast path).

    Same as :func:`tir_frame_features` but the elements come as a structured array of
    :data:`ELEMENT_DTYPE` (no DataFrame is built).

    Parameters
    ----------
    d, contact, layout, valid, time_s, peak_window_mm, free
        See :func:`tir_frame_features`.

    Returns
    -------
    frame : dict
        Keys :data:`FRAME_KEYS`.
    elements : (n,) ndarray of ELEMENT_DTYPE
        One record per element in contact, element 0 first.

    Examples
    --------
    >>> from tir_contact.segment import segment_frame
    >>> d = np.zeros((8, 40), np.float32)
    >>> d[:, 5:15] = 0.8; d[:, 20:30] = 0.8      # two strips of 1.0 mm, 0.5 mm apart
    >>> layout = BlockLayout(0.1, "left", element_lengths_mm=(1.0, 1.0), sipe_width_mm=0.5)
    >>> frame, el = tir_frame_records(d, segment_frame(d), layout)
    >>> el["element"].tolist(), el["contact_length_mm"].round(6).tolist()
    ([0, 1], [1.0, 1.0])
    >>> frame["block_front_x_mm"], round(frame["contact_ratio"], 6)
    (0.5, 1.0)
    """
    if d.ndim != 2 or d.shape != tuple(contact.shape):
        raise ValueError(
            f"d must be a 2-D image of the mask's shape {tuple(contact.shape)}, got {d.shape}"
        )
    if valid is not None and valid.shape != d.shape:
        raise ValueError(f"valid must have the shape of d {d.shape}, got {valid.shape}")
    if not (math.isfinite(peak_window_mm) and peak_window_mm > 0):
        raise ValueError(f"peak_window_mm must be > 0, got {peak_window_mm=}")
    if free is not None and not (all(math.isfinite(x) for x in free) and free.sigma_px >= 0
                                 and free.full > free.offset):
        raise ValueError("free must hold finite darkness levels, sigma_px >= 0 and full "
                         f"contact darker than the free surface, got {free!r}")
    frame, rows = frame_rows(d, contact, layout, valid, time_s, peak_window_mm, free=free)
    return frame, element_records(rows)


def element_records(rows: list[ElementRow]) -> np.ndarray:
    """Element rows as a record array of :data:`ELEMENT_DTYPE` (one array per batch)."""
    rec = np.zeros(len(rows), ELEMENT_DTYPE)
    if rows:
        rec[:] = rows
    return rec


def _contact_span(
    contact: FrameContact, counts: np.ndarray, row_counts: np.ndarray
) -> tuple[int, int, int, int] | None:
    """Rows ``r0:r1`` and columns ``c_lo:c_hi`` holding contact (image frame), None if none."""
    span = _tight_box(contact.box, counts, row_counts)
    if span is not None:
        return span
    nz = counts.nonzero()[0]
    if nz.size == 0:
        return None
    rows_on = row_counts.nonzero()[0]
    return int(rows_on[0]), int(rows_on[-1]) + 1, int(nz[0]), int(nz[-1]) + 1


def _image_mm(x_px: float, n_cols: int, px: float, flip: bool) -> float:
    """A position in the mirrored frame (px, leading side left) as image x in mm."""
    return (n_cols - x_px) * px if flip else x_px * px


def _frame_without_geometry(
    d: np.ndarray,
    contact: FrameContact,
    layout: BlockLayout,
    counts: np.ndarray,
    span: tuple[int, int, int, int],
    peak_window_mm: float,
    valid: np.ndarray | None = None,
    valid_counts: ValidCounts | None = None,
) -> dict[str, float | int | bool]:
    """The whole contact as one strip: area, block front and front peak (module notes);
    no front where the strip starts at the view's end (the image's, or the lit zone's with
    `valid`)."""
    px = layout.mm_per_px
    n_cols = d.shape[1]
    flip = layout.sliding_direction == "right"
    _, _, c_lo, c_hi = span
    first = _view(valid, span, flip, counts, valid_counts)[1][0]
    total = int(counts[c_lo:c_hi].sum())
    frame = _empty_frame(contact.n_regions, total * px * px)
    frame["block_in_view"] = True
    prof = _masked_column_mean(d, contact.mask, counts, c_lo, c_hi)
    if flip:
        prof = prof[::-1]
        c_lo, c_hi = n_cols - c_hi, n_cols - c_lo
    p = [0.0] * c_lo + prof.tolist() + [0.0] * (n_cols - c_hi)
    if c_lo > first:
        frame["block_front_x_mm"] = _image_mm(float(c_lo), n_cols, px, flip)
        pos, _, contrast = _front_peak(p, c_lo, c_hi - 1, peak_window_mm / px)
        frame["front_peak_x_mm"] = _image_mm(pos, n_cols, px, flip)
        frame["front_peak_contrast"] = contrast
    return frame


def _mirrored_band(d: np.ndarray, r0: int, r1: int, c_lo: int, c_hi: int, flip: bool,
                   sums: ColumnSums | None, fill: float = 0.0
                   ) -> tuple[np.ndarray, int, int]:
    """The mean darkness of rows r0..r1-1 over columns c_lo..c_hi-1 widened by
    :data:`EDGE_MARGIN_PX` (`fill` where a column has no measured pixel), in the mirrored
    frame, with its first and end column there."""
    n_cols = d.shape[1]
    a, b = max(c_lo - EDGE_MARGIN_PX, 0), min(c_hi + EDGE_MARGIN_PX, n_cols)
    prof = column_mean(d, r0, r1, a, b, sums, fill)
    return (prof[::-1], n_cols - b, n_cols - a) if flip else (prof, a, b)


def _mirrored_profiles(
    d: np.ndarray,
    counts: np.ndarray,
    span: tuple[int, int, int, int],
    flip: bool,
    sums: ColumnSums | None,
) -> tuple[list[float], np.ndarray, list[int], list[int]]:
    """Step 1 of the module notes in the mirrored frame (leading side left).

    Returns the darkness profile ``p`` over all columns, the contact counts ``n``, and the
    first and last columns of the runs above half coverage.
    """
    r0, r1, c_lo, c_hi = span
    n_cols = d.shape[1]
    prof, a, b = _mirrored_band(d, r0, r1, c_lo, c_hi, flip, sums)
    p = [0.0] * n_cols
    p[a:b] = prof.tolist()
    starts, ends = _half_runs(counts, c_lo, c_hi)
    if flip:
        counts = counts[::-1]
        last = n_cols - 1
        starts, ends = [last - c for c in reversed(ends)], [last - c for c in reversed(starts)]
    return p, counts, starts, ends


def _element_runs(
    pieces: list[_Piece],
    areas: list[float],
    p: list[float],
    n_cols: int,
    view: tuple[int, int],
    edge_level: float | None = None,
) -> dict[int, _Run]:
    """Step 3: each element's front edge, summed length, area and first run (px).

    A further run of the same element adds its length and area; the front and peak stay
    the first run's. A run is clipped where it reaches the view's first or last column
    (`view`, mirrored frame: :func:`_view`). The edges cross half the run's median
    darkness, or `edge_level` where given (graded contact's presence level,
    :mod:`tir_contact.graded`).
    """
    first, last = view
    per: dict[int, _Run] = {}
    for piece, area in zip(pieces, areas, strict=True):
        c0, c1 = piece.c0, piece.c1
        level = 0.5 * _median(p[c0 : c1 + 1]) if edge_level is None else edge_level
        x_f = float(c0) if piece.split_front else _front_edge(p, c0, c1, level)
        x_b = float(c1 + 1) if piece.split_back else _back_edge(p, c0, c1, level, n_cols)
        e = per.get(piece.element)
        if e is None:
            per[piece.element] = _Run(x_f, x_b - x_f, area, c0, c1,
                                      c0 <= first and not piece.split_front, c1 >= last)
        else:
            e.length_px += x_b - x_f
            e.area_px += area
            e.back_clipped = c1 >= last
    return per


def _element_rows(
    per: dict[int, _Run],
    x0: float,
    x_und: float,
    layout: BlockLayout,
    p: list[float],
    n_cols: int,
    peak_window_mm: float,
    view: tuple[int, int],
) -> list[ElementRow]:
    """Steps 4 to 6 of the module notes: peak, lift-off and deflection of each element
    (lift-off only for an element whose template lies within the `view`, mirrored frame:
    :func:`_view`)."""
    first, last = view
    px = layout.mm_per_px
    flip = layout.sliding_direction == "right"
    s = -1.0 if flip else 1.0
    fronts_l, lengths_l, _ = layout._template_lists
    fronts_mm = layout.element_fronts_mm
    lengths_mm = layout.element_lengths_mm
    height = layout.height_mm
    window_px = peak_window_mm / px
    rows = []
    for i in sorted(per):
        run = per[i]
        x_f, clip_f, clip_b = run.front_px, run.front_clipped, run.back_clipped
        t = x0 + fronts_l[i]
        inside = t >= first and t + lengths_l[i] <= last + 1
        length_mm = run.length_px * px
        if clip_f:
            front_mm = pk_mm = width_mm = contrast = _NAN
        else:
            front_mm = _image_mm(x_f, n_cols, px, flip)
            pos, width_px, contrast = _front_peak(p, run.c0, run.c1, window_px)
            pk_mm = _image_mm(pos, n_cols, px, flip) if pos == pos else _NAN
            width_mm = width_px * px
        tip = angle = _NAN
        if front_mm == front_mm and x_und == x_und:
            tip = s * (front_mm - x_und) - fronts_mm[i]
            if height is not None:
                angle = math.degrees(math.atan2(tip, height))
        liftoff = _NAN if (clip_f or clip_b or not inside) else max(0.0, lengths_mm[i] - length_mm)
        rows.append(ElementRow(
            element=i, contact_area_mm2=run.area_px * px * px, contact_length_mm=length_mm,
            front_edge_x_mm=front_mm, front_peak_x_mm=pk_mm, front_peak_contrast=contrast,
            liftoff_mm=liftoff, deflection_angle_deg=angle, front_peak_width_mm=width_mm,
            tip_deflection_mm=tip))
    return rows


def _contact_ratio(
    total_px: float,
    x0: float,
    layout: BlockLayout,
    span: tuple[int, int, int, int],
    n_cols: int,
    vcum: list[int] | None,
) -> float:
    """Contact area over the nominal visible area of the fitted template (module notes);
    `vcum`: the valid pixels' cumulative counts per column (:func:`_view`), None without a
    valid mask."""
    r0, r1 = span[:2]
    fronts_l, lengths_l, _ = layout._template_lists
    rows_px = 0.0
    if vcum is None:
        rows_px = float(r1 - r0)
        if layout.width_mm is not None:
            rows_px = min(rows_px, layout.width_mm / layout.mm_per_px)
    nominal = _nominal_px2(x0, fronts_l, lengths_l, n_cols, rows_px, vcum)
    return total_px / nominal if nominal > 0 else _NAN


def _block_values(frame: dict[str, float | int | bool], rows: list[ElementRow]) -> None:
    """The block's values from its elements: the leading one's front and peak, mean angles."""
    frame["n_elements_in_contact"] = len(rows)
    if not rows:
        return
    lead = rows[0]
    frame["block_front_x_mm"] = lead.front_edge_x_mm
    frame["front_peak_x_mm"] = lead.front_peak_x_mm
    frame["front_peak_contrast"] = lead.front_peak_contrast
    tips = [r.tip_deflection_mm for r in rows if r.tip_deflection_mm == r.tip_deflection_mm]
    angles = [r.deflection_angle_deg for r in rows
              if r.deflection_angle_deg == r.deflection_angle_deg]
    if tips:
        frame["tip_deflection_mm"] = sum(tips) / len(tips)
    if angles:
        frame["deflection_angle_deg"] = sum(angles) / len(angles)


def graded_back_px(layout: BlockLayout) -> int:
    """Columns either side of the half-coverage contact that graded contact is sought in:
    the longest element and a sipe (0 without the geometry)."""
    if layout.element_lengths_mm is None:
        return 0
    return math.ceil((max(layout.element_lengths_mm) + layout.sipe_width_mm)
                     / layout.mm_per_px)


def _graded_profiles(
    d: np.ndarray,
    span: tuple[int, int, int, int] | None,
    box: tuple[slice, slice] | None,
    free: FreeLevel,
    layout: BlockLayout,
    sums: ColumnSums | None,
) -> tuple[tuple[int, int, int, int], list[float], Any] | None:
    """Graded contact's span, mirrored profile ``p`` and runs
    (:class:`tir_contact.graded.GradedRuns`, columns in the mirrored frame), or None where
    no column holds contact.

    The rows and columns are the contact's, its columns widened by :data:`EDGE_MARGIN_PX`
    and the longest element and a sipe (:func:`graded_back_px`: the last face's faint back
    lies past the last column that reaches half coverage, at its front, and a face leaving
    the view ahead of the first), and to the box where given (a junction field's faint contact:
    faces that reach half coverage nowhere), the box's alone without half-coverage
    contact. A column without a measured pixel is taken at the free surface's level.

    Returns ``(span, p, (starts, ends, level, column_px))``.
    """
    n_cols = d.shape[1]
    flip = layout.sliding_direction == "right"
    if span is not None:
        r0, r1, c_lo, c_hi = span
        # a face's faint back lies past its front band, a leaving face's ahead of the
        # first band in view
        back = graded_back_px(layout)
        c_lo, c_hi = c_lo - back, c_hi + back
        if box is not None:  # faces that reach half coverage nowhere
            c_lo, c_hi = min(c_lo, box[1].start), max(c_hi, box[1].stop)
    elif box is not None:
        r0, r1, c_lo, c_hi = box[0].start, box[0].stop, box[1].start, box[1].stop
    else:
        return None
    prof, a, b = _mirrored_band(d, r0, r1, c_lo, c_hi, flip, sums, free.offset)
    runs = graded_runs(prof, r1 - r0, free)
    if runs is None:
        return None
    column_px = np.zeros(n_cols)
    column_px[a:b] = runs.column_px
    p = [0.0] * n_cols
    p[a:b] = prof.tolist()
    return ((r0, r1, max(c_lo, 0), min(c_hi, n_cols)), p,
            ([s + a for s in runs.starts], [e + a for e in runs.ends], runs.level, column_px))


def frame_rows(
    d: np.ndarray,
    contact: FrameContact,
    layout: BlockLayout,
    valid: np.ndarray | None,
    time_s: float | None,
    peak_window_mm: float,
    sums: ColumnSums | None = None,
    valid_counts: ValidCounts | None = None,
    free: FreeLevel | None = None,
    faint_box: tuple[slice, slice] | None = None,
) -> tuple[dict[str, float | int | bool], list[ElementRow]]:
    """:func:`tir_frame_records` without the checks, the elements as :class:`ElementRow`.

    A batch builds one record array at the end (:func:`element_records`) instead of one per
    frame. `sums`: column sums of `d` already taken (see
    :func:`tir_contact._columns.column_mean`); `valid_counts`: the video's cache of
    valid-pixel counts. `free`: the free surface's darkness and noise where contact is
    graded (:mod:`tir_contact.graded`; a frame where no column clears its presence level
    falls back to the half-coverage runs); `faint_box`: where a junction field's faint
    contact lies, sought there when no pixel reaches half coverage.
    """
    px = layout.mm_per_px
    n_cols = d.shape[1]
    counts, row_counts = contact.line_counts
    span = _contact_span(contact, counts, row_counts)
    if layout.element_lengths_mm is None:
        frame = (_empty_frame(contact.n_regions) if span is None else _frame_without_geometry(
            d, contact, layout, counts, span, peak_window_mm, valid, valid_counts))
        # no elements to count without the block's geometry (0 read as "none in
        # contact"; helper-11)
        frame["n_elements_in_contact"] = _NAN
        return frame, []
    graded = None
    if free is not None:
        graded = _graded_profiles(d, span, faint_box, free, layout, sums)
    if span is None and graded is None:
        return _empty_frame(contact.n_regions), []
    flip = layout.sliding_direction == "right"
    edge_level = need = None
    if graded is None:
        p, counts, starts, ends = _mirrored_profiles(d, counts, span, flip, sums)
    else:
        span, p, runs = graded
        starts, ends, edge_level, counts = runs
        need = (span[1] - span[0] + 1) // 2  # a column seen in at least half the rows
    # Step 2: the template's offset and the element of each run.
    fronts, lengths = layout._template_px
    fronts_l, lengths_l, quarters_l = layout._template_lists
    x_und = layout.undeformed_front_mm(time_s, n_cols * px)
    x0_carrier = _NAN
    if math.isfinite(x_und):
        x0_carrier = n_cols - x_und / px if flip else x_und / px
    # the view's ends along the contact's rows: where the lit zone ends, a run is cut and
    # the template clipped as at the image border
    vcum, view = _view(valid, span, flip, counts, valid_counts, need)
    x0 = _fit_offset(starts, ends, fronts, lengths, n_cols, x0_carrier, fronts_l, lengths_l,
                     view)
    pieces = _assign(starts, ends, x0, fronts_l, lengths_l, quarters_l,
                     layout.sipe_width_mm / px)
    # Columns between runs (below half coverage) count for the area of the nearer run.
    bounds = [0]
    for a, b in itertools.pairwise(pieces):
        bounds.append((a.c1 + 1 + b.c0) // 2)
    areas = np.add.reduceat(counts, bounds,
                            dtype=np.int64 if graded is None else np.float64).tolist()
    if graded is not None:  # a face's noise may sum below zero
        areas = [max(x, 0.0) for x in areas]
    total = sum(areas)  # the pieces' areas partition the columns
    frame = _empty_frame(contact.n_regions, total * px * px)
    frame["block_in_view"] = True
    per = _element_runs(pieces, areas, p, n_cols, view, edge_level)
    rows = _element_rows(per, x0, x_und, layout, p, n_cols, peak_window_mm, view)
    frame["contact_ratio"] = _contact_ratio(total, x0, layout, span, n_cols, vcum)
    _block_values(frame, rows)
    return frame, rows


def tir_frame_features(
    d: np.ndarray,
    contact: FrameContact,
    layout: BlockLayout,
    *,
    valid: np.ndarray | None = None,
    time_s: float | None = None,
    peak_window_mm: float = 1.0,
    free: FreeLevel | None = None,
) -> FrameFeatures:
    """Block and element features of one TIR frame (see the module notes for the method).

    Parameters
    ----------
    d : (M, N) ndarray of float
        Darkness (:func:`tir_contact.flatfield.darkness`), NaN where excluded.
    contact : FrameContact
        Segmentation of `d` (:func:`tir_contact.segment.segment_frame`).
    layout : BlockLayout
        Scale, sliding direction and (optionally) block geometry and carrier trajectory.
    valid : (M, N) ndarray of bool, optional
        Usable pixels (:attr:`tir_contact.flatfield.Reference.valid`); only they count for
        the nominal area of ``contact_ratio``, and where they end along the contact's rows
        the view ends (module notes, step 1).
    time_s : float, optional
        Time of the frame (middle of the exposure), s; with the layout's trajectory it gives
        the deflection.
    peak_window_mm : float
        Length behind an element's front edge searched for the pressure peak, mm (at most
        half the element's contact); 1 mm holds the 0.4 mm edge band of a new sample.
    free : FreeLevel, optional
        For graded contact (a field of junctions below the pixel, densest at each face's
        front; :func:`tir_contact.graded.graded_contact` tells it from a video's frames,
        and the analysis gives this where it is): the free surface's darkness and noise
        and full contact's darkness. The runs are then the columns that hold contact
        (:mod:`tir_contact.graded`); without it the half-coverage runs (module notes,
        step 1). Used with the block's geometry only; graded contact is sought round the
        half-coverage contact (a frame without any reads as no contact here; the analysis
        also seeks a junction field where its seeds place it). Each element's area is its
        unmixed darkness against ``free.full``: where that was read on dense clusters of
        junctions rather than full contact, the areas are that much too high.

    Returns
    -------
    FrameFeatures

    Notes
    -----
    x in mm from the left image edge (pixel column c covers ``[c, c+1) * mm_per_px``).

    Examples
    --------
    >>> from tir_contact.segment import segment_frame
    >>> d = np.zeros((8, 40), np.float32)
    >>> d[:, 5:15] = 0.8; d[:, 20:28] = 0.8      # element 1's back is lifted by 0.2 mm
    >>> layout = BlockLayout(0.1, "left", element_lengths_mm=(1.0, 1.0), sipe_width_mm=0.5)
    >>> f = tir_frame_features(d, segment_frame(d), layout)
    >>> f.elements[["element", "contact_length_mm", "liftoff_mm"]].round(6).values.tolist()
    [[0.0, 1.0, 0.0], [1.0, 0.8, 0.2]]
    """
    frame, rec = tir_frame_records(
        d, contact, layout, valid=valid, time_s=time_s, peak_window_mm=peak_window_mm,
        free=free,
    )
    elements = pd.DataFrame({name: rec[name] for name in rec.dtype.names}, copy=False)
    return FrameFeatures(frame, elements)
