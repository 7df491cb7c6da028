"""Thesis case 3: Table 4.6, friction that rises with velocity at -1 degC and rH > 90 %.

Table 4.6 of the thesis gives the measured G3 characteristics for 1..7 m/s: at -5 degC and
rH < 50 % mu falls with velocity (A v^-0.5 + B), at -1 degC and rH > 90 % it *rises*
(A v^0.5 + B). The dry/wet model without its humidity and viscous physics (the bound water
layer of the humid air and the viscous shear of the melt film) cannot rise with velocity:
more speed means more frictional heat, more melt water and less dry contact, so mu only
falls. The discrepancy workflow should say which effect closes that gap.

Part 1, synthetic data with a hidden truth. :func:`synthetic.measurements.make_steady_table`
makes the characteristic as a rig reports it (mean of 10 repeats, 5 % relative noise, the
scatter of the Table 4.6 measurements about the calibrated model) on the Table 4.6 grid:
G3, 2.5 and 5 bar, 1..7 m/s, at -5 degC / 40 % (cold-dry) and -1 degC / 95 % (warm-humid;
the table gives the humidities only as bounds, the calibration takes 40 % and 95 %). Hidden
in it: ``humidity_water_layer`` and ``viscous_shear`` at strength 1, the calibrated
model's physics (:class:`friction_model.contact.effects.Effects`); the other effects are off
(salinity 0 %; no ice preheating). Nothing in the table says so. The base model of the
workflow (:class:`friction_model.discrepancy.SteadyProblem`) is the calibrated dry/wet
model with every effect off, plus one fitted level factor. The humidity layer changes mu
by a few per cent only (printed below), under the noise of this small grid, where
temperature and humidity also change together, so the workflow may well name only the
viscous shear: what the data can show, not what is hidden, decides.

Part 2, the thesis's own numbers: the four Table 4.6 curves sampled at 1..7 m/s, with the
same 5 % relative standard uncertainty (the table gives none), against the same base model.

Run: ``python examples/thesis_table_4_6.py [--out FOLDER]`` (default
``examples/out/thesis_table_4_6``; about 20 s). Writes ``synthetic/`` and ``table_4_6/``
(result.json, report.md and the workflow's PNGs each) and ``table_4_6_curves.png``
(measured, base and corrected characteristics of both parts).
"""

from __future__ import annotations

import textwrap
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from _common import example_arguments, save_figure

from friction_model.discrepancy import SteadyProblem, run_discrepancy, write_result
from friction_model.identification.table_4_6 import TABLE_4_6, table_4_6_targets
from synthetic.measurements import DEFAULT_NOISE, make_steady_table

HIDDEN = {"humidity_water_layer": 1.0, "viscous_shear": 1.0}
COLD_DRY = (-5.0, 40.0)
WARM_HUMID = (-1.0, 95.0)
GRID = {
    "velocities_mps": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0],
    "pressures_bar": [2.5, 5.0],
    "temperatures_C": [COLD_DRY[0], WARM_HUMID[0]],
    "humidities_pct": [COLD_DRY[1], WARM_HUMID[1]],
    "salinities_pct": [0.0],
    "n_sipes": [3],
}


def _table_4_6_climates(table: pd.DataFrame) -> pd.DataFrame:
    """Keep the two climates of Table 4.6 (the grid crosses temperature and humidity)."""
    keep = np.zeros(len(table), bool)
    for temp, rh in (COLD_DRY, WARM_HUMID):
        keep |= (table["temperature_C"] == temp).to_numpy() & (
            table["humidity_pct"] == rh
        ).to_numpy()
    return table[keep].reset_index(drop=True)


def synthetic_table(seed: int) -> tuple[pd.DataFrame, dict[str, float]]:
    """The Table 4.6 grid with the hidden effects, and each effect's RMS share of mu."""
    table = _table_4_6_climates(make_steady_table(GRID, effects=HIDDEN, rng=seed))
    truth = _table_4_6_climates(make_steady_table(GRID, effects=HIDDEN, noise=0.0))
    truth = truth["mu"].to_numpy()
    size = {}
    for name in HIDDEN:
        others = {k: v for k, v in HIDDEN.items() if k != name}
        without = _table_4_6_climates(make_steady_table(GRID, effects=others, noise=0.0))
        size[name] = float(np.sqrt(np.mean((truth / without["mu"].to_numpy() - 1.0) ** 2)))
    return table, size


