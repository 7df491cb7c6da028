"""Phantom CINE file layout: the header fields and image records the footage reader needs.

A CINE file (Vision Research, "Cine File Format", PhFile release 13.5.792) starts with
three structures, all little-endian and packed without padding:

* ``CINEFILEHEADER`` (44 bytes at offset 0): ``Type`` (the two bytes ``"CI"``),
  ``Headersize``, ``Compression`` (0 grey or interpolated colour, 1 JPEG, 2 raw Bayer),
  ``Version``, ``FirstMovieImage``, ``TotalImageCount``, ``FirstImageNo`` (signed, the first
  image's number relative to the trigger), ``ImageCount``, ``OffImageHeader``, ``OffSetup``,
  ``OffImageOffsets`` and an 8-byte trigger time.
* ``BITMAPINFOHEADER`` (40 bytes at ``OffImageHeader``), as in Windows bitmaps: ``biWidth``,
  ``biHeight`` (positive: rows stored bottom-up), ``biBitCount`` (8/16 grey, 24/48 colour),
  ``biCompression`` (0 uncompressed; 256 and 1024 are packed 10- and 12-bit) and
  ``biSizeImage``.
* ``SETUP`` (at ``OffSetup``, byte-aligned): ``FrameRate16`` (uint16, byte 0; the frame rate
  of old files, saturated at 65535), the ``"ST"`` mark (byte 140), ``Length`` (uint16,
  byte 142: the size of this version of the setup), ``FrameRate`` (uint32, byte 768, in
  frames per second) and ``RealBPP`` (uint32, byte 896: the effective bits per pixel).
  Fields past the setup's own length are absent in older files.

At ``OffImageOffsets`` follow ``ImageCount`` 64-bit file offsets, one per image. Each image
record starts with a uint32 ``AnnotationSize`` (at least 8); the last four bytes of the
annotation are a uint32 ``ImageSize``; the pixels follow the annotation.

The offsets above are those of the pycine project's ctypes transcription of the Vision
Research documentation, checked on the two sample files of the test suite (a PCC 3.3.781
file and a 2008 file).
"""

from __future__ import annotations

import os
import struct
from dataclasses import dataclass

import numpy as np

__all__ = ["CineFormatError", "CineHeader", "ImageRecord", "read_cine_header", "scan_images"]

#: CINEFILEHEADER up to OffImageOffsets: Type, Headersize, Compression, Version,
#: FirstMovieImage, TotalImageCount, FirstImageNo, ImageCount, OffImageHeader, OffSetup,
#: OffImageOffsets.
_FILE_HEADER = struct.Struct("<2sHHHiIiIIII")

#: BITMAPINFOHEADER: biSize, biWidth, biHeight, biPlanes, biBitCount, biCompression,
#: biSizeImage, biXPelsPerMeter, biYPelsPerMeter, biClrUsed, biClrImportant.
_BITMAP_HEADER = struct.Struct("<IiiHHIIiiII")

#: Byte positions of the SETUP fields read, with their struct formats.
_SETUP_FRAME_RATE16 = (0, "<H")
_SETUP_LENGTH = (142, "<H")
_SETUP_FRAME_RATE = (768, "<I")
_SETUP_REAL_BPP = (896, "<I")

#: Bytes of the SETUP read: up to the end of RealBPP.
_SETUP_READ = _SETUP_REAL_BPP[0] + 4


class CineFormatError(ValueError):
    """The bytes are not a readable CINE header; the message says which field is wrong."""


@dataclass(frozen=True)
class CineHeader:
    """The header fields of a CINE file that the reader uses.

    Attributes
    ----------
    compression : int
        ``CINEFILEHEADER.Compression``: 0 grey or interpolated colour, 1 JPEG, 2 raw Bayer.
    first_image_no : int
        ``FirstImageNo``: number of the first stored image relative to the trigger (may be
        negative).
    image_count : int
        ``ImageCount``: number of images the file claims to hold.
    width, height : int
        ``biWidth`` and ``biHeight`` in pixels; a positive height means rows are stored
        bottom-up.
    bit_count : int
        ``biBitCount``: bits per stored pixel (8, 16 grey; 24, 48 colour).
    bi_compression : int
        ``biCompression``: 0 uncompressed, otherwise packed pixels.
    frame_rate : int
        ``FrameRate`` in frames per second, or ``FrameRate16`` where the setup has no
        ``FrameRate`` or it is 0; 0 when neither is set.
    real_bpp : int or None
        ``RealBPP``, the effective bits per pixel; None where the setup is too short to hold it.
    image_offsets : (image_count,) ndarray of int64
        File offset of each image record.
    """

    compression: int
    first_image_no: int
    image_count: int
    width: int
    height: int
    bit_count: int
    bi_compression: int
    frame_rate: int
    real_bpp: int | None
    image_offsets: np.ndarray


def _field(data: bytes, where: tuple[int, str], limit: int) -> int | None:
    """A SETUP field, or None where it lies past `limit` bytes (absent in that version)."""
    offset, fmt = where
    if offset + struct.calcsize(fmt) > min(limit, len(data)):
        return None
    return int(struct.unpack_from(fmt, data, offset)[0])


