"""Streaming footage readers: frame folders, TIFF stacks, videos, Photron MRAW, Phantom CINE.

Every reader gives grey frames one at a time and never holds the whole footage in memory::

    with open_footage("run_07/frames") as reader:
        meta = load_meta("run_07/frames", {"mm_per_px": 0.05}, frame_rate=reader.frame_rate)
        for index, frame in enumerate(reader):
            ...

The interface follows pims and pyidi: ``len(reader)``, ``reader.get_frame(i)``,
``reader.frame_shape``, ``reader.frame_rate``, iteration, ``close()`` and ``with``.
:func:`open_footage` picks the reader by file type; when none fits, its
:class:`FootageError` lists every reader's reason.

Notes
-----
Frames are ``(H, W)`` arrays, row 0 at the top, column 0 at the left, of dtype uint8 or
uint16 as stored (12-bit camera data in uint16, values 0 to 4095; see ``bit_depth``). Colour
is converted to grey with the ITU-R BT.601 luma rule ``Y = 0.299 R + 0.587 G + 0.114 B``,
rounded, in the stored bit depth. ``frame_rate`` is in Hz (frames per second).
"""

from __future__ import annotations

import abc
import contextlib
import inspect
import logging
import os
import re
from collections.abc import Iterator, Sequence
from pathlib import Path
from types import TracebackType
from typing import Any, ClassVar, Self

import cv2
import numpy as np
import tifffile

from tir_common.naming import natural_key
from tir_contact._cih import CihFormatError, read_cih
from tir_contact._cine import CineFormatError, ImageRecord, read_cine_header, scan_images
from tir_contact._readers import (
    COMPANION_NAMES,
    COMPANION_SUFFIXES,
    IMAGE_SUFFIXES,
    FootageError,
    check_pixels,
    decode_image_file,
    is_image_name,
    one_line,
    ranges_text,
    size_text,
    tiff_page_to_yxs,
    to_grey,
    unpack_12bit,
)
from tir_contact.meta import META_FILENAME, clip_footage, load_meta

logger = logging.getLogger(__name__)

__all__ = [
    "READERS",
    "VIDEO_SUFFIXES",
    "ArrayReader",
    "CineReader",
    "FootageError",
    "FootageReader",
    "FrameFolderReader",
    "ImageFileReader",
    "MrawReader",
    "MultiPageTiffReader",
    "VideoFileReader",
    "load_meta",
    "open_footage",
    "readers",
    "register_reader",
    "unregister_reader",
]

#: Suffixes (lower case) of video files read through OpenCV.
VIDEO_SUFFIXES: tuple[str, ...] = (".avi", ".mp4", ".mov", ".mkv")


