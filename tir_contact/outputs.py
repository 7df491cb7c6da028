"""After the last frame: the result tables, ``summary.json``, overlays and writing them.

The tables are collected frame by frame (:class:`Tables`), built once at the end, and written
with the summary, overlay images and optional plots, Parquet copies and overlay video into a
staging folder that is moved into place when complete (:func:`write_results`).
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pandas as pd

from tir_common.atomic import write_json
from tir_contact import __version__
from tir_contact._outdir import replace_folder, staging_folder, temporary_name
from tir_contact._readers import FootageError
from tir_contact.features import ELEMENT_DTYPE, ELEMENT_FIELDS, FRAME_KEYS, element_records
from tir_contact.options import AnalysisOptions
from tir_contact.prepare import VideoSetup, footage_fingerprint, input_files

__all__ = [
    "ELEMENT_COLUMNS",
    "FRAME_COLUMNS",
    "REGION_COLUMNS",
    "RESULT_FILES",
    "Tables",
    "VideoAnalysis",
    "footage_warnings",
    "write_results",
]

#: Columns of ``frames.csv``, in order: the frame and its time, the per-frame features
#: (:data:`tir_contact.features.FRAME_KEYS`, with the video's ``block_fully_in_view`` after the
#: block's front peak) and whether the contact touches the lit zone's rim.
FRAME_COLUMNS = [
    "frame",
    "time_s",
    *FRAME_KEYS[:7],
    "block_fully_in_view",
    *FRAME_KEYS[7:],
    "contact_at_lit_rim",
    "contact_area_low_mm2",
    "contact_area_high_mm2",
]

#: Columns of ``elements.csv``, in order (element 0 leads): the frame and its time, then
#: :data:`tir_contact.features.ELEMENT_FIELDS`.
ELEMENT_COLUMNS = ["frame", "time_s", *ELEMENT_FIELDS]

#: Columns of ``regions.csv`` (every contact region, no geometry needed).
REGION_COLUMNS = [
    "frame",
    "time_s",
    "region",
    "area_mm2",
    "centroid_x_mm",
    "centroid_y_mm",
    "bbox_x0_mm",
    "bbox_y0_mm",
    "bbox_width_mm",
    "bbox_height_mm",
    "mean_darkness",
    "at_lit_rim",
]

#: Files that make a result complete (``--resume`` checks them).
RESULT_FILES = ("frames.csv", "elements.csv", "summary.json")

_RESULT_VERSION = 1


@dataclass
class VideoAnalysis:
    """Result of :func:`analyze_video`.

    Attributes
    ----------
    frames : pandas.DataFrame
        One row per analysed frame (:data:`FRAME_COLUMNS`).
    elements : pandas.DataFrame
        One row per frame and element in contact or in view (:data:`ELEMENT_COLUMNS`).
    regions : pandas.DataFrame or None
        One row per frame and contact region (TIR view; :data:`REGION_COLUMNS`); None when
        not computed (see :attr:`AnalysisOptions.regions`).
    summary : dict
        What ``summary.json`` holds: steady values, reference, skipped frames, settings.
    out_dir : Path or None
        Where the results were written.
    """

    frames: pd.DataFrame
    elements: pd.DataFrame
    regions: pd.DataFrame | None
    summary: dict[str, Any]
    out_dir: Path | None = None
    skipped: list[dict[str, Any]] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """True when every frame was analysed."""
        return not self.skipped


def _reorder(df: pd.DataFrame, columns: list[str]) -> pd.DataFrame:
    """`columns` first (NaN where missing), then any further columns (`df` itself when it
    holds exactly `columns`, in order)."""
    if list(df.columns) == columns:
        return df
    for c in columns:
        if c not in df.columns:
            df[c] = np.nan
    return df[columns + [c for c in df.columns if c not in columns]]


def _concat(parts: list[pd.DataFrame], columns: list[str]) -> pd.DataFrame:
    parts = [p for p in parts if len(p)]
    return _reorder(pd.concat(parts, ignore_index=True) if parts else pd.DataFrame(), columns)


class Tables:
    """Collects the :class:`~tir_contact.frame.FrameResult` of each frame of one video and
    builds its tables once at the end."""

    def __init__(self, setup: VideoSetup, want_regions: bool) -> None:
        self.setup = setup
        self.want_regions = want_regions
        self.rows: list[dict] = []
        self._el_rows: list[tuple] = []  # TIR element tuples of every frame
        self._el_frames: list[int] = []
        self._el_tables: list[pd.DataFrame] = []  # side-view element tables
        self._regions: list[dict] = []

    def add(self, result: Any) -> None:
        """Add one frame's result."""
        self.rows.append(result.row)
        el = result.elements
        if isinstance(el, pd.DataFrame):
            self._el_tables.append(el)
        elif el:
            self._el_rows += el
            self._el_frames += [result.row["frame"]] * len(el)
        if result.regions is not None:
            self._regions.append(result.regions)

    def frames(self) -> pd.DataFrame:
        """``frames.csv``: one row per frame (:data:`FRAME_COLUMNS` first)."""
        if self.rows and self.rows[0].keys() == set(FRAME_COLUMNS):  # exactly those columns
            return pd.DataFrame({c: [r[c] for r in self.rows] for c in FRAME_COLUMNS})
        return _reorder(pd.DataFrame(self.rows), FRAME_COLUMNS)

    def elements(self) -> pd.DataFrame:
        """``elements.csv``: one row per frame and element (:data:`ELEMENT_COLUMNS` first),
        from the element records (TIR) or the element tables (side view) of the frames."""
        if self._el_tables:
            return _concat(self._el_tables, ELEMENT_COLUMNS)
        return _records_table(self._el_rows, self._el_frames, self.setup.fps)

    def regions(self) -> pd.DataFrame | None:
        """``regions.csv`` (:data:`REGION_COLUMNS`), None when regions are not wanted."""
        return _regions_table(self._regions, self.setup) if self.want_regions else None


