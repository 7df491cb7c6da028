"""``tir-contact synth``: synthetic TIR footage and synthetic test-rig measurements.

Usage::

    tir-contact synth footage --preset G3 --view tir --velocity 1 --frames 400 --seed 1 \\
        --out DIR [--fps F] [--exposure S] [--mm-per-px X] [--width W] [--height H]
        [--bit-depth B] [--gain G] [--read-noise DN | --no-noise] [--rotation DEG]
        [--pressure BAR] [--temperature C] [--humidity PCT] [--salinity PCT]
        [--sliding-direction D] [--contact-is C] [--format png|tiff|avi|multitiff]

    tir-contact synth measurements --kind steady|transient|raw --out PATH
        [--effect NAME[=X]]... [--strength X]... [--noise SIGMA] [--seed N] [--reveal]
        [--velocities 1,3,5] [--pressures 2.5] [--temperatures=-8,-4,-1] [--humidities 40,90]
        [--salinities 0,0.05] [--sipes 0,3] [--repeats N] [--sample-rate HZ]
        [--t-step S] [--duration S] [--profile steady|instationary] [--no-sensor-noise]

``footage`` renders with :mod:`synthetic.footage`; camera and condition options left out take
the renderer's defaults. ``measurements`` writes a steady or transient table (PATH is a CSV
file) or raw runs (PATH is a folder, filled with ``run_001.csv``, ...); the data carry no hint
of the effects; ``--reveal`` also writes ``PATH.truth.json``. Write negative list values with
``=``: ``--temperatures=-8,-4``. Prints one summary line. Exit codes: 0 success, 1 when
generation fails (message on stderr), 2 for bad arguments.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import cv2

from tir_contact.commands._types import UsageError, output_folder, output_path
from tir_contact.commands._types import finite_number as _number
from tir_contact.commands._types import non_negative_number as _non_negative
from tir_contact.commands._types import positive_int as _positive_int
from tir_contact.commands._types import positive_number as _positive

__all__ = ["DESCRIPTION", "add_arguments", "footage_kwargs", "measurement_effects", "run"]

DESCRIPTION = (
    "Make synthetic data with exact ground truth: TIR contact footage of a sliding "
    "tread block, or test-rig measurements with switchable physical effects."
)

_KINDS = ("steady", "transient", "raw")
_FORMATS = ("png", "jpg", "tiff", "avi", "multitiff")
#: The default of ``--noise`` as its help states it (:data:`synthetic.measurements.
#: DEFAULT_NOISE`, not imported for ``--help``; a test holds the two equal).
HELP_DEFAULT_NOISE = 0.05
#: JPEG quality of ``--format jpg`` without ``--jpeg-quality``: compressed visibly but not
#: coarsely (OpenCV's own default is 95, Pillow's 75).
DEFAULT_JPEG_QUALITY = 90
# CLI option dest -> CameraSettings field of synthetic.footage
_CAMERA_FIELDS = {
    "fps": "fps",
    "exposure": "exposure_s",
    "mm_per_px": "mm_per_px",
    "width": "width_px",
    "height": "height_px",
    "bit_depth": "bit_depth",
    "gain": "gain",
    "read_noise": "read_noise_dn",
    "rotation": "rotation_deg",
    "white_level": "white_level",
    "vignetting": "vignetting",
    "lit_shape": "lit_shape",
    "lit_fraction": "lit_fraction",
    "lit_rim": "lit_rim_mm",
    "jpeg_quality": "jpeg_quality",
    "optical_blur": "optical_blur_mm",
    "fold_depth": "fold_depth",
    "fold_x": "fold_x_mm",
    "fold_width": "fold_width_mm",
    "fold_edge": "fold_edge_mm",
    "stray_light": "stray_light",
}
# CLI option dest -> FootageSpec field of synthetic.footage
_SPEC_FIELDS = {
    "preset": "preset",
    "view": "view",
    "velocity": "velocity_mps",
    "frames": "n_frames",
    "pressure": "pressure_bar",
    "temperature": "temperature_C",
    "humidity": "humidity_pct",
    "salinity": "salinity_pct",
    "sliding_direction": "sliding_direction",
    "contact_is": "contact_is",
    "seed": "seed",
    "scene": "scene",
    "real_contact": "real_contact",
    "follow_camera": "follow_camera",
    "roughness": "roughness",
    "pad_radius": "pad_radius_mm",
    "sphere_radius": "sphere_radius_mm",
    "substrate": "substrate",
    "gap_medium": "gap_medium",
    "texture": "texture",
}


# -- argument types --------------------------------------------------------------------------
def _number_list(text: str) -> tuple[float, ...]:
    parts = [p.strip() for p in text.split(",")]
    if not parts or any(not p for p in parts):
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}")
    return tuple(_number(p) for p in parts)


def _int_list(text: str) -> tuple[int, ...]:
    values = _number_list(text)
    if any(v != int(v) or v < 0 for v in values):
        raise argparse.ArgumentTypeError(f"expected integers >= 0, got {text!r}")
    return tuple(int(v) for v in values)


def _effect(text: str) -> tuple[str, float | None]:
    """argparse type of ``--effect NAME[=X]``: a name of the effect registry
    (:func:`friction_model.effect_registry.effect_names`, registered effects included; the
    model is imported only when one is given)."""
    from friction_model.effect_registry import effect_names

    name, sep, value = text.partition("=")
    name = name.strip()
    if name not in effect_names():
        raise argparse.ArgumentTypeError(
            f"unknown effect {name!r}; valid effects are {', '.join(effect_names())}"
        )
    return name, (_non_negative(value) if sep else None)


# -- parser ----------------------------------------------------------------------------------
def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``synth`` sub-commands ``footage`` and ``measurements`` with their options."""
    sub = parser.add_subparsers(dest="synth_command", metavar="WHAT")
    sub.required = True
    _add_footage(sub)
    _add_measurements(sub)


