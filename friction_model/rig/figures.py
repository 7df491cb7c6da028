"""Figures of the rig evaluation: ``mu(t)`` of every run and ``mu(v)`` of the batch.

matplotlib is imported inside the plotting functions: it costs about 0.3 s at start-up and
only the figures need it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from friction_model.rig.results import EvaluationResult, InstationaryRunResult, SteadyRunResult
from tir_common.atomic import atomic_write

__all__: list[str] = []


def _save_figure(fig: Any, path: Path) -> Path:
    """Write ``fig`` as PNG to ``path`` atomically."""
    return atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))


def _plot_mu_t(result: SteadyRunResult | InstationaryRunResult, path: Path) -> Path:
    """``mu(t)`` and ``v(t)`` of one run with its evaluated window or branches (PNG)."""
    from matplotlib.figure import Figure

    tr = result.trace
    fig = Figure(figsize=(8.0, 4.5), layout="constrained")
    ax = fig.subplots()
    ax.plot(tr["time_s"], tr["mu"], lw=0.6, color="0.35", label=r"$\mu(t) = F_F/F_N$")
    if isinstance(result, SteadyRunResult):
        w = result.window
        ax.axvspan(w.start_s, w.end_s, color="tab:green", alpha=0.2, label="evaluated window")
        ax.axhline(result.mu_mean_method1, color="tab:green", lw=1.2, label=r"$\bar\mu$ (method 1)")
        title = f"v = {result.velocity_mps:.3g} m/s, mu = {result.mu_mean_method1:.4f}"
        inside = tr["mu"][(tr["time_s"] >= w.start_s) & (tr["time_s"] <= w.end_s)]
    else:
        ax.plot(tr["time_s"], tr["mu_corrected"], lw=1.0, color="tab:blue", label="inertia removed")
        colours = {"accelerating": "tab:red", "decelerating": "tab:blue"}
        for branch, (t0, t1) in tr["spans"].items():
            ax.axvspan(t0, t1, color=colours[branch], alpha=0.12, label=branch)
        title = f"instationary, m = {result.inertial_mass_kg:.4g} kg"
        inside = tr["mu_corrected"]
    finite = inside[np.isfinite(inside)]
    if finite.size:
        lo, hi = np.percentile(finite, [0.5, 99.5])
        pad = 0.5 * (hi - lo) + 0.02
        ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(r"friction coefficient $\mu$ [-]")
    ax2 = ax.twinx()
    ax2.plot(tr["time_s"], tr["velocity_mps"], lw=0.8, color="tab:orange")
    ax2.set_ylabel("sliding velocity v [m/s]", color="tab:orange")
    ident = " ".join(x for x in (result.specimen, result.condition) if x)
    run = f" run {result.run}" if result.run is not None else ""
    ax.set_title(f"{Path(result.file).name}: {ident}{run} - {title}", fontsize=9)
    ax.legend(loc="lower right", fontsize=8)
    return _save_figure(fig, path)


def _plot_mu_v(result: EvaluationResult, path: Path) -> Path:
    """Steady aggregates with error bars and instationary branches over velocity (PNG)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.5), layout="constrained")
    ax = fig.subplots()
    steady = result.steady
    if not steady.empty:
        runs = steady[steady["row_type"] == "run"]
        agg = steady[steady["row_type"] == "aggregate"]
        ax.plot(runs["velocity_mps"], runs["mu_mean_method1"], ".", color="0.6", ms=3)
        for (specimen, condition), g in agg.groupby(["specimen", "condition"], sort=False):
            label = " ".join(x for x in (str(specimen), str(condition)) if x) or "steady"
            ax.errorbar(
                g["velocity_mps"],
                g["mu_mean_method1"],
                yerr=g["mu_std_runs"].fillna(0.0),
                fmt="o",
                capsize=3,
                label=f"{label} (steady)",
            )
    styles = {"accelerating": "-", "decelerating": "--"}
    for r in result.instationary_runs:
        ident = " ".join(x for x in (r.specimen, r.condition) if x) or Path(r.file).stem
        for branch, g in r.table.groupby("branch", sort=False):
            ax.plot(g["velocity_mps"], g["mu"], styles[branch], label=f"{ident} {branch}")
    ax.set_xlabel("sliding velocity v [m/s]")
    ax.set_ylabel(r"friction coefficient $\mu$ [-]")
    ax.set_xlim(left=0.0)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    return _save_figure(fig, path)
