"""``report.html`` of an analysis folder (``tir-contact analyze --out DIR``), from disk.

The clips are the result folders (``DIR/<name>/summary.json``) and the videos of
``DIR/batch_report.json`` (which knows the failed and interrupted ones); a folder merged in
from another run, or a batch report from an older version, is read as it is. Thumbnails and
plots go to ``DIR/report_files/<name>/`` and are made again only when their source changed.
"""

from __future__ import annotations

import json
import os
import re
import zlib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any
from urllib.parse import quote

import cv2
import numpy as np
import pandas as pd

from tir_common.atomic import atomic_write
from tir_common.naming import natural_key
from tir_contact import __version__
from tir_contact.report._html import Cell, esc, fmt, link, page, table
from tir_contact.report._svg import time_series_svg

__all__ = ["ASSETS", "Clip", "collect_clips", "write_analysis_report"]

#: Folder of the report's thumbnails and plots, beside ``report.html``.
ASSETS = "report_files"
#: Thumbnail width, px (the overlay images are 256 px high and more).
THUMB_WIDTH_PX = 240
#: Order of the clips by default: the ones to look at first.
RANK = {"failed": 0, "interrupted": 1, "partial": 2, "warned": 3, "done": 4}
#: Result files a card links to, when present.
LINKED = ("frames.csv", "elements.csv", "regions.csv", "frames.parquet", "elements.parquet",
          "regions.parquet", "summary.json", "lit_mask.png", "contact.png", "elements.png",
          "deflection.png", "overlay.avi")
#: Steady per-element quantities, in the order of the card's table.
ELEMENT_QUANTITIES = (("contact_area_mm2", "area (mm²)"),
                      ("contact_length_mm", "contact length (mm)"),
                      ("liftoff_mm", "lift-off (mm)"),
                      ("deflection_angle_deg", "deflection angle (°)"),
                      ("tip_deflection_mm", "tip deflection (mm)"),
                      ("front_peak_contrast", "front-peak contrast"),
                      ("front_peak_width_mm", "front-peak width (mm)"))


@dataclass
class Clip:
    """One clip of the report: its status (batch report or summary) and results."""

    name: str
    status: str  # done, partial, failed, interrupted
    message: str = ""
    video: str = ""
    warnings: list[str] = field(default_factory=list)
    seconds: float | None = None
    summary: dict[str, Any] | None = None
    folder: Path | None = None

    @property
    def anchor(self) -> str:
        """The id of its card: the name with anything but letters, digits, ``-``, ``_`` and
        ``.`` as ``_`` and a short hash of the name (two names never share one)."""
        slug = re.sub(r"[^A-Za-z0-9_.-]", "_", self.name)
        return f"clip-{slug}-{zlib.crc32(self.name.encode()):08x}"

    @property
    def rank(self) -> int:
        """Default order: failed, interrupted, partial, warned, done."""
        key = "warned" if self.status == "done" and self.warnings else self.status
        return RANK.get(key, 0)


class NoResultsError(ValueError):
    """A folder without analysis results (:func:`write_analysis_report`)."""


def _read_json(path: Path) -> Any:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def collect_clips(folder: Path) -> list[Clip]:
    """The clips of an analysis folder: its batch report's videos and its result folders.

    A video the batch report calls ``resumed`` is ``done``; a result folder the batch
    report does not know takes its status from its summary (``complete``: done, otherwise
    partial).
    """
    folder = Path(folder)
    report = _read_json(folder / "batch_report.json") or {}
    clips: dict[str, Clip] = {}
    for v in report.get("videos", []) if isinstance(report, dict) else []:
        status = "done" if v.get("status") == "resumed" else str(v.get("status", "failed"))
        clips[str(v["name"])] = Clip(str(v["name"]), status, str(v.get("message") or ""),
                                     str(v.get("path", "")), list(v.get("warnings") or []),
                                     v.get("seconds") if status != "interrupted" else None)
    for entry in os.scandir(folder):
        if not entry.is_dir() or entry.name.startswith(".") or entry.name == ASSETS:
            continue
        summary = _read_json(Path(entry.path) / "summary.json")
        if not isinstance(summary, dict):
            continue
        clip = clips.get(entry.name)
        if clip is None:
            done = summary.get("complete") is not False and not summary.get("lost_frames") \
                and not summary.get("skipped_frames")
            clip = clips[entry.name] = Clip(entry.name, "done" if done else "partial",
                                            video=str(summary.get("video", "")),
                                            warnings=list(summary.get("warnings") or []))
        clip.summary, clip.folder = summary, Path(entry.path)
    return sorted(clips.values(), key=lambda c: (c.rank, natural_key(c.name)))


def _steady(summary: dict[str, Any] | None, key: str) -> float | None:
    """A steady mean from the summary (``{"mean": x}`` or a bare number), None if absent."""
    if not summary:
        return None
    value = (summary.get("steady") or {}).get(key, summary.get(key))
    if isinstance(value, dict):
        value = value.get("mean")
    return value if isinstance(value, int | float) else None


