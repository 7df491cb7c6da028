"""Figures of the friction model: Fig. 4.26 (dry run-in length) and Table 4.6 (calibration)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from friction_model.contact.flash_temperature import dry_run_in_length

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["fig_4_26_table", "plot_fig_4_26", "plot_table_4_6"]


def fig_4_26_table(
    *,
    velocities_mps: np.ndarray | None = None,
    delta_T_K: tuple[float, ...] = (1.0, 4.0, 8.0),
    pressures_bar: tuple[float, ...] = (1.0, 2.5, 5.0),
    mu_dry: tuple[float, ...] = (0.5, 1.0, 1.5, 2.0),
) -> pd.DataFrame:
    """Dry run-in length (Eq. 4.7) over the parameter grid of Fig. 4.26.

    Parameters
    ----------
    velocities_mps : ndarray, optional
        Sliding velocities, m/s (0.5..10 by default).
    delta_T_K, pressures_bar, mu_dry : tuple of float
        The curves: temperature differences (K), nominal pressures (bar), dry friction
        coefficients.

    Returns
    -------
    pandas.DataFrame
        ``velocity_mps, delta_T_K, pressure_bar, mu_dry, dry_length_mm`` for every
        combination.
    """
    v = np.linspace(0.5, 10.0, 96) if velocities_mps is None else np.asarray(velocities_mps)
    grid = pd.MultiIndex.from_product(
        [v, delta_T_K, pressures_bar, mu_dry],
        names=["velocity_mps", "delta_T_K", "pressure_bar", "mu_dry"],
    ).to_frame(index=False)
    grid["dry_length_mm"] = 1e3 * dry_run_in_length(
        grid["delta_T_K"].to_numpy(),
        grid["pressure_bar"].to_numpy() * 1e5,
        grid["mu_dry"].to_numpy(),
        grid["velocity_mps"].to_numpy(),
    )
    return grid


def plot_fig_4_26(table: pd.DataFrame | None = None) -> Figure:
    """Fig. 4.26: a) length over v for dT and p at mu_dry = 1.5, b) over dT for mu_dry and p.

    Parameters
    ----------
    table : pandas.DataFrame, optional
        Output of :func:`fig_4_26_table`; computed with defaults when omitted.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4.2))
    t = fig_4_26_table() if table is None else table
    a = t[t["mu_dry"] == 1.5]
    for (dT, p), g in a.groupby(["delta_T_K", "pressure_bar"]):
        ax_a.plot(g["velocity_mps"], g["dry_length_mm"], label=f"ΔT = {dT:g} K, p = {p:g} bar")
    ax_a.set(xlabel="sliding velocity v / (m/s)", ylabel="dry run-in length ε / mm",
             yscale="log", title="a) Eq. 4.7, μ_dry = 1.5")
    ax_a.legend(fontsize=7)
    dT = np.linspace(0.5, 10.0, 80)
    for mu in sorted(t["mu_dry"].unique()):
        for p in (2.5, 5.0):
            eps = 1e3 * dry_run_in_length(dT, p * 1e5, mu, 1.0)
            ax_b.plot(dT, eps, ls="-" if p == 2.5 else "--", label=f"μ_dry = {mu:g}, {p:g} bar")
    ax_b.set(xlabel="temperature difference ΔT / K", ylabel="dry run-in length ε / mm",
             yscale="log", title="b) Eq. 4.7, v = 1 m/s")
    ax_b.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return fig


def plot_table_4_6(table: pd.DataFrame, rmse: dict[str, float]) -> Figure:
    """Measured characteristics of Table 4.6 against the calibrated model.

    Parameters
    ----------
    table : pandas.DataFrame
        ``curve, velocity_mps, mu_target, mu_model`` as returned by
        :func:`friction_model.identification.table_4_6.evaluate_on_table_4_6`.
    rmse : dict
        RMSE per curve (shown in the legend).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, (name, g) in enumerate(table.groupby("curve", sort=False)):
        color = f"C{i}"
        ax.plot(g["velocity_mps"], g["mu_target"], "o", color=color, mfc="none")
        ax.plot(g["velocity_mps"], g["mu_model"], "-", color=color,
                label=f"{name} (RMSE {rmse[name]:.4f})")
    ax.set(xlabel="sliding velocity v / (m/s)", ylabel="friction coefficient μ",
           title="G3: Table 4.6 fits (circles) vs. dry/wet model (lines)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig
