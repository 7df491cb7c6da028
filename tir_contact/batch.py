"""Analyse many videos: find them, run them in parallel, resume, never lose finished results.

Each video's results are written to ``OUT/<name>/`` by :func:`tir_contact.analyze.analyze_video`
(built in a staging folder and moved into place when complete). A broken video (unreadable
file, corrupt frame, missing metadata) is reported and the others go on; the batch's report
``OUT/batch_report.json`` (and ``.csv``) lists every video with its status, and the batch
fails (non-zero exit of ``tir-contact analyze``) when anything failed. ``OUT/report.html``
shows them all in a browser (:mod:`tir_contact.report`).

Interrupted (Ctrl-C, SIGINT): no new video is started, the workers are ended, and the
report lists every video whose results were written (found on disk, also those a worker
finished while the interrupt arrived), the rest as ``interrupted``; then
:class:`KeyboardInterrupt` goes on to the caller.

Parallel work: local processes (``workers``, default all cores) or an existing
``dask.distributed`` cluster (``scheduler`` address).
"""

from __future__ import annotations

import json
import logging
import math
import os
import re
import sys
import time
import traceback
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd
import tifffile

from tir_common.atomic import atomic_write, json_safe, write_json
from tir_common.progress import progress_bar, show_progress
from tir_contact import _workers
from tir_contact._interrupt import one_interrupt
from tir_contact._outdir import remove_stale_temporaries
from tir_contact._readers import FootageError, is_image_name, one_line
from tir_contact.analyze import AnalysisOptions, analyze_video
from tir_contact.meta import META_FILENAME, clip_footage, load_meta
from tir_contact.options import checked_options
from tir_contact.outputs import _RESULT_VERSION, RESULT_FILES
from tir_contact.prepare import (
    INPUT_FILE_OPTIONS,
    _images_in,
    footage_fingerprint,
    input_files,
    resolve_footage,
)
from tir_contact.report import write_report

logger = logging.getLogger(__name__)

__all__ = [
    "FOOTAGE_FILE_SUFFIXES",
    "BatchReport",
    "Footage",
    "VideoStatus",
    "analyze_batch",
    "find_footage",
    "is_current",
]

#: File types that hold a whole video (frame folders are recognised by their images).
FOOTAGE_FILE_SUFFIXES = (".avi", ".mp4", ".mov", ".mkv", ".tif", ".tiff", ".mraw", ".cihx",
                         ".cih", ".cine")


@dataclass(frozen=True)
class Footage:
    """One video to analyse.

    Attributes
    ----------
    path : Path
        What the reader opens (frame folder or file).
    name : str
        Result folder name under the output root.
    """

    path: Path
    name: str


@dataclass
class VideoStatus:
    """Outcome of one video in a batch."""

    name: str
    path: str
    # "done", "resumed" (complete and current, skipped), "partial", "failed",
    # "interrupted" (the batch was stopped before the video's results were written)
    status: str
    message: str = ""
    n_frames: int = 0
    skipped_frames: int = 0
    seconds: float = 0.0
    warnings: list[str] = field(default_factory=list)


@dataclass
class BatchReport:
    """Outcome of a batch; ``ok`` is False when any video failed or lost frames."""

    videos: list[VideoStatus] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return all(v.status in ("done", "resumed") for v in self.videos)

    @property
    def failed(self) -> list[VideoStatus]:
        return [v for v in self.videos if v.status not in ("done", "resumed")]

    def table(self) -> pd.DataFrame:
        """One row per video; the warnings joined by ``"; "``."""
        rows = [{**asdict(v), "warnings": "; ".join(v.warnings)} for v in self.videos]
        return pd.DataFrame(rows, columns=list(VideoStatus.__dataclass_fields__))


# --------------------------------------------------------------------------------------------
# finding footage


def _resolve(path: Path) -> Footage:
    """A user-given path to the footage it means (a clip folder to its frames or video)."""
    inner, name = resolve_footage(path)
    return Footage(inner, name)


