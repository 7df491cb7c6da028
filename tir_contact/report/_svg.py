"""Small time-series plots as SVG text: fast to write (no plotting library), sharp at any
zoom, a few kB each."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tir_contact.report._html import esc, fmt

__all__ = ["time_series_svg"]

#: Plot size in CSS pixels: width, height of one panel, left and bottom margins.
WIDTH, PANEL, LEFT, BOTTOM = 560, 96, 64, 30
#: Points drawn per line at most (longer series are thinned evenly).
MAX_POINTS = 600


def _path(x: np.ndarray, y: np.ndarray) -> str:
    """An SVG path through the finite points; a NaN breaks the line."""
    out, pen = [], "M"
    for xi, yi in zip(x.tolist(), y.tolist(), strict=True):
        if yi != yi:  # NaN
            pen = "M"
            continue
        out.append(f"{pen}{xi:.1f} {yi:.1f}")
        pen = "L"
    return " ".join(out)


def time_series_svg(t_ms: np.ndarray, panels: Sequence[tuple[str, np.ndarray]],
                    shade: tuple[float, float] | None = None) -> str:
    """Stacked panels sharing the time axis, as a standalone SVG document.

    Parameters
    ----------
    t_ms : (n,) ndarray
        Time of each sample, ms.
    panels : sequence of (label, (n,) ndarray)
        One panel per quantity (NaN where none).
    shade : (float, float), optional
        A span of time shaded in every panel (the whole block in view), ms.

    Returns
    -------
    str
        The SVG document (``width`` and ``height`` set: it shows with its natural size).

    Examples
    --------
    >>> svg = time_series_svg(np.arange(3.0), [("a", np.array([1.0, np.nan, 3.0]))])
    >>> svg.startswith("<svg") and "M" in svg
    True
    """
    t = np.asarray(t_ms, float)
    step = max(1, int(np.ceil(len(t) / MAX_POINTS)))
    t = t[::step]
    t0, t1 = (float(np.nanmin(t)), float(np.nanmax(t))) if len(t) else (0.0, 1.0)
    t1 = t1 if t1 > t0 else t0 + 1.0
    right = WIDTH - 10
    height = PANEL * len(panels) + BOTTOM
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" '
             f'viewBox="0 0 {WIDTH} {height}" font-family="sans-serif" font-size="11">',
             f'<rect width="{WIDTH}" height="{height}" fill="white"/>']

    def sx(v: np.ndarray | float) -> np.ndarray | float:
        return LEFT + (np.asarray(v) - t0) / (t1 - t0) * (right - LEFT)

    for k, (label, values) in enumerate(panels):
        y = np.asarray(values, float)[::step]
        top, bottom = k * PANEL + 8, (k + 1) * PANEL - 8
        finite = y[np.isfinite(y)]
        lo, hi = (float(finite.min()), float(finite.max())) if len(finite) else (0.0, 1.0)
        if hi <= lo:
            lo, hi = lo - 0.5 * (abs(lo) or 1.0), hi + 0.5 * (abs(hi) or 1.0)
        if shade is not None:
            a, b = sx(shade[0]), sx(shade[1])
            parts.append(f'<rect x="{a:.1f}" y="{top}" width="{max(b - a, 1):.1f}" '
                         f'height="{bottom - top}" fill="#e8e8e8"/>')
        parts.append(f'<rect x="{LEFT}" y="{top}" width="{right - LEFT}" '
                     f'height="{bottom - top}" fill="none" stroke="#888"/>')
        py = bottom - (y - lo) / (hi - lo) * (bottom - top)
        parts.append(f'<path d="{_path(sx(t), py)}" fill="none" stroke="#1f77b4" '
                     'stroke-width="1.2"/>')
        digits = next((d for d in range(3, 9) if fmt(lo, d) != fmt(hi, d)), 9)
        parts.append(f'<text x="{LEFT - 4}" y="{top + 9}" text-anchor="end">'
                     f'{fmt(hi, digits)}</text>')
        parts.append(f'<text x="{LEFT - 4}" y="{bottom}" text-anchor="end">'
                     f'{fmt(lo, digits)}</text>')
        parts.append(f'<text x="{LEFT + 4}" y="{top + 12}" fill="#333">{esc(label)}'
                     f'{"" if len(finite) else " (none)"}</text>')
    base = PANEL * len(panels)
    parts.append(f'<text x="{LEFT}" y="{base + 12}">{fmt(t0, 4)}</text>')
    parts.append(f'<text x="{right}" y="{base + 12}" text-anchor="end">{fmt(t1, 4)}</text>')
    parts.append(f'<text x="{(LEFT + right) / 2}" y="{base + 24}" text-anchor="middle">'
                 "time (ms); grey: whole block in view</text></svg>\n")
    return "".join(parts)
