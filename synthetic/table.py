"""Renders of the kind of the real images of issue 21's table (the images themselves are
not ours to ship).

Each entry of :func:`table_specs` is a :class:`~synthetic.footage.FootageSpec`; its truth is
the renderer's ground truth (``contact_area_mm2`` of the ``element == -1`` rows: contact
inside the lit mask). What each render assumes:

``"three points, fold"``
    The camera of :func:`synthetic.domain.real_photo_specs` (8-bit JPEG q85, 640 x 512 px at
    0.0357 mm/px, a vignetted lit disc over 28 % of the frame with a 2 mm rim, patchy real
    contact), three round contacts of radius :data:`POINT_RADIUS_MM` at 80 % of the disc's
    radius (near the rim, at 100, 140 and 180 deg; with the patchy share about 8 mm2 of
    real contact together, as in the issue), and a darker fold
    on the other side of the disc: a straight band along y where the light falls steeply
    (over :data:`FOLD_EDGE_MM`) to ``1 - FOLD_DEPTH`` (:data:`FOLD_DEPTH` = 0.5, deeper than
    the contacts' own near-contact grey at their rim). The fold is light, not contact: the
    truth has none there.
``"round pad"``
    :func:`~synthetic.domain.real_photo_specs`' round pad: a static round contact of
    radius 2.75 mm (a coin pressed on a pad, 23.8 mm2 nominal) in the vignetted lit disc,
    8-bit JPEG.
``"smooth sphere on glass"``
    A smooth elastomer sphere on glass: its contact is the Hertz disc, in full optical
    contact everywhere inside (gap 0, so the frustrated-TIR darkness is the same over the
    disc), covering :data:`SPHERE_SHARE` of an evenly lit frame (``scene="round_pad"``,
    solid contact: a smooth surface has no real-contact patches at this scale).
``"bright patches"``
    Fluorescent contact: patchy real contact drawn bright on a dark field
    (``contact_is="bright"``), in a round pad of radius 3 mm at 0.05 mm/px.

:func:`empty_reference` renders the rig's own empty frame of a spec (the same light, ice and
dust, no contact) at another exposure and shifted by a few pixels, as a user's
``--reference``.
"""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np

from synthetic._physical import PHYSICAL_SCENES
from synthetic.domain import real_photo_specs
from synthetic.footage import CameraSettings, FootageSpec, _Clip

__all__ = [
    "EMPTY_REFERENCE_SCENES",
    "FOLD_DEPTH",
    "FOLD_EDGE_MM",
    "POINT_RADIUS_MM",
    "REFERENCE_EXPOSURE",
    "REFERENCE_SHIFT_PX",
    "SPHERE_SHARE",
    "TABLE_NAMES",
    "empty_reference",
    "table_specs",
]

#: Radius of the three contacts, mm: 12.7 mm2 nominal, about 8 mm2 of real (patchy) contact.
POINT_RADIUS_MM = 1.16
#: Share of the light lost in the fold's core (issue 21: "falls off steeply at one side").
FOLD_DEPTH = 0.5
#: Width of each edge of the fold, mm (about 8 px: steep against the 2 mm rim).
FOLD_EDGE_MM = 0.3
#: Share of the frame the smooth sphere's contact covers (issue 21: "about 14 %").
SPHERE_SHARE = 0.14
#: Exposure of the rig's empty frame relative to the footage (issue 21: 0.87x).
REFERENCE_EXPOSURE = 0.87
#: Shift of the empty frame against the footage, px (x, y): "a few px".
REFERENCE_SHIFT_PX = (3.0, -2.0)
#: The names :func:`table_specs` returns, in the issue table's order.
TABLE_NAMES = ("round pad", "smooth sphere on glass", "bright patches", "three points, fold")
#: The scenes :func:`empty_reference` renders an empty frame of: the static scenes whose
#: light does not depend on where the contact is.
EMPTY_REFERENCE_SCENES = ("three_point", *PHYSICAL_SCENES)


