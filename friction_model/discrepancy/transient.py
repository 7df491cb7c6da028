"""Discrepancy problem for transient data: a tread-block element through a velocity step.

The thesis matched its velocity-step simulation to the rig (Fig. 5.7) only after adding the
time dependence of friction, Eq. 5.12. :class:`TransientProblem` puts that comparison into
the form the discrepancy workflow fits (the ``Problem`` protocol of
``friction_model.discrepancy._problem``): measured deflection angles of one or more runs
against the linearised element of Eq. 5.8
(:func:`friction_model.dynamics.element_step.step_response`)
without relaxation and with the constant modulus E0, and two candidate extensions:

``friction_relaxation``
    Eq. 5.12 with time constant ``tau_s`` (null 0, bounds [0, 0.2] s).
``frequency_dependent_modulus``
    The rubber modulus E(f) = E0 (1 + s alpha log10(f / f0)) with strength ``s``
    (null 0, bounds [0, 5]).

Base (nuisance) parameters: per run, the steady deflection before and after the step. They
absorb whatever sets the steady friction at the two velocities (the dry/wet effects,
humidity, salinity, the run's ice): a transient record holds two steady levels, not enough to
tell those effects apart, so this problem does not try; a steady characteristic table does.
The candidates change only the path between the levels, never the levels themselves.

Data: transient tables (docs/formats.md "Transient table": ``time_s``, ``velocity_mps``,
``angle_deg``), each one run, or the per-element deflection of the pipeline (``elements.csv``
of ``tir-contact analyze``: ``frame``, ``time_s``, ``element``, ``deflection_angle_deg``)
with the commanded velocity step given by the user.

Notes
-----
Units: time s, angle degrees, velocity m/s, pressure bar, frequency Hz. ``time_since_step_s``
is ``t - t_step`` (negative before the step).
"""

from __future__ import annotations

import itertools
import logging
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from friction_model._table_io import TableSource, read_table
from friction_model.discrepancy._problem import Candidate, get_candidate
from friction_model.dynamics.element_step import step_element, step_response

__all__ = [
    "DEFAULT_BLOCK_EDGES_S",
    "MODULUS",
    "RELAXATION",
    "TAU_MAX_S",
    "TransientProblem",
    "TransientRun",
    "candidate_specs",
    "read_elements_table",
    "read_transient_table",
    "relaxation_and_modulus",
    "run_from_table",
    "runs_from_elements",
]

logger = logging.getLogger(__name__)

#: Candidate names this problem fits.
RELAXATION = "friction_relaxation"
MODULUS = "frequency_dependent_modulus"
#: Largest relaxation time fitted, s (narrows the library bounds of ``friction_relaxation``
#: through :meth:`TransientProblem.parameter_bounds`): ten times the 20 ms reference
#: (``TAU_REF_S``) and as long as the 0.2 s recorded after the step in Fig. 5.7; a longer lag
#: cannot be told from a drift of the level within such a record.
TAU_MAX_S = 0.2
#: Edges of the after-step blocks of a single run, in time since the step, s. The element
#: rings for about 2 ms (585 Hz, damped within a few periods), the relaxation of Fig. 5.7
#: lasts tens of ms, the modulus creep continues over the decades after it: blocks spaced
#: about geometrically in time since the step give each of these a block of its own.
DEFAULT_BLOCK_EDGES_S: tuple[float, ...] = (0.002, 0.01, 0.03, 0.1)

_COLUMNS = ("time_s", "velocity_mps", "angle_deg")
_ELEMENT_COLUMNS = ("time_s", "element", "deflection_angle_deg")
# Fewest samples before the step from which their scatter estimates the noise; with fewer,
# the scatter of successive differences over the whole run does.
_MIN_NOISE_SAMPLES = 20
# Normal-distribution constant: MAD / 0.6745 estimates a standard deviation.
_MAD_TO_STD = 0.6744897501960817
# Smallest sigma accepted, relative to the largest |angle| (noise-free synthetic data).
_SIGMA_FLOOR_REL = 1e-9
# Cached unit responses (per parameter pair, all runs): the workflow evaluates the same scan
# points in every fold and resample. The cache holds at most this many floats (32 MB).
_CACHE_FLOATS = 4_000_000
# Relative determinant below which the rows cannot tell the two levels of a run apart (the
# rows lie all before or all long after the step).
_RANK_RTOL = 1e-9


