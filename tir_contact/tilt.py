"""Whether the block's element edges run along the image columns (TIR view).

The TIR features read the block as sliding along the image rows (``tir_contact.features``,
Limits): each element's front edge is a column, and its deflection is its front's
displacement along the rows from where the carrier's travel puts the undeformed front. A
camera turned about its axis tilts every edge; the edges' position, length and area stay
row means, but the deflection angles drift. Measured on the synthetic G7 and G3 blocks
(100-200 frames at 1 m/s, seed 3, median angle error against the renderer's truth): the
angle moves by -0.16 / -0.15 deg at a 1 deg turn, -1.02 / -0.37 deg at 2 deg and -2.41 /
-2.06 deg at 3 deg; one pixel's angle over the element height is 0.95 deg.

The edges' orientation is read from the contact of a few sampled frames as the structure
tensor of the contact's share of each pixel (:func:`edge_tilt`): its dominant gradient
direction is the edges' normal, and its coherence says whether straight edges dominate.
Measured on the TIR clips among seed 0's first 60 domain draws: 0.97-1.0 for most blocks
(6 of 10 following cameras, 3 of 6 passing blocks, turned by 0-7.7 deg and read within
0.2 deg of it), 0.01-0.73 for all 25 static contacts (round pads, coins, three points);
blocks with patchy contact read 0.04-0.67 and are not judged. No clip that is not turned
is warned about. Not judged either: a block seen whole across the rows (its sides along the
rows add a second edge direction: four 24 x 60 px elements turned 3 deg read coherence
0.41) and a contact whose sides along the rows dominate (a rib; |tilt| over 45 deg).
The rules were set on these draws (coherence) and on seed 3's G3 / G7 turns (the 1.5 deg;
it is tied to the synthetic scale: one pixel's angle, 0.1 mm over 6 mm). Held out, seed 1's
first 60 draws (43 TIR clips): warned only on the one 3.0 deg turned passing block whose
edges it reads (2.94 deg); static contacts 0.74 at most.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from tir_contact.flatfield import Normaliser, Reference

__all__ = ["MAX_TILT_DEG", "MIN_COHERENCE", "EdgeTilt", "edge_tilt", "tilt_warning"]

#: A tilt of the element edges beyond this many degrees is warned about where the
#: deflection angles are read: the angle's drift (module notes) reaches one pixel's angle
#: near a 2 deg turn, which the tensor reads as about 1.9 deg (it reads 0.97 of a turn).
MAX_TILT_DEG = 1.5
#: The edges are straight and dominate where the tensor's coherence is at least this.
MIN_COHERENCE = 0.9
#: Sampled frames the tilt is read from, at most.
TILT_SAMPLES = 4


@dataclass(frozen=True)
class EdgeTilt:
    """The dominant orientation of the contact's edges.

    Attributes
    ----------
    tilt_deg : float
        The edges' normal against the image rows, degrees (0: edges along the columns;
        positive: turned towards +y, i.e. clockwise on the screen).
    coherence : float
        0 (no dominant orientation) to 1 (all edges parallel).
    """

    tilt_deg: float
    coherence: float

    @property
    def straight(self) -> bool:
        """Whether straight parallel edges dominate (:data:`MIN_COHERENCE`)."""
        return self.coherence >= MIN_COHERENCE

    def summary(self) -> dict[str, float]:
        """``summary.json``'s ``edge_tilt``."""
        return {"tilt_deg": round(self.tilt_deg, 3), "coherence": round(self.coherence, 3)}


