"""Frame writers and the ``meta.json`` record of synthetic footage (private helpers of
:mod:`synthetic.footage`).

Every writer streams: a frame goes to disk when it is rendered, nothing of the clip is kept
in memory. All outputs are byte-for-byte deterministic for the same frames (no timestamps;
PNG through OpenCV with a fixed compression level, TIFF through tifffile without date,
AVI as lossless FFV1 through OpenCV's FFmpeg backend).

``spec`` below is a :class:`synthetic.footage.FootageSpec`; it is annotated ``Any`` because
that module imports this one (an import back, even for type checking only, would be a
circle).
"""

from __future__ import annotations

import importlib.metadata
import json
import logging
import re
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import tifffile

__all__ = ["FrameSink", "open_sink", "write_meta"]

logger = logging.getLogger(__name__)

#: zlib level of the PNG frames: 1 writes fastest; higher levels shrink the noisy frames by
#: only a few per cent.
_PNG_LEVEL = 1
#: Above this estimated size the multi-page TIFF is written as BigTIFF (classic TIFF offsets
#: are 32-bit), bytes.
_BIGTIFF_ABOVE = 2**31
#: Video codecs tried for ``fmt="avi"``, lossless first.
_AVI_CODECS = ("FFV1", "Y800")
#: The highest frame rate (Hz) OpenCV's FFmpeg backend writes every frame of an AVI at
#: (measured with OpenCV 4.8 and 5.1: 1000 Hz writes all 60 frames of a test clip; at 1001
#: Hz and above frames are dropped or garbled, 13 of 60 kept at 4000 Hz, the header saying
#: 600 Hz). Faster clips are written at this container rate; ``meta.json`` keeps the true
#: ``fps`` and records the header's as ``container_fps``.
AVI_MAX_FPS = 1000.0
_FRAME_FILE = re.compile(r"^frame_\d{6}\.(png|tif|jpg)$")


class FrameSink:
    """Writes the frames of one clip in one format.

    Attributes
    ----------
    fmt : str
        ``"png"``, ``"tiff"``, ``"avi"`` or ``"multitiff"``.
    info : dict
        What ``meta.json`` records about the frame files (pattern or file name, codec).
    """

    def __init__(self, out_dir: Path, fmt: str, spec: Any) -> None:
        self.out_dir = out_dir
        self.fmt = fmt
        self.count = 0
        cam = spec.camera
        self._video: Any = None
        self._rate = float(cam.fps)
        self._tiff: Any = None
        if fmt in ("png", "tiff", "jpg"):
            frames = out_dir / "frames"
            frames.mkdir(exist_ok=True)
            for old in frames.iterdir():  # replace an earlier render of this writer
                if old.is_file() and _FRAME_FILE.match(old.name):
                    old.unlink()
            ext = {"png": "png", "tiff": "tif", "jpg": "jpg"}[fmt]
            self.info = {"frame_pattern": f"frames/frame_{{frame:06d}}.{ext}"}
        elif fmt == "avi":
            path = out_dir / "footage.avi"
            rate = self._rate = min(float(cam.fps), AVI_MAX_FPS)
            for codec in _AVI_CODECS:
                writer = cv2.VideoWriter(
                    str(path),
                    cv2.VideoWriter_fourcc(*codec),
                    rate,
                    (cam.width_px, cam.height_px),
                    isColor=False,
                )
                if writer.isOpened():
                    self._video = writer
                    self.info = {"video_file": "footage.avi", "fourcc": codec}
                    if rate != float(cam.fps):
                        self.info["container_fps"] = rate
                    break
                writer.release()
            if self._video is None:
                raise RuntimeError(
                    f"OpenCV could not open an AVI writer with any of the codecs {_AVI_CODECS}"
                )
        else:
            path = out_dir / "footage.tif"
            itemsize = 1 if cam.bit_depth == 8 else 2
            size = spec.n_frames * cam.width_px * cam.height_px * itemsize
            big = size > _BIGTIFF_ABOVE
            self._tiff = tifffile.TiffWriter(path, bigtiff=big)
            self.info = {"video_file": "footage.tif", "bigtiff": big}

    def write(self, k: int, image: np.ndarray, *, encoded: bytes | None = None) -> None:
        """Write frame ``k`` (frames arrive in order); ``encoded``: its JPEG bytes."""
        if self.fmt == "jpg":
            if encoded is None:
                raise ValueError(f"fmt='jpg' needs the JPEG bytes of frame {k}, got None")
            (self.out_dir / "frames" / f"frame_{k:06d}.jpg").write_bytes(encoded)
        elif self.fmt == "png":
            name = self.out_dir / "frames" / f"frame_{k:06d}.png"
            if not cv2.imwrite(str(name), image, [cv2.IMWRITE_PNG_COMPRESSION, _PNG_LEVEL]):
                raise OSError(f"could not write {name}")
        elif self.fmt == "tiff":
            name = self.out_dir / "frames" / f"frame_{k:06d}.tif"
            tifffile.imwrite(name, image, photometric="minisblack", metadata=None)
        elif self.fmt == "avi":
            self._video.write(np.ascontiguousarray(image))
        else:
            self._tiff.write(image, photometric="minisblack", contiguous=True)
        self.count += 1

    def close(self) -> None:
        """Finish the video or multi-page file.

        Raises
        ------
        OSError
            The AVI's header holds fewer frames than were written (the video backend
            dropped some).
        """
        if self._video is not None:
            self._video.release()
            self._video = None
            self._check_video()
        if self._tiff is not None:
            self._tiff.close()
            self._tiff = None


    def _check_video(self) -> None:
        """The AVI's header counts every frame written (OpenCV's writer gives no error
        when its backend drops a frame)."""
        path = self.out_dir / self.info["video_file"]
        cap = cv2.VideoCapture(str(path))
        try:
            held = int(cap.get(cv2.CAP_PROP_FRAME_COUNT) or 0) if cap.isOpened() else 0
        finally:
            cap.release()
        if held != self.count:
            raise OSError(
                f"{path}: the video backend wrote {held} of the {self.count} frames "
                f"({self.info['fourcc']} at {self._rate:g} frames/s); write png or tiff "
                "frames instead"
            )


def open_sink(out_dir: Path, fmt: str, spec: Any) -> FrameSink:
    """A :class:`FrameSink` for ``fmt`` writing into ``out_dir``."""
    return FrameSink(out_dir, fmt, spec)


def _version() -> str:
    try:
        return importlib.metadata.version("tir-contact")
    except importlib.metadata.PackageNotFoundError:
        return "unknown"


def write_meta(
    out_dir: Path,
    spec: Any,
    sink: FrameSink,
    *,
    truth_columns: tuple[str, ...],
    extra: dict[str, Any] | None = None,
) -> Path:
    """Write ``meta.json`` (keys in ``docs/formats.md``) and return its path.

    A static scene (``spec.is_static``) has no ``block`` entry and velocity 0 in
    ``conditions``; ``extra`` (the real-footage entries) goes before ``format``.
    """
    cam = spec.camera
    geom = spec.geometry
    meta: dict[str, Any] = {
        "view": spec.view,
        "fps": cam.fps,
        "mm_per_px": cam.mm_per_px,
        "sliding_direction": spec.sliding_direction,
        "contact_is": spec.contact_is,
        "block": {
            "preset": spec.preset if spec.block is None else None,
            "length_mm": geom.length_mm,
            "width_mm": geom.width_mm,
            "n_sipes": int(geom.n_sipes),
            "sipe_width_mm": geom.sipe_width_mm,
            "height_mm": geom.height_mm,
            "element_lengths_mm": [float(x) for x in geom.element_lengths],
        },
        "conditions": {
            "velocity_mps": spec.velocity_mps,
            "pressure_bar": spec.pressure_bar,
            "temperature_C": spec.temperature_C,
            "humidity_pct": spec.humidity_pct,
            "salinity_pct": spec.salinity_pct,
        },
        "n_frames": sink.count,
        "width_px": cam.width_px,
        "height_px": cam.height_px,
        "bit_depth": cam.bit_depth,
        "dtype": "uint8" if cam.bit_depth == 8 else "uint16",
        "max_dn": (1 << cam.bit_depth) - 1,
        "exposure_s": cam.exposure_s,
        "center_time_s": spec.center_time_s
        if spec.center_time_s is not None
        else 0.5 * spec.duration_s,
        "intensity": {
            "white_level": cam.white_level,
            "contrast": spec.contrast,
            "contrast_max": spec.contrast_max,
            "pressure_ref_MPa": spec.pressure_ref_MPa,
            "edge_band_mm": spec.edge_band_mm,
        },
        **(extra or {}),
        "format": sink.fmt,
        **sink.info,
        "ground_truth_file": "ground_truth.csv",
        "ground_truth_columns": list(truth_columns),
        "read_noise_dn": cam.read_noise,
        "seed": spec.seed,
        "spec": spec.to_dict(),
        "generator": "synthetic.footage",
        "package": "tir-contact",
        "package_version": _version(),
    }
    if spec.is_static:
        del meta["block"]
        meta["conditions"]["velocity_mps"] = 0.0
    path = out_dir / "meta.json"
    path.write_text(json.dumps(meta, indent=2, sort_keys=False) + "\n", encoding="utf-8")
    return path