def _finite_float(name: str, value: Any) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(out):
        raise ValueError(f"{name} must be finite, got {name}={value!r}")
    return out


def relaxation_and_modulus(
    effects: Mapping[str, Sequence[float]], *, data: str
) -> tuple[float, float]:
    """(tau_s, modulus strength) from an effects mapping of the two dynamic effects.

    An absent effect is 0. Each present one takes one finite parameter >= 0.

    Parameters
    ----------
    effects : mapping of str to sequence of float
        Parameters by effect name; only ``RELAXATION`` and ``MODULUS`` may appear.
    data : str
        What the effects are applied to, for the message of an effect that does not apply
        (e.g. ``"transient data"``).

    Returns
    -------
    tuple of float
        The relaxation time tau_s (s) and the modulus strength.

    Raises
    ------
    TypeError
        ``effects`` is not a mapping, or a parameter is not a number.
    ValueError
        An effect other than the two, not one parameter, or one that is not finite or < 0.
    """
    if not isinstance(effects, Mapping):
        raise TypeError(f"effects must be a mapping, got {type(effects).__name__}")
    valid = (RELAXATION, MODULUS)
    unknown = sorted(set(effects) - set(valid))
    if unknown:
        raise ValueError(
            f"effects {', '.join(unknown)} do not apply to {data}; valid: {', '.join(valid)}"
        )
    values = []
    for name in valid:
        params = tuple(effects.get(name, (0.0,)))
        if len(params) != 1:
            raise ValueError(f"effect {name} takes one parameter, got {params!r}")
        value = _finite_float(name, params[0])
        if value < 0:
            raise ValueError(f"effect {name} parameter must be >= 0, got {value!r}")
        values.append(value)
    return values[0], values[1]


@dataclass(frozen=True, eq=False)
class TransientRun:
    """One measured deflection time series through one velocity step.

    Parameters
    ----------
    label : str
        Name of the run (a file name, ``element 0``, ...).
    time_s : (n,) array_like
        Strictly increasing sample times, s.
    angle_deg : (n,) array_like
        Deflection angle of the element, degrees (> 0 trailing).
    v1_mps, v2_mps : float
        Commanded sliding velocity before and after the step, m/s.
    t_step_s : float
        Time of the step, s (on the axis of ``time_s``).
    n_sipes : int
        Sipes of the 20 mm x 80 mm block (3: G3).
    pressure_bar : float
        Nominal pressure, bar.
    sigma_deg : float, optional
        Noise std of the angle, degrees; estimated when omitted: the sample std of the angle
        before the step (the element slides steadily there, so the model is a constant), or
        with fewer than 20 samples there the MAD of successive differences / sqrt(2).
    element : int, optional
        Element index for pipeline data (0 leads).

    Raises
    ------
    ValueError
        On bad shapes, non-finite values, unsorted times or a step outside the record.
    """

    label: str
    time_s: np.ndarray
    angle_deg: np.ndarray
    v1_mps: float
    v2_mps: float
    t_step_s: float
    n_sipes: int = 3
    pressure_bar: float = 1.2
    sigma_deg: float | None = None
    element: int | None = None
    _sigma: float = field(init=False, repr=False, compare=False, default=0.0)

    def __post_init__(self) -> None:
        t = np.asarray(self.time_s, dtype=float)
        a = np.asarray(self.angle_deg, dtype=float)
        where = f"run {self.label!r}"
        if t.ndim != 1 or a.shape != t.shape or t.size < 3:
            raise ValueError(
                f"{where}: time_s and angle_deg must be 1-D of the same length >= 3, got "
                f"shapes {t.shape} and {a.shape}"
            )
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a))):
            raise ValueError(f"{where}: time_s and angle_deg must be finite (drop NaN rows)")
        if np.any(np.diff(t) <= 0):
            raise ValueError(f"{where}: time_s must be strictly increasing")
        t_step = _finite_float("t_step_s", self.t_step_s)
        if not t[0] < t_step <= t[-1]:
            raise ValueError(
                f"{where}: t_step_s={t_step!r} must lie after the first and at or before the "
                f"last sample ({t[0]!r} .. {t[-1]!r} s)"
            )
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "angle_deg", a)
        object.__setattr__(self, "t_step_s", t_step)
        object.__setattr__(self, "v1_mps", _finite_float("v1_mps", self.v1_mps))
        object.__setattr__(self, "v2_mps", _finite_float("v2_mps", self.v2_mps))
        # validates n_sipes and pressure_bar (a buckling element is refused here)
        step_element(n_sipes=self.n_sipes, pressure_bar=self.pressure_bar)
        if self.sigma_deg is not None:
            sigma = _finite_float("sigma_deg", self.sigma_deg)
            if sigma <= 0:
                raise ValueError(f"{where}: sigma_deg must be > 0, got {sigma!r}")
        else:
            sigma = _estimate_sigma(t, a, t_step)
        object.__setattr__(self, "_sigma", sigma)

    @property
    def sigma(self) -> float:
        """Noise std of the angle used for the run, degrees (given or estimated)."""
        return self._sigma


