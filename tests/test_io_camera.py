"""Tests of the camera-file readers (tir_contact.io MrawReader, CineReader) and their parsers.

Truth: the facts of ../shared/camera-samples/README.md (read from the headers by the people
who published the files), pixel checksums of the samples frozen from the previous
implementation (which parsed the headers with pyMRAW 0.33.0 and pycine 0.3.2; its MRAW frames
equalled ``pyMRAW.load_video`` and its CINE frames pycine's own ``frame_reader`` with neutral
black/white levels, bit for bit), and files written by hand in each test from the documented
layouts. Pixel data are integers, so every comparison is exact. No optional package is needed.
"""

from __future__ import annotations

import hashlib
import logging
import shutil
import struct
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from tir_contact._cih import parse_cih_text, parse_cihx_bytes
from tir_contact.io import CineReader, FootageError, MrawReader, open_footage

SAMPLES = Path(__file__).resolve().parents[2] / "shared" / "camera-samples"

#: Frozen from the previous implementation (see the module notes): SHA-256 of all frames
#: stacked as little-endian uint16 in C order, the sum of all pixels, and single pixels
#: ``(frame, row, column): value`` with row 0 at the top. Integer data: exact.
FROZEN = {
    "beam.mraw": (
        "148e6af67046a8bcab46852857ba40394f6998c3a40618a941dc0c8015e21f3b",
        252377021,
        {(0, 0, 0): 76, (0, 40, 341): 1564, (0, 79, 1023): 538, (3, 0, 0): 125,
         (3, 40, 341): 1275, (3, 79, 1023): 922},
    ),
    "ball_12bit.mraw": (
        "72e92de42669032f6b77b6ff301a4e466c466ef9c1c465bcd46f8f4ce0907a2e",
        7728115494,
        {(0, 0, 0): 4095, (0, 192, 128): 4095, (0, 383, 383): 165, (14, 0, 0): 4095,
         (14, 192, 128): 4095, (14, 383, 383): 161},
    ),
    "cine_781.cine": (
        "ea806498c3d79ca9b4138f24789d56658426ddc70491f3068105054c1efc0756",
        2651114107,
        {(0, 0, 0): 2921, (0, 128, 85): 2864, (0, 255, 255): 2809, (14, 0, 0): 2928,
         (14, 128, 85): 2830, (14, 255, 255): 2767},
    ),
    "cine_legacy.cine": (
        "780c14b25c610f000c66b004d22171666f936a3e6a3e7418e121edace6b3a4bb",
        6634654973,
        {(0, 0, 0): 0, (0, 64, 42): 586, (0, 127, 127): 0, (96, 0, 0): 5493,
         (96, 64, 42): 5293, (96, 127, 127): 4517},
    ),
}


# --- helpers -----------------------------------------------------------------------------


def samples_or_skip() -> Path:
    if not (SAMPLES / "README.md").is_file():
        pytest.skip(f"camera samples not found at {SAMPLES}")
    return SAMPLES


def read_all(path: Path) -> tuple[np.ndarray, object]:
    with open_footage(path) as reader:
        return np.stack(list(reader)), reader


def assert_frozen(name: str, frames: np.ndarray) -> None:
    digest, total, pixels = FROZEN[name]
    assert frames.dtype == np.uint16
    for (k, y, x), value in pixels.items():
        assert int(frames[k, y, x]) == value, (name, k, y, x)
    assert int(frames.sum(dtype=np.int64)) == total
    stacked = np.ascontiguousarray(frames.astype("<u2")).tobytes()
    assert hashlib.sha256(stacked).hexdigest() == digest


def pack_12bit(values: np.ndarray) -> np.ndarray:
    """Pack 12-bit values the Photron way: ``AAAAAAAA AAAABBBB BBBBBBBB``."""
    v = values.astype(np.uint16).reshape(-1, 2)
    a, b = v[:, 0], v[:, 1]
    out = np.stack([a >> 4, ((a & 0xF) << 4) | (b >> 8), b & 0xFF], axis=1)
    return out.astype(np.uint8).ravel()


