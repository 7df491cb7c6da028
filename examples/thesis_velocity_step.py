"""Thesis case 1: the velocity step of Fig. 5.7 needs the friction relaxation of Eq. 5.12.

The thesis's simulation of a velocity step matched the rig only after the time dependence
of friction (Eq. 5.12) was added. This script repeats that comparison end to end, with the
measurement made by the image pipeline:

1. Render side-view footage (``synthetic.footage``, camera following the block) of a G3
   block at 2.5 bar stepping from 1 m/s to 5 m/s at t = 40 ms, simulated with the rigid
   block model (:func:`friction_model.dynamics.rigid.simulate_block_dynamics`, Eq. 5.7
   friction) *with* the relaxation of Eq. 5.12, tau = 20 ms
   (:data:`friction_model.dynamics.element_step.TAU_REF_S`); 4000 frames/s, 40 ms before and 200 ms
   after the step (Fig. 5.7 records 0.2 s after the step).
2. Analyse it with the pipeline (:func:`tir_contact.analyze.analyze_video`): deflection
   angle of every element in every frame (``elements.csv``).
3. Compare the leading element's angle with the simulation *without* relaxation
   (:class:`friction_model.discrepancy.transient.TransientProblem`: the linearised element
   of Eq. 5.8 with its steady angles before and after the step fitted per run) and run the
   discrepancy workflow (:func:`friction_model.discrepancy.run_discrepancy`), which should
   name ``friction_relaxation`` with tau near 20 ms and close most of the gap.

Hold-out: contiguous time blocks of the run (two before the step, then 0-2, 2-10, 10-30,
30-100 ms and 100 ms to the end after it), each left out once (leave-one-block-out; with
fewer folds than blocks one fold can hold both late blocks and the level after the step
must then be extrapolated from the first 30 ms).

What the base model cannot match beyond the relaxation: the rendered block is the
nonlinear two-bar chain with face contact, the workflow's model the linearised one-bar
element; the two ring differently in the first ~10 ms after the step (a few hundredths of
a degree on a 3 degree step). The pipeline measures the angle to about 0.01 deg, so this
difference is resolved and the second round of the workflow may report it as an
"unexplained residual" after naming the relaxation; the script prints its size.

Run: ``python examples/thesis_velocity_step.py [--out FOLDER]`` (default
``examples/out/thesis_velocity_step``; about 40 s). Writes the footage
(``footage/footage.tif`` + ``ground_truth.csv`` + ``meta.json``), the pipeline results
(``analysis/velocity_step/``), the workflow result (``discrepancy/result.json``,
``report.md`` and its PNGs) and ``velocity_step.png`` (angle of the leading element:
pipeline, ground truth, the model without and with the relaxation).
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from _common import example_arguments, save_figure

from friction_model.discrepancy import run_discrepancy, write_result
from friction_model.discrepancy.transient import TransientProblem
from friction_model.dynamics.element_step import TAU_REF_S
from synthetic.footage import CameraSettings, FootageSpec, render_footage
from tir_contact.analyze import AnalysisOptions, analyze_video

V1_MPS, V2_MPS = 1.0, 5.0
T_STEP_S = 0.04
FPS = 4000.0
N_FRAMES = 961  # 0 .. 0.24 s: 40 ms before, 200 ms after the step
PRESSURE_BAR = 2.5
#: Largest median |pipeline - truth| angle error (deg) accepted before falling back to
#: the ground truth: tests/test_side.py holds the side view to 0.5 deg.
MAX_PIPELINE_ERROR_DEG = 0.5
#: Noise added to the ground truth in the fallback, deg (the side-view pipeline's typical
#: error on this footage is ~0.01-0.02 deg; 0.05 deg is a conservative stand-in).
FALLBACK_NOISE_DEG = 0.05


def footage_spec(seed: int) -> FootageSpec:
    """The clip: G3, side view, camera following the block, 1 -> 5 m/s, tau = 20 ms."""
    return FootageSpec(
        preset="G3",
        view="side",
        follow_camera=True,
        velocity_mps=V1_MPS,
        velocity_step_to_mps=V2_MPS,
        step_time_s=T_STEP_S,
        friction_relaxation_s=TAU_REF_S,
        pressure_bar=PRESSURE_BAR,
        n_frames=N_FRAMES,
        # 320 px = 32 mm at 0.1 mm/px holds the 20 mm block (the camera follows it)
        camera=CameraSettings(fps=FPS, width_px=320),
        # 0.1 s lead-in: the start from rest has settled (with relaxation the friction
        # creeps for several tau) before the first frame
        settle_s=0.1,
        seed=seed,
    )


def measure(spec: FootageSpec, out: Path) -> tuple[pd.DataFrame, str]:
    """Render and analyse; the leading element's angle per frame and where it came from."""
    clip = render_footage(spec, out / "footage", fmt="multitiff")
    # The following camera never shows the free background; the analysis sees that no
    # frame differs from the percentile image and normalises every frame by its own
    # background (tir_contact.side.side_darkness without a reference).
    options = AnalysisOptions(overlay_video=False, parquet=False)
    analysis = analyze_video(
        clip / "footage.tif", out / "analysis", options=options, name="velocity_step"
    )
    truth = pd.read_csv(clip / "ground_truth.csv")
    truth = truth[truth["element"] >= 0][["frame", "element", "deflection_angle_deg"]]
    both = analysis.elements.merge(
        truth, on=["frame", "element"], how="right", suffixes=("", "_true")
    )
    lead = both[both["element"] == 0].sort_values("frame")
    err = (lead["deflection_angle_deg"] - lead["deflection_angle_deg_true"]).abs()
    ok = lead["deflection_angle_deg"].notna().mean()
    print(
        f"pipeline, element 0: {ok:.0%} of {len(lead)} frames measured, |angle - truth| "
        f"median {err.median():.4f} deg, max {err.max():.4f} deg"
    )
    if ok >= 0.95 and err.median() <= MAX_PIPELINE_ERROR_DEG:
        return lead, "pipeline"
    print(
        "FALLBACK: the pipeline's angles are missing or off; using the GROUND-TRUTH angle "
        f"with {FALLBACK_NOISE_DEG} deg Gaussian noise instead"
    )
    rng = np.random.default_rng(spec.seed)
    lead = lead.copy()
    lead["deflection_angle_deg"] = lead["deflection_angle_deg_true"] + rng.normal(
        0.0, FALLBACK_NOISE_DEG, len(lead)
    )
    return lead, "ground truth + noise"