def _area_cell(summary: dict[str, Any] | None) -> Cell:
    """Steady contact area, with its low-high band where the summary gives one."""
    mean = _steady(summary, "contact_area_mm2")
    low = _steady(summary, "contact_area_low_mm2")
    high = _steady(summary, "contact_area_high_mm2")
    text = esc(fmt(mean))
    if low is not None and high is not None:
        text += f' <span class="muted">({esc(fmt(low))}–{esc(fmt(high))})</span>'
    return Cell(text, "" if mean is None else mean, "num")


def _num(value: Any, digits: int = 4) -> Cell:
    ok = isinstance(value, int | float) and np.isfinite(value)
    return Cell(esc(fmt(value, digits)), value if ok else "", "num")


def _row(c: Clip) -> tuple[list[Cell], str]:
    s = c.summary or {}
    status = c.status + (" (warned)" if c.rank == RANK["warned"] else "")
    seconds = c.seconds
    if seconds is None and s.get("frames_per_s"):
        seconds = s.get("n_frames_analysed", 0) / s["frames_per_s"]
    warn = f'<span title="{esc(chr(10).join(c.warnings))}">{len(c.warnings)}</span>' \
        if c.warnings else ""
    row = [Cell(link(f"#{c.anchor}", c.name), c.name),
           Cell(esc(status), c.rank),
           Cell(warn, len(c.warnings), "num"),
           Cell(esc(s.get("view", "")), s.get("view", "")),
           Cell(esc(s.get("camera", "")), s.get("camera", "")),
           _num(s.get("lit_fraction"), 3),
           _area_cell(c.summary),
           _num(_steady(c.summary, "contact_ratio"), 3),
           _num(_steady(c.summary, "deflection_angle_deg"), 3),
           _num(s.get("n_frames_analysed")),
           _num(seconds, 2)]
    cls = {0: "failed", 1: "interrupted", 2: "partial", 3: "warned"}.get(c.rank, "")
    return row, cls


def _fresh(target: Path, source: Path) -> bool:
    """True when `target` exists and is not older than `source`."""
    try:
        return target.stat().st_mtime >= source.stat().st_mtime
    except OSError:
        return False


def _thumbnails(clip: Clip, assets: Path, root: Path) -> str:
    """Three overlay thumbnails (first, middle, last), each a link to the full image."""
    overlays = sorted((clip.folder / "overlays").glob("frame_*.png")) if clip.folder else []
    if not overlays:
        return '<p class="muted">no overlay images (analysed with --overlay-frames 0)</p>'
    picks = sorted({0, len(overlays) // 2, len(overlays) - 1})
    out = []
    for k in picks:
        src = overlays[k]
        thumb = assets / (src.stem + ".jpg")
        img = None if _fresh(thumb, src) else cv2.imread(str(src), cv2.IMREAD_COLOR)
        if img is not None:
            h = max(1, round(img.shape[0] * THUMB_WIDTH_PX / img.shape[1]))
            small = cv2.resize(img, (THUMB_WIDTH_PX, h), interpolation=cv2.INTER_AREA)
            atomic_write(thumb, lambda tmp, small=small: _write_jpeg(tmp, small))
        else:
            small = cv2.imread(str(thumb), cv2.IMREAD_GRAYSCALE)
            h = small.shape[0] if small is not None else THUMB_WIDTH_PX // 2
        href, small_href = (quote(p.relative_to(root).as_posix()) for p in (src, thumb))
        out.append(f'<a href="{esc(href)}"><img src="{esc(small_href)}"'
                   f' width="{THUMB_WIDTH_PX}" height="{h}" loading="lazy" '
                   f'alt="{esc(clip.name)} {esc(src.stem)}"></a>')
    return '<div class="thumbs">' + "".join(out) + "</div>"


def _write_jpeg(tmp: Path, img: np.ndarray) -> None:
    ok, data = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, 85])
    if not ok:
        raise OSError(f"{tmp}: JPEG encoding failed")
    Path(tmp).write_bytes(data.tobytes())


#: Columns of ``frames.csv`` the plot shows, with their labels.
PLOTTED = (("contact_area_mm2", "contact area (mm²)"), ("contact_ratio", "contact ratio (–)"),
           ("deflection_angle_deg", "deflection angle (°)"))