def _add_light_faults(p: Any) -> None:
    """The TIR light's faults: a darker fold across the lit zone and stray light."""
    light = p.add_argument_group("light faults (TIR view; default: none)")
    light.add_argument("--fold-depth", type=_non_negative, metavar="F",
                       help="share of the light lost in a darker fold along y, in [0, 1)")
    light.add_argument("--fold-x", type=_number, metavar="MM",
                       help="the fold's centre line from the image centre along x, mm")
    light.add_argument("--fold-width", type=_non_negative, metavar="MM",
                       help="width of the fold's flat core, mm (default 1)")
    light.add_argument("--fold-edge", type=_non_negative, metavar="MM",
                       help="width of each fold edge (the fall-off), mm (default 0.3)")
    light.add_argument("--stray-light", type=_non_negative, metavar="F",
                       help="stray light added to the reflected light, fraction of the white "
                       "level, in [0, 1): full contact no longer nearly black")


def _add_footage(sub: Any) -> None:
    p = sub.add_parser(
        "footage",
        help="render synthetic TIR footage of a sliding tread block",
        description=(
            "Render synthetic footage with synthetic.footage. Camera and condition options "
            "left out take the renderer's defaults."
        ),
    )
    p.add_argument("--preset", default="G3", help="tread-block preset, e.g. G0, G3 (default G3)")
    p.add_argument("--view", default="tir", choices=("tir", "side"),
                   help="camera view: tir (contact through the prism) or side (default tir)")
    p.add_argument(
        "--velocity", type=_positive, default=1.0, metavar="MPS", help="sliding velocity, m/s"
    )
    p.add_argument(
        "--frames", type=_positive_int, default=400, metavar="N", help="frames (default 400)"
    )
    p.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    p.add_argument("--out", type=output_folder, required=True, metavar="DIR",
                   help="output folder")
    p.add_argument("--format", choices=_FORMATS, default=None,
                   help="output format (default png; jpg with --jpeg-quality)")
    p.add_argument("--empty-frame", action="store_true",
                   help="also write OUT/empty.png, the rig's own empty frame of a static scene "
                   "(three_point, rough_pad, rough_sphere: the same light and ice without "
                   "the contact), for 'analyze --reference'")
    cam = p.add_argument_group("camera (default: the renderer's)")
    cam.add_argument("--fps", type=_positive, metavar="HZ", help="frame rate, 1/s")
    cam.add_argument("--exposure", type=_positive, metavar="S", help="exposure time, s")
    cam.add_argument("--mm-per-px", type=_positive, metavar="MM", help="scale, mm per pixel")
    cam.add_argument("--width", type=_positive_int, metavar="PX", help="image width, px")
    cam.add_argument("--height", type=_positive_int, metavar="PX", help="image height, px")
    cam.add_argument("--bit-depth", type=_positive_int, metavar="BITS", help="bits per pixel")
    cam.add_argument("--gain", type=_positive, metavar="G", help="camera gain (renderer's unit)")
    noise = cam.add_mutually_exclusive_group()
    noise.add_argument("--read-noise", type=_non_negative, metavar="DN", help="read noise std, DN")
    noise.add_argument("--no-noise", action="store_true", help="no shot noise and no read noise")
    cam.add_argument("--rotation", type=_number, metavar="DEG", help="image rotation, degrees")
    real = p.add_argument_group("real-footage look (default: a lit frame, strong clean signal)")
    real.add_argument("--white-level", type=_positive, metavar="F",
                      help="free-surface level, fraction of full scale (0.4: peak grey ~100)")
    real.add_argument("--vignetting", type=_non_negative, metavar="F",
                      help="light fall-off in the corners, fraction in [0, 1)")
    real.add_argument("--lit-shape", choices=("full", "disc", "ellipse", "band"),
                      help="shape of the zone TIR light reaches; dark outside")
    real.add_argument("--lit-fraction", type=_positive, metavar="F",
                      help="share of the frame lit, in [0.2, 1]")
    real.add_argument("--lit-rim", type=_non_negative, metavar="MM",
                      help="width of the lit zone's soft rim, mm")
    real.add_argument("--jpeg-quality", type=_positive_int, metavar="Q",
                      help="JPEG-compress the frames (8 bit; 1-100; default "
                           f"{DEFAULT_JPEG_QUALITY} with --format jpg)")
    real.add_argument("--scene",
                      choices=("block", "round_pad", "coin", "three_point", "rough_pad",
                               "rough_sphere"),
                      help="a sliding block (default) or a static contact; rough_pad and "
                      "rough_sphere: contact from a rough-contact solver and TIR optics "
                      "(needs the contact extra); a load series is a loop over --pressure")
    real.add_argument("--real-contact", choices=("solid", "patchy", "physical"),
                      help="patchy: micro-contact patches with the friction model's share; "
                      "physical: rough faces in the solved contact (contact extra)")
    real.add_argument("--follow-camera", action="store_const", const=True, default=None,
                      help="the camera moves with the block")
    real.add_argument("--pad-radius", type=_positive, metavar="MM",
                      help="round_pad / rough_pad radius, mm")
    real.add_argument("--texture", type=_non_negative, metavar="F",
                      help="rms light texture of the free surface, fraction (e.g. 0.1)")
    _add_physical(p)
    _add_light_faults(p)
    _add_conditions(p)


