"""The demo: the toolkit's main job on data it makes itself (``tir-contact demo``).

It tells the mission's story first: rig measurements are made with an effect the base model
lacks hidden in them (seeded, the files name no effect), and the discrepancy workflow finds
where model and data disagree, names the missing effect with its interval and shows the
held-out gap before and after adding it (``discrepancy_hidden_effect.json``). Then it shows
the friction model (Fig. 4.26, the Table 4.6 comparison, the per-element result of
a siped block) and the test-rig evaluation (synthetic runs with known friction, evaluated
and compared with the truth), and renders TIR and side-view footage with known ground truth
and analyses it with the contact pipeline (``tir-contact analyze``), and ends with the
discrepancy workflow on the stick-slip case (1500 Hz measured against the frequency the
model predicts from the one rubber), printing the verdict and the gap before and after.

The steps are :func:`run_demo` (plain arguments, a :class:`DemoResult`);
:mod:`tir_contact.commands.demo` parses the options, calls it and prints
:meth:`DemoResult.report`. Only this module and :mod:`tir_contact.commands.synth` import
:mod:`synthetic` (the demo makes its own data). The model, the analysis and the renderer are
imported by the steps that use them, so that importing this module stays cheap.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

if TYPE_CHECKING:
    from friction_model import BlockGeometry, DryWetParameters

logger = logging.getLogger(__name__)

__all__ = [
    "HIDDEN_EFFECT",
    "HIDDEN_GRID",
    "HIDDEN_STRENGTH",
    "RUNS_RANGE",
    "DemoResult",
    "HiddenEffectCase",
    "run_demo",
    "run_hidden_effect",
]

#: Allowed repeated runs per velocity.
RUNS_RANGE = (1, 10)
#: The effect hidden in the demo's rig measurements: the viscous shear of the melt film
#: (Eq. 4.3), which the base model lacks.
HIDDEN_EFFECT = "viscous_shear"
#: Its strength: three times the calibrated shear, an effect about 3.9 times the 5 % noise on
#: :data:`HIDDEN_GRID` once the base model's factor on mu has absorbed what it can
#: (``synthetic.effect_size.effect_size``): the size the workflow's tests ask it to find.
HIDDEN_STRENGTH = 3.0
#: The conditions of the hidden-effect measurements: velocity 1, 3, 5 m/s, 2.5 bar, -6, -3,
#: -1.5 degC, 40 and 90 % humidity, fresh and saline ice, G0 and G3 (72 rows, 24 hold-out
#: groups: a rig campaign of section 4.2 in miniature).
HIDDEN_GRID: dict[str, tuple[float, ...]] = {
    "velocities_mps": (1.0, 3.0, 5.0),
    "pressures_bar": (2.5,),
    "temperatures_C": (-6.0, -3.0, -1.5),
    "humidities_pct": (40.0, 90.0),
    "salinities_pct": (0.0, 0.05),
    "n_sipes": (0, 3),
}
#: Block-bootstrap resamples and permutations of the hidden-effect case: fewer than the
#: workflow's defaults (100, 999), enough for a 95 % interval and a p-value down to 0.005,
#: and quick enough for a demo.
_HIDDEN_BOOTSTRAP = 40
_HIDDEN_PERMUTATIONS = 199
#: The footage the demo renders: name, preset, view, velocity in m/s.
_FOOTAGE_CASES = (("G3_tir_1mps", "G3", "tir", 1.0), ("G7_tir_3mps", "G7", "tir", 3.0),
                  ("G3_side_1mps", "G3", "side", 1.0))


@dataclass(frozen=True)
class HiddenEffectCase:
    """The demo's first story: an effect hidden in rig measurements, found by the workflow.

    Attributes
    ----------
    hidden : str
        The effect hidden in the data.
    hidden_strength : float
        Its strength in the data.
    noise : float
        Relative noise of the measurements.
    result : DiscrepancyResult
        The workflow's result on the measurements (it was not told what is hidden).
    """

    hidden: str
    hidden_strength: float
    noise: float
    result: Any

    @property
    def named(self) -> list[str]:
        """The effects the workflow named."""
        return list(self.result.missing_effects)

    @property
    def found(self) -> bool:
        """The hidden effect named, and nothing else, with the gap at least halved."""
        r = self.result
        return self.named == [self.hidden] and r.gap_after <= 0.5 * r.gap_before

    def disagreement(self) -> list[dict[str, float | str]]:
        """The covariates the base model's residuals follow (significant ones, strongest
        first): name, Spearman rho and permutation p-value."""
        rows = [c for c in self.result.where.get("before", {}).get("covariates", [])
                if c.get("significant")]
        rows.sort(key=lambda c: -abs(c["spearman_rho"]))
        return [{"covariate": c["name"], "spearman_rho": c["spearman_rho"],
                 "p_value": c["p_value"]} for c in rows]

    def to_dict(self) -> dict[str, Any]:
        """The content of ``discrepancy_hidden_effect.json``."""
        r = self.result
        return {
            "hidden": self.hidden,
            "hidden_strength": self.hidden_strength,
            "noise": self.noise,
            "named": self.named,
            "verdict": r.verdict,
            "fitted": r.fitted,
            "gap_before": r.gap_before,
            "gap_after": r.gap_after,
            "gap_after_over_before": r.gap_after / r.gap_before,
            "disagreement": self.disagreement(),
            "found": self.found,
        }

    def lines(self) -> list[str]:
        """The printed story."""
        r = self.result
        out = [
            f"Hidden effect: synthetic rig measurements (steady mu, {r.n} conditions, "
            f"{self.noise:.0%} noise) made with an effect the base model lacks; the workflow "
            "is not told which.",
            "  disagreement of the base model: residuals follow "
            + (", ".join(f"{d['covariate']} (rho {d['spearman_rho']:+.2f}, p = "
                         f"{d['p_value']:.3f})" for d in self.disagreement()[:3]) or "nothing"),
            f"  verdict: {r.verdict}",
        ]
        for name in self.named:
            (p, *_) = r.fitted[name]["parameters"]
            out.append(f"  named {name}: {p['name']} {p['value']:.2f} (95 % interval "
                       f"{p['ci_lower']:.2f} to {p['ci_upper']:.2f})")
        out += [
            f"  hidden was {self.hidden} at strength {self.hidden_strength:g}: "
            + ("found" if self.found else "NOT found"),
            f"  held-out gap (weighted RMSE of mu) before {r.gap_before:.4f}, after "
            f"{r.gap_after:.4f} ({r.gap_after / r.gap_before - 1:+.0%})",
        ]
        return out


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
    hidden_effect : HiddenEffectCase or None
        The discrepancy workflow on measurements with a hidden effect (the first story).
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
    hidden_effect: HiddenEffectCase | None = None

    @property
    def ok(self) -> bool:
        """Whether every rig run and every video was used."""
        return not (self.rig_failures or self.footage_failures)

    def report(self) -> str:
        """The demo's printed report: the hidden-effect story first."""
        lines = [*self.hidden_effect.lines(), ""] if self.hidden_effect is not None else []
        lines += ["Dry/wet model vs. Table 4.6 (G3, v = 1..7 m/s), RMSE of mu per curve:"]
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
    """Step 2, Fig. 4.26: the dry run-in length of Eq. 4.7 over v, p, dT and mu_dry."""
    from friction_model.plots import fig_4_26_table, plot_fig_4_26

    fig_4_26_table().to_csv(out / "fig_4_26_dry_length.csv", index=False)
    _save_figure(plot_fig_4_26(), out / "fig_4_26_dry_length.png")


