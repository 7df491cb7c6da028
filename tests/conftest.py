"""Fixtures shared by the test files: the console command, small rendered clips and their
meta.json, a test-rig ramp run, file bytes."""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from os import PathLike
from pathlib import Path

import numpy as np
import pytest
from _footage import STEADY_SETTLE_S

from synthetic.footage import CameraSettings, FootageSpec, render_footage
from synthetic.rig import make_raw_run, write_run_csv
from tir_contact import cli

#: A small, fast camera (320 x 128 px at 0.2 mm/px) for clips that are analysed end to end.
SMALL_CAMERA = CameraSettings(mm_per_px=0.2, width_px=320, height_px=128)


@pytest.fixture(scope="session")
def run_cli() -> Callable[[Sequence[str | PathLike]], int]:
    """Run ``tir-contact ARGV`` through the real entry point :func:`tir_contact.cli.main`.

    The returned function takes the words of the command line (paths may be given as
    :class:`~pathlib.Path`) and returns the exit code; output goes to stdout/stderr as
    for a user (read it with ``capsys``).
    """

    def run(argv: Sequence[str | PathLike]) -> int:
        return cli.main([str(word) for word in argv])

    return run


@pytest.fixture(scope="session")
def render_clip() -> Callable[..., Path]:
    """Render a small synthetic clip with :func:`synthetic.footage.render_footage`.

    ``render_clip(folder, fmt="png", **spec_fields)`` writes the footage of a G3 block
    sliding steadily at 3 m/s, 160 frames, seen by :data:`SMALL_CAMERA`, into `folder`
    (any :class:`~synthetic.footage.FootageSpec` field given overrides these) and returns
    `folder`.
    """

    def render(folder: Path, fmt: str = "png", **spec_fields) -> Path:
        spec = FootageSpec(**{"preset": "G3", "velocity_mps": 3.0, "n_frames": 160,
                              "dynamics": "steady", "settle_s": STEADY_SETTLE_S,
                              "camera": SMALL_CAMERA, **spec_fields})
        render_footage(spec, folder, fmt=fmt, progress=False)
        return folder

    return render


@pytest.fixture(scope="session")
def copy_meta() -> Callable[..., Path]:
    """Copy a clip's ``meta.json`` into another footage folder, edited.

    ``copy_meta(clip, folder, drop=(), **changes)`` writes ``folder/meta.json``: the clip's
    metadata without the keys `drop`, with the keys `changes` set; returns its path.
    """

    def copy(clip: Path, folder: Path, drop: Sequence[str] = (), **changes) -> Path:
        meta = json.loads((Path(clip) / "meta.json").read_text())
        for key in drop:
            meta.pop(key, None)
        meta.update(changes)
        path = Path(folder) / "meta.json"
        path.write_text(json.dumps(meta))
        return path

    return copy


@pytest.fixture(scope="session")
def tree_bytes() -> Callable[[Path], dict[str, bytes]]:
    """The bytes of every file under a folder (keyed by relative POSIX path), or of one file
    (keyed by its name): ``tree_bytes(a) == tree_bytes(b)`` says two outputs are identical."""

    def read(path: Path) -> dict[str, bytes]:
        path = Path(path)
        if not path.is_dir():
            return {path.name: path.read_bytes()}
        return {p.relative_to(path).as_posix(): p.read_bytes()
                for p in sorted(path.rglob("*")) if p.is_file()}

    return read


@pytest.fixture(scope="session")
def ramp_law() -> Callable[[np.ndarray], np.ndarray]:
    """The friction law of :func:`write_ramp_run`: mu(v) = 0.12 + 0.25 exp(-v / 1.5 m/s)."""

    def law(v_mps):
        return 0.12 + 0.25 * np.exp(-np.asarray(v_mps) / 1.5)

    return law


@pytest.fixture(scope="session")
def write_ramp_run(ramp_law) -> Callable[..., Path]:
    """Write an instationary test-rig run (:func:`synthetic.rig.make_raw_run`) to a CSV file.

    ``write_ramp_run(path, **options)``: specimen G0 ramped up to 3 m/s and down at 4 m/s^2,
    4 kHz, F_N = 300 N (1 N force noise), inertial mass 12.5 kg, friction :func:`ramp_law`,
    seed 5; `options` override the arguments of ``make_raw_run``. Returns `path`.
    """

    def write(path: Path, **options) -> Path:
        df = make_raw_run(
            ramp_law,
            **{"kind": "instationary", "velocity_mps": 3.0, "accel_mps2": 4.0,
               "decel_mps2": 4.0, "sample_rate_Hz": 4000, "normal_force_N": 300.0,
               "force_noise_N": 1.0, "inertial_mass_kg": 12.5, "rng": 5,
               "metadata": {"specimen": "G0"}, **options},
        )
        return write_run_csv(df, path)

    return write