def _add_conditions(p: argparse.ArgumentParser) -> None:
    """Options of the test conditions and of how the block and contact look."""
    cond = p.add_argument_group("conditions (default: the renderer's)")
    cond.add_argument("--pressure", type=_positive, metavar="BAR", help="nominal pressure, bar")
    cond.add_argument("--temperature", type=_number, metavar="C", help="ice temperature, degC")
    cond.add_argument("--humidity", type=_non_negative, metavar="PCT", help="rel. humidity, %%")
    cond.add_argument("--salinity", type=_non_negative, metavar="PCT", help="salinity, %%")
    cond.add_argument(
        "--sliding-direction", choices=("left", "right"),
        help="direction the block slides in the image (default left)"
    )
    cond.add_argument("--contact-is", choices=("dark", "bright"),
                      help="how contact looks (default dark)")


def _add_physical(p: argparse.ArgumentParser) -> None:
    """Options of the physical scenes (contact mechanics and optics)."""
    phys = p.add_argument_group("physical contact (rough_pad, rough_sphere, --real-contact "
                                "physical)")
    phys.add_argument("--roughness", metavar="NAME",
                      help="rough surface: abraded_rubber (default), moulded_rubber, "
                      "sandblasted_elastomer, rough_ice")
    phys.add_argument("--sphere-radius", type=_positive, metavar="MM",
                      help="rough_sphere radius, mm (default 5)")
    phys.add_argument("--substrate", choices=("ice", "acrylic", "glass"),
                      help="what the rubber touches (default ice)")
    phys.add_argument("--gap-medium", choices=("air", "water"),
                      help="what fills the gap (default air)")
    phys.add_argument("--optical-blur", type=_non_negative, metavar="MM",
                      help="lens point-spread standard deviation, mm (default 0)")


