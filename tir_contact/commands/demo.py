"""``tir-contact demo``: the main job on data the toolkit makes itself.

It shows the friction model (Fig. 4.26, the Table 4.6 comparison, the per-element result of
a siped block) and the test-rig evaluation (synthetic runs with known friction, evaluated
and compared with the truth), and renders TIR and side-view footage with known ground truth
and analyses it with the contact pipeline (``tir-contact analyze``), and ends with the
discrepancy workflow on the stick-slip case (1500 Hz measured against the frequency the
model predicts from the one rubber), printing the verdict and the gap before and after.
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

from tir_contact.commands._types import output_folder

logger = logging.getLogger(__name__)


def add_parser(subparsers: argparse._SubParsersAction) -> None:
    """Register the ``demo`` sub-command."""
    p = subparsers.add_parser(
        "demo",
        help="run the main job on synthetic data it makes itself",
        description=(
            "Compute the friction model's Fig. 4.26 and Table 4.6 comparison, make synthetic "
            "test-rig runs with known friction and evaluate them. Writes CSV and PNG files."
        ),
    )
    p.add_argument("--out", type=output_folder, default=Path("demo-out"),
                   help="output folder")
    p.add_argument("--seed", type=int, default=1, help="random seed of the synthetic runs")
    p.add_argument("--runs", type=int, default=3, help="repeated runs per velocity (1..10)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run the demo; returns the exit code."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    import pandas as pd

    from friction_model import (
        Conditions,
        DryWetParameters,
        evaluate_on_table_4_6,
        friction_table,
        reference_block,
        simulate_block,
    )
    from friction_model.plots import fig_4_26_table, plot_fig_4_26, plot_table_4_6
    from friction_model.rig import evaluate_runs, write_outputs
    from synthetic.rig import make_raw_run, write_run_csv

    if not 1 <= args.runs <= 10:
        raise SystemExit(f"tir-contact demo: --runs must lie in 1..10, got {args.runs}")
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    params = DryWetParameters()

    # 1. Fig. 4.26: the dry run-in length of Eq. 4.7 over v, p, dT and mu_dry
    fig_4_26_table().to_csv(out / "fig_4_26_dry_length.csv", index=False)
    fig = plot_fig_4_26()
    fig.savefig(out / "fig_4_26_dry_length.png", dpi=120)
    plt.close(fig)

    # 2. Table 4.6: the calibrated model against the measured characteristics
    table, rmse = evaluate_on_table_4_6(params)
    table.to_csv(out / "table_4_6_model.csv", index=False)
    fig = plot_table_4_6(table, rmse)
    fig.savefig(out / "table_4_6_model.png", dpi=120)
    plt.close(fig)
    print("Dry/wet model vs. Table 4.6 (G3, v = 1..7 m/s), RMSE of mu per curve:")
    for name, value in rmse.items():
        print(f"  {name:22s} {value:.4f}")

    # 3. The siped block element by element (Fig. 4.25)
    g3 = reference_block("G3")
    frames = []
    for label, cond in (
        ("cold-dry", Conditions.from_bar(1.0, 2.5, -5.0, humidity_pct=40.0)),
        ("warm-humid", Conditions.from_bar(5.0, 2.5, -1.0, humidity_pct=95.0)),
    ):
        res = simulate_block(g3, cond, params)
        frames.append(res.elements.assign(case=label))
        fig = res.plot()
        fig.savefig(out / f"block_profile_{label}.png", dpi=120)
        plt.close(fig)
    elements = pd.concat(frames, ignore_index=True)
    elements.to_csv(out / "g3_elements.csv", index=False)
    print("\nG3 element by element (dry run-in shrinks from the leading element backwards):")
    print(
        elements[["case", "element", "run_in_length_mm", "film_end_um", "mu", "regime"]]
        .round(4)
        .to_string(index=False)
    )

    # 4. Synthetic rig runs with the model's friction as the known truth, then evaluated
    runs_dir = out / "rig_runs"
    runs_dir.mkdir(exist_ok=True)
    rng = np.random.default_rng(args.seed)
    truth_rows = []
    for v in (1.0, 3.0, 5.0):
        cond = Conditions.from_bar(v, 2.5, -4.0, humidity_pct=73.0)
        mu_true = float(friction_table(g3, [cond], params)["mu"].iloc[0])
        truth_rows.append({"velocity_mps": v, "mu_true": mu_true})
        for k in range(args.runs):
            df = make_raw_run(
                lambda vv, m=mu_true: np.full_like(np.asarray(vv, float), m),
                velocity_mps=v,
                sample_rate_Hz=5000,
                normal_force_N=400.0,
                temperature_C=-4.0,
                humidity_pct=73.0,
                rng=rng,
                metadata={"specimen": "G3", "run": k + 1, "condition": f"v{v:g}"},
            )
            write_run_csv(df, runs_dir / f"G3_v{v:g}_run{k + 1:02d}.csv", df.attrs["metadata"])
    result = evaluate_runs(sorted(runs_dir.glob("*.csv")), progress=False)
    write_outputs(result, out / "evaluation")
    steady = result.steady
    runs = steady[steady["row_type"] == "run"].assign(
        velocity_mps=lambda d: d["velocity_mps"].round(1)
    )
    summary = runs.groupby("velocity_mps", as_index=False).agg(
        mu_evaluated=("mu_mean_method1", "mean"), n_runs=("mu_mean_method1", "size")
    )
    summary = summary.merge(pd.DataFrame(truth_rows), on="velocity_mps", how="left")
    summary["error_pct"] = 100 * (summary["mu_evaluated"] / summary["mu_true"] - 1)
    print("\nSynthetic rig runs (G3, 2.5 bar, -4 degC, 73 %), evaluated vs. truth:")
    print(summary.round(4).to_string(index=False))
    failed = list(result.failures)
    for f in failed:
        print(f"FAILED {f}")

    # 5. Synthetic footage (TIR and side view) rendered with known truth, then analysed
    footage_table, footage_failed = _footage_demo(out, args.seed)
    print("\nSynthetic footage analysed vs. ground truth (frames with the whole block in view):")
    print(footage_table.to_string(index=False))
    failed += footage_failed

    # 6. The discrepancy workflow on the stick-slip case (end of section 5.3.2): the rig's
    # 1500 Hz against the model's prediction from the one rubber (nothing tuned to 1111 Hz)
    from friction_model.discrepancy import predicted_stick_slip_problem, stick_slip_case
    from tir_contact._outdir import write_json

    problem = predicted_stick_slip_problem()
    case = stick_slip_case(problem)
    write_json(out / "discrepancy_stick_slip.json", case.to_dict())
    fit = case.candidates.get("frequency_dependent_modulus", {})
    print("\nDiscrepancy workflow, stick-slip frequency (rig 1500 Hz; model predicted from the "
          f"one rubber: {problem.simulated_frequency_Hz[0]:.0f} Hz):")
    print(f"  verdict: {case.verdict}")
    print(f"  frequency_dependent_modulus beyond the rubber's own: strength "
          f"{fit.get('value', float('nan')):.2f} (95 % interval "
          f"{fit.get('interval', [float('nan')] * 2)[0]:.2f} to "
          f"{fit.get('interval', [float('nan')] * 2)[1]:.2f}; plausible <= "
          f"{problem.max_plausible_strength:.2f})")
    print(f"  gap before {case.gap_before_Hz:.0f} Hz, after {case.gap_after_Hz:.0f} Hz")
    if failed:
        return 1
    print(f"\nWrote results to {out.resolve()}")
    return 0


def _footage_demo(out: Path, seed: int) -> tuple[object, list[str]]:
    """Render a small footage set, analyse it with the batch runner, compare with the truth."""
    import numpy as np
    import pandas as pd

    from synthetic.footage import FootageSpec, render_footage
    from tir_contact.analyze import AnalysisOptions
    from tir_contact.batch import analyze_batch, find_footage

    footage_dir = out / "footage"
    cases = [("G3_tir_1mps", "G3", "tir", 1.0), ("G7_tir_3mps", "G7", "tir", 3.0),
             ("G3_side_1mps", "G3", "side", 1.0)]
    for name, preset, view, v in cases:
        spec = FootageSpec(preset=preset, view=view, velocity_mps=v, n_frames=400,
                           dynamics="steady", seed=seed)
        render_footage(spec, footage_dir / name, fmt="png", progress=False)
    analysis_dir = out / "analysis"
    report = analyze_batch(find_footage([footage_dir / c[0] for c in cases]), analysis_dir,
                           options=AnalysisOptions(), progress=False)
    rows = []
    for name, _, view, _ in cases:
        res = analysis_dir / name
        if not (res / "frames.csv").is_file():
            continue
        frames = pd.read_csv(res / "frames.csv")
        truth = pd.read_csv(footage_dir / name / "ground_truth.csv")
        block = truth[truth.element == -1].set_index("frame")
        full = frames[frames.block_fully_in_view.astype(bool)].set_index("frame")
        t = block.loc[full.index]
        if view == "tir":
            err = np.median(np.abs(full.contact_area_mm2 / t.contact_area_mm2 - 1)) * 100
            rows.append({"video": name, "quantity": "contact area (mm2)",
                         "measured": full.contact_area_mm2.mean(),
                         "truth": t.contact_area_mm2.mean(), "median_error": f"{err:.2f} %"})
        else:
            err = np.median(np.abs(full.deflection_angle_deg - t.deflection_angle_deg))
            rows.append({"video": name, "quantity": "deflection angle (deg)",
                         "measured": full.deflection_angle_deg.mean(),
                         "truth": t.deflection_angle_deg.mean(),
                         "median_error": f"{err:.2f} deg"})
    table = pd.DataFrame(rows).round(3)
    return table, [f"{v.path}: {v.message}" for v in report.failed]