def write_mraw(stem: Path, frames: np.ndarray, *, bits: int, side="Lower", effective=None):
    """Write .mraw + .cih by hand (Photron layout), 8/16-bit words or 12-bit packed."""
    n, h, w = frames.shape
    if bits == 12:
        data = pack_12bit(frames.ravel()).tobytes()
    else:
        data = frames.astype(np.uint8 if bits == 8 else "<u2").tobytes()
    stem.with_suffix(".mraw").write_bytes(data)
    lines = {
        "Record Rate(fps)": "20000",
        "Total Frame": n,
        "Image Width": w,
        "Image Height": h,
        "Color Type": "Mono",
        "Color Bit": bits,
        "File Format": "MRaw",
        "EffectiveBit Depth": effective or min(bits, 12),
        "EffectiveBit Side": side,
    }
    text = "#Camera Information Header\n" + "".join(f"{k} : {v}\n" for k, v in lines.items())
    stem.with_suffix(".cih").write_text(text + "\n")


def make_frames(n: int, shape=(24, 32), *, dtype=np.uint8, colour=False, seed=0) -> np.ndarray:
    """Distinct frames: noise plus the frame index in pixel (0, 0)."""
    rng = np.random.default_rng(seed)
    top = np.iinfo(dtype).max
    full = (*shape, 3) if colour else shape
    frames = rng.integers(0, top, size=(n, *full), endpoint=True).astype(dtype)
    frames[:, 0, 0] = (np.arange(n) % (top + 1))[:, None] if colour else np.arange(n) % (top + 1)
    return frames


