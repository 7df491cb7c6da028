"""Before the first frame: footage, metadata, reference and threshold of one video.

:func:`prepare_video` reads the metadata and a sample of frames spread through the video
and returns a :class:`VideoSetup`, everything the per-frame step
(:mod:`tir_contact.frame`) needs. :func:`resolve_footage` says what a user's path means.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tir_contact._readers import FootageError, is_image_name
from tir_contact.features import BlockLayout
from tir_contact.flatfield import Reference
from tir_contact.meta import META_FILENAME, clip_footage, find_meta, load_meta, read_meta_json
from tir_contact.optics import full_contact_from_meta
from tir_contact.options import AnalysisOptions
from tir_contact.side_view import SideView
from tir_contact.tir_view import TirView
from tir_contact.travel import expected_travel_px

__all__ = [
    "VideoSetup",
    "footage_fingerprint",
    "input_files",
    "output_name",
    "prepare_video",
    "resolve_footage",
]


def output_name(path: str | os.PathLike[str]) -> str:
    """Name of a video's result folder: the folder name or the file name without suffix.

    Examples
    --------
    >>> output_name("runs/G3_1mps/footage.avi"), output_name("runs/G3_1mps/frames")
    ('footage', 'frames')
    """
    p = Path(path)
    return p.name if p.is_dir() or not p.suffix else p.stem


def _images_in(folder: Path) -> int:
    try:
        return sum(1 for q in folder.iterdir() if q.is_file() and is_image_name(q.name))
    except OSError:
        return 0


def resolve_footage(path: str | os.PathLike[str], *, strict: bool = False) -> tuple[Path, str]:
    """The footage a path means, and its result name.

    A synthetic clip folder (``meta.json`` naming ``frames/...`` or a video file that
    exists) means its frames folder or video, named after the clip folder; this holds for
    a multi-page TIFF in the clip folder too.

    Parameters
    ----------
    path : str or os.PathLike
        What the user named.
    strict : bool
        Raise the ``meta.json`` error of a folder that holds no images and whose
        ``meta.json`` cannot be read (instead of reading the folder as frames, which then
        reports "no image files").

    Returns
    -------
    (Path, str)
        What the reader opens, and the result folder name.
    """
    p = Path(path)
    if p.is_dir():
        inner = clip_footage(p)
        if inner is not None and (inner.exists() or _images_in(p) == 0):
            return inner, p.name
        if strict and inner is None and (p / META_FILENAME).is_file() and _images_in(p) == 0:
            read_meta_json(p / META_FILENAME)  # raises the JSON error, naming the file
    return p, output_name(p)


def footage_fingerprint(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Sizes and modification times of the footage and its metadata (for ``--resume``)."""

    p = Path(path)
    files = sorted(q for q in p.iterdir() if q.is_file()) if p.is_dir() else [p]
    meta = find_meta(p)
    if meta is not None and meta not in files:
        files.append(meta)
    return {
        "files": len(files),
        "bytes": int(sum(q.stat().st_size for q in files)),
        "mtime_ns": int(max((q.stat().st_mtime_ns for q in files), default=0)),
    }


#: Analysis options that name a file: ``--resume`` compares the file (resolved path, size,
#: modification time), not the text the option was given as.
INPUT_FILE_OPTIONS = ("reference", "lit_mask")


def input_files(options: AnalysisOptions) -> dict[str, dict[str, Any]]:
    """The files the analysis options name (``reference``, ``lit_mask``): resolved path,
    size and modification time of each given one (for ``--resume``)."""
    out: dict[str, dict[str, Any]] = {}
    for key in INPUT_FILE_OPTIONS:
        value = getattr(options, key, None)
        if not value:
            continue
        q = Path(value).resolve()
        entry: dict[str, Any] = {"path": str(q)}
        with contextlib.suppress(OSError):
            st = q.stat()
            entry.update(bytes=int(st.st_size), mtime_ns=int(st.st_mtime_ns))
        out[key] = entry
    return out


@dataclass
class VideoSetup:
    """What is fixed for all frames of one video (:func:`prepare_video`).

    Attributes
    ----------
    meta : dict
        The metadata used.
    view : TirView or SideView
        The view and what it decided for this video (:mod:`tir_contact.tir_view`,
        :mod:`tir_contact.side_view`): reference, camera mode and the view's own state.
    contact_is : str
    fps, mm_per_px : float
    layout : BlockLayout
    n_frames : int
    shape : (int, int)
    max_dn : float
    skipped : list of dict
        Sampled frames that could not be read.
    numbers : ndarray of int
        Recorded frame number of each frame.
    bad : set of int
        Indices of frames that could not be read.
    grey_range : (float, float)
        1st and 99th percentile of the sampled pixels.
    notes : list of str
        Warnings found while preparing (``summary.json`` lists them).
    """
    meta: dict[str, Any]
    view: TirView | SideView
    contact_is: str
    fps: float
    mm_per_px: float
    layout: Any
    n_frames: int
    shape: tuple[int, int]
    max_dn: float
    skipped: list[dict[str, Any]]
    numbers: np.ndarray  # recorded frame number of each readable frame (reader.frame_numbers)
    bad: set[int] = field(default_factory=set)  # indices of frames that could not be read
    grey_range: tuple[float, float] = (0.0, 0.0)  # 1st and 99th percentile of sampled pixels
    notes: list[str] = field(default_factory=list)  # what the user must know (warnings)

    @property
    def view_name(self) -> str:
        """``"tir"`` or ``"side"``."""
        return self.view.name

    @property
    def reference(self) -> Reference | None:
        """The view's free surface (TIR) or background (side; None: each frame's own)."""
        return self.view.reference

    @property
    def reference_method(self) -> str:
        return self.view.method

    @property
    def camera(self) -> str:
        """``"fixed"``: the block passes the camera; ``"follows"``: it stays in view."""
        return self.view.camera


