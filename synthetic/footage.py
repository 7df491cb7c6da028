"""Synthetic high-speed footage of a tread block sliding over ice, with exact ground truth.

Two views of the experiment of thesis section 4.3.6 / 4.3.1:

* ``view="tir"``: the camera under the acrylic prism looks up through the ice (Fig. 4.20 a,
  4.21). The free ice surface reflects the light totally (bright); where rubber touches the
  ice the total reflection is frustrated (dark, or bright with ``contact_is="bright"``),
  darker where the contact pressure is higher, so the pressure peak at each element's front
  edge shows as a darker band.
* ``view="side"``: a camera beside the track sees the elements deformed over the ice surface
  line (Fig. 4.11 b, 5.14).

The block is the reference sample ``preset`` (20 mm x 80 mm, 0/3/5/6/7 sipes,
:func:`friction_model.reference_block`). Its elements move as the rigid-bar block model with
face contact predicts (:func:`friction_model.dynamics.rigid.simulate_block_dynamics`, set up
as in :mod:`friction_model.dynamics.contact`): the model is integrated once per spec and gives
every element's tilt, deflection and contact fraction at every frame (``dynamics="simulated"``)
or their steady means (``dynamics="steady"``).

Orientation, scale and timing (defaults)
----------------------------------------
The block slides along the image x axis (``sliding_direction="left"``: from right to left,
as in Fig. 4.21), element 0 leads. At 0.1 mm/px the 640 x 256 px image covers 64 mm of the
path and 25.6 mm of the 80 mm block width: the TIR view shows a band of the footprint about
the block centreline (the contact model does not vary across the width, so the visible band
has the block's contact ratio), and all areas in the ground truth are the visible part. The
pass is centred in the clip: the block centre crosses the image centre at the clip's middle
(``center_time_s``). At the default 4000 frames/s and 1 m/s the block travels 0.25 mm = 2.5 px
per frame and 100 mm in the 400-frame clip, so it enters, crosses the 64 mm view (84 mm of
travel from first to last contact) and leaves, with about 8 % of the frames empty at either
end. Other speeds or frame rates change the travel per frame; the pass stays centred.

Time and coordinates
--------------------
Frame ``k`` is exposed over ``exposure_s`` centred on ``time_s = k / fps``. Image x and y are
in mm from the left and top image edges (pixel ``(r, c)`` covers ``[c, c+1) * mm_per_px`` in
x); ground-truth positions are image x of points on the block centreline. The file layout and
every column are described in ``docs/footage_format.md``.

Examples
--------
>>> spec = FootageSpec(preset="G3", dynamics="steady", settle_s=0.004)
>>> frames = iter_frames(spec)
>>> k, image, truth = next(frames)  # frame 0: the block has not reached the view yet
>>> image.shape, image.dtype, list(truth["element"])
((256, 640), dtype('uint8'), [-1])
>>> truth["contact_area_mm2"].tolist()
[0.0]
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import math
import numbers
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from friction_model.geometry import REFERENCE_SAMPLES, BlockGeometry, reference_block
from synthetic._camera import Sensor, dust_field, illumination_field, max_dn
from synthetic._render_side import (
    SideLayout,
    deflection_angles,
    ice_texture_frame,
    render_side_signal,
    rotate_scene,
)
from synthetic._render_tir import (
    ContactParams,
    ElementFrame,
    PathGeometry,
    block_profile,
    block_row,
    element_contacts,
    element_row,
    ice_transmission,
    render_tir_signal,
    tir_truth_rows,
)
from synthetic._writers import FrameSink, open_sink, write_meta

__all__ = [
    "TRUTH_COLUMNS",
    "CameraSettings",
    "FootageSpec",
    "iter_frames",
    "render_footage",
]

logger = logging.getLogger(__name__)

#: Columns of ``ground_truth.csv`` and of the per-frame tables of :func:`iter_frames`.
TRUTH_COLUMNS = (
    "frame",
    "time_s",
    "element",
    "in_view",
    "contact_area_mm2",
    "contact_length_mm",
    "front_edge_x_mm",
    "front_peak_x_mm",
    "deflection_angle_deg",
    "tilt_deg",
    "tip_deflection_mm",
    "contact_fraction",
    "normal_force_N",
    "peak_pressure_MPa",
    "lever_arm_mm",
)

#: Friction law of :mod:`friction_model.dynamics.contact` (Eq. 5.7; mu = 0.26 at 1 m/s).
_EQ57 = {"a1": 0.15, "a2": 0.25, "a3": -0.8}
#: Fraction of the settling run averaged for ``dynamics="steady"`` (as in
#: :func:`friction_model.dynamics.contact.reference_contact_ratios`).
_STEADY_FRACTION = 0.3
#: Relative and absolute tolerance of the rigid-model integration (angles in rad). The
#: rendered geometry needs the angles to ~0.01 deg. At rtol 1e-4 the phase of the
#: self-excited stick-slip depends on the solver's step choice, and the ``steady`` average,
#: whose window may end mid-cycle, moved by 8 % between scipy 1.10 and 1.17; at 1e-5 both
#: agree with the converged value (rtol 1e-8) to 1e-4 relative, for 20 % more run time.
_RTOL, _ATOL = 1e-5, 1e-8
#: Side view: image row of the ice surface line as a fraction of the image height.
_SIDE_ICE_ROW = 0.75
#: Fields of the velocity step and the friction relaxation and their defaults (left out of
#: ``FootageSpec.to_dict`` at these values).
_STEP_FIELDS = ("velocity_step_to_mps", "step_time_s", "friction_relaxation_s")
_STEP_DEFAULTS: dict[str, Any] = {
    "velocity_step_to_mps": None,
    "step_time_s": None,
    "friction_relaxation_s": 0.0,
}


# -- validation helpers --------------------------------------------------------------------
def _real(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}: {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {name}={value!r}")
    return value


def _in_range(
    name: str, value: Any, low: float, high: float, *, low_open: bool = False, unit: str = ""
) -> float:
    v = _real(name, value)
    ok = (low < v if low_open else low <= v) and v <= high
    if not ok:
        br = "(" if low_open else "["
        u = f" {unit}" if unit else ""
        raise ValueError(f"{name} must lie in {br}{low:g}, {high:g}]{u}, got {name}={value!r}")
    return v


def _integer(name: str, value: Any, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}: {value!r}")
    if not low <= int(value) <= high:
        raise ValueError(f"{name} must lie in [{low}, {high}], got {name}={value!r}")
    return int(value)


def _choice(name: str, value: Any, options: tuple[Any, ...]) -> Any:
    if value not in options:
        raise ValueError(f"{name} must be one of {list(options)}, got {name}={value!r}")
    return value


def _flag(name: str, value: Any) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a bool, got {type(value).__name__}: {value!r}")
    return bool(value)


# -- public settings -------------------------------------------------------------------------
@dataclass(frozen=True)
class CameraSettings:
    """High-speed camera, optics and the static scene seen through them.

    Parameters
    ----------
    fps : float
        Frame rate, frames/s, in (0, 1e7]. 4000 is a common high-speed rate; at 1 m/s the
        default 400-frame clip then spans 100 mm of travel, enough for the whole pass.
    exposure_s : float
        Exposure (shutter) time, s, in [0, 1/fps]; the motion blur is ``v * exposure_s``
        (20 us: 0.02 mm = 0.2 px at 1 m/s, a typical short shutter under bright TIR light).
        0 renders without blur.
    mm_per_px : float
        Pixel pitch in the object plane, mm/px, in (0, 10]. 0.1 mm/px resolves the 0.6 mm
        sipes with 6 px and the 2 mm elements of G7 with 20 px.
    width_px, height_px : int
        Image size, px, each in [16, 16384]; 640 x 256, a common high-speed sub-window.
    bit_depth : {8, 12, 16}
        Bits per sample; 12-bit frames are stored in uint16 (0..4095, not shifted).
    gain : float
        Gain relative to unity (at which the full well maps to the largest digital number),
        in (0, 100]; it scales signal and noise, the free surface saturates above
        ``1 / white_level``.
    read_noise_dn : float, optional
        Read-noise standard deviation, DN of the output bit depth, >= 0. Default: 20
        electrons (a typical high-speed CMOS sensor) converted with the gain and bit depth.
    full_well_e : float
        Full-well capacity, electrons, in [100, 1e7]; 16000 e- is typical of high-speed CMOS
        pixels (~20 um).
    white_level : float
        Level of the free (totally reflecting) ice surface at the image centre, fraction of
        full scale, in (0, 1]; 0.8 leaves the usual headroom against saturation.
    shot_noise : bool
        Poisson noise of the photo-electrons.
    rotation_deg : float
        Rotation of the block path (TIR) or of the whole scene (side view) against the image
        x axis, deg, in [-45, 45]; positive turns +x towards +y.
    illumination_gradient : float
        Rise of the illumination from the left to the right image edge as a fraction of the
        centre level, in [0, 1); 0.15: a prism lit from one side.
    vignetting : float
        Light fall-off in the image corners, fraction, in [0, 1); 0.2 is typical of a lens
        used near full aperture.
    n_bubbles : int
        Air bubbles in the ice within the view, in [0, 10000]; 12 as in the few bubbles of
        Fig. 4.20 b. In the side view: bubbles in the ice slab per image width.
    n_scratches : int
        Scratches on the ice surface, in [0, 10000]; 5 for a track used a few times.
    groove_depth : float
        Darkening at the centre of a worn groove along the track, fraction, in [0, 1); 0.05:
        a shallow rut hardly visible by eye. 0 removes it.
    n_dust : int
        Out-of-focus dust particles on the prism or lens, in [0, 10000]; 20.
    """

    fps: float = 4000.0
    exposure_s: float = 20e-6
    mm_per_px: float = 0.1
    width_px: int = 640
    height_px: int = 256
    bit_depth: int = 8
    gain: float = 1.0
    read_noise_dn: float | None = None
    full_well_e: float = 16000.0
    white_level: float = 0.8
    shot_noise: bool = True
    rotation_deg: float = 0.0
    illumination_gradient: float = 0.15
    vignetting: float = 0.2
    n_bubbles: int = 12
    n_scratches: int = 5
    groove_depth: float = 0.05
    n_dust: int = 20

    def __post_init__(self) -> None:
        put = functools.partial(object.__setattr__, self)
        put("fps", _in_range("fps", self.fps, 0.0, 1e7, low_open=True, unit="frames/s"))
        put(
            "exposure_s",
            _in_range("exposure_s", self.exposure_s, 0.0, 1.0 / self.fps, unit="s (<= 1/fps)"),
        )
        put("mm_per_px", _in_range("mm_per_px", self.mm_per_px, 0.0, 10.0, low_open=True))
        put("width_px", _integer("width_px", self.width_px, 16, 16384))
        put("height_px", _integer("height_px", self.height_px, 16, 16384))
        put("bit_depth", _choice("bit_depth", self.bit_depth, (8, 12, 16)))
        put("gain", _in_range("gain", self.gain, 0.0, 100.0, low_open=True))
        if self.read_noise_dn is not None:
            put("read_noise_dn", _in_range("read_noise_dn", self.read_noise_dn, 0.0, 1e6))
        put("full_well_e", _in_range("full_well_e", self.full_well_e, 100.0, 1e7))
        put("white_level", _in_range("white_level", self.white_level, 0.0, 1.0, low_open=True))
        put("shot_noise", _flag("shot_noise", self.shot_noise))
        put("rotation_deg", _in_range("rotation_deg", self.rotation_deg, -45.0, 45.0))
        g = _in_range("illumination_gradient", self.illumination_gradient, 0.0, 1.0)
        if g >= 1.0:
            raise ValueError(
                f"illumination_gradient must lie in [0, 1), got illumination_gradient={g!r}"
            )
        put("illumination_gradient", g)
        vg = _in_range("vignetting", self.vignetting, 0.0, 1.0)
        if vg >= 1.0:
            raise ValueError(f"vignetting must lie in [0, 1), got vignetting={vg!r}")
        put("vignetting", vg)
        for name in ("n_bubbles", "n_scratches", "n_dust"):
            put(name, _integer(name, getattr(self, name), 0, 10000))
        gd = _in_range("groove_depth", self.groove_depth, 0.0, 1.0)
        if gd >= 1.0:
            raise ValueError(f"groove_depth must lie in [0, 1), got groove_depth={gd!r}")
        put("groove_depth", gd)

    @property
    def read_noise(self) -> float:
        """Read-noise standard deviation in DN of the output bit depth (default resolved)."""
        if self.read_noise_dn is not None:
            return float(self.read_noise_dn)
        return 20.0 * self.gain * max_dn(self.bit_depth) / self.full_well_e

    @property
    def field_of_view_mm(self) -> tuple[float, float]:
        """Image width and height in the object plane, mm."""
        return self.width_px * self.mm_per_px, self.height_px * self.mm_per_px


@dataclass(frozen=True)
class FootageSpec:
    """Everything that determines a synthetic clip (same spec and seed: same bytes).

    Parameters
    ----------
    preset : str
        Reference sample G0, G3, G5, G6 or G7 (20 mm x 80 mm, 0/3/5/6/7 sipes of 0.6 mm,
        6 mm high), ignored when ``block`` is given.
    view : {"tir", "side"}
        Bottom view through the prism (TIR) or side view of the deformed elements.
    velocity_mps : float
        Sliding velocity, m/s, in (0, 30]; with ``velocity_step_to_mps`` the velocity
        before the step.
    n_frames : int
        Frames in the clip, in [1, 10^7].
    pressure_bar : float
        Nominal pressure F_N / (L w), bar, in (0, 10]; sets the preload of the model and the
        load carried by the rendered pressure.
    temperature_C, humidity_pct, salinity_pct : float
        Climate ([-60, 0] degC, [0, 100] %, [0, 3.5] %); they enter the friction only with
        ``friction="drywet"`` and are recorded in ``meta.json``.
    sliding_direction : {"left", "right"}
        Direction the block moves in the image; "left" as in Fig. 4.21.
    contact_is : {"dark", "bright"}
        TIR: contact dark on the bright free surface (frustrated TIR) or bright on dark.
        Side view: rubber dark on a bright backlight, or bright rubber on a dark background.
    camera : CameraSettings
    seed : int
        Seed (>= 0) of the ice imperfections, dust and noise.
    noise : bool
        False renders without shot and read noise (still quantised).
    follow_camera : bool
        Side view only: the camera moves with the block (block fixed in the image, the ice
        moves); the TIR camera is fixed under the prism.
    dynamics : {"simulated", "steady"}
        ``"simulated"``: the rigid model is integrated over ``settle_s`` plus the clip and
        frame ``k`` shows its state at ``settle_s + k / fps`` (self-excited oscillations
        included; the run costs about 0.1 s of CPU time per simulated ms for G3, and memory
        in proportion to the clip); ``"steady"``: every frame shows the mean state over the
        last 30 % of a ``settle_s`` run (cheap for any clip length).
    settle_s : float
        Lead-in of the simulation before the first frame, s, in (0, 1]; 0.02 s lets the
        start-up transient (from rest) decay at the default damping.
    friction : {"exponential", "drywet"}
        Friction law of the model: Eq. 5.7 with the values of
        :mod:`friction_model.dynamics.contact` (mu = 0.26 at 1 m/s), or the dry/wet model
        (:class:`friction_model.DryWetLaw`) at the given climate (much slower to integrate).
    loss_factor : float
        Rubber loss factor tan(delta) of the element springs, in [0, 2]; 0.4 as in
        :func:`friction_model.dynamics.contact.reference_contact_ratios`.
    center_time_s : float, optional
        Time at which the block centre passes the image centre, s; default the clip middle
        ``(n_frames - 1) / (2 fps)``.
    lateral_offset_mm : float
        Offset of the block centreline from the image centre row across the path, mm.
    contrast : float
        C, in (0, 1]: fraction of the free-surface light removed where the rubber just
        touches (the contact boundary, vanishing pressure); 0.75: micro-gaps within the
        evanescent depth (~0.1 um) still reflect part of the light.
    contrast_max : float
        C_max, in [C, 1]: fraction removed under high pressure; 0.95 leaves the 5 % that
        black filled rubber scatters back.
    pressure_ref_MPa : float
        p_ref of the darkness law ``D = C + (C_max - C)(1 - exp(-p/p_ref))``, MPa, > 0;
        1 MPa, about E/4 of the tread rubber, where its micro-contact with smooth ice closes.
    edge_band_mm : float
        Width b of the pressure peak at the front edge, mm, in [0, 5]; 0.4 mm (a new sample's
        edge, Fig. 5.11 a); 0 removes the band.
    block : BlockGeometry, optional
        Any block instead of ``preset``.
    velocity_step_to_mps : float, optional
        Velocity after an instantaneous step, m/s, in (0, 30] (Fig. 5.7): the sliding
        velocity is ``velocity_mps`` before ``step_time_s`` and this value from it on. The
        block position (fixed camera) or the ice (following camera) moves by the integral
        of the velocity, the motion blur follows the velocity of each frame, and the rigid
        model sees the step. Needs ``dynamics="simulated"``. None: constant velocity.
    step_time_s : float, optional
        Time of the velocity step on the clip's time axis (frame ``k`` at ``k / fps``), s,
        in [0, ``duration_s``]; required with ``velocity_step_to_mps`` and only with it.
    friction_relaxation_s : float
        Time constant tau of the friction's lag behind its steady law (Eq. 5.12, as
        :class:`friction_model.laws.RelaxedFriction`), s, in [0, 1]; 0 (the default) uses
        the steady law. The model starts (``settle_s`` before frame 0) with mu at its
        steady value.

    Notes
    -----
    Invalid values raise ``ValueError`` (``TypeError`` for a wrong type) naming the field.
    Specs that leave the last three fields at their defaults render exactly as before they
    existed (same bytes, same ``meta.json``: :meth:`to_dict` lists them only when set).
    """

    preset: str = "G3"
    view: str = "tir"
    velocity_mps: float = 1.0
    n_frames: int = 400
    pressure_bar: float = 2.5
    temperature_C: float = -5.0
    humidity_pct: float = 50.0
    salinity_pct: float = 0.0
    sliding_direction: str = "left"
    contact_is: str = "dark"
    camera: CameraSettings = field(default_factory=CameraSettings)
    seed: int = 0
    noise: bool = True
    follow_camera: bool = False
    dynamics: str = "simulated"
    settle_s: float = 0.02
    friction: str = "exponential"
    loss_factor: float = 0.4
    center_time_s: float | None = None
    lateral_offset_mm: float = 0.0
    contrast: float = 0.75
    contrast_max: float = 0.95
    pressure_ref_MPa: float = 1.0
    edge_band_mm: float = 0.4
    block: BlockGeometry | None = None
    velocity_step_to_mps: float | None = None
    step_time_s: float | None = None
    friction_relaxation_s: float = 0.0

    def __post_init__(self) -> None:
        put = functools.partial(object.__setattr__, self)
        if self.block is None:
            if not isinstance(self.preset, str) or self.preset.upper() not in REFERENCE_SAMPLES:
                raise ValueError(
                    f"preset must be one of {sorted(REFERENCE_SAMPLES)}, got preset={self.preset!r}"
                )
            put("preset", self.preset.upper())
        elif not isinstance(self.block, BlockGeometry):
            raise TypeError(f"block must be a BlockGeometry, got {type(self.block).__name__}")
        put("view", _choice("view", self.view, ("tir", "side")))
        put(
            "velocity_mps",
            _in_range("velocity_mps", self.velocity_mps, 0.0, 30.0, low_open=True, unit="m/s"),
        )
        put("n_frames", _integer("n_frames", self.n_frames, 1, 10_000_000))
        put(
            "pressure_bar",
            _in_range("pressure_bar", self.pressure_bar, 0.0, 10.0, low_open=True, unit="bar"),
        )
        put("temperature_C", _in_range("temperature_C", self.temperature_C, -60.0, 0.0))
        put("humidity_pct", _in_range("humidity_pct", self.humidity_pct, 0.0, 100.0))
        put("salinity_pct", _in_range("salinity_pct", self.salinity_pct, 0.0, 3.5))
        put(
            "sliding_direction",
            _choice("sliding_direction", self.sliding_direction, ("left", "right")),
        )
        put("contact_is", _choice("contact_is", self.contact_is, ("dark", "bright")))
        if not isinstance(self.camera, CameraSettings):
            raise TypeError(f"camera must be CameraSettings, got {type(self.camera).__name__}")
        put("seed", _integer("seed", self.seed, 0, 2**63 - 1))
        put("noise", _flag("noise", self.noise))
        put("follow_camera", _flag("follow_camera", self.follow_camera))
        if self.follow_camera and self.view != "side":
            raise ValueError(
                "follow_camera must be False for view='tir' (the camera is fixed under the "
                "prism), got follow_camera=True"
            )
        put("dynamics", _choice("dynamics", self.dynamics, ("simulated", "steady")))
        put("settle_s", _in_range("settle_s", self.settle_s, 0.0, 1.0, low_open=True, unit="s"))
        put("friction", _choice("friction", self.friction, ("exponential", "drywet")))
        put("loss_factor", _in_range("loss_factor", self.loss_factor, 0.0, 2.0))
        if self.center_time_s is not None:
            put("center_time_s", _real("center_time_s", self.center_time_s))
        put("lateral_offset_mm", _real("lateral_offset_mm", self.lateral_offset_mm))
        put("contrast", _in_range("contrast", self.contrast, 0.0, 1.0, low_open=True))
        put(
            "contrast_max",
            _in_range("contrast_max", self.contrast_max, self.contrast, 1.0, unit="(>= contrast)"),
        )
        put(
            "pressure_ref_MPa",
            _in_range("pressure_ref_MPa", self.pressure_ref_MPa, 0.0, 1e4, low_open=True),
        )
        put("edge_band_mm", _in_range("edge_band_mm", self.edge_band_mm, 0.0, 5.0, unit="mm"))
        self._check_step(put)

    def _check_step(self, put: Any) -> None:
        """Validate the velocity step and the friction relaxation (Eq. 5.12) fields."""
        put(
            "friction_relaxation_s",
            _in_range("friction_relaxation_s", self.friction_relaxation_s, 0.0, 1.0, unit="s"),
        )
        if self.velocity_step_to_mps is None:
            if self.step_time_s is not None:
                raise ValueError(
                    "step_time_s needs velocity_step_to_mps (the velocity after the step), got "
                    f"step_time_s={self.step_time_s!r} with velocity_step_to_mps=None"
                )
            return
        put(
            "velocity_step_to_mps",
            _in_range(
                "velocity_step_to_mps",
                self.velocity_step_to_mps,
                0.0,
                30.0,
                low_open=True,
                unit="m/s",
            ),
        )
        if self.step_time_s is None:
            raise ValueError(
                "step_time_s must be given with velocity_step_to_mps (the time of the step on "
                "the clip's time axis, s), got step_time_s=None"
            )
        put(
            "step_time_s",
            _in_range("step_time_s", self.step_time_s, 0.0, self.duration_s, unit="s"),
        )
        if self.dynamics != "simulated":
            raise ValueError(
                "dynamics must be 'simulated' with a velocity step (a steady state has no "
                f"step), got dynamics={self.dynamics!r}"
            )

    @property
    def has_step(self) -> bool:
        """True when the clip has a velocity step (``velocity_step_to_mps`` given)."""
        return self.velocity_step_to_mps is not None

    def velocity_at(self, time_s: float) -> float:
        """Sliding velocity at clip time ``time_s`` (frame k at k / fps), m/s.

        Examples
        --------
        >>> spec = FootageSpec(velocity_step_to_mps=5.0, step_time_s=0.05)
        >>> spec.velocity_at(0.0), spec.velocity_at(0.05)
        (1.0, 5.0)
        """
        if self.velocity_step_to_mps is None or time_s < float(self.step_time_s):
            return self.velocity_mps
        return float(self.velocity_step_to_mps)

    def travel_since_mm(self, t0_s: float, t1_s: float) -> float:
        """Distance slid from clip time ``t0_s`` to ``t1_s`` (the integral of the velocity), mm.

        Examples
        --------
        >>> spec = FootageSpec(velocity_step_to_mps=5.0, step_time_s=0.05)
        >>> round(spec.travel_since_mm(0.0, 0.06), 9)  # 50 mm at 1 m/s, then 50 mm at 5 m/s
        100.0
        """
        if self.velocity_step_to_mps is None:
            return self.velocity_mps * 1e3 * (t1_s - t0_s)
        return 1e3 * (self._distance_m(t1_s) - self._distance_m(t0_s))

    def _distance_m(self, t: float) -> float:
        """Distance slid since clip time 0 (negative before it), m."""
        ts, v1, v2 = float(self.step_time_s), self.velocity_mps, float(self.velocity_step_to_mps)
        return v1 * t if t < ts else v1 * ts + v2 * (t - ts)

    @property
    def geometry(self) -> BlockGeometry:
        """The block: ``block`` if given, else ``reference_block(preset)``."""
        return self.block if self.block is not None else reference_block(self.preset)

    @property
    def duration_s(self) -> float:
        """Time from the first to the last frame, s."""
        return (self.n_frames - 1) / self.camera.fps

    def to_dict(self) -> dict[str, Any]:
        """The spec as plain JSON-compatible values (nested camera and block included).

        The velocity step and relaxation fields appear only when set (a spec without them
        gives the same dict, and ``meta.json``, as before they existed).
        """
        out = _jsonable(dataclasses.asdict(self))
        for name in _STEP_FIELDS:
            if out[name] == _STEP_DEFAULTS[name]:
                del out[name]
        return out


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


# -- the block model -------------------------------------------------------------------------
@dataclass(frozen=True)
class _ModelStates:
    """Bar angles and normal forces of every element at every frame (or one steady row)."""

    phi_rad: np.ndarray  # (T, N, nb)
    chord_deg: np.ndarray  # (T, N)
    preload_mm: float
    first_row: int  # row of frame 0 (T == 1: steady)

    def row(self, k: int) -> int:
        return 0 if self.phi_rad.shape[0] == 1 else self.first_row + k


@dataclass(frozen=True)
class _ModelInput:
    """The inputs of the block model (the cache key: specs differing elsewhere share it)."""

    geometry: BlockGeometry
    velocity_mps: float
    pressure_bar: float
    friction: str
    loss_factor: float
    settle_s: float
    dynamics: str
    climate: tuple[float, ...]
    timing: tuple[float, ...]
    #: (velocity after the step, m/s; step time on the model's axis, s) or ().
    step: tuple[float, ...] = ()
    relaxation_s: float = 0.0

    @classmethod
    def of(cls, spec: FootageSpec) -> _ModelInput:
        return cls(
            geometry=spec.geometry,
            velocity_mps=spec.velocity_mps,
            pressure_bar=spec.pressure_bar,
            friction=spec.friction,
            loss_factor=spec.loss_factor,
            settle_s=spec.settle_s,
            dynamics=spec.dynamics,
            climate=(spec.temperature_C, spec.humidity_pct, spec.salinity_pct)
            if spec.friction == "drywet"
            else (),
            timing=(spec.camera.fps, float(spec.n_frames)) if spec.dynamics == "simulated" else (),
            step=(float(spec.velocity_step_to_mps), spec.settle_s + float(spec.step_time_s))
            if spec.has_step
            else (),
            relaxation_s=spec.friction_relaxation_s,
        )


@functools.lru_cache(maxsize=16)
def _simulate(spec: _ModelInput) -> _ModelStates:
    """Integrate the rigid block model once per distinct model input (cached)."""
    from friction_model.drywet_law import DryWetLaw
    from friction_model.dynamics import velocity_step
    from friction_model.dynamics.rigid import BlockParams, simulate_block_dynamics
    from friction_model.laws import ExponentialLaw, RelaxedFriction

    geom = spec.geometry
    lengths = geom.element_lengths * 1e-3
    params = BlockParams(
        n_elements=geom.n_elements,
        height_m=geom.height_mm * 1e-3,
        element_length_m=tuple(lengths.tolist()),
        width_m=geom.width_mm * 1e-3,
        sipe_width_m=geom.sipe_width_mm * 1e-3,
        contact_model="face",
        loss_factor=spec.loss_factor,
    )
    if spec.friction == "drywet":
        law: Any = DryWetLaw(
            geom,
            temperature_C=spec.climate[0],
            humidity_pct=spec.climate[1],
            salinity_pct=spec.climate[2],
        )
    else:
        law = ExponentialLaw(**_EQ57)
    if spec.relaxation_s > 0.0:
        law = RelaxedFriction(law, tau_s=spec.relaxation_s)  # Eq. 5.12
    # Frame k shows model time settle_s + k / fps, so the step sits at settle_s + step_time_s.
    velocity: Any = (
        velocity_step(spec.velocity_mps, spec.step[0], spec.step[1])
        if spec.step
        else spec.velocity_mps
    )
    load_N = spec.pressure_bar * 1e5 * geom.nominal_area_mm2 * 1e-6
    stiffness = params.youngs_modulus_Pa * lengths.sum() * params.width_m / params.height_m
    preload = params.height_m - load_N / stiffness
    if spec.dynamics == "simulated":
        fps, n_frames = spec.timing[0], int(spec.timing[1])
        first = round(spec.settle_s * fps)
        step = 1.0 / fps
        # A quarter step beyond the last frame: the output grid arange(0, t_end + step/2,
        # step) then ends exactly at the last frame despite rounding.
        t_end = (max(first + n_frames, 2) - 0.75) * step
    else:
        first, step, t_end = 0, spec.settle_s / 200.0, spec.settle_s
    logger.info(
        "rigid block model: %d elements, v = %g m/s, %g bar, %.4g s simulated",
        geom.n_elements,
        spec.velocity_mps,
        spec.pressure_bar,
        t_end,
    )
    res = simulate_block_dynamics(
        params,
        velocity=velocity,
        preload=preload,
        friction=law,
        t_end_s=t_end,
        output_step_s=step,
        rtol=_RTOL,
        atol=_ATOL,
    )
    phi = np.asarray(res.fields["phi_rad"], dtype=np.float64)
    n = geom.n_elements
    chord = res.data["angle_deg"].to_numpy().reshape(-1, n)
    if spec.dynamics == "steady":
        t = res.fields["time_s"]
        sel = t >= (1.0 - _STEADY_FRACTION) * t[-1]
        phi = phi[sel].mean(axis=0, keepdims=True)
        chord = chord[sel].mean(axis=0, keepdims=True)
    elif phi.shape[0] >= first + n_frames:
        phi, chord = phi[: first + n_frames], chord[: first + n_frames]
    else:
        raise RuntimeError(
            f"rigid model returned {phi.shape[0]} output rows, expected {first + n_frames}"
        )
    phi.setflags(write=False)
    chord.setflags(write=False)
    return _ModelStates(phi, chord, preload * 1e3, first)


def _element_frame(geom: BlockGeometry, states: _ModelStates, k: int) -> ElementFrame:
    r = states.row(k)
    phi = states.phi_rad[r]  # (N, nb)
    nb = phi.shape[1]
    bar = geom.height_mm / nb
    lengths = geom.element_lengths
    return ElementFrame(
        root_centre_mm=geom.element_front_positions_mm + 0.5 * lengths,
        length_mm=lengths,
        tip_x_mm=bar * np.sin(phi).sum(axis=1),
        tip_depth_mm=bar * np.cos(phi).sum(axis=1),
        tilt_rad=phi[:, -1].copy(),
        chord_deg=np.asarray(states.chord_deg[r], dtype=np.float64),
        preload_mm=states.preload_mm,
    )


# -- the clip --------------------------------------------------------------------------------
class _Clip:
    """Everything static of one spec: model, path, scene; renders frame ``k`` on demand."""

    def __init__(self, spec: FootageSpec) -> None:
        self.spec = spec
        cam = spec.camera
        self.geom = spec.geometry
        self.states = _simulate(_ModelInput.of(spec))
        w_mm, h_mm = cam.field_of_view_mm
        self.path = PathGeometry(
            width_mm=w_mm,
            height_mm=h_mm,
            mm_per_px=cam.mm_per_px,
            rotation_rad=math.radians(cam.rotation_deg),
            lateral_mm=spec.lateral_offset_mm,
            direction=1 if spec.sliding_direction == "left" else -1,
            block_width_mm=self.geom.width_mm,
        )
        self.contact = ContactParams(
            winkler_Pa_per_mm=_youngs_modulus() / self.geom.height_mm,
            width_mm=self.geom.width_mm,
            load_N=spec.pressure_bar * 1e5 * self.geom.nominal_area_mm2 * 1e-6,
            contrast=spec.contrast,
            contrast_max=spec.contrast_max,
            pressure_ref_Pa=spec.pressure_ref_MPa * 1e6,
            band_mm=spec.edge_band_mm,
        )
        self.t_mid = spec.center_time_s if spec.center_time_s is not None else 0.5 * spec.duration_s
        self.blur_mm = spec.velocity_mps * cam.exposure_s * 1e3
        self.blur_after_mm = (
            float(spec.velocity_step_to_mps) * cam.exposure_s * 1e3
            if spec.has_step
            else self.blur_mm
        )
        scene_rng = np.random.default_rng(np.random.SeedSequence(spec.seed, spawn_key=(0,)))
        illum = illumination_field(
            cam.height_px,
            cam.width_px,
            gradient=cam.illumination_gradient,
            vignetting=cam.vignetting,
        )
        dust = dust_field(cam.height_px, cam.width_px, n_dust=cam.n_dust, rng=scene_rng)
        level = np.float32(cam.white_level)
        if spec.view == "tir":
            ice = ice_transmission(
                self.path,
                rng=scene_rng,
                n_bubbles=cam.n_bubbles,
                n_scratches=cam.n_scratches,
                groove_depth=cam.groove_depth,
            )
            self.base = (level * illum * ice * dust).astype(np.float32)
            self.lateral = self.path.lateral_coverage()
        else:
            self.base = (level * illum * dust).astype(np.float32)
            dark = spec.contact_is == "dark"
            # Levels (fractions of S): backlight 1.0 / 0.1, carbon-black rubber reflects
            # ~8 % (0.85 front-lit), matte steel 0.4 / 0.5, ice slab 0.6 / 0.3. The rubber
            # above the sipe ground is not given in the thesis: 2 mm, a usual tread base,
            # glued to a 3 mm steel carrier that overhangs the block by 1 mm.
            self.layout = SideLayout(
                ice_y_mm=_SIDE_ICE_ROW * h_mm,
                base_mm=2.0,
                carrier_mm=3.0,
                carrier_overhang_mm=1.0,
                background=1.0 if dark else 0.1,
                rubber=0.08 if dark else 0.85,
                carrier=0.4 if dark else 0.5,
                ice=0.6 if dark else 0.3,
            )
            # Bubbles of the ice slab over the whole stretch of track the camera can see:
            # radius 0.05-0.3 mm as in the TIR view, 0.3-5 mm below the surface, brighter
            # than the ice by 15-40 % (they scatter the backlight towards the camera).
            v_max = max(spec.velocity_mps, spec.velocity_step_to_mps or 0.0)
            travel = v_max * 1e3 * spec.duration_s
            span = w_mm + 2.0 * travel
            n_b = round(cam.n_bubbles * span / w_mm)
            bubbles = np.column_stack(
                [
                    scene_rng.uniform(-travel, w_mm + travel, n_b),
                    scene_rng.uniform(0.3, 5.0, n_b),
                    scene_rng.uniform(0.05, 0.3, n_b),
                    scene_rng.uniform(0.15, 0.4, n_b),
                ]
            )
            self.bubbles = bubbles[np.argsort(bubbles[:, 0], kind="stable")]
            self.static_ice = (
                None
                if spec.follow_camera
                else ice_texture_frame(self.path, self.layout, bubbles=self.bubbles, offset_mm=0.0)
            )
        self.node_spacing_mm = cam.mm_per_px / 8.0
        self._cached: tuple[int, Any] | None = None
        self.sensor = Sensor(
            (cam.height_px, cam.width_px),
            bit_depth=cam.bit_depth,
            gain=cam.gain,
            full_well_e=cam.full_well_e,
            read_noise_dn=cam.read_noise,
            shot_noise=cam.shot_noise,
        )

    # -- timing -----------------------------------------------------------------------------
    def time_of(self, k: int) -> float:
        return k / self.spec.camera.fps

    def travel_mm(self, k: int) -> float:
        """Distance the block has moved since the reference time t_mid, mm."""
        if self.spec.has_step:
            return self.spec.travel_since_mm(self.t_mid, self.time_of(k))
        return self.spec.velocity_mps * 1e3 * (self.time_of(k) - self.t_mid)

    def blur_of(self, k: int) -> float:
        """Motion during the exposure of frame k (velocity at its centre time), mm."""
        if self.spec.has_step and self.time_of(k) >= float(self.spec.step_time_s):
            return self.blur_after_mm
        return self.blur_mm

    def u_front(self, k: int) -> float:
        """Path coordinate u of the block's leading face at frame k, mm."""
        s = self.path.direction
        xc = 0.5 * self.path.width_mm
        if self.spec.follow_camera:
            return xc - s * 0.5 * self.geom.length_mm
        return xc - s * self.travel_mm(k) - s * 0.5 * self.geom.length_mm

    # -- one frame --------------------------------------------------------------------------
    def _model_frame(self, k: int) -> tuple[ElementFrame, list[Any], np.ndarray, Any]:
        """Element state, contacts, deflection angles and darkness profile of frame k.

        Cached for the last model row (every frame of a steady clip shares one).
        """
        row = self.states.row(k)
        if self._cached is not None and self._cached[0] == row:
            return self._cached[1]
        frame = _element_frame(self.geom, self.states, k)
        contacts = element_contacts(frame, self.contact, node_spacing_mm=self.node_spacing_mm)
        deflection = deflection_angles(frame, self.geom.height_mm)
        profile = block_profile(frame, contacts, self.contact) if self.spec.view == "tir" else None
        out = (frame, contacts, deflection, profile)
        self._cached = (row, out)
        return out

    def signal(self, k: int) -> tuple[np.ndarray, pd.DataFrame]:
        spec = self.spec
        frame, contacts, deflection, profile = self._model_frame(k)
        u_front = self.u_front(k)
        bright = spec.contact_is == "bright"
        if spec.view == "tir":
            sig = render_tir_signal(
                profile,
                self.path,
                u_front=u_front,
                blur_mm=self.blur_of(k),
                lateral=self.lateral,
                base=self.base,
                contrast=spec.contrast_max,
                bright=bright,
            )
            rows = tir_truth_rows(
                frame, contacts, self.path, u_front=u_front, deflection_deg=deflection
            )
        else:
            if spec.follow_camera:
                tex = ice_texture_frame(
                    self.path,
                    self.layout,
                    bubbles=self.bubbles,
                    offset_mm=-self.path.direction * self.travel_mm(k),
                )
            else:
                tex = self.static_ice
            sig, polys = render_side_signal(
                frame,
                height_mm=self.geom.height_mm,
                block_length_mm=self.geom.length_mm,
                layout=self.layout,
                u_front=u_front,
                path=self.path,
                base=self.base,
                ice_texture=tex,
                blur_px=self.blur_of(k) / spec.camera.mm_per_px,
                blur_block=not spec.follow_camera,
            )
            rows = self._side_rows(frame, contacts, polys, u_front, deflection)
        rows.sort(key=lambda r: r["element"])
        n = len(rows)
        data: dict[str, Any] = {
            "frame": np.full(n, k, dtype=np.int64),
            "time_s": np.full(n, self.time_of(k)),
        }
        for col in TRUTH_COLUMNS[2:]:
            data[col] = [r[col] for r in rows]
        table = pd.DataFrame(data)
        table["in_view"] = table["in_view"].astype(bool)
        return sig, table

    def _side_rows(
        self,
        frame: ElementFrame,
        contacts: list[Any],
        polys: list[np.ndarray],
        u_front: float,
        deflection: np.ndarray,
    ) -> list[dict[str, Any]]:
        path = self.path
        s = path.direction
        y_root = self.layout.ice_y_mm - frame.preload_mm
        rows: list[dict[str, Any]] = []
        xs_front, xs_peak = [], []
        front = frame.front_corner_mm
        for i, c in enumerate(contacts):
            p = polys[i]
            if (
                p[:, 0].max() < 0
                or p[:, 0].min() > path.width_mm
                or p[:, 1].max() < 0
                or p[:, 1].min() > path.height_mm
            ):
                continue
            ell = float(frame.length_mm[i])
            y_corner = (
                y_root + frame.tip_depth_mm[i] + 0.5 * ell * math.sin(float(frame.tilt_rad[i]))
            )
            if c.length_mm > 0:
                xf, _ = rotate_scene(path, np.array([u_front + s * front[i]]), np.array([y_corner]))
                xp, _ = rotate_scene(
                    path,
                    np.array([u_front + s * (front[i] + c.peak_zeta_mm)]),
                    np.array([self.layout.ice_y_mm]),
                )
                x_front, x_peak = float(xf[0]), float(xp[0])
            else:
                x_front = x_peak = math.nan
            xs_front.append(x_front)
            xs_peak.append((c.peak_pressure_Pa, x_peak))
            rows.append(
                element_row(
                    i,
                    frame,
                    c,
                    c.length_mm * self.geom.width_mm,
                    c.length_mm,
                    x_front,
                    x_peak,
                    float(deflection[i]),
                )
            )
        rows.append(block_row(rows, frame, xs_front, xs_peak, direction=s))
        return rows

    def noise_rng(self, k: int) -> np.random.Generator | None:
        if not self.spec.noise:
            return None
        return np.random.default_rng(np.random.SeedSequence(self.spec.seed, spawn_key=(1, k)))

    def image(self, k: int) -> tuple[np.ndarray, pd.DataFrame]:
        sig, table = self.signal(k)
        return self.sensor(sig, self.noise_rng(k)), table