def _plot(clip: Clip, assets: Path, root: Path) -> str:
    """The clip's contact area, ratio and deflection angle over time (SVG)."""
    frames_csv = clip.folder / "frames.csv" if clip.folder else None
    if frames_csv is None or not frames_csv.is_file():
        return ""
    svg = assets / "timeseries.svg"
    if not _fresh(svg, frames_csv):
        wanted = {"time_s", "block_fully_in_view", *(c for c, _ in PLOTTED)}
        frames = pd.read_csv(frames_csv, usecols=lambda c: c in wanted)
        panels = [(label, frames[c].to_numpy(float)) for c, label in PLOTTED
                  if c in frames and frames[c].notna().any()]
        if not panels or "time_s" not in frames:
            return '<p class="muted">nothing to plot: no contact in any frame</p>'
        t_ms = frames["time_s"].to_numpy(float) * 1e3
        full = frames.get("block_fully_in_view")
        shade = None
        if full is not None and full.astype(bool).any():
            sel = t_ms[full.astype(bool).to_numpy()]
            shade = (float(sel.min()), float(sel.max()))
        text = time_series_svg(t_ms, panels, shade)
        atomic_write(svg, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
    return (f'<img class="plot" src="{esc(quote(svg.relative_to(root).as_posix()))}" '
            f'loading="lazy" alt="{esc(clip.name)}: contact over time">')


def _elements_table(summary: dict[str, Any] | None) -> str:
    per = ((summary or {}).get("steady") or {}).get("elements") or {}
    if not per:
        return ""
    cols = [(k, label) for k, label in ELEMENT_QUANTITIES
            if any(k in v for v in per.values())]
    rows = [[Cell(esc(e), None, "num"), *(_num(v.get(k)) for k, _ in cols)]
            for e, v in sorted(per.items(), key=lambda kv: int(kv[0]))]
    return ("<h3>Steady, per element (frames with the whole block in view)</h3>"
            + table(["element", *(label for _, label in cols)], rows))


def _card(clip: Clip, root: Path) -> str:
    parts = [f'<div class="card" id="{clip.anchor}"><h2>{esc(clip.name)} '
             f'<span class="{"err" if clip.rank < 3 else "muted"}">{esc(clip.status)}</span>'
             "</h2>"]
    if clip.video:
        parts.append(f'<div class="muted">{esc(clip.video)}</div>')
    if clip.message:
        parts.append(f'<p class="err">{esc(clip.message)}</p>')
    if clip.warnings:
        parts.append('<ul class="warnings warn">'
                     + "".join(f"<li>{esc(w)}</li>" for w in clip.warnings) + "</ul>")
    if clip.folder is None:
        parts.append('<p class="muted">no results written</p></div>')
        return "".join(parts)
    assets = root / ASSETS / clip.name
    assets.mkdir(parents=True, exist_ok=True)
    parts.append(_thumbnails(clip, assets, root))
    parts.append(_plot(clip, assets, root))
    parts.append(_elements_table(clip.summary))
    present = set(os.listdir(clip.folder))
    links = [link(f"{clip.name}/{f}", f) for f in LINKED if f in present]
    parts.append("<p>" + " · ".join(links) + "</p></div>")
    return "".join(parts)


def _cards(clips: list[Clip], root: Path) -> list[str]:
    """The cards of `clips`, in order, made in threads (decoding the overlay images, most of
    the time, runs outside Python's lock: about one core's worth of speed-up per core)."""
    with ThreadPoolExecutor(max_workers=min(8, os.cpu_count() or 1)) as pool:
        return list(pool.map(lambda c: _card(c, root), clips))


HEADER = ["clip", "status", "warnings", "view", "camera", "lit fraction",
          "steady area (mm²) (low–high)", "contact ratio", "deflection (°)", "frames",
          "time (s)"]


def write_analysis_report(folder: str | os.PathLike[str]) -> Path:
    """Write ``folder/report.html`` of the analysis results in `folder` (from disk).

    Parameters
    ----------
    folder : path
        An ``analyze --out`` folder.

    Returns
    -------
    Path
        The report.

    Raises
    ------
    ValueError
        `folder` holds no batch report and no result folder.
    """
    root = Path(folder)
    clips = collect_clips(root)
    if not clips:
        raise NoResultsError(f"{root}: no analysis results (no batch_report.json, no "
                             "<clip>/summary.json)")
    counts: dict[str, int] = {}
    for c in clips:
        counts[c.status] = counts.get(c.status, 0) + 1
    warned = sum(1 for c in clips if c.warnings)
    rows = [_row(c) for c in clips]
    head = (f"<h1>Contact analysis: {esc(root.resolve().name)}</h1>"
            f'<p>{len(clips)} clip(s): '
            + ", ".join(f"{n} {esc(s)}" for s, n in sorted(counts.items()))
            + f"; {warned} with warnings. "
            f'<span class="muted">Built {datetime.now(UTC):%Y-%m-%d %H:%M} UTC by '
            f"tir-contact {esc(__version__)}; rebuild with <code>tir-contact report "
            f"{esc(root)}</code>. Click a column to sort.</span></p>")
    body = (head + table(HEADER, [r for r, _ in rows], sortable=True,
                         row_classes=[cls for _, cls in rows])
            + "".join(_cards(clips, root)))
    text = page(f"Contact analysis: {root.resolve().name}", body, script=True)
    return atomic_write(root / "report.html",
                        lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