def table_specs(seed: int = 0, *, n_frames: int = 6) -> dict[str, FootageSpec]:
    """The renders of issue 21's table (see the module notes for what each assumes).

    Parameters
    ----------
    seed : int
        Seed of the scenes and the noise.
    n_frames : int
        Frames of each clip (all static: only the noise changes).

    Returns
    -------
    dict of str to FootageSpec
        Keyed by :data:`TABLE_NAMES`.

    Examples
    --------
    >>> specs = table_specs(n_frames=2)
    >>> sorted(specs) == sorted(TABLE_NAMES)
    True
    >>> specs["three points, fold"].camera.fold_depth
    0.5
    """
    photo = real_photo_specs(seed, n_frames=n_frames)
    three = photo["three points"]
    cam = three.camera
    disc_r = math.sqrt(cam.lit_fraction * cam.width_px * cam.height_px / math.pi) * cam.mm_per_px
    # the contacts lie at 100-180 deg (left); the fold crosses the right half of the disc
    fold = dataclasses.replace(cam, fold_depth=FOLD_DEPTH, fold_x_mm=0.45 * disc_r,
                               fold_width_mm=0.2 * disc_r, fold_edge_mm=FOLD_EDGE_MM)
    even = CameraSettings(width_px=320, height_px=256, mm_per_px=0.05, vignetting=0.1,
                          illumination_gradient=0.05)
    w_mm, h_mm = even.field_of_view_mm
    return {
        "round pad": photo["round pad"],
        "smooth sphere on glass": FootageSpec(
            scene="round_pad", pad_radius_mm=math.sqrt(SPHERE_SHARE * w_mm * h_mm / math.pi),
            camera=even, n_frames=n_frames, seed=seed),
        "bright patches": FootageSpec(
            scene="round_pad", pad_radius_mm=3.0, real_contact="patchy", contact_is="bright",
            camera=even, n_frames=n_frames, seed=seed),
        "three points, fold": dataclasses.replace(three, camera=fold,
                                                  point_radius_mm=POINT_RADIUS_MM),
    }


def empty_reference(spec: FootageSpec, *, exposure: float = REFERENCE_EXPOSURE,
                    shift_px: tuple[float, float] = REFERENCE_SHIFT_PX) -> np.ndarray:
    """The rig's own empty frame of a static scene: the same light, ice, dust, stray light
    and seed without the contact, at ``exposure`` times the white level, moved by
    ``shift_px`` (x, y; bilinear, edges replicated), losslessly.

    The scene is rendered without its contact (``_Clip(..., contact=False)``): its light
    before the contact darkens it, the rubber lifted off, what a rig records before
    loading.

    Parameters
    ----------
    spec : FootageSpec
        A scene of :data:`EMPTY_REFERENCE_SCENES`.
    exposure : float
        Exposure relative to the footage, in (0, 1 / white_level].
    shift_px : (float, float)

    Returns
    -------
    (H, W) ndarray of the clip's dtype
    """
    if spec.scene not in EMPTY_REFERENCE_SCENES:
        raise ValueError(f"scene must be one of {', '.join(EMPTY_REFERENCE_SCENES)} for an "
                         f"empty reference, got scene={spec.scene!r}")
    level = spec.camera.white_level * exposure
    if not 0.0 < level <= 1.0:
        raise ValueError(f"exposure must keep white_level * exposure in (0, 1], got "
                         f"exposure={exposure!r} with white_level={spec.camera.white_level}")
    cam = dataclasses.replace(spec.camera, white_level=level, jpeg_quality=None)
    clip = _Clip(dataclasses.replace(spec, camera=cam), contact=False)
    # noise of its own, drawn as for the frame after the clip's last (a copy of a frame's
    # noise would cancel that frame's noise wherever the analysis aligns the two)
    image = clip.image(spec.n_frames)[0]
    m = np.float32([[1, 0, shift_px[0]], [0, 1, shift_px[1]]])
    return cv2.warpAffine(image, m, image.shape[::-1], flags=cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_REPLICATE)