def _add_measurements(sub: Any) -> None:
    p = sub.add_parser(
        "measurements",
        help="make synthetic test-rig measurements with switchable effects",
        description=(
            "Make a steady friction table, a velocity-step transient table or raw test-rig "
            "runs from the friction model with named effects switched on. The data carry no "
            "hint of the effects; --reveal writes the truth to OUT.truth.json. Negative list "
            "values need '=': --temperatures=-8,-4."
        ),
    )
    p.add_argument("--kind", required=True, choices=_KINDS, help="what to make")
    p.add_argument(
        "--out",
        type=output_path,
        required=True,
        metavar="PATH",
        help="CSV file (steady, transient) or folder of run_NNN.csv files (raw)",
    )
    p.add_argument(
        "--effect",
        action="append",
        type=_effect,
        default=[],
        metavar="NAME[=X]",
        help="switch an effect on (repeatable; none: the base model); =X sets its strength; "
        "a wrong name lists the valid ones",
    )
    p.add_argument(
        "--strength",
        action="append",
        type=_non_negative,
        default=[],
        metavar="X",
        help="strength for the effects (once: all; once per --effect: in order; default 1)",
    )
    p.add_argument(
        "--noise",
        type=_non_negative,
        default=None,
        metavar="SIGMA",
        help=f"relative noise, e.g. 0.05 = 5 %% (default {HELP_DEFAULT_NOISE:g})",
    )
    p.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    p.add_argument("--reveal", action="store_true", help="also write OUT.truth.json")
    grid = p.add_argument_group(
        "conditions (lists; transient: two velocities and one value of the others; raw: one "
        "value of pressure, temperature, humidity, salinity)"
    )
    grid.add_argument("--velocities", type=_number_list, metavar="V,...", help="m/s")
    grid.add_argument("--pressures", type=_number_list, metavar="P,...", help="bar")
    grid.add_argument("--temperatures", type=_number_list, metavar="T,...", help="degC")
    grid.add_argument("--humidities", type=_number_list, metavar="RH,...", help="%%")
    grid.add_argument("--salinities", type=_number_list, metavar="K,...", help="%%")
    grid.add_argument("--sipes", type=_int_list, metavar="N,...", help="sipes per block")
    opt = p.add_argument_group("kind-specific options")
    opt.add_argument(
        "--repeats", type=_positive_int, metavar="N", help="repeats (steady: 10, raw: 3)"
    )
    opt.add_argument("--sample-rate", type=_positive, metavar="HZ", help="transient, raw: 10000")
    opt.add_argument("--t-step", type=_positive, metavar="S", help="transient: step time, s")
    opt.add_argument(
        "--duration", type=_positive, metavar="S", help="transient: time after the step, s"
    )
    opt.add_argument(
        "--profile",
        choices=("steady", "instationary"),
        default="steady",
        help="raw: velocity profile (default steady)",
    )
    opt.add_argument(
        "--no-sensor-noise", action="store_true", help="raw: no force/velocity sensor noise"
    )


# -- footage ---------------------------------------------------------------------------------
def footage_kwargs(args: argparse.Namespace) -> tuple[dict[str, Any], dict[str, Any]]:
    """Keyword arguments of ``CameraSettings`` and ``FootageSpec`` from parsed options.

    Options left out are not passed (the renderer's defaults apply); ``--no-noise`` gives
    ``shot_noise=False`` and ``read_noise_dn=0``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed ``synth footage`` options.

    Returns
    -------
    camera : dict
        Keyword arguments of ``synthetic.footage.CameraSettings``.
    spec : dict
        Keyword arguments of ``synthetic.footage.FootageSpec`` without ``camera``.
    """
    camera = {
        field: getattr(args, dest)
        for dest, field in _CAMERA_FIELDS.items()
        if getattr(args, dest) is not None
    }
    if args.no_noise:
        camera["shot_noise"] = False
        camera["read_noise_dn"] = 0.0
    spec = {
        field: getattr(args, dest)
        for dest, field in _SPEC_FIELDS.items()
        if getattr(args, dest) is not None
    }
    return camera, spec


#: Scene options and where the renderer uses them: the scenes, and for the physical
#: contact's options a TIR view of a physical scene or of ``--real-contact physical``.
_SCENE_OPTIONS = {"pad_radius": ("round_pad", "rough_pad"), "sphere_radius": ("rough_sphere",)}
_PHYSICAL_OPTIONS = ("roughness", "substrate", "gap_medium")
_PHYSICAL_SCENES = ("rough_pad", "rough_sphere")


