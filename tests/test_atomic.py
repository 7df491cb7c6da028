"""Atomic writes: complete files only, with the permissions a plain ``open()`` gives."""

from __future__ import annotations

import os
import stat
import sys

import pytest

from tir_common.atomic import atomic_write, make_temporary, write_json

posix_only = pytest.mark.skipif(sys.platform == "win32", reason="POSIX permission bits")


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture
def umask():
    """Set the process umask for one test and restore it afterwards."""
    saved = os.umask(0o022)
    os.umask(saved)
    yield os.umask
    os.umask(saved)


@posix_only
@pytest.mark.parametrize("mask, expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_atomic_write_gives_the_mode_of_a_plain_open(tmp_path, umask, mask, expected):
    umask(mask)
    plain = tmp_path / "plain.txt"
    with open(plain, "w") as fh:
        fh.write("x")
    atomic_write(tmp_path / "a.txt", lambda tmp: tmp.write_text("done"))
    write_json(tmp_path / "summary.json", {"a": 1})
    # 0o666 less the umask: the rule open() follows, checked against open() itself
    assert _mode(plain) == expected
    assert _mode(tmp_path / "a.txt") == expected
    assert _mode(tmp_path / "summary.json") == expected
    assert (tmp_path / "a.txt").read_text() == "done"


@posix_only
def test_make_temporary_is_new_and_not_owner_only(tmp_path, umask):
    umask(0o022)
    names = {make_temporary(tmp_path, ".overlay-", ".avi") for _ in range(20)}
    assert len(names) == 20
    for name in names:
        assert name.parent == tmp_path and name.name.startswith(".overlay-")
        assert name.suffix == ".avi" and name.stat().st_size == 0
        assert _mode(name) == 0o644


def test_failed_writer_leaves_nothing(tmp_path):
    def fail(tmp):
        tmp.write_text("half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        atomic_write(tmp_path / "out.csv", fail)
    assert list(tmp_path.iterdir()) == []