def _youngs_modulus() -> float:
    from friction_model.dynamics.rigid import REFERENCE_YOUNGS_MODULUS_PA

    return float(REFERENCE_YOUNGS_MODULUS_PA)


# -- public API ------------------------------------------------------------------------------
def iter_frames(spec: FootageSpec) -> Iterator[tuple[int, np.ndarray, pd.DataFrame]]:
    """Render the clip frame by frame.

    Parameters
    ----------
    spec : FootageSpec

    Yields
    ------
    frame : int
        Frame index k (time ``k / fps``).
    image : (height_px, width_px) ndarray of uint8 or uint16
        The frame (uint8 for 8-bit, uint16 holding 12- or 16-bit values).
    truth : pandas.DataFrame
        Ground-truth rows of this frame, columns :data:`TRUTH_COLUMNS`: the block total
        (element -1) first, then every element (0 leads) with any part in view.

    Notes
    -----
    The rigid block model is integrated (or fetched from a cache of recent specs) before the
    first frame. Memory does not grow with the clip length.
    """
    if not isinstance(spec, FootageSpec):
        raise TypeError(f"spec must be a FootageSpec, got {type(spec).__name__}")
    clip = _Clip(spec)
    for k in range(spec.n_frames):
        img, table = clip.image(k)
        yield k, img, table