def _unused_scene_options(args: argparse.Namespace, spec: Any) -> list[str]:
    """The scene options given that the spec's scene does not use (they would be
    recorded in ``meta.json`` as if they had shaped the render)."""
    physical = spec.view == "tir" and (spec.scene in _PHYSICAL_SCENES
                                       or spec.real_contact == "physical")
    unused = [dest for dest, scenes in _SCENE_OPTIONS.items()
              if getattr(args, dest) is not None and spec.scene not in scenes]
    if not physical:
        unused += [dest for dest in _PHYSICAL_OPTIONS if getattr(args, dest) is not None]
    return ["--" + dest.replace("_", "-") for dest in unused]


def _footage_format(args: argparse.Namespace) -> str:
    """The file format of ``--format`` and ``--jpeg-quality`` together (a quality without
    a format is JPEG; JPEG without a quality takes :data:`DEFAULT_JPEG_QUALITY`); sets
    ``args.jpeg_quality`` for it. A quality with another format is a usage error."""
    if args.jpeg_quality is not None:
        if args.format not in (None, "jpg"):
            raise UsageError(f"--jpeg-quality {args.jpeg_quality}: JPEG frames, but --format "
                             f"{args.format} asks for another format; drop one of them")
        return "jpg"
    if args.format == "jpg":
        args.jpeg_quality = DEFAULT_JPEG_QUALITY
    return args.format or "png"


def _run_footage(args: argparse.Namespace) -> int:
    """Render the footage; a renderer that cannot be imported or rejects the options is
    raised (exit code 1)."""
    fmt = _footage_format(args)
    try:
        from synthetic.footage import CameraSettings, FootageSpec, render_footage
        from synthetic.table import EMPTY_REFERENCE_SCENES, empty_reference
    except ImportError as exc:
        raise ImportError(f"the renderer synthetic.footage is not available ({exc})") from exc
    camera, spec_kwargs = footage_kwargs(args)
    spec = FootageSpec(**spec_kwargs, camera=CameraSettings(**camera))
    unused = _unused_scene_options(args, spec)
    if unused:
        raise UsageError(f"{', '.join(unused)} not used by --scene {spec.scene} "
                         f"(--view {spec.view}, --real-contact {spec.real_contact})")
    if args.empty_frame and spec.scene not in EMPTY_REFERENCE_SCENES:
        raise UsageError(f"--empty-frame is rendered for the static scenes whose light does "
                         f"not depend on the contact ({', '.join(EMPTY_REFERENCE_SCENES)}), "
                         f"got --scene {spec.scene}")
    path = render_footage(spec, args.out, fmt=fmt)
    what = args.preset if spec.scene == "block" else f"the {spec.scene} scene"
    print(f"footage: rendered {spec.n_frames} frames ({fmt}) of {what} to {path}")
    if args.empty_frame:
        empty = Path(path) / "empty.png"
        # the same exposure and position as the footage, lossless (16-bit PNG above 8 bits)
        if not cv2.imwrite(str(empty), empty_reference(spec, exposure=1.0, shift_px=(0.0, 0.0))):
            raise OSError(f"{empty}: could not write the empty frame")
        print(f"empty frame: {empty} (tir-contact analyze {path} --reference {empty})")
    return 0


# -- measurements ----------------------------------------------------------------------------
def measurement_effects(
    effects: list[tuple[str, float | None]], strengths: list[float]
) -> dict[str, float]:
    """Effect name -> strength from the ``--effect`` and ``--strength`` options.

    ``--strength`` given once applies to every ``--effect`` without ``=X``; given as often
    as ``--effect``, pairwise in order; not given, strength 1.

    Raises
    ------
    ValueError
        For a repeated effect or a ``--strength`` count that fits neither rule.

    Examples
    --------
    >>> measurement_effects([("viscous_shear", None), ("friction_relaxation", 2.0)], [0.5])
    {'viscous_shear': 0.5, 'friction_relaxation': 2.0}
    """
    names = [name for name, _ in effects]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ValueError(f"--effect: {', '.join(repeated)} given more than once")
    if strengths and not effects:
        raise ValueError("--strength needs at least one --effect")
    if len(strengths) > 1 and len(strengths) != len(effects):
        raise ValueError(
            f"--strength: give it once (for every effect) or once per --effect "
            f"({len(effects)}), got {len(strengths)}"
        )
    out: dict[str, float] = {}
    for i, (name, value) in enumerate(effects):
        if value is not None:
            out[name] = value
        elif len(strengths) == 1:
            out[name] = strengths[0]
        elif strengths:
            out[name] = strengths[i]
        else:
            out[name] = 1.0
    return out


