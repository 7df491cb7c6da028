"""Random footage specs from the domain of real TIR and side-view footage.

The analysis pipeline was built with the renderer's defaults (lit frame, strong clean
signal, a block crossing a fixed view, solid contact). :func:`sample_spec` draws clips from
the ranges real footage shows, so that the pipeline can be validated on footage it was not
designed around. Every draw comes from the generator passed in: the same seed gives the
same specs.

Case classes (drawn with equal probability)
-------------------------------------------
``"tir passing block"``
    Fixed TIR camera, the block enters, crosses and leaves the view.
``"tir follow camera"``
    TIR camera moving with the block (block fixed, ice moving).
``"tir static pad"``, ``"tir static coin"``, ``"tir static three-point"``
    Static contacts: round pad (radius 1.5-4 mm), coin rim (outer radius 3-8 mm, rim
    0.3-1.5 mm wide), three points (radius 0.7-1.3 mm; in half the clips near the rim of
    the lit zone, at 75-95 % of its size from its centre, else within 50 %; the size is the
    radius of a disc of the requested lit area, for a band at most half the frame's
    smaller side, for a fully lit frame half its smaller side).
``"side fixed"``, ``"side follow"``
    Side view, fixed or following camera.

Ranges (uniform unless said)
----------------------------
* Frame: width 160-320 px, height 96-256 px; 0.05-0.15 mm/px for the sliding block, 0.03-
  0.08 mm/px for the static scenes (a real FTIR photograph: 0.036 mm/px); a side view at
  least 16 mm high (the elements, base and carrier above the ice line in view), and a
  following side camera at least twice the block's 20 mm wide (the block's background is
  seen beside it; up to 800 px wide then); a following TIR camera at least 26 mm wide
  (free surface in view before and behind the 20 mm block: a frame filled with contact
  has nothing to measure it against); a coin at most 0.45 of the smaller side of the view
  in radius (a dark ring cut by the frame's corners looks like the unlit outside of a lit
  disc).
* Clip: 40-120 frames; block: preset G0, G3, G5, G6 or G7, 0.5-3 m/s, 1.5-4 bar, steady
  state of a 4 ms model run (``dynamics="steady"``: every clip integrates the model once,
  about 0.5 s); the frame rate makes the pass of a fixed camera fill the clip (image width
  plus block length plus 10 mm of travel), 500-20000 frames/s; exposure 0-40 us (at most
  1/fps); sliding direction left or right; rotation 0 in 70 % of the fixed TIR and side
  clips, else -8..8 deg.
* Light: TIR lit zone "full" in 25 % of the clips, else disc, ellipse or band covering
  20-100 % of the frame with a rim of 0.3-3 mm, centred within 15 % of the field of view of
  the image centre, outside level 0.02-0.1; vignetting 0-0.6; illumination gradient 0-0.3;
  recorded free-surface level (white level x gain) 0.3-0.9 of full scale.
* Sensor: 8 bit in 70 % of the clips, else 12 bit; JPEG (quality 70-95) on half of the 8-bit
  clips; gain 1-4; contact dark in 90 % of the clips, else bright.
* Contact: TIR real contact patchy in half of the clips (patch correlation 0.1-0.4 mm),
  else solid.
* Ice: 0-40 bubbles, 0-10 scratches, groove depth 0-0.1, 0-40 dust particles.

With these ranges 200 clips render in a few minutes on one core (measured: 257 s through
:func:`synthetic.footage.iter_frames` on a shared 2-core machine; most of the time in
the patchy clips and the model runs).

Examples
--------
>>> specs = sample_specs(3, seed=1)
>>> [case for _, case in specs] == [case for _, case in sample_specs(3, seed=1)]
True
"""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np

from synthetic._lighting import LIT_SHAPES
from synthetic._render_tir import ice_flaws_expected
from synthetic.footage import CameraSettings, FootageSpec

__all__ = [
    "CASE_CLASSES",
    "PHYSICAL_CASE_CLASSES",
    "real_photo_specs",
    "sample_physical_spec",
    "sample_physical_specs",
    "sample_spec",
    "sample_specs",
]

logger = logging.getLogger(__name__)