class FootageReader(abc.ABC):
    """Random-access, streaming reader of grey frames: the interface every reader follows.

    A reader declares which footage it reads (:attr:`suffixes`, :attr:`reads_folders`, or
    its own :meth:`claims`), implements :meth:`_read` (one frame by index) and the public
    properties ``__len__``, :attr:`frame_shape`, :attr:`dtype` and :attr:`frame_rate`;
    :attr:`bit_depth`, :attr:`frame_numbers` and :attr:`lost_frames` have defaults (the
    storage bits, ``0, 1, 2, ...``, none) that a reader overrides when its footage knows
    better. :func:`register_reader` adds it to the readers :func:`open_footage` chooses
    from. Everything else (index checks, size and type checks of every frame, iteration,
    ``close`` and ``with``) is done here.

    Attributes
    ----------
    path : Path or None
        The footage (file or folder); None for in-memory frames.

    Examples
    --------
    A reader of ``.npy`` stacks is one class (registered, ``open_footage`` picks it by
    suffix)::

        @register_reader
        class NpyReader(FootageReader):
            kind = "npy"
            suffixes = (".npy",)

            def __init__(self, path):
                super().__init__(path)
                self._frames = np.load(path, mmap_mode="r")

            def __len__(self):
                return len(self._frames)

            frame_shape = property(lambda self: self._frames.shape[1:])
            dtype = property(lambda self: self._frames.dtype)
            frame_rate = property(lambda self: None)

            def _read(self, index):
                return np.array(self._frames[index])
    """

    #: Short name used in :func:`open_footage` (``kind=``) and in messages.
    kind: ClassVar[str] = ""
    #: File suffixes (lower case, with the dot) this reader reads; :meth:`claims` uses them.
    suffixes: ClassVar[tuple[str, ...]] = ()
    #: Whether this reader reads a folder (then :meth:`claims` takes every folder).
    reads_folders: ClassVar[bool] = False

    def __init__(self, path: str | os.PathLike[str] | None) -> None:
        self.path = None if path is None else Path(path)
        self._closed = False

    @classmethod
    def claims(cls, path: Path) -> bool:
        """Whether ``path`` is footage of this reader's type (by default: a folder for a
        folder reader, else the file suffix is one of :attr:`suffixes`)."""
        if cls.reads_folders:
            return path.is_dir()
        return path.suffix.lower() in cls.suffixes

    # --- interface -------------------------------------------------------------------------
    @abc.abstractmethod
    def __len__(self) -> int:
        """Number of frames."""

    @property
    @abc.abstractmethod
    def frame_shape(self) -> tuple[int, int]:
        """Shape ``(H, W)`` of every frame in pixels."""

    @property
    @abc.abstractmethod
    def dtype(self) -> np.dtype[Any]:
        """Pixel type of the frames: uint8 or uint16."""

    @property
    @abc.abstractmethod
    def frame_rate(self) -> float | None:
        """Frame rate in Hz from the footage header, or None when the footage has none."""

    @property
    def bit_depth(self) -> int:
        """Effective bits per pixel, e.g. 12 for 12-bit camera data held in uint16
        (default: the storage bits of :attr:`dtype`)."""
        return int(np.dtype(self.dtype).itemsize * 8)

    @property
    def frame_numbers(self) -> np.ndarray:
        """Recorded frame number of each readable frame, ``(len,)`` int64, increasing.

        ``0, 1, 2, ...`` unless the footage numbers its frames itself: a frame folder takes
        the number in each file name, so a missing file leaves a gap (``..., 9, 20, ...``)
        and the frame's time is ``frame_number / frame_rate``.
        """
        return np.arange(len(self), dtype=np.int64)

    @property
    def lost_frames(self) -> tuple[int, ...]:
        """Frame numbers the container claims but cannot deliver (cut short or corrupt).

        Empty for intact footage. The readable frames are still read; an analysis of footage
        with lost frames is reported as partial.
        """
        return ()

    @property
    def closed(self) -> bool:
        """True after :meth:`close`."""
        return self._closed

    def get_frame(self, i: int) -> np.ndarray:
        """Read one frame.

        Parameters
        ----------
        i : int
            Frame index, 0-based; negative counts from the end.

        Returns
        -------
        (H, W) ndarray of uint8 or uint16
            A new array the caller may modify.

        Raises
        ------
        IndexError
            When `i` is out of range.
        FootageError
            When the frame cannot be read (truncated, corrupt, another size than the first).
        """
        if self._closed:
            raise FootageError(f"{self._name()}: reader is closed", self.path)
        n = len(self)
        index = int(i)
        if index < 0:
            index += n
        if not 0 <= index < n:
            raise IndexError(f"frame index out of range: got {i}, footage has {n} frames")
        frame = self._read(index)
        shape = tuple(self.frame_shape)
        if frame.shape != shape:
            raise FootageError(
                f"{self._frame_name(index)}: frame size {size_text(frame.shape)} differs from "
                f"the first frame's {size_text(shape)}",
                self.path,
            )
        if frame.dtype != self.dtype:
            raise FootageError(
                f"{self._frame_name(index)}: pixel type {frame.dtype} differs from the first "
                f"frame's {self.dtype}",
                self.path,
            )
        return frame

    def __getitem__(self, i: int) -> np.ndarray:
        """Same as :meth:`get_frame` (integer indices only)."""
        if not isinstance(i, int | np.integer):
            raise TypeError(f"frame index must be an integer, got {type(i).__name__}")
        return self.get_frame(int(i))

    def __iter__(self) -> Iterator[np.ndarray]:
        """Yield the frames in order, one at a time."""
        for i in range(len(self)):
            yield self.get_frame(i)

    def close(self) -> None:
        """Release the file handles; further reads raise :class:`FootageError`."""
        if not getattr(self, "_closed", True):
            self._closed = True
            self._release()

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # pragma: no cover - interpreter shutdown
            pass

    def __repr__(self) -> str:
        try:
            rate = "unknown fps" if self.frame_rate is None else f"{self.frame_rate:g} fps"
            what = (f"{len(self)} frames, {size_text(self.frame_shape)}, {self.bit_depth}-bit, "
                    f"{rate}")
        except Exception:  # a reader that failed to open
            what = "not open"
        return f"<{type(self).__name__} {self._name()}: {what}>"

    # --- for subclasses -------------------------------------------------------------------
    @abc.abstractmethod
    def _read(self, index: int) -> np.ndarray:
        """Read frame `index` (0 <= index < len) as a grey array."""

    def _release(self) -> None:  # noqa: B027 - optional hook, nothing to release by default
        """Close files; called once by :meth:`close`."""

    def _name(self) -> str:
        return "<in-memory frames>" if self.path is None else str(self.path)

    def _frame_name(self, index: int) -> str:
        """How a frame is named in messages."""
        return f"{self._name()} (frame {index})"


class _StoredFormat(FootageReader):
    """Base of the built-in readers: the interface's properties from fields set on opening
    (``_length``, ``_frame_shape``, ``_dtype``, ``_frame_rate``, ``_bit_depth``, optionally
    ``_frame_numbers`` and ``_lost_frames``; :meth:`_set_format` records the first frame's)."""

    def __init__(self, path: str | os.PathLike[str] | None) -> None:
        super().__init__(path)
        self._length = 0
        self._frame_shape: tuple[int, int] = (0, 0)
        self._dtype = np.dtype(np.uint8)
        self._frame_rate: float | None = None
        self._bit_depth = 8
        self._frame_numbers: np.ndarray | None = None
        self._lost_frames: tuple[int, ...] = ()

    def __len__(self) -> int:
        """Number of frames."""
        return self._length

    @property
    def frame_shape(self) -> tuple[int, int]:
        """Shape ``(H, W)`` of every frame in pixels."""
        return self._frame_shape

    @property
    def dtype(self) -> np.dtype[Any]:
        """Pixel type of the frames: uint8 or uint16."""
        return self._dtype

    @property
    def frame_rate(self) -> float | None:
        """Frame rate in Hz from the footage header, or None when the footage has none."""
        return self._frame_rate

    @property
    def bit_depth(self) -> int:
        """Effective bits per pixel, e.g. 12 for 12-bit camera data held in uint16."""
        return self._bit_depth

    @property
    def frame_numbers(self) -> np.ndarray:
        """Recorded frame number of each readable frame (see :class:`FootageReader`)."""
        if self._frame_numbers is None:
            return np.arange(self._length, dtype=np.int64)
        return self._frame_numbers.copy()

    @property
    def lost_frames(self) -> tuple[int, ...]:
        """Frame numbers the container claims but cannot deliver (cut short or corrupt)."""
        return self._lost_frames

    def _set_format(self, first: np.ndarray, *, bit_depth: int | None = None) -> None:
        """Record shape and dtype from the first frame."""
        self._frame_shape = (int(first.shape[0]), int(first.shape[1]))
        self._dtype = first.dtype
        storage = first.dtype.itemsize * 8
        self._bit_depth = storage if bit_depth is None else int(min(max(bit_depth, 1), storage))