def _records_table(rows: list[tuple], frames: list[int], fps: float) -> pd.DataFrame:
    """The elements table from the element tuples of every frame, built once."""
    # no rows: the columns typed all the same (int frame and element, float values), so
    # that arithmetic on an empty table works as on a full one
    rec = element_records(rows) if rows else np.zeros(0, ELEMENT_DTYPE)
    frame = np.array(frames, dtype=np.int64)
    data = {"frame": frame, "time_s": frame / fps}
    data.update({name: rec[name] for name in rec.dtype.names})
    return _reorder(pd.DataFrame(data), ELEMENT_COLUMNS)


def _regions_table(regions: list[dict], setup: VideoSetup) -> pd.DataFrame:
    """``regions.csv`` in mm from the per-frame region arrays."""
    if not regions:
        return pd.DataFrame(columns=REGION_COLUMNS)
    cat = {key: np.concatenate([r[key] for r in regions]) for key in regions[0]}
    mm, mm2 = setup.mm_per_px, setup.mm_per_px ** 2
    return pd.DataFrame({
        "frame": cat["frame"], "time_s": cat["frame"] / setup.fps, "region": cat["label"],
        "area_mm2": cat["area_px"] * mm2,
        "centroid_x_mm": (cat["centroid_x_px"] + 0.5) * mm,
        "centroid_y_mm": (cat["centroid_y_px"] + 0.5) * mm,
        "bbox_x0_mm": cat["bbox_x0_px"] * mm, "bbox_y0_mm": cat["bbox_y0_px"] * mm,
        "bbox_width_mm": cat["bbox_width_px"] * mm, "bbox_height_mm": cat["bbox_height_px"] * mm,
        "mean_darkness": cat["mean_darkness"],
        "at_lit_rim": cat["at_lit_rim"].astype(bool),
    }, columns=REGION_COLUMNS)


