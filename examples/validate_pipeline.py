"""Validate the contact pipeline against synthetic ground truth.

Three parts (each can be skipped):

1. *Random real-footage domain* (``--domain N``, default 200 clips): clips drawn by
   :func:`synthetic.domain.sample_spec` (lit zones of 20-100 % of the frame with a dark
   outside, vignetting, low signal, 12 bit, JPEG, static pad/coin/three-point contacts,
   TIR and side cameras that follow the block, patchy contact, tilted scenes, bright
   contact), each analysed as a user would and compared with its truth
   (``_domain_validation.py`` says how each error is defined). Prints and writes the
   median and 95th percentile of each error per case class (``validation_domain.md``,
   the table the README quotes) and every clip (``validation_domain.csv``).
   Targets: contact area median <= 3 %, 95th percentile <= 10 %; no area outside the lit
   zone; element contact length median <= 0.1 mm; side-view angle median <= 0.5 deg.
2. *Contact ratio G0-G7* (``--ratio``): patchy contact rendered for each reference sample
   at 1 m/s, the pipeline's steady contact ratio against the model's
   (:func:`synthetic.footage.model_contact_ratio`): within 0.05.
2b. *Physical world* (``--physical N``, default 12 clips; needs the contact extra): clips
   drawn by :func:`synthetic.domain.sample_physical_spec` (a rough pad or sphere whose
   contact comes from the rough-contact solver, with frustrated-TIR grey levels,
   sub-pixel junctions, lens blur and texture; the sliding block with physical real
   contact), their own case classes in ``validation_physical.md``; the truth is the true
   contact area (gap 0). The static scenes among them (rough pads and spheres) are
   analysed again with the rig's own empty frame as ``--reference``
   (:func:`synthetic.table.empty_reference`; ``validation_physical_empty_frame.md``;
   ``--no-empty-frame`` skips it): the free surface under the contact measured instead of
   estimated from the image.
2c. *Contact area as a measurement* (issue 21; written as ``validation_measurement.md``):
   for the physical classes and the domain, the area error's median and 95th percentile
   and the share of frames whose true area lies in the pipeline's error bar
   ``[contact_area_low_mm2, contact_area_high_mm2]`` (n/a where ``frames.csv`` has no such
   columns); ``--load-series``: a rough pad on a textured field at 0.5/1/2/4 bar, the
   intercept at zero load of the line through (load, measured area) over the lowest load's
   area, and the same series on eight further draws (its own rough face and texture each:
   each load's area error and the measured line's departure from the true one,
   ``validation_load_series_draws.csv``; ``--no-load-series-draws`` skips them);
   ``--table``: the renders of issue 21's table
   (:mod:`synthetic.table`; the three contacts with a fold with and without the scene's
   own empty frame as ``--reference``, the round pad, the smooth sphere, the bright
   patches, and a rough pad under stray light).
   Targets (``MEASUREMENT_TARGETS``): area median <= 2 %, p95 <= 8 %, truth in the bar in
   >= 90 % of frames, |intercept| < 20 %.
3. *Fixed thesis cases* (``--fixed``): the renderer's default camera (0.1 mm/px,
   640 x 256 px, 4000 frames/s, noise, motion blur, uneven illumination, bubbles and
   scratches) for G0, G3 and G7 at 1 and 3 m/s, TIR and side view:

* TIR: median relative error of the block contact area (target <= 2 %), median absolute
  error of the element contact length (<= 0.1 mm) and of the front-peak position
  (<= 1 px = 0.1 mm), frames without the block reported as such;
* side view: median absolute error of the deflection angle (<= 0.5 deg).

Run: ``python examples/validate_pipeline.py [--out validation-out] [--domain 200]
[--physical 12] [--seed 0] [--workers 2] [--no-ratio] [--no-fixed] [--frames 400]
[--table] [--no-load-series] [--no-load-series-draws]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _domain_validation import (
    LOAD_ERROR_PREFIX,
    MEASUREMENT_TARGETS,
    angle_errors,
    element_pairs,
    length_errors,
    load_error_columns,
    load_series,
    load_series_draws,
    summarise,
    validate_clip,
    validate_table_clip,
)

from friction_model.geometry import reference_block
from synthetic.domain import sample_physical_specs, sample_specs
from synthetic.footage import FootageSpec, model_contact_ratio, render_footage
from tir_contact.analyze import AnalysisOptions, analyze_video

DOMAIN_TARGETS = {"area_err_pct median": 3.0, "area_err_pct p95": 10.0,
                  # beyond the rim: 0 as the table prints it (0.005 rounds to 0.00)
                  "outside_lit_pct median": 0.0, "beyond_rim_pct p95": 0.005,
                  "length_err_mm median": 0.1,
                  "angle_err_deg median": 0.5}

TARGETS = {"area_err_pct": 2.0, "length_err_mm": 0.1, "peak_err_px": 1.0, "angle_err_deg": 0.5}


def compare_tir(res, truth: pd.DataFrame, mm_per_px: float) -> dict:
    """Median errors of a TIR analysis against the truth (frames with contact)."""
    frames = res.frames.set_index("frame")
    block = truth[truth.element == -1].set_index("frame")
    contact = block.index[block.in_view & (block.contact_area_mm2 > 0)]
    area = frames.loc[contact, "contact_area_mm2"] / block.loc[contact, "contact_area_mm2"] - 1
    empty = block.index[~block.in_view]
    missed = int(frames.loc[empty, "block_in_view"].astype(bool).sum())
    el_truth, merged = element_pairs(res, truth, with_contact=True)
    length = length_errors(merged)  # elements wholly inside the image
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
    el_truth, merged = element_pairs(res, truth, with_contact=False)
    err = angle_errors(merged)
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


def run_domain(n: int, seed: int, workers: int, out: Path, *, physical: bool = False,
               empty_frame: bool = False) -> pd.DataFrame | None:
    """Validate `n` random clips; writes the per-clip table and the summary.

    ``physical``: clips of the physical world (contact mechanics and optics, their own
    classes, written as ``validation_physical*``) instead of the real-footage domain.
    ``empty_frame``: only the static clips among the draws, each with the rig's own empty
    frame as ``--reference`` (``*_empty_frame*``; None without static clips): the free
    surface under a static contact measured, not estimated from the image (whose bubbles,
    scratches and dust under the contact nothing else tells from faint contact), what
    recording an empty frame is worth.
    """
    specs = sample_physical_specs(n, seed=seed) if physical else sample_specs(n, seed=seed)
    name = "validation_physical" if physical else "validation_domain"
    title = "Physical world (rough contact, FTIR optics)" if physical else None
    draws = list(enumerate(specs))
    if empty_frame:
        draws = [(i, (s, c)) for i, (s, c) in draws if s.is_static]
        if not draws:
            return None
        name += "_empty_frame"
        title = f"{title or 'Static scenes'} with the rig's empty frame"
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max(1, workers)) as pool:
        rows = []
        for k, row in enumerate(pool.map(validate_clip, [s for _, (s, _) in draws],
                                         [c for _, (_, c) in draws], [i for i, _ in draws],
                                         [empty_frame] * len(draws))):
            rows.append(row)
            if (k + 1) % 20 == 0:
                print(f"  {k + 1}/{len(draws)} clips ({time.perf_counter() - t0:.0f} s)",
                      flush=True)
    table = pd.DataFrame(rows)
    table.to_csv(out / f"{name}.csv", index=False)
    summary = summarise(table)
    if empty_frame:
        summary.loc[summary.case == "all", "case"] = "all static, empty frame"
    summary.to_csv(out / f"{name}_summary.csv", index=False)
    (out / f"{name}.md").write_text(_markdown(summary, len(draws), seed, title))
    return summary


def _markdown(summary: pd.DataFrame, n: int, seed: int, title: str | None = None) -> str:
    """The summary as the README's table (errors as defined in _domain_validation.py)."""
    cols = [("area_err_pct", "contact area error, %"), ("outside_lit_pct",
            "area outside the lit zone, %"), ("beyond_rim_pct",
            "of it more than 2 px outside, %"), ("length_err_mm", "contact length error, mm"),
            ("angle_err_deg", "angle error, deg")]
    if "optical_err_pct median" in summary:  # physical scenes: the optical contact too
        cols[1:1] = [("optical_err_pct", "error against the optical contact, %"),
                     ("optical_over_real_pct", "optical over true contact, %")]
    head = "| case | clips | " + " | ".join(f"{t} (median / p95)" for _, t in cols) + " |"
    lines = [f"{title or 'Random real-footage domain'}, {n} clips (seed {seed}):", "", head,
             "|" + "---|" * (len(cols) + 2)]
    for row in summary.to_dict("records"):
        cells = []
        for key, _ in cols:
            med, p95 = row.get(f"{key} median"), row.get(f"{key} p95")
            cells.append("" if med is None or pd.isna(med) else f"{med:.2f} / {p95:.2f}")
        lines.append(f"| {row['case']} | {row['clips']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def table_cases(seed: int = 0, n_frames: int = 6,
                physical: bool = True) -> list[tuple[str, FootageSpec, bool]]:
    """The "table" set: (name, spec, with the scene's own empty frame as reference) for each
    render of issue 21's table, the fold scene twice (without and with the reference), and
    (``physical``, needs the contact extra) a rough pad under 15 % stray light."""
    from _domain_validation import stray_light_spec

    from synthetic.table import TABLE_NAMES, table_specs

    specs = table_specs(seed, n_frames=n_frames)
    cases = [(name, specs[name], False) for name in TABLE_NAMES]
    cases.append(("three points, fold", specs["three points, fold"], True))
    if physical:
        cases.append(("rough pad, stray light 0.15", stray_light_spec(n_frames=min(n_frames, 3)),
                      False))
    return cases