def thesis_table() -> pd.DataFrame:
    """Table 4.6 curves at 1..7 m/s as a steady table, 5 % relative uncertainty."""
    t = table_4_6_targets()
    return pd.DataFrame(
        {
            "velocity_mps": t["velocity_mps"],
            "pressure_bar": t["pressure_bar"],
            "temperature_C": t["temperature_C"],
            "humidity_pct": t["humidity_pct"],
            "salinity_pct": 0.0,
            "n_sipes": 3,
            "mu": t["mu_target"],
            "mu_std": DEFAULT_NOISE * t["mu_target"],
        }
    )


def _slope(result, which: np.ndarray) -> float:
    """Mean d mu / d v (1/(m/s)) over the warm-humid curves of ``which``."""
    cov = result.covariates
    out = []
    for p in np.unique(cov["pressure_bar"]):
        m = (cov["temperature_C"] == WARM_HUMID[0]).to_numpy() & (
            cov["pressure_bar"] == p
        ).to_numpy()
        out.append(np.polyfit(cov["velocity_mps"].to_numpy()[m], which[m], 1)[0])
    return float(np.mean(out))


def report(label: str, result) -> None:
    print(f"\n{label}")
    print(f"  warm-humid slope d mu/dv (per m/s): measured {_slope(result, result.y):+.4f}, "
          f"base {_slope(result, result.prediction_before):+.4f}, with the named effect(s) "
          f"{_slope(result, result.prediction_after):+.4f}")
    for name, info in result.fitted.items():
        for p in info["parameters"]:
            print(f"  fitted {name} strength {p['value']:.2f} (95 % interval "
                  f"{p['ci_lower']:.2f} .. {p['ci_upper']:.2f})")
    print(f"  held-out gap (RMSE of mu): before {result.gap_before:.4f}, after "
          f"{result.gap_after:.4f} ({1 - result.gap_after / result.gap_before:.0%} smaller); "
          f"reduced chi2 {result.gap['reduced_chi2_before']:.1f} -> "
          f"{result.gap['reduced_chi2_after']:.1f}")
    print(f"  verdict: {result.verdict}")


def main(argv: list[str] | None = None) -> int:
    args = example_arguments(argv, __doc__, "thesis_table_4_6", seed=0,
                             seed_help="seed of the synthetic noise")
    out: Path = args.out
    t0 = time.perf_counter()

    table, size = synthetic_table(args.seed)
    sizes = ", ".join(f"{k} {v:.1%}" for k, v in size.items())
    print(f"Part 1: synthetic Table 4.6 grid ({len(table)} rows, {DEFAULT_NOISE:.0%} noise); "
          f"hidden effects change mu by (RMS): {sizes}")
    synth = run_discrepancy(SteadyProblem(table), n_bootstrap=200, n_permutations=499, seed=0)
    report("Part 1 result (hidden: " + " + ".join(HIDDEN) + ")", synth)
    write_result(synth, out / "synthetic")

    thesis = run_discrepancy(SteadyProblem(thesis_table()), n_bootstrap=200,
                             n_permutations=499, seed=0)
    report(f"Part 2: the Table 4.6 curves themselves ({DEFAULT_NOISE:.0%} assumed "
           "uncertainty)", thesis)
    write_result(thesis, out / "table_4_6")

    _plot([("synthetic, hidden: humidity layer + viscous shear", synth),
           ("Table 4.6 (thesis)", thesis)], out / "table_4_6_curves.png")
    print(f"\nwrote {out} ({time.perf_counter() - t0:.0f} s)")
    return 0


def _plot(parts, path: Path) -> None:
    fig, axes = plt.subplots(1, len(parts), figsize=(11, 4.2), sharey=True)
    names = {(T, rh, p): name for name, T, rh, p, *_ in TABLE_4_6}
    for ax, (title, res) in zip(axes, parts, strict=True):
        cov = res.covariates
        keys = cov[["temperature_C", "humidity_pct", "pressure_bar"]].itertuples(index=False)
        label = np.array([names.get(tuple(k), str(tuple(k))) for k in keys])
        for i, name in enumerate(n for n, *_ in TABLE_4_6):  # one colour per curve
            m = label == name
            if not m.any():
                continue
            v = cov["velocity_mps"].to_numpy()[m]
            o = np.argsort(v)
            c = f"C{i}"
            ax.errorbar(v[o], res.y[m][o], yerr=res.sigma[m][o], fmt="o", ms=4, color=c,
                        label=name)
            ax.plot(v[o], res.prediction_before[m][o], ":", color=c)
            ax.plot(v[o], res.prediction_after[m][o], "-", color=c)
        ax.set_title(title + "\n" + textwrap.fill(res.verdict, 70), fontsize=9)
        ax.legend(fontsize=8)
        ax.set_xlabel("velocity / (m/s)")
    axes[0].set_ylabel("mu  (dots: measured, dotted: base, line: + named effect)")
    save_figure(fig, path)


if __name__ == "__main__":
    raise SystemExit(main())
