"""Random-domain validation of the contact pipeline (used by ``validate_pipeline.py``).

Each clip is drawn by :func:`synthetic.domain.sample_spec`, rendered to a temporary folder,
analysed as a user would (:func:`tir_contact.analyze.analyze_video`) and compared with its
ground truth. Per clip:

* ``area_err_pct`` (TIR): sum over frames of |measured - true| contact area over the sum
  of the true area (frames with and without contact alike, so a frame at the edge of the
  pass with 0.1 mm2 of contact does not dominate), in %; not scored for clips with under
  1 mm2 of contact on average;
* ``outside_lit_mm2`` (TIR): contact the pipeline counted outside the true lit zone
  (``lit_mask.png`` of the renderer: where the light exceeds half of its span), summed over
  frames, and ``outside_lit_pct`` of the measured area; ``beyond_rim_pct`` counts only the
  contact more than two pixels outside it: where a static contact covers the rim, the
  pipeline cannot see the half-light line and continues the light under the contact, and
  the renderer and the pipeline each place a soft rim's half-light line on their own
  samples;
* ``length_err_mm`` (TIR block): median |error| of the element contact length, elements
  wholly in the image;
* ``angle_err_deg`` (side view): median |error| of the element deflection angle.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import cv2
import numpy as np
import pandas as pd

from synthetic.footage import FootageSpec, render_footage
from tir_contact.analyze import AnalysisOptions, analyze_video

OPTIONS = AnalysisOptions(overlay_frames=0, parquet=False, regions="never")
#: Clips with less contact than this on average (mm2) get no relative area error.
MIN_SCORED_MM2 = 1.0
#: Physical scenes: their true contact is micro-junctions (0.01-1 mm^2 at 0.004-0.03
#: mm/px); a clip is scored when its mean true area covers at least this many pixels.
MIN_SCORED_PX_PHYSICAL = 25.0


class _OutsideLit:
    """Contact pixels outside the true lit zone, more than two pixels outside it, and in
    all, summed over the frames as the analysis makes them (``on_frame``)."""

    def __init__(self, truth_lit: np.ndarray) -> None:
        self.inside = truth_lit
        self.far = cv2.distanceTransform((~truth_lit).astype(np.uint8), cv2.DIST_L2, 5) > 2.5
        self.outside = self.beyond = self.total = 0

    def __call__(self, result) -> None:
        mask = result.detail.mask
        self.outside += int(np.count_nonzero(mask & ~self.inside))
        self.beyond += int(np.count_nonzero(mask & self.far))
        self.total += int(np.count_nonzero(mask))


def validate_clip(spec: FootageSpec, case: str, index: int) -> dict:
    """Render, analyse and compare one clip; the footage is deleted afterwards."""
    work = Path(tempfile.mkdtemp(prefix="tir-validate-"))
    try:
        clip = render_footage(spec, work / "clip", progress=False)
        lit_file = clip / "lit_mask.png"
        lit = (_OutsideLit(cv2.imread(str(lit_file), cv2.IMREAD_GRAYSCALE) > 0)
               if spec.view == "tir" and lit_file.exists() else None)
        res = analyze_video(clip, options=OPTIONS, on_frame=lit)
        truth = pd.read_csv(clip / "ground_truth.csv")
        row = {"clip": index, "case": case, "preset": spec.preset if spec.scene == "block"
               else spec.scene, "real_contact": spec.real_contact,
               "lit_shape": spec.camera.lit_shape, "lit_fraction": spec.camera.lit_fraction,
               "bit_depth": spec.camera.bit_depth, "jpeg": spec.camera.jpeg_quality,
               "white_level": spec.camera.white_level, "camera_found": res.summary["camera"],
               "warnings": "; ".join(res.summary["warnings"])}
        if spec.view == "tir":
            least = (MIN_SCORED_PX_PHYSICAL * spec.camera.mm_per_px**2 if spec.is_physical
                     else MIN_SCORED_MM2)
            row.update(_compare_tir(res, truth, lit, least))
        else:
            row.update(_compare_side(res, truth))
        return row
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _compare_tir(res, truth: pd.DataFrame, lit: _OutsideLit | None,
                 least_mm2: float = MIN_SCORED_MM2) -> dict:
    block = truth[truth.element == -1].set_index("frame")["contact_area_mm2"]
    measured = res.frames.set_index("frame")["contact_area_mm2"].reindex(block.index)
    true_sum = float(block.sum())
    mean_true = true_sum / max(len(block), 1)
    # a clip with under 1 mm2 of contact on average (a sliver of a ring at the rim) has
    # no meaningful relative error: it is listed, not scored
    out = {"true_area_mm2": mean_true,
           "area_err_pct": 100 * float((measured - block).abs().sum()) / true_sum
           if mean_true >= least_mm2 else np.nan}
    if lit is not None:
        px2 = float(res.summary["meta"]["mm_per_px"]) ** 2
        out["outside_lit_mm2"] = lit.outside * px2
        out["outside_lit_pct"] = 100 * lit.outside / lit.total if lit.total else 0.0
        out["beyond_rim_pct"] = 100 * lit.beyond / lit.total if lit.total else 0.0
    if len(res.elements):
        el_truth, merged = element_pairs(res, truth, with_contact=True)
        length = length_errors(merged)
        if len(el_truth) and len(length):
            out["length_err_mm"] = float(length.median())
    return out


def element_pairs(res, truth: pd.DataFrame, *,
                  with_contact: bool) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The truth's elements in view (with contact, when `with_contact`) and those of them the
    analysis measured, merged on frame and element (the truth's columns end in ``_t``)."""
    el_truth = truth[(truth.element >= 0) & truth.in_view]
    if with_contact:
        el_truth = el_truth[el_truth.contact_length_mm > 0]
    return el_truth, el_truth.merge(res.elements, on=["frame", "element"], suffixes=("_t", ""))


def length_errors(merged: pd.DataFrame) -> pd.Series:
    """|contact length error| (mm) of the elements wholly inside the image."""
    whole = merged[np.isfinite(merged.liftoff_mm)]
    return (whole.contact_length_mm - whole.contact_length_mm_t).abs()


def angle_errors(merged: pd.DataFrame) -> pd.Series:
    """|deflection angle error| (deg), NaN where no angle was measured."""
    return (merged.deflection_angle_deg - merged.deflection_angle_deg_t).abs()


def _compare_side(res, truth: pd.DataFrame) -> dict:
    _, merged = element_pairs(res, truth, with_contact=False)
    err = angle_errors(merged)
    return {"angle_err_deg": float(np.nanmedian(err)) if err.notna().any() else np.nan,
            "angles_found_pct": 100 * float(err.notna().mean()) if len(err) else 0.0}


def summarise(table: pd.DataFrame) -> pd.DataFrame:
    """Median and 95th percentile of each error per case class, and over all clips."""
    metrics = [m for m in ("area_err_pct", "outside_lit_pct", "beyond_rim_pct",
                           "length_err_mm", "angle_err_deg") if m in table]
    rows = []
    for case, group in [*table.groupby("case", sort=True), ("all", table)]:
        row = {"case": case, "clips": len(group)}
        for m in metrics:
            values = group[m].dropna()
            if len(values):
                row[f"{m} median"] = float(values.median())
                row[f"{m} p95"] = float(values.quantile(0.95))
        rows.append(row)
    return pd.DataFrame(rows)