def run_table(out: Path, seed: int, workers: int, *, physical: bool = True) -> pd.DataFrame:
    """Validate the "table" set (:func:`table_cases`); writes ``validation_table.csv``."""
    cases = table_cases(seed, physical=physical)
    with ProcessPoolExecutor(max(1, workers)) as pool:
        futures = [pool.submit(validate_table_clip, n, s, reference=r) for n, s, r in cases]
        table = pd.DataFrame([f.result() for f in futures])
    if "frames_scored" in table:
        table["in_band_pct"] = 100 * table.frames_in_band / table.frames_scored
    table.to_csv(out / "validation_table.csv", index=False)
    return table


def _pct(value) -> str:
    return "n/a" if value is None or pd.isna(value) else f"{value:.1f}"


def measurement_markdown(summaries: dict[str, pd.DataFrame], table: pd.DataFrame | None,
                         series: tuple[pd.DataFrame, dict] | None,
                         draws: pd.DataFrame | None = None) -> str:
    """Issue 21's measurement table: per class (of each summary), per table render, the
    load series and its further draws, with the targets."""
    t = MEASUREMENT_TARGETS
    lines = ["Contact area as a measurement (issue 21). Targets: area error median <= "
             f"{t['area_err_pct median']:g} %, p95 <= {t['area_err_pct p95']:g} %, true area "
             f"in [low, high] in >= {t['in_band_pct']:g} % of frames, load-series |intercept| "
             f"< {t['intercept_pct']:g} % of the lowest load's area.", "",
             "| set | case | clips | area error median, % | area error p95, % | "
             "truth in [low, high], % of frames | optical contact in [low, high], % of "
             "frames | bar width, % of the true area (median / p95 of the clips) |",
             "|---|---|---|---|---|---|---|---|"]
    for name, summary in summaries.items():
        for row in summary.to_dict("records"):
            width = (f"{_pct(row.get('band_width_pct median'))} / "
                     f"{_pct(row.get('band_width_pct p95'))}")
            lines.append(f"| {name} | {row['case']} | {row['clips']} | "
                         f"{_pct(row.get('area_err_pct median'))} | "
                         f"{_pct(row.get('area_err_pct p95'))} | {_pct(row.get('in_band_pct'))} | "
                         f"{_pct(row.get('in_band_optical_pct'))} | {width} |")
    if table is not None:
        lines += ["", "Renders of issue 21's table (synthetic.table):", "",
                  "| image | true area, mm2 | measured, mm2 | bar (mean low / high), mm2 | "
                  "area error, % | truth in bar, % of frames | warnings |",
                  "|---|---|---|---|---|---|---|"]
        for row in table.to_dict("records"):
            bar = (f"{row['low_mm2']:.2f} / {row['high_mm2']:.2f}" if "low_mm2" in row
                   and not pd.isna(row["low_mm2"]) else "n/a")
            lines.append(f"| {row['case']} | {row['true_area_mm2']:.3f} | "
                         f"{row['measured_mm2']:.3f} | {bar} | {row['area_err_pct']:.1f} | "
                         f"{_pct(row.get('in_band_pct'))} | {row['warnings'] or '-'} |")
    if series is not None:
        frame, fit = series
        lines += ["", "Load series (rough pad on a textured field, no empty frame):", "",
                  "| load, bar | true area, mm2 | measured, mm2 |", "|---|---|---|"]
        lines += [f"| {r['pressure_bar']:g} | {r['true_area_mm2']:.4f} | "
                  f"{r['measured_mm2']:.4f} |" for r in frame.to_dict("records")]
        lines += ["", f"Intercept at zero load: measured {fit['intercept_pct']:.1f} % of the "
                  f"lowest load's area (truth {fit['true_intercept_pct']:.1f} %)."]
    if draws is not None:
        lines += ["", "", draws_markdown(draws)]
    return "\n".join(lines) + "\n"