def _holds_stacks(folder: Path) -> bool:
    """True when the first image file of `folder` (by name) is a multi-page TIFF: the
    folder then holds stacks, each a video, not one frame per file."""
    try:
        first = min((q for q in folder.iterdir() if q.is_file() and is_image_name(q.name)),
                    default=None)
        if first is None or first.suffix.lower() not in (".tif", ".tiff"):
            return False
        with tifffile.TiffFile(first) as tif:
            return len(tif.pages) > 1
    except Exception:  # unreadable: the folder's reader reports it
        return False


def _walk(root: Path) -> list[Footage]:
    found: list[Footage] = []
    for folder, subdirs, files in os.walk(root):
        here = Path(folder)
        name = here.name or here.resolve().name  # "." names the current folder
        subdirs[:] = sorted(d for d in subdirs if not d.startswith("."))
        inner = clip_footage(here)
        if inner is not None and _images_in(here) == 0:
            found.append(Footage(inner, name))
            subdirs[:] = [d for d in subdirs if here / d != inner]
            files = [f for f in files if here / f != inner]
        elif _images_in(here) > 0 and not _holds_stacks(here):
            found.append(Footage(here, name))  # its sub-folders are walked still
            continue
        elif (here / META_FILENAME).is_file() and not any(
            Path(f).suffix.lower() in FOOTAGE_FILE_SUFFIXES for f in files
        ):
            found.append(Footage(here, name))  # metadata without footage: reported
        for f in sorted(files):
            p = here / f
            if f.startswith(".") or p.suffix.lower() not in FOOTAGE_FILE_SUFFIXES:
                continue
            if p.suffix.lower() in (".cih", ".cihx"):
                continue  # the .mraw beside it is the footage
            found.append(Footage(p, p.stem))
    return found


def _has_subfolder(folder: Path) -> bool:
    try:
        return any(q.is_dir() and not q.name.startswith(".") for q in folder.iterdir())
    except OSError:
        return False


def _unique_names(items: list[Footage]) -> list[Footage]:
    """Make result names unique: a name that collides takes the fewest parent folder
    names that tell its video from the others of that name (``x__clip``, ``y__clip``; a
    parent named as the video itself, as ``clip/clip.tif``, adds nothing and is passed
    over); a numbered suffix where even three parents do not."""
    groups: dict[str, list[int]] = {}
    for i, it in enumerate(items):
        groups.setdefault(it.name, []).append(i)
    names = [it.name for it in items]
    for name, members in groups.items():
        if len(members) == 1:
            continue
        parents = [[p.name for p in items[i].path.parents if p.name and p.name != name]
                   for i in members]
        for i, own in zip(members, parents, strict=True):
            depth = next((d for d in range(1, 4)
                          if sum(ps[:d] == own[:d] for ps in parents) == 1), 3)
            names[i] = "__".join([*reversed(own[:depth]), name])
    return [Footage(it.path, n if names.count(n) == 1 else f"{n}__{i}")
            for i, (it, n) in enumerate(zip(items, names, strict=True))]


def find_footage(
    paths: Sequence[str | os.PathLike[str]], *, recursive: bool = False
) -> list[Footage]:
    """The videos named by `paths`.

    Parameters
    ----------
    paths : sequence of path
        Footage folders or files; with `recursive`, trees searched for them (frame
        folders, video/stack/camera files, synthetic clip folders with a ``meta.json``).
    recursive : bool
        Search folders that are not footage themselves.

    Returns
    -------
    list of Footage
        In the given order, with unique result names.

    Raises
    ------
    FootageError
        A path does not exist, or (without `recursive`) a folder holds no footage.
    """
    items: list[Footage] = []
    for raw in paths:
        p = Path(raw)
        if not p.exists():
            raise FootageError(f"{p}: does not exist", p)
        # walked: a tree that is no footage itself, a folder of stacks, and a frame folder
        # with sub-folders (a stray image beside clip folders must not hide them)
        images = p.is_dir() and recursive and _images_in(p) > 0
        if p.is_dir() and recursive and (
                (not images and clip_footage(p) is None)
                or (images and (_holds_stacks(p) or _has_subfolder(p)))):
            found = _walk(p)
            if not found:
                raise FootageError(f"{p}: no footage found in the tree", p)
            items.extend(found)
        else:
            items.append(_resolve(p))
    return _unique_names(_drop_repeats(items))