def _steady(frames: pd.DataFrame, elements: pd.DataFrame) -> dict[str, Any]:
    """Means and standard deviations over the frames with the whole block in view.

    Each mean and standard deviation is pandas' own (``Series.mean``, ``Series.std``) of
    the selected values, without building the selected tables and groups.
    """
    full = frames["block_fully_in_view"].to_numpy().astype(bool)
    out: dict[str, Any] = {"n_frames": int(full.sum())}
    for col in ("contact_area_mm2", "contact_area_low_mm2", "contact_area_high_mm2",
                "contact_ratio", "front_peak_contrast", "deflection_angle_deg",
                "tip_deflection_mm"):
        if col not in frames:
            continue
        values = pd.Series(frames[col].to_numpy()[full])
        finite = int(values.notna().sum())
        if finite:
            out[col] = {"mean": float(values.mean()),
                        "std": float(values.std(ddof=1)) if finite > 1 else 0.0}
    if out["n_frames"] and len(elements):
        frame_no = elements["frame"].to_numpy()
        sel = np.isin(frame_no, frames["frame"].to_numpy()[full])
        element = elements["element"].to_numpy()
        columns = [c for c in ("contact_area_mm2", "contact_length_mm", "front_peak_contrast",
                               "liftoff_mm", "deflection_angle_deg", "tip_deflection_mm",
                               "front_peak_width_mm") if c in elements]
        arrays = {c: elements[c].to_numpy() for c in columns}
        per = {}
        for e in np.unique(element[sel]):  # ascending, as groupby
            rows = sel & (element == e)
            means = {}
            for col in columns:
                values = pd.Series(arrays[col][rows])
                if values.notna().any():
                    means[col] = float(values.mean())
            per[str(int(e))] = means
        out["elements"] = per
    return out