def _table_4_6(out: Path, params: DryWetParameters) -> dict[str, float]:
    """Step 3, Table 4.6: the calibrated model against the measured characteristics."""
    from friction_model import evaluate_on_table_4_6
    from friction_model.plots import plot_table_4_6

    table, rmse = evaluate_on_table_4_6(params)
    table.to_csv(out / "table_4_6_model.csv", index=False)
    _save_figure(plot_table_4_6(table, rmse), out / "table_4_6_model.png")
    return rmse


def _block_elements(out: Path, params: DryWetParameters, block: BlockGeometry) -> pd.DataFrame:
    """Step 4, Fig. 4.25: the siped block element by element, cold-dry and warm-humid."""
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
    """Step 5: synthetic rig runs with the model's friction as the known truth, evaluated;
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
    from tir_contact.report import write_evaluation_report

    write_evaluation_report(out / "evaluation")
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
    """Step 6: render a small footage set, analyse it with the batch runner, compare with
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
    """Step 7, end of section 5.3.2: the rig's 1500 Hz against the model's prediction from
    the one rubber (nothing tuned to 1111 Hz), through the discrepancy workflow."""
    from friction_model.discrepancy import predicted_stick_slip_problem, stick_slip_case
    from tir_common.atomic import write_json

    problem = predicted_stick_slip_problem()
    case = stick_slip_case(problem)
    write_json(out / "discrepancy_stick_slip.json", case.to_dict())
    return problem, case


