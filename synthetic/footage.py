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

Real footage
------------
Real rigs differ from the defaults: the TIR light may reach only part of the frame
(``CameraSettings.lit_shape``, ``lit_fraction``, ``lit_rim_mm``, ``outside_level``; the
ground truth then counts only contact inside the lit mask, :func:`lit_mask`), the signal may
be low (``white_level``) and JPEG-compressed (``jpeg_quality``), the TIR camera may follow
the block (``follow_camera``), the contact may be a static pad, coin or three points
(``scene``), and the real contact is patchy (``real_contact="patchy"``: micro-contact
patches covering the share :func:`friction_model.real_contact_fraction` of the nominal
contact at the local pressure; :func:`model_contact_ratio`). :mod:`synthetic.domain` draws
random clips from these ranges.

Time and coordinates
--------------------
Frame ``k`` is exposed over ``exposure_s`` centred on ``time_s = k / fps``. Image x and y are
in mm from the left and top image edges (pixel ``(r, c)`` covers ``[c, c+1) * mm_per_px`` in
x); ground-truth positions are image x of points on the block centreline. The file layout and
every column are described in ``docs/formats.md``.

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
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pandas as pd
import tifffile
from scipy.ndimage import gaussian_filter

from friction_model.compound import REFERENCE_COMPOUND
from friction_model.contact.drywet_law import DryWetLaw
from friction_model.contact.laws import ExponentialLaw, RelaxedFriction
from friction_model.dynamics import (
    BlockParams,
    SolverOptions,
    simulate_block_dynamics,
    velocity_step,
)
from friction_model.dynamics.rigid import REFERENCE_YOUNGS_MODULUS_PA
from friction_model.effect_registry import get_effect
from friction_model.geometry import REFERENCE_SAMPLES, BlockGeometry, reference_block
from synthetic._camera import (
    Sensor,
    box_blur_x,
    dust_field,
    illumination_field,
    interval_coverage,
    max_dn,
)
from synthetic._lighting import LIT_SHAPES, fold_factor, lit_distance, lit_factor, lit_zone_size
from synthetic._physical import PHYSICAL_SCENES, PhysicalSetup, render_physical, scene_contact
from synthetic._physical_block import BinIntegrals, PhysicalBlock, physical_fractions
from synthetic._real_contact import (
    SUPERSAMPLE,
    PatchTexture,
    StaticScene,
    pool,
    pressure_cells,
    real_fraction,
    sample_points,
)
from synthetic._render_side import (
    SideLayout,
    deflection_angles,
    element_polygons,
    ice_texture_frame,
    render_side_signal,
    rotate_scene,
)
from synthetic._render_tir import (
    THESIS_BUBBLES,
    THESIS_FIELD_MM,
    ContactParams,
    ElementFrame,
    PathGeometry,
    block_profile,
    block_row,
    element_contacts,
    element_row,
    ice_flaws_expected,
    ice_transmission,
    render_tir_signal,
    tir_truth_rows,
)
from synthetic._writers import FrameSink, open_sink, write_meta
from synthetic.ftir import GAP_INDEX, SUBSTRATE_INDEX, FtirOptics
from synthetic.roughness import ROUGHNESS_PRESETS, e_star_Pa
from tir_common.atomic import atomic_write, json_safe
from tir_common.progress import progress_bar
from tir_common.validate import check_number