def _drop_repeats(items: list[Footage]) -> list[Footage]:
    """The footage once each, in first-given order: the same video given twice (``run1``
    and ``./run1/``, or a file inside a tree also searched) would be analysed twice and
    written under two names; each repeat is logged as a warning."""
    seen: set[Path] = set()
    out = []
    for it in items:
        key = it.path.resolve()
        if key in seen:
            logger.warning("%s: given more than once; analysed once", it.path)
            continue
        seen.add(key)
        out.append(it)
    return out


# --------------------------------------------------------------------------------------------
# running


def is_current(footage: Footage, out: Path, *, options: AnalysisOptions | None = None,
               overrides: Mapping[str, Any] | None = None) -> bool:
    """True when ``out/<name>`` holds complete results of this footage as it is now.

    With `options` (and `overrides`, the command line's metadata values), the results must
    also have been made with the same analysis options (the same ``--reference`` and
    ``--lit-mask`` files, however their paths are spelled) and the same metadata, that of
    ``meta.json`` with these overrides: ``--resume`` after ``--contrast 0.5`` was added, or
    after an ``--mm-per-px`` was dropped, reanalyses; it does not keep the old numbers.
    """
    folder = out / footage.name
    if not all((folder / f).is_file() for f in RESULT_FILES):
        return False
    try:
        summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
        fingerprint = footage_fingerprint(footage.path)
    except (OSError, ValueError):
        return False
    current = (summary.get("complete") is True
               and summary.get("result_version") == _RESULT_VERSION
               and summary.get("fingerprint") == fingerprint
               and not summary.get("skipped_frames")
               and not summary.get("lost_frames"))
    if not current or options is None:
        return current
    changed = _changed_settings(footage, summary, options, overrides)
    if changed:
        logger.info("%s: results made with other %s; analysed again", footage.path,
                    ", ".join(changed))
    return not changed


def _changed_settings(footage: Footage, summary: Mapping[str, Any], options: AnalysisOptions,
                      overrides: Mapping[str, Any] | None) -> list[str]:
    """What of this run differs from what ``summary.json`` recorded: analysis options (by
    field name; a file option by the file itself, resolved path, size and time), and the
    metadata this run would use (``meta.json`` with these overrides: an override given
    then and dropped now counts too)."""
    stored = summary.get("options") or {}
    files_then = summary.get("input_files")
    files_now = input_files(options)
    changed = []
    for key, value in json_safe(asdict(options)).items():
        if key in INPUT_FILE_OPTIONS and files_then is not None:
            differs = files_then.get(key) != files_now.get(key)
        else:
            differs = stored.get(key, value) != value
        if differs:
            changed.append(f"option {key}")
    meta_then = summary.get("meta") or {}
    try:
        meta_now = json_safe(load_meta(footage.path, overrides, frame_rate=meta_then.get("fps")))
    except (FootageError, ValueError, OSError):
        return [*changed, "metadata (it cannot be read now)"]
    changed += [f"metadata {key}" for key in sorted(set(meta_then) | set(meta_now))
                if not _same(meta_then.get(key), meta_now.get(key))]
    return changed


def _same(a: Any, b: Any) -> bool:
    """Equal, numbers to a relative 1e-9 (a value written to JSON and read back), dicts and
    lists item by item."""
    if isinstance(a, dict) and isinstance(b, dict):
        return set(a) == set(b) and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if (isinstance(a, int | float) and isinstance(b, int | float)
            and not isinstance(a, bool) and not isinstance(b, bool)):
        return math.isclose(float(a), float(b), rel_tol=1e-9, abs_tol=1e-15)
    return a == b