def _overlay_choice(frames: pd.DataFrame, n: int) -> list[int]:
    inview = frames[frames["block_in_view"].astype(bool)]
    if inview.empty or n <= 0:
        return [int(frames["frame"].iloc[len(frames) // 2])] if n > 0 and len(frames) else []
    picks = [int(inview["frame"].iloc[0]), int(inview["frame"].iloc[len(inview) // 2]),
             int(inview["frame"].iloc[-1])]
    if inview["contact_area_mm2"].notna().any():
        picks.append(int(inview.loc[inview["contact_area_mm2"].idxmax(), "frame"]))
    extra = np.linspace(0, len(inview) - 1, n + 2).round().astype(int)[1:-1]
    picks += [int(inview["frame"].iloc[i]) for i in extra]
    seen: list[int] = []
    for p in picks:
        if p not in seen:
            seen.append(p)
    return sorted(seen[:n])


#: Below this fraction of full scale, the brightest 1 % of pixels are not a lit field.
DARK_FOOTAGE_FRACTION = 0.03
#: Above this fraction of full scale, the darkest 1 % of pixels are saturated.
SATURATED_FRACTION = 0.98


def footage_warnings(setup: VideoSetup, frames: pd.DataFrame, lost: list[int]) -> list[str]:
    """What the user must know about a video whose numbers may mean nothing.

    Footage without a lit field (black), saturated footage (white), a video in which no
    frame shows contact or the block, gaps in the recorded frame numbers, and frames lost
    from a container that was cut short.
    """
    out = list(setup.notes)
    low, high = setup.grey_range
    if high <= DARK_FOOTAGE_FRACTION * setup.max_dn:
        out.append(f"no lit field: the brightest 1 % of pixels reach grey {high:.0f} of "
                   f"{setup.max_dn:.0f} (black footage?)")
    elif low >= SATURATED_FRACTION * setup.max_dn:
        out.append(f"saturated footage: even the darkest 1 % of pixels reach grey {low:.0f} "
                   f"of {setup.max_dn:.0f}")
    in_view = frames["block_in_view"].astype(bool)
    if len(frames) and not in_view.any():
        out.append(f"no {setup.view.subject} found in any of the {len(frames)} frames "
                   f"analysed (reference: {setup.reference_method})"
                   + setup.view.none_found(frames))
    out += setup.view.warnings(frames)
    for check in (_against_direction, _beyond_faces, _fewer_elements):
        said = check(setup, frames)
        if said:
            out.append(said)
    numbers = setup.numbers
    jumps = np.flatnonzero(np.diff(numbers) > 1)
    if len(jumps):
        missing = int(sum(numbers[j + 1] - numbers[j] - 1 for j in jumps))
        first = int(jumps[0])
        out.append(f"{missing} frame number(s) missing from the footage in {len(jumps)} "
                   f"gap(s), the first from frame {numbers[first]} to {numbers[first + 1]}; "
                   "times follow the frame numbers")
    if lost:
        out.append(f"the container was cut short: {len(lost)} frame(s) lost "
                   f"({lost[0]}-{lost[-1]})")
    return out


#: The block's front edge must travel (:func:`_front_travel`) this many standard errors of
#: that travel (from the edge's own scatter about its fitted lines) ...
DIRECTION_SIGMAS = 5.0
#: ... and at least this many px before its direction of travel is compared with
#: ``sliding_direction``: a front edge is placed to about a pixel, and a held block's
#: deformation moves it by a few (before: 10 % of the view's width, so a 20-frame pass of
#: 4.75 mm in a 64 mm view was not checked; helper-11).
DIRECTION_MIN_PX = 8.0
#: A step of the front between consecutive frames that departs from their median step by
#: more than this many px (and 5 robust spreads) is a change of leading element (the front
#: is the leading element's in contact: when it leaves the view, the next one's, an
#: element pitch behind), not travel.
FRONT_JUMP_PX = 2.0


def _front_travel(frame: np.ndarray, t: np.ndarray, x: np.ndarray, mm_per_px: float
                  ) -> tuple[float, float] | None:
    """The front edge's travel over the frames' time span and its standard error, mm: one
    slope fitted to the stretches of consecutive frames with the same leading element, each
    with its own offset (a line through them all slopes against the motion where the front
    jumps back an element pitch as the leading one leaves the view: the review of this
    check, 0.8 mm "right" for a block moving left at 16000 fps). None with fewer than 4
    frames or no stretch of 2."""
    if len(t) < 4 or np.ptp(t) <= 0:
        return None
    dx = np.diff(x)
    med = float(np.median(dx))
    spread = 1.4826 * float(np.median(np.abs(dx - med)))
    cut = (np.diff(frame) != 1) | (np.abs(dx - med) > max(5.0 * spread, FRONT_JUMP_PX * mm_per_px))
    stretch = np.concatenate(([0], np.cumsum(cut)))
    tc, xc = t.astype(float).copy(), x.astype(float).copy()
    for k in np.unique(stretch):
        on = stretch == k
        tc[on] -= tc[on].mean()
        xc[on] -= xc[on].mean()
    sxx = float(tc @ tc)
    dof = len(t) - len(np.unique(stretch)) - 1
    if sxx <= 0 or dof < 1:
        return None
    slope = float(tc @ xc) / sxx
    resid = xc - slope * tc
    span = float(np.ptp(t))
    return slope * span, span * math.sqrt(float(resid @ resid) / dof / sxx)


def _against_direction(setup: VideoSetup, frames: pd.DataFrame) -> str | None:
    """A warning when a block passing a fixed camera moves against ``sliding_direction``
    (a wrong direction reads every element's back edge as its front: deflection angles
    and front peaks on the wrong side), else None."""
    if setup.camera != "fixed" or not len(frames) or "block_front_x_mm" not in frames:
        return None
    shown = frames["block_in_view"].astype(bool).to_numpy()
    seen = frames[shown]
    x = seen["block_front_x_mm"].to_numpy(float)
    t = seen["time_s"].to_numpy(float)
    ok = np.isfinite(x) & np.isfinite(t)
    # consecutive rows of the frames table (a frame without a front, or without the
    # block, ends a stretch)
    row = np.flatnonzero(shown)[ok]
    fit = _front_travel(row, t[ok], x[ok], setup.mm_per_px)
    if fit is None:
        return None
    travel, se = fit
    direction = setup.meta.get("sliding_direction")
    moves = "right" if travel > 0 else "left"
    least = max(DIRECTION_SIGMAS * se, DIRECTION_MIN_PX * setup.mm_per_px)
    if abs(travel) < least or moves == direction:
        return None
    return (f"the block moves {moves} in the image ({abs(travel):.1f} mm over "
            f"{int(ok.sum())} frames) but sliding_direction is '{direction}': each "
            "element's back edge is read as its front (deflection angles and front peaks "
            "on the wrong side); check meta.json or --sliding-direction")


#: Median contact ratio (contact over the element faces' nominal area) above which the
#: image scale or the block's geometry is wrong: contact lies on the faces, and blur and
#: unmixing add about a pixel at each edge (a ratio of 1.2 for faces of 10 px).
MAX_CONTACT_RATIO = 1.5


def _beyond_faces(setup: VideoSetup, frames: pd.DataFrame) -> str | None:
    """A warning when the contact covers clearly more than the block's element faces
    (``contact_ratio``: a wrong ``mm_per_px`` or block geometry), else None."""
    if "contact_ratio" not in frames or not len(frames):
        return None
    ratio = frames["contact_ratio"].to_numpy(float)
    ratio = ratio[np.isfinite(ratio)]
    if not ratio.size or float(np.median(ratio)) <= MAX_CONTACT_RATIO:
        return None
    return (f"the contact covers {float(np.median(ratio)):.3g} times the block's element "
            f"faces (contact_ratio, median over {ratio.size} frames): the image scale "
            f"(mm_per_px {setup.mm_per_px:g}) or the block's geometry in meta.json is wrong")


#: Share of the block's elements that the frames showing the whole block find in contact
#: (median) at or below which the scale or the geometry is taken as wrong. At a scale k
#: times the true one (k < 1) the element template spans 1/k times the block's length in
#: the image, and the contact fills only its first k N elements: half the true mm_per_px
#: found 2 of G3's 4 elements and 4 of G7's 8 (helper-11), the true scale all of them
#: (solid and patchy contact). In the renderer's model a sliding block keeps every element
#: in contact (lift-off shortens an element's contact); an element that lost contact
#: entirely (a trailing one lifted off under a braking moment) would read so too, and the
#: warning names that. Judged only where the lit zone spans the frame's width: elements
#: outside a smaller lit zone show no contact at any scale (helper-15's review: a lit disc
#: of a fifth of the frame found 2 of 4 at the true scale).
MIN_ELEMENT_SHARE = 0.5
#: The lit zone spans the frame's width where its columns cover this share of it.
SPANNING_LIT_SHARE = 0.95


def _fewer_elements(setup: VideoSetup, frames: pd.DataFrame) -> str | None:
    """A warning when the frames that show the whole block find at most
    :data:`MIN_ELEMENT_SHARE` of its elements in contact (median; a too small
    ``mm_per_px`` or a wrong block geometry), else None."""
    lengths = getattr(setup.layout, "element_lengths_mm", None)
    if (setup.view_name != "tir" or lengths is None or len(lengths) < 2
            or "n_elements_in_contact" not in frames or "block_fully_in_view" not in frames):
        return None
    lit = setup.view.tir.lit.mask
    if float(lit.any(axis=0).mean()) < SPANNING_LIT_SHARE:
        return None
    whole = frames["block_fully_in_view"].eq(True).to_numpy()  # NaN: not shown whole
    found = frames["n_elements_in_contact"].to_numpy(float)[whole]
    found = found[np.isfinite(found)]
    if not found.size:
        return None
    median = float(np.median(found))
    if median > MIN_ELEMENT_SHARE * len(lengths):
        return None
    return (f"the block has {len(lengths)} elements but the frames that show it whole find "
            f"{median:g} in contact (median over {found.size} frames): the image scale "
            f"(mm_per_px {setup.mm_per_px:g}) may be too small or the block's geometry in "
            "meta.json wrong (at half the true scale half the elements are found), unless "
            "that many elements really carry no contact")


def _gaps(numbers: np.ndarray) -> list[dict[str, int]]:
    jumps = np.flatnonzero(np.diff(numbers) > 1)
    return [{"after": int(numbers[j]), "before": int(numbers[j + 1]),
             "missing": int(numbers[j + 1] - numbers[j] - 1)} for j in jumps]


def _summary(path: Path, name: str, setup: VideoSetup, options: AnalysisOptions,
             frames: pd.DataFrame, elements: pd.DataFrame, skipped: list[dict[str, Any]],
             elapsed: float, lost: list[int]) -> dict[str, Any]:
    ref = setup.reference
    fit = setup.view.reference_fit  # TIR with --reference
    in_view = frames["block_in_view"].astype(bool)
    return {
        "result_version": _RESULT_VERSION,
        # every frame the footage claims was analysed: none skipped, none lost
        "complete": not skipped and not lost,
        "video": str(path),
        "name": name,
        "view": setup.view_name,
        "n_frames": setup.n_frames,
        "n_frames_analysed": len(frames),
        "frames_without_block": int((~in_view).sum()),
        "frames_with_whole_block": int(frames["block_fully_in_view"].astype(bool).sum()),
        "skipped_frames": skipped,
        "lost_frames": lost,
        "frame_gaps": _gaps(setup.numbers),
        "warnings": footage_warnings(setup, frames, lost),
        "steady": _steady(frames, elements),
        "reference": {
            "method": setup.reference_method,
            "n_frames": ref.n_frames if ref is not None else 1,
            "excluded_fraction": ref.excluded_fraction if ref is not None else None,
            **({"fit": fit.as_dict()} if fit is not None else {}),
        },
        "camera": setup.camera,
        **setup.view.summary(),
        "meta": setup.meta,
        "options": asdict(options),
        "fingerprint": footage_fingerprint(path),
        "input_files": input_files(options),
        "frames_per_s": len(frames) / elapsed if elapsed > 0 else None,
        "package_version": __version__,
    }


class _OverlayVideo:
    """Streams every k-th overlay frame into ``overlay.avi`` in a staging file."""

    def __init__(self, setup: VideoSetup, options: AnalysisOptions, folder: Path) -> None:
        self.setup = setup
        self.step = max(1, math.ceil(setup.n_frames / options.overlay_video_max_frames))
        folder.mkdir(parents=True, exist_ok=True)
        self.path = folder / temporary_name("overlay", ".avi")
        self.writer = None

    def add(self, i: int, frame: np.ndarray, result: Any) -> None:
        """Add frame index `i` with its :class:`~tir_contact.frame.FrameResult` when it is on
        the video's step."""
        if i % self.step:
            return
        img = _draw(self.setup, frame, result)
        if self.writer is None:
            fourcc = cv2.VideoWriter_fourcc(*"MJPG")
            fps = min(25.0, self.setup.fps)
            self.writer = cv2.VideoWriter(str(self.path), fourcc, fps,
                                          (img.shape[1], img.shape[0]))
        self.writer.write(img)

    def close(self) -> None:
        if self.writer is not None:
            self.writer.release()
            self.writer = None


def _draw(setup: VideoSetup, frame: np.ndarray, result: Any) -> np.ndarray:
    """The overlay image of a frame and its :class:`~tir_contact.frame.FrameResult`, drawn
    by the video's view."""
    k = result.row["frame"]
    label = f"frame {k}  t = {k / setup.fps * 1e3:.2f} ms"
    return setup.view.overlay(setup, frame, result, label)


def write_results(result: VideoAnalysis, final: Path, reader: Any, analyser: Any,
                  options: AnalysisOptions, video: _OverlayVideo | None = None) -> Path:
    """Write a video's results into the folder `final` (atomically: staged, then moved).

    Parameters
    ----------
    result : VideoAnalysis
    final : Path
        The result folder.
    reader : footage reader
        To read the frames of the overlay images again.
    analyser : FrameAnalyser
        To analyse those frames again for drawing.
    options : AnalysisOptions
    video : _OverlayVideo, optional
        The streamed overlay video, moved into the folder.

    Returns
    -------
    Path
        The result folder.
    """
    from tir_contact.plots import plot_video_results  # matplotlib: only when plots are wanted

    setup = analyser.setup
    stage = staging_folder(final)
    try:
        tables = {"frames": result.frames, "elements": result.elements}
        if result.regions is not None:
            tables["regions"] = result.regions
        for stem, df in tables.items():
            df.to_csv(stage / f"{stem}.csv", index=False, lineterminator="\n",
                      float_format="%.6g")
        if options.parquet and _has_pyarrow():
            for stem, df in tables.items():
                df.to_parquet(stage / f"{stem}.parquet", index=False)
        if options.plots:
            plot_video_results(result.frames, result.elements, stage, view=setup.view_name,
                               title=result.summary["name"])
        if options.overlay_frames > 0:
            (stage / "overlays").mkdir()
            index_of = {int(n): i for i, n in enumerate(setup.numbers)}
            for k in _overlay_choice(result.frames, options.overlay_frames):
                try:
                    frame = reader.get_frame(index_of[k])
                except FootageError:
                    continue
                cv2.imwrite(str(stage / "overlays" / f"frame_{k:06d}.png"),
                            _draw(setup, frame, analyser(k, frame)))
        if video is not None and video.path.exists() and video.path.stat().st_size > 0:
            os.replace(video.path, stage / "overlay.avi")
        for name, image in setup.view.images().items():  # the view's own (the lit zone)
            cv2.imwrite(str(stage / name), image)
        write_json(stage / "summary.json", result.summary)
        return replace_folder(stage, final)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    finally:
        if video is not None:
            video.path.unlink(missing_ok=True)


def _has_pyarrow() -> bool:
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        return False
    return True