def _progress_bar(total: int, progress: bool | None) -> Any:
    from tqdm import tqdm

    disable = (not progress) if progress is not None else not sys.stderr.isatty()
    return tqdm(total=total, disable=disable, unit="frame", desc="footage", leave=False)


def render_footage(
    spec: FootageSpec,
    out_dir: str | Path,
    *,
    fmt: str = "png",
    progress: bool | None = None,
) -> Path:
    """Render a clip to ``out_dir``: frames, ``ground_truth.csv`` and ``meta.json``.

    Parameters
    ----------
    spec : FootageSpec
    out_dir : str or Path
        Output folder (created). Earlier frames of this writer's own naming are replaced.
    fmt : {"png", "tiff", "avi", "multitiff"}
        ``"png"``: ``frames/frame_000000.png`` ... (8-bit or 16-bit PNG); ``"tiff"``:
        ``frames/frame_000000.tif`` ... (uint8 or uint16 TIFF, uncompressed); ``"avi"``:
        ``footage.avi``, lossless FFV1 through OpenCV, 8-bit only; ``"multitiff"``:
        ``footage.tif``, one multi-page TIFF (BigTIFF above 2 GiB).
    progress : bool, optional
        Show a tqdm progress bar; default only when stderr is a terminal.

    Returns
    -------
    Path
        ``out_dir``.

    Raises
    ------
    ValueError
        For an unknown ``fmt``, or ``fmt="avi"`` with a bit depth other than 8.
    """
    if not isinstance(spec, FootageSpec):
        raise TypeError(f"spec must be a FootageSpec, got {type(spec).__name__}")
    _choice("fmt", fmt, ("png", "tiff", "avi", "multitiff"))
    if fmt == "avi" and spec.camera.bit_depth != 8:
        raise ValueError(
            "bit_depth must be 8 for fmt='avi' (OpenCV writes 8-bit video), got "
            f"bit_depth={spec.camera.bit_depth}"
        )
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    sink: FrameSink = open_sink(out, fmt, spec)
    bar = _progress_bar(spec.n_frames, progress)
    truth_path = out / "ground_truth.csv"
    try:
        with open(truth_path, "w", newline="", encoding="utf-8") as fh:
            fh.write(",".join(TRUTH_COLUMNS) + "\n")
            for k, img, table in iter_frames(spec):
                sink.write(k, img)
                _write_rows(fh, table)
                bar.update(1)
    finally:
        sink.close()
        bar.close()
    write_meta(out, spec, sink, truth_columns=TRUTH_COLUMNS)
    logger.info("wrote %d frames to %s (%s)", spec.n_frames, out, fmt)
    return out


def _fmt(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    f = float(v)
    if math.isnan(f):
        return ""
    return f"{f:.9g}"


def _write_rows(fh: Any, table: pd.DataFrame) -> None:
    cols = [table[c].to_numpy() for c in TRUTH_COLUMNS]
    fh.write("".join(",".join(_fmt(c[i]) for c in cols) + "\n" for i in range(len(table))))