def read_cine_header(fd: int, size: int) -> CineHeader:
    """Read and check the header of a CINE file.

    Parameters
    ----------
    fd : int
        Open file descriptor of the file (read with ``os.pread``, position unchanged).
    size : int
        File size in bytes.

    Returns
    -------
    CineHeader
        The fields, see the module notes for their places in the file.

    Raises
    ------
    CineFormatError
        When the signature is not ``"CI"``, the file claims no images, or a header or the
        table of image offsets lies past the end of the file; the message names the field.
    """
    head = os.pread(fd, _FILE_HEADER.size, 0)
    if len(head) < _FILE_HEADER.size or head[:2] != b"CI":
        raise CineFormatError("not a Phantom CINE file (no 'CI' signature)")
    (
        _,
        _headersize,
        compression,
        _version,
        _first_movie_image,
        _total_image_count,
        first_image_no,
        image_count,
        off_image_header,
        off_setup,
        off_image_offsets,
    ) = _FILE_HEADER.unpack(head)
    if image_count == 0:
        raise CineFormatError("CINE file holds no images (ImageCount 0)")
    past = (
        off_image_header + _BITMAP_HEADER.size > size
        or off_setup + 2 > size
        or off_image_offsets + 8 * image_count > size
    )
    if past:
        raise CineFormatError(
            f"truncated or corrupt CINE header (offsets point past the end of the {size}-byte "
            f"file: OffImageHeader {off_image_header}, OffSetup {off_setup}, OffImageOffsets "
            f"{off_image_offsets} + 8 x ImageCount {image_count})"
        )
    (
        _bi_size,
        width,
        height,
        _planes,
        bit_count,
        bi_compression,
        _size_image,
        *_,
    ) = _BITMAP_HEADER.unpack(os.pread(fd, _BITMAP_HEADER.size, off_image_header))
    setup = os.pread(fd, _SETUP_READ, off_setup)
    # the setup ends where the next block begins; its Length field, when plausible, is
    # the size of this version of the structure (older versions lack the later fields)
    limit = off_image_offsets - off_setup if off_image_offsets > off_setup else size - off_setup
    length = _field(setup, _SETUP_LENGTH, limit)
    if length is not None and _SETUP_LENGTH[0] + 2 <= length <= limit:
        limit = length
    rate16 = _field(setup, _SETUP_FRAME_RATE16, limit) or 0
    rate = _field(setup, _SETUP_FRAME_RATE, limit) or rate16
    offsets = np.frombuffer(
        os.pread(fd, 8 * image_count, off_image_offsets), dtype="<i8"
    ).astype(np.int64)
    return CineHeader(
        compression=int(compression),
        first_image_no=int(first_image_no),
        image_count=int(image_count),
        width=int(width),
        height=int(height),
        bit_count=int(bit_count),
        bi_compression=int(bi_compression),
        frame_rate=int(rate),
        real_bpp=_field(setup, _SETUP_REAL_BPP, limit),
        image_offsets=offsets,
    )


@dataclass(frozen=True)
class ImageRecord:
    """Where one image's pixels lie, or why they cannot be read.

    Attributes
    ----------
    data_offset : int
        File offset of the first pixel byte (-1 when unreadable).
    problem : str
        Empty for an intact image; otherwise what is wrong (``"truncated file ..."`` or
        ``"corrupt image header"`` or a size mismatch).
    """

    data_offset: int
    problem: str = ""


def scan_images(fd: int, size: int, offsets: np.ndarray, image_bytes: int) -> list[ImageRecord]:
    """Locate the pixels of every image record and check that they lie inside the file.

    Parameters
    ----------
    fd : int
        Open file descriptor (read with ``os.pread``).
    size : int
        File size in bytes.
    offsets : (n,) ndarray of int64
        The image offsets of the header.
    image_bytes : int
        Bytes of one image's pixels expected from the bitmap header.

    Returns
    -------
    list of ImageRecord
        One per offset: intact, or with the problem (record past the end of the file, an
        annotation size below 8, an ``ImageSize`` other than `image_bytes`).
    """
    records: list[ImageRecord] = []
    for start in offsets.tolist():
        if start < 0 or start + 4 > size:
            records.append(ImageRecord(-1, "truncated file (image offset past the end)"))
            continue
        annotation = int.from_bytes(os.pread(fd, 4, start), "little")
        if annotation < 8:
            records.append(ImageRecord(-1, "corrupt image header"))
            continue
        data_offset = start + annotation
        if data_offset > size:
            records.append(ImageRecord(-1, "truncated file (image header past the end)"))
            continue
        stored = int.from_bytes(os.pread(fd, 4, data_offset - 4), "little")
        if stored != image_bytes:
            records.append(ImageRecord(-1, f"image holds {stored} bytes, {image_bytes} expected"))
            continue
        if data_offset + image_bytes > size:
            records.append(
                ImageRecord(
                    -1,
                    f"truncated file ({max(size - data_offset, 0)} of {image_bytes} bytes)",
                )
            )
            continue
        records.append(ImageRecord(data_offset))
    return records