class ArrayReader(_StoredFormat):
    """Frames held in memory: a ``(N, H, W)`` or ``(N, H, W, C)`` array or a list of frames.

    For tests and for library users who already have the frames.

    Parameters
    ----------
    frames : ndarray or sequence of ndarray
        Grey ``(H, W)`` or colour ``(H, W, 3|4)`` RGB(A) frames of uint8 or uint16. An array is
        not copied; each :meth:`get_frame` returns a copy of one frame.
    frame_rate : float, optional
        Frame rate in Hz.
    bit_depth : int, optional
        Effective bits per pixel (default: 8 for uint8, 16 for uint16).
    path : str or os.PathLike, optional
        Name used in messages.

    Examples
    --------
    >>> import numpy as np
    >>> reader = ArrayReader(np.zeros((3, 4, 5), np.uint8), frame_rate=100.0)
    >>> len(reader), reader.frame_shape, reader.get_frame(-1).shape
    (3, (4, 5), (4, 5))
    """

    kind = "array"

    def __init__(
        self,
        frames: np.ndarray | Sequence[np.ndarray],
        *,
        frame_rate: float | None = None,
        bit_depth: int | None = None,
        path: str | os.PathLike[str] | None = None,
    ) -> None:
        super().__init__(path)
        self._frames = frames if isinstance(frames, np.ndarray) else list(frames)
        self._length = len(self._frames)
        if self._length == 0:
            raise FootageError(f"{self._name()}: no frames given", self.path)
        if frame_rate is not None and not frame_rate > 0:
            raise ValueError(f"frame_rate must be > 0 Hz, got {frame_rate=}")
        self._frame_rate = None if frame_rate is None else float(frame_rate)
        self._set_format(self._read(0), bit_depth=bit_depth)

    def _read(self, index: int) -> np.ndarray:
        image = np.asarray(self._frames[index])
        check_pixels(image, self._frame_name(index))
        return np.array(to_grey(image, order="rgb"), copy=True)


class FrameFolderReader(_StoredFormat):
    """A folder of single-image files, one frame per file, in natural order.

    Parameters
    ----------
    path : str or os.PathLike
        The folder.

    Notes
    -----
    Frames are the ``.tif``, ``.tiff``, ``.png``, ``.bmp``, ``.jpg`` and ``.jpeg`` files
    (any case), sorted naturally (``f2`` before ``f10``). Hidden files (name starting with
    ``.``), sub-folders, files expected beside frames (``.json``, ``.csv``, ``.txt``,
    ``.md``, ``.yaml``, ``.yml``, ``.toml``, ``.ini``, ``.cfg``, ``.log``, ``Thumbs.db``,
    ``desktop.ini``) are skipped (logged at DEBUG level); any other file is an error naming
    it. Files are decoded when read: a truncated or corrupt file, or a frame of another
    size or bit depth than the first, is an error naming that file. TIFF frames are read
    with tifffile (first page), the rest with OpenCV. The frame rate is unknown (None):
    ``meta.json`` gives it.

    Frame numbers (:attr:`frame_numbers`) are the last number in each file name
    (``frame_000020.png`` is frame 20), so a missing file leaves a gap in the numbers and
    does not shift the later frames' times. When the names carry no such number, or two
    files share one, frames are numbered by position (a warning says so).
    """

    kind = "folder"
    reads_folders = True

    def __init__(self, path: str | os.PathLike[str]) -> None:
        super().__init__(path)
        folder = Path(path)
        if not folder.is_dir():
            raise FootageError(f"{folder}: not a folder", folder)
        files: list[Path] = []
        skipped: list[str] = []
        subfolders: list[str] = []
        with os.scandir(folder) as entries:
            for entry in entries:
                name = entry.name
                if name.startswith("."):
                    continue
                if entry.is_dir():
                    subfolders.append(name)
                    continue
                suffix = os.path.splitext(name)[1].lower()
                if suffix in IMAGE_SUFFIXES:
                    files.append(Path(entry.path))
                elif suffix in COMPANION_SUFFIXES or name.lower() in COMPANION_NAMES:
                    skipped.append(name)
                else:
                    raise FootageError(
                        f"{Path(entry.path)}: not an image file among the frames (frames are "
                        f"{', '.join(IMAGE_SUFFIXES)}; only {', '.join(COMPANION_SUFFIXES)} "
                        "files may lie beside them): move it out of the folder",
                        entry.path,
                    )
        if skipped:
            logger.debug("%s: skipped %d non-frame files: %s", folder, len(skipped), skipped)
        if not files:
            extra = f" (only {', '.join(sorted(skipped))})" if skipped else ""
            raise FootageError(
                f"{folder}: no image files ({', '.join(IMAGE_SUFFIXES)}) in the folder{extra}"
                + _subfolder_hint(folder, subfolders),
                folder,
            )
        files.sort(key=lambda p: natural_key(p.name))
        self._files = files
        self._length = len(files)
        self._frame_numbers = _file_numbers(files)
        first = decode_image_file(files[0])
        self._set_format(first)

    @property
    def files(self) -> list[Path]:
        """The frame files in reading order."""
        return list(self._files)

    def _read(self, index: int) -> np.ndarray:
        return decode_image_file(self._files[index])

    def _frame_name(self, index: int) -> str:
        return f"{self._files[index]} (frame {index})"


def _subfolder_hint(folder: Path, subfolders: Sequence[str]) -> str:
    """A hint naming the sub-folders of `folder` that hold frames, for the message of a
    frame folder without images (a clip folder whose ``meta.json`` lacks ``frame_pattern``)."""
    with_frames = []
    example = ""  # the first frame file of the first such sub-folder
    for name in sorted(subfolders, key=natural_key):
        try:
            with os.scandir(folder / name) as entries:
                images = sorted((e.name for e in entries if is_image_name(e.name)),
                                key=natural_key)
        except OSError:
            continue
        if images:
            with_frames.append(name)
            example = example or images[0]
    if not with_frames:
        return ""
    first = with_frames[0]
    where = (f"sub-folder{'s' if len(with_frames) > 1 else ''} "
             f"{', '.join(with_frames)}")
    if (folder / META_FILENAME).is_file():
        return (f"; the frames may be in its {where}: for {folder / META_FILENAME} to name "
                f"them, add \"frame_pattern\": \"{first}/{_pattern_of(example)}\" to it")
    return f"; the frames may be in its {where}: give {folder / first}, or use --recursive"


