"""Private helpers of the footage readers in :mod:`tir_contact.io`.

Natural sorting of frame files, decoding one image file, colour to grey conversion, unpacking
12-bit packed Photron data and message helpers. Nothing here is public API;
:mod:`tir_contact.io` re-exports :class:`FootageError`. The camera file layouts live in
:mod:`tir_contact._cih` (Photron headers) and :mod:`tir_contact._cine` (Phantom CINE).
"""

from __future__ import annotations

import io
import logging
import os
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np
import tifffile

logger = logging.getLogger(__name__)

__all__ = [
    "COMPANION_NAMES",
    "COMPANION_SUFFIXES",
    "IMAGE_SUFFIXES",
    "FootageError",
    "check_pixels",
    "decode_image_file",
    "is_image_name",
    "one_line",
    "ranges_text",
    "size_text",
    "tiff_page_to_yxs",
    "to_grey",
    "unpack_12bit",
]

#: Suffixes (lower case) of the single-image files a frame folder may hold.
IMAGE_SUFFIXES: tuple[str, ...] = (".tif", ".tiff", ".png", ".bmp", ".jpg", ".jpeg")


def is_image_name(name: str) -> bool:
    """True for the file name of a frame a folder may hold: an image suffix
    (:data:`IMAGE_SUFFIXES`, any case), not hidden (a leading dot: ``._frame.png`` is
    macOS's resource fork, not a frame).

    Examples
    --------
    >>> is_image_name("frame_000001.PNG"), is_image_name("._frame.png"), is_image_name("a.csv")
    (True, False, False)
    """
    return os.path.splitext(name)[1].lower() in IMAGE_SUFFIXES and not name.startswith(".")

#: Suffixes (lower case) of files expected beside frames (metadata, ground truth, notes):
#: skipped by the frame-folder reader, logged at DEBUG level.
COMPANION_SUFFIXES: tuple[str, ...] = (
    ".json",
    ".csv",
    ".txt",
    ".md",
    ".yaml",
    ".yml",
    ".toml",
    ".ini",
    ".cfg",
    ".log",
)

#: File names (lower case) skipped in frame folders: thumbnail caches of file browsers.
COMPANION_NAMES: tuple[str, ...] = ("thumbs.db", "desktop.ini")

#: ITU-R BT.601 luma weights for red, green and blue, in thousandths (exact integer maths).
_LUMA_RGB_PERMILLE = np.array([299, 587, 114], dtype=np.int64)



class FootageError(ValueError):
    """Footage or its metadata cannot be read.

    The message is one line: the file (or folder) first, then what is wrong with it,
    e.g. ``"frames/f0007.png: truncated or corrupt image"``.

    Parameters
    ----------
    message : str
        The one-line message.
    path : str or os.PathLike, optional
        The file the message is about, kept as :attr:`path`.
    """

    def __init__(self, message: str, path: str | os.PathLike[str] | None = None) -> None:
        super().__init__(message)
        self.path = None if path is None else Path(path)


def size_text(shape: tuple[int, ...]) -> str:
    """Frame size as ``"W x H px"`` (width first, like camera headers)."""
    return f"{shape[1]} x {shape[0]} px"


def to_grey(image: np.ndarray, *, order: str) -> np.ndarray:
    """Convert a colour image to grey with the ITU-R BT.601 luma rule, keeping the dtype.

    ``Y = 0.299 R + 0.587 G + 0.114 B``, computed exactly in integers as
    ``(299 R + 587 G + 114 B + 500) // 1000`` (nearest integer, halves rounded up); the
    weights sum to 1, so Y stays in the range of the dtype. An alpha channel is dropped; a
    grey + alpha image keeps its grey channel; a grey image is returned unchanged.

    Parameters
    ----------
    image : (H, W) or (H, W, C) ndarray
        Grey (C = 1 or 2 with alpha) or colour (C = 3 or 4 with alpha) pixels.
    order : {"rgb", "bgr"}
        Channel order of a colour image (OpenCV decodes to BGR, tifffile to RGB).

    Returns
    -------
    (H, W) ndarray
        Grey image, same dtype as `image`.
    """
    if image.ndim == 2:
        return image
    if image.ndim != 3:
        raise ValueError(f"image must be 2-D or 3-D, got {image.ndim=}")
    channels = image.shape[2]
    if channels in (1, 2):
        return np.ascontiguousarray(image[:, :, 0])
    if channels not in (3, 4):
        raise ValueError(f"image must have 1 to 4 channels, got {channels=}")
    weights = _LUMA_RGB_PERMILLE if order == "rgb" else _LUMA_RGB_PERMILLE[::-1]
    luma = (image[:, :, :3].astype(np.int64) @ weights + 500) // 1000
    return luma.astype(image.dtype)


def check_pixels(image: np.ndarray, name: str) -> None:
    """Raise :class:`FootageError` unless `image` holds 8- or 16-bit unsigned pixels.

    Parameters
    ----------
    image : ndarray
        Decoded pixels.
    name : str
        The file (and frame) the pixels came from, for the message.
    """
    if image.dtype not in (np.uint8, np.uint16):
        raise FootageError(
            f"{name}: pixel type {image.dtype} is not supported "
            "(8- or 16-bit unsigned integers expected)"
        )
    if image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] > 4):
        raise FootageError(
            f"{name}: image of shape {image.shape} is neither grey (H, W) nor colour (H, W, C<=4)"
        )


