"""Tests of the streaming footage readers and of meta.json handling (tir_contact.io, .meta)."""

from __future__ import annotations

import json
import logging
import re
import tracemalloc
from pathlib import Path

import cv2
import numpy as np
import pytest
import tifffile
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal

from tir_common.naming import natural_key
from tir_contact._readers import to_grey, unpack_12bit
from tir_contact.io import (
    ArrayReader,
    FootageError,
    FootageReader,
    FrameFolderReader,
    ImageFileReader,
    MultiPageTiffReader,
    VideoFileReader,
    load_meta,
    open_footage,
)
from tir_contact.meta import clip_footage, option_flag

# --- helpers -----------------------------------------------------------------------------


def luma(rgb: np.ndarray) -> np.ndarray:
    """BT.601 grey of an RGB image in the input's dtype, halves rounded up (the documented rule)."""
    c = rgb.astype(np.int64)
    return ((299 * c[..., 0] + 587 * c[..., 1] + 114 * c[..., 2] + 500) // 1000).astype(rgb.dtype)


def make_frames(n: int, shape=(24, 32), *, dtype=np.uint8, colour=False, seed=0) -> np.ndarray:
    """Distinct frames: noise plus the frame index in pixel (0, 0)."""
    rng = np.random.default_rng(seed)
    top = np.iinfo(dtype).max
    full = (*shape, 3) if colour else shape
    frames = rng.integers(0, top, size=(n, *full), endpoint=True).astype(dtype)
    index = np.arange(n) % (top + 1)
    frames[:, 0, 0] = index[:, None] if colour else index  # grey of equal channels: index
    return frames


def smooth_rgb(shape=(48, 64)) -> np.ndarray:
    """A smooth colour image, for lossy codecs."""
    y, x = np.mgrid[0 : shape[0], 0 : shape[1]]
    return np.stack([x * 3, y * 4, (x + y) * 2], axis=-1).astype(np.uint8)


def write_image(path: Path, image: np.ndarray) -> None:
    """Write one grey or RGB image: TIFF through tifffile, the rest through OpenCV (BGR)."""
    if path.suffix in (".tif", ".tiff"):
        tifffile.imwrite(path, image, photometric="rgb" if image.ndim == 3 else "minisblack")
    else:
        bgr = image[..., ::-1] if image.ndim == 3 else image
        assert cv2.imwrite(str(path), np.ascontiguousarray(bgr))


def write_folder(folder: Path, frames: np.ndarray, ext: str, *, pattern="f{:d}") -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for i, frame in enumerate(frames):
        write_image(folder / (pattern.format(i) + ext), frame)


def traced_peak(run) -> int:
    """Peak traced memory in bytes while `run()` executes."""
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        run()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


# --- natural sort and grey conversion ------------------------------------------------------


def test_natural_key_orders_numbers_by_value():
    names = ["f10.png", "f2.png", "f1.png", "F3.png", "f02b.png", "g1.png"]
    assert sorted(names, key=natural_key) == [
        "f1.png",
        "f2.png",
        "f02b.png",
        "F3.png",
        "f10.png",
        "g1.png",
    ]


@settings(max_examples=60, deadline=None)
@given(
    value=st.integers(0, 65535),
    dtype=st.sampled_from([np.uint8, np.uint16]),
    order=st.sampled_from(["rgb", "bgr"]),
)
def test_grey_of_equal_channels_is_the_channel(value, dtype, order):
    value = min(value, np.iinfo(dtype).max)
    image = np.full((2, 3, 3), value, dtype=dtype)
    grey = to_grey(image, order=order)
    assert grey.dtype == dtype
    assert_array_equal(grey, value)


@settings(max_examples=60, deadline=None)
@given(rgb=st.lists(st.integers(0, 65535), min_size=3, max_size=3))
def test_grey_is_bt601_and_between_channels(rgb):
    image = np.array(rgb, dtype=np.uint16).reshape(1, 1, 3)
    grey = int(to_grey(image, order="rgb")[0, 0])
    exact = (299 * rgb[0] + 587 * rgb[1] + 114 * rgb[2]) / 1000  # BT.601 in exact decimals
    assert abs(grey - exact) <= 0.5
    assert min(rgb) <= grey <= max(rgb)
    assert int(to_grey(image[..., ::-1], order="bgr")[0, 0]) == grey


def pack_12bit(values: np.ndarray) -> np.ndarray:
    """Pack 12-bit values the Photron way (the inverse of unpack_12bit)."""
    v = values.astype(np.uint16).reshape(-1, 2)
    a, b = v[:, 0], v[:, 1]
    out = np.stack([a >> 4, ((a & 0xF) << 4) | (b >> 8), b & 0xFF], axis=1)
    return out.astype(np.uint8).ravel()


@settings(max_examples=50, deadline=None)
@given(values=st.lists(st.integers(0, 4095), min_size=1, max_size=40))
def test_unpack_12bit_round_trip(values):
    if len(values) % 2:
        values = [*values, 0]
    arr = np.array(values, dtype=np.uint16)
    assert_array_equal(unpack_12bit(pack_12bit(arr), arr.size), arr)


# --- in-memory reader (the fake reader of the other tests) -------------------------------


def test_array_reader_interface():
    frames = make_frames(5, dtype=np.uint16)
    with ArrayReader(frames, frame_rate=2000.0, bit_depth=12) as reader:
        assert isinstance(reader, FootageReader)
        assert len(reader) == 5
        assert reader.frame_shape == (24, 32)
        assert reader.frame_rate == 2000.0
        assert reader.bit_depth == 12
        assert reader.dtype == np.uint16
        assert_array_equal(reader.get_frame(-1), frames[4])
        assert_array_equal(reader[2], frames[2])
        assert_array_equal(np.stack(list(reader)), frames)
        got = reader.get_frame(1)
        got[:] = 0  # a copy: the source is untouched
        assert_array_equal(reader.get_frame(1), frames[1])
        with pytest.raises(IndexError, match="out of range"):
            reader.get_frame(5)
    assert reader.closed
    with pytest.raises(FootageError, match="closed"):
        reader.get_frame(0)


def test_array_reader_converts_rgb_and_checks_frames():
    rgb = make_frames(2, colour=True)
    assert_array_equal(ArrayReader(rgb).get_frame(0), luma(rgb[0]))
    mixed = [np.zeros((4, 5), np.uint8), np.zeros((4, 5), np.uint8), np.zeros((4, 6), np.uint8)]
    reader = ArrayReader(mixed)
    with pytest.raises(FootageError, match=r"frame 2\): frame size 6 x 4 px differs"):
        reader.get_frame(2)
    with pytest.raises(FootageError, match="float64 is not supported"):
        ArrayReader(np.zeros((2, 3, 3)))
    with pytest.raises(FootageError, match="no frames"):
        ArrayReader([])


# --- frame folders -------------------------------------------------------------------------


FOLDER_CASES = [
    (".png", np.uint8, False),
    (".png", np.uint16, False),
    (".png", np.uint8, True),
    (".png", np.uint16, True),
    (".tif", np.uint8, False),
    (".tiff", np.uint16, False),
    (".tif", np.uint16, True),
    (".bmp", np.uint8, False),
    (".bmp", np.uint8, True),
]


@pytest.mark.parametrize(("ext", "dtype", "colour"), FOLDER_CASES)
def test_frame_folder_round_trip(tmp_path, ext, dtype, colour):
    frames = make_frames(4, dtype=dtype, colour=colour)
    write_folder(tmp_path / "frames", frames, ext)
    expected = luma(frames) if colour else frames
    with open_footage(tmp_path / "frames") as reader:
        assert isinstance(reader, FrameFolderReader)
        assert len(reader) == 4
        assert reader.frame_shape == (24, 32)
        assert reader.dtype == dtype
        assert reader.bit_depth == 8 * np.dtype(dtype).itemsize
        assert reader.frame_rate is None
        for i, frame in enumerate(reader):
            assert_array_equal(frame, expected[i])  # lossless formats: exact


@pytest.mark.parametrize("colour", [False, True])
def test_frame_folder_jpeg_within_codec_tolerance(tmp_path, colour):
    rgb = smooth_rgb()
    image = rgb if colour else luma(rgb)
    write_folder(tmp_path / "jpg", np.stack([image, image]), ".jpg")
    with open_footage(tmp_path / "jpg") as reader:
        frame = reader.get_frame(1)
    # JPEG at OpenCV's quality 95 on a smooth image: a few grey levels at most
    assert np.abs(frame.astype(int) - luma(rgb).astype(int)).max() <= 3


def test_frame_folder_natural_order_and_companions(tmp_path, caplog):
    folder = tmp_path / "run"
    frames = make_frames(12)
    write_folder(folder, frames, ".png", pattern="frame{:d}")
    (folder / "meta.json").write_text("{}")
    (folder / "ground_truth.csv").write_text("frame,area\n")
    (folder / "notes.txt").write_text("x")
    (folder / ".DS_Store").write_bytes(b"\0\1")
    (folder / "out").mkdir()
    with caplog.at_level(logging.DEBUG, logger="tir_contact"):
        reader = FrameFolderReader(folder)
    assert [p.name for p in reader.files[:3]] == ["frame0.png", "frame1.png", "frame2.png"]
    assert reader.files[-1].name == "frame11.png"
    assert [int(f[0, 0]) for f in reader] == list(range(12))  # f2 before f10
    assert "skipped 3 non-frame files" in caplog.text


def test_empty_folder(tmp_path):
    with pytest.raises(FootageError, match=re.escape(f"{tmp_path}: no image files")):
        open_footage(tmp_path)
    (tmp_path / "meta.json").write_text("{}")
    with pytest.raises(FootageError, match=r"no image files .* \(only meta.json\)"):
        open_footage(tmp_path)


@pytest.mark.parametrize("ext", [".png", ".jpg", ".bmp"])
def test_a_single_image_file_is_a_one_frame_video(tmp_path, ext, caplog):
    # before: read as a video through OpenCV, "header says -9223372036854775808 frames",
    # then "cannot decode this frame"
    frame = make_frames(1)[0]
    path = tmp_path / f"shot{ext}"
    write_image(path, frame)
    with caplog.at_level(logging.WARNING, logger="tir_contact"), open_footage(path) as r:
        assert isinstance(r, ImageFileReader) and len(r) == 1
        got = next(iter(r))
    assert got.shape == frame.shape
    if ext != ".jpg":  # lossless
        assert_array_equal(got, frame)
    assert "header says" not in caplog.text
    # an image under a video's name: no count in its header, so none claimed lost
    disguised = tmp_path / "shot.avi"
    disguised.write_bytes(path.read_bytes())
    try:
        reader = VideoFileReader(disguised)
    except FootageError:
        return  # this OpenCV build does not open it at all: an error, which is fine
    with reader:
        assert reader.lost_frames == () and "-9223372036854775808" not in caplog.text


def test_empty_folder_names_the_subfolder_that_holds_the_frames(tmp_path):
    # a clip folder whose meta.json lacks frame_pattern, frames in frames/: the message
    # names frames/ and the key to add; after adding it, the same path reads the frames
    clip = tmp_path / "run1"
    write_folder(clip / "frames", make_frames(3), ".png")
    (clip / "notes").mkdir()  # a sub-folder without images is not named
    (clip / "meta.json").write_text("{}")
    with pytest.raises(FootageError) as err:
        open_footage(clip)
    message = str(err.value)
    assert "sub-folder frames:" in message and "notes" not in message
    # the pattern of the frames' own names (write_folder's f0.png, f1.png, ...)
    assert '"frame_pattern": "frames/f{frame}.png"' in message
    (clip / "meta.json").write_text(json.dumps({"frame_pattern": "frames/f{frame:03d}.png"}))
    assert len(FrameFolderReader(clip_footage(clip))) == 3
    # and the clip folder itself opens them, as the analysis reads it (before: the same
    # message, asking for the key it now had)
    with open_footage(clip) as reader:
        assert len(reader) == 3 and Path(reader.path) == clip / "frames"
    # without meta.json the hint is to give the sub-folder itself
    (clip / "meta.json").unlink()
    hint = re.escape(f"give {clip / 'frames'}, or use --recursive")
    with pytest.raises(FootageError, match=hint):
        open_footage(clip)


def test_non_image_file_among_frames(tmp_path):
    write_folder(tmp_path, make_frames(3), ".png")
    (tmp_path / "f1.raw").write_bytes(b"\0" * 10)
    with pytest.raises(FootageError, match=r"f1\.raw: not an image file among the frames"):
        open_footage(tmp_path)


@pytest.mark.parametrize("ext", [".png", ".jpg", ".tif", ".bmp"])
def test_truncated_frame_named_when_read(tmp_path, ext):
    write_folder(tmp_path, make_frames(3), ext)
    bad = tmp_path / f"f1{ext}"
    data = bad.read_bytes()
    bad.write_bytes(data[: len(data) // 2])
    reader = open_footage(tmp_path)  # only the first frame is decoded when opening
    assert_array_equal(reader.get_frame(2)[0, 0], 2)
    with pytest.raises(FootageError, match=re.escape(f"{bad}: truncated or corrupt image")):
        reader.get_frame(1)


def test_corrupt_and_empty_frame_files(tmp_path):
    write_folder(tmp_path, make_frames(2), ".png")
    (tmp_path / "f0.png").write_bytes(b"this is no image")
    with pytest.raises(FootageError, match=r"f0\.png: truncated or corrupt image"):
        open_footage(tmp_path)  # the first frame is read when opening
    (tmp_path / "f0.png").write_bytes(b"")
    with pytest.raises(FootageError, match=r"f0\.png: empty file"):
        open_footage(tmp_path)


def test_mixed_sizes_and_depths_name_the_frame(tmp_path):
    write_folder(tmp_path, make_frames(3), ".png")
    write_image(tmp_path / "f10.png", make_frames(1, shape=(20, 32))[0])
    write_image(tmp_path / "f11.png", make_frames(1, dtype=np.uint16)[0])
    reader = open_footage(tmp_path)
    with pytest.raises(FootageError, match=r"f10\.png \(frame 3\): frame size 32 x 20 px"):
        reader.get_frame(3)
    with pytest.raises(FootageError, match=r"f11\.png \(frame 4\): pixel type uint16 differs"):
        reader.get_frame(4)


def test_alpha_is_dropped_and_stacks_are_refused_in_folders(tmp_path):
    rgba = np.dstack([smooth_rgb(), np.full((48, 64), 7, np.uint8)])
    cv2.imwrite(str(tmp_path / "f0.png"), rgba[..., [2, 1, 0, 3]])  # BGRA on disk
    with open_footage(tmp_path) as reader:
        assert_array_equal(reader.get_frame(0), luma(smooth_rgb()))
    tifffile.imwrite(tmp_path / "f1.tif", make_frames(5), photometric="minisblack")
    with pytest.raises(FootageError, match=r"f1\.tif: TIFF holds 5 pages"):
        open_footage(tmp_path).get_frame(1)


def test_float_tiff_frame_is_refused(tmp_path):
    tifffile.imwrite(tmp_path / "f0.tif", np.zeros((4, 5), np.float32))
    with pytest.raises(FootageError, match=r"f0\.tif: pixel type float32 is not supported"):
        open_footage(tmp_path)


# --- multi-page TIFF ------------------------------------------------------------------------


@pytest.mark.parametrize("compression", [None, "zlib"])
@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_multipage_tiff_round_trip(tmp_path, compression, dtype):
    frames = make_frames(6, dtype=dtype)
    path = tmp_path / "stack.tif"
    tifffile.imwrite(path, frames, compression=compression, photometric="minisblack")
    with open_footage(path) as reader:
        assert isinstance(reader, MultiPageTiffReader)
        assert (reader._contiguous is not None) == (compression is None)  # offset reads
        assert len(reader) == 6
        assert reader.bit_depth == 8 * np.dtype(dtype).itemsize
        assert_array_equal(reader.get_frame(4), frames[4])
        assert_array_equal(reader.get_frame(0), frames[0])
        assert_array_equal(np.stack(list(reader)), frames)


def test_multipage_tiff_colour_and_imagej_rate(tmp_path):
    rgb = make_frames(3, colour=True)
    path = tmp_path / "rgb.tif"
    tifffile.imwrite(path, rgb, photometric="rgb")
    with open_footage(path) as reader:
        assert_array_equal(reader.get_frame(2), luma(rgb[2]))
        assert reader.frame_rate is None
    grey = make_frames(4, dtype=np.uint16)
    tifffile.imwrite(tmp_path / "ij.tif", grey, imagej=True, metadata={"finterval": 0.0002})
    with open_footage(tmp_path / "ij.tif") as reader:
        assert reader.frame_rate == pytest.approx(5000.0)


def test_multipage_tiff_mixed_page_sizes(tmp_path):
    path = tmp_path / "mixed.tif"
    for shape in [(24, 32), (24, 32), (20, 32)]:
        tifffile.imwrite(path, np.zeros(shape, np.uint8), append=True)
    reader = open_footage(path)
    assert len(reader) == 3
    with pytest.raises(FootageError, match=r"mixed\.tif \(page 2\): frame size 32 x 20 px"):
        reader.get_frame(2)


def test_truncated_and_foreign_tiff(tmp_path):
    path = tmp_path / "stack.tif"
    tifffile.imwrite(path, make_frames(4), compression="zlib", photometric="minisblack")
    data = path.read_bytes()
    path.write_bytes(data[:40])
    with pytest.raises(FootageError, match=re.escape(str(path))):
        open_footage(path)
    path.write_bytes(b"no tiff at all")
    with pytest.raises(FootageError, match=r"stack\.tif: not a readable TIFF file"):
        open_footage(path)


# --- video files ----------------------------------------------------------------------------


def write_video(path: Path, frames: np.ndarray, fourcc: str, fps: float = 25.0) -> None:
    colour = frames.ndim == 4
    size = (frames.shape[2], frames.shape[1])
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*fourcc), fps, size, colour)
    if not writer.isOpened():
        pytest.skip(f"OpenCV cannot write {fourcc} {path.suffix} here")
    for frame in frames:
        writer.write(np.ascontiguousarray(frame[..., ::-1] if colour else frame))
    writer.release()


@pytest.mark.parametrize("colour", [False, True])
def test_video_lossless_round_trip_and_random_access(tmp_path, colour):
    frames = make_frames(12, colour=colour)
    path = tmp_path / "run.avi"
    write_video(path, frames, "FFV1")
    expected = luma(frames) if colour else frames
    with open_footage(path) as reader:
        assert isinstance(reader, VideoFileReader)
        assert len(reader) == 12
        assert reader.frame_rate == pytest.approx(25.0)
        assert reader.bit_depth == 8
        assert_array_equal(np.stack(list(reader)), expected)  # FFV1 is lossless: exact
        for i in (7, 2, 11, 0, 5):
            assert_array_equal(reader.get_frame(i), expected[i])


@pytest.mark.parametrize(("fourcc", "ext"), [("MJPG", ".avi"), ("mp4v", ".mp4"), ("mp4v", ".mov")])
def test_video_lossy_within_tolerance(tmp_path, fourcc, ext):
    base = smooth_rgb()
    frames = np.stack([np.roll(base, 2 * i, axis=1) for i in range(8)])
    path = tmp_path / f"run{ext}"
    write_video(path, frames, fourcc)
    with open_footage(path) as reader:
        assert len(reader) == 8
        got = reader.get_frame(5)
    # lossy codecs on a smooth image: mean error of a few grey levels
    assert np.abs(got.astype(int) - luma(frames[5]).astype(int)).mean() < 4


def test_video_cut_short_lists_its_lost_frames(tmp_path):
    """An AVI cut at half its bytes: the frames its header claims past the last one that
    decodes are lost (the analysis then marks the video partial), and that last one too
    (it may be cut: OpenCV 4.8 decodes a truncated FFV1 frame with 19 % of its pixels
    wrong); the rest read exactly."""
    frames = make_frames(20)
    whole = tmp_path / "whole.avi"
    write_video(whole, frames, "FFV1")
    data = whole.read_bytes()
    cut = tmp_path / "cut.avi"
    cut.write_bytes(data[: len(data) // 2])
    with open_footage(cut) as reader:
        n = len(reader)
        assert 1 <= n < 20
        assert reader.lost_frames == tuple(range(n, 20))
        for i in range(n):
            assert_array_equal(reader.get_frame(i), frames[i])  # FFV1: exact
    with open_footage(whole) as reader:
        assert reader.lost_frames == ()


def test_video_with_zero_frames(tmp_path):
    path = tmp_path / "empty.avi"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"FFV1"), 25.0, (32, 24), False)
    writer.release()
    if not path.exists():
        pytest.skip("OpenCV wrote no file for an empty video")
    with pytest.raises(FootageError, match=r"empty\.avi: video holds no frames"):
        open_footage(path)


def test_corrupt_video(tmp_path):
    path = tmp_path / "broken.mp4"
    path.write_bytes(b"\x00garbage" * 50)
    with pytest.raises(FootageError, match=r"broken\.mp4: OpenCV cannot open it"):
        open_footage(path)


# --- open_footage ---------------------------------------------------------------------------


def test_open_footage_reports_every_reader(tmp_path):
    with pytest.raises(FootageError, match=r"nothing\.avi: does not exist"):
        open_footage(tmp_path / "nothing.avi")
    odd = tmp_path / "data.xyz"
    odd.write_bytes(b"plain bytes, no footage")
    with pytest.raises(FootageError) as info:
        open_footage(odd)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{odd}: no reader fits: ")
    for name in ("MultiPageTiffReader", "VideoFileReader", "MrawReader", "CineReader"):
        assert name + ":" in message


def test_open_footage_kind(tmp_path):
    path = tmp_path / "stack.dat"
    tifffile.imwrite(path, make_frames(2), photometric="minisblack")
    with open_footage(path, kind="tiff") as reader:
        assert len(reader) == 2
    with open_footage(path) as reader:  # unknown suffix: the readers are tried in turn
        assert isinstance(reader, MultiPageTiffReader)
    with pytest.raises(ValueError, match="kind must be one of"):
        open_footage(path, kind="gif")


# --- bounded memory -------------------------------------------------------------------------


@pytest.mark.parametrize("source", ["tiff", pytest.param("tiff-zlib", marks=pytest.mark.slow),
                                    "folder"])
def test_iterating_2000_frames_keeps_memory_bounded(tmp_path, source):
    n, shape = 2000, (64, 64)
    frames = np.zeros((n, *shape), np.uint16)
    frames[:, 0, 0] = np.arange(n)
    video_bytes = frames.nbytes  # 16 MiB
    if source == "folder":
        write_folder(tmp_path / "frames", frames, ".png")
        path = tmp_path / "frames"
    else:
        path = tmp_path / "stack.tif"
        tifffile.imwrite(path, frames, compression="zlib" if source == "tiff-zlib" else None)
    del frames
    reader = open_footage(path)
    seen = []

    def run() -> None:
        for frame in reader:
            seen.append(int(frame[0, 0]))

    peak = traced_peak(run)
    reader.close()
    assert seen == list(range(n))
    assert peak < video_bytes / 20, f"peak {peak} bytes while iterating {video_bytes} bytes"


# --- meta.json ------------------------------------------------------------------------------


META = {
    "view": "tir",
    "fps": 5000.0,
    "mm_per_px": 0.05,
    "sliding_direction": "right",
    "contact_is": "dark",
    "block": {
        "length_mm": 20,
        "width_mm": 20,
        "n_sipes": 2,
        "sipe_width_mm": 0.4,
        "height_mm": 10,
    },
    "conditions": {
        "velocity_mps": 0.1,
        "pressure_bar": 2.5,
        "temperature_C": -5,
        "humidity_pct": 70,
        "salinity_pct": 0,
    },
    "operator": "kept as is",
}


def write_meta(folder: Path, data, name="meta.json") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return path


def test_meta_read_and_overridden(tmp_path):
    write_meta(tmp_path, META)
    meta = load_meta(tmp_path)
    assert meta["fps"] == 5000.0
    assert meta["block"]["n_sipes"] == 2
    assert isinstance(meta["block"]["length_mm"], float)
    assert meta["operator"] == "kept as is"
    meta = load_meta(
        tmp_path,
        {"fps": 2500, "block.n_sipes": "3", "mm_per_px": "0.1", "view": None, "extra.x": 1},
    )
    assert meta["fps"] == 2500.0
    assert meta["block"]["n_sipes"] == 3
    assert meta["mm_per_px"] == 0.1
    assert meta["view"] == "tir"  # None: option not given
    assert meta["extra"] == {"x": 1}


def test_a_misspelt_override_is_warned_about(tmp_path, caplog):
    # before, a script's mm_per_pixel or blok.length_mm changed nothing without a word; a
    # key of the user's own (extra.x, operator) is kept without one
    write_meta(tmp_path, META)
    with caplog.at_level("WARNING", logger="tir_contact"):
        meta = load_meta(tmp_path, {"mm_per_pixel": 0.2, "blok.length_mm": 5, "extra.x": 1})
    assert meta["mm_per_px"] == META["mm_per_px"]
    assert "'mm_per_pixel' is not a key the analysis reads (did you mean 'mm_per_px'?)" \
        in caplog.text
    assert "did you mean 'block.length_mm'?" in caplog.text
    assert "extra" not in caplog.text


def test_meta_without_file_uses_overrides_header_and_defaults(tmp_path):
    video = tmp_path / "run.avi"
    video.write_bytes(b"")
    meta = load_meta(video, {"mm_per_px": 0.02, "sliding_direction": "LEFT"}, frame_rate=10000.0)
    assert meta == {
        "mm_per_px": 0.02,
        "sliding_direction": "left",
        "fps": 10000.0,
        "view": "tir",
        "contact_is": "dark",
    }
    write_meta(tmp_path, {"mm_per_px": 0.9})
    given = {"sliding_direction": "left", "fps": 1}
    assert load_meta(video, given)["mm_per_px"] == 0.9  # the folder's meta.json
    # run.meta.json (the name without its suffix) wins over it, run.avi.meta.json over both
    write_meta(tmp_path, {"mm_per_px": 0.7}, name="run.meta.json")
    assert load_meta(video, given)["mm_per_px"] == 0.7
    write_meta(tmp_path, {"mm_per_px": 0.5}, name="run.avi.meta.json")
    assert load_meta(video, given)["mm_per_px"] == 0.5


@pytest.mark.parametrize(
    ("key", "pattern"),
    [
        ("mm_per_px", r"meta\.json has no 'mm_per_px': add it to meta\.json or pass --mm-per-px"),
        ("fps", r"has no 'fps': .* pass --fps \(the footage header gives no frame rate\)"),
        ("sliding_direction", r"pass --sliding-direction"),
    ],
)
def test_meta_missing_required_key(tmp_path, key, pattern):
    data = {k: v for k, v in META.items() if k != key}
    write_meta(tmp_path, data)
    with pytest.raises(FootageError, match=pattern):
        load_meta(tmp_path)
    assert option_flag("block.n_sipes") == "--block-n-sipes"


def test_meta_missing_file_says_where(tmp_path):
    # every missing key at once, each with its option (not one per run)
    with pytest.raises(
        FootageError,
        match=r"no meta\.json beside the footage gives 'fps', 'mm_per_px', 'sliding_direction':"
              r" add them to .*meta\.json or pass --fps, --mm-per-px, --sliding-direction "
              r"\(the footage header gives no frame rate\)",
    ):
        load_meta(tmp_path)
    with pytest.raises(FootageError, match=r"gives 'sliding_direction': add it to .* or pass "
                                           r"--sliding-direction$"):
        load_meta(tmp_path, overrides={"fps": 100.0, "mm_per_px": 0.1})


def test_meta_header_rate_used_and_disagreement_logged(tmp_path, caplog):
    write_meta(tmp_path, META)
    with caplog.at_level(logging.WARNING, logger="tir_contact"):
        meta = load_meta(tmp_path, frame_rate=4000.0)
    assert meta["fps"] == 5000.0
    assert "footage header 4000 Hz" in caplog.text


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ("{not json", r"meta\.json: not valid JSON \(.* line 1, column 2\)"),
        ("[1, 2]", r"meta\.json: expected a JSON object"),
        ('{"fps": "fast"}', r"meta\.json: 'fps' must be a number > 0, got 'fast' \(str\)"),
        ('{"fps": true}', r"'fps' must be a number > 0, got True \(bool\)"),
        ('{"fps": -3}', r"'fps' must be a number > 0, got -3"),
        ('{"view": "top"}', r"'view' must be one of 'tir', 'side', got 'top'"),
        ('{"block": [1]}', r"'block' must be a JSON object"),
        ('{"block": {"n_sipes": 2.5}}', r"'block.n_sipes' must be an integer >= 0, got 2.5"),
        ('{"conditions": {"humidity_pct": 140}}', r"'conditions.humidity_pct' must be a number"),
    ],
)
def test_meta_bad_file(tmp_path, text, pattern):
    path = write_meta(tmp_path, text)
    with pytest.raises(FootageError, match=pattern):
        load_meta(tmp_path, required=())
    with pytest.raises(FootageError) as info:
        load_meta(path, required=())
    assert str(info.value).startswith(str(path))
    assert "\n" not in str(info.value)


def test_meta_bad_override_and_nulls(tmp_path):
    write_meta(tmp_path, {**META, "block": None, "fps": None})
    meta = load_meta(tmp_path, frame_rate=300.0)
    assert "block" not in meta
    assert meta["fps"] == 300.0
    with pytest.raises(FootageError, match=r"option --fps: 'fps' must be a number > 0, got 'x'"):
        load_meta(tmp_path, {"fps": "x"})
    with pytest.raises(FootageError, match=r"option --sliding-direction: 'sliding_direction'"):
        load_meta(tmp_path, {"sliding_direction": "up"})
    with pytest.raises(FootageError, match=r"cannot set 'view.x' because 'view' is not an object"):
        load_meta(tmp_path, {"view.x": 1})