def _estimate_sigma(t: np.ndarray, a: np.ndarray, t_step: float) -> float:
    before = a[t < t_step]
    if before.size >= _MIN_NOISE_SAMPLES:
        sigma = float(np.std(before, ddof=1))
    else:
        diff = np.diff(a)
        sigma = float(np.median(np.abs(diff - np.median(diff))) / _MAD_TO_STD / math.sqrt(2.0))
    floor = _SIGMA_FLOOR_REL * max(1.0, float(np.max(np.abs(a))))
    return max(sigma, floor)


def read_transient_table(path: str | os.PathLike[str]) -> pd.DataFrame:
    """Read and check a transient table CSV (docs/formats.md "Transient table").

    Any delimiter and decimal mark of :mod:`friction_model._table_io` are read (``,`` with
    ``.``, ``;`` or tab with ``.`` or ``,``).

    Parameters
    ----------
    path : str or path-like
        CSV with columns ``time_s``, ``velocity_mps``, ``angle_deg``.

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    ValueError
        Naming the file, the column, the data row and file line and what was expected: a
        missing column, an entry that is not a finite number, time that does not increase
        strictly, fewer than 3 rows.
    OSError
        When the file cannot be opened.
    """
    table, source = read_table(
        path,
        required=_COLUMNS,
        floats=_COLUMNS,
        finite=_COLUMNS,
        expected=f"{', '.join(_COLUMNS)} (docs/formats.md, Transient table)",
    )
    if len(table) < 3:
        raise source.error(
            f"expected at least 3 data rows after the column header (file line "
            f"{source.header_line}), got {len(table)}"
        )
    _check_increasing(table["time_s"].to_numpy(float), source)
    return table


def read_elements_table(path: str | os.PathLike[str]) -> pd.DataFrame:
    """Read and check the pipeline's ``elements.csv`` for :func:`runs_from_elements`.

    Parameters
    ----------
    path : str or path-like
        ``elements.csv`` of ``tir-contact analyze`` (columns ``time_s``, ``element``,
        ``deflection_angle_deg``; others are kept). Any delimiter and decimal mark of
        :mod:`friction_model._table_io` are read.

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    ValueError
        Naming the file, the column, the data row and file line and what was expected: a
        missing column, an entry that is not a number (``time_s`` and ``element`` must be
        finite; an empty ``deflection_angle_deg`` is an element out of view).
    OSError
        When the file cannot be opened.
    """
    table, _ = read_table(
        path,
        required=_ELEMENT_COLUMNS,
        floats=_ELEMENT_COLUMNS,
        finite=("time_s", "element"),
        expected=f"{', '.join(_ELEMENT_COLUMNS)} (docs/formats.md, elements.csv)",
    )
    return table