def _jpeg_complete(data: bytes) -> bool:
    """True when JPEG bytes end with the end-of-image marker (padding allowed)."""
    return data.rstrip(b"\x00\n\r ")[-2:] == b"\xff\xd9"


def _png_complete(data: bytes) -> bool:
    """True when PNG bytes hold the IEND chunk near the end."""
    return b"IEND" in data[-32:]


def decode_image_file(path: Path) -> np.ndarray:
    """Read one image file into a grey frame.

    TIFF files are decoded with tifffile (first page), the other formats with OpenCV from the
    file's bytes. Colour is converted with :func:`to_grey`.

    Parameters
    ----------
    path : Path
        A ``.tif``, ``.tiff``, ``.png``, ``.bmp``, ``.jpg`` or ``.jpeg`` file.

    Returns
    -------
    (H, W) ndarray of uint8 or uint16
        The grey frame.

    Raises
    ------
    FootageError
        When the file is unreadable, truncated, corrupt or of an unsupported pixel type.
    """
    suffix = path.suffix.lower()
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise FootageError(f"{path}: cannot be read ({exc.strerror or exc})", path) from exc
    if not data:
        raise FootageError(f"{path}: empty file (0 bytes)", path)
    if suffix in (".tif", ".tiff"):
        image = _decode_tiff_bytes(data, path)
        order = "rgb"
    else:
        if suffix in (".jpg", ".jpeg") and not _jpeg_complete(data):
            raise FootageError(
                f"{path}: truncated or corrupt image (JPEG end marker missing)", path
            )
        if suffix == ".png" and not _png_complete(data):
            raise FootageError(f"{path}: truncated or corrupt image (PNG end chunk missing)", path)
        image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), cv2.IMREAD_UNCHANGED)
        if image is None:
            raise FootageError(
                f"{path}: truncated or corrupt image (OpenCV cannot decode it)", path
            )
        order = "bgr"
    check_pixels(image, str(path))
    return to_grey(image, order=order)


def _decode_tiff_bytes(data: bytes, path: Path) -> np.ndarray:
    """Decode the first page of a TIFF held in memory; see :func:`decode_image_file`."""
    try:
        with tifffile.TiffFile(io.BytesIO(data)) as tif:
            n_pages = len(tif.pages)
            if n_pages == 0:
                raise FootageError(f"{path}: truncated or corrupt image (TIFF has no page)", path)
            if n_pages > 1:
                raise FootageError(
                    f"{path}: TIFF holds {n_pages} pages, a frame folder needs one image per "
                    "file: open the TIFF itself as a multi-page stack (or its folder with "
                    "--recursive: each stack a video)",
                    path,
                )
            page = tif.pages.first
            image = page.asarray()
            axes = page.axes
    except FootageError:
        raise
    except Exception as exc:
        raise FootageError(f"{path}: truncated or corrupt image ({one_line(exc)})", path) from exc
    return tiff_page_to_yxs(image, axes)


def tiff_page_to_yxs(image: np.ndarray, axes: str) -> np.ndarray:
    """Put the samples axis of a TIFF page last (planar RGB ``SYX`` becomes ``YXS``)."""
    if image.ndim == 3 and axes.startswith("S"):
        return np.moveaxis(image, 0, -1)
    return image


def one_line(exc: BaseException | str, limit: int | None = 200) -> str:
    """An exception's text (or a text) as one line of at most `limit` characters.

    An exception without text gives its type name.

    Examples
    --------
    >>> one_line(ValueError("a\\n  b")), one_line(KeyError()), one_line("x " * 200, limit=5)
    ('a b', 'KeyError', 'x x x')
    """
    text = " ".join(str(exc).split())
    if not text and isinstance(exc, BaseException):
        return type(exc).__name__
    return text if limit is None else text[:limit]


def unpack_12bit(packed: np.ndarray, count: int) -> np.ndarray:
    """Unpack 12-bit packed pixels (two pixels in three bytes, big-endian nibbles).

    Byte layout of Photron MRAW 12-bit files: ``AAAAAAAA AAAABBBB BBBBBBBB`` gives pixel
    ``A`` (first 12 bits) and pixel ``B`` (last 12 bits).

    Parameters
    ----------
    packed : (3 * count // 2,) ndarray of uint8
        The packed bytes.
    count : int
        Number of pixels, even.

    Returns
    -------
    (count,) ndarray of uint16
        Pixel values 0 to 4095.
    """
    if count % 2 or packed.size != count * 3 // 2:
        raise ValueError(f"12-bit data needs 3 bytes per 2 pixels, got {packed.size=}, {count=}")
    triples = packed.reshape(-1, 3).astype(np.uint16)
    out = np.empty(count, dtype=np.uint16)
    out[0::2] = (triples[:, 0] << 4) | (triples[:, 1] >> 4)
    out[1::2] = ((triples[:, 1] & 0x0F) << 8) | triples[:, 2]
    return out


def ranges_text(numbers: Sequence[int]) -> str:
    """Increasing integers as compact ranges, for messages.

    Examples
    --------
    >>> ranges_text([2, 3, 4, 9, 11, 12])
    '2-4, 9, 11-12'
    """
    parts: list[str] = []
    if not numbers:
        return ""
    start = prev = numbers[0]
    for k in [*numbers[1:], None]:
        if k is not None and k == prev + 1:
            prev = k
            continue
        parts.append(str(start) if start == prev else f"{start}-{prev}")
        if k is not None:
            start = prev = k
    return ", ".join(parts)