def main(argv: list[str] | None = None) -> int:
    args = example_arguments(argv, __doc__, "thesis_velocity_step", seed=1,
                             seed_help="seed of the footage noise")
    out: Path = args.out
    t0 = time.perf_counter()

    spec = footage_spec(args.seed)
    lead, source = measure(spec, out)
    elements = lead[["frame", "element", "deflection_angle_deg"]].assign(
        time_s=lead["frame"] / FPS
    )
    problem = TransientProblem.from_elements(
        elements,
        v1_mps=V1_MPS,
        v2_mps=V2_MPS,
        t_step_s=T_STEP_S,
        element=0,
        n_sipes=spec.geometry.n_sipes,
        pressure_bar=PRESSURE_BAR,
    )
    n_blocks = len(np.unique(problem.groups))
    result = run_discrepancy(
        problem, n_folds=n_blocks, n_bootstrap=200, n_permutations=499, seed=0
    )
    write_result(result, out / "discrepancy")

    print(f"\nFig. 5.7 velocity step {V1_MPS:g} -> {V2_MPS:g} m/s, G3, {PRESSURE_BAR} bar, "
          f"footage rendered with tau = {TAU_REF_S * 1e3:g} ms (angles: {source})")
    print(f"noise of the angle (std before the step): {problem.runs[0].sigma:.4f} deg")
    print(f"{'held-out block':<28}{'n':>5}{'RMSE base':>12}{'RMSE +effect':>14}")
    for row in sorted(result.gap["per_condition"], key=lambda r: _block_order(r["group"])):
        print(f"{row['group'].split(':', 1)[1]:<28}{row['n']:>5}{row['rmse_before']:>12.4f}"
              f"{row['rmse_after']:>14.4f}")
    for name, info in result.fitted.items():
        for p in info["parameters"]:
            scale = 1e3 if p["unit"] == "s" else 1.0
            unit = "ms" if p["unit"] == "s" else p["unit"]
            print(f"fitted {name}.{p['name']} = {p['value'] * scale:.2f} {unit} "
                  f"(95 % interval {p['ci_lower'] * scale:.2f} .. {p['ci_upper'] * scale:.2f}; "
                  f"rendered with {TAU_REF_S * 1e3:g})")
    print(f"held-out gap (RMSE, deg): before {result.gap_before:.4f}, after "
          f"{result.gap_after:.4f} ({1 - result.gap_after / result.gap_before:.0%} smaller)")
    print(f"verdict: {result.verdict}")
    if "unexplained" in result.verdict:
        early = [r for r in result.gap["per_condition"] if r["group"].endswith(("0ms-2ms",
                                                                                  "2ms-10ms"))]
        sizes = ", ".join(f"{r['rmse_after']:.3f}" for r in early)
        print(f"  what is left: RMSE {sizes} deg in the first 10 ms against a noise of "
              f"{problem.runs[0].sigma:.3f} deg: the rendered two-bar block rings differently "
              "from the linearised one-bar element of the workflow (module notes), not a "
              "further missing effect")

    _plot(result, problem, lead, out / "velocity_step.png")
    print(f"wrote {out} ({time.perf_counter() - t0:.0f} s)")
    return 0


