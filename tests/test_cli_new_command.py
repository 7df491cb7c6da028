"""Adding a command is a module with DESCRIPTION, add_arguments and run, and one line in
:data:`tir_contact.cli.COMMANDS` (docs/architecture.md, "A command").

This test module is itself the toy command's module: ``tir-contact wear`` takes a sliding
distance and a wear rate, calls one library function (:func:`worn_depth_mm`, Archard's law
h = k p s) and prints what it returns. The truth is the law by hand.
"""

from __future__ import annotations

import argparse

import pytest

from tir_contact import cli

DESCRIPTION = "Worn tread depth after a sliding distance (Archard's law h = k p s)."


def worn_depth_mm(distance_m: float, pressure_bar: float, rate_mm3_per_Nm: float) -> float:
    """The library function: worn depth h = k p s, mm (k in mm^3/(N m), p in N/mm^2)."""
    if distance_m < 0:
        raise ValueError(f"distance_m must be >= 0, got {distance_m}")
    return rate_mm3_per_Nm * pressure_bar * 0.1 * distance_m


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--distance", type=float, required=True, help="sliding distance, m")
    p.add_argument("--pressure", type=float, default=2.5, help="pressure, bar")
    p.add_argument("--rate", type=float, default=1e-4, help="wear rate, mm^3/(N m)")


def run(args: argparse.Namespace) -> int:
    depth = worn_depth_mm(args.distance, args.pressure, args.rate)
    print(f"worn depth {depth:.4g} mm")
    return 0


@pytest.fixture
def wear_command(monkeypatch):
    monkeypatch.setitem(cli.COMMANDS, "wear", cli.Command(
        "worn tread depth after a sliding distance", data_errors=(), module=__name__))


def test_a_new_command_is_one_module_and_one_table_line(wear_command, capsys):
    assert cli.main(["wear", "--distance", "1000", "--pressure", "2.5", "--rate", "2e-4"]) == 0
    # h = 2e-4 mm^3/(N m) x 0.25 N/mm^2 x 1000 m = 0.05 mm
    assert capsys.readouterr().out.strip() == "worn depth 0.05 mm"
    assert cli.main(["--help"]) == 0
    assert "worn tread depth after a sliding distance" in capsys.readouterr().out
    # its errors end in cli.main like every command's: one line, exit code 2
    assert cli.main(["wear", "--distance", "-1"]) == 2
    assert "tir-contact wear: error: distance_m must be >= 0, got -1.0" in capsys.readouterr().err