__all__ = [
    "HOLDERS",
    "PHYSICAL_TRUTH_COLUMNS",
    "REAL_TRUTH_COLUMNS",
    "SCENES",
    "TRUTH_COLUMNS",
    "CameraSettings",
    "FootageSpec",
    "LitZone",
    "iter_frames",
    "lit_mask",
    "lit_zone",
    "model_contact_ratio",
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
_SOLVER = SolverOptions(rtol=1e-5, atol=1e-8)
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
#: Real-footage fields of the spec and the camera, and their defaults as JSON values (left
#: out of ``FootageSpec.to_dict`` at these values).
_REAL_DEFAULTS: dict[str, Any] = {
    "scene": "block",
    "pad_radius_mm": 2.75,
    "coin_radii_mm": [7.0, 8.0],
    "point_radius_mm": 1.0,
    "point_positions_mm": None,
    "real_contact": "solid",
    "patch_correlation_mm": 0.2,
    "roughness": "abraded_rubber",
    "sphere_radius_mm": 5.0,
    "substrate": "ice",
    "gap_medium": "air",
    "incidence_deg": 60.0,
    "wavelength_nm": 550.0,
    "texture": 0.0,
    "texture_mm": 0.05,
}
_CAMERA_REAL_DEFAULTS: dict[str, Any] = {
    "lit_shape": "full",
    "lit_fraction": 1.0,
    "lit_rim_mm": 1.0,
    "lit_center_mm": [0.0, 0.0],
    "outside_level": 0.05,
    "jpeg_quality": None,
    "optical_blur_mm": 0.0,
    "fold_depth": 0.0,
    "fold_x_mm": 0.0,
    "fold_width_mm": 1.0,
    "fold_edge_mm": 0.3,
    "stray_light": 0.0,
}
#: Side-view fields and their defaults (left out of ``FootageSpec.to_dict`` at them).
_SIDE_DEFAULTS: dict[str, Any] = {"holder": "carrier"}
#: What holds the block in the side view (``FootageSpec.holder``).
HOLDERS = ("carrier", "plate", "carriage")
#: Scenes of the TIR view: the sliding block or a static contact.
SCENES = ("block", "round_pad", "coin", "three_point", *PHYSICAL_SCENES)
#: Extra ground-truth columns of specs that use a real-footage field.
REAL_TRUTH_COLUMNS = ("nominal_contact_area_mm2", "real_contact_fraction")
#: Extra ground-truth columns of the physical scenes (``contact_area_mm2`` is the true
#: contact, gap 0): the area whose gap is below a tenth of the evanescent depth, and the
#: optical contact, the scene's darkness over that of full contact (what a perfect TIR
#: reading counts: a gap within the evanescent depth darkens too).
PHYSICAL_TRUTH_COLUMNS = ("near_contact_area_mm2", "optical_contact_area_mm2")


# -- validation helpers --------------------------------------------------------------------
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
    n_bubbles : int, optional
        Air bubbles in the ice within the view, in [0, 10000]. None (default): the thesis's
        ice, the few bubbles of Fig. 4.20 b (12 in its 64 x 25.6 mm view), counted in this
        view by area (:meth:`ice_flaws`; a 2.56 mm micro view holds none). In the side
        view: bubbles in the ice slab per image width (None: 12 per 64 mm).
    n_scratches : int, optional
        Scratches on the ice surface, in [0, 10000]. None (default): those of a track used a
        few times (5 in the thesis's view), counted in this view by the ones that cross it.
    groove_depth : float
        Darkening at the centre of a worn groove along the track, fraction, in [0, 1); 0.05:
        a shallow rut hardly visible by eye. 0 removes it.
    n_dust : int
        Out-of-focus dust particles on the prism or lens, in [0, 10000]; 20.
    lit_shape : {"full", "disc", "ellipse", "band"}
        TIR view: where the totally reflected light reaches the camera. "full": the whole
        frame (as before this field existed); otherwise a disc, an ellipse (the frame's
        aspect ratio) or a band along x with a dark outside (real rigs often light only a
        vignetted disc, e.g. 28 % of the frame). Side view: "full" only.
    lit_fraction : float
        Share of the frame inside the lit zone (its lit mask, see :func:`lit_mask`), in
        [0.2, 1]; ignored for ``lit_shape="full"``.
    lit_rim_mm : float
        Width of the soft rim over which the light falls from the lit level to the
        outside level, mm, in [0, 100] (at least one pixel is used); 1 mm.
    lit_center_mm : (float, float)
        Centre of the lit zone relative to the image centre, (x, y), mm.
    outside_level : float
        Light left outside the lit zone, fraction of the lit level, in [0, 1); 0.05.
    jpeg_quality : int, optional
        JPEG quality 1-100: every frame is JPEG-compressed (OpenCV) and decoded again, and a
        clip folder gets ``.jpg`` frames; 8-bit only. None (default): no compression.
    optical_blur_mm : float
        Standard deviation of the lens's Gaussian point-spread function in the object
        plane, mm, in [0, 10]; used by the physical scenes (``FootageSpec.scene``
        "rough_pad", "rough_sphere"), which draw contact finer than a pixel. 0: an ideal
        lens. A lens at f/4 and 550 nm resolves about 3 um on the sensor; at 0.01 mm/px
        and a 1:1 image, 0.003.
    fold_depth : float
        TIR view: share of the light lost in a darker fold across the lit zone (a band
        along y where the light falls off steeply; the profile of
        ``synthetic._lighting.fold_factor``), in [0, 1); 0 (default): no fold. Light
        only: the truth is unchanged.
    fold_x_mm : float
        Centre line of the fold from the image centre along x, mm, in [-1e4, 1e4].
    fold_width_mm : float
        Width of the fold's flat core, mm, in [0, 1e4]; 1.
    fold_edge_mm : float
        Width of each of the fold's edges (the fall-off), mm, in [0, 1e4]; 0.3.
    stray_light : float
        TIR view: stray light (flare, a camera black offset) added uniformly to the
        reflected light, fraction of ``white_level``, scaled by the lit zone's light factor,
        in [0, 1); 0 (default): none. With it, full contact is no longer nearly black:
        its darkness falls from ``1 - R_contact`` to ``(1 - R_contact) / (1 + stray_light)``
        at the centre of an evenly lit frame.
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
    n_bubbles: int | None = None
    n_scratches: int | None = None
    groove_depth: float = 0.05
    n_dust: int = 20
    lit_shape: str = "full"
    lit_fraction: float = 1.0
    lit_rim_mm: float = 1.0
    lit_center_mm: tuple[float, float] = (0.0, 0.0)
    outside_level: float = 0.05
    jpeg_quality: int | None = None
    optical_blur_mm: float = 0.0
    fold_depth: float = 0.0
    fold_x_mm: float = 0.0
    fold_width_mm: float = 1.0
    fold_edge_mm: float = 0.3
    stray_light: float = 0.0

    def __post_init__(self) -> None:
        put = functools.partial(object.__setattr__, self)
        put("fps", check_number("fps", self.fps, low=0.0, high=1e7, low_open=True, unit="frames/s"))
        put(
            "exposure_s",
            check_number(
                "exposure_s", self.exposure_s, low=0.0, high=1.0 / self.fps, unit="s (<= 1/fps)"
            ),
        )
        put(
            "mm_per_px",
            check_number("mm_per_px", self.mm_per_px, low=0.0, high=10.0, low_open=True),
        )
        put("width_px", _integer("width_px", self.width_px, 16, 16384))
        put("height_px", _integer("height_px", self.height_px, 16, 16384))
        put("bit_depth", _choice("bit_depth", self.bit_depth, (8, 12, 16)))
        put("gain", check_number("gain", self.gain, low=0.0, high=100.0, low_open=True))
        if self.read_noise_dn is not None:
            put(
                "read_noise_dn",
                check_number("read_noise_dn", self.read_noise_dn, low=0.0, high=1e6),
            )
        put("full_well_e", check_number("full_well_e", self.full_well_e, low=100.0, high=1e7))
        put(
            "white_level",
            check_number("white_level", self.white_level, low=0.0, high=1.0, low_open=True),
        )
        put("shot_noise", _flag("shot_noise", self.shot_noise))
        put("rotation_deg", check_number("rotation_deg", self.rotation_deg, low=-45.0, high=45.0))
        for name in ("illumination_gradient", "vignetting"):
            put(name, check_number(name, getattr(self, name), low=0.0, high=1.0, high_open=True))
        for name in ("n_bubbles", "n_scratches", "n_dust"):
            if getattr(self, name) is not None or name == "n_dust":
                put(name, _integer(name, getattr(self, name), 0, 10000))
        put("groove_depth",
            check_number("groove_depth", self.groove_depth, low=0.0, high=1.0, high_open=True))
        self._check_real_footage(put)

    def _check_real_footage(self, put: Any) -> None:
        """Validate the lit zone and JPEG fields."""
        put("lit_shape", _choice("lit_shape", self.lit_shape, LIT_SHAPES))
        put("lit_fraction", check_number("lit_fraction", self.lit_fraction, low=0.2, high=1.0))
        put(
            "lit_rim_mm",
            check_number("lit_rim_mm", self.lit_rim_mm, low=0.0, high=100.0, unit="mm"),
        )
        centre = self.lit_center_mm
        if not isinstance(centre, (tuple, list)) or len(centre) != 2:
            raise TypeError(
                f"lit_center_mm must be a pair (x, y) of numbers, got lit_center_mm={centre!r}"
            )
        put(
            "lit_center_mm",
            (
                check_number("lit_center_mm[0]", centre[0]),
                check_number("lit_center_mm[1]", centre[1]),
            ),
        )
        put("outside_level",
            check_number("outside_level", self.outside_level, low=0.0, high=1.0, high_open=True))
        put(
            "optical_blur_mm",
            check_number("optical_blur_mm", self.optical_blur_mm, low=0.0, high=10.0, unit="mm"),
        )
        for name, low, high in (("fold_x_mm", -1e4, 1e4), ("fold_width_mm", 0.0, 1e4),
                                ("fold_edge_mm", 0.0, 1e4)):
            put(name, check_number(name, getattr(self, name), low=low, high=high, unit="mm"))
        for name in ("fold_depth", "stray_light"):
            put(name, check_number(name, getattr(self, name), low=0.0, high=1.0, high_open=True))
        if self.jpeg_quality is not None:
            put("jpeg_quality", _integer("jpeg_quality", self.jpeg_quality, 1, 100))
            if self.bit_depth != 8:
                raise ValueError(
                    "bit_depth must be 8 with jpeg_quality (JPEG frames are 8-bit), got "
                    f"bit_depth={self.bit_depth} with jpeg_quality={self.jpeg_quality}"
                )

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

    def ice_flaws(self, view: str = "tir") -> tuple[int, int]:
        """Bubbles and scratches the renderer draws in this view: the given counts, or
        where a count is None the thesis's ice seen here.

        TIR view: the thesis's 12 bubbles and 5 scratches in its 64 x 25.6 mm view as
        densities (:func:`synthetic._render_tir.ice_flaws_expected`: bubbles by area,
        scratches by the ones that cross the view), rounded to whole flaws. Side view: the
        bubbles in the ice slab per image width, 12 per 64 mm of width.

        The counts used to be 12 and 5 in every view: a 2.56 mm micro view at 0.01 mm/px
        held 12 bubbles of 0.05-0.3 mm, 250 times the thesis's ice.

        Examples
        --------
        >>> CameraSettings().ice_flaws()
        (12, 5)
        >>> CameraSettings(mm_per_px=0.01, width_px=256, height_px=256).ice_flaws()
        (0, 0)
        >>> CameraSettings(mm_per_px=0.01, n_bubbles=3).ice_flaws()  # given: as given
        (3, 0)
        """
        _choice("view", view, ("tir", "side"))
        w_mm, h_mm = self.field_of_view_mm
        bubbles, scratches = ice_flaws_expected(w_mm, h_mm)
        if view == "side":
            bubbles = THESIS_BUBBLES * w_mm / THESIS_FIELD_MM[0]
        return (
            round(bubbles) if self.n_bubbles is None else self.n_bubbles,
            round(scratches) if self.n_scratches is None else self.n_scratches,
        )


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
        The camera moves with the block: the block stays fixed in the image and the ice
        (side view: its slab and bubbles; TIR: bubbles, scratches and groove) moves under
        it, without motion blur of the block; the light field, dust and vignetting stay
        fixed to the camera. Not with a static ``scene``.
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
        Rubber loss factor tan(delta) of the element springs, in [0, 2]; by default the one
        rubber's (:data:`friction_model.compound.REFERENCE_COMPOUND`, 0.2), as in
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
        :class:`friction_model.contact.laws.RelaxedFriction`), s, in [0, 1] (the bounds of
        ``friction_relaxation`` in :mod:`friction_model.effect_registry`); 0 (the default) uses
        the steady law. The model starts (``settle_s`` before frame 0) with mu at its
        steady value.
    scene : {"block", "round_pad", "coin", "three_point"}
        TIR view: what touches the ice. "block": the sliding tread block (as before this
        field existed). The others are static contacts, the same in every frame (only the
        noise changes), centred on the lit zone: a round pad of radius ``pad_radius_mm``
        with a Hertz-like pressure ``3/2 p sqrt(1 - r^2/a^2)``; a coin whose flat face
        touches along its rim, an annulus of radii ``coin_radii_mm`` with an elliptic
        profile across it; three round contacts of radius ``point_radius_mm`` at
        ``point_positions_mm``. Their mean pressure is ``pressure_bar``.
    pad_radius_mm : float
        Radius of the round pad, mm, in (0, 100]; 2.75 as in a real FTIR photograph.
    coin_radii_mm : (float, float)
        Inner and outer radius of the coin's contact rim, mm, 0 <= inner < outer <= 100.
    point_radius_mm : float
        Radius of each of the three point contacts, mm, in (0, 100].
    point_positions_mm : tuple of three (x, y), optional
        Centres of the three point contacts relative to the lit zone's centre, mm; default
        an equilateral triangle 3 mm from the centre (at 90, 210 and 330 deg).
    real_contact : {"solid", "patchy", "physical"}
        TIR view: "solid": the whole nominal contact touches (as before this field
        existed); "patchy": only micro-contact patches touch, covering the share
        ``phi(p)`` of the nominal contact that :func:`friction_model.real_contact_fraction`
        gives at the local pressure (see :mod:`synthetic._real_contact`); "physical": each
        element's rough face (``roughness``) in the contact solved at its local pressure,
        with frustrated-TIR grey levels (:mod:`synthetic._physical_block`; needs the
        contact extra, ``rotation_deg`` 0).
    patch_correlation_mm : float
        Size of the micro-contact patches: standard deviation of the Gaussian filter of the
        random field, mm, in (0, 10]; 0.2.
    roughness : str
        Physical scenes ("rough_pad", "rough_sphere"): the rubber's rough surface, a key of
        :data:`synthetic.roughness.ROUGHNESS_PRESETS`. The contact is solved by tamaas
        (optional extra ``contact``) at the nominal pressure ``pressure_bar`` (pad) or the
        mean Hertz pressure ``pressure_bar`` (sphere), with the one rubber's E*; see
        :mod:`synthetic._physical`.
    sphere_radius_mm : float
        Radius of the rough sphere, mm, in (0, 1000]; 5.
    substrate, gap_medium : str
        Physical scenes: what the rubber touches ("ice", "acrylic", "glass") and what fills
        the gap ("air", "water"), :class:`synthetic.ftir.FtirOptics`.
    incidence_deg, wavelength_nm : float
        Physical scenes: angle of the light in the substrate (deg; 60) and its wavelength
        (nm; 550).
    texture : float
        Relative rms modulation of the free surface's light by the ice's (or glass's) own
        texture, in [0, 1): a Gaussian random field of correlation ``texture_mm``,
        multiplied into the light of the static ice (TIR view without ``follow_camera``).
        0 (default): none.
    texture_mm : float
        Correlation length of the texture, mm, in (0, 100]; 0.05.
    holder : {"carrier", "plate", "carriage"}
        Side view: what holds the block. "carrier": the 3 mm steel plate the block is glued
        to, 1 mm longer than the block at either end, backlight above it (as before this
        field existed). "plate": that carrier spans the whole frame width (and the block's
        travel) at all times. "carriage": the plate, and above it the rig's carriage, as
        dark as the plate, up to the top of the frame. TIR view: "carrier" only.

    Notes
    -----
    Invalid values raise ``ValueError`` (``TypeError`` for a wrong type) naming the field.
    Specs that leave the velocity-step fields and the real-footage fields (``scene`` and
    after, the camera's ``lit_*``, ``outside_level`` and ``jpeg_quality``, a TIR
    ``follow_camera``) at their defaults render exactly as before they existed (same bytes,
    same ``meta.json``: :meth:`to_dict` lists them only when set).
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
    loss_factor: float = REFERENCE_COMPOUND.loss_factor
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
    scene: str = "block"
    pad_radius_mm: float = 2.75
    coin_radii_mm: tuple[float, float] = (7.0, 8.0)
    point_radius_mm: float = 1.0
    point_positions_mm: tuple[tuple[float, float], ...] | None = None
    real_contact: str = "solid"
    patch_correlation_mm: float = 0.2
    roughness: str = "abraded_rubber"
    sphere_radius_mm: float = 5.0
    substrate: str = "ice"
    gap_medium: str = "air"
    incidence_deg: float = 60.0
    wavelength_nm: float = 550.0
    texture: float = 0.0
    texture_mm: float = 0.05
    holder: str = "carrier"

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
            check_number(
                "velocity_mps", self.velocity_mps, low=0.0, high=30.0, low_open=True, unit="m/s"
            ),
        )
        put("n_frames", _integer("n_frames", self.n_frames, 1, 10_000_000))
        put(
            "pressure_bar",
            check_number(
                "pressure_bar", self.pressure_bar, low=0.0, high=10.0, low_open=True, unit="bar"
            ),
        )
        put("temperature_C", check_number("temperature_C", self.temperature_C, low=-60.0, high=0.0))
        put("humidity_pct", check_number("humidity_pct", self.humidity_pct, low=0.0, high=100.0))
        put("salinity_pct", check_number("salinity_pct", self.salinity_pct, low=0.0, high=3.5))
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
        put("dynamics", _choice("dynamics", self.dynamics, ("simulated", "steady")))
        put(
            "settle_s",
            check_number("settle_s", self.settle_s, low=0.0, high=1.0, low_open=True, unit="s"),
        )
        put("friction", _choice("friction", self.friction, ("exponential", "drywet")))
        put("loss_factor", check_number("loss_factor", self.loss_factor, low=0.0, high=2.0))
        if self.center_time_s is not None:
            put("center_time_s", check_number("center_time_s", self.center_time_s))
        put("lateral_offset_mm", check_number("lateral_offset_mm", self.lateral_offset_mm))
        put("contrast", check_number("contrast", self.contrast, low=0.0, high=1.0, low_open=True))
        put(
            "contrast_max",
            check_number(
                "contrast_max", self.contrast_max, low=self.contrast, high=1.0, unit="(>= contrast)"
            ),
        )
        put(
            "pressure_ref_MPa",
            check_number(
                "pressure_ref_MPa", self.pressure_ref_MPa, low=0.0, high=1e4, low_open=True
            ),
        )
        put(
            "edge_band_mm",
            check_number("edge_band_mm", self.edge_band_mm, low=0.0, high=5.0, unit="mm"),
        )
        self._check_step(put)
        self._check_real_footage(put)

    def _check_real_footage(self, put: Any) -> None:
        """Validate the scene and real-contact fields."""
        put("scene", _choice("scene", self.scene, SCENES))
        put(
            "real_contact",
            _choice("real_contact", self.real_contact, ("solid", "patchy", "physical")),
        )
        put(
            "pad_radius_mm",
            check_number("pad_radius_mm", self.pad_radius_mm, low=0.0, high=100.0, low_open=True),
        )
        put(
            "point_radius_mm",
            check_number(
                "point_radius_mm", self.point_radius_mm, low=0.0, high=100.0, low_open=True
            ),
        )
        put(
            "patch_correlation_mm",
            check_number(
                "patch_correlation_mm", self.patch_correlation_mm, low=0.0, high=10.0, low_open=True
            ),
        )
        radii = self.coin_radii_mm
        if not isinstance(radii, (tuple, list)) or len(radii) != 2:
            raise TypeError(f"coin_radii_mm must be a pair (inner, outer), got {radii!r}")
        r_in = check_number("coin_radii_mm[0]", radii[0], low=0.0, high=100.0)
        r_out = check_number("coin_radii_mm[1]", radii[1], low=r_in, high=100.0, low_open=True)
        put("coin_radii_mm", (r_in, r_out))
        if self.point_positions_mm is not None:
            pts = self.point_positions_mm
            if not isinstance(pts, (tuple, list)) or len(pts) != 3:
                raise ValueError(
                    "point_positions_mm must hold three (x, y) pairs, got "
                    f"point_positions_mm={pts!r}"
                )
            clean = []
            for j, pt in enumerate(pts):
                if not isinstance(pt, (tuple, list)) or len(pt) != 2:
                    raise TypeError(f"point_positions_mm[{j}] must be a pair (x, y), got {pt!r}")
                clean.append(
                    (
                        check_number(f"point_positions_mm[{j}]", pt[0]),
                        check_number(f"point_positions_mm[{j}]", pt[1]),
                    )
                )
            put("point_positions_mm", tuple(clean))
        self._check_physical(put)
        if self.view == "side":
            for name, value, default in (
                ("scene", self.scene, "block"),
                ("real_contact", self.real_contact, "solid"),
                ("camera.lit_shape", self.camera.lit_shape, "full"),
                ("camera.fold_depth", self.camera.fold_depth, 0.0),
                ("camera.stray_light", self.camera.stray_light, 0.0),
            ):
                if value != default:
                    raise ValueError(
                        f"{name} must be {default!r} for view='side' (a TIR feature), got "
                        f"{name}={value!r}"
                    )
        put("holder", _choice("holder", self.holder, HOLDERS))
        if self.view == "tir" and self.holder != "carrier":
            raise ValueError(f"holder must be 'carrier' for view='tir' (a side-view feature), "
                             f"got holder={self.holder!r}")
        if self.scene != "block" and self.follow_camera:
            raise ValueError(
                f"follow_camera must be False for a static scene, got follow_camera=True with "
                f"scene={self.scene!r}"
            )

    def _check_physical(self, put: Any) -> None:
        """Validate the fields of the physical scenes and the surface texture."""
        put("roughness", _choice("roughness", self.roughness, tuple(ROUGHNESS_PRESETS)))
        put(
            "sphere_radius_mm",
            check_number(
                "sphere_radius_mm", self.sphere_radius_mm, low=0.0, high=1000.0, low_open=True
            ),
        )
        put("substrate", _choice("substrate", self.substrate, tuple(SUBSTRATE_INDEX)))
        put("gap_medium", _choice("gap_medium", self.gap_medium, tuple(GAP_INDEX)))
        put("texture", check_number("texture", self.texture, low=0.0, high=1.0, high_open=True))
        put(
            "texture_mm",
            check_number("texture_mm", self.texture_mm, low=0.0, high=100.0, low_open=True),
        )
        optics = self.optics  # validates angle and wavelength
        if self.is_physical and not optics.total_reflection:
            raise ValueError(
                f"incidence_deg={self.incidence_deg!r} gives no total reflection from "
                f"{self.substrate} into {self.gap_medium} (needs n sin(theta) > "
                f"{optics.n_gap}): a TIR camera would see no contact image"
            )
        if self.is_physical and self.contact_is != "dark":
            raise ValueError(
                "contact_is must be 'dark' for a physical scene (frustrated TIR darkens the "
                f"contact), got contact_is={self.contact_is!r}"
            )
        if self.real_contact == "physical" and (self.scene != "block" or self.view != "tir"):
            raise ValueError(
                "real_contact='physical' is for the sliding block in the TIR view (the static "
                "physical scenes are 'rough_pad' and 'rough_sphere'), got "
                f"scene={self.scene!r}, view={self.view!r}"
            )
        if self.real_contact == "physical" and self.camera.rotation_deg != 0.0:
            raise ValueError(
                "camera.rotation_deg must be 0 with real_contact='physical' (the block's rough "
                f"faces are precomputed along the image rows), got {self.camera.rotation_deg!r}"
            )
        if self.texture > 0.0 and self.follow_camera:
            raise ValueError(
                "texture must be 0 with follow_camera=True (the texture is fixed to the ice), "
                f"got texture={self.texture!r}"
            )

    @property
    def optics(self) -> FtirOptics:
        """The frustrated-TIR optics of the physical scenes."""
        return FtirOptics(
            substrate=self.substrate,
            gap=self.gap_medium,
            incidence_deg=self.incidence_deg,
            wavelength_nm=self.wavelength_nm,
        )

    @property
    def is_physical(self) -> bool:
        """True when contact is drawn from contact mechanics and optics (the static scenes
        "rough_pad" and "rough_sphere", or the block with ``real_contact="physical"``)."""
        return self.scene in PHYSICAL_SCENES or self.real_contact == "physical"

    @property
    def is_static(self) -> bool:
        """True for a static contact scene (no sliding block)."""
        return self.scene != "block"

    @property
    def uses_real_footage_fields(self) -> bool:
        """True when any real-footage field differs from its default (extended outputs:
        the ground-truth columns :data:`REAL_TRUTH_COLUMNS` and ``lit_mask.png``)."""
        d = self.to_dict()
        return (
            any(k in d for k in _REAL_DEFAULTS)
            or any(k in d["camera"] for k in _CAMERA_REAL_DEFAULTS)
            or (self.follow_camera and self.view == "tir")
        )

    @property
    def truth_columns(self) -> tuple[str, ...]:
        """Columns of this spec's ground truth: :data:`TRUTH_COLUMNS`, plus
        :data:`REAL_TRUTH_COLUMNS` when it uses a real-footage field."""
        if self.is_physical:
            return TRUTH_COLUMNS + REAL_TRUTH_COLUMNS + PHYSICAL_TRUTH_COLUMNS
        if self.uses_real_footage_fields:
            return TRUTH_COLUMNS + REAL_TRUTH_COLUMNS
        return TRUTH_COLUMNS

    def _check_step(self, put: Any) -> None:
        """Validate the velocity step and the friction relaxation (Eq. 5.12) fields (tau in
        the bounds of the registry's ``friction_relaxation``)."""
        tau = get_effect("friction_relaxation").parameter
        put(
            "friction_relaxation_s",
            check_number(
                "friction_relaxation_s", self.friction_relaxation_s, low=tau.lower,
                high=tau.upper, unit="s"
            ),
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
            check_number(
                "velocity_step_to_mps",
                self.velocity_step_to_mps,
                low=0.0,
                high=30.0,
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
            check_number("step_time_s", self.step_time_s, low=0.0, high=self.duration_s, unit="s"),
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
        out = json_safe(dataclasses.asdict(self))
        # the flaws drawn, whether given or the thesis's ice in this view (so a camera
        # rebuilt from meta.json holds them as given counts; the side view draws no
        # scratches, whatever the count)
        out["camera"]["n_bubbles"], out["camera"]["n_scratches"] = self.camera.ice_flaws(self.view)
        for name in _STEP_FIELDS:
            if out[name] == _STEP_DEFAULTS[name]:
                del out[name]
        for name, default in _REAL_DEFAULTS.items():
            if out[name] == default:
                del out[name]
        for name, default in _CAMERA_REAL_DEFAULTS.items():
            if out["camera"][name] == default:
                del out["camera"][name]
        for name, default in _SIDE_DEFAULTS.items():
            if out[name] == default:
                del out[name]
        return out


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


@functools.lru_cache(maxsize=64)
def _simulate(spec: _ModelInput) -> _ModelStates:
    """Integrate the rigid block model once per distinct model input (cached)."""
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
        solver=_SOLVER,
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


def _contact_params(spec: FootageSpec) -> ContactParams:
    geom = spec.geometry
    return ContactParams(
        winkler_Pa_per_mm=float(REFERENCE_YOUNGS_MODULUS_PA) / geom.height_mm,
        width_mm=geom.width_mm,
        load_N=spec.pressure_bar * 1e5 * geom.nominal_area_mm2 * 1e-6,
        contrast=spec.contrast,
        contrast_max=spec.contrast_max,
        pressure_ref_Pa=spec.pressure_ref_MPa * 1e6,
        band_mm=spec.edge_band_mm,
    )


def model_contact_ratio(spec: FootageSpec) -> float:
    """Contact ratio (real contact area / nominal area) that the models predict for ``spec``.

    Parameters
    ----------
    spec : FootageSpec

    Returns
    -------
    float
        ``scene="block"``: the real contact area over the block's nominal area ``L w``
        (Fig. 4.21), ``sum_i int phi(p_i) dxi / L`` over the pressure cells the renderer
        draws (``phi = 1`` for ``real_contact="solid"``: the face contact ratio of the rigid
        model), averaged over the clip's frames (one steady state for
        ``dynamics="steady"``). Static scenes: the real area over the scene's nominal
        contact area, the mean of ``phi(p)`` over its pressure profile (1 when solid).

    Notes
    -----
    The renderer draws ``phi`` as the expected covered share; a rendered clip's ratio
    differs from this by the finite sample of micro-contact patches and by the parts of the
    contact outside the image or the lit zone.
    """
    if not isinstance(spec, FootageSpec):
        raise TypeError(f"spec must be a FootageSpec, got {type(spec).__name__}")
    patchy = spec.real_contact == "patchy"
    if spec.is_physical and spec.is_static:
        setup = physical_setup(spec)
        solved = scene_contact(setup)
        if spec.scene == "rough_pad":
            return solved.contact_fraction
        a_mm = setup.hertz_radius_mm
        return solved.contact_fraction * solved.size_mm**2 / (math.pi * a_mm * a_mm)
    if spec.is_static:
        if not patchy:
            return 1.0
        sc = static_scene(spec)
        n = 20000
        if sc.kind == "coin":
            r = sc.inner_radius_mm + (np.arange(n) + 0.5) / n * (sc.radius_mm - sc.inner_radius_mm)
        else:
            r = (np.arange(n) + 0.5) / n * sc.radius_mm
        p, _ = sc.pressure(r + sc.centres_mm[0][0], np.full(n, sc.centres_mm[0][1]))
        return float(np.sum(real_fraction(p) * r) / np.sum(r))
    geom = spec.geometry
    states = _simulate(_ModelInput.of(spec))
    params = _contact_params(spec)
    spacing = spec.camera.mm_per_px / 8.0
    ratios = []
    rows = {states.row(k) for k in range(spec.n_frames)}
    for row in sorted(rows):
        k = row - states.first_row if states.phi_rad.shape[0] > 1 else 0
        frame = _element_frame(geom, states, k)
        contacts = element_contacts(frame, params, node_spacing_mm=spacing)
        nodes, p_mid, elem = pressure_cells(frame, contacts)
        if spec.real_contact == "physical":
            weight = physical_fractions(
                ROUGHNESS_PRESETS[spec.roughness], spec.seed, p_mid, spec.pressure_bar * 1e5
            ) * (elem >= 0)
        else:
            weight = real_fraction(p_mid) if patchy else (elem >= 0).astype(float)
        ratios.append(float(np.sum(weight * np.diff(nodes))) / geom.length_mm)
    return float(np.mean(ratios))


# -- real footage: lit zone, static scenes, moving ice ------------------------------------------
@dataclass(frozen=True)
class LitZone:
    """The lit zone of a spec's TIR view (fixed to the camera).

    Attributes
    ----------
    shape : str
        ``camera.lit_shape``.
    size_mm : float
        Disc radius, ellipse semi-axis along x or band half-height, mm (inf for "full").
    factor : (H, W) ndarray of float32
        Light factor of each pixel: 1 inside, ``outside_level`` outside, a smooth step
        over the rim (all ones for "full").
    mask : (H, W) ndarray of bool
        The lit mask: pixels whose centre lies inside the zone boundary, i.e. whose light
        factor is at least half-way from ``outside_level`` to 1 (all True for "full").
    """

    shape: str
    size_mm: float
    factor: np.ndarray
    mask: np.ndarray

    @property
    def fraction(self) -> float:
        """Share of the frame's pixels in the lit mask."""
        return float(np.mean(self.mask))


def lit_zone(spec: FootageSpec) -> LitZone:
    """The lit zone of ``spec`` (light factor and lit mask, see :class:`LitZone`).

    Parameters
    ----------
    spec : FootageSpec

    Returns
    -------
    LitZone
        Its size is chosen so that the mask covers ``camera.lit_fraction`` of the frame (to
        the pixels along one perimeter); the boundary is the level ``s = 1/2`` of the rim's
        smooth step (:mod:`synthetic._lighting`).
    """
    cam = spec.camera
    h, w = cam.height_px, cam.width_px
    if cam.lit_shape == "full":
        return LitZone("full", math.inf, np.ones((h, w), dtype=np.float32), np.ones((h, w), bool))
    size = lit_zone_size(
        cam.lit_shape,
        cam.lit_fraction,
        height_px=h,
        width_px=w,
        mm_per_px=cam.mm_per_px,
        center_mm=cam.lit_center_mm,
    )
    d = lit_distance(
        cam.lit_shape,
        size,
        height_px=h,
        width_px=w,
        mm_per_px=cam.mm_per_px,
        center_mm=cam.lit_center_mm,
    )
    factor = lit_factor(
        d, rim_mm=cam.lit_rim_mm, mm_per_px=cam.mm_per_px, outside=cam.outside_level
    )
    return LitZone(cam.lit_shape, size, factor, d >= 0.0)


def lit_mask(spec: FootageSpec) -> np.ndarray:
    """The lit mask of ``spec``: (H, W) bool, True where the TIR light reaches the camera.

    The ground truth counts contact only inside it (``lit_mask.png`` of a clip folder holds
    it as 0/255). See :class:`LitZone`.
    """
    return lit_zone(spec).mask


def static_scene(spec: FootageSpec) -> StaticScene:
    """The static contact of ``spec.scene`` in image coordinates (mm; not for "block")."""
    cam = spec.camera
    w_mm, h_mm = cam.field_of_view_mm
    cx = 0.5 * w_mm + cam.lit_center_mm[0]
    cy = 0.5 * h_mm + cam.lit_center_mm[1]
    p = spec.pressure_bar * 1e5
    if spec.scene == "round_pad":
        return StaticScene("round_pad", ((cx, cy),), spec.pad_radius_mm, 0.0, p)
    if spec.scene == "coin":
        r_in, r_out = spec.coin_radii_mm
        return StaticScene("coin", ((cx, cy),), r_out, r_in, p)
    if spec.scene == "three_point":
        pts = spec.point_positions_mm
        if pts is None:
            pts = tuple(
                (3.0 * math.cos(math.radians(a)), -3.0 * math.sin(math.radians(a)))
                for a in (90.0, 210.0, 330.0)
            )
        centres = tuple((cx + dx, cy + dy) for dx, dy in pts)
        return StaticScene("three_point", centres, spec.point_radius_mm, 0.0, p)
    raise ValueError(f"scene must be a static scene, got scene={spec.scene!r}")


def physical_setup(spec: FootageSpec) -> PhysicalSetup:
    """The contact-mechanics and optics set-up of a physical scene (centred on the lit zone)."""
    if not (spec.is_physical and spec.is_static):
        raise ValueError(f"scene must be one of {list(PHYSICAL_SCENES)}, got {spec.scene!r}")
    cam = spec.camera
    w_mm, h_mm = cam.field_of_view_mm
    return PhysicalSetup(
        scene=spec.scene,
        roughness=ROUGHNESS_PRESETS[spec.roughness],
        optics=spec.optics,
        pressure_Pa=spec.pressure_bar * 1e5,
        pad_radius_mm=spec.pad_radius_mm,
        sphere_radius_mm=spec.sphere_radius_mm,
        centre_mm=(0.5 * w_mm + cam.lit_center_mm[0], 0.5 * h_mm + cam.lit_center_mm[1]),
        seed=spec.seed,
        optical_blur_mm=cam.optical_blur_mm,
    )


def _texture_field(spec: FootageSpec, mm_per_px: float) -> np.ndarray:
    """Light factor of the free surface's own texture: ``1 + texture * f`` (clipped at 0),
    ``f`` a Gaussian random field of unit variance and correlation ``texture_mm``."""
    cam = spec.camera
    rng = np.random.default_rng(np.random.SeedSequence(spec.seed, spawn_key=(3,)))
    noise = rng.standard_normal((cam.height_px, cam.width_px))
    sigma = spec.texture_mm / mm_per_px
    field_ = gaussian_filter(noise, sigma, mode="wrap") if sigma > 0.1 else noise
    field_ /= max(float(field_.std()), 1e-12)
    return np.clip(1.0 + spec.texture * field_, 0.0, None).astype(np.float32)


class _IceCanvas:
    """Ice imperfections over the whole stretch a following TIR camera sees (moving ice)."""

    def __init__(self, clip: _Clip, rng: np.random.Generator) -> None:
        spec, cam, path = clip.spec, clip.spec.camera, clip.path
        px = cam.mm_per_px
        travel = max(abs(clip.travel_mm(0)), abs(clip.travel_mm(spec.n_frames - 1))) + px
        self.c, self.s = math.cos(path.rotation_rad), math.sin(path.rotation_rad)
        self.mx = math.ceil(travel * abs(self.c) / px) + 2
        self.my = math.ceil(travel * abs(self.s) / px) + 2
        w, h = cam.width_px + 2 * self.mx, cam.height_px + 2 * self.my
        canvas = dataclasses.replace(path, width_mm=w * px, height_mm=h * px)
        scale = (w * h) / (cam.width_px * cam.height_px)
        n_bubbles, n_scratches = cam.ice_flaws()
        self.ice = ice_transmission(
            canvas,
            rng=rng,
            n_bubbles=round(n_bubbles * scale),
            n_scratches=round(n_scratches * scale),
            groove_depth=cam.groove_depth,
        )
        self.clip = clip
        self.shape = (cam.height_px, cam.width_px)
        self.px = px

    def frame(self, k: int) -> np.ndarray:
        """Ice transmission seen in frame k: the canvas shifted by the travel (bilinear)."""
        d = self.clip.path.direction * self.clip.travel_mm(k) / self.px
        oy, ox = self.my - d * self.s, self.mx - d * self.c
        iy, ix = math.floor(oy), math.floor(ox)
        fy, fx = np.float32(oy - iy), np.float32(ox - ix)
        h, w = self.shape
        a = self.ice
        top = (1 - fx) * a[iy : iy + h, ix : ix + w] + fx * a[iy : iy + h, ix + 1 : ix + 1 + w]
        bot = (1 - fx) * a[iy + 1 : iy + 1 + h, ix : ix + w] + fx * a[
            iy + 1 : iy + 1 + h, ix + 1 : ix + 1 + w
        ]
        return ((1 - fy) * top + fy * bot).astype(np.float32)


# -- the clip --------------------------------------------------------------------------------
class _Clip:
    """Everything static of one spec: model, path, scene; renders frame ``k`` on demand."""

    def __init__(self, spec: FootageSpec, *, contact: bool = True) -> None:
        """`contact`: False renders a static scene without its contact (its light alone:
        the rig's empty frame, :func:`synthetic.table.empty_reference`)."""
        self.spec = spec
        self.extended = spec.uses_real_footage_fields
        self.columns = spec.truth_columns
        cam = spec.camera
        self.geom = spec.geometry
        self.states = None if spec.is_static else _simulate(_ModelInput.of(spec))
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
        self.contact = _contact_params(spec)
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
        self.lit = lit_zone(spec)
        if cam.fold_depth > 0.0:  # skipped at 0: clips without a fold stay byte-identical
            illum = illum * fold_factor(
                cam.height_px, cam.width_px, mm_per_px=cam.mm_per_px, x_mm=cam.fold_x_mm,
                width_mm=cam.fold_width_mm, edge_mm=cam.fold_edge_mm, depth=cam.fold_depth,
            )
        #: stray light added to every frame's signal (None without it)
        self.stray: np.ndarray | None = None
        if cam.stray_light > 0.0:
            self.stray = (cam.stray_light * level * self.lit.factor).astype(np.float32)
        self.ice_canvas: _IceCanvas | None = None
        if spec.view == "tir":
            self._init_tir_background(level, illum, dust, scene_rng)
        else:
            self._init_side_background(level, illum, dust, scene_rng)
        self.node_spacing_mm = cam.mm_per_px / 8.0
        self._cached: tuple[int, Any] | None = None
        self.patches: PatchTexture | None = None
        if spec.real_contact == "patchy":
            self.patches = self._patch_texture()
        self.static: tuple[np.ndarray, list[dict[str, Any]]] | None = None
        self.physical: Any = None
        self.phys_block: PhysicalBlock | None = None
        self._phys_cache: tuple[int, Any] | None = None
        #: set by render_footage for the frames whose covered-fraction image it writes
        self.keep_covered = False
        self.last_covered: np.ndarray | None = None
        self._frame_k = 0
        if spec.real_contact == "physical":
            self.phys_block = self._physical_block()
        if spec.is_static:
            if not contact:  # the light alone
                self.static = (self.base.astype(np.float32), [])
            elif spec.is_physical:
                self.static = self._render_physical()
            else:
                self.static = self._render_static()
        self.sensor = Sensor(
            (cam.height_px, cam.width_px),
            bit_depth=cam.bit_depth,
            gain=cam.gain,
            full_well_e=cam.full_well_e,
            read_noise_dn=cam.read_noise,
            shot_noise=cam.shot_noise,
        )

    def _init_tir_background(
        self, level: np.float32, illum: np.ndarray, dust: np.ndarray, scene_rng: np.random.Generator
    ) -> None:
        """Signal of the TIR view without the block: light, ice (or the moving ice canvas of
        ``follow_camera``), dust and the lit zone."""
        spec, cam = self.spec, self.spec.camera
        if spec.follow_camera:
            self.ice_canvas = _IceCanvas(self, scene_rng)
            self.camera_base = (level * illum * dust * self.lit.factor).astype(np.float32)
            self.base = self.camera_base * self.ice_canvas.frame(0)
        else:
            n_bubbles, n_scratches = cam.ice_flaws()
            ice = ice_transmission(
                self.path,
                rng=scene_rng,
                n_bubbles=n_bubbles,
                n_scratches=n_scratches,
                groove_depth=cam.groove_depth,
            )
            if spec.texture > 0.0:
                ice = ice * _texture_field(spec, self.path.mm_per_px)
            # the factor is exactly 1 everywhere for a fully lit frame
            self.base = (level * illum * ice * dust * self.lit.factor).astype(np.float32)
        self.lateral = self.path.lateral_coverage()
        self._lit_grid = self._lit_strip_grid()

    def _lit_strip_grid(self) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
        """What :meth:`_lit_area` needs of the clip, fixed for all frames: the lateral
        coverage of the lit pixels and, on a rotated path, each pixel's mid-row segment in
        path coordinates (start and end)."""
        lat_lit = self.lateral.astype(np.float64) * self.lit.mask
        path, px = self.path, self.path.mm_per_px
        if path.rotation_rad == 0.0:
            return lat_lit.sum(axis=0), None, None
        h, w = lat_lit.shape
        c, s = math.cos(path.rotation_rad), math.sin(path.rotation_rad)
        xc, yc = path.centre
        xs = np.arange(w, dtype=np.float64) * px
        ys = (np.arange(h, dtype=np.float64) + 0.5) * px
        ua = xc + (xs[None, :] - xc) * c + (ys[:, None] - yc) * s
        return lat_lit, ua, ua + px * c

    def _init_side_background(
        self, level: np.float32, illum: np.ndarray, dust: np.ndarray, scene_rng: np.random.Generator
    ) -> None:
        """Side view without the block: light and dust, the layout of its levels and the
        bubbles of the ice slab."""
        spec, cam = self.spec, self.spec.camera
        w_mm, h_mm = cam.field_of_view_mm
        self.base = (level * illum * dust).astype(np.float32)
        dark = spec.contact_is == "dark"
        # Levels (fractions of S): backlight 1.0 / 0.1, carbon-black rubber reflects
        # ~8 % (0.85 front-lit), matte steel 0.4 / 0.5, ice slab 0.6 / 0.3. The rubber
        # above the sipe ground is not given in the thesis: 2 mm, a usual tread base,
        # glued to a 3 mm steel carrier that overhangs the block by 1 mm.
        # holder="plate": the carrier spans the view wherever the block is (its travel
        # included); "carriage": above it the rig's carriage, as dark, to the frame's top
        v_max = max(spec.velocity_mps, spec.velocity_step_to_mps or 0.0)
        travel = v_max * 1e3 * spec.duration_s
        reach = w_mm + self.geom.length_mm + 2.0 * travel + 1.0
        base_mm, ice_y = 2.0, _SIDE_ICE_ROW * h_mm
        self.layout = SideLayout(
            ice_y_mm=ice_y,
            base_mm=base_mm,
            carrier_mm=3.0 if spec.holder != "carriage" else 3.0 + ice_y + 2.0 * h_mm,
            carrier_overhang_mm=1.0 if spec.holder == "carrier" else reach,
            background=1.0 if dark else 0.1,
            rubber=0.08 if dark else 0.85,
            carrier=0.4 if dark else 0.5,
            ice=0.6 if dark else 0.3,
        )
        # Bubbles of the ice slab over the whole stretch of track the camera can see:
        # radius 0.05-0.3 mm as in the TIR view, 0.3-5 mm below the surface, brighter
        # than the ice by 15-40 % (they scatter the backlight towards the camera).
        span = w_mm + 2.0 * travel
        n_b = round(cam.ice_flaws("side")[0] * span / w_mm)
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

    def _patch_texture(self) -> PatchTexture:
        """The micro-contact field, fixed to the rubber (block: (xi, v); static: (x, y))."""
        spec, cam = self.spec, self.spec.camera
        rng = np.random.default_rng(np.random.SeedSequence(spec.seed, spawn_key=(2,)))
        h = cam.mm_per_px / SUPERSAMPLE
        w_mm, h_mm = cam.field_of_view_mm
        if spec.is_static:
            return PatchTexture((0.0, 0.0), (w_mm, h_mm), h, spec.patch_correlation_mm, rng)
        half_diag = 0.5 * math.hypot(w_mm, h_mm)
        v0 = max(spec.lateral_offset_mm - 0.5 * self.geom.width_mm, -half_diag) - 1.0
        v1 = min(spec.lateral_offset_mm + 0.5 * self.geom.width_mm, half_diag) + 1.0
        xi0 = -0.5 * self.geom.height_mm - 1.0  # tips trail or lead by less than the height
        extent = (self.geom.length_mm + self.geom.height_mm + 2.0, v1 - v0)
        return PatchTexture((xi0, v0), extent, h, spec.patch_correlation_mm, rng)

    def _render_static(self) -> tuple[np.ndarray, list[dict[str, Any]]]:
        """Signal and ground-truth rows of a static scene (the same in every frame)."""
        spec, cam = self.spec, self.spec.camera
        scene = static_scene(spec)
        px = cam.mm_per_px
        rows_px, cols_px = scene.bbox_px(px, cam.height_px, cam.width_px)
        x, y = sample_points(rows_px, cols_px, px)
        p, idx = scene.pressure(x, y)
        patches = self.patches
        phi = real_fraction(p) if patches is not None else None
        covered = idx >= 0
        if patches is not None:
            covered &= patches(np.broadcast_to(x, p.shape), np.broadcast_to(y, p.shape)) < phi
        dark = np.where(covered, self.contact.darkness(p), 0.0)
        sig = self._apply_darkness(self.base, dark, rows_px, cols_px, blur_px=0.0)
        sub_area = (px / SUPERSAMPLE) ** 2
        lit = self._lit_samples(rows_px, cols_px)
        n = len(scene.centres_mm)
        nominal = np.bincount(idx[(idx >= 0) & lit], minlength=n)[:n] * sub_area
        real = np.bincount(idx[covered & lit], minlength=n)[:n] * sub_area
        in_view = np.bincount(idx[idx >= 0], minlength=n)[:n] > 0
        nan = math.nan
        rows: list[dict[str, Any]] = []
        for i in range(n):
            if not in_view[i]:
                continue
            xc, _ = scene.centres_mm[i]
            rows.append(
                {
                    "element": i,
                    "in_view": True,
                    "contact_area_mm2": float(real[i]),
                    "contact_length_mm": nan,
                    "front_edge_x_mm": nan,
                    "front_peak_x_mm": xc if spec.scene != "coin" else nan,
                    "deflection_angle_deg": nan,
                    "tilt_deg": nan,
                    "tip_deflection_mm": nan,
                    "contact_fraction": 1.0,
                    "normal_force_N": scene.pressure_Pa * scene.element_area_mm2 * 1e-6,
                    "peak_pressure_MPa": scene.peak_pressure_Pa * 1e-6,
                    "lever_arm_mm": nan,
                    "nominal_contact_area_mm2": float(nominal[i]),
                    "real_contact_fraction": float(real[i] / nominal[i]) if nominal[i] > 0 else nan,
                }
            )
        total: dict[str, Any] = {col: nan for col in TRUTH_COLUMNS + REAL_TRUTH_COLUMNS}
        total.update(element=-1, in_view=bool(rows))
        nom_sum = float(sum(r["nominal_contact_area_mm2"] for r in rows))
        real_sum = float(sum(r["contact_area_mm2"] for r in rows))
        total.update(
            contact_area_mm2=real_sum,
            nominal_contact_area_mm2=nom_sum,
            real_contact_fraction=real_sum / nom_sum if nom_sum > 0 else nan,
        )
        if rows:
            total.update(
                contact_fraction=1.0,
                normal_force_N=float(sum(r["normal_force_N"] for r in rows)),
                peak_pressure_MPa=scene.peak_pressure_Pa * 1e-6,
            )
        return sig, [total, *rows]

    def _physical_block(self) -> PhysicalBlock:
        """Precompute the block's rough faces over the pixel rows it can cover."""
        spec, cam = self.spec, self.spec.camera
        lat_rows = np.nonzero(self.lateral.max(axis=1) > 0)[0]
        self._phys_rows = (int(lat_rows[0]), int(lat_rows[-1]) + 1)
        r0, r1 = self._phys_rows
        # area of each pixel the truth counts: lateral coverage x lit mask x pixel area
        px = cam.mm_per_px
        self._phys_weight = self.lateral[r0:r1] * self.lit.mask[r0:r1] * px * px
        rows = np.arange(*self._phys_rows, dtype=np.float64)
        row_v = rows * cam.mm_per_px - self.path.centre[1] - self.path.lateral_mm
        states = self.states
        sample = np.unique(np.linspace(0, spec.n_frames - 1, min(spec.n_frames, 12)).astype(int))
        p_max = 0.0
        for k in sample:
            frame = _element_frame(self.geom, states, int(k))
            contacts = element_contacts(frame, self.contact, node_spacing_mm=self.node_spacing_mm)
            _, p_mid, _ = pressure_cells(frame, contacts)
            p_max = max(p_max, float(p_mid.max()) if p_mid.size else 0.0)
        return PhysicalBlock(
            ROUGHNESS_PRESETS[spec.roughness],
            spec.optics,
            spec.seed,
            n_elements=self.geom.n_elements,
            row_v_mm=row_v,
            mm_per_px=cam.mm_per_px,
            nominal_pressure_Pa=spec.pressure_bar * 1e5,
            max_pressure_Pa=p_max,
        )

    def _render_physical_block(
        self,
        frame: ElementFrame,
        contacts: list[Any],
        u_front: float,
        base: np.ndarray,
        blur_mm: float,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """TIR signal of the block's physical contact; each element's true, near-contact and
        optical contact area inside the lit mask, mm^2 (the optical: its darkness before
        the blur over that of full contact)."""
        pb = self.phys_block
        n = frame.n_elements
        key = self.states.row(self._frame_k)
        if self._phys_cache is None or self._phys_cache[0] != key:
            nodes, p_mid, elem = pressure_cells(frame, contacts)
            if p_mid.size == 0:
                self._phys_cache = (key, None)
            else:
                fb = pb.bins(nodes, p_mid, elem)
                ints = tuple(
                    BinIntegrals(v, fb.xi0_mm, pb.bin_mm) for v in (fb.dark, fb.covered, fb.near)
                )
                edges = fb.xi0_mm + np.arange(fb.element.size + 1) * pb.bin_mm
                spans = []
                for i in range(n):
                    sel = np.nonzero(fb.element == i)[0]
                    spans.append((edges[sel[0]], edges[sel[-1] + 1]) if sel.size else None)
                self._phys_cache = (key, (ints, spans))
        cached = self._phys_cache[1]
        if cached is None:
            return base.copy(), np.zeros(n), np.zeros(n), np.zeros(n)
        (dark_i, cov_i, near_i), spans = cached
        px = self.path.mm_per_px
        w = base.shape[1]
        xs = np.arange(w + 1, dtype=np.float64) * px
        xi = (xs - u_front) * self.path.direction
        lo, hi = np.minimum(xi[:-1], xi[1:]), np.maximum(xi[:-1], xi[1:])
        r0, r1 = self._phys_rows
        lat = self.lateral[r0:r1]
        out = base.copy()
        end = dark_i.xi0 + dark_i.m * pb.bin_mm
        cols = np.nonzero((hi + blur_mm > dark_i.xi0) & (lo - blur_mm < end))[0]
        if cols.size:
            c0, c1 = int(cols[0]), int(cols[-1]) + 1
            dark = dark_i.box_means(lo[c0:c1], hi[c0:c1], blur_mm) * lat[:, c0:c1]
            out[r0:r1, c0:c1] = base[r0:r1, c0:c1] * (1.0 - dark).astype(np.float32)
            if self.keep_covered:
                cov = np.zeros(base.shape, np.float32)
                cov[r0:r1, c0:c1] = cov_i.box_means(lo[c0:c1], hi[c0:c1]) * lat[:, c0:c1]
                self.last_covered = cov
        weight = self._phys_weight
        real, near, optical = np.zeros(n), np.zeros(n), np.zeros(n)
        full = self.spec.optics.contact_darkness
        for i, span in enumerate(spans):
            if span is None:
                continue
            a, b = span
            c = np.nonzero((hi > a) & (lo < b))[0]
            if not c.size:
                continue
            la, hb = np.clip(lo[c], a, b), np.clip(hi[c], a, b)
            # integrals over the element's part of each pixel, per pixel area
            wc = weight[:, c] / (hi[c] - lo[c])
            real[i] = float(np.sum((cov_i.first(hb) - cov_i.first(la)) * wc))
            near[i] = float(np.sum((near_i.first(hb) - near_i.first(la)) * wc))
            optical[i] = float(np.sum((dark_i.first(hb) - dark_i.first(la)) * wc)) / full
        return out, real, near, optical

    def _render_physical(self) -> tuple[np.ndarray, list[dict[str, Any]]]:
        """Signal and ground-truth rows of a physical scene (contact mechanics and optics)."""
        spec, cam = self.spec, self.spec.camera
        setup = physical_setup(spec)
        r = render_physical(
            setup, height_px=cam.height_px, width_px=cam.width_px, mm_per_px=cam.mm_per_px
        )
        self.physical = r
        sig = (self.base * r.reflectance).astype(np.float32)
        lit = self.lit.mask
        px2 = cam.mm_per_px**2
        real = float(np.sum(r.covered[lit], dtype=np.float64)) * px2
        near = float(np.sum(r.near[lit], dtype=np.float64)) * px2
        optical = float(np.sum(r.optical[lit], dtype=np.float64)) * px2
        nominal = float(np.sum(r.nominal[lit], dtype=np.float64)) * px2
        radius = setup.nominal_radius_mm
        load_N = setup.pressure_Pa * math.pi * (radius * 1e-3) ** 2
        peak = setup.pressure_Pa * (1.5 if spec.scene == "rough_sphere" else 1.0)
        nan = math.nan
        in_view = bool(np.any(r.nominal > 0))
        row: dict[str, Any] = {col: nan for col in self.columns[2:]}
        row.update(
            element=0,
            in_view=in_view,
            contact_area_mm2=real,
            front_peak_x_mm=setup.centre_mm[0],
            contact_fraction=1.0,
            normal_force_N=load_N,
            peak_pressure_MPa=peak * 1e-6,
            nominal_contact_area_mm2=nominal,
            real_contact_fraction=real / nominal if nominal > 0 else nan,
            near_contact_area_mm2=near,
            optical_contact_area_mm2=optical,
        )
        total = dict(row, element=-1, front_peak_x_mm=nan)
        return sig, [total, row] if in_view else [dict(total, in_view=False)]

    def _lit_samples(self, rows_px: tuple[int, int], cols_px: tuple[int, int]) -> np.ndarray:
        """The lit mask of the pixels in the ranges, repeated onto their sub-pixel samples."""
        m = self.lit.mask[rows_px[0] : rows_px[1], cols_px[0] : cols_px[1]]
        return np.repeat(np.repeat(m, SUPERSAMPLE, axis=0), SUPERSAMPLE, axis=1)

    def _apply_darkness(
        self,
        base: np.ndarray,
        dark_samples: np.ndarray,
        rows_px: tuple[int, int],
        cols_px: tuple[int, int],
        *,
        blur_px: float,
    ) -> np.ndarray:
        """The TIR signal with the pixel means of ``dark_samples`` in the given ranges."""
        bright = self.spec.contact_is == "bright"
        c_max = np.float32(self.spec.contrast_max)
        out = base * np.float32(1.0 - c_max) if bright else base.copy()
        if dark_samples.size == 0:
            return out
        dark = pool(dark_samples).astype(np.float32)
        if blur_px > 0.0:
            dark = box_blur_x(dark, blur_px)
        r0, r1 = rows_px
        c0, c1 = cols_px
        b = base[r0:r1, c0:c1]
        out[r0:r1, c0:c1] = b * ((np.float32(1.0) - c_max + dark) if bright else (1.0 - dark))
        return out

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
        if self.static is not None:
            return self.static[0], self._table(k, [dict(r) for r in self.static[1]])
        frame, contacts, deflection, profile = self._model_frame(k)
        self._frame_k = k
        u_front = self.u_front(k)
        bright = spec.contact_is == "bright"
        if spec.view == "tir":
            base = (
                self.base
                if self.ice_canvas is None
                else self.camera_base * self.ice_canvas.frame(k)
            )
            blur = 0.0 if spec.follow_camera else self.blur_of(k)
            real = near = optical = None
            if self.patches is not None:
                sig, real = self._render_patchy(frame, contacts, u_front, base, blur)
            elif self.phys_block is not None:
                sig, real, near, optical = self._render_physical_block(
                    frame, contacts, u_front, base, blur
                )
            else:
                sig = render_tir_signal(
                    profile,
                    self.path,
                    u_front=u_front,
                    blur_mm=blur,
                    lateral=self.lateral,
                    base=base,
                    contrast=spec.contrast_max,
                    bright=bright,
                )
            rows = tir_truth_rows(
                frame, contacts, self.path, u_front=u_front, deflection_deg=deflection
            )
            if self.extended:
                self._real_truth(rows, frame, contacts, u_front, real)
            if near is not None:
                for r in rows:
                    i = int(r["element"])
                    r["near_contact_area_mm2"] = float(near[i] if i >= 0 else near.sum())
                    r["optical_contact_area_mm2"] = float(
                        optical[i] if i >= 0 else optical.sum()
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
            outlines = element_polygons(
                frame,
                height_mm=self.geom.height_mm,
                block_length_mm=self.geom.length_mm,
                layout=self.layout,
                u_front=u_front,
                path=self.path,
            )
            sig = render_side_signal(
                outlines,
                layout=self.layout,
                path=self.path,
                base=self.base,
                ice_texture=tex,
                blur_px=self.blur_of(k) / spec.camera.mm_per_px,
                blur_block=not spec.follow_camera,
            )
            rows = self._side_rows(frame, contacts, outlines[0], u_front, deflection)
            if self.extended:
                self._real_truth(rows, frame, contacts, u_front, None)
        return sig, self._table(k, rows)

    def _table(self, k: int, rows: list[dict[str, Any]]) -> pd.DataFrame:
        rows.sort(key=lambda r: r["element"])
        n = len(rows)
        data: dict[str, Any] = {
            "frame": np.full(n, k, dtype=np.int64),
            "time_s": np.full(n, self.time_of(k)),
        }
        for col in self.columns[2:]:
            data[col] = [r[col] for r in rows]
        table = pd.DataFrame(data)
        table["in_view"] = table["in_view"].astype(bool)
        return table

    # -- real footage: lit zone, patchy contact -----------------------------------------------
    def _lit_area(self, u0: float, u1: float) -> float:
        """Area (mm^2) of the block strip ``u0 <= u <= u1`` inside the lit mask's pixels.

        Exact for ``rotation_deg = 0`` (the product of the lateral and the along-path pixel
        coverage); with rotation each pixel is approximated by its mid-row segment.
        """
        lo, hi = min(u0, u1), max(u0, u1)
        if hi - lo <= 0:
            return 0.0
        path, px = self.path, self.path.mm_per_px
        lat_lit, ua, ub = self._lit_grid
        if ua is None:
            cov = interval_coverage(lo, hi, lat_lit.shape[0], px)
            return float(px * px * np.dot(lat_lit, cov))
        c = math.cos(path.rotation_rad)
        cov = np.clip(np.minimum(ub, hi) - np.maximum(ua, lo), 0.0, None) / (px * c)
        return float(px * px * np.sum(lat_lit * cov))

    def _real_truth(
        self,
        rows: list[dict[str, Any]],
        frame: ElementFrame,
        contacts: list[Any],
        u_front: float,
        real: np.ndarray | None,
    ) -> None:
        """Fill the real-footage columns: areas inside the lit zone, real (patchy) area."""
        front = frame.front_corner_mm
        nan = math.nan
        total_nom = total_real = 0.0
        for r in rows:
            i = int(r["element"])
            if i < 0:
                continue
            c = contacts[i]
            if self.lit.shape == "full":
                nominal = float(r["contact_area_mm2"])
            elif c.length_mm > 0:
                ua = float(self.path.u_of_xi(front[i] + c.zeta_start_mm, u_front))
                ub = float(self.path.u_of_xi(front[i] + c.zeta_end_mm, u_front))
                nominal = self._lit_area(ua, ub)
            else:
                nominal = 0.0
            area = float(real[i]) if real is not None else nominal
            r["contact_area_mm2"] = area
            r["nominal_contact_area_mm2"] = nominal
            r["real_contact_fraction"] = area / nominal if nominal > 0 else nan
            total_nom += nominal
            total_real += area
        for r in rows:
            if int(r["element"]) == -1:
                r["contact_area_mm2"] = total_real
                r["nominal_contact_area_mm2"] = total_nom
                r["real_contact_fraction"] = total_real / total_nom if total_nom > 0 else nan

    def _render_patchy(
        self,
        frame: ElementFrame,
        contacts: list[Any],
        u_front: float,
        base: np.ndarray,
        blur_mm: float,
    ) -> tuple[np.ndarray, np.ndarray]:
        """TIR signal with patchy real contact and each element's real area in the lit zone."""
        path = self.path
        px = path.mm_per_px
        w = base.shape[1]
        n = frame.n_elements
        nodes, p_mid, elem = pressure_cells(frame, contacts)
        blur_px = blur_mm / px
        empty = np.zeros((0, 0))
        if p_mid.size == 0:
            return self._apply_darkness(base, empty, (0, 0), (0, 0), blur_px=0.0), np.zeros(n)
        if path.rotation_rad == 0.0:
            ends = np.sort(path.u_of_xi(nodes[[0, -1]], u_front))
            pad = math.ceil(blur_px) + 1
            c0 = max(math.floor(ends[0] / px) - pad, 0)
            c1 = min(math.ceil(ends[1] / px) + pad, w)
        else:
            c0, c1 = 0, w
        lat_rows = np.nonzero(self.lateral.max(axis=1) > 0)[0]
        if c0 >= c1 or lat_rows.size == 0:
            return self._apply_darkness(base, empty, (0, 0), (0, 0), blur_px=0.0), np.zeros(n)
        rows_px, cols_px = (int(lat_rows[0]), int(lat_rows[-1]) + 1), (c0, c1)
        x, y = sample_points(rows_px, cols_px, px)
        half_w = 0.5 * path.block_width_mm
        if path.rotation_rad == 0.0:
            # Separable: xi depends on x only, v on y only (u = x, v = y - yc).
            xi = (x[0] - u_front) * path.direction
            v = y[:, 0] - path.centre[1]
            p1, e1 = _cells_at(nodes, p_mid, elem, xi)
            e = np.where(np.abs(v - path.lateral_mm)[:, None] <= half_w, e1[None, :], -1)
            phi = real_fraction(p1)
            covered = (e >= 0) & (self.patches.grid(xi, v) < phi[None, :])
            dark = np.where(covered, self.contact.darkness(p1)[None, :], 0.0)
        else:
            u, v = path.to_path(x, y)
            u, v = np.broadcast_arrays(u, v)
            xi = (u - u_front) * path.direction
            p, e = _cells_at(nodes, p_mid, elem, xi)
            e = np.where(np.abs(v - path.lateral_mm) <= half_w, e, -1)
            covered = (e >= 0) & (self.patches(xi, v) < real_fraction(p))
            dark = np.where(covered, self.contact.darkness(p), 0.0)
        sig = self._apply_darkness(base, dark, rows_px, cols_px, blur_px=blur_px)
        lit = self._lit_samples(rows_px, cols_px)
        real = np.bincount(e[covered & lit], minlength=n)[:n] * (px / SUPERSAMPLE) ** 2
        return sig, real

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

    def image(self, k: int) -> tuple[np.ndarray, pd.DataFrame, bytes | None]:
        """Frame k: the image, its ground truth and its JPEG bytes (None without JPEG)."""
        sig, table = self.signal(k)
        if self.stray is not None:
            sig = sig + self.stray
        img = self.sensor(sig, self.noise_rng(k))
        quality = self.spec.camera.jpeg_quality
        if quality is None:
            return img, table, None
        ok, buf = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
        if not ok:
            raise RuntimeError(f"OpenCV could not JPEG-encode frame {k}")
        return cv2.imdecode(buf, cv2.IMREAD_GRAYSCALE), table, buf.tobytes()


def _cells_at(
    nodes: np.ndarray, p_mid: np.ndarray, elem: np.ndarray, xi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Pressure (Pa, 0 outside) and element (-1 outside) of the cells at the points ``xi``."""
    k = np.searchsorted(nodes, xi, side="right") - 1
    inside = (k >= 0) & (k < p_mid.size)
    kk = np.clip(k, 0, p_mid.size - 1)
    p = np.where(inside, p_mid[kk], 0.0)
    return p, np.where(inside & (p > 0), elem[kk], -1)


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
        Ground-truth rows of this frame, columns ``spec.truth_columns``
        (:data:`TRUTH_COLUMNS`, plus :data:`REAL_TRUTH_COLUMNS` when a real-footage field is
        set): the block total (element -1) first, then every element (0 leads) with any
        part in view (static scenes: every contact touching the image).

    Notes
    -----
    The rigid block model is integrated (or fetched from a cache of recent specs) before the
    first frame. Memory does not grow with the clip length.
    """
    if not isinstance(spec, FootageSpec):
        raise TypeError(f"spec must be a FootageSpec, got {type(spec).__name__}")
    for k, img, table, _ in _iter_encoded(_Clip(spec)):
        yield k, img, table


def _iter_encoded(
    clip: _Clip, keep_covered: set[int] | frozenset[int] = frozenset()
) -> Iterator[tuple[int, np.ndarray, pd.DataFrame, bytes | None]]:
    for k in range(clip.spec.n_frames):
        clip.keep_covered = k in keep_covered
        clip.last_covered = None
        img, table, encoded = clip.image(k)
        yield k, img, table, encoded


def render_footage(
    spec: FootageSpec,
    out_dir: str | Path,
    *,
    fmt: str | None = None,
    progress: bool | None = None,
) -> Path:
    """Render a clip to ``out_dir``: frames, ``ground_truth.csv`` and ``meta.json``.

    Parameters
    ----------
    spec : FootageSpec
    out_dir : str or Path
        Output folder (created). Earlier frames of this writer's own naming are replaced.
    fmt : {"png", "jpg", "tiff", "avi", "multitiff"}, optional
        Default ``"jpg"`` when ``camera.jpeg_quality`` is set, else ``"png"``. ``"jpg"``:
        ``frames/frame_000000.jpg`` ... holding the very JPEG bytes whose decoding
        :func:`iter_frames` yields (needs ``jpeg_quality``); with the other formats a JPEG
        clip's decoded frames are stored losslessly.
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

    Notes
    -----
    A spec that uses a real-footage field (``FootageSpec.uses_real_footage_fields``) also
    gets ``lit_mask.png`` (TIR view; uint8, 255 inside the lit mask of :func:`lit_mask`,
    0 outside) and the ground-truth columns :data:`REAL_TRUTH_COLUMNS`.

    Raises
    ------
    ValueError
        For an unknown ``fmt``, ``fmt="avi"`` with a bit depth other than 8, or
        ``fmt="jpg"`` without ``camera.jpeg_quality``.
    """
    if not isinstance(spec, FootageSpec):
        raise TypeError(f"spec must be a FootageSpec, got {type(spec).__name__}")
    if fmt is None:
        fmt = "png" if spec.camera.jpeg_quality is None else "jpg"
    _choice("fmt", fmt, ("png", "jpg", "tiff", "avi", "multitiff"))
    if fmt == "jpg" and spec.camera.jpeg_quality is None:
        raise ValueError(
            "camera.jpeg_quality must be set (1-100) for fmt='jpg', got jpeg_quality=None"
        )
    if fmt == "avi" and spec.camera.bit_depth != 8:
        raise ValueError(
            "bit_depth must be 8 for fmt='avi' (OpenCV writes 8-bit video), got "
            f"bit_depth={spec.camera.bit_depth}"
        )
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    sink: FrameSink = open_sink(out, fmt, spec)
    bar = progress_bar(spec.n_frames, progress=progress, unit="frame", desc="footage", leave=False)
    truth_path = out / "ground_truth.csv"
    columns = spec.truth_columns
    clip = _Clip(spec)
    # the block's physical contact: the covered-fraction image of a quarter, the middle and
    # three quarters of the clip
    covered_frames = (
        {spec.n_frames // 4, spec.n_frames // 2, (3 * spec.n_frames) // 4}
        if clip.phys_block is not None
        else set()
    )
    try:
        with open(truth_path, "w", newline="", encoding="utf-8") as fh:
            fh.write(",".join(columns) + "\n")
            for k, img, table, encoded in _iter_encoded(clip, covered_frames):
                sink.write(k, img, encoded=encoded)
                if k in covered_frames:
                    cov = clip.last_covered
                    if cov is None:
                        cov = np.zeros((spec.camera.height_px, spec.camera.width_px), np.float32)
                    (out / "covered_fraction").mkdir(exist_ok=True)
                    _write_atomic_tiff(out / "covered_fraction" / f"frame_{k:06d}.tif", cov)
                _write_rows(fh, table, columns)
                bar.update(1)
    finally:
        bar.close()
        sink.close()
    extra: dict[str, Any] = {}
    if clip.physical is not None:
        # the share of each pixel in true contact (gap 0), the same in every frame
        _write_atomic_tiff(out / "covered_fraction.tif", clip.physical.covered)
    if spec.uses_real_footage_fields:
        extra = (
            _write_lit_mask(out, spec, clip.lit)
            if spec.view == "tir"
            else {"jpeg_quality": spec.camera.jpeg_quality}
        )
    write_meta(out, spec, sink, truth_columns=columns, extra=extra)
    logger.info("wrote %d frames to %s (%s)", spec.n_frames, out, fmt)
    return out


def _physical_meta(spec: FootageSpec) -> dict[str, Any]:
    """The ``meta.json`` entry ``physical_contact`` of a physical spec."""
    rough, optics = ROUGHNESS_PRESETS[spec.roughness], spec.optics
    entry: dict[str, Any] = {"scene": spec.scene}
    if spec.is_static:
        setup = physical_setup(spec)
        entry.update(centre_mm=list(setup.centre_mm), nominal_radius_mm=setup.nominal_radius_mm)
    entry.update(
        roughness=dataclasses.asdict(rough) | {"rms_height_m": rough.rms_height_m},
        optics=dataclasses.asdict(optics) | {"evanescent_depth_m": optics.evanescent_depth_m},
        e_star_Pa=e_star_Pa(),
        solver="tamaas PolonskyKeerRey",
    )
    if spec.is_static:
        entry["covered_fraction_file"] = "covered_fraction.tif"
    else:
        entry["covered_fraction_dir"] = "covered_fraction"
    return entry


def _write_atomic_tiff(path: Path, image: np.ndarray) -> None:
    data = np.asarray(image, dtype=np.float32)
    atomic_write(path, lambda tmp: tifffile.imwrite(tmp, data))


def _fmt(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    f = float(v)
    if math.isnan(f):
        return ""
    return f"{f:.9g}"


def _write_lit_mask(out: Path, spec: FootageSpec, zone: LitZone) -> dict[str, Any]:
    """Write ``lit_mask.png`` of the clip's lit `zone`; return the ``meta.json`` entries of
    the real-footage fields."""
    path = out / "lit_mask.png"
    if not cv2.imwrite(str(path), zone.mask.astype(np.uint8) * 255):
        raise OSError(f"could not write {path}")
    cam = spec.camera
    entries: dict[str, Any] = {
        "lit_zone": {
            "shape": cam.lit_shape,
            "fraction": zone.fraction,
            "size_mm": None if math.isinf(zone.size_mm) else zone.size_mm,
            "rim_mm": cam.lit_rim_mm,
            "center_mm": list(cam.lit_center_mm),
            "outside_level": cam.outside_level,
            "mask_file": "lit_mask.png",
        },
        "scene": spec.scene,
        "real_contact": spec.real_contact,
        "jpeg_quality": cam.jpeg_quality,
    }
    if spec.is_physical:
        entries["physical_contact"] = _physical_meta(spec)
        # what a rig's user knows of its optics (tir_contact.optics): not the rubber's
        # index, which the analysis then takes at its default
        entries["optics"] = {"substrate": spec.optics.substrate,
                             "incidence_deg": spec.optics.incidence_deg}
    elif spec.is_static:
        sc = static_scene(spec)
        entries["static_contact"] = {
            "centres_mm": [list(c) for c in sc.centres_mm],
            "radius_mm": sc.radius_mm,
            "inner_radius_mm": sc.inner_radius_mm,
            "nominal_area_mm2": sc.element_area_mm2 * len(sc.centres_mm),
        }
    return entries


def _write_rows(fh: Any, table: pd.DataFrame, columns: tuple[str, ...] = TRUTH_COLUMNS) -> None:
    cols = [table[c].to_numpy() for c in columns]
    fh.write("".join(",".join(_fmt(c[i]) for c in cols) + "\n" for i in range(len(table))))
