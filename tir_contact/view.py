"""What every view of the footage (TIR, side) is: prepare, analyse one frame, tables.

A view is one object per video, made before the first frame by its ``prepare``
(:meth:`tir_contact.tir_view.TirView.prepare`, :meth:`tir_contact.side_view.SideView.prepare`)
from the sampled frames; :func:`tir_contact.prepare.prepare_video` keeps it in
:attr:`tir_contact.prepare.VideoSetup.view`. Its :meth:`View.analyser` gives the per-frame
step (``analyser(k, frame) -> FrameResult``), :meth:`View.summary` its part of
``summary.json``, :meth:`View.overlay` a frame's overlay, :meth:`View.warnings` and
:meth:`View.images` its own warnings and images; :class:`tir_contact.outputs.Tables`
builds the tables from the results.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import cv2
import numpy as np
import pandas as pd

from tir_contact._readers import FootageError
from tir_contact.features import ElementRow, element_records
from tir_contact.flatfield import Reference

__all__ = ["FrameResult", "View", "fully_in_view", "read_reference_file", "wants_regions"]


@dataclass(slots=True)
class FrameResult:
    """What one frame gave.

    Attributes
    ----------
    row : dict
        The frame's row of ``frames.csv`` (``frame``, ``time_s`` and the measured columns).
    elements : list of ElementRow or pandas.DataFrame
        TIR: one :class:`~tir_contact.features.ElementRow` per element in contact
        (:meth:`element_table` makes a table of them); side view: the element table.
    regions : dict of ndarray or None
        TIR: every contact region's columns (pixels), when regions are wanted.
    detail : FrameContact or SideFeatures
        The segmentation (TIR) or the side-view features, for drawing overlays.
    """

    row: dict[str, Any]
    elements: list[ElementRow] | pd.DataFrame
    regions: dict[str, np.ndarray] | None
    detail: Any

    def element_table(self) -> pd.DataFrame:
        """The elements as a table with ``frame`` and ``time_s`` first."""
        if isinstance(self.elements, pd.DataFrame):
            return self.elements
        rec = element_records(self.elements)
        df = pd.DataFrame({name: rec[name] for name in rec.dtype.names})
        df.insert(0, "time_s", self.row["time_s"])
        df.insert(0, "frame", self.row["frame"])
        return df


class View(Protocol):
    """One view of the footage, prepared for one video.

    Attributes
    ----------
    name : {"tir", "side"}
        The view's name (``summary.json``'s ``view``).
    reference : Reference or None
        The free surface (TIR) or the background (side view; None: each frame's own).
    method : str
        How the reference was made.
    camera : {"fixed", "follows"}
    reference_fit : ReferenceFit or None
        A user's reference fitted to the footage (TIR with ``--reference``).
    subject : str
        What the view finds in a frame ("contact", "block"), for the user's messages.
    """

    name: str
    subject: str
    reference_fit: Any

    @property
    def reference(self) -> Reference | None: ...

    @property
    def method(self) -> str: ...

    @property
    def camera(self) -> str: ...

    def analyser(self, setup: Any, options: Any) -> Callable[[int, np.ndarray], FrameResult]:
        """The per-frame step of this video: ``analyser(k, frame) -> FrameResult``."""
        ...

    def summary(self) -> dict[str, Any]:
        """The view's part of ``summary.json`` (after ``camera``, before ``meta``)."""
        ...

    def overlay(self, setup: Any, frame: np.ndarray, result: FrameResult,
                label: str) -> np.ndarray:
        """The overlay image (BGR uint8) of a frame and its result."""
        ...

    def warnings(self, frames: pd.DataFrame) -> list[str]:
        """What the video's ``frames.csv`` calls to the user's attention, for this view."""
        ...

    def none_found(self, frames: pd.DataFrame) -> str:
        """What the frames' values are when no frame shows the subject: a clause after
        "no <subject> found in any of the N frames" ("" when nothing is to be said)."""
        ...

    def images(self) -> dict[str, np.ndarray]:
        """Images written into the result folder beside the tables, by file name."""
        ...


def wants_regions(options: Any, setup: Any) -> bool:
    """Whether the results hold the contact regions (``regions.csv``): ``--regions always``,
    or ``auto`` for footage whose element lengths are not known."""
    return options.regions == "always" or (
        options.regions == "auto" and setup.layout.element_lengths_mm is None)


def fully_in_view(front_mm: float, setup: Any, margin_mm: float = 0.5) -> bool:
    """True when the whole block footprint lies in the image (`margin_mm` from its ends)."""
    if not math.isfinite(front_mm) or setup.layout.element_lengths_mm is None:
        return math.isfinite(front_mm)
    total = setup.layout.block_length_mm
    width_mm = setup.shape[1] * setup.mm_per_px
    back = front_mm + total if setup.layout.sliding_direction == "left" else front_mm - total
    lo, hi = min(front_mm, back), max(front_mm, back)
    return lo >= margin_mm and hi <= width_mm - margin_mm


def read_reference_file(path: str, shape: tuple[int, int],
                        min_relative: float = 0.2) -> Reference:
    """A user's reference image (``--reference``), grey, of the footage's size."""
    if not Path(path).is_file():
        raise FootageError(f"{path}: the reference image does not exist", path)
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise FootageError(f"{path}: cannot read the reference image", path)
    if image.ndim == 3:
        image = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    if image.shape != shape:
        raise FootageError(
            f"{path}: reference size {image.shape[1]}x{image.shape[0]} differs from the "
            f"footage's {shape[1]}x{shape[0]}",
            path,
        )
    image = image.astype(float)
    valid = image > min_relative * float(np.median(image))
    return Reference(image, valid, "file", 1)
