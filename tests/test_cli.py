"""The console command as a user meets it: help, exit codes, one-line errors, no traceback."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys

import pytest

from tir_contact.cli import build_parser, main

#: Every command a user can type (``synth`` has two of its own).
COMMANDS = [
    [],
    ["analyze"],
    ["evaluate"],
    ["calibrate"],
    ["simulate"],
    ["discrepancy"],
    ["demo"],
    ["report"],
    ["synth"],
    ["synth", "footage"],
    ["synth", "measurements"],
]

#: A minimal valid command line of each command with an output path, the output last.
WITH_OUT = {
    "analyze": ["analyze", "clip", "--out"],
    "evaluate": ["evaluate", "runs", "--out"],
    "calibrate": ["calibrate", "--characteristic", "c.csv", "--out"],
    "simulate": ["simulate", "--params", "p.json", "--out"],
    "discrepancy": ["discrepancy", "--steady", "s.csv", "--out"],
    "demo": ["demo", "--out"],
    "synth footage": ["synth", "footage", "--out"],
    "synth measurements": ["synth", "measurements", "--kind", "steady", "--out"],
}


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: " ".join(c) or "tir-contact")
def test_help_of_every_command(command, capsys):
    assert main([*command, "--help"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"usage: {' '.join(['tir-contact', *command])}")
    assert "Traceback" not in out


def test_help_through_the_console_script():
    # the installed entry point, as a user types it (a new process: no pytest capture)
    done = subprocess.run([sys.executable, "-m", "tir_contact", "analyze", "--help"],
                          capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert "--conditions-humidity-pct" in done.stdout and "in %" in done.stdout


def test_top_level_help_imports_no_command_and_no_heavy_library():
    """``tir-contact --help`` stays fast: the command modules (and with them pandas, scipy,
    the image libraries and friction_model) are imported only for the command given."""
    probe = (
        "import sys; from tir_contact.cli import main; main(['--help']); "
        "heavy = ('tir_contact.commands.analyze', 'tir_contact.commands.demo', 'pandas', "
        "'scipy', 'cv2', 'friction_model', 'synthetic', 'matplotlib'); "
        "print(sorted(m for m in heavy if m in sys.modules), file=sys.stderr)"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stderr.strip() == "[]"
    assert "calibrate" in done.stdout and "synth" in done.stdout


def test_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.startswith("tir-contact ")


@pytest.mark.parametrize("argv", [["analyze"], ["bogus"], ["evaluate", "x", "--out", "o", "--nope"],
                                  ["analyze", "x", "--out", "o", "--workers", "0"]])
def test_bad_options_exit_2_without_traceback(argv, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "error:" in err.splitlines()[-1]
    assert "Traceback" not in err


def test_unknown_option_is_said_by_the_command_with_the_nearest_one(capsys):
    """A typo after the command: the command's own usage line and error (before: the top
    level's, which does not list the command's options), and the option meant."""
    assert main(["analyze", "x", "--out", "o", "--mm-px", "0.05"]) == 2
    err = capsys.readouterr().err
    assert "usage: tir-contact analyze" in err
    last = err.splitlines()[-1]
    assert last.startswith("tir-contact analyze: error: unrecognized arguments: --mm-px")
    assert "did you mean --mm-per-px?" in last


@pytest.mark.parametrize(("option", "value", "message"), [
    ("--mm-per-px", "0.1mm", "option --mm-per-px: 'mm_per_px' must be a number > 0, got '0.1mm'"),
    ("--sliding-direction", "leftward", "option --sliding-direction: 'sliding_direction' must be"),
    ("--fps", "4kHz", "option --fps: 'fps' must be a number > 0, got '4kHz'"),
    ("--lit-mask", "no_mask.png", "argument --lit-mask: no_mask.png: no such file"),
    ("--reference", "no_reference.png", "argument --reference: no_reference.png: no such file"),
])
def test_analyze_option_that_cannot_be_used_is_a_usage_error(option, value, message, tmp_path,
                                                               capsys, monkeypatch):
    """A metadata or input option the analysis cannot use is the same for every video: exit
    code 2 before any video is read, the option named, no output folder (before, each video
    failed with it, exit code 1, and the batch's folder and report were written)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "clip").mkdir()
    out = tmp_path / "out"
    assert main(["analyze", "clip", "--out", str(out), option, value]) == 2
    err = capsys.readouterr().err
    assert message in err.splitlines()[-1] and "Traceback" not in err
    assert not out.exists()


@pytest.mark.parametrize("name", sorted(WITH_OUT))
def test_output_under_a_file_is_one_line(name, tmp_path, capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    assert main([*WITH_OUT[name], str(blocker / "out")]) == 2
    err = capsys.readouterr().err
    last = err.splitlines()[-1]
    assert "argument --out" in last and str(blocker) in last and "not a folder" in last
    assert "Traceback" not in err


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc (Linux)")
def test_output_where_nothing_can_be_written(capsys):
    assert main(["demo", "--out", "/proc/self/no_such_dir/out"]) == 2
    last = capsys.readouterr().err.splitlines()[-1]
    assert "/proc/self/no_such_dir/out: cannot write there" in last


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0,
                    reason="root writes into read-only folders")
def test_read_only_output_folder(tmp_path, capsys):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        assert main(["demo", "--out", str(folder / "out")]) == 2
    finally:
        folder.chmod(0o700)
    assert "cannot write there" in capsys.readouterr().err


def test_output_check_leaves_nothing_behind(tmp_path):
    target = tmp_path / "new" / "deeper"
    args = build_parser().parse_args(["demo", "--out", str(target)])
    assert args.out == target
    assert list(tmp_path.iterdir()) == []  # no folder made, no probe file left


def _every_command_runs(func, monkeypatch) -> None:
    """Make :func:`tir_contact.cli.main` call `func(args)` instead of the command's ``run``
    (the arguments parsed as usual)."""
    parser = build_parser()
    real_parse = parser.parse_known_args

    def parse(argv=None, namespace=None):
        args, extras = real_parse(argv, namespace)
        args.func = func
        return args, extras

    monkeypatch.setattr(parser, "parse_known_args", parse)
    monkeypatch.setattr("tir_contact.cli.build_parser", lambda commands=None: parser)


@pytest.mark.parametrize(("exc", "code", "words"), [
    (ValueError("runs.csv: column 'mu' missing"), 2, "error: runs.csv: column 'mu' missing"),
    (FileNotFoundError(2, "No such file or directory", "x.csv"), 2, "No such file"),
    (RuntimeError("boom\nsecond line"), 1, "internal error: RuntimeError: boom second line"),
])
def test_errors_from_a_command_are_one_line(monkeypatch, capsys, exc, code, words):
    def fail(args: argparse.Namespace) -> int:
        raise exc

    _every_command_runs(fail, monkeypatch)
    assert main(["demo"]) == code
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err and "Traceback" not in err


def test_quiet_switches_progress_off(monkeypatch):
    seen = {}

    def record(args: argparse.Namespace) -> int:
        seen.update(vars(args))
        return 0

    _every_command_runs(record, monkeypatch)
    assert main(["analyze", "clip", "--out", "o", "-q"]) == 0
    assert seen["no_progress"] is True and seen["quiet"] is True
    seen.clear()
    assert main(["-q", "evaluate", "runs", "--out", "o"]) == 0
    assert seen["no_progress"] is True
    seen.clear()
    assert main(["analyze", "clip", "--out", "o"]) == 0
    assert seen["no_progress"] is False and seen["quiet"] is False
