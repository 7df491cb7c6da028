"""Free-surface reference and flat-field normalisation of TIR frames.

Under total internal reflection the free ice surface is bright and a contact frustrates
the reflection: it is dark (or bright, for the opposite set-up). Illumination is uneven
(gradient, vignetting) and the ice carries static bubbles, scratches and dust, so a
contact is measured against the free-surface image of the same pixel: the *darkness*
``D = 1 - I / I_ref`` (``contact_is="dark"``) or ``D = I / I_ref - 1`` (``"bright"``).
Static imperfections and uneven light cancel in the ratio.

Reference: each pixel's high percentile over frames spread through the video, because a
sliding block covers any pixel in a minority of frames (the block enters, crosses and
leaves). Where no clean reference exists (a single frame, or a block that never leaves),
:func:`reference_from_frame` estimates it from the frame itself with a morphological
closing larger than the contact strips. Pixels the TIR light does not reach (dark in the
reference) are excluded and reported, never counted as contact.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from dataclasses import dataclass

import cv2
import numpy as np

from tir_contact._percentile import pixelwise_percentile

__all__ = [
    "Normaliser",
    "Reference",
    "darkness",
    "reference_from_frame",
    "reference_from_frames",
]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class Reference:
    """Free-surface image and the mask of pixels usable for analysis.

    Attributes
    ----------
    image : (M, N) ndarray of float
        Free-surface intensity in the frames' units (grey values).
    valid : (M, N) ndarray of bool
        False where the TIR light does not reach (reference below ``min_relative`` of its
        median); such pixels are excluded from every measurement.
    method : str
        ``"percentile"`` (from many frames) or ``"closing"`` (from a single frame).
    n_frames : int
        Frames the reference was built from.
    """

    image: np.ndarray
    valid: np.ndarray
    method: str
    n_frames: int

    @property
    def excluded_fraction(self) -> float:
        """Fraction of the image excluded because the light does not reach it."""
        return float(1.0 - self.valid.mean())


class Normaliser:
    """Darkness of frames against a fixed reference, NaN at excluded pixels
    (:func:`darkness`, which the per-frame step of the analysis runs through this).

    ``D = 1 - I / I_ref`` for dark contact, ``I / I_ref - 1`` for bright contact, in
    float32 as one multiply and one add per pixel, ``D = I * scale + offset``: the scale
    ``-1 / I_ref`` (dark) or ``1 / I_ref`` (bright) and the offset ``1`` or ``-1`` are
    made once per reference; the scale is NaN at excluded pixels, so they come out NaN at
    no extra cost.
    """

    def __init__(self, reference: Reference, contact_is: str) -> None:
        _check_contact_is(contact_is)
        self.reference = reference
        self.valid = reference.valid
        self.contact_is = contact_is
        inv = np.where(reference.valid, 1.0 / np.maximum(reference.image, 1e-6), np.nan)
        sign = -1.0 if contact_is == "dark" else 1.0
        self.scale = (sign * inv).astype(np.float32)
        self.offset = (-sign * reference.valid).astype(np.float32)

    def __call__(self, frame: np.ndarray) -> np.ndarray:
        d = frame.astype(np.float32)
        d *= self.scale
        d += self.offset
        return d

    def region(self, frame: np.ndarray, rows: slice, cols: slice) -> np.ndarray:
        """The darkness of ``frame[rows, cols]``, bit-identical to ``self(frame)[rows, cols]``."""
        d = frame[rows, cols].astype(np.float32)
        d *= self.scale[rows, cols]
        d += self.offset[rows, cols]
        return d


def _check_contact_is(contact_is: str) -> None:
    if contact_is not in ("dark", "bright"):
        raise ValueError(f"contact_is must be 'dark' or 'bright', got {contact_is!r}")


def _valid_mask(image: np.ndarray, min_relative: float) -> np.ndarray:
    level = float(np.median(image))
    return image > min_relative * level


def reference_from_frames(
    frames: Iterable[np.ndarray],
    *,
    contact_is: str = "dark",
    percentile: float = 90.0,
    max_frames: int = 64,
    n_total: int | None = None,
    min_relative: float = 0.2,
) -> Reference:
    """Free-surface reference from frames spread through a video.

    Parameters
    ----------
    frames : iterable of (M, N) ndarray
        Frames in order (a reader or any iterable); only up to ``max_frames`` of them,
        evenly spaced when ``n_total`` is given, are kept in memory.
    contact_is : {"dark", "bright"}
        Polarity of the contact. For dark contact the reference is each pixel's
        ``percentile`` (a bright free surface), for bright contact its
        ``100 - percentile``.
    percentile : float
        Percentile in (50, 100]; 90 keeps the block out as long as it covers a pixel in
        less than 10 % of the sampled frames.
    max_frames : int
        Frames kept in memory.
    n_total : int, optional
        Number of frames of the video (to space the samples evenly).
    min_relative : float
        Pixels whose reference is below this fraction of the median are excluded.

    Returns
    -------
    Reference
    """
    _check_contact_is(contact_is)
    if not 50.0 < percentile <= 100.0:
        raise ValueError(f"percentile must lie in (50, 100], got {percentile!r}")
    step = max(1, (n_total or 0) // max_frames) if n_total else 1
    kept: list[np.ndarray] = []
    for i, frame in enumerate(frames):
        if i % step == 0:
            kept.append(np.asarray(frame))
            if len(kept) >= max_frames:
                break
    if not kept:
        raise ValueError("no frames to build a reference from")
    if len(kept) < 5:
        logger.warning(
            "reference from only %d frame(s); use reference_from_frame for single frames",
            len(kept),
        )
    shapes = {f.shape for f in kept}
    if len(shapes) > 1 or kept[0].ndim != 2:
        raise ValueError(f"frames must be 2-D images of one shape, got shapes {sorted(shapes)}")
    dtype = np.result_type(*kept)
    kept = [f.astype(dtype, copy=False) for f in kept]
    q = percentile if contact_is == "dark" else 100.0 - percentile
    image = pixelwise_percentile(kept, q)
    return Reference(image, _valid_mask(image, min_relative), "percentile", len(kept))


def reference_from_frame(
    frame: np.ndarray,
    *,
    contact_is: str = "dark",
    size_px: int = 61,
    min_relative: float = 0.2,
) -> Reference:
    """Free-surface estimate from a single frame (no clean reference available).

    A grey closing (dark contact) or opening (bright contact) with a square of
    ``size_px`` removes contact strips narrower than ``size_px`` and keeps the slowly
    varying illumination; a box mean then smooths the result. Contacts wider than
    ``size_px`` in both directions are not removed: choose ``size_px`` larger than the
    widest contact strip.

    Parameters
    ----------
    frame : (M, N) ndarray
    contact_is : {"dark", "bright"}
    size_px : int
        Side of the structuring element, px (odd, >= 3).
    min_relative : float
        Pixels whose reference is below this fraction of the median are excluded.

    Returns
    -------
    Reference
    """
    _check_contact_is(contact_is)
    if size_px < 3 or size_px % 2 == 0:
        raise ValueError(f"size_px must be odd and >= 3, got size_px={size_px!r}")
    img = np.asarray(frame, dtype=np.float32)
    kernel = np.ones((size_px, size_px), np.uint8)
    op = cv2.MORPH_CLOSE if contact_is == "dark" else cv2.MORPH_OPEN
    ref = cv2.morphologyEx(img, op, kernel, borderType=cv2.BORDER_REFLECT)
    ref = cv2.blur(ref, (size_px // 2 | 1, size_px // 2 | 1), borderType=cv2.BORDER_REFLECT)
    image = ref.astype(float)
    return Reference(image, _valid_mask(image, min_relative), "closing", 1)


def darkness(frame: np.ndarray, reference: Reference, *, contact_is: str = "dark") -> np.ndarray:
    """Flat-field contact signal: 0 on the free surface, growing with contact pressure.

    Parameters
    ----------
    frame : (M, N) ndarray
    reference : Reference
    contact_is : {"dark", "bright"}

    Returns
    -------
    (M, N) ndarray of float32
        ``1 - I/I_ref`` for dark contact, ``I/I_ref - 1`` for bright; NaN where the
        reference is not valid.

    Examples
    --------
    >>> ref = Reference(np.full((2, 2), 200.0), np.ones((2, 2), bool), "percentile", 10)
    >>> darkness(np.array([[200, 50], [100, 200]]), ref).tolist()
    [[0.0, 0.75], [0.5, 0.0]]
    """
    _check_contact_is(contact_is)
    frame = np.asarray(frame)
    if frame.shape != reference.image.shape:
        raise ValueError(
            f"frame shape {frame.shape} differs from the reference {reference.image.shape}"
        )
    return Normaliser(reference, contact_is)(frame)
