"""Plots of one video's analysis: contact over time, per element."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from tir_common.atomic import atomic_write

__all__ = ["plot_video_results"]


#: Resolution of the PNG plots (dots per inch).
DPI = 90


def _figure(width_in: float, height_in: float) -> Any:
    """A figure outside pyplot's global state (nothing to close, nothing shared)."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width_in, height_in), layout="constrained")


def _save(fig: Any, path: Path) -> Path:
    atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=DPI))
    return path


def _legend(ax: Any, **kw: Any) -> None:
    """A legend when something carries a label (an empty one warns)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kw)


def _shade_full(ax: Any, frames: pd.DataFrame) -> None:
    """Shade the time span where the whole block is in view."""
    full = frames.loc[frames["block_fully_in_view"].astype(bool), "time_s"]
    if len(full):
        ax.axvspan(full.min() * 1e3, full.max() * 1e3, color="0.9", zorder=0,
                   label="whole block in view")


def plot_video_results(
    frames: pd.DataFrame,
    elements: pd.DataFrame,
    folder: str | Path,
    *,
    view: str = "tir",
    title: str = "",
) -> list[Path]:
    """Write the PNG plots of one video's results.

    TIR view: ``contact.png`` (block contact area with its error bar as a band, and contact
    ratio over time) and
    ``elements.png`` (contact area, contact length and front-peak contrast per element over
    time). Side view: ``deflection.png`` (deflection angle and tip deflection per element).

    Parameters
    ----------
    frames, elements : pandas.DataFrame
        ``frames.csv`` and ``elements.csv`` of :func:`tir_contact.analyze.analyze_video`.
    folder : str or Path
        Where the PNG files go.
    view : {"tir", "side"}
        Camera view of the footage.
    title : str
        Figure title (the video name).

    Returns
    -------
    list of Path
        The files written.
    """
    folder = Path(folder)
    written: list[Path] = []
    t_ms = frames["time_s"].to_numpy() * 1e3
    if view == "tir":
        fig = _figure(8, 5.5)
        a1, a2 = fig.subplots(2, 1, sharex=True)
        for ax in (a1, a2):
            _shade_full(ax, frames)
        if {"contact_area_low_mm2", "contact_area_high_mm2"} <= set(frames):
            a1.fill_between(t_ms, frames["contact_area_low_mm2"],
                            frames["contact_area_high_mm2"], color="C0", alpha=0.25, lw=0,
                            label="error bar (low-high)")
        a1.plot(t_ms, frames["contact_area_mm2"], lw=1, label="contact area")
        a1.set_ylabel("real contact area (mm²)")
        a2.plot(t_ms, frames["contact_ratio"], lw=1, color="C1")
        a2.set_ylabel("contact ratio (–)")
        a2.set_xlabel("time (ms)")
        _legend(a1, loc="upper right", fontsize=8)
        a1.set_title(title)
        written.append(_save(fig, folder / "contact.png"))
        quantities = [("contact_area_mm2", "contact area (mm²)"),
                      ("contact_length_mm", "contact length (mm)"),
                      ("front_peak_contrast", "front-peak contrast (–)")]
        name = "elements.png"
    else:
        quantities = [("deflection_angle_deg", "deflection angle (°)"),
                      ("tip_deflection_mm", "tip deflection (mm)")]
        name = "deflection.png"
    if len(elements):
        fig = _figure(8, 2.4 * len(quantities))
        axes = fig.subplots(len(quantities), 1, sharex=True, squeeze=False)
        for ax, (col, label) in zip(axes[:, 0], quantities, strict=True):
            _shade_full(ax, frames)
            if col in elements:
                for element, grp in elements.groupby("element"):
                    ax.plot(grp["time_s"] * 1e3, grp[col], lw=1, label=f"element {element}")
            ax.set_ylabel(label)
        axes[-1, 0].set_xlabel("time (ms)")
        n_el = elements["element"].nunique()
        if n_el <= 8:
            _legend(axes[0, 0], loc="upper right", fontsize=7, ncol=min(n_el + 1, 4))
        axes[0, 0].set_title(title)
        written.append(_save(fig, folder / name))
    elif view != "tir":
        fig = _figure(8, 3)
        ax = fig.subplots()
        ax.plot(t_ms, np.full_like(t_ms, np.nan))
        ax.set_title(f"{title}: no element found in any frame")
        written.append(_save(fig, folder / name))
    return written