_LAST_NUMBER = re.compile(r"(\d+)(?!.*\d)")


def _pattern_of(name: str) -> str:
    """A ``frame_pattern`` file part for frame files named like `name`: its last number
    as the ``{frame}`` field (``frame_000010.png`` -> ``frame_{frame:06d}.png``)."""
    match = _LAST_NUMBER.search(name)
    if match is None:
        return "<file name with {frame}>"
    width = len(match.group(1))
    field = f"{{frame:0{width}d}}" if width > 1 else "{frame}"
    return name[:match.start()] + field + name[match.end():]


def _file_numbers(files: Sequence[Path]) -> np.ndarray | None:
    """The last number in each file's stem, when they increase strictly; else None."""
    numbers = []
    for f in files:
        match = _LAST_NUMBER.search(f.stem)
        if match is None:
            if len(files) > 1:
                logger.warning("%s: no frame number in the name; frames numbered by position",
                               f)
            return None
        numbers.append(int(match.group(1)))
    out = np.array(numbers, dtype=np.int64)
    if len(out) > 1 and not np.all(np.diff(out) > 0):
        logger.warning("%s: frame numbers in the file names repeat or do not increase in "
                       "name order; frames numbered by position", files[0].parent)
        return None
    return out


class MultiPageTiffReader(_StoredFormat):
    """A TIFF file holding one frame per page (a single-page TIFF is a 1-frame video).

    Parameters
    ----------
    path : str or os.PathLike
        The ``.tif`` or ``.tiff`` file.

    Notes
    -----
    When the pages form one uncompressed, contiguous series (as ``tifffile.imwrite`` writes
    a stack) each frame is one positioned read of its bytes (no memory map, so the memory
    used does not grow with the frames read); otherwise each page is decoded when read. The frame
    rate comes from ImageJ metadata (``fps`` or ``finterval``) when present, else None.
    ``bit_depth`` is the TIFF ``BitsPerSample``. Colour pages (RGB) are converted to grey.
    """

    kind = "tiff"
    suffixes = (".tif", ".tiff")

    def __init__(self, path: str | os.PathLike[str]) -> None:
        super().__init__(path)
        file = Path(path)
        if not file.is_file():
            raise FootageError(f"{file}: not a file", file)
        with _quiet_tifffile():  # its complaints become our one warning, naming the frames
            try:
                self._tif = tifffile.TiffFile(file)
            except Exception as exc:
                raise FootageError(
                    f"{file}: not a readable TIFF file ({one_line(exc)})", file
                ) from exc
            try:
                self._open()
            except BaseException:
                self._tif.close()
                raise

    def _open(self) -> None:
        tif = self._tif
        file = self.path
        pages = tif.pages
        n_pages = len(pages)
        if n_pages == 0:
            raise FootageError(f"{file}: TIFF file holds no page (truncated?)", file)
        first_page = pages.first
        self._axes = first_page.axes
        shape = tuple(int(n) for n in first_page.shape)
        frame_px = int(np.prod(shape))
        claimed = _claimed_pages(tif, frame_px, n_pages)
        self._length = n_pages
        self._contiguous: tuple[int, int, np.dtype[Any], tuple[int, ...]] | None = None
        try:
            offset = _contiguous_offset(tif, first_page, frame_px, claimed)
            if offset is not None:
                dtype = np.dtype(first_page.dtype).newbyteorder(tif.byteorder)
                nbytes = frame_px * dtype.itemsize
                whole = (os.path.getsize(file) - offset) // nbytes
                self._length = int(min(claimed, whole))
                self._contiguous = (offset, nbytes, dtype, shape)
        except Exception as exc:
            logger.debug("%s: pages decoded one by one (%s)", file, one_line(exc))
        if self._contiguous is None:  # pages whose data run past the end are lost too
            size = os.path.getsize(file)
            while self._length > 0 and _page_end(pages[self._length - 1]) > size:
                self._length -= 1
        if self._length < 1:
            raise FootageError(
                f"{file}: cut short before the end of its first frame ({claimed} claimed)", file
            )
        if claimed > self._length:
            self._lost_frames = tuple(range(self._length, claimed))
            lost = self._lost_frames
            logger.warning("%s: cut short: %d of the %d frames it claims are intact; %s lost",
                           file, self._length, claimed,
                           f"frame {lost[0]} is" if len(lost) == 1
                           else f"frames {lost[0]}-{lost[-1]} are")
        if self._contiguous is not None:
            # one positioned read per frame: as fast as a memory map, but the pages read do
            # not stay resident, so memory does not grow with the length of the video
            self._fd = os.open(file, os.O_RDONLY | getattr(os, "O_BINARY", 0))
            logger.debug("%s: contiguous, %d pages read by offset", file, self._length)
        first = self._read(0)
        self._set_format(first, bit_depth=int(first_page.bitspersample))
        self._frame_rate = _imagej_rate(tif)

    def _read(self, index: int) -> np.ndarray:
        if self._contiguous is not None:
            offset, nbytes, dtype, shape = self._contiguous
            data = os.pread(self._fd, nbytes, offset + index * nbytes)
            if len(data) != nbytes:
                raise FootageError(
                    f"{self._frame_name(index)}: truncated page ({len(data)} of {nbytes} bytes)",
                    self.path,
                )
            image = np.frombuffer(data, dtype).reshape(shape).astype(dtype.newbyteorder("="))
            axes = self._axes
        else:
            try:
                page = self._tif.pages[index]
                image = page.asarray()
                axes = page.axes
            except Exception as exc:
                raise FootageError(
                    f"{self._frame_name(index)}: truncated or corrupt page ({one_line(exc)})",
                    self.path,
                ) from exc
        image = tiff_page_to_yxs(image, axes)
        check_pixels(image, self._frame_name(index))
        return to_grey(image, order="rgb")

    def _frame_name(self, index: int) -> str:
        return f"{self._name()} (page {index})"

    def _release(self) -> None:
        if self._contiguous is not None:
            os.close(self._fd)
            self._contiguous = None
        self._tif.close()