#: The case classes :func:`sample_spec` draws from (equally likely).
CASE_CLASSES: tuple[str, ...] = (
    "tir passing block",
    "tir follow camera",
    "tir static pad",
    "tir static coin",
    "tir static three-point",
    "side fixed",
    "side follow",
)
_PRESETS = ("G0", "G3", "G5", "G6", "G7")
#: The lit shapes with a rim (``"full"`` is drawn apart).
_LIT_SHAPES = tuple(s for s in LIT_SHAPES if s != "full")
#: Block length of the reference samples, mm.
_BLOCK_MM = 20.0
#: Least image height of a side view, mm: 6 mm elements, 2 mm base and 3 mm carrier above
#: the ice line at 3/4 of the height, with 1 mm to spare.
_SIDE_VIEW_MM = 16.0


def _u(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


def _camera(rng: np.random.Generator, case: str, *, static: bool) -> dict[str, Any]:
    """Camera fields shared by every case (frame, light, sensor, scene clutter)."""
    tir = case.startswith("tir")
    bit_depth = 8 if rng.random() < 0.7 else 12
    cam: dict[str, Any] = {
        "width_px": int(rng.integers(160, 321)),
        "height_px": int(rng.integers(96, 257)),
        "mm_per_px": _u(rng, 0.03, 0.08) if static else _u(rng, 0.05, 0.15),
        "bit_depth": bit_depth,
        "gain": _u(rng, 1.0, 4.0),
        # the recorded free-surface level (white level x gain) is 0.3-0.9 of full scale: a
        # rig's exposure is set below saturation (a saturated free surface hides how
        # much light a contact removes); the gain amplifies the noise
        "white_level": _u(rng, 0.3, 0.9),
        "vignetting": _u(rng, 0.0, 0.6),
        "illumination_gradient": _u(rng, 0.0, 0.3),
        "n_bubbles": int(rng.integers(0, 41)),
        "n_scratches": int(rng.integers(0, 11)),
        "groove_depth": _u(rng, 0.0, 0.1),
        "n_dust": int(rng.integers(0, 41)),
    }
    if bit_depth == 8 and rng.random() < 0.5:
        cam["jpeg_quality"] = int(rng.integers(70, 96))
    if not tir:
        # a side camera is framed to show the whole element height with the block base
        # above it (the root of each element is where its angle is measured from): at
        # least _SIDE_VIEW_MM of height (the ice line lies at 3/4 of the height)
        cam["mm_per_px"] = max(cam["mm_per_px"], _SIDE_VIEW_MM / cam["height_px"])
        if case == "side follow":  # the block, 20 mm long, spans at most half the width
            cam["width_px"] = max(cam["width_px"], math.ceil(2.0 * _BLOCK_MM / cam["mm_per_px"]))
    if case == "tir follow camera":  # free surface in view before and behind the block
        cam["width_px"] = max(cam["width_px"], math.ceil((_BLOCK_MM + 6.0) / cam["mm_per_px"]))
    fixed_path = case in ("tir passing block", "side fixed")
    cam["rotation_deg"] = _u(rng, -8.0, 8.0) if fixed_path and rng.random() >= 0.7 else 0.0
    if tir and rng.random() >= 0.25:
        w_mm = cam["width_px"] * cam["mm_per_px"]
        h_mm = cam["height_px"] * cam["mm_per_px"]
        cam.update(
            lit_shape=str(rng.choice(_LIT_SHAPES)),
            lit_fraction=_u(rng, 0.2, 1.0),
            lit_rim_mm=_u(rng, 0.3, 3.0),
            lit_center_mm=(_u(rng, -0.15, 0.15) * w_mm, _u(rng, -0.15, 0.15) * h_mm),
            outside_level=_u(rng, 0.02, 0.1),
        )
    return cam


def _timing(rng: np.random.Generator, cam: dict[str, Any], velocity_mps: float, n: int) -> None:
    """Frame rate and exposure: a fixed camera's pass fills the clip."""
    travel_mm = cam["width_px"] * cam["mm_per_px"] + _BLOCK_MM + 10.0
    fps = float(np.clip(velocity_mps * 1e3 * (n - 1) / travel_mm, 500.0, 20000.0))
    cam["fps"] = fps
    cam["exposure_s"] = min(_u(rng, 0.0, 40e-6), 1.0 / fps)


def _static_fields(rng: np.random.Generator, case: str, cam: dict[str, Any]) -> dict[str, Any]:
    if case == "tir static pad":
        return {"scene": "round_pad", "pad_radius_mm": _u(rng, 1.5, 4.0)}
    if case == "tir static coin":
        # the coin inside the view: a dark ring cut by the frame's corners cannot be told
        # from the unlit outside of a lit disc
        w_mm = cam["width_px"] * cam["mm_per_px"]
        h_mm = cam["height_px"] * cam["mm_per_px"]
        outer = min(_u(rng, 3.0, 8.0), 0.45 * min(w_mm, h_mm))
        return {"scene": "coin", "coin_radii_mm": (outer - _u(rng, 0.3, 1.5), outer)}
    # three points, near the rim of the lit zone in half of the clips
    w_mm = cam["width_px"] * cam["mm_per_px"]
    h_mm = cam["height_px"] * cam["mm_per_px"]
    if cam.get("lit_shape", "full") == "full":
        reach = 0.5 * min(w_mm, h_mm)
    else:
        reach = math.sqrt(cam["lit_fraction"] * w_mm * h_mm / math.pi)  # disc of that area
        reach = min(reach, 0.5 * min(w_mm, h_mm)) if cam["lit_shape"] == "band" else reach
    near_rim = rng.random() < 0.5
    angles = rng.uniform(0.0, 2.0 * math.pi, 3)
    dist = rng.uniform(0.75, 0.95, 3) if near_rim else rng.uniform(0.0, 0.5, 3)
    pts = tuple(
        (float(d * reach * math.cos(a)), float(d * reach * math.sin(a)))
        for d, a in zip(dist, angles, strict=True)
    )
    return {
        "scene": "three_point",
        "point_radius_mm": _u(rng, 0.7, 1.3),
        "point_positions_mm": pts,
    }


def sample_spec(rng: int | np.random.Generator | None = None) -> tuple[FootageSpec, str]:
    """Draw one random clip from the real-footage domain (ranges in the module notes).

    Parameters
    ----------
    rng : int, numpy.random.Generator or None
        Seed or generator (``numpy.random.default_rng(rng)``).

    Returns
    -------
    spec : FootageSpec
    case_class : str
        One of :data:`CASE_CLASSES`.
    """
    rng = np.random.default_rng(rng)
    case = CASE_CLASSES[int(rng.integers(len(CASE_CLASSES)))]
    static = "static" in case
    cam = _camera(rng, case, static=static)
    n_frames = int(rng.integers(40, 121))
    velocity = _u(rng, 0.5, 3.0)
    cam["white_level"] /= cam["gain"]
    _timing(rng, cam, velocity, n_frames)
    fields: dict[str, Any] = {
        "preset": str(rng.choice(_PRESETS)),
        "view": "tir" if case.startswith("tir") else "side",
        "velocity_mps": velocity,
        "n_frames": n_frames,
        "pressure_bar": _u(rng, 1.5, 4.0),
        "sliding_direction": "left" if rng.random() < 0.5 else "right",
        "contact_is": "dark" if rng.random() < 0.9 else "bright",
        "seed": int(rng.integers(0, 2**31)),
        "follow_camera": case in ("tir follow camera", "side follow"),
        "dynamics": "steady",
        "settle_s": 0.004,
    }
    if case.startswith("tir") and rng.random() < 0.5:
        fields.update(real_contact="patchy", patch_correlation_mm=_u(rng, 0.1, 0.4))
    if static:
        fields.update(_static_fields(rng, case, cam))
    spec = FootageSpec(camera=CameraSettings(**cam), **fields)
    return spec, case


def sample_specs(n: int, seed: int | None = 0) -> list[tuple[FootageSpec, str]]:
    """``n`` independent draws of :func:`sample_spec` from one seeded generator.

    Parameters
    ----------
    n : int
        Number of clips, >= 0.
    seed : int or None
        Seed of ``numpy.random.default_rng``; the same seed gives the same specs.

    Returns
    -------
    list of (FootageSpec, str)
    """
    return _draws(sample_spec, n, seed)


def _draws(draw: Any, n: int, seed: int | None) -> list[tuple[FootageSpec, str]]:
    """``n`` draws of ``draw(rng)`` from one generator seeded with ``seed``."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise TypeError(f"n must be an integer, got {type(n).__name__}: {n!r}")
    if n < 0:
        raise ValueError(f"n must be >= 0, got n={n!r}")
    rng = np.random.default_rng(seed)
    return [draw(rng) for _ in range(int(n))]


def real_photo_specs(seed: int = 0, *, n_frames: int = 10) -> dict[str, FootageSpec]:
    """Specs that imitate the two real FTIR photographs the pipeline failed on.

    Both: 8-bit JPEG (quality 85) of 640 x 512 px at 0.0357 mm/px, white level 0.4 (the
    free surface near grey 100), vignetting 0.5, illumination gradient 0.05, a lit disc
    covering 28 % of the frame with a 2 mm rim and 9 % of the light outside (the
    photograph's median grey 9), patchy real contact.

    * ``"round pad"``: one static round contact of radius 2.75 mm (77 px) in the lit disc.
    * ``"three points"``: three round contacts of radius 1 mm near the rim of the lit disc
      at 80 % of the lit disc's radius (about 6.1 mm) from its centre, at 100, 140 and
      180 deg.

    Parameters
    ----------
    seed : int
        Seed of the scene and the noise.
    n_frames : int
        Frames of each clip (static: only the noise changes).

    Returns
    -------
    dict of str to FootageSpec
    """
    cam = CameraSettings(
        width_px=640,
        height_px=512,
        mm_per_px=0.0357,
        bit_depth=8,
        white_level=0.4,
        vignetting=0.5,
        illumination_gradient=0.05,
        lit_shape="disc",
        lit_fraction=0.28,
        lit_rim_mm=2.0,
        outside_level=0.09,
        jpeg_quality=85,
    )
    area = 0.28 * cam.width_px * cam.height_px * cam.mm_per_px**2
    radius = math.sqrt(area / math.pi)
    pts = tuple(
        (0.8 * radius * math.cos(math.radians(a)), -0.8 * radius * math.sin(math.radians(a)))
        for a in (100.0, 140.0, 180.0)
    )
    common = {"camera": cam, "n_frames": n_frames, "seed": seed, "real_contact": "patchy"}
    return {
        "round pad": FootageSpec(scene="round_pad", pad_radius_mm=2.75, **common),
        "three points": FootageSpec(
            scene="three_point", point_radius_mm=1.0, point_positions_mm=pts, **common
        ),
    }


#: The physical case classes :func:`sample_physical_spec` draws from (equally likely):
#: contact from the rough-contact solver and frustrated-TIR optics (needs the contact extra).
PHYSICAL_CASE_CLASSES: tuple[str, ...] = (
    "tir rough pad",
    "tir rough sphere",
    "tir physical block",
)


def sample_physical_spec(rng: int | np.random.Generator | None = None) -> tuple[FootageSpec, str]:
    """Draw one clip of the physical world (contact mechanics and optics).

    Ranges (uniform unless said): the camera, light, sensor and ice of :func:`sample_spec`
    (the lit zone drawn for its static view and scaled with the view: the same share of the
    frame, its rim as many pixels; the ice's bubbles and scratches drawn as densities over
    the thesis's field of view and counted in this one, :func:`_ice_flaws_in_view`, none of
    them bubbles on glass; the camera's dust as drawn, in pixels) with the static pixel
    scale 0.004-0.03 mm/px for the pad and the sphere (junctions from a fifth of a pixel to
    several pixels wide) and 0.05-0.12 mm/px for the block, rotation 0; roughness any of
    :data:`synthetic.roughness.ROUGHNESS_PRESETS`; pressure 0.5-4 bar;
    a lens blur of 0-1.5 px; a free-surface texture of 0-0.15 (rms, correlation 0.02-0.2
    mm) in half of the clips; substrate ice (glass in a quarter of the clips); pad radius
    0.3-0.45 of the smaller side of the view; sphere radius 2-8 mm; 10-40 frames (static) or
    40-80 (block, steady state).

    Parameters
    ----------
    rng : int, numpy.random.Generator or None

    Returns
    -------
    spec : FootageSpec
    case_class : str
        One of :data:`PHYSICAL_CASE_CLASSES`.
    """
    from synthetic.roughness import ROUGHNESS_PRESETS

    rng = np.random.default_rng(rng)
    case = PHYSICAL_CASE_CLASSES[int(rng.integers(len(PHYSICAL_CASE_CLASSES)))]
    block = case == "tir physical block"
    cam = _camera(rng, "tir static pad", static=True)
    cam["rotation_deg"] = 0.0
    cam["white_level"] /= cam["gain"]
    old_scale = cam["mm_per_px"]
    cam["mm_per_px"] = _u(rng, 0.05, 0.12) if block else _u(rng, 0.004, 0.03)
    cam["optical_blur_mm"] = _u(rng, 0.0, 1.5) * cam["mm_per_px"]
    if "lit_center_mm" in cam:  # the lit zone was drawn for the view at the other scale
        ratio = cam["mm_per_px"] / old_scale
        cam["lit_center_mm"] = tuple(float(c * ratio) for c in cam["lit_center_mm"])
        # its rim too: left at the other scale's 0.3-3 mm it spanned up to 750 px (40-470
        # px in the validation's draws) of a 100-300 px frame, the zone's lit plateau and
        # its outside were not both in view, and the truth (contact inside the rim's
        # half-light line) left out contact seen at a third of the light
        cam["lit_rim_mm"] = float(cam["lit_rim_mm"] * ratio)
    w_mm = cam["width_px"] * cam["mm_per_px"]
    h_mm = cam["height_px"] * cam["mm_per_px"]
    fields: dict[str, Any] = {
        "view": "tir",
        "pressure_bar": _u(rng, 0.5, 4.0),
        "seed": int(rng.integers(0, 2**31)),
        "roughness": str(rng.choice(sorted(ROUGHNESS_PRESETS))),
        "substrate": "glass" if rng.random() < 0.25 else "ice",
        "dynamics": "steady",
        "settle_s": 0.004,
    }
    if rng.random() < 0.5:
        fields.update(texture=_u(rng, 0.0, 0.15), texture_mm=_u(rng, 0.02, 0.2))
    if block:
        n_frames = int(rng.integers(40, 81))
        velocity = _u(rng, 0.5, 3.0)
        _timing(rng, cam, velocity, n_frames)
        fields.update(
            preset=str(rng.choice(_PRESETS)),
            real_contact="physical",
            velocity_mps=velocity,
            n_frames=n_frames,
            sliding_direction="left" if rng.random() < 0.5 else "right",
        )
        fields.pop("texture", None)
        fields.pop("texture_mm", None)
    else:
        fields["n_frames"] = int(rng.integers(10, 41))
        if case == "tir rough pad":
            fields.update(scene="rough_pad",
                          pad_radius_mm=_u(rng, 0.3, 0.45) * min(w_mm, h_mm))
        else:
            fields.update(scene="rough_sphere", sphere_radius_mm=_u(rng, 2.0, 8.0))
    cam.update(_ice_flaws_in_view(cam, fields["seed"], glass=fields["substrate"] == "glass"))
    spec = FootageSpec(camera=CameraSettings(**cam), **fields)
    return spec, case


def _ice_flaws_in_view(cam: dict[str, Any], seed: int, *, glass: bool) -> dict[str, int]:
    """The bubbles and scratches a physical clip's view holds: the counts drawn for the
    domain's view (0-40 bubbles, 0-10 scratches: ``cam``'s, read as the counts of the
    thesis's 64 x 25.6 mm field, :data:`synthetic._render_tir.THESIS_FIELD_MM`, where the
    renderer's default flaws hold) as densities of the ice, seen in
    this view (:func:`synthetic._render_tir.ice_flaws_expected`: bubbles by area,
    scratches by the ones that cross it).

    Each count is a Poisson draw with that mean from a generator of its own, seeded by the
    clip's seed (the draws of the clip's other fields stay as they were). Glass holds no
    bubbles.

    The domain's counts were kept per view at the physical world's 0.004-0.12 mm/px: a
    1.3 mm view held up to 40 bubbles of 0.05-0.3 mm (more than it can show side by side,
    1000 times the thesis's ice), which the static scenes read as contact; a bug of the
    kind of the lit rim left at the domain's scale.
    """
    w_mm, h_mm = cam["width_px"] * cam["mm_per_px"], cam["height_px"] * cam["mm_per_px"]
    bubbles, scratches = ice_flaws_expected(
        w_mm, h_mm, bubbles_per_field=cam["n_bubbles"], scratches_per_field=cam["n_scratches"])
    rng = np.random.default_rng([int(seed), 0x1CE])
    bubbles = 0.0 if glass else bubbles
    return {"n_bubbles": int(rng.poisson(bubbles)), "n_scratches": int(rng.poisson(scratches))}


def sample_physical_specs(n: int, seed: int | None = 0) -> list[tuple[FootageSpec, str]]:
    """``n`` independent draws of :func:`sample_physical_spec` from one seeded generator.

    Kept apart from :func:`sample_specs` so that its draws (and the published validation
    of the domain) stay what they were.
    """
    return _draws(sample_physical_spec, n, seed)