def _check_increasing(t: np.ndarray, source: TableSource) -> None:
    """Raise at the first sample whose time does not exceed the one before."""
    steps = np.diff(t)
    if not np.all(steps > 0):
        i = int(np.flatnonzero(~(steps > 0))[0]) + 1
        raise source.error(
            f"column 'time_s', {source.where(i)}: time must increase strictly, got "
            f"{float(t[i])!r} s after {float(t[i - 1])!r} s",
            column="time_s",
            index=i,
        )


def _check_columns(table: pd.DataFrame, columns: Sequence[str], where: str) -> None:
    if not isinstance(table, pd.DataFrame):
        raise TypeError(f"{where} must be a pandas DataFrame, got {type(table).__name__}")
    missing = [c for c in columns if c not in table.columns]
    if missing:
        raise ValueError(
            f"{where} lacks column(s) {', '.join(missing)}; expected {', '.join(columns)}"
        )
    for c in columns:
        if not pd.api.types.is_numeric_dtype(table[c]):
            raise ValueError(f"{where}: column {c} must be numeric, got dtype {table[c].dtype}")


def run_from_table(
    table: pd.DataFrame,
    *,
    label: str = "run",
    t_step_s: float | None = None,
    n_sipes: int = 3,
    pressure_bar: float = 1.2,
    sigma_deg: float | None = None,
) -> TransientRun:
    """A :class:`TransientRun` from a transient table.

    v1 and v2 are the first and last commanded velocity; the step is the first sample whose
    velocity has moved more than half-way from v1 to v2 (the table's velocity is the exact
    commanded step, so this is the step sample) unless ``t_step_s`` is given.

    Parameters
    ----------
    table : pandas.DataFrame
        Columns ``time_s``, ``velocity_mps``, ``angle_deg``.
    label : str
        Run name.
    t_step_s : float, optional
        Step time, s (overrides the detection).
    n_sipes, pressure_bar, sigma_deg
        As in :class:`TransientRun` (defaults: the table defaults, G3 at 1.2 bar).

    Returns
    -------
    TransientRun

    Raises
    ------
    ValueError
        If a column is missing or the velocity does not step.
    """
    where = f"transient table {label!r}"
    _check_columns(table, _COLUMNS, where)
    v = table["velocity_mps"].to_numpy(float)
    t = table["time_s"].to_numpy(float)
    if v.size < 3 or not np.all(np.isfinite(v)):
        raise ValueError(f"{where}: velocity_mps must hold >= 3 finite values")
    v1, v2 = float(v[0]), float(v[-1])
    if t_step_s is None:
        if v1 == v2:
            raise ValueError(
                f"{where}: velocity_mps does not step (first and last value {v1!r}); give "
                "t_step_s or a table with a velocity step"
            )
        moved = np.flatnonzero(np.abs(v - v1) > 0.5 * abs(v2 - v1))
        t_step_s = float(t[moved[0]])
    return TransientRun(
        label=label,
        time_s=t,
        angle_deg=table["angle_deg"].to_numpy(float),
        v1_mps=v1,
        v2_mps=v2,
        t_step_s=t_step_s,
        n_sipes=n_sipes,
        pressure_bar=pressure_bar,
        sigma_deg=sigma_deg,
    )


