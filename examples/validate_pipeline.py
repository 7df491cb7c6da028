"""Validate the contact pipeline against synthetic ground truth (issue requirements).

Renders footage with ``synthetic.footage`` at its default camera settings (0.1 mm/px,
640 x 256 px, 4000 frames/s, noise, motion blur, uneven illumination, bubbles and scratches)
for G0, G3 and G7 at 1 and 3 m/s, TIR and side view, analyses each clip with
``tir_contact.analyze.analyze_video`` and compares with ``ground_truth.csv``:

* TIR: median relative error of the block contact area (target <= 2 %), median absolute
  error of the element contact length (<= 0.1 mm) and of the front-peak position
  (<= 1 px = 0.1 mm), frames without the block reported as such;
* side view: median absolute error of the deflection angle (<= 0.5 deg).

Run: ``python examples/validate_pipeline.py [--out validation-out] [--frames 400]``.
Prints one table row per case and writes ``validation.csv``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from synthetic.footage import FootageSpec, render_footage
from tir_contact.analyze import AnalysisOptions, analyze_video

TARGETS = {"area_err_pct": 2.0, "length_err_mm": 0.1, "peak_err_px": 1.0, "angle_err_deg": 0.5}


def compare_tir(res, truth: pd.DataFrame, mm_per_px: float) -> dict:
    """Median errors of a TIR analysis against the truth (frames with contact)."""
    frames = res.frames.set_index("frame")
    block = truth[truth.element == -1].set_index("frame")
    contact = block.index[block.in_view & (block.contact_area_mm2 > 0)]
    area = frames.loc[contact, "contact_area_mm2"] / block.loc[contact, "contact_area_mm2"] - 1
    empty = block.index[~block.in_view]
    missed = int(frames.loc[empty, "block_in_view"].astype(bool).sum())
    el_truth = truth[(truth.element >= 0) & truth.in_view & (truth.contact_length_mm > 0)]
    merged = el_truth.merge(res.elements, on=["frame", "element"], suffixes=("_t", ""))
    # element lengths are compared where the whole element is inside the image
    whole = merged[np.isfinite(merged.liftoff_mm)]
    length = (whole.contact_length_mm - whole.contact_length_mm_t).abs()
    peak = (merged.front_peak_x_mm - merged.front_peak_x_mm_t).abs() / mm_per_px
    return {
        "frames_with_contact": len(contact),
        "area_err_pct": 100 * float(np.nanmedian(np.abs(area))),
        "length_err_mm": float(np.nanmedian(length)),
        "peak_err_px": float(np.nanmedian(peak)),
        "empty_frames": len(empty),
        "empty_frames_wrong": missed,
        "elements_matched_pct": 100 * len(merged) / max(len(el_truth), 1),
    }


def compare_side(res, truth: pd.DataFrame) -> dict:
    """Median deflection-angle error of a side-view analysis against the truth."""
    el_truth = truth[(truth.element >= 0) & truth.in_view]
    merged = el_truth.merge(res.elements, on=["frame", "element"], suffixes=("_t", ""))
    err = (merged.deflection_angle_deg - merged.deflection_angle_deg_t).abs()
    block = truth[truth.element == -1].set_index("frame")
    frames = res.frames.set_index("frame")
    empty = block.index[~block.in_view]
    return {
        "frames_with_contact": int(block.in_view.sum()),
        "angle_err_deg": float(np.nanmedian(err)),
        "angle_mean_truth_deg": float(el_truth.deflection_angle_deg.mean()),
        "empty_frames": len(empty),
        "empty_frames_wrong": int(frames.loc[empty, "block_in_view"].astype(bool).sum()),
        "elements_matched_pct": 100 * float(np.isfinite(merged.deflection_angle_deg).sum())
        / max(len(el_truth), 1),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("validation-out"))
    ap.add_argument("--frames", type=int, default=400)
    args = ap.parse_args()
    options = AnalysisOptions(overlay_video=False)
    rows = []
    for view in ("tir", "side"):
        for preset in ("G0", "G3", "G7"):
            for v in (1.0, 3.0):
                name = f"{preset}_{view}_{v:g}mps"
                n = args.frames if v == 1.0 else max(args.frames // 2, 160)
                spec = FootageSpec(preset=preset, view=view, velocity_mps=v, n_frames=n)
                clip = render_footage(spec, args.out / "footage" / name, fmt="png",
                                      progress=False)
                res = analyze_video(clip, args.out / "analysis", options=options, name=name)
                truth = pd.read_csv(Path(clip) / "ground_truth.csv")
                row = {"case": name}
                row.update(compare_tir(res, truth, spec.camera.mm_per_px) if view == "tir"
                           else compare_side(res, truth))
                rows.append(row)
                print(f"  {name}: done", flush=True)
    table = pd.DataFrame(rows)
    ok = {k: bool((table[k].dropna() <= t).all()) for k, t in TARGETS.items() if k in table}
    pd.set_option("display.width", 160)
    print(table.round(3).to_string(index=False))
    print("targets met:", ", ".join(f"{k} <= {TARGETS[k]}: {'yes' if v else 'NO'}"
                                    for k, v in ok.items()))
    table.to_csv(args.out / "validation.csv", index=False)


if __name__ == "__main__":
    main()
