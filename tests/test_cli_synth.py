"""Tests of the ``tir-contact synth`` sub-command (through tir_contact.cli)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import pandas as pd
import pytest

from friction_model.contact.effects import EFFECT_NAMES
from friction_model.rig import read_run
from synthetic.measurements import STEADY_COLUMNS, TRANSIENT_COLUMNS
from tir_contact import cli
from tir_contact.commands import synth

# the renderer's contract (synthetic.footage), field names the CLI must produce
CAMERA_FIELDS = {
    "fps",
    "exposure_s",
    "mm_per_px",
    "width_px",
    "height_px",
    "bit_depth",
    "gain",
    "read_noise_dn",
    "shot_noise",
    "rotation_deg",
}
SPEC_FIELDS = {
    "preset",
    "view",
    "velocity_mps",
    "n_frames",
    "pressure_bar",
    "temperature_C",
    "humidity_pct",
    "salinity_pct",
    "sliding_direction",
    "contact_is",
    "seed",
}
# small, fast versions of each kind
SMALL = {
    "steady": ["--velocities", "1,3", "--pressures", "2.5", "--temperatures=-5,-1"],
    "transient": ["--sample-rate", "2000"],
    "raw": ["--velocities", "1", "--sipes", "3", "--repeats", "2", "--sample-rate", "1000"],
}


def parser() -> argparse.ArgumentParser:
    return cli.build_parser(("synth",))


@pytest.fixture
def measurements(run_cli):
    """``measurements(kind, out, *extra)``: ``tir-contact synth measurements`` of a small
    table of `kind` into `out`; returns the exit code."""

    def run(kind: str, out: Path, *extra: str) -> int:
        return run_cli(["synth", "measurements", "--kind", kind, "--out", out, *SMALL[kind],
                        *extra])

    return run


def out_path(tmp_path: Path, kind: str, name: str = "out") -> Path:
    return tmp_path / (name if kind == "raw" else f"{name}.csv")


# -- measurements ----------------------------------------------------------------------------
def test_steady_end_to_end(measurements, tmp_path, capsys):
    out = out_path(tmp_path, "steady")
    assert measurements("steady", out, "--effect", "viscous_shear", "--seed", "3") == 0
    table = pd.read_csv(out)
    assert list(table.columns) == list(STEADY_COLUMNS)
    assert len(table) == 2 * 1 * 2 * 2 * 2 * 2  # v, p, T, rH, K, sipes
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("steady: wrote 32 rows")
    assert "viscous_shear" not in lines[0]  # not announced without --reveal


def test_transient_end_to_end(measurements, tmp_path, capsys):
    out = out_path(tmp_path, "transient")
    rc = measurements(
        "transient", out, "--effect", "friction_relaxation=1.5", "--velocities", "2,4"
    )
    assert rc == 0
    table = pd.read_csv(out)
    assert list(table.columns) == list(TRANSIENT_COLUMNS)
    assert table["velocity_mps"].iloc[0] == 2.0 and table["velocity_mps"].iloc[-1] == 4.0
    # default duration after the 0.2 s step: max(0.2 s, 10 tau) = 0.3 s at 2000 Hz
    assert len(table) == 1001
    assert capsys.readouterr().out.startswith("transient: wrote 1001 rows")


def test_raw_end_to_end(measurements, tmp_path, capsys):
    out = out_path(tmp_path, "raw")
    rc = measurements("raw", out, "--profile", "instationary", "--no-sensor-noise")
    assert rc == 0
    files = sorted(out.glob("*.csv"))
    assert [f.name for f in files] == ["run_001.csv", "run_002.csv"]
    run = read_run(files[0])
    assert run.metadata["kind"] == "instationary" and run.metadata["specimen"] == "G3"
    assert capsys.readouterr().out.startswith("raw: wrote 2 runs")


def test_registered_in_the_top_level_cli(run_cli, tmp_path, capsys):
    out = tmp_path / "t.csv"
    assert run_cli(["synth", "measurements", "--kind", "transient", "--out", out]) == 0
    assert out.exists()


@pytest.mark.parametrize("kind", ["steady", "transient", "raw"])
def test_same_seed_same_bytes(measurements, tree_bytes, kind, tmp_path):
    effect = ["--effect", "humidity_water_layer", "--effect", "frequency_dependent_modulus"]
    outs = [out_path(tmp_path, kind, name) for name in ("a", "b", "c")]
    for out, seed in zip(outs, ("5", "5", "6"), strict=True):
        assert measurements(kind, out, *effect, "--seed", seed) == 0
    a, b, c = (tree_bytes(o) for o in outs)
    assert list(a.values()) == list(b.values())
    assert all(x != y for x, y in zip(a.values(), c.values(), strict=True))


@pytest.mark.parametrize("kind", ["steady", "transient", "raw"])
def test_reveal_writes_the_truth_and_only_then(measurements, tree_bytes, kind, tmp_path, capsys):
    effects = ["--effect", "ice_preheating=0.5", "--effect", "friction_relaxation"]
    hidden = out_path(tmp_path, kind, "hidden")
    assert measurements(kind, hidden, *effects) == 0
    for content in tree_bytes(hidden).values():
        assert not any(name.encode() in content for name in EFFECT_NAMES)
    assert not list(tmp_path.glob("*.truth.json"))
    shown = out_path(tmp_path, kind, "shown")
    assert measurements(kind, shown, *effects, "--reveal", "--noise", "0.02") == 0
    truth = json.loads(Path(f"{shown}.truth.json").read_text())
    assert truth["effects"]["ice_preheating"] == 0.5
    assert truth["effects"]["friction_relaxation"] == 1.0
    assert truth["effects"]["viscous_shear"] == 0.0
    assert (truth["seed"], truth["noise"]) == (1, 0.02)
    assert "truth in" in capsys.readouterr().out.strip().splitlines()[-1]


def test_strength_option_applies_to_all_or_pairwise():
    f = synth.measurement_effects
    assert f([("viscous_shear", None)], []) == {"viscous_shear": 1.0}
    assert f([("viscous_shear", None), ("ice_preheating", None)], [0.3]) == {
        "viscous_shear": 0.3,
        "ice_preheating": 0.3,
    }
    assert f([("viscous_shear", None), ("ice_preheating", None)], [2.0, 0.3]) == {
        "viscous_shear": 2.0,
        "ice_preheating": 0.3,
    }


# -- bad arguments ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--kind", "video", "--out", "x"], "--kind"),
        (["--kind", "steady", "--out", "x", "--effect", "bogus"], "--effect"),
        (["--kind", "steady", "--out", "x", "--noise", "-1"], "--noise"),
        (["--kind", "steady", "--out", "x", "--velocities", "1,a"], "--velocities"),
        (["--kind", "steady"], "--out"),
    ],
)
def test_argparse_errors_exit_2_naming_the_option(run_cli, argv, message, capsys):
    assert run_cli(["synth", "measurements", *argv]) == 2
    assert message in capsys.readouterr().err


def test_unknown_effect_message_lists_the_valid_ones(run_cli, capsys):
    argv = ["synth", "measurements", "--kind", "raw", "--out", "x", "--effect", "bogus"]
    assert run_cli(argv) == 2
    err = capsys.readouterr().err
    assert all(name in err for name in EFFECT_NAMES)


@pytest.mark.parametrize(
    ("kind", "extra", "message"),
    [
        ("transient", ["--pressures", "1,2"], "--pressures"),
        ("transient", ["--velocities", "1,2,3"], "--velocities"),
        ("raw", ["--temperatures=-5,-4"], "--temperatures"),
        (
            "steady",
            ["--effect", "viscous_shear", "--strength", "1", "--strength", "2", "--strength", "3"],
            "--strength",
        ),
        ("steady", ["--effect", "viscous_shear", "--effect", "viscous_shear"], "--effect"),
        ("steady", ["--t-step", "0.1"], "--t-step"),
        ("steady", ["--repeats", "1"], "--repeats"),
    ],
)
def test_inconsistent_options_return_2_naming_the_option(
    run_cli, kind, extra, message, tmp_path, capsys
):
    out = out_path(tmp_path, kind)
    assert run_cli(["synth", "measurements", "--kind", kind, "--out", out, *extra]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_a_condition_the_model_refuses_returns_1(run_cli, tmp_path, capsys):
    out = tmp_path / "s.csv"
    rc = run_cli(
        ["synth", "measurements", "--kind", "steady", "--out", str(out), "--temperatures", "5"]
    )
    assert rc == 1
    assert "temperature_C" in capsys.readouterr().err


# -- footage ---------------------------------------------------------------------------------
FOOTAGE_ARGS = [
    "synth", "footage", "--preset", "G5", "--view", "tir", "--velocity", "2.5", "--frames",
    "40", "--seed", "9", "--out", "frames", "--fps", "5000", "--exposure", "1e-4",
    "--mm-per-px", "0.05", "--width", "320", "--height", "200", "--bit-depth", "12", "--gain",
    "0.8", "--read-noise", "3", "--rotation", "1.5", "--pressure", "2.5", "--temperature",
    "-4", "--humidity", "70", "--salinity", "0.05", "--sliding-direction", "right",
    "--contact-is", "bright", "--format", "tiff",
]  # fmt: skip


def test_footage_options_map_onto_the_renderer_fields():
    args = parser().parse_args(FOOTAGE_ARGS)
    camera, spec = synth.footage_kwargs(args)
    assert set(camera) == CAMERA_FIELDS - {"shot_noise"}
    assert set(spec) == SPEC_FIELDS
    assert camera == {
        "fps": 5000.0,
        "exposure_s": 1e-4,
        "mm_per_px": 0.05,
        "width_px": 320,
        "height_px": 200,
        "bit_depth": 12,
        "gain": 0.8,
        "read_noise_dn": 3.0,
        "rotation_deg": 1.5,
    }
    assert spec == {
        "preset": "G5",
        "view": "tir",
        "velocity_mps": 2.5,
        "n_frames": 40,
        "pressure_bar": 2.5,
        "temperature_C": -4.0,
        "humidity_pct": 70.0,
        "salinity_pct": 0.05,
        "sliding_direction": "right",
        "contact_is": "bright",
        "seed": 9,
    }
    assert args.format == "tiff"


def test_footage_defaults_leave_the_renderer_defaults():
    args = parser().parse_args(["synth", "footage", "--out", "d", "--no-noise"])
    camera, spec = synth.footage_kwargs(args)
    assert camera == {"shot_noise": False, "read_noise_dn": 0.0}
    assert spec == {
        "preset": "G3",
        "view": "tir",
        "velocity_mps": 1.0,
        "n_frames": 400,
        "seed": 1,
    }


def test_footage_fields_exist_in_the_renderer():
    footage = pytest.importorskip("synthetic.footage")
    from dataclasses import fields

    assert CAMERA_FIELDS <= {f.name for f in fields(footage.CameraSettings)}
    assert SPEC_FIELDS | {"camera"} <= {f.name for f in fields(footage.FootageSpec)}


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--no-noise", "--read-noise", "2"], "--read-noise"),
        (["--format", "gif"], "--format"),
        (["--frames", "0"], "--frames"),
    ],
)
def test_footage_bad_arguments_exit_2(extra, message, capsys):
    with pytest.raises(SystemExit) as exc:
        parser().parse_args(["synth", "footage", "--out", "d", *extra])
    assert exc.value.code == 2
    assert message in capsys.readouterr().err


def test_footage_run_builds_the_spec_and_renders(run_cli, monkeypatch, tmp_path, capsys):
    """The renderer's own spec classes, with a stand-in ``render_footage`` of the agreed
    signature that records its call (the real one is tested elsewhere)."""
    calls = []

    def render_footage(spec, out_dir, *, fmt="png", progress=None):
        calls.append((spec, out_dir, fmt))
        return Path(out_dir)

    monkeypatch.setattr("synthetic.footage.render_footage", render_footage)
    argv = ["synth", "footage", "--out", str(tmp_path / "f"), "--fps", "2000", "--no-noise"]
    assert run_cli(argv) == 0
    ((spec, out_dir, fmt),) = calls
    assert (spec.preset, spec.view, spec.n_frames, fmt) == ("G3", "tir", 400, "png")
    assert (spec.camera.fps, spec.camera.shot_noise, spec.camera.read_noise_dn) == (
        2000.0,
        False,
        0.0,
    )
    assert out_dir == tmp_path / "f"
    assert capsys.readouterr().out.startswith("footage: rendered 400 frames")


@pytest.mark.parametrize(("extra", "fmt", "quality"), [
    (["--format", "jpg"], "jpg", 90),  # before: exit 1, "camera.jpeg_quality must be set"
    (["--jpeg-quality", "70"], "jpg", 70),
    (["--format", "jpg", "--jpeg-quality", "70"], "jpg", 70),
    (["--format", "multitiff"], "multitiff", None),
    ([], "png", None),
])
def test_footage_format_and_jpeg_quality(run_cli, monkeypatch, tmp_path, extra, fmt, quality):
    calls = []
    monkeypatch.setattr("synthetic.footage.render_footage",
                        lambda spec, out, *, fmt="png", progress=None:
                        calls.append((spec, fmt)) or Path(out))
    assert run_cli(["synth", "footage", "--out", str(tmp_path / "f"), *extra]) == 0
    ((spec, got),) = calls
    assert (got, spec.camera.jpeg_quality) == (fmt, quality)


def test_footage_jpeg_quality_with_another_format_is_a_usage_error(run_cli, tmp_path, capsys):
    # before: rendered as JPEG frames, the --format multitiff dropped without a word
    argv = ["synth", "footage", "--out", str(tmp_path / "f"), "--format", "multitiff",
            "--jpeg-quality", "80"]
    assert run_cli(argv) == 2
    err = capsys.readouterr().err
    assert "--jpeg-quality 80" in err and "--format multitiff" in err
    assert not (tmp_path / "f").exists()


@pytest.mark.parametrize(("extra", "named"), [
    (["--sphere-radius", "3", "--roughness", "rough_ice"], "--sphere-radius, --roughness"),
    (["--pad-radius", "3"], "--pad-radius"),
    (["--scene", "round_pad", "--substrate", "glass"], "--substrate"),
    (["--view", "side", "--gap-medium", "water"], "--gap-medium"),
    (["--scene", "rough_sphere", "--pad-radius", "3"], "--pad-radius"),
])
def test_footage_scene_options_the_scene_does_not_use_are_usage_errors(
        run_cli, monkeypatch, tmp_path, extra, named, capsys):
    # before: accepted, the frames byte-identical to the default render, and meta.json
    # recording them as if they had shaped it
    calls = []
    monkeypatch.setattr("synthetic.footage.render_footage",
                        lambda spec, out, **kw: calls.append(spec) or Path(out))
    assert run_cli(["synth", "footage", "--out", str(tmp_path / "f"), *extra]) == 2
    assert f"{named} not used by --scene" in capsys.readouterr().err and not calls


@pytest.mark.parametrize("extra", [
    ["--scene", "rough_sphere", "--sphere-radius", "3", "--roughness", "rough_ice"],
    ["--scene", "round_pad", "--pad-radius", "3"],
    ["--real-contact", "physical", "--substrate", "glass", "--gap-medium", "air"],
])
def test_footage_scene_options_the_scene_uses_pass(run_cli, monkeypatch, tmp_path, extra):
    calls = []
    monkeypatch.setattr("synthetic.footage.render_footage",
                        lambda spec, out, **kw: calls.append(spec) or Path(out))
    assert run_cli(["synth", "footage", "--out", str(tmp_path / "f"), *extra]) == 0
    assert len(calls) == 1


def test_footage_without_renderer_fails_with_a_message(run_cli, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "synthetic.footage", None)  # import raises ImportError
    assert run_cli(["synth", "footage", "--out", "d"]) == 1
    assert "synthetic.footage" in capsys.readouterr().err


# -- footage with the look of real footage ---------------------------------------------------
def test_footage_real_look_options_reach_the_renderer(run_cli, tree_bytes, tmp_path, capsys):
    """The real-footage options render what the library renders for the same spec."""
    from synthetic.footage import CameraSettings, FootageSpec, lit_mask, render_footage

    out = tmp_path / "cli"
    argv = ["synth", "footage", "--out", str(out), "--frames", "2", "--scene", "round_pad",
            "--lit-shape", "disc", "--lit-fraction", "0.3", "--white-level", "0.4",
            "--jpeg-quality", "85", "--real-contact", "patchy", "--width", "160",
            "--height", "128", "--mm-per-px", "0.05"]
    assert run_cli(argv) == 0
    assert "(jpg)" in capsys.readouterr().out
    spec = FootageSpec(
        scene="round_pad", real_contact="patchy", n_frames=2, seed=1,
        camera=CameraSettings(lit_shape="disc", lit_fraction=0.3, white_level=0.4,
                              jpeg_quality=85, width_px=160, height_px=128, mm_per_px=0.05))
    ref = render_footage(spec, tmp_path / "lib", fmt="jpg", progress=False)
    assert tree_bytes(out / "frames") == tree_bytes(ref / "frames")
    assert (out / "lit_mask.png").is_file()
    assert lit_mask(spec).mean() == pytest.approx(0.3, abs=0.01)  # the requested share


def test_help_states_the_noise_default_the_generator_uses():
    from synthetic.measurements import DEFAULT_NOISE

    assert synth.HELP_DEFAULT_NOISE == DEFAULT_NOISE


def test_footage_sliding_direction_is_left_or_right(capsys):
    # before: the parser took any text and the renderer refused it later (exit 1, not 2)
    with pytest.raises(SystemExit) as exc:
        parser().parse_args(["synth", "footage", "--out", "d", "--sliding-direction", "+x"])
    assert exc.value.code == 2 and "--sliding-direction" in capsys.readouterr().err