def _block_order(group: str) -> float:
    label = group.split(":", 1)[1]
    if label.startswith("before"):
        return -2.0 + float(label[-1]) * 0.1
    return float(label.split("-")[1].removesuffix("ms"))


def _plot(result, problem: TransientProblem, lead: pd.DataFrame, path: Path) -> None:
    t_ms = (problem.covariates["time_since_step_s"].to_numpy()) * 1e3
    fig, (ax, ax_r) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True,
                                   gridspec_kw={"height_ratios": [2, 1]})
    ax.plot(t_ms, lead["deflection_angle_deg_true"].to_numpy(), color="0.6", lw=2.5,
            label="ground truth (rigid model, tau = 20 ms)")
    ax.plot(t_ms, problem.y, ".", ms=2.5, color="k", label="pipeline (elements.csv)")
    ax.plot(t_ms, result.prediction_before, color="C3", lw=1.2,
            label="model without relaxation (held out)")
    ax.plot(t_ms, result.prediction_after, color="C0", lw=1.2,
            label="model + " + " + ".join(result.missing_effects or ["nothing"]) + " (held out)")
    ax.axvline(0.0, color="0.5", ls="--", lw=0.8)
    ax.set_ylabel("deflection angle, element 0 / deg")
    ax.legend(fontsize=8)
    ax.set_title("Velocity step 1 -> 5 m/s (cp. Fig. 5.7): the missing Eq. 5.12")
    ax_r.plot(t_ms, problem.y - result.prediction_before, color="C3", lw=0.8, label="base")
    ax_r.plot(t_ms, problem.y - result.prediction_after, color="C0", lw=0.8,
              label="with the named effect")
    ax_r.axhline(0.0, color="0.5", lw=0.6)
    ax_r.set_ylabel("residual / deg")
    ax_r.set_xlabel("time since the step / ms")
    ax_r.legend(fontsize=8)
    save_figure(fig, path)


if __name__ == "__main__":
    raise SystemExit(main())