def _resumed(footage: Footage, out: Path) -> VideoStatus:
    """The status of a video whose results are complete and current, from its summary."""
    summary = json.loads((out / footage.name / "summary.json").read_text(encoding="utf-8"))
    return VideoStatus(footage.name, str(footage.path), "resumed",
                       "results complete and current",
                       n_frames=int(summary.get("n_frames_analysed", 0)),
                       warnings=list(summary.get("warnings", [])))


def _run_one(footage: Footage, out: str, overrides: Mapping[str, Any] | None,
             options: AnalysisOptions, progress: bool | None, position: int) -> VideoStatus:
    """Analyse one video, turning any failure into a status (runs in a worker)."""
    t0 = time.perf_counter()
    path = str(footage.path)
    try:
        result = analyze_video(footage.path, out, overrides=overrides, options=options,
                               name=footage.name, progress=progress,
                               progress_position=position)
    except (FootageError, ValueError, OSError) as exc:
        return VideoStatus(footage.name, path, "failed", _message(exc, path),
                           seconds=time.perf_counter() - t0)
    except Exception as exc:  # a bug must not lose the other videos' results
        logger.debug("%s", traceback.format_exc())
        return VideoStatus(footage.name, path, "failed",
                           f"{type(exc).__name__}: {_message(exc, path)}",
                           seconds=time.perf_counter() - t0)
    skipped = result.skipped
    lost = result.summary.get("lost_frames") or []
    status = "partial" if skipped or lost else "done"
    parts = []
    if lost:
        parts.append(f"{len(lost)} frame(s) lost from the container: {_numbers(lost)}")
    if skipped:
        parts.append(f"{len(skipped)} frame(s) skipped, first: "
                     f"{_message(skipped[0]['reason'], path)}")
    return VideoStatus(footage.name, path, status, "; ".join(parts),
                       n_frames=len(result.frames), skipped_frames=len(skipped),
                       seconds=time.perf_counter() - t0,
                       warnings=list(result.summary.get("warnings", [])))


def _numbers(values: Sequence[int], most: int = 8) -> str:
    """``"40-99"`` or ``"3, 7, 12, ... (20 in all)"``: frame numbers in a message."""
    values = sorted(int(v) for v in values)
    if values and values[-1] - values[0] == len(values) - 1 and len(values) > 2:
        return f"{values[0]}-{values[-1]}"
    text = ", ".join(str(v) for v in values[:most])
    return text + (f", ... ({len(values)} in all)" if len(values) > most else "")


def _message(exc: BaseException | str, path: str) -> str:
    """One line, without the video's own path in front (the report names it once)."""
    text = one_line(exc, limit=None)
    for prefix in (f"{path}: ", f"{path}{os.sep}", f"{Path(path).name}: "):
        text = text.removeprefix(prefix)
    return text


