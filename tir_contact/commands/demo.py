"""``tir-contact demo``: the main job on data the toolkit makes itself.

It shows the friction model (Fig. 4.26, the Table 4.6 comparison, the per-element result of
a siped block) and the test-rig evaluation (synthetic runs with known friction, evaluated
and compared with the truth), and renders TIR and side-view footage with known ground truth
and analyses it with the contact pipeline (``tir-contact analyze``), and ends with the
discrepancy workflow on the stick-slip case (1500 Hz measured against the frequency the
model predicts from the one rubber), printing the verdict and the gap before and after.

The steps are :func:`run_demo` (plain arguments, a :class:`DemoResult`); the command prints
its report. Only this module and :mod:`tir_contact.commands.synth` import :mod:`synthetic`.
The model, the analysis and the renderer are imported by the steps that use them, so that
``tir-contact demo --help`` stays fast.
"""

from __future__ import annotations

import argparse
import logging
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from tir_contact.commands._types import output_folder

if TYPE_CHECKING:
    from friction_model import BlockGeometry, DryWetParameters

logger = logging.getLogger(__name__)

__all__ = ["DESCRIPTION", "DemoResult", "add_arguments", "run", "run_demo"]

DESCRIPTION = (
    "Compute the friction model's Fig. 4.26 and Table 4.6 comparison, make synthetic "
    "test-rig runs with known friction and evaluate them. Writes CSV and PNG files."
)
#: Allowed repeated runs per velocity.
_RUNS_RANGE = (1, 10)
#: The footage the demo renders: name, preset, view, velocity in m/s.
_FOOTAGE_CASES = (("G3_tir_1mps", "G3", "tir", 1.0), ("G7_tir_3mps", "G7", "tir", 3.0),
                  ("G3_side_1mps", "G3", "side", 1.0))


def _runs(text: str) -> int:
    """argparse type of ``--runs``: an integer in 1..10."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    lo, hi = _RUNS_RANGE
    if not lo <= value <= hi:
        raise argparse.ArgumentTypeError(f"expected an integer in {lo}..{hi}, got {text!r}")
    return value


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``tir-contact demo``."""
    p.add_argument("--out", type=output_folder, default=Path("demo-out"),
                   help="output folder")
    p.add_argument("--seed", type=int, default=1, help="random seed of the synthetic runs")
    p.add_argument("--runs", type=_runs, default=3, help="repeated runs per velocity (1..10)")


@dataclass(frozen=True)
class DemoResult:
    """What :func:`run_demo` computed (its files are in ``out_dir``).

    Attributes
    ----------
    out_dir : Path
    table_4_6_rmse : dict
        RMSE of mu per Table 4.6 curve.
    elements : pandas.DataFrame
        The G3 block element by element in two cases (Fig. 4.25).
    rig_summary : pandas.DataFrame
        Evaluated against true mu of the synthetic rig runs per velocity.
    rig_failures : list of str
        Rig runs the evaluation could not use.
    footage : pandas.DataFrame
        Measured against true contact area / deflection angle per synthetic video.
    footage_failures : list of str
        Videos the analysis could not use.
    stick_slip_problem, stick_slip_case
        The discrepancy workflow on the stick-slip frequency.
    """

    out_dir: Path
    table_4_6_rmse: dict[str, float]
    elements: pd.DataFrame
    rig_summary: pd.DataFrame
    rig_failures: list[str]
    footage: pd.DataFrame
    footage_failures: list[str]
    stick_slip_problem: Any
    stick_slip_case: Any

    @property
    def ok(self) -> bool:
        """Whether every rig run and every video was used."""
        return not (self.rig_failures or self.footage_failures)

    def report(self) -> str:
        """The demo's printed report."""
        lines = ["Dry/wet model vs. Table 4.6 (G3, v = 1..7 m/s), RMSE of mu per curve:"]
        lines += [f"  {name:22s} {value:.4f}" for name, value in self.table_4_6_rmse.items()]
        lines += [
            "\nG3 element by element (dry run-in shrinks from the leading element backwards):",
            self.elements[["case", "element", "run_in_length_mm", "film_end_um", "mu", "regime"]]
            .round(4).to_string(index=False),
            "\nSynthetic rig runs (G3, 2.5 bar, -4 degC, 73 %), evaluated vs. truth:",
            self.rig_summary.round(4).to_string(index=False),
            *(f"FAILED {f}" for f in self.rig_failures),
            "\nSynthetic footage analysed vs. ground truth (frames with the whole block in "
            "view):",
            self.footage.to_string(index=False),
            *self._stick_slip_lines(),
        ]
        if self.ok:
            lines.append(f"\nWrote results to {self.out_dir.resolve()}")
        return "\n".join(lines)

    def _stick_slip_lines(self) -> list[str]:
        """The verdict, the strength of the modulus effect and the gap before and after."""
        problem, case = self.stick_slip_problem, self.stick_slip_case
        fit = case.candidates.get("frequency_dependent_modulus", {})
        low, high = fit.get("interval", [float("nan")] * 2)
        return [
            "\nDiscrepancy workflow, stick-slip frequency (rig 1500 Hz; model predicted from "
            f"the one rubber: {problem.simulated_frequency_Hz[0]:.0f} Hz):",
            f"  verdict: {case.verdict}",
            f"  frequency_dependent_modulus beyond the rubber's own: strength "
            f"{fit.get('value', float('nan')):.2f} (95 % interval {low:.2f} to {high:.2f}; "
            f"plausible <= {problem.max_plausible_strength:.2f})",
            f"  gap before {case.gap_before_Hz:.0f} Hz, after {case.gap_after_Hz:.0f} Hz",
        ]


