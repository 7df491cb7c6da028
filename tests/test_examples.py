"""Every example script takes ``--out`` and ``--help`` and refuses an option it does not
know, before it computes anything.

Before, seven scripts read no command line at all: ``--help``, ``--out X`` or a misspelt
option ran the whole computation and wrote into ``examples/out/`` of the source tree.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted(p for p in (Path(__file__).parents[1] / "examples").glob("*.py")
                  if not p.name.startswith("_"))


def _run(script: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(script), *args], capture_output=True,
                          text=True, timeout=120, check=False)


# with -m slow (two runs of each script, each importing the model: about a minute)
@pytest.mark.slow
@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_takes_out_and_help_and_refuses_unknown_options(script, tmp_path):
    shown = _run(script, "--help")
    assert shown.returncode == 0, shown.stderr
    assert "--out" in shown.stdout
    wrong = _run(script, "--no-such-option", "--out", str(tmp_path / "x"))
    assert wrong.returncode == 2 and "--no-such-option" in wrong.stderr
    assert not (tmp_path / "x").exists()  # refused before anything is written