def draws_markdown(draws: pd.DataFrame) -> str:
    """The load series' further draws (:func:`load_series_draws`) as a markdown table and
    their summary line."""
    errs = load_error_columns(draws)
    loads = [c.removeprefix(LOAD_ERROR_PREFIX) for c in errs]
    lines = ["Load series, further draws (seeds "
             f"{draws.seed.min()}-{draws.seed.max()}): area error at each load, intercepts:", "",
             "| seed | " + " | ".join(f"{p} bar, %" for p in loads)
             + " | intercept, % (truth) | measured - true, points |",
             "|---" * (len(errs) + 3) + "|"]
    for r in draws.to_dict("records"):
        lines.append(f"| {r['seed']} | " + " | ".join(f"{r[c]:+.1f}" for c in errs)
                     + f" | {r['intercept_pct']:.1f} ({r['true_intercept_pct']:.1f}) | "
                     f"{r['intercept_off_pts']:+.1f} |")
    e = np.abs(draws[errs].to_numpy().ravel())
    lines += ["", f"Over their {e.size} loads the area error's median magnitude is "
              f"{np.median(e):.1f} % and its p95 {np.percentile(e, 95):.1f} %; the truth in the "
              f"bar in {draws.frames_in_band.sum()} of {draws.frames_scored.sum()} frames; the "
              f"measured intercept within {draws.intercept_off_pts.abs().max():.1f} points of "
              "the true one."]
    return "\n".join(lines)