def _save_figure(fig: Any, path: Path) -> None:
    """Write a figure as PNG and close it."""
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=120)
    plt.close(fig)


def _fig_4_26(out: Path) -> None:
    """Step 1, Fig. 4.26: the dry run-in length of Eq. 4.7 over v, p, dT and mu_dry."""
    from friction_model.plots import fig_4_26_table, plot_fig_4_26

    fig_4_26_table().to_csv(out / "fig_4_26_dry_length.csv", index=False)
    _save_figure(plot_fig_4_26(), out / "fig_4_26_dry_length.png")


def _table_4_6(out: Path, params: DryWetParameters) -> dict[str, float]:
    """Step 2, Table 4.6: the calibrated model against the measured characteristics."""
    from friction_model import evaluate_on_table_4_6
    from friction_model.plots import plot_table_4_6

    table, rmse = evaluate_on_table_4_6(params)
    table.to_csv(out / "table_4_6_model.csv", index=False)
    _save_figure(plot_table_4_6(table, rmse), out / "table_4_6_model.png")
    return rmse


def _block_elements(out: Path, params: DryWetParameters, block: BlockGeometry) -> pd.DataFrame:
    """Step 3, Fig. 4.25: the siped block element by element, cold-dry and warm-humid."""
    from friction_model import Conditions, simulate_block

    frames = []
    for label, cond in (
        ("cold-dry", Conditions.from_bar(1.0, 2.5, -5.0, humidity_pct=40.0)),
        ("warm-humid", Conditions.from_bar(5.0, 2.5, -1.0, humidity_pct=95.0)),
    ):
        res = simulate_block(block, cond, params)
        frames.append(res.elements.assign(case=label))
        _save_figure(res.plot(), out / f"block_profile_{label}.png")
    elements = pd.concat(frames, ignore_index=True)
    elements.to_csv(out / "g3_elements.csv", index=False)
    return elements


def _rig_runs(
    out: Path, params: DryWetParameters, block: BlockGeometry, seed: int, runs: int
) -> tuple[pd.DataFrame, list[str]]:
    """Step 4: synthetic rig runs with the model's friction as the known truth, evaluated;
    the evaluated mu per velocity against the truth, and the runs that failed."""
    from friction_model import Conditions, friction_table
    from friction_model.rig import evaluate_runs, write_outputs
    from synthetic.rig import make_raw_run, write_run_csv

    runs_dir = out / "rig_runs"
    runs_dir.mkdir(exist_ok=True)
    rng = np.random.default_rng(seed)
    truth_rows = []
    for v in (1.0, 3.0, 5.0):
        cond = Conditions.from_bar(v, 2.5, -4.0, humidity_pct=73.0)
        mu_true = float(friction_table(block, [cond], params)["mu"].iloc[0])
        truth_rows.append({"velocity_mps": v, "mu_true": mu_true})
        for k in range(runs):
            df = make_raw_run(
                lambda vv, m=mu_true: np.full_like(np.asarray(vv, float), m),
                velocity_mps=v,
                sample_rate_Hz=5000,
                normal_force_N=400.0,
                temperature_C=-4.0,
                humidity_pct=73.0,
                rng=rng,
                metadata={"specimen": "G3", "run": k + 1, "condition": f"v{v:g}",
                          "salinity_pct": cond.salinity_pct},
            )
            write_run_csv(df, runs_dir / f"G3_v{v:g}_run{k + 1:02d}.csv", df.attrs["metadata"])
    result = evaluate_runs(sorted(runs_dir.glob("*.csv")), progress=False)
    write_outputs(result, out / "evaluation")
    steady = result.steady
    evaluated = steady[steady["row_type"] == "run"].assign(
        velocity_mps=lambda d: d["velocity_mps"].round(1)
    )
    summary = evaluated.groupby("velocity_mps", as_index=False).agg(
        mu_evaluated=("mu_mean_method1", "mean"), n_runs=("mu_mean_method1", "size")
    )
    summary = summary.merge(pd.DataFrame(truth_rows), on="velocity_mps", how="left")
    summary["error_pct"] = 100 * (summary["mu_evaluated"] / summary["mu_true"] - 1)
    return summary, list(result.failures)