def edge_tilt(samples: Sequence[np.ndarray], reference: Reference, threshold: float,
              contact_is: str = "dark", *, full_darkness: float | None = None,
              inside: np.ndarray | None = None) -> EdgeTilt | None:
    """The orientation of the contact's edges over up to :data:`TILT_SAMPLES` of `samples`.

    Each frame's contact share (its darkness against `reference` over `full_darkness`,
    full contact's darkness, or twice `threshold` where that is not given; clipped to
    0..1) is differentiated (Scharr's kernel, the
    rotation-fair one); the summed structure tensor ``J = sum [gx^2, gx gy; gx gy, gy^2]``
    over `inside` (the reference's valid pixels eroded by 4 px when not given: the lit zone's own
    rim is not a contact edge) gives the tilt ``0.5 atan2(2 Jxy, Jxx - Jyy)`` and the
    coherence ``|(Jxx - Jyy, 2 Jxy)| / (Jxx + Jyy)``. None without any contact edge or
    without a positive darkness scale.

    Parameters
    ----------
    samples : sequence of (M, N) ndarray
        Sampled frames; the tilt is read from up to :data:`TILT_SAMPLES` spread over them.
    reference : Reference
        The free surface and its valid pixels.
    threshold : float
        The contact threshold (darkness).
    contact_is : {"dark", "bright"}
    full_darkness : float, optional
        Full contact's darkness (the view's contrast).
    inside : (M, N) ndarray of bool, optional
        The pixels whose gradients count.

    Returns
    -------
    EdgeTilt or None

    Examples
    --------
    >>> yy, xx = np.mgrid[:100, :200]
    >>> turned = (xx - 100) * np.cos(np.radians(4)) + (yy - 50) * np.sin(np.radians(4))
    >>> frame = 110.0 - 90.0 * np.tanh(3 * np.sin(turned / 6.0))  # stripes turned by 4 deg
    >>> ref = Reference(np.full((100, 200), 200.0), np.ones((100, 200), bool), "file", 1)
    >>> t = edge_tilt([frame], ref, 0.5)
    >>> round(t.tilt_deg), t.straight
    (4, True)
    """
    scale = 2.0 * threshold
    if full_darkness is not None and math.isfinite(full_darkness) and full_darkness > 0:
        scale = full_darkness
    if not (math.isfinite(scale) and scale > 0) or not samples:
        return None
    norm = Normaliser(reference, contact_is)
    if inside is None:
        inside = cv2.erode(reference.valid.astype(np.uint8), np.ones((9, 9), np.uint8)) > 0
    weight = inside.astype(np.float32)
    pick = np.unique(np.linspace(0, len(samples) - 1, min(len(samples), TILT_SAMPLES))
                     .round().astype(int))
    jxx = jyy = jxy = 0.0
    for i in pick:
        d = norm(np.asarray(samples[int(i)]))
        # contact's share of each pixel: edges keep their sub-pixel place, where a mask's
        # steps pull a turned edge towards the columns (a 4 deg turn read as 3.3 deg)
        m = np.clip(np.nan_to_num(d * np.float32(1.0 / scale)), 0.0, 1.0)
        gx = cv2.Scharr(m, cv2.CV_32F, 1, 0)
        gy = cv2.Scharr(m, cv2.CV_32F, 0, 1)
        gx *= weight
        jxx += float(np.vdot(gx, gx))
        jxy += float(np.vdot(gx, gy))
        gy *= weight
        jyy += float(np.vdot(gy, gy))
    total = jxx + jyy
    if total <= 0:
        return None
    tilt = 0.5 * math.degrees(math.atan2(2 * jxy, jxx - jyy))
    return EdgeTilt(tilt, math.hypot(jxx - jyy, 2 * jxy) / total)


def tilt_warning(tilt: EdgeTilt | None, n_angles: int) -> str | None:
    """A warning when straight element edges are tilted beyond :data:`MAX_TILT_DEG` and
    `n_angles` frames carry a deflection angle, else None.

    Edges whose normal lies nearer the columns than the rows (|tilt| over 45 deg: a long
    narrow contact whose sides along the rows dominate, helper-15's review) are not the
    elements' front and back edges, and are not judged.

    Parameters
    ----------
    tilt : EdgeTilt or None
        :func:`edge_tilt` of the video.
    n_angles : int
        Frames that carry a deflection angle.

    Returns
    -------
    str or None
    """
    if (tilt is None or not tilt.straight or abs(tilt.tilt_deg) <= MAX_TILT_DEG
            or abs(tilt.tilt_deg) > 45.0 or n_angles == 0):
        return None
    return (f"the element edges are tilted {tilt.tilt_deg:+.1f} deg against the image "
            "columns (the camera is turned about its axis, or the block slides askew): the "
            "block is taken to slide along the image rows, and its deflection angles drift "
            "with the tilt (on synthetic blocks by about 1 deg at a 2 deg turn and 2 deg "
            "at 3 deg); turn the camera or the footage so that the edges run along the "
            "columns")