def run_ratio(out: Path) -> pd.DataFrame:
    """Contact ratio of rendered patchy G0-G7 footage against the model's."""
    rows = []
    for preset in ("G0", "G3", "G5", "G6", "G7"):
        spec = FootageSpec(preset=preset, velocity_mps=1.0, n_frames=200, dynamics="steady",
                           real_contact="patchy", seed=3)
        clip = render_footage(spec, out / "ratio" / preset, progress=False)
        res = analyze_video(clip, options=AnalysisOptions(overlay_frames=0, parquet=False))
        # the pipeline's ratio is over the element faces, the model's (and Fig. 4.21's) over
        # the block's nominal area L w, sipes included
        geom = reference_block(preset)
        measured = (res.summary["steady"]["contact_ratio"]["mean"]
                    * geom.rubber_area_mm2 / geom.nominal_area_mm2)
        model = model_contact_ratio(spec)
        rows.append({"preset": preset, "model_contact_ratio": model,
                     "measured_contact_ratio": measured, "difference": measured - model})
    table = pd.DataFrame(rows)
    table.to_csv(out / "validation_contact_ratio.csv", index=False)
    return table


def run_fixed(out: Path, frames: int) -> pd.DataFrame:
    """The renderer's default camera, G0/G3/G7 at 1 and 3 m/s, TIR and side view."""
    options = AnalysisOptions(overlay_video=False)
    rows = []
    for view in ("tir", "side"):
        for preset in ("G0", "G3", "G7"):
            for v in (1.0, 3.0):
                name = f"{preset}_{view}_{v:g}mps"
                n = frames if v == 1.0 else max(frames // 2, 160)
                spec = FootageSpec(preset=preset, view=view, velocity_mps=v, n_frames=n)
                clip = render_footage(spec, out / "footage" / name, fmt="png",
                                      progress=False)
                res = analyze_video(clip, out / "analysis", options=options, name=name)
                truth = pd.read_csv(Path(clip) / "ground_truth.csv")
                row = {"case": name}
                row.update(compare_tir(res, truth, spec.camera.mm_per_px) if view == "tir"
                           else compare_side(res, truth))
                rows.append(row)
                print(f"  {name}: done", flush=True)
    table = pd.DataFrame(rows)
    table.to_csv(out / "validation.csv", index=False)
    return table


def _measurement(args: argparse.Namespace, summaries: dict[str, pd.DataFrame]) -> None:
    """The table set, the load series and ``validation_measurement.md``."""
    table = series = draws = None
    if args.load_series:
        from synthetic.roughness import MissingExtraError, require_tamaas

        try:
            require_tamaas()
        except MissingExtraError as exc:
            print(f"load series and stray-light render skipped: {exc}")
            args.load_series = False
    if args.table:
        print("renders of issue 21's table")
        table = run_table(args.out, args.seed, args.workers, physical=args.load_series)
        print(table.drop(columns="warnings").round(3).to_string(index=False))
    if args.load_series:
        series = load_series()
        series[0].to_csv(args.out / "validation_load_series.csv", index=False)
        print(series[0].round(4).to_string(index=False))
        print(f"load-series intercept {series[1]['intercept_pct']:.1f} % of the lowest load's "
              f"area (truth {series[1]['true_intercept_pct']:.1f} %; target |.| < "
              f"{MEASUREMENT_TARGETS['intercept_pct']:g} %)")
        if args.load_series_draws:
            draws = load_series_draws()
            draws.to_csv(args.out / "validation_load_series_draws.csv", index=False)
            print(draws_markdown(draws))
    if summaries or table is not None or series is not None:
        (args.out / "validation_measurement.md").write_text(
            measurement_markdown(summaries, table, series, draws))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("validation-out"))
    ap.add_argument("--domain", type=int, default=200, metavar="N",
                    help="random real-footage clips (0: skip)")
    ap.add_argument("--physical", type=int, default=12, metavar="N",
                    help="clips of the physical world, their own classes (0: skip; needs "
                    "the contact extra)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--ratio", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--fixed", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--frames", type=int, default=400)
    ap.add_argument("--table", action=argparse.BooleanOptionalAction, default=False,
                    help="the renders of issue 21's table (synthetic.table)")
    ap.add_argument("--empty-frame", action=argparse.BooleanOptionalAction, default=True,
                    help="the physical draws' static scenes again with the rig's own empty "
                    "frame as --reference")
    ap.add_argument("--load-series", action=argparse.BooleanOptionalAction, default=True,
                    help="rough pad at 0.5/1/2/4 bar (needs the contact extra)")
    ap.add_argument("--load-series-draws", action=argparse.BooleanOptionalAction, default=True,
                    help="with --load-series: the same series on eight further draws "
                         "(about 40 s)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    pd.set_option("display.width", 200)
    pd.set_option("display.max_columns", 20)
    summaries: dict[str, pd.DataFrame] = {}
    if args.domain > 0:
        print(f"random real-footage domain: {args.domain} clips (seed {args.seed})")
        summary = summaries["domain"] = run_domain(args.domain, args.seed, args.workers,
                                                   args.out)
        print(summary.round(3).to_string(index=False))
        overall = summary[summary.case == "all"].iloc[0]
        print("targets:", ", ".join(
            f"{k} <= {t}: {'met' if overall.get(k, np.nan) <= t else 'NOT met'} "
            f"({overall.get(k, np.nan):.3f})" for k, t in DOMAIN_TARGETS.items()))
    if args.physical > 0:
        print(f"physical world: {args.physical} clips (seed {args.seed})")
        summary = summaries["physical"] = run_domain(args.physical, args.seed, args.workers,
                                                     args.out, physical=True)
        print(summary.round(3).to_string(index=False))
        if args.empty_frame:
            empty = run_domain(args.physical, args.seed, args.workers, args.out,
                               physical=True, empty_frame=True)
            if empty is not None:
                summaries["physical, empty frame"] = empty
                print("the same static scenes with the rig's empty frame (--reference):")
                print(empty.round(3).to_string(index=False))
    _measurement(args, summaries)
    if args.ratio:
        table = run_ratio(args.out)
        print("contact ratio of rendered patchy footage against the model (target 0.05):")
        print(table.round(3).to_string(index=False))
    if args.fixed:
        table = run_fixed(args.out, args.frames)
        ok = {k: bool((table[k].dropna() <= t).all()) for k, t in TARGETS.items()
              if k in table}
        print(table.round(3).to_string(index=False))
        print("targets met:", ", ".join(f"{k} <= {TARGETS[k]}: {'yes' if v else 'NO'}"
                                        for k, v in ok.items()))


if __name__ == "__main__":
    main()