def luma(rgb: np.ndarray) -> np.ndarray:
    """BT.601 grey of an RGB image in the input's dtype, halves rounded up (the documented rule)."""
    c = rgb.astype(np.int64)
    return ((299 * c[..., 0] + 587 * c[..., 1] + 114 * c[..., 2] + 500) // 1000).astype(rgb.dtype)


def write_cine(
    path: Path,
    frames: np.ndarray,
    *,
    fps: int = 1000,
    real_bpp: int | None = None,
    setup_length: int = 1024,
    annotation: int = 8,
    first_image_no: int = -3,
) -> list[int]:
    """Write an uncompressed CINE file by hand from the documented layout; return offsets.

    CINEFILEHEADER (44 bytes), BITMAPINFOHEADER (40 bytes), a SETUP of `setup_length` bytes
    (FrameRate16 at byte 0, "ST" and Length at 140/142, FrameRate at 768 and RealBPP at 896
    where the setup is long enough), the image offsets, then one record per image:
    AnnotationSize, annotation bytes, ImageSize, pixels stored bottom-up (BGR for colour).
    """
    n, h, w = frames.shape[:3]
    colour = frames.ndim == 4
    bits = 8 * frames.dtype.itemsize * (3 if colour else 1)
    setup = bytearray(setup_length)
    struct.pack_into("<H", setup, 0, min(fps, 65535))
    setup[140:142] = b"ST"
    struct.pack_into("<H", setup, 142, setup_length)
    if setup_length >= 772:
        struct.pack_into("<I", setup, 768, fps)
    if setup_length >= 900:
        struct.pack_into("<I", setup, 896, real_bpp or 8 * frames.dtype.itemsize)
    off_offsets = 44 + 40 + setup_length
    image_bytes = h * w * bits // 8
    first = off_offsets + 8 * n
    offsets = [first + i * (annotation + image_bytes) for i in range(n)]
    cfh = struct.pack(
        "<2sHHHiIiIIII", b"CI", 44, 0, 1, first_image_no, n, first_image_no, n, 44, 84,
        off_offsets,
    ) + bytes(8)
    bih = struct.pack("<IiiHHIIiiII", 40, w, h, 1, bits, 0, image_bytes, 0, 0, 0, 0)
    with open(path, "wb") as fh:
        fh.write(cfh + bih + bytes(setup))
        fh.write(np.array(offsets, "<i8").tobytes())
        for frame in frames:
            stored = frame[::-1, :, ::-1] if colour else frame[::-1]  # bottom-up, BGR
            fh.write(struct.pack("<I", annotation) + b"\x07" * (annotation - 8))
            fh.write(struct.pack("<I", image_bytes))
            fh.write(np.ascontiguousarray(stored).astype(frames.dtype.newbyteorder("<")).tobytes())
    return offsets


def cut_copy(tmp_path: Path, name: str, keep: int) -> Path:
    """Copy a sample (with its header) into `tmp_path`, keeping the first `keep` data bytes."""
    source = samples_or_skip() / name
    target = tmp_path / name
    target.write_bytes(source.read_bytes()[:keep])
    if source.suffix == ".mraw":
        shutil.copy(source.with_suffix(".cihx"), target.with_suffix(".cihx"))
    return target


# --- no optional package ---------------------------------------------------------------


def test_samples_read_without_pymraw_or_pycine(monkeypatch):
    samples = samples_or_skip()
    for name in ("pyMRAW", "pymraw", "pycine", "pycine.file", "xmltodict"):
        monkeypatch.setitem(sys.modules, name, None)  # makes `import name` fail
    for name in ("beam.cihx", "ball_12bit.mraw", "cine_781.cine", "cine_legacy.cine"):
        with open_footage(samples / name) as reader:
            assert len(reader) > 0
            reader.get_frame(-1)


# --- Photron headers --------------------------------------------------------------------


def test_cih_text_values_and_sections():
    text = (
        "#Camera Information Header\r\n"
        "Record Rate(fps) : 60000\r\n"
        "Shutter Speed(s) : 1/800000\r\n"
        "Time : 00:11\r\n"
        "Pre LUT Gain : 1.0\r\n"
        "Partition Number: 1\r\n"
        "Scene Name : \r\n"
        "\r\n"
        "#Photron Fastcam Viewer Version Information:\r\n"
        "PFV.exe : 3.6.3.0\r\n"
    )
    assert parse_cih_text(text) == {
        "Record Rate(fps)": 60000,
        "Shutter Speed(s)": "1/800000",
        "Time": "00:11",
        "Pre LUT Gain": 1.0,
        "Partition Number": 1,
        "Scene Name": "",
    }


def test_cihx_sample_header_facts():
    samples = samples_or_skip()
    beam = parse_cihx_bytes((samples / "beam.cihx").read_bytes())
    # the README's facts: 50000 fps, 4 frames of 1024 x 80, effective depth 12 in 16-bit words
    assert beam["Record Rate(fps)"] == 50000.0
    assert (beam["Total Frame"], beam["Image Width"], beam["Image Height"]) == (4, 1024, 80)
    assert (beam["Color Bit"], beam["EffectiveBit Depth"]) == (16, 12)
    ball = parse_cihx_bytes((samples / "ball_12bit.cihx").read_bytes())
    assert ball["Record Rate(fps)"] == 30000.0
    assert (ball["Total Frame"], ball["Image Width"], ball["Image Height"]) == (15, 384, 384)
    assert (ball["Color Bit"], ball["EffectiveBit Depth"]) == (12, 12)  # packed on disk


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (b"<cih><nothing/></cih>", r"bad\.cihx: unreadable header \(element <recordInfo/"),
        (b"\x00\x01 no xml here", r"bad\.cihx: unreadable header \(no <cih>"),
        (b"<cih><recordInfo></cih>", r"bad\.cihx: unreadable header \(malformed XML"),
    ],
)
def test_bad_cihx_is_named(tmp_path, text, message):
    (tmp_path / "bad.cihx").write_bytes(text)
    (tmp_path / "bad.mraw").write_bytes(b"\0" * 8)
    with pytest.raises(FootageError, match=message):
        open_footage(tmp_path / "bad.cihx")


def test_cihx_bad_number_and_cih_without_fields(tmp_path):
    samples = samples_or_skip()
    data = (samples / "beam.cihx").read_bytes().replace(
        b"<totalFrame>4</totalFrame>", b"<totalFrame>four</totalFrame>"
    )
    (tmp_path / "b.cihx").write_bytes(data)
    (tmp_path / "b.mraw").write_bytes(b"\0" * 8)
    with pytest.raises(FootageError, match=r"b\.cihx: .*<frameInfo/totalFrame> is 'four'"):
        open_footage(tmp_path / "b.mraw")
    (tmp_path / "t.cih").write_text("\nTotal Frame : 4\n")
    (tmp_path / "t.mraw").write_bytes(b"\0" * 8)
    with pytest.raises(FootageError, match=r"t\.cih: unreadable header \(no 'Key : Value'"):
        open_footage(tmp_path / "t.cih")
    (tmp_path / "t.cih").write_text("Total Frame : 4\n")
    with pytest.raises(FootageError, match=r"t\.cih: header lacks a usable value .*Image"):
        open_footage(tmp_path / "t.cih")


# --- Photron MRAW -----------------------------------------------------------------------


