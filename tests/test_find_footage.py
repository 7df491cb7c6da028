"""Which videos ``analyze --recursive`` finds in a tree (:func:`tir_contact.batch.find_footage`):
a folder of multi-page TIFF stacks is one video per stack, not one frame folder, and a stray
image beside clip folders does not hide them."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import tifffile

from tir_contact.batch import find_footage


def _stack(path: Path, pages: int) -> None:
    tifffile.imwrite(path, np.zeros((pages, 8, 12), np.uint8), photometric="minisblack")


def _frames(folder: Path, n: int) -> None:
    folder.mkdir(parents=True)
    for k in range(n):
        cv2.imwrite(str(folder / f"f{k:03d}.png"), np.full((8, 12), k, np.uint8))


def _found(root: Path, **kw) -> set[tuple[str, str]]:
    return {(f.path.relative_to(root).as_posix(), f.name)
            for f in find_footage([root], **kw)}


def test_a_folder_of_stacks_is_one_video_per_stack(tmp_path):
    stacks = tmp_path / "stacks"
    stacks.mkdir()
    for name in ("run1", "run2"):
        _stack(stacks / f"{name}.tif", 3)
    assert _found(stacks, recursive=True) == {("run1.tif", "run1"), ("run2.tif", "run2")}
    # inside a tree too
    assert _found(tmp_path, recursive=True) == {("stacks/run1.tif", "run1"),
                                                ("stacks/run2.tif", "run2")}
    # single-page TIFF frames stay one frame folder
    single = tmp_path / "single"
    single.mkdir()
    for k in range(3):
        _stack(single / f"f{k}.tif", 1)
    assert _found(single, recursive=True) == {(".", "single")}


def test_a_stray_image_beside_clip_folders_does_not_hide_them(tmp_path):
    root = tmp_path / "mixed"
    _frames(root / "good", 3)
    _frames(root / "other", 2)
    cv2.imwrite(str(root / "stray.png"), np.zeros((8, 12), np.uint8))
    # the stray image is a (one-frame) video of its own, and the clips are found
    assert _found(root, recursive=True) == {(".", "mixed"), ("good", "good"),
                                            ("other", "other")}
    # without --recursive the folder given is one video
    assert _found(root) == {(".", "mixed")}


def test_the_same_video_given_twice_is_analysed_once(tmp_path, monkeypatch, caplog):
    # run1, ./run1/ and a tree holding run1: one video, under its own name, each repeat
    # said; two different videos of the same name are both kept (names made unique)
    _frames(tmp_path / "run1", 3)
    _frames(tmp_path / "b" / "run1", 2)
    monkeypatch.chdir(tmp_path)
    with caplog.at_level("WARNING", logger="tir_contact"):
        found = find_footage(["run1", "./run1/", str(tmp_path / "run1")])
    assert [(f.path.resolve(), f.name) for f in found] == [((tmp_path / "run1").resolve(),
                                                            "run1")]
    assert caplog.text.count("given more than once") == 2
    both = find_footage(["run1", "b"], recursive=True)
    assert len(both) == 2 and len({f.name for f in both}) == 2


def test_videos_of_one_name_take_the_parents_that_tell_them_apart(tmp_path):
    # x/clip/clip.tif and y/clip/clip.tif: the folder named as the video adds nothing
    # (before: x__clip__clip, y__clip__clip); a third video of the name one folder deeper
    for parent in ("x", "y", "z/x"):
        (tmp_path / parent / "clip").mkdir(parents=True)
        _stack(tmp_path / parent / "clip" / "clip.tif", 2)
    found = find_footage([tmp_path / "x" / "clip" / "clip.tif",
                          tmp_path / "y" / "clip" / "clip.tif"])
    assert [f.name for f in found] == ["x__clip", "y__clip"]
    found = find_footage([tmp_path / p / "clip" / "clip.tif" for p in ("x", "y", "z/x")])
    assert [f.name for f in found] == [f"{tmp_path.name}__x__clip", "y__clip", "z__x__clip"]