@contextlib.contextmanager
def _quiet_tifffile() -> Iterator[None]:
    """Turn tifffile's ERROR log lines about a damaged file into DEBUG lines meanwhile."""
    tiff_logger = logging.getLogger("tifffile")
    demote = _Demote()
    tiff_logger.addFilter(demote)
    try:
        yield
    finally:
        tiff_logger.removeFilter(demote)


class _Demote(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        logger.debug("tifffile: %s", record.getMessage())
        return False


def _page_end(page: Any) -> int:
    """File offset just past a page's pixel data."""
    ends = [int(o) + int(n) for o, n in zip(page.dataoffsets, page.databytecounts, strict=False)]
    return max(ends, default=0)


def _claimed_pages(tif: Any, frame_px: int, n_pages: int) -> int:
    """How many frames a TIFF says it holds: its pages, its series shape, or the shape
    tifffile or ImageJ wrote into its description (those survive a file cut short, when
    the page directories at the end of the file are lost)."""
    counts = [n_pages]
    try:
        counts.append(int(np.prod(tif.series[0].shape)) // frame_px)
    except Exception as exc:  # a damaged file: the pages still count
        logger.debug("no series shape (%s)", one_line(exc))
    for meta in tif.shaped_metadata or ():
        if isinstance(meta, dict) and isinstance(meta.get("shape"), list | tuple):
            counts.append(int(np.prod(meta["shape"])) // frame_px)
    imagej = tif.imagej_metadata or {}
    if isinstance(imagej.get("images"), int):
        counts.append(int(imagej["images"]))
    return max(counts)


def _contiguous_offset(tif: Any, first_page: Any, frame_px: int, claimed: int) -> int | None:
    """File offset of frame 0 when all frames lie uncompressed one after another, else None.

    A stack written by tifffile (one shaped series) or ImageJ is contiguous by design; a
    stack of other pages is contiguous when its single series says so.
    """
    if first_page.compression != 1 or first_page.is_tiled:
        return None
    series = tif.series[0]
    if len(tif.series) == 1 and series.dataoffset is not None:
        if int(np.prod(series.shape)) in (frame_px, claimed * frame_px):
            return int(series.dataoffset)
    if tif.is_imagej and first_page.dataoffsets:
        return int(first_page.dataoffsets[0])
    return None


def _imagej_rate(tif: Any) -> float | None:
    """Frame rate in Hz from ImageJ metadata, or None."""
    meta = getattr(tif, "imagej_metadata", None) or {}
    try:
        fps = float(meta.get("fps", 0) or 0)
        if fps > 0:
            return fps
        interval = float(meta.get("finterval", 0) or 0)
        if interval > 0:
            return 1.0 / interval
    except (TypeError, ValueError):
        return None
    return None


class VideoFileReader(_StoredFormat):
    """A video file decoded by OpenCV (``.avi``, ``.mp4``, ``.mov``, ``.mkv``).

    Parameters
    ----------
    path : str or os.PathLike
        The video file.

    Notes
    -----
    Sequential reading (iteration, or ``get_frame(i)`` right after ``i - 1``) decodes the
    next frame; other indices seek with ``CAP_PROP_POS_FRAMES``. The frame count in the
    container header is verified when opening: by reading the last frame, and by counting
    the frames when that fails or more frames follow; frames the header claims past the
    last one that decodes (a file cut short) are listed in :attr:`lost_frames`, and so is
    that last one, which may be cut as well (a decoder conceals the missing bytes of a
    truncated frame rather than fail on it). A video without frames is an error.
    Frames are 8-bit; colour (OpenCV decodes to BGR) is converted to grey.
    """

    kind = "video"
    suffixes = VIDEO_SUFFIXES

    def __init__(self, path: str | os.PathLike[str]) -> None:
        super().__init__(path)
        file = Path(path)
        if not file.is_file():
            raise FootageError(f"{file}: not a file", file)
        self._cap = cv2.VideoCapture(str(file))
        if not self._cap.isOpened():
            self._cap.release()
            raise FootageError(
                f"{file}: OpenCV cannot open it as a video (corrupt file or unknown codec)", file
            )
        try:
            self._open()
        except BaseException:
            self._cap.release()
            raise

    def _open(self) -> None:
        cap = self._cap
        file = self.path
        self._next = 0
        ok, first = cap.read()
        if not ok or first is None:
            raise FootageError(f"{file}: video holds no frames", file)
        self._next = 1
        self._set_format(self._to_grey(first, 0))
        fps = cap.get(cv2.CAP_PROP_FPS)
        self._frame_rate = float(fps) if fps and np.isfinite(fps) and fps > 0 else None
        claimed = int(cap.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
        self._length = self._verified_count(claimed)
        if claimed < 1:  # no count in the header (OpenCV gives 0 or INT64_MIN): none lost
            claimed = self._length
        if 1 < self._length < claimed:
            # cut short: the frames past the last decodable are lost, and so is the last
            # one that decodes, which may be cut too: a decoder conceals a frame's missing
            # bytes (OpenCV 4.8's FFmpeg returns a truncated FFV1 frame 19 % wrong)
            self._length -= 1
        if self._length < claimed:
            self._lost_frames = tuple(range(self._length, claimed))
        if self._length != claimed:
            logger.warning("%s: header says %d frames, %d can be read", file, claimed, self._length)

    def _verified_count(self, claimed: int) -> int:
        """Frame count checked against the decoder, see the class notes."""
        if claimed >= 1 and self._seek_read(claimed - 1) is not None:
            count = claimed  # the header is right so far; count any frames after it
        else:
            self._rewind()
            count = 0
        while self._cap.grab():
            count += 1
        self._rewind()
        return max(count, 1)

    def _rewind(self) -> None:
        cap = self._cap
        cap.set(cv2.CAP_PROP_POS_FRAMES, 0)
        self._next = 0

    def _seek_read(self, index: int) -> np.ndarray | None:
        if index != self._next:
            self._cap.set(cv2.CAP_PROP_POS_FRAMES, index)
        ok, image = self._cap.read()
        if not ok or image is None:
            self._next = -1
            return None
        self._next = index + 1
        return image

    def _to_grey(self, image: np.ndarray, index: int) -> np.ndarray:
        check_pixels(image, self._frame_name(index))
        return to_grey(image, order="bgr")

    def _read(self, index: int) -> np.ndarray:
        image = self._seek_read(index)
        if image is None:
            raise FootageError(
                f"{self._frame_name(index)}: OpenCV cannot decode this frame (truncated or "
                "corrupt video)",
                self.path,
            )
        return self._to_grey(image, index)

    def _release(self) -> None:
        self._cap.release()


class MrawReader(_StoredFormat):
    """Photron MRAW footage: ``.mraw`` data with its ``.cihx`` or ``.cih`` header.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.mraw``, ``.cihx`` or ``.cih`` file; the other one has the same name beside it
        (``.cihx`` is preferred to ``.cih``).

    Attributes
    ----------
    cih : dict
        The header's fields keyed by their ``.cih`` names (``"Record Rate(fps)"``,
        ``"Total Frame"``, ``"Color Bit"``, ...), also for a ``.cihx`` header.
    header_path : Path
        The ``.cihx`` or ``.cih`` file.

    Notes
    -----
    The header is parsed by the package itself (no optional package needed). 8- and 16-bit
    data are memory-mapped; 12-bit packed data (two pixels in three bytes) are memory-mapped
    as bytes and unpacked one frame at a time. ``bit_depth`` is the header's effective bit
    depth; data aligned to the high bits (``EffectiveBit Side`` ``Higher``) are shifted
    down so values run from 0 to ``2**bit_depth - 1``. Pixels are read as stored (colour
    sensors give their raw mosaic). The frame rate is the header's record rate.

    A data file shorter than the header's ``Total Frame`` frames (a copy cut short) is
    read up to its last whole frame: ``len(reader)`` is the number of whole frames and
    :attr:`lost_frames` names the others (frame numbers count from 0 in file order); a
    WARNING is logged. Only a data file without one whole frame is an error.
    """

    kind = "mraw"
    suffixes = (".mraw", ".cihx", ".cih")

    def __init__(self, path: str | os.PathLike[str]) -> None:
        super().__init__(path)
        file = Path(path)
        if file.suffix.lower() not in self.suffixes:
            raise FootageError(f"{file}: not a Photron file (.mraw, .cihx or .cih)", file)
        header = next(
            (c for c in (file.with_suffix(".cihx"), file.with_suffix(".cih")) if c.is_file()),
            None,
        )
        if header is None:
            raise FootageError(f"{file}: no .cihx or .cih header beside it", file)
        raw = file.with_suffix(".mraw")
        if not raw.is_file():
            raise FootageError(f"{header}: no .mraw data file beside the header", header)
        try:
            cih = read_cih(header)
        except (CihFormatError, OSError) as exc:
            raise FootageError(f"{header}: unreadable header ({one_line(exc)})", header) from exc
        self.header_path = header
        self.path = raw
        self.cih: dict[str, Any] = dict(cih)
        self._map_data(cih, header, raw)

    def _map_data(self, cih: dict[str, Any], header: Path, raw: Path) -> None:
        try:
            n = int(cih["Total Frame"])
            h = int(cih["Image Height"])
            w = int(cih["Image Width"])
            bits = int(cih["Color Bit"])
            effective = int(cih.get("EffectiveBit Depth", bits) or bits)
            side = str(cih.get("EffectiveBit Side", "Lower") or "Lower").lower()
            fmt = str(cih.get("File Format", "MRaw"))
            rate = float(cih.get("Record Rate(fps)", 0) or 0)
        except (KeyError, TypeError, ValueError) as exc:
            raise FootageError(
                f"{header}: header lacks a usable value ({one_line(exc)})", header
            ) from exc
        if fmt.lower() != "mraw":
            raise FootageError(f"{header}: file format {fmt!r} is not MRAW", header)
        if bits not in (8, 12, 16):
            raise FootageError(
                f"{header}: {bits} bits per pixel not supported (8, 12 packed, 16)", header
            )
        if n < 1 or h < 1 or w < 1:
            raise FootageError(f"{header}: header says {n} frames of {w} x {h} px", header)
        if bits == 12 and (h * w) % 2:
            raise FootageError(f"{header}: 12-bit packed frames need an even pixel count", header)
        frame_bytes = h * w * bits // 8
        size = raw.stat().st_size
        whole = min(size // frame_bytes, n)
        if whole == 0:
            raise FootageError(
                f"{raw}: truncated: {size} bytes, not one whole frame of the header's {n} "
                f"frames of {w} x {h} px at {bits} bits ({frame_bytes} bytes each)",
                raw,
            )
        if whole < n:
            self._lost_frames = tuple(range(whole, n))
            logger.warning(
                "%s: truncated: %d bytes hold %d of the header's %d frames; %d frames lost "
                "(frames %s)",
                raw, size, whole, n, n - whole, ranges_text(self._lost_frames),
            )
        elif size > n * frame_bytes:
            logger.debug("%s: %d bytes after the last frame ignored", raw, size - n * frame_bytes)
        self._packed = bits == 12
        if self._packed:
            self._data = np.memmap(raw, dtype=np.uint8, mode="r", shape=(whole, frame_bytes))
        else:
            dtype = np.uint8 if bits == 8 else np.dtype("<u2")
            self._data = np.memmap(raw, dtype=dtype, mode="r", shape=(whole, h, w))
        self._shift = bits - effective if side == "higher" and bits in (8, 16) else 0
        self._length = whole
        self._hw = (h, w)
        self._frame_rate = rate if rate > 0 else None
        self._set_format(self._read(0), bit_depth=min(effective, 16))

    def _read(self, index: int) -> np.ndarray:
        if self._packed:
            frame = unpack_12bit(np.asarray(self._data[index]), self._hw[0] * self._hw[1])
            return frame.reshape(self._hw)
        frame = np.array(self._data[index], dtype=self._data.dtype.newbyteorder("="))
        if self._shift > 0:
            frame >>= self._shift
        return frame

    def _release(self) -> None:
        self._data = None  # type: ignore[assignment]


class CineReader(_StoredFormat):
    """Vision Research Phantom ``.cine`` footage.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.cine`` file.

    Attributes
    ----------
    header : CineHeader
        The header fields read (``image_count``, ``first_image_no``, ``width``, ``height``,
        ``bit_count``, ``frame_rate``, ``real_bpp``, ``image_offsets``, ...).

    Notes
    -----
    The file layout is read by the package itself (no optional package needed). Reads
    uncompressed 8- and 16-bit grey images and uncompressed 24/48-bit colour images (BGR,
    converted to grey), one image per :meth:`get_frame` from the offsets in the file.
    Values are raw as stored (no black/white level or LUT applied); images stored bottom-up
    (positive ``biHeight``) are flipped so that row 0 is the top. ``bit_depth`` is the
    setup's ``RealBPP``. JPEG-compressed, raw-Bayer (uninterpolated) and packed 10/12-bit
    files are refused with a message. The frame rate is the setup's ``FrameRate``
    (``FrameRate16`` in files whose setup predates it).

    Frame numbers count the stored images from 0 in file order; the camera's own numbering
    relative to the trigger starts at ``header.first_image_no`` (often negative). Images
    whose record runs past the end of the file (a copy cut short) or whose record header
    is corrupt are lost: they are listed in :attr:`lost_frames`, the others are read
    (``len(reader)`` counts them, :attr:`frame_numbers` keeps their numbers) and a WARNING
    is logged. Only a file without one intact image is an error.
    """

    kind = "cine"
    suffixes = (".cine",)

    def __init__(self, path: str | os.PathLike[str]) -> None:
        super().__init__(path)
        self._fd = -1
        file = Path(path)
        if not file.is_file():
            raise FootageError(f"{file}: not a file", file)
        try:
            self._fd = os.open(file, os.O_RDONLY | getattr(os, "O_BINARY", 0))
        except OSError as exc:
            raise FootageError(f"{file}: cannot be read ({exc.strerror or exc})", file) from exc
        try:
            self._open(file)
        except BaseException:
            self.close()
            raise

    def _open(self, file: Path) -> None:
        size = os.fstat(self._fd).st_size
        try:
            header = read_cine_header(self._fd, size)
        except CineFormatError as exc:
            raise FootageError(f"{file}: {exc}", file) from exc
        self.header = header
        if header.compression != 0:
            what = {1: "JPEG-compressed", 2: "raw Bayer (uninterpolated)"}.get(
                header.compression, f"compression {header.compression}"
            )
            raise FootageError(f"{file}: {what} CINE files are not supported", file)
        if header.bi_compression != 0:
            raise FootageError(
                f"{file}: packed pixel data (biCompression {header.bi_compression}) not "
                "supported; save the cine uncompressed (8 or 16 bit)",
                file,
            )
        bits = header.bit_count
        if bits not in (8, 16, 24, 48):
            raise FootageError(f"{file}: {bits} bits per pixel not supported", file)
        self._channels = 3 if bits in (24, 48) else 1
        self._dtype_file = np.dtype(np.uint8) if bits in (8, 24) else np.dtype("<u2")
        self._w = header.width
        self._h = abs(header.height)
        self._flip = header.height > 0
        if self._w < 1 or self._h < 1:
            raise FootageError(f"{file}: header says {self._w} x {self._h} px images", file)
        self._frame_bytes = self._w * self._h * bits // 8
        records = scan_images(self._fd, size, header.image_offsets, self._frame_bytes)
        intact = [i for i, r in enumerate(records) if not r.problem]
        lost = [i for i, r in enumerate(records) if r.problem]
        if not intact:
            raise FootageError(f"{self._frame_name(0)}: {self._problem(records[0])}", file)
        if lost:
            first = records[lost[0]]
            logger.warning(
                "%s: %d of the header's %d images lost (frames %s), %d intact read; "
                "first lost, frame %d: %s",
                file, len(lost), len(records), ranges_text(lost), len(intact), lost[0],
                self._problem(first),
            )
            self._lost_frames = tuple(lost)
            self._frame_numbers = np.asarray(intact, dtype=np.int64)
        self._data_offsets = [records[i].data_offset for i in intact]
        self._length = len(intact)
        self._frame_rate = float(header.frame_rate) if header.frame_rate > 0 else None
        storage = self._dtype_file.itemsize * 8
        real = header.real_bpp or 0
        self._set_format(self._read(0), bit_depth=real if 8 <= real <= storage else storage)

    def _problem(self, record: ImageRecord) -> str:
        """A lost image's problem, with the expected size where the size is wrong."""
        if record.problem.startswith("image holds"):
            return f"{record.problem} for {self._w} x {self._h} px (truncated or corrupt file)"
        return record.problem

    def _frame_name(self, index: int) -> str:
        number = index if self._frame_numbers is None else int(self._frame_numbers[index])
        return f"{self._name()} (frame {number})"

    def _read(self, index: int) -> np.ndarray:
        data = os.pread(self._fd, self._frame_bytes, self._data_offsets[index])
        if len(data) != self._frame_bytes:
            raise FootageError(
                f"{self._frame_name(index)}: truncated file ({len(data)} of "
                f"{self._frame_bytes} bytes)",
                self.path,
            )
        image = np.frombuffer(data, dtype=self._dtype_file)
        shape = (self._h, self._w, 3) if self._channels == 3 else (self._h, self._w)
        image = image.reshape(shape)
        if self._flip:
            image = image[::-1]
        return np.array(to_grey(image, order="bgr"), dtype=self._dtype_file.newbyteorder("="))

    def _release(self) -> None:
        fd, self._fd = self._fd, -1
        if fd >= 0:
            os.close(fd)


class ImageFileReader(_StoredFormat):
    """A single PNG, BMP or JPEG image: a 1-frame video (as a single-page TIFF is).

    Parameters
    ----------
    path : str or os.PathLike
        The image file.

    Notes
    -----
    A static test photographed once, or one frame taken out of a clip. The frame rate is
    unknown (None); its number is 0.
    """

    kind = "image"
    suffixes = (".png", ".bmp", ".jpg", ".jpeg")

    def __init__(self, path: str | os.PathLike[str]) -> None:
        super().__init__(path)
        file = Path(path)
        if not file.is_file():
            raise FootageError(f"{file}: not a file", file)
        self._frame = decode_image_file(file)  # decoded once: the video's only frame
        self._set_format(self._frame)
        self._length = 1

    def _read(self, index: int) -> np.ndarray:
        return self._frame.copy()  # the caller may change it


_REGISTRY: dict[str, type[FootageReader]] = {}


def register_reader(
    cls: type[FootageReader], *, replace: bool = False
) -> type[FootageReader]:
    """Add a reader class to those :func:`open_footage` chooses from (usable as a decorator).

    Parameters
    ----------
    cls : type
        A :class:`FootageReader` subclass with a ``kind`` and suffixes (or its own
        ``claims``); tried after the readers registered before it.
    replace : bool
        Allow replacing the reader of the same ``kind``.

    Returns
    -------
    type
        ``cls``.

    Raises
    ------
    TypeError
        Not a concrete FootageReader subclass.
    ValueError
        No ``kind``, or a ``kind`` already registered (without ``replace``).
    """
    if not (isinstance(cls, type) and issubclass(cls, FootageReader)):
        raise TypeError(f"a reader must be a FootageReader subclass, got {cls!r}")
    if inspect.isabstract(cls):
        missing = ", ".join(sorted(cls.__abstractmethods__))
        raise TypeError(f"reader {cls.__name__} does not implement {missing}")
    if not cls.kind:
        raise ValueError(f"reader {cls.__name__} needs a kind (its short name)")
    if cls.kind in _REGISTRY and not replace:
        raise ValueError(f"a reader of kind {cls.kind!r} is already registered "
                         f"({_REGISTRY[cls.kind].__name__}); pass replace=True")
    _REGISTRY[cls.kind] = cls
    return cls


def unregister_reader(kind: str) -> None:
    """Remove the reader of ``kind`` (KeyError naming the registered kinds otherwise)."""
    if kind not in _REGISTRY:
        raise KeyError(f"no reader of kind {kind!r}; registered: {', '.join(_REGISTRY)}")
    del _REGISTRY[kind]


def readers() -> tuple[type[FootageReader], ...]:
    """The registered reader classes in the order :func:`open_footage` tries them."""
    return tuple(_REGISTRY.values())


class _ReaderTable(Sequence[type[FootageReader]]):
    """A live, read-only view of the registered readers (``READERS``)."""

    def __getitem__(self, index):  # type: ignore[override]
        return readers()[index]

    def __len__(self) -> int:
        return len(_REGISTRY)

    def __repr__(self) -> str:
        return f"READERS{readers()!r}"


for _reader in (FrameFolderReader, MultiPageTiffReader, ImageFileReader, VideoFileReader,
                MrawReader, CineReader):
    register_reader(_reader)

#: Reader classes in the order :func:`open_footage` tries them: a live view of the registry
#: (:func:`register_reader`, :func:`readers`).
READERS: Sequence[type[FootageReader]] = _ReaderTable()


def open_footage(path: str | os.PathLike[str], *, kind: str | None = None) -> FootageReader:
    """Open footage with the reader that fits its file type.

    Parameters
    ----------
    path : str or os.PathLike
        A folder of frames, a ``.tif``/``.tiff`` stack, a single ``.png``/``.bmp``/``.jpg``
        image (a 1-frame video), a video (``.avi``, ``.mp4``,
        ``.mov``, ``.mkv``), a Photron ``.mraw``/``.cihx``/``.cih`` or a Phantom ``.cine``;
        or a clip folder whose ``meta.json`` names its footage (``video_file``, or a
        ``frame_pattern`` in a sub-folder, :func:`tir_contact.meta.clip_footage`): that
        footage is opened, as the analysis reads it.
    kind : {"folder", "tiff", "image", "video", "mraw", "cine"} or a registered kind, optional
        Force a reader instead of choosing by file type.

    Returns
    -------
    FootageReader
        An open reader; close it (or use ``with``).

    Raises
    ------
    FootageError
        When the path does not exist, or no reader can read it: one line listing each
        tried reader's reason. The readers that claim the path (:meth:`FootageReader.claims`)
        are tried in registry order; when none does, every file reader is tried.
    """
    path = Path(path)
    if not path.exists():
        raise FootageError(f"{path}: does not exist", path)
    if kind is not None:
        if kind not in _REGISTRY:
            raise ValueError(f"kind must be one of {sorted(_REGISTRY)}, got {kind=}")
        return _REGISTRY[kind](path)
    named = clip_footage(path) if path.is_dir() else None
    if named is not None and named.exists() and named != path:
        # a clip folder: the footage its meta.json names, as the analysis reads it
        return open_footage(named)
    candidates = [cls for cls in readers() if cls.claims(path)]
    if not candidates and path.is_dir():
        raise FootageError(f"{path}: no reader reads this folder", path)
    if not candidates:
        candidates = [cls for cls in readers() if not cls.reads_folders]
    if len(candidates) == 1:
        return candidates[0](path)  # the file's own type: its reader's message says most
    reasons: list[str] = []
    for cls in candidates:
        try:
            return cls(path)
        except FootageError as exc:
            reason = str(exc)
            prefix = f"{path}: "
            reasons.append(f"{cls.__name__}: {reason.removeprefix(prefix)}")
    raise FootageError(f"{path}: no reader fits: " + "; ".join(reasons), path)