def test_mraw_beam_sample():
    samples = samples_or_skip()
    for name in ("beam.cihx", "beam.mraw"):
        frames, reader = read_all(samples / name)
        assert isinstance(reader, MrawReader)
        # README: 50000 fps, 4 frames, 1024 x 80, effective bit depth 12, largest value 4095
        assert len(reader) == 4
        assert reader.frame_shape == (80, 1024)
        assert reader.frame_rate == 50000.0
        assert reader.bit_depth == 12
        assert reader.dtype == np.uint16
        assert int(frames.max()) == 4095
        assert reader.lost_frames == ()
        assert_array_equal(reader.frame_numbers, np.arange(4))
        assert_frozen("beam.mraw", frames)


def test_mraw_12bit_packed_sample():
    samples = samples_or_skip()
    frames, reader = read_all(samples / "ball_12bit.cihx")
    # README: 30000 fps, 15 frames of 384 x 384, 12-bit packed, decoded largest value 4095
    assert len(reader) == 15
    assert reader.frame_shape == (384, 384)
    assert reader.frame_rate == 30000.0
    assert reader.bit_depth == 12
    assert reader.cih["Color Bit"] == 12  # packed on disk
    assert int(frames.max()) == 4095
    assert_frozen("ball_12bit.mraw", frames)


@pytest.mark.parametrize("bits", [8, 12, 16])
def test_mraw_written_by_hand(tmp_path, bits):
    top = {8: 255, 12: 4095, 16: 4095}[bits]
    rng = np.random.default_rng(1)
    frames = rng.integers(0, top, size=(5, 6, 10), endpoint=True)
    write_mraw(tmp_path / "hand", frames, bits=bits, effective=8 if bits == 8 else 12)
    with open_footage(tmp_path / "hand.cih") as reader:
        assert reader.frame_rate == 20000.0
        assert reader.bit_depth == (8 if bits == 8 else 12)
        assert_array_equal(np.stack(list(reader)), frames)


def test_mraw_high_aligned_bits_are_shifted_down(tmp_path):
    frames = np.arange(2 * 4 * 6).reshape(2, 4, 6) * 50
    write_mraw(tmp_path / "hi", frames << 4, bits=16, side="Higher", effective=12)
    with open_footage(tmp_path / "hi.mraw") as reader:
        assert_array_equal(reader.get_frame(1), frames[1])


