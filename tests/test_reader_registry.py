"""Adding a footage reader is one class: it declares its suffixes, implements the public
properties and ``_read``, and is registered; ``open_footage`` and the analysis then read its
footage. The toy reader here reads NumPy ``.npy`` stacks (N, H, W), written by NumPy itself
(an independent writer); the truth is the rendered frames and their analysis from the PNG
folder they came from.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.io import (
    READERS,
    FootageError,
    FootageReader,
    FrameFolderReader,
    open_footage,
    readers,
    register_reader,
    unregister_reader,
)

FAST = AnalysisOptions(overlay_video=False, plots=False, overlay_frames=0, parquet=False)


class NpyStackReader(FootageReader):
    """Frames of a ``.npy`` file holding an (N, H, W) uint8 or uint16 stack (memory-mapped,
    one frame read at a time)."""

    kind = "npy"
    suffixes = (".npy",)

    def __init__(self, path):
        super().__init__(path)
        try:
            self._stack = np.load(self.path, mmap_mode="r")
        except ValueError as exc:
            raise FootageError(f"{self.path}: not a NumPy array file ({exc})", self.path) from exc
        if self._stack.ndim != 3:
            raise FootageError(f"{self.path}: expected (N, H, W), got {self._stack.shape}",
                               self.path)

    def __len__(self) -> int:
        return int(self._stack.shape[0])

    @property
    def frame_shape(self) -> tuple[int, int]:
        return (int(self._stack.shape[1]), int(self._stack.shape[2]))

    @property
    def dtype(self) -> np.dtype:
        return self._stack.dtype

    @property
    def frame_rate(self) -> float | None:
        return None  # meta.json gives it

    def _read(self, index: int) -> np.ndarray:
        return np.array(self._stack[index])


@pytest.fixture
def npy_reader():
    register_reader(NpyStackReader)
    try:
        yield NpyStackReader
    finally:
        unregister_reader("npy")


def test_a_toy_reader_is_chosen_by_suffix_and_its_footage_analysed(
    npy_reader, render_clip, copy_meta, tmp_path
):
    clip = render_clip(tmp_path / "clip", n_frames=24)
    with open_footage(clip / "frames") as folder:
        frames = np.stack(list(folder))
    stack = tmp_path / "npy" / "footage.npy"
    stack.parent.mkdir()
    np.save(stack, frames)
    copy_meta(clip, stack.parent)
    assert READERS[-1] is NpyStackReader and npy_reader in readers()
    assert [cls for cls in readers() if cls.claims(stack)] == [NpyStackReader]
    with open_footage(stack) as reader:
        assert isinstance(reader, NpyStackReader)
        assert (len(reader), reader.frame_shape, reader.bit_depth) == (24, frames.shape[1:], 8)
        np.testing.assert_array_equal(reader.get_frame(-1), frames[-1])
        np.testing.assert_array_equal(reader.frame_numbers, np.arange(24))
    # the whole analysis reads it as it reads the PNG folder the frames came from
    a = analyze_video(clip / "frames", options=FAST)
    b = analyze_video(stack, options=FAST)
    pd.testing.assert_frame_equal(a.frames, b.frames)


def test_registry_rules(npy_reader, tmp_path):
    with pytest.raises(ValueError, match="already registered"):
        register_reader(NpyStackReader)
    with pytest.raises(TypeError, match="does not implement"):
        register_reader(type("Half", (FootageReader,), {"kind": "half"}))
    with pytest.raises(ValueError, match="needs a kind"):
        register_reader(type("Nameless", (FrameFolderReader,), {"kind": ""}))
    unregister_reader("npy")
    path = tmp_path / "x.npy"
    np.save(path, np.zeros((2, 3, 4), np.uint8))
    with pytest.raises(FootageError, match="no reader fits"):
        open_footage(path)  # no longer claimed: every file reader tried, none reads it
    register_reader(NpyStackReader)