def analyze_batch(
    footage: Iterable[Footage],
    out: str | os.PathLike[str],
    *,
    overrides: Mapping[str, Any] | None = None,
    options: AnalysisOptions | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    progress: bool | None = None,
    on_done: Callable[[VideoStatus], None] | None = None,
    html: bool = True,
) -> BatchReport:
    """Analyse several videos; each result lands in ``out/<name>/`` as soon as it is done.

    Parameters
    ----------
    footage : iterable of Footage
        From :func:`find_footage`.
    out : path
        Output root.
    overrides : mapping, optional
        Metadata given on the command line, for every video.
    options : AnalysisOptions, optional
        Analysis settings.
    workers : int, optional
        Local worker processes (default: all cores; 1 runs in this process).
    scheduler : str, optional
        Address of a running ``dask.distributed`` scheduler (``tcp://host:8786``); the
        videos are then analysed on that cluster. Needs the ``dask`` extra.
    resume : bool
        Skip videos whose results are complete and current (:func:`is_current`).
    progress : bool or None
        True: progress bars (per video too with one worker). None: bars on a terminal,
        otherwise one plain line per finished video on stderr. False: neither.
    on_done : callable, optional
        Called with each video's status as it finishes.
    html : bool
        Write ``out/report.html`` at the end (also when interrupted), from every result in
        `out` (:func:`tir_contact.report.write_report`).

    Returns
    -------
    BatchReport
        Also written to ``out/batch_report.json`` and ``out/batch_report.csv``.
    """
    options = checked_options(options)
    out_path = Path(out)
    out_path.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(out_path)
    items = list(footage)
    report = BatchReport()
    started = time.time()  # results written after this are this batch's
    todo: list[Footage] = []
    for it in items:
        if resume and is_current(it, out_path, options=options, overrides=overrides):
            report.videos.append(_resumed(it, out_path))
        else:
            todo.append(it)
    n_workers = max(1, workers if workers is not None else (os.cpu_count() or 1))
    n_workers = min(n_workers, max(1, len(todo)))
    bars = show_progress(progress)
    lines = progress is None and not bars
    # per-video bars only where they cannot interleave (one worker, a terminal)
    video_progress = bars and n_workers == 1 and scheduler is None
    bar: Any = None  # made after the workers started: its display thread must not be forked

    def finish(status: VideoStatus) -> None:
        nonlocal bar
        report.videos.append(status)
        if bar is None:
            bar = _bar(len(items), len(items) - len(todo), bars)
        bar.update(1)
        _log(status, scheduler is not None)
        if lines:
            _print_line(status, len(report.videos), len(items))
        if on_done is not None:
            on_done(status)
        _write_report(report, out_path, items)

    def start_bar() -> None:
        nonlocal bar
        bar = _bar(len(items), len(items) - len(todo), bars)

    with one_interrupt():  # a second Ctrl-C cannot cut the clean-up short
        try:
            if scheduler is not None:
                _run_dask(todo, out_path, overrides, options, scheduler, finish)
            elif n_workers == 1:
                start_bar()
                for it in todo:
                    finish(_run_one(it, str(out_path), overrides, options, video_progress, 1))
            else:
                _run_local(todo, out_path, overrides, options, n_workers, finish, start_bar)
        except KeyboardInterrupt:
            # the workers are ended (_run_local); what they wrote is on disk, nothing else
            remove_stale_temporaries(out_path)
            _settle_interrupted(report, todo, out_path, started)
            _write_report(report, out_path, items, html)
            raise
        finally:
            if bar is not None:
                bar.close()
    _write_report(report, out_path, items, html)
    return report


def _run_local(todo: list[Footage], out: Path, overrides: Mapping[str, Any] | None,
               options: AnalysisOptions, n_workers: int,
               finish: Callable[[VideoStatus], None], started: Callable[[], None]) -> None:
    """Analyse `todo` in `n_workers` local processes, calling `finish` as each ends.

    On any exception here (Ctrl-C included) the queued videos are cancelled and the workers
    ended at once (:func:`tir_contact._workers.end_workers`) before it goes on.
    """
    before = _workers.children()
    pool = ProcessPoolExecutor(max_workers=n_workers, mp_context=_workers.context(),
                               initializer=_workers.init_worker, initargs=(os.getpid(),))
    try:
        futures = {pool.submit(_run_one, it, str(out), overrides, options, False, 0): it
                   for it in todo}
        started()
        for fut in as_completed(futures):
            it = futures[fut]
            try:
                status = fut.result()
            except Exception as exc:  # worker crashed (e.g. killed)
                status = VideoStatus(it.name, str(it.path), "failed",
                                     f"worker failed: {_message(exc, str(it.path))}")
            finish(status)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        _workers.end_workers(before)
        raise
    pool.shutdown(wait=True)