def runs_from_elements(
    elements: pd.DataFrame,
    *,
    v1_mps: float,
    v2_mps: float,
    t_step_s: float,
    element: int | Sequence[int] = 0,
    n_sipes: int = 3,
    pressure_bar: float = 1.2,
    sigma_deg: float | None = None,
    label: str = "element",
) -> list[TransientRun]:
    """Runs from the per-element deflection of the pipeline (``elements.csv``).

    Parameters
    ----------
    elements : pandas.DataFrame
        Columns ``time_s``, ``element``, ``deflection_angle_deg`` (others ignored); rows
        with a NaN angle (element out of view) are dropped.
    v1_mps, v2_mps, t_step_s : float
        The commanded velocity step: before, after (m/s) and its time on the footage's time
        axis (s).
    element : int or sequence of int
        Elements to use (0 leads; the model describes the leading element). Each becomes a
        run labelled ``"<label> <k>"``.
    n_sipes, pressure_bar, sigma_deg
        As in :class:`TransientRun`.
    label : str
        Prefix of the run labels.

    Returns
    -------
    list of TransientRun

    Raises
    ------
    ValueError
        If a column is missing or an element has no rows.
    """
    _check_columns(elements, _ELEMENT_COLUMNS, "elements table")
    wanted = [element] if np.ndim(element) == 0 else list(element)
    runs = []
    for k in wanted:
        rows = elements[elements["element"] == k].dropna(subset=["deflection_angle_deg"])
        if rows.empty:
            raise ValueError(f"elements table has no rows with a deflection for element {k}")
        rows = rows.sort_values("time_s")
        runs.append(
            TransientRun(
                label=f"{label} {k}",
                time_s=rows["time_s"].to_numpy(float),
                angle_deg=rows["deflection_angle_deg"].to_numpy(float),
                v1_mps=v1_mps,
                v2_mps=v2_mps,
                t_step_s=t_step_s,
                n_sipes=n_sipes,
                pressure_bar=pressure_bar,
                sigma_deg=sigma_deg,
                element=int(k),
            )
        )
    return runs