def run_hidden_effect(out_dir: str | Path, *, seed: int = 1) -> HiddenEffectCase:
    """Step 1, the mission: measurements with :data:`HIDDEN_EFFECT` hidden in them, through
    the discrepancy workflow, which is told nothing of it.

    Parameters
    ----------
    out_dir : path-like
        Folder (created) for ``hidden_effect_measurements.csv`` (the data, no truth) and
        ``discrepancy_hidden_effect.json`` (:meth:`HiddenEffectCase.to_dict`).
    seed : int
        Seed of the measurement noise and of the workflow's folds and resamples.

    Returns
    -------
    HiddenEffectCase
    """
    from friction_model.discrepancy import SteadyProblem, run_discrepancy
    from synthetic.measurements import DEFAULT_NOISE, make_steady_table
    from tir_common.atomic import write_json

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    table = make_steady_table(HIDDEN_GRID, effects={HIDDEN_EFFECT: HIDDEN_STRENGTH},
                              noise=DEFAULT_NOISE, rng=seed)
    table.attrs.clear()  # the truth stays out of the file, as on a real rig
    table.to_csv(out / "hidden_effect_measurements.csv", index=False, float_format="%.10g")
    result = run_discrepancy(SteadyProblem(table), n_bootstrap=_HIDDEN_BOOTSTRAP,
                             n_permutations=_HIDDEN_PERMUTATIONS, seed=seed)
    case = HiddenEffectCase(HIDDEN_EFFECT, HIDDEN_STRENGTH, DEFAULT_NOISE, result)
    write_json(out / "discrepancy_hidden_effect.json", case.to_dict())
    return case


def run_demo(out_dir: str | Path, *, seed: int = 1, runs: int = 3) -> DemoResult:
    """Run the demo's seven steps, writing CSV, PNG and JSON files into `out_dir` (created).

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

    Notes
    -----
    Step 1 hides :data:`HIDDEN_EFFECT` in synthetic steady measurements
    (``hidden_effect_measurements.csv``) and runs the discrepancy workflow on them
    (``discrepancy_hidden_effect.json``: ``hidden``, ``named``, ``gap_before``,
    ``gap_after``, ...); steps 2-7 are Fig. 4.26, Table 4.6, the G3 block element by element,
    synthetic rig runs, synthetic footage and the stick-slip case.

    Raises
    ------
    ValueError
        `runs` outside 1..10.
    """
    lo, hi = RUNS_RANGE
    if not lo <= runs <= hi:
        raise ValueError(f"runs must lie in {lo}..{hi}, got {runs}")
    from friction_model import DryWetParameters, reference_block

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    params = DryWetParameters()
    g3 = reference_block("G3")
    hidden = run_hidden_effect(out, seed=seed)
    _fig_4_26(out)
    rmse = _table_4_6(out, params)
    elements = _block_elements(out, params, g3)
    rig_summary, rig_failures = _rig_runs(out, params, g3, seed, runs)
    footage, footage_failures = _footage_demo(out, seed)
    problem, case = _stick_slip(out)
    return DemoResult(out, rmse, elements, rig_summary, rig_failures, footage,
                      footage_failures, problem, case, hidden)