@pytest.mark.parametrize("bits", [8, 12, 16])
def test_mraw_cut_short_reads_the_whole_frames(tmp_path, bits, caplog):
    rng = np.random.default_rng(2)
    frames = rng.integers(0, 255 if bits == 8 else 4095, size=(6, 4, 10), endpoint=True)
    write_mraw(tmp_path / "cut", frames, bits=bits)
    raw = tmp_path / "cut.mraw"
    frame_bytes = 4 * 10 * bits // 8
    raw.write_bytes(raw.read_bytes()[: 2 * frame_bytes + frame_bytes // 2])  # 2.5 frames
    with caplog.at_level(logging.WARNING, logger="tir_contact.io"):
        reader = open_footage(raw)
    with reader:
        assert len(reader) == 2
        assert reader.lost_frames == (2, 3, 4, 5)
        assert_array_equal(reader.frame_numbers, [0, 1])
        assert_array_equal(np.stack(list(reader)), frames[:2])
        with pytest.raises(IndexError):
            reader.get_frame(2)
    (record,) = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert str(raw) in record.getMessage()
    assert "4 frames lost (frames 2-5)" in record.getMessage()


@pytest.mark.parametrize(("name", "n", "frame_bytes"), [
    ("beam.mraw", 4, 1024 * 80 * 2),
    ("ball_12bit.mraw", 15, 384 * 384 * 3 // 2),
])
def test_mraw_sample_cut_short(tmp_path, name, n, frame_bytes, caplog):
    full, _ = read_all(samples_or_skip() / name)
    for keep_frames in (n - 1, 1):
        cut = cut_copy(tmp_path, name, keep_frames * frame_bytes + 7)  # and a part frame
        with caplog.at_level(logging.WARNING, logger="tir_contact.io"):
            frames, reader = read_all(cut)
        assert len(reader) == keep_frames
        assert reader.lost_frames == tuple(range(keep_frames, n))
        assert_array_equal(frames, full[:keep_frames])
        assert f"{n - keep_frames} frames lost" in caplog.text
    cut = cut_copy(tmp_path, name, frame_bytes - 1)
    with pytest.raises(FootageError, match=rf"{name}: truncated: {frame_bytes - 1} bytes, not"):
        open_footage(cut)


def test_mraw_missing_parts(tmp_path):
    (tmp_path / "lonely.mraw").write_bytes(b"\0" * 8)
    with pytest.raises(FootageError, match=r"lonely\.mraw: no \.cihx or \.cih header"):
        open_footage(tmp_path / "lonely.mraw")
    (tmp_path / "alone.cih").write_text("Total Frame : 1\n")
    with pytest.raises(FootageError, match=r"alone\.cih: no \.mraw data file"):
        open_footage(tmp_path / "alone.cih")


# --- Phantom CINE ---------------------------------------------------------------------------


def test_cine_781_sample():
    frames, reader = read_all(samples_or_skip() / "cine_781.cine")
    assert isinstance(reader, CineReader)
    # README: 15 images of 256 x 256 at 90000 fps, 12-bit
    assert len(reader) == 15
    assert reader.frame_shape == (256, 256)
    assert reader.frame_rate == 90000.0
    assert reader.bit_depth == 12
    assert int(frames.max()) <= 4095
    assert reader.header.image_count == 15
    assert reader.lost_frames == ()
    assert_frozen("cine_781.cine", frames)


def test_cine_legacy_sample():
    frames, reader = read_all(samples_or_skip() / "cine_legacy.cine")
    # README: 97 images of 128 x 128; frame rate and depth as the previous implementation
    # read them from the setup (FrameRate 35087, RealBPP 14)
    assert len(reader) == 97
    assert reader.frame_shape == (128, 128)
    assert reader.frame_rate == 35087.0
    assert reader.bit_depth == 14
    assert_frozen("cine_legacy.cine", frames)


@pytest.mark.parametrize(
    ("dtype", "colour"),
    [(np.uint8, False), (np.uint16, False), (np.uint8, True), (np.uint16, True)],
)
def test_cine_written_by_hand(tmp_path, dtype, colour):
    frames = make_frames(4, dtype=dtype, colour=colour)
    write_cine(tmp_path / "hand.cine", frames, fps=4000, annotation=24)
    expected = luma(frames) if colour else frames
    with open_footage(tmp_path / "hand.cine") as reader:
        assert reader.frame_rate == 4000.0
        assert reader.bit_depth == 8 * np.dtype(dtype).itemsize
        assert reader.header.first_image_no == -3
        assert_array_equal(reader.frame_numbers, np.arange(4))  # 0-based, in file order
        assert_array_equal(np.stack(list(reader)), expected)  # row 0 is the top


def test_cine_real_bpp_and_old_setup(tmp_path):
    frames = make_frames(2, dtype=np.uint16)
    write_cine(tmp_path / "a.cine", frames, fps=90000, real_bpp=12)
    with open_footage(tmp_path / "a.cine") as reader:
        assert (reader.bit_depth, reader.frame_rate) == (12, 90000.0)
    # a setup of 600 bytes predates FrameRate and RealBPP: FrameRate16, storage depth
    write_cine(tmp_path / "b.cine", frames, fps=2500, setup_length=600)
    with open_footage(tmp_path / "b.cine") as reader:
        assert (reader.bit_depth, reader.frame_rate) == (16, 2500.0)
        assert reader.header.real_bpp is None
        assert_array_equal(reader.get_frame(1), frames[1])


def test_cine_cut_short_reads_the_intact_images(tmp_path, caplog):
    frames = make_frames(5, dtype=np.uint16)
    path = tmp_path / "cut.cine"
    offsets = write_cine(path, frames)
    data = path.read_bytes()
    path.write_bytes(data[: offsets[3] + 8 + 100])  # image 3 cut in its pixels, 4 gone
    with caplog.at_level(logging.WARNING, logger="tir_contact.io"):
        reader = open_footage(path)
    with reader:
        assert len(reader) == 3
        assert reader.lost_frames == (3, 4)
        assert_array_equal(reader.frame_numbers, [0, 1, 2])
        assert_array_equal(np.stack(list(reader)), frames[:3])
    assert str(path) in caplog.text
    assert "2 of the header's 5 images lost (frames 3-4)" in caplog.text
    assert "truncated file (100 of 1536 bytes)" in caplog.text
    path.write_bytes(data[: offsets[0] + 8 + 10])  # not one intact image
    with pytest.raises(FootageError, match=r"cut\.cine \(frame 0\): truncated file"):
        open_footage(path)


def test_cine_corrupt_image_in_the_middle_is_lost(tmp_path):
    frames = make_frames(4, dtype=np.uint8)
    path = tmp_path / "mid.cine"
    offsets = write_cine(path, frames)
    data = bytearray(path.read_bytes())
    struct.pack_into("<I", data, offsets[1] + 4, 999)  # ImageSize of image 1 is wrong
    path.write_bytes(bytes(data))
    with open_footage(path) as reader:
        assert reader.lost_frames == (1,)
        assert_array_equal(reader.frame_numbers, [0, 2, 3])
        assert_array_equal(np.stack(list(reader)), frames[[0, 2, 3]])


@pytest.mark.parametrize(("name", "n", "cut_image"), [
    ("cine_781.cine", 15, 12),
    ("cine_legacy.cine", 97, 40),
])
def test_cine_sample_cut_short(tmp_path, name, n, cut_image, caplog):
    full, reader = read_all(samples_or_skip() / name)
    offset = int(reader.header.image_offsets[cut_image])
    cut = cut_copy(tmp_path, name, offset + 300)  # into image `cut_image`
    with caplog.at_level(logging.WARNING, logger="tir_contact.io"):
        frames, reader = read_all(cut)
    assert len(reader) == cut_image
    assert reader.lost_frames == tuple(range(cut_image, n))
    assert_array_equal(frames, full[:cut_image])
    assert f"{n - cut_image} of the header's {n} images lost" in caplog.text


def test_cine_foreign_and_broken_headers(tmp_path):
    path = tmp_path / "x.cine"
    path.write_bytes(b"XX" + b"\0" * 100)
    with pytest.raises(FootageError, match=r"x\.cine: not a Phantom CINE file"):
        open_footage(path)
    write_cine(path, make_frames(2))
    data = bytearray(path.read_bytes())
    struct.pack_into("<I", data, 20, 0)  # ImageCount
    path.write_bytes(bytes(data))
    with pytest.raises(FootageError, match=r"x\.cine: CINE file holds no images"):
        open_footage(path)
    struct.pack_into("<I", data, 20, 10**8)  # offsets table far past the end
    path.write_bytes(bytes(data))
    with pytest.raises(FootageError, match=r"x\.cine: truncated or corrupt CINE header"):
        open_footage(path)
    struct.pack_into("<I", data, 20, 2)
    struct.pack_into("<H", data, 4, 1)  # Compression: JPEG
    path.write_bytes(bytes(data))
    with pytest.raises(FootageError, match=r"x\.cine: JPEG-compressed CINE files"):
        open_footage(path)
    struct.pack_into("<H", data, 4, 0)
    struct.pack_into("<I", data, 44 + 16, 1024)  # biCompression: packed 12-bit
    path.write_bytes(bytes(data))
    with pytest.raises(FootageError, match=r"x\.cine: packed pixel data \(biCompression 1024"):
        open_footage(path)


# --- a camera file that is not TIR footage -------------------------------------------------


def test_a_field_that_is_not_tir_says_no_contact_can_be_told_apart():
    # beam.mraw films a bright beam, not a prism's lit zone: its "free surface" reads
    # darker than full contact itself (a reach near 2.9 against an assumed 0.97). The
    # analysis says so; before it said resolved contact "is counted above 2.934 only"
    # (helper-10), a darkness no contact has
    from tir_contact import analyze_video

    result = analyze_video(samples_or_skip() / "beam.cihx",
                           overrides={"mm_per_px": 0.05, "sliding_direction": "right"})
    note = next(w for w in result.summary["warnings"] if "do not separate" in w)
    assert "beyond the darkness of full contact itself" in note
    assert "no contact can be told from the free surface" in note
    assert "counted above" not in note
    # no contact is the truth: the bar reaches it in every frame, and the warning that no
    # contact is found says the areas are the darkness unmixed alone (before, the 58-60 mm2
    # stood beside "no contact found" without a word)
    assert (result.frames["contact_area_low_mm2"] == 0.0).all()
    found = next(w for w in result.summary["warnings"] if "no contact found" in w)
    assert "contact_area_mm2 is the darkness unmixed alone" in found