def _settle_interrupted(report: BatchReport, todo: list[Footage], out: Path,
                        started: float) -> None:
    """After an interrupt: each video of `todo` not yet in `report` gets its status from
    the results this batch wrote for it (a worker may have finished as the interrupt came),
    or ``interrupted``."""
    have = {v.name for v in report.videos}
    for it in todo:
        if it.name in have:
            continue
        path = out / it.name / "summary.json"
        try:
            written = path.stat().st_mtime >= started - 0.01  # file times are coarse
            summary = json.loads(path.read_text(encoding="utf-8")) if written else None
        except (OSError, ValueError):
            summary = None
        if summary is None:
            report.videos.append(VideoStatus(
                it.name, str(it.path), "interrupted",
                "the batch was interrupted before this video's results were written"))
            continue
        lost = summary.get("lost_frames") or []
        skipped = summary.get("skipped_frames") or []
        report.videos.append(VideoStatus(
            it.name, str(it.path), "partial" if lost or skipped else "done",
            "written as the batch was interrupted (status from its summary.json)",
            n_frames=int(summary.get("n_frames_analysed", 0)), skipped_frames=len(skipped),
            warnings=list(summary.get("warnings", []))))


#: Warnings a local reader has already logged as it opened the footage (a container cut
#: short): the console shows them once; summary.json and the report keep them.
_LOGGED_BY_READER = ("the container was cut short",)


#: The part of a partial video's message that names its skipped frames (:func:`_run_one`).
_SKIPPED = re.compile(r"\d+ frame\(s\) skipped, first: .*$", re.DOTALL)


def _log(status: VideoStatus, remote: bool) -> None:
    """Print a finished video's failure and warnings once (``ERROR:`` / ``WARNING:``)."""
    if status.status == "failed":
        logger.error("%s: %s", status.path, status.message)
    skipped = _SKIPPED.search(status.message) if status.status == "partial" else None
    if skipped is not None:  # lost frames are said by the reader or among the warnings
        logger.warning("%s: %s", status.path, skipped.group(0))
    for text in status.warnings:
        if remote or not text.startswith(_LOGGED_BY_READER):
            logger.warning("%s: %s", status.path, text)


def _bar(total: int, done: int, show: bool) -> Any:
    """The bar over the videos, starting at the `done` ones resumed."""
    return progress_bar(total, progress=show, desc="videos", unit="video", initial=done,
                        position=0)


def _print_line(status: VideoStatus, done: int, total: int) -> None:
    """One plain line per finished video (progress where stderr is not a terminal)."""
    text = f"[{done}/{total}] {status.status}: {status.name}"
    if status.status in ("done", "partial"):
        text += f" ({status.n_frames} frames, {status.seconds:.1f} s)"
    # a failure's message was printed as an ERROR line, lost frames as a WARNING line
    if status.message and status.status not in ("failed", "partial"):
        text += f": {status.message}"
    print(text, file=sys.stderr, flush=True)


def _run_dask(todo: list[Footage], out: Path, overrides: Mapping[str, Any] | None,
              options: AnalysisOptions, scheduler: str,
              finish: Callable[[VideoStatus], None]) -> None:
    try:
        from dask.distributed import Client, as_completed
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(
            "--scheduler needs dask.distributed: pip install 'tir-contact[dask]'"
        ) from exc
    with Client(scheduler) as client:
        futures = {
            client.submit(_run_one, it, str(out), overrides, options, False, 0, pure=False): it
            for it in todo
        }
        try:
            for fut in as_completed(list(futures)):
                it = futures[fut]
                try:
                    status = fut.result()
                except Exception as exc:
                    status = VideoStatus(it.name, str(it.path), "failed",
                                         f"worker failed: {_message(exc, str(it.path))}")
                finish(status)
        except BaseException:
            client.cancel(list(futures))  # no new video starts on the cluster
            raise


def _write_report(report: BatchReport, out: Path, items: list[Footage],
                  html: bool = False) -> None:
    order = {it.name: i for i, it in enumerate(items)}
    report.videos.sort(key=lambda v: order.get(v.name, len(order)))
    write_json(out / "batch_report.json",
               {"ok": report.ok, "videos": [asdict(v) for v in report.videos]})
    table = report.table()
    atomic_write(out / "batch_report.csv",
                 lambda tmp: table.to_csv(tmp, index=False, lineterminator="\n"))
    if html:
        try:
            write_report(out)
        except (OSError, ValueError) as exc:  # the results and the batch report stand
            logger.error("%s: report.html not written: %s", out, one_line(exc, limit=None))