def _sample_frames(reader: Any, n_sample: int, skipped: list[dict[str, Any]],
                   bad: set[int], numbers: np.ndarray) -> tuple[list[np.ndarray], list[int]]:
    """`n_sample` frames spread evenly through the video, and the recorded frame number of
    each (a frame that cannot be read is left out and listed in `skipped` and `bad`)."""
    n = len(reader)
    idx = np.unique(np.linspace(0, n - 1, min(n, n_sample)).round().astype(int))
    frames, read = [], []
    for i in idx:
        try:
            frames.append(reader.get_frame(int(i)))
            read.append(int(numbers[i]))
        except FootageError as exc:
            skipped.append({"frame": int(numbers[i]), "reason": str(exc)})
            bad.add(int(i))
    return frames, read


def prepare_video(reader: Any, path: Path, overrides: Mapping[str, Any] | None,
                  options: AnalysisOptions) -> VideoSetup:
    """What the analysis of each frame needs, from the metadata and sampled frames.

    Reads the metadata, samples ``options.reference_frames`` frames spread through the
    video, and prepares the view the metadata names (:meth:`tir_contact.tir_view.TirView.prepare`:
    the lit zone, the camera mode, the free surface, the noise, the contact threshold and the
    darkness populations; :meth:`tir_contact.side_view.SideView.prepare`: the background
    reference, the camera mode and the ice line's tilt).

    Parameters
    ----------
    reader : footage reader
        An open reader (:func:`tir_contact.io.open_footage`).
    path : Path
        The footage (for messages and the metadata).
    overrides : mapping, optional
        Metadata by dotted key, winning over ``meta.json``.
    options : AnalysisOptions

    Returns
    -------
    VideoSetup

    Raises
    ------
    FootageError
        No frames, no readable sampled frame, or bad metadata.
    """

    meta = load_meta(path, overrides, frame_rate=reader.frame_rate)
    n = len(reader)
    if n == 0:
        raise FootageError(f"{path}: the footage has no frames", path)
    view, contact_is = meta["view"], meta["contact_is"]
    skipped: list[dict[str, Any]] = []
    bad: set[int] = set()
    numbers = np.asarray(reader.frame_numbers, dtype=np.int64)
    samples, sampled = _sample_frames(reader, options.reference_frames, skipped, bad, numbers)
    if not samples:
        raise FootageError(f"{path}: none of the sampled frames could be read "
                           f"(first reason: {skipped[0]['reason']})", path)
    shape = samples[0].shape
    max_dn = float(meta.get("max_dn") or (2 ** reader.bit_depth - 1))
    pixels = np.concatenate([f[::4, ::4].ravel() for f in samples])
    grey_range = (float(np.percentile(pixels, 1)), float(np.percentile(pixels, 99)))
    if view == "tir":
        view_obj, notes = TirView.prepare(samples, shape, contact_is, options,
                                          optics=_optics(meta, path, contact_is),
                                          travel_px=expected_travel_px(meta, sampled))
    else:
        view_obj, notes = SideView.prepare(samples, shape, contact_is, options)
    layout = BlockLayout.from_meta(meta)
    if view == "tir" and options.camera == "follows":
        # only a following camera given as such: auto's "follows" is also its answer
        # without evidence of motion (one frame, a short or slow pass of a fixed camera),
        # whose frames off centre_time_s the carrier's travel places right
        layout = dataclasses.replace(layout, camera_follows=True)
    return VideoSetup(meta, view_obj, contact_is, float(meta["fps"]), float(meta["mm_per_px"]),
                      layout, n, shape, max_dn, skipped, numbers, bad, grey_range, notes)


def _optics(meta: Mapping[str, Any], path: Path, contact_is: str) -> tuple[float, str] | None:
    """Full contact's darkness from the metadata's ``optics`` (dark contact only: bright
    contact has no full level), :func:`tir_contact.optics.full_contact_from_meta`; a value
    that cannot be used is an error naming the metadata file."""
    if contact_is != "dark":
        return None
    try:
        return full_contact_from_meta(meta)
    except ValueError as exc:
        where = find_meta(path) or path
        raise FootageError(f"{where}: {exc}", path) from exc