def _single(option: str, values: tuple | None, kind: str) -> Any:
    if values is None:
        return None
    if len(values) != 1:
        raise ValueError(f"{option}: --kind {kind} takes one value, got {len(values)}")
    return values[0]


def _options(args: argparse.Namespace) -> dict[str, Any]:
    """Keyword options of the maker of ``args.kind`` (only those given)."""
    kind = args.kind
    opts: dict[str, Any] = {}
    if kind == "steady":
        grid = {
            key: value
            for key, value in (
                ("velocities_mps", args.velocities),
                ("pressures_bar", args.pressures),
                ("temperatures_C", args.temperatures),
                ("humidities_pct", args.humidities),
                ("salinities_pct", args.salinities),
                ("n_sipes", args.sipes),
            )
            if value is not None
        }
        if grid:
            opts["grid"] = grid
        if args.repeats is not None:
            if args.repeats < 2:
                raise ValueError(f"--repeats: --kind steady needs >= 2, got {args.repeats}")
            opts["n_repeats"] = args.repeats
        return opts
    singles = {
        "pressure_bar": _single("--pressures", args.pressures, kind),
        "temperature_C": _single("--temperatures", args.temperatures, kind),
        "humidity_pct": _single("--humidities", args.humidities, kind),
        "salinity_pct": _single("--salinities", args.salinities, kind),
        "sample_rate_Hz": args.sample_rate,
    }
    opts.update({k: v for k, v in singles.items() if v is not None})
    if kind == "transient":
        if args.velocities is not None:
            if len(args.velocities) != 2:
                raise ValueError(
                    "--velocities: --kind transient takes two values (before and after the "
                    f"step), got {len(args.velocities)}"
                )
            opts["v1_mps"], opts["v2_mps"] = args.velocities
        sipes = _single("--sipes", args.sipes, kind)
        if sipes is not None:
            opts["n_sipes"] = sipes
        if args.t_step is not None:
            opts["t_step_s"] = args.t_step
        if args.duration is not None:
            opts["duration_s"] = args.duration
        return opts
    if args.velocities is not None:
        opts["velocities_mps"] = args.velocities
    if args.sipes is not None:
        opts["n_sipes"] = args.sipes
    if args.repeats is not None:
        opts["n_repeats"] = args.repeats
    opts["profile"] = args.profile
    if args.no_sensor_noise:
        opts["sensor_noise"] = False
    return opts


def _run_measurements(args: argparse.Namespace) -> int:
    """Write the measurements; options that do not fit the kind are a usage error."""
    from synthetic.measurements import DEFAULT_NOISE, write_measurements

    try:
        effects = measurement_effects(args.effect, args.strength)
        options = _options(args)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    ignored = [
        flag
        for flag, given, kinds in (
            ("--t-step", args.t_step is not None, ("transient",)),
            ("--duration", args.duration is not None, ("transient",)),
            ("--sample-rate", args.sample_rate is not None, ("transient", "raw")),
            ("--no-sensor-noise", args.no_sensor_noise, ("raw",)),
            ("--profile", args.profile != "steady", ("raw",)),
        )
        if given and args.kind not in kinds
    ]
    if ignored:
        raise UsageError(f"{', '.join(ignored)} not used by --kind {args.kind}")
    noise = DEFAULT_NOISE if args.noise is None else args.noise
    result = write_measurements(
        args.kind,
        args.out,
        effects=effects,
        noise=noise,
        seed=args.seed,
        reveal=args.reveal,
        **options,
    )
    unit = "run" if args.kind == "raw" else "row"
    what = f"{result.n_rows} {unit}{'' if result.n_rows == 1 else 's'}"
    line = f"{args.kind}: wrote {what} to {args.out} (seed {args.seed}, noise {noise:g})"
    if result.truth_file is not None:
        on = ", ".join(f"{k}={v:g}" for k, v in effects.items()) or "none (base model)"
        line += f"; effects {on}; truth in {result.truth_file}"
    print(line)
    return 0


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact synth footage`` or ``tir-contact synth measurements``.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments of the parser :func:`add_arguments` filled.

    Returns
    -------
    int
        0 on success (generation that fails, and arguments that do not fit together, are
        raised: :class:`UsageError` for the latter).
    """
    if args.synth_command == "footage":
        return _run_footage(args)
    return _run_measurements(args)