def _footage_row(name: str, view: str, frames: pd.DataFrame, truth: pd.DataFrame) -> dict:
    """Measured against true contact area (TIR) or deflection angle (side view), over the
    frames with the whole block in view."""
    block = truth[truth.element == -1].set_index("frame")
    full = frames[frames.block_fully_in_view.astype(bool)].set_index("frame")
    t = block.loc[full.index]
    if view == "tir":
        err = np.median(np.abs(full.contact_area_mm2 / t.contact_area_mm2 - 1)) * 100
        return {"video": name, "quantity": "contact area (mm2)",
                "measured": full.contact_area_mm2.mean(),
                "truth": t.contact_area_mm2.mean(), "median_error": f"{err:.2f} %"}
    err = np.median(np.abs(full.deflection_angle_deg - t.deflection_angle_deg))
    return {"video": name, "quantity": "deflection angle (deg)",
            "measured": full.deflection_angle_deg.mean(),
            "truth": t.deflection_angle_deg.mean(), "median_error": f"{err:.2f} deg"}


def _footage_demo(out: Path, seed: int) -> tuple[pd.DataFrame, list[str]]:
    """Step 5: render a small footage set, analyse it with the batch runner, compare with
    the truth."""
    from synthetic.footage import FootageSpec, render_footage
    from tir_contact.analyze import AnalysisOptions
    from tir_contact.batch import analyze_batch, find_footage

    footage_dir = out / "footage"
    for name, preset, view, v in _FOOTAGE_CASES:
        spec = FootageSpec(preset=preset, view=view, velocity_mps=v, n_frames=400,
                           dynamics="steady", seed=seed)
        render_footage(spec, footage_dir / name, fmt="png", progress=False)
    analysis_dir = out / "analysis"
    report = analyze_batch(find_footage([footage_dir / c[0] for c in _FOOTAGE_CASES]),
                           analysis_dir, options=AnalysisOptions(), progress=False)
    rows = []
    for name, _, view, _ in _FOOTAGE_CASES:
        res = analysis_dir / name
        if not (res / "frames.csv").is_file():
            continue
        rows.append(_footage_row(name, view, pd.read_csv(res / "frames.csv"),
                                 pd.read_csv(footage_dir / name / "ground_truth.csv")))
    table = pd.DataFrame(rows).round(3)
    return table, [f"{v.path}: {v.message}" for v in report.failed]


def _stick_slip(out: Path) -> tuple[Any, Any]:
    """Step 6, end of section 5.3.2: the rig's 1500 Hz against the model's prediction from
    the one rubber (nothing tuned to 1111 Hz), through the discrepancy workflow."""
    from friction_model.discrepancy import predicted_stick_slip_problem, stick_slip_case
    from tir_common.atomic import write_json

    problem = predicted_stick_slip_problem()
    case = stick_slip_case(problem)
    write_json(out / "discrepancy_stick_slip.json", case.to_dict())
    return problem, case


def run_demo(out_dir: str | Path, *, seed: int = 1, runs: int = 3) -> DemoResult:
    """Run the demo's six steps, writing CSV, PNG and JSON files into `out_dir` (created).

    Parameters
    ----------
    out_dir : path-like
        Output folder.
    seed : int
        Random seed of the synthetic runs and footage.
    runs : int
        Repeated rig runs per velocity, 1..10.

    Returns
    -------
    DemoResult

    Raises
    ------
    ValueError
        `runs` outside 1..10.
    """
    lo, hi = _RUNS_RANGE
    if not lo <= runs <= hi:
        raise ValueError(f"runs must lie in {lo}..{hi}, got {runs}")
    from friction_model import DryWetParameters, reference_block

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    params = DryWetParameters()
    g3 = reference_block("G3")
    _fig_4_26(out)
    rmse = _table_4_6(out, params)
    elements = _block_elements(out, params, g3)
    rig_summary, rig_failures = _rig_runs(out, params, g3, seed, runs)
    footage, footage_failures = _footage_demo(out, seed)
    problem, case = _stick_slip(out)
    return DemoResult(out, rmse, elements, rig_summary, rig_failures, footage,
                      footage_failures, problem, case)


def run(args: argparse.Namespace) -> int:
    """Run ``tir-contact demo``: :func:`run_demo`, then its report; 1 when anything failed."""
    result = run_demo(args.out, seed=args.seed, runs=args.runs)
    print(result.report())
    return 0 if result.ok else 1