def _levels(g: np.ndarray, y: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Weighted least squares of y = A1 g + A2 (1 - g) (normal equations of two unknowns);
    all rows at weight 1 when the weighted rows cannot fix both levels."""
    h = 1.0 - g
    terms = np.stack([g * g, g * h, h * h, g * y, h * y])
    for weights in (w, np.ones_like(w)):
        # einsum, not BLAS: threaded BLAS products of long vectors stall on a busy machine
        s11, s12, s22, b1, b2 = np.einsum("ij,j->i", terms, weights)
        det = s11 * s22 - s12 * s12
        if det > _RANK_RTOL * s11 * s22 and s11 > 0 and s22 > 0:
            return np.array([(s22 * b1 - s12 * b2) / det, (s11 * b2 - s12 * b1) / det])
    raise ValueError("the run's samples cannot fix its levels before and after the step")


def _block_labels(run: TransientRun, edges_s: Sequence[float]) -> np.ndarray:
    """Contiguous time blocks of one run: two halves before the step, then after-step
    windows between ``edges_s`` (time since the step), empty blocks dropped."""
    since = run.time_s - run.t_step_s
    labels = np.empty(since.size, dtype=object)
    before = since < 0
    t_before = run.time_s[before]
    half = 0.5 * (t_before[0] + t_before[-1]) if t_before.size else 0.0
    labels[before] = np.where(run.time_s[before] < half, "before-1", "before-2")
    bounds = [0.0, *sorted(float(e) for e in edges_s if e > 0), math.inf]
    for lo, hi in itertools.pairwise(bounds):
        inside = (since >= lo) & (since < hi)
        hi_txt = "end" if math.isinf(hi) else f"{hi * 1e3:g}ms"
        labels[inside] = f"after-{lo * 1e3:g}ms-{hi_txt}"
    return np.array([f"{run.label}:{x}" for x in labels], dtype=object)


class TransientProblem:
    """Measured element deflection through velocity steps against the linearised element.

    Implements the ``Problem`` protocol of ``friction_model.discrepancy._problem``.

    Parameters
    ----------
    runs : sequence of TransientRun
        One or more runs (labels unique).
    grouping : {"auto", "runs", "blocks"}
        Hold-out / bootstrap groups: ``runs`` holds out whole runs; ``blocks`` contiguous
        time blocks of each run (two halves before the step, so that either leaves the other
        to fix the level, then windows in time since the step at ``block_edges_s``); ``auto``:
        runs when there are two or more, else blocks.
        Never random points: the residuals of a sampled response are correlated in time (a
        missing effect leaves a smooth misfit; camera noise correlates frame to frame), so
        a random held-out point sits between training neighbours and is predicted by
        interpolation, whatever the model. A contiguous window longer than that correlation
        must be predicted by the dynamics.
    block_edges_s : sequence of float
        Edges of the after-step blocks in time since the step, s.

    Attributes
    ----------
    kind : str
        ``"transient"``.
    y, sigma : (n,) ndarray
        Measured angle and its noise std, degrees, all runs concatenated.
    groups : (n,) ndarray of str
        Hold-out group of each observation.
    covariates : pandas.DataFrame
        ``run``, ``element`` (-1 unless pipeline data), ``time_s``, ``time_since_step_s``,
        ``velocity_mps`` (commanded: v1 before, v2 from the step), ``n_sipes``,
        ``pressure_bar``. ``time_s`` with ``groups`` also gives the workflow the residual
        spectrum of each run (a missing relaxation shows below 1 / (2 pi tau), a wrong
        modulus at the element's ringing frequency).
    effect_names : tuple of str
        ``("friction_relaxation", "frequency_dependent_modulus")``.
    n_base : int
        Two per run: the steady angle before and after the step.

    Notes
    -----
    ``effects`` maps a candidate name to its parameter tuple: ``(tau_s,)`` for
    ``friction_relaxation``, ``(strength,)`` for ``frequency_dependent_modulus``; absent
    names are at their null (0). The model is linear in the two levels of a run:
    ``angle = A2 + (A1 - A2) g(t)``, g the response to a unit drop of mu_ss divided by
    its static angle (1 before the step, 0 long after), so :meth:`fit_base` is a linear
    least-squares fit per run.

    A run with no rows in ``train`` (a held-out whole run) gets its two levels from its own
    rows: levels scatter from run to run (ice, climate), so no other run can predict them,
    and the held-out score then tests what the candidates change, the path between them
    (2 of thousands of samples, the same for every candidate and the base model).

    Examples
    --------
    >>> import numpy as np
    >>> from friction_model.dynamics.element_step import step_response
    >>> t = np.arange(0.0, 0.1, 1e-4)
    >>> angle = step_response(t, 0.05, mu_before=0.6, mu_after=0.4, tau_s=0.02)
    >>> p = TransientProblem([TransientRun("r", t, angle, 1.0, 5.0, 0.05, sigma_deg=0.5)])
    >>> relaxed = {"friction_relaxation": (0.02,)}
    >>> base = p.fit_base(np.ones(p.y.size, bool), relaxed)
    >>> [round(float(x), 3) for x in base]  # 0.6 and 0.4 times 35.478 deg
    [21.287, 14.191]
    >>> bool(np.allclose(p.predict(base, relaxed), angle, atol=1e-9))
    True
    """

    kind: str = "transient"
    effect_names: tuple[str, ...] = (RELAXATION, MODULUS)

    def __init__(
        self,
        runs: Sequence[TransientRun],
        *,
        grouping: str = "auto",
        block_edges_s: Sequence[float] = DEFAULT_BLOCK_EDGES_S,
    ) -> None:
        runs = list(runs)
        if not runs or not all(isinstance(r, TransientRun) for r in runs):
            raise TypeError("runs must be a non-empty sequence of TransientRun")
        labels = [r.label for r in runs]
        if len(set(labels)) != len(labels):
            raise ValueError(f"run labels must be unique, got {labels}")
        if grouping not in ("auto", "runs", "blocks"):
            raise ValueError(f"grouping must be 'auto', 'runs' or 'blocks', got {grouping!r}")
        if grouping == "auto":
            grouping = "runs" if len(runs) > 1 else "blocks"
        self.runs: tuple[TransientRun, ...] = tuple(runs)
        self.grouping = grouping
        sizes = [r.time_s.size for r in runs]
        self._slices = []
        start = 0
        for size in sizes:
            self._slices.append(slice(start, start + size))
            start += size
        self.y = np.concatenate([r.angle_deg for r in runs])
        self.sigma = np.concatenate([np.full(r.time_s.size, r.sigma) for r in runs])
        if grouping == "runs":
            self.groups = np.concatenate([np.full(r.time_s.size, r.label, object) for r in runs])
        else:
            self.groups = np.concatenate([_block_labels(r, block_edges_s) for r in runs])
        self.covariates = pd.DataFrame(
            {
                "run": np.concatenate([np.full(r.time_s.size, r.label, object) for r in runs]),
                "element": np.concatenate(
                    [np.full(r.time_s.size, -1 if r.element is None else r.element) for r in runs]
                ),
                "time_s": np.concatenate([r.time_s for r in runs]),
                "time_since_step_s": np.concatenate([r.time_s - r.t_step_s for r in runs]),
                "velocity_mps": np.concatenate(
                    [np.where(r.time_s < r.t_step_s, r.v1_mps, r.v2_mps) for r in runs]
                ),
                "n_sipes": np.concatenate([np.full(r.time_s.size, r.n_sipes) for r in runs]),
                "pressure_bar": np.concatenate(
                    [np.full(r.time_s.size, float(r.pressure_bar)) for r in runs]
                ),
            }
        )
        self.n_base = 2 * len(runs)
        self._cache: dict[tuple[float, float], list[np.ndarray]] = {}

    # -- construction helpers ------------------------------------------------------------
    @classmethod
    def from_tables(
        cls,
        tables: pd.DataFrame | Sequence[pd.DataFrame],
        *,
        labels: Sequence[str] | None = None,
        n_sipes: int = 3,
        pressure_bar: float = 1.2,
        t_step_s: float | None = None,
        grouping: str = "auto",
        block_edges_s: Sequence[float] = DEFAULT_BLOCK_EDGES_S,
    ) -> TransientProblem:
        """A problem from transient tables, one run each (see :func:`run_from_table`)."""
        if isinstance(tables, pd.DataFrame):
            tables = [tables]
        tables = list(tables)
        if labels is None:
            labels = [f"run {k + 1}" for k in range(len(tables))]
        if len(labels) != len(tables):
            raise ValueError(f"got {len(labels)} labels for {len(tables)} tables")
        runs = [
            run_from_table(
                tb, label=str(lb), t_step_s=t_step_s, n_sipes=n_sipes, pressure_bar=pressure_bar
            )
            for tb, lb in zip(tables, labels, strict=True)
        ]
        return cls(runs, grouping=grouping, block_edges_s=block_edges_s)

    @classmethod
    def from_elements(
        cls,
        elements: pd.DataFrame,
        *,
        v1_mps: float,
        v2_mps: float,
        t_step_s: float,
        element: int | Sequence[int] = 0,
        n_sipes: int = 3,
        pressure_bar: float = 1.2,
        grouping: str = "auto",
        block_edges_s: Sequence[float] = DEFAULT_BLOCK_EDGES_S,
    ) -> TransientProblem:
        """A problem from pipeline ``elements.csv`` rows (see :func:`runs_from_elements`)."""
        runs = runs_from_elements(
            elements,
            v1_mps=v1_mps,
            v2_mps=v2_mps,
            t_step_s=t_step_s,
            element=element,
            n_sipes=n_sipes,
            pressure_bar=pressure_bar,
        )
        return cls(runs, grouping=grouping, block_edges_s=block_edges_s)

    # -- the model -----------------------------------------------------------------------
    def effect_parameters(self, effects: Mapping[str, Sequence[float]]) -> tuple[float, float]:
        """(tau_s, modulus strength) from an effects mapping (absent: 0).

        The candidates' bounds are those of the registry (:func:`candidate_specs`); here
        only the physics is checked: tau_s >= 0 and strength >= 0.
        """
        return relaxation_and_modulus(effects, data="transient data")

    def parameter_bounds(self, name: str) -> list[tuple[float, float]] | None:
        """Narrower bounds for a candidate on this data: tau_s in [0, ``TAU_MAX_S``].

        The workflow intersects them with the library bounds; None leaves those.
        """
        if name == RELAXATION:
            return [(0.0, TAU_MAX_S)]
        return None

    def unit_responses(self, effects: Mapping[str, Sequence[float]]) -> list[np.ndarray]:
        """g(t) per run: the response to a unit drop of mu_ss over its static angle."""
        key = self.effect_parameters(effects)
        cached = self._cache.get(key)
        if cached is not None:
            return cached
        tau, strength = key
        out = []
        for run in self.runs:
            el = step_element(
                n_sipes=run.n_sipes, pressure_bar=run.pressure_bar, modulus_strength=strength
            )
            angle = step_response(
                run.time_s,
                run.t_step_s,
                mu_before=1.0,
                mu_after=0.0,
                n_sipes=run.n_sipes,
                pressure_bar=run.pressure_bar,
                tau_s=tau,
                modulus_strength=strength,
            )
            out.append(angle / el.angle_per_mu_deg)
        if (len(self._cache) + 1) * self.y.size > _CACHE_FLOATS and self._cache:
            self._cache.pop(next(iter(self._cache)))
        self._cache[key] = out
        return out

    def fit_base(
        self,
        train: np.ndarray,
        effects: Mapping[str, Sequence[float]],
        *,
        weights: np.ndarray | None = None,
    ) -> np.ndarray:
        """Steady angles before and after the step of each run, by least squares on ``train``.

        Parameters
        ----------
        train : (n,) bool ndarray
            Rows to fit on. A run with no training row (held out whole), or whose training
            rows lie all on one side of the step, is fitted on all its rows (see Notes of
            the class).
        effects : mapping
            Candidate parameters held fixed.
        weights : (n,) array_like, optional
            Row weights >= 0 (block-bootstrap counts); 1 when omitted. Rows outside
            ``train`` count 0.

        Returns
        -------
        (n_base,) ndarray
            ``[A1_run1, A2_run1, A1_run2, ...]``, degrees.
        """
        train = np.asarray(train)
        if train.dtype != bool or train.shape != self.y.shape:
            raise ValueError(
                f"train must be a bool mask of shape {self.y.shape}, got {train.dtype} "
                f"{train.shape}"
            )
        w = np.ones(self.y.size) if weights is None else np.asarray(weights, dtype=float)
        if w.shape != self.y.shape or not np.all(np.isfinite(w)) or np.any(w < 0):
            raise ValueError(f"weights must be finite, >= 0 and of shape {self.y.shape}")
        w = np.where(train, w, 0.0)
        base = np.empty(self.n_base)
        for k, (sl, g) in enumerate(zip(self._slices, self.unit_responses(effects), strict=True)):
            base[2 * k : 2 * k + 2] = _levels(g, self.y[sl], w[sl])
        return base

    def predict(self, base: np.ndarray, effects: Mapping[str, Sequence[float]]) -> np.ndarray:
        """Model angle for every observation, degrees (Eq. 5.8 linearised, Eq. 5.12).

        Parameters
        ----------
        base : (n_base,) array_like
            Levels from :meth:`fit_base`.
        effects : mapping
            Candidate parameters.

        Returns
        -------
        (n,) ndarray
        """
        base = np.asarray(base, dtype=float)
        if base.shape != (self.n_base,):
            raise ValueError(f"base must have shape ({self.n_base},), got {base.shape}")
        out = np.empty(self.y.size)
        for k, (sl, g) in enumerate(zip(self._slices, self.unit_responses(effects), strict=True)):
            a1, a2 = base[2 * k], base[2 * k + 1]
            out[sl] = a2 + (a1 - a2) * g
        return out


def candidate_specs() -> tuple[Candidate, Candidate]:
    """The two candidates a transient problem fits, as registered in the library.

    Returns
    -------
    tuple of Candidate
        ``friction_relaxation`` (parameter ``tau_s``, s, null 0) and
        ``frequency_dependent_modulus`` (``strength``, null 0), with the bounds of
        :func:`friction_model.discrepancy._problem.get_candidate`.

    Examples
    --------
    >>> [(c.name, c.parameters[0].name, c.null) for c in candidate_specs()]
    [('friction_relaxation', 'tau_s', (0.0,)), ('frequency_dependent_modulus', 'strength', (0.0,))]
    """
    return get_candidate(RELAXATION), get_candidate(MODULUS)
