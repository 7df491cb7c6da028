"""Output folder of the discrepancy workflow: result.json, report.md and PNG plots."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from friction_model.discrepancy._workflow import DiscrepancyResult
from tir_common.atomic import atomic_write, json_safe

__all__ = ["PLOT_FILES", "write_result"]

#: The plots written next to result.json.
PLOT_FILES: tuple[str, ...] = ("residuals.png", "measured_vs_simulated.png", "candidates.png")


def _write_text(path: Path, text: str) -> None:
    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)

    atomic_write(path, write)


def _save_figure(fig, path: Path) -> None:
    import matplotlib.pyplot as plt

    atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))
    plt.close(fig)


def _report_md(result: DiscrepancyResult) -> str:
    """The text of report.md: verdict, effects, residual structure, rounds, scores, plots."""
    lines = [
        *_summary_lines(result),
        *_effect_lines(result),
        *_where_lines(result),
        *_round_lines(result),
        *_score_lines(result),
        "",
        "## Plots",
        "",
        *(f"![{name}]({name})" for name in PLOT_FILES),
        "",
    ]
    return "\n".join(lines)


def _summary_lines(result: DiscrepancyResult) -> list[str]:
    """Title, verdict, data size, the gap before and after, effects not tried."""
    lines = [
        "# Discrepancy report",
        "",
        f"**Verdict:** {result.verdict}",
        "",
        f"- data: {result.kind}, {result.n} observations",
        f"- held-out RMSE before: {result.gap_before:.4g}, after: {result.gap_after:.4g}"
        + (
            f" ({100 * (1 - result.gap_after / result.gap_before):.0f} % smaller)"
            if result.gap_before > 0
            else ""
        ),
        f"- held-out reduced chi-square before: {result.gap['reduced_chi2_before']:.3g}, "
        f"after: {result.gap['reduced_chi2_after']:.3g}",
    ]
    if result.not_revealable:
        lines.append(
            "- not tried, this data cannot reveal them (they leave it exactly unchanged or "
            "the problem cannot evaluate them): " + ", ".join(result.not_revealable)
        )
    return lines


def _effect_lines(result: DiscrepancyResult) -> list[str]:
    """The missing effects with their fitted parameters, intervals and bounds."""
    lines = ["", "## Missing effects", ""]
    if not result.fitted:
        lines.append("None named.")
    for name, info in result.fitted.items():
        for p in info["parameters"]:
            lines.append(
                f"- {name} (round {info['round']}): {p['name']} = {p['value']:.4g} {p['unit']}"
                f", 95 % interval [{p['ci_lower']:.4g}, {p['ci_upper']:.4g}], "
                f"bounds [{p['lower']:.4g}, {p['upper']:.4g}]"
            )
    return lines


def _where_lines(result: DiscrepancyResult) -> list[str]:
    """Residual structure before the effects: one table row per covariate, spectra."""
    lines = ["", "## Where model and data disagree (before)", ""]
    lines.append("| covariate | Spearman rho | p | significant ranges |")
    lines.append("|---|---|---|---|")
    for e in result.where["before"]["covariates"]:
        ranges = ", ".join(
            (f"{r['lower']:g}" if r["lower"] == r["upper"] else f"{r['lower']:g}..{r['upper']:g}")
            + f" (z={r['z']:.1f})"
            for r in e["ranges"]
            if r["significant"]
        )
        lines.append(
            f"| {e['name']} | {e['spearman_rho']:.3f} | {e['p_value']:.3g} | {ranges or '-'} |"
        )
    for key in ("spectrum_before", "spectrum_after"):
        if key in result.where:
            s = result.where[key]
            lines.append(
                f"\nResidual spectrum ({key.split('_')[1]}): peak at {s['peak_Hz']:.4g} Hz, "
                f"share {s['peak_share']:.3f}, Fisher p = {s['p_value']:.3g}"
            )
    return lines


def _round_lines(result: DiscrepancyResult) -> list[str]:
    """The decision of each round and the criteria of its best candidate."""
    lines = ["", "## Rounds", ""]
    for r in result.rounds:
        lines.append(f"- round {r['round']} (current model: {r['current_model']}): {r['text']}")
        if "criteria" in r:
            crit = ", ".join(f"{k}={'yes' if v else 'no'}" for k, v in r["criteria"].items())
            lines.append(f"  - best candidate {r['best']}: {crit}")
    return lines


def _score_lines(result: DiscrepancyResult) -> list[str]:
    """The held-out score table (trends with dBIC < 0 left out)."""
    lines = [
        "",
        "## Scores (held out)",
        "",
        "| round | model | k | RSS | AICc | BIC | dBIC vs current | bootstrap wins | parameters |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in result.candidates:
        if c["kind"] == "trend" and c["delta_bic"] < 0:
            continue
        params = "; ".join(
            f"{p['name']}={p['value']:.3g} [{p['ci_lower']:.3g}, {p['ci_upper']:.3g}]"
            for p in c["parameters"]
        )
        lines.append(
            f"| {c['round']} | {c['name']} | {c['k']} | {c['rss_heldout']:.4g} | "
            f"{c['aicc']:.1f} | {c['bic']:.1f} | {c['delta_bic']:.1f} | "
            f"{c['bootstrap_wins']:.2f} | {params or '-'} |"
        )
    lines += [
        "",
        "Trend models with dBIC < 0 are left out of the table (they are in result.json).",
    ]
    return lines


def _plots(result: DiscrepancyResult, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    y = result.y
    rb = (y - result.prediction_before) / result.sigma
    ra = (y - result.prediction_after) / result.sigma
    cov = result.giveaway
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    x = (
        result.covariates[cov].to_numpy(float)
        if cov is not None
        else np.arange(y.size, dtype=float)
    )
    jitter = 0.01 * (np.ptp(x) or 1.0) * np.random.default_rng(0).standard_normal(x.size)
    for ax, r, title in ((axes[0], rb, "before"), (axes[1], ra, "after")):
        ax.axhline(0.0, color="k", lw=0.8)
        ax.plot(x + jitter, r, ".", ms=3, alpha=0.6)
        ax.set_title(f"held-out residual {title}")
        ax.set_xlabel(cov or "row")
    axes[0].set_ylabel("(measured - simulated) / sigma")
    fig.suptitle(result.verdict, fontsize=9)
    fig.tight_layout()
    _save_figure(fig, out / PLOT_FILES[0])

    fig, ax = plt.subplots(figsize=(5, 5))
    ax.plot(result.prediction_before, y, ".", ms=3, alpha=0.6, label="before")
    ax.plot(result.prediction_after, y, ".", ms=3, alpha=0.6, label="after")
    lo = float(min(y.min(), result.prediction_before.min(), result.prediction_after.min()))
    hi = float(max(y.max(), result.prediction_before.max(), result.prediction_after.max()))
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
    ax.set_xlabel("simulated (held out)")
    ax.set_ylabel("measured")
    ax.legend()
    ax.set_title(f"RMSE {result.gap_before:.3g} -> {result.gap_after:.3g}", fontsize=9)
    fig.tight_layout()
    _save_figure(fig, out / PLOT_FILES[1])

    first = [c for c in result.candidates if c["round"] == 1 and c["kind"] != "current"]
    first = sorted(first, key=lambda c: -c["delta_bic"])[:12]
    fig, ax = plt.subplots(figsize=(7, 0.35 * max(len(first), 3) + 1.2))
    names = [c["name"] for c in first][::-1]
    values = [c["delta_bic"] for c in first][::-1]
    colors = ["tab:blue" if c["kind"] == "candidate" else "tab:gray" for c in first][::-1]
    ax.barh(names, values, color=colors)
    ax.axvline(10.0, color="k", ls="--", lw=0.8)
    ax.set_xscale("symlog", linthresh=10.0)
    ax.set_xlabel("held-out BIC improvement over the base model (round 1)")
    fig.tight_layout()
    _save_figure(fig, out / PLOT_FILES[2])


def write_result(result: DiscrepancyResult, out_dir: str | os.PathLike[str]) -> Path:
    """Write result.json, report.md and the PNG plots into ``out_dir`` (created if needed).

    Every file is written to a temporary file in the folder and moved into place with
    :func:`os.replace`, so a reader never sees a half-written file.

    Parameters
    ----------
    result : DiscrepancyResult
    out_dir : path

    Returns
    -------
    pathlib.Path
        The folder.
    """
    if not isinstance(result, DiscrepancyResult):
        raise TypeError(f"result must be a DiscrepancyResult, got {type(result).__name__}")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"out_dir {str(out)!r} exists and is not a folder")
    out.mkdir(parents=True, exist_ok=True)
    text = json.dumps(json_safe(result.to_dict()), indent=2)
    _write_text(out / "result.json", text + "\n")
    _write_text(out / "report.md", _report_md(result))
    _plots(result, out)
    return out
