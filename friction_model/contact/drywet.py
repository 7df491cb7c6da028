"""The dry run-in / wet rubber-ice friction model of section 4.5.1, made quantitative.

Each element of a (siped) tread block has a dry run-in area at its front, where the
frictional heat of dry rubber friction ``mu_dry p`` warms the ice to its melting point
(Eq. 4.6/4.7) and melts a first film, followed by a wet area whose friction is the shear of
the melt-water film (Eq. 4.3) plus a boundary part from asperity contacts (mixed
lubrication, as Evans et al. describe it, section 2.6.3). The friction force is the sum
``F_F = F_dry + F_wet`` (Eq. 4.2, 4.4, 4.5) over the split ``A = A_dry + A_wet`` (Eq. 4.1).

The film thickness ``h`` that the thesis leaves open follows from a heat balance in the wet
zone, taken from the frictional-melting models of section 2.6 (Evans et al. 2.6.3,
Oksanen and Keinonen 2.6.6, Bäurle 2.6.8): the frictional heat of the film goes into
conduction into the ice (whose surface is held at the melting point) and into melting::

    rho_w L dh/dt = K (tau_b + eta v / h) v - q_ice(t)

``q_ice`` comes from exact 1-D heat conduction into the semi-infinite ice with the full heat
history of the block (see :mod:`friction_model.contact._march`). This yields both classical limits:
cold ice, where conduction dominates, gives ``mu ~ v^-1/2`` (Evans); near the melting point,
where melting dominates, ``h ~ sqrt(v)`` and ``mu ~ v^+1/2`` (Oksanen). When the heat cannot
keep the film at the critical thickness ``h_c`` the film collapses locally and dry patches
mix in until the heat balances conduction.

The siped block (Fig. 4.25): each element wipes the melt water down to the bound initial
layer ``h0`` and heats the ice for the elements behind it; across the sipe (duration
``f / v``) the ice surface cools. So the dry run-in length shrinks from the first to the last
element. Everything is per unit width; the real contact area is a fraction ``phi`` of the
rubber face (from TIR measurements or a pressure law), and the local pressure is
``p_local = F_N / A_real``.
"""

from __future__ import annotations

import difflib
import math
import warnings
from dataclasses import dataclass, field, fields, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from friction_model.conditions import Conditions
from friction_model.constants import ICE, WATER, IceProperties, WaterProperties
from friction_model.contact._march import Grid, MarchInput, MarchOutput, build_grid, march
from friction_model.contact.effects import Effects
from friction_model.contact.water_layer import freezing_point_depression_K, initial_water_layer_m
from friction_model.geometry import BlockGeometry, as_geometry
from tir_common.validate import check_nonnegative, check_positive, check_range

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = [
    "REGIMES",
    "BlockFriction",
    "DryWetParameters",
    "element_friction_table",
    "friction_table",
    "real_contact_fraction",
    "simulate_block",
]

REGIMES = ("dry-dominated", "mixed", "viscous")


@dataclass(frozen=True)
class DryWetParameters:
    """Parameters of the dry/wet model (SI units).

    The defaults are the one shared parameter set calibrated on Table 4.6 of the thesis
    (:func:`friction_model.identification.table_4_6.calibrate_table_4_6`, reproduced by
    ``examples/calibrate_table_4_6.py``; RMSE of mu 0.007, 0.005, 0.007, 0.006 on the four
    curves); ``mu_dry`` and ``heat_fraction`` are the thesis values.

    Parameters
    ----------
    mu_dry : float
        Dry friction coefficient of the run-in area (thesis: about 1.5, rubber on dry glass).
    heat_fraction : float
        K, the fraction of the frictional heat that goes into the ice (thesis: K = 1).
    boundary_shear_Pa : float
        Shear strength tau_b of the asperity contacts in the wet zone (mixed lubrication), Pa.
    critical_film_m : float
        Film thickness h_c above which the contact is wet (separates the surfaces), m.
    qll_thickness_m : float
        Bound water layer at 1 K below the melting point in dry air, m. Not fitted: 20 nm,
        inside the spread of the measured premelted layer near -1 degC that the thesis
        shows in Fig. 2.7 (ellipsometry to X-ray, roughly 10-100 nm).
    humidity_gain : float
        Growth of the bound layer from 0 to 100 % relative humidity (relative). Not
        fitted (Table 4.6 cannot separate humidity from temperature): 2, i.e. saturated air
        triples the layer, an assumption for the condensation the thesis describes.
    salt_enrichment : float
        Surface-brine / bulk salinity ratio; an assumption (brine rejection), not fitted:
        no data in the thesis pins it down; 20 makes K = 0.05 % lower the melting point of
        the surface by 0.59 K.
    contact_fraction_ref : float
        Real contact fraction of the rubber face at ``contact_pressure_ref_Pa``.
    contact_pressure_exponent : float
        gamma in ``phi = phi_ref (p / p_ref)^gamma`` (more pressure, more real contact).
    contact_pressure_ref_Pa : float
        Reference nominal pressure of the contact law, Pa.
    effects : Effects
        Strengths of the switchable effects (all 1 by default; ``Effects.none()`` = base).
    ice, water : IceProperties, WaterProperties
        Material constants.
    n_cells : int
        Cells per element along the sliding direction (graded towards the leading edge).
    grid_grading : float
        Grading exponent of the cells (1 = uniform).
    """

    mu_dry: float = 1.5
    heat_fraction: float = 1.0
    boundary_shear_Pa: float = 1.094e4
    critical_film_m: float = 4.361e-7
    qll_thickness_m: float = 2.0e-8
    humidity_gain: float = 2.0
    salt_enrichment: float = 20.0
    contact_fraction_ref: float = 0.6837
    contact_pressure_exponent: float = 0.2237
    contact_pressure_ref_Pa: float = 2.5e5
    effects: Effects = field(default_factory=Effects)
    ice: IceProperties = ICE
    water: WaterProperties = WATER
    n_cells: int = 60
    grid_grading: float = 2.0

    def __post_init__(self) -> None:
        check_positive("mu_dry", self.mu_dry)
        check_range("heat_fraction", self.heat_fraction, 1e-6, 1.0)
        check_nonnegative("boundary_shear_Pa", self.boundary_shear_Pa)
        check_positive("critical_film_m", self.critical_film_m)
        check_nonnegative("qll_thickness_m", self.qll_thickness_m)
        check_nonnegative("humidity_gain", self.humidity_gain)
        check_nonnegative("salt_enrichment", self.salt_enrichment)
        check_range("contact_fraction_ref", self.contact_fraction_ref, 1e-3, 1.0)
        check_range("contact_pressure_exponent", self.contact_pressure_exponent, 0.0, 1.0)
        check_positive("contact_pressure_ref_Pa", self.contact_pressure_ref_Pa)
        if int(self.n_cells) != self.n_cells or self.n_cells < 4:
            raise ValueError(f"n_cells must be an integer >= 4, got n_cells={self.n_cells!r}")
        check_range("grid_grading", self.grid_grading, 1.0, 4.0)
        if not isinstance(self.effects, Effects):
            raise TypeError(f"effects must be an Effects instance, got {type(self.effects)}")

    def with_(self, **changes: Any) -> DryWetParameters:
        """A copy with some parameters changed."""
        return replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """Plain dict of the scalar parameters plus the effect strengths (for JSON)."""
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, Effects):
                out["effects"] = value.as_dict()
            elif isinstance(value, IceProperties | WaterProperties):
                out[f.name] = {g.name: getattr(value, g.name) for g in fields(value)}
            else:
                out[f.name] = value
        return out


def real_contact_fraction(pressure_Pa: np.ndarray | float, params: DryWetParameters):
    """Real contact area as a fraction of the rubber face, from the nominal pressure.

    ``phi = clip(phi_ref (p / p_ref)^gamma, 0.01, 1)``: a softer-than-linear growth of the
    real contact with load (TIR measurements give the value directly; pass it through
    :attr:`Conditions.contact_fraction` instead when available).

    Parameters
    ----------
    pressure_Pa : float or ndarray
        Nominal pressure, Pa.
    params : DryWetParameters

    Returns
    -------
    float or ndarray
        phi in (0, 1].
    """
    p = np.asarray(pressure_Pa, dtype=float)
    phi = params.contact_fraction_ref * (p / params.contact_pressure_ref_Pa) ** (
        params.contact_pressure_exponent
    )
    phi = np.clip(phi, 0.01, 1.0)
    return float(phi) if phi.ndim == 0 else phi


def _regime(run_in_share: np.ndarray, viscous_share: np.ndarray) -> np.ndarray:
    """Classify by the share of the friction force from the dry run-in areas at the element
    fronts (``dry-dominated`` when >= 1/2) and from viscous shear (``viscous`` when >= 1/2);
    everything else, including dry patches and boundary friction inside the wet zone
    (mixed lubrication), is ``mixed``."""
    return np.where(
        run_in_share >= 0.5, REGIMES[0], np.where(viscous_share >= 0.5, REGIMES[2], REGIMES[1])
    )


def _subcooling_K(
    temperature_C: np.ndarray,
    melting_point_C: np.ndarray,
    salinity_pct: np.ndarray,
    salt_strength: np.ndarray | None = None,
) -> np.ndarray:
    """Melting point minus ice temperature, K, per row; the model needs it > 0.

    ``salt_strength`` (per row), when given, is named in the error as the
    ``salinity_melting_point`` strength that lowered the melting point.
    """
    dT = melting_point_C - temperature_C
    if np.any(dT <= 0):
        bad = int(np.flatnonzero(dT <= 0)[0])
        cause = (
            ""
            if salt_strength is None
            else f", salinity_melting_point strength {salt_strength[bad]:g}"
        )
        raise ValueError(
            f"temperature_C={temperature_C[bad]} is not below the melting point of the ice "
            f"({melting_point_C[bad]:.3f} degC at salinity_pct={salinity_pct[bad]}{cause}); "
            "the model needs ice below its melting point"
        )
    return dT


@dataclass(frozen=True)
class _Prepared:
    grid: Grid
    inp: MarchInput
    phi: np.ndarray
    p_face: np.ndarray
    melting_point_C: np.ndarray


def _prepare(geometry: BlockGeometry, table: pd.DataFrame, params: DryWetParameters) -> _Prepared:
    lengths_m = geometry.element_lengths * 1e-3
    grid = build_grid(
        lengths_m,
        geometry.sipe_width_mm * 1e-3,
        n_cells=int(params.n_cells),
        grading=params.grid_grading,
    )
    eff = params.effects
    v = table["velocity_mps"].to_numpy(float)
    p_nom = table["pressure_Pa"].to_numpy(float)
    T = table["temperature_C"].to_numpy(float)
    rh = table["humidity_pct"].to_numpy(float)
    sal = table["salinity_pct"].to_numpy(float)
    given = table["contact_fraction"].to_numpy(float)
    phi = np.where(np.isfinite(given), given, real_contact_fraction(p_nom, params))
    # the load is carried by the element faces (the sipes carry none)
    p_face = p_nom * geometry.nominal_area_mm2 / geometry.rubber_area_mm2
    p_local = p_face / phi
    t_melt = params.ice.melting_point_C - freezing_point_depression_K(
        sal, enrichment=params.salt_enrichment * eff.salinity_melting_point
    )
    dT = _subcooling_K(T, t_melt, sal)
    h0 = initial_water_layer_m(
        dT,
        rh,
        qll_thickness_m=params.qll_thickness_m,
        humidity_gain=params.humidity_gain * eff.humidity_water_layer,
    )
    inp = MarchInput(
        velocity=v,
        pressure_local=p_local,
        delta_T=dT,
        h0=h0,
        mu_dry=params.mu_dry,
        heat_fraction=params.heat_fraction,
        boundary_shear=params.boundary_shear_Pa,
        critical_film=params.critical_film_m,
        viscous_strength=eff.viscous_shear,
        preheating=eff.ice_preheating,
        viscosity=params.water.viscosity_Pa_s,
        melt_energy=params.water.density_kg_m3 * params.ice.latent_heat_J_kg,
        conduction_factor=2.0 / math.sqrt(math.pi * params.ice.thermal_inertia),
    )
    return _Prepared(grid=grid, inp=inp, phi=phi, p_face=p_face, melting_point_C=t_melt)


_CONDITION_COLUMNS = (
    "velocity_mps",
    "pressure_Pa",
    "temperature_C",
    "humidity_pct",
    "salinity_pct",
    "contact_fraction",
)


def _check_columns(table: pd.DataFrame) -> None:
    """A conditions table's pressure given twice must agree (else which one is used is not
    the user's choice), and a column close to a condition's name is warned about (a
    misspelt ``humidity`` would fall back to 50 % without a word)."""
    if "pressure_Pa" in table and "pressure_bar" in table:
        pa = table["pressure_Pa"].to_numpy(float)
        bar = table["pressure_bar"].to_numpy(float)
        # 1 %: bar rounded to three figures beside its Pa agrees, another unit does not
        if not np.allclose(pa, bar * 1e5, rtol=0.01, atol=0.0, equal_nan=True):
            k = int(np.flatnonzero(~np.isclose(pa, bar * 1e5, rtol=0.01, atol=0.0))[0])
            raise ValueError(
                f"conditions table gives pressure_Pa and pressure_bar that disagree (row {k}: "
                f"{pa[k]:g} Pa against {bar[k]:g} bar); give one of them"
            )
    known = (*_CONDITION_COLUMNS, "pressure_bar")
    for col in table.columns:
        if isinstance(col, str) and col not in known:
            close = difflib.get_close_matches(col, known, n=1, cutoff=0.8)
            if close and close[0] not in table.columns:  # 'velocity_mps_std' beside its own
                warnings.warn(f"conditions table: column {col!r} is not read; did you mean "
                              f"{close[0]!r}?", UserWarning, stacklevel=4)


def _as_table(conditions: Conditions | pd.DataFrame | list[Conditions]) -> pd.DataFrame:
    if isinstance(conditions, Conditions):
        conditions = [conditions]
    if isinstance(conditions, list | tuple):
        rows = [{name: getattr(c, name) for name in _CONDITION_COLUMNS} for c in conditions]
        table = pd.DataFrame(rows, columns=list(_CONDITION_COLUMNS))
    elif isinstance(conditions, pd.DataFrame):
        table = conditions.copy()
        _check_columns(table)
        if "pressure_Pa" not in table and "pressure_bar" in table:
            table["pressure_Pa"] = table["pressure_bar"] * 1e5
        table = table.assign(
            **{
                name: table[name] if name in table else default
                for name, default in (
                    ("humidity_pct", 50.0),
                    ("salinity_pct", 0.0),
                    ("contact_fraction", np.nan),
                )
            }
        )
        missing = [c for c in _CONDITION_COLUMNS if c not in table]
        if missing:
            raise ValueError(
                f"conditions table is missing column(s) {missing}; expected "
                f"{list(_CONDITION_COLUMNS)} (pressure_bar accepted for pressure_Pa)"
            )
        # validate every row through the dataclass (clear messages with the row)
        for i, row in enumerate(table[list(_CONDITION_COLUMNS)].itertuples(index=False)):
            try:
                Conditions(*row[:5], contact_fraction=None if pd.isna(row[5]) else float(row[5]))
            except ValueError as exc:
                raise ValueError(f"conditions row {i}: {exc}") from None
    else:
        raise TypeError(
            "conditions must be Conditions, a list of them or a DataFrame, "
            f"got {type(conditions).__name__}"
        )
    table["contact_fraction"] = table["contact_fraction"].astype(float)
    return table.reset_index(drop=True)


def _element_tables(
    geometry: BlockGeometry,
    prep: _Prepared,
    res: MarchOutput,
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Integrate the cell results per element; arrays of shape (n_c, n_elements)."""
    grid = prep.grid
    dx = grid.dx
    n_c = len(prep.phi)
    n_el = geometry.n_elements
    w_eff = geometry.width_mm * 1e-3 * prep.phi  # real contact width, m
    out: dict[str, np.ndarray] = {
        k: np.zeros((n_c, n_el))
        for k in (
            "dry_length_m",
            "run_in_length_m",
            "F_dry",
            "F_visc",
            "F_bnd",
            "film_mean_m",
            "film_end_m",
        )
    }
    for i in range(n_el):
        s, e = grid.element_starts[i], grid.element_ends[i]
        d = dx[s:e]
        dry = res.dry_fraction[:, s:e]
        out["dry_length_m"][:, i] = dry @ d
        out["F_dry"][:, i] = (res.tau_dry[:, s:e] @ d) * w_eff
        out["F_visc"][:, i] = (res.tau_viscous[:, s:e] @ d) * w_eff
        out["F_bnd"][:, i] = (res.tau_boundary[:, s:e] @ d) * w_eff
        wet_len = (1.0 - dry) @ d
        out["film_mean_m"][:, i] = np.where(
            wet_len > 0, ((1.0 - dry) * res.film[:, s:e]) @ d / np.maximum(wet_len, 1e-30), 0.0
        )
        out["film_end_m"][:, i] = res.film[:, e - 1]
        # run-in: the contiguous dry length from the leading edge (heating, then melting
        # the first film up to h_c); dry patches further back do not count
        part = res.run_in_part[:, s:e]
        ends = part < 1.0 - 1e-12
        first = np.where(ends.any(axis=1), ends.argmax(axis=1), e - s)
        x_rel = grid.nodes_m[s : e + 1] - grid.nodes_m[s]
        run_in = np.empty(n_c)
        for c in range(n_c):
            j = first[c]
            run_in[c] = x_rel[j] + (part[c, j] * d[j] if j < e - s else 0.0)
        out["run_in_length_m"][:, i] = run_in
    lengths = geometry.element_lengths * 1e-3
    return lengths, out


@dataclass(frozen=True)
class BlockFriction:
    """Result of :func:`simulate_block` for one condition.

    Attributes
    ----------
    conditions : Conditions
    geometry : BlockGeometry
    elements : pandas.DataFrame
        One row per element (0 leads): ``element, length_mm, heating_length_mm,
        run_in_length_mm, dry_length_mm, wet_length_mm, dry_area_mm2, wet_area_mm2,
        film_mean_um, film_end_um, entry_temperature_C, normal_force_N, dry_force_N,
        viscous_force_N, boundary_force_N, friction_force_N, mu, mu_wet, run_in_force_N,
        regime``. ``dry_force_N`` includes dry patches inside the wet zone;
        ``run_in_force_N`` is the part from the leading dry run-in area alone.
    block : dict
        Block totals: ``mu, mu_dry, mu_wet, friction_force_N, normal_force_N,
        dry_force_N, viscous_force_N, boundary_force_N, dry_area_mm2, wet_area_mm2,
        contact_fraction, pressure_local_Pa, melting_point_C, run_in_force_N, regime``.
    profile : pandas.DataFrame
        Per cell: ``x_mm`` (cell centre behind the block's leading edge), ``element``
        (-1 in a sipe), ``shear_stress_Pa``, ``dry_fraction``, ``film_um`` (at the cell end),
        ``x_end_mm`` (cell end) and ``surface_temperature_C`` (ice surface at the cell end).
    """

    conditions: Conditions
    geometry: BlockGeometry
    elements: pd.DataFrame
    block: dict[str, Any]
    profile: pd.DataFrame

    @property
    def mu(self) -> float:
        """Friction coefficient of the block, F_F / F_N."""
        return float(self.block["mu"])

    def plot(self, ax=None) -> Figure:
        """Shear stress, dry fraction and film thickness along the block (Fig. 4.24/4.25).

        Parameters
        ----------
        ax : sequence of two matplotlib Axes, optional
            Axes for the stress and the film panels; new figure when omitted.

        Returns
        -------
        matplotlib.figure.Figure
        """
        import matplotlib.pyplot as plt

        if ax is None:
            fig, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        else:
            fig = ax[0].figure
        prof = self.profile
        contact = prof["element"] >= 0
        x = prof["x_mm"].where(contact)
        ax[0].plot(x, prof["shear_stress_Pa"].where(contact) / 1e3, color="k", lw=1.2)
        ax[0].fill_between(
            prof["x_mm"],
            0,
            (prof["shear_stress_Pa"] * prof["dry_fraction"]).where(contact) / 1e3,
            color="tab:red",
            alpha=0.35,
            label="dry part",
        )
        ax[0].set_ylabel("shear stress / kPa")
        ax[0].legend(loc="upper right")
        ax[1].semilogy(x, prof["film_um"].where(prof["film_um"] > 0), color="tab:blue")
        ax[1].set_ylabel("film thickness / µm")
        ax[1].set_xlabel("distance behind the leading edge / mm")
        c = self.conditions
        ax[0].set_title(
            f"v = {c.velocity_mps:g} m/s, p = {c.pressure_bar:g} bar, T = {c.temperature_C:g} °C,"
            f" rH = {c.humidity_pct:g} %: mu = {self.mu:.3f} ({self.block['regime']})"
        )
        fig.tight_layout()
        return fig


def _run(
    geometry: BlockGeometry, table: pd.DataFrame, params: DryWetParameters
) -> tuple[_Prepared, MarchOutput, dict[str, np.ndarray]]:
    prep = _prepare(geometry, table, params)
    res = march(prep.grid, prep.inp)
    _, agg = _element_tables(geometry, prep, res)
    return prep, res, agg


def friction_table(
    geometry: BlockGeometry | str,
    conditions: Conditions | pd.DataFrame | list[Conditions],
    params: DryWetParameters | None = None,
) -> pd.DataFrame:
    """Block friction coefficient and its parts for many conditions at once (vectorised).

    Parameters
    ----------
    geometry : BlockGeometry or str
        The tread block, or a reference sample's name (``"G3"``).
    conditions : Conditions, list of Conditions or pandas.DataFrame
        A table needs ``velocity_mps``, ``pressure_Pa`` (or ``pressure_bar``) and
        ``temperature_C``; ``humidity_pct`` (default 50), ``salinity_pct`` (0) and
        ``contact_fraction`` (NaN = model law) are optional.
    params : DryWetParameters, optional
        Model parameters; the calibrated defaults when omitted.

    Returns
    -------
    pandas.DataFrame
        The condition columns plus ``mu, mu_wet, dry_share, run_in_share, viscous_share,
        regime,
        run_in_length_first_mm, run_in_length_last_mm, dry_fraction, film_end_um,
        contact_fraction, pressure_local_Pa``. The shares are fractions of the friction
        force: all dry contact, the dry run-in areas alone, viscous shear.

    Examples
    --------
    >>> from friction_model.geometry import reference_block
    >>> t = friction_table(reference_block("G3"), [Conditions.from_bar(1.0, 2.5, -5.0)])
    >>> bool(0.1 < t.loc[0, "mu"] < 0.5)
    True
    """
    geometry = as_geometry(geometry)
    params = params or DryWetParameters()
    table = _as_table(conditions)
    prep, _res, agg = _run(geometry, table, params)
    F_dry = agg["F_dry"].sum(axis=1)
    F_visc = agg["F_visc"].sum(axis=1)
    F_bnd = agg["F_bnd"].sum(axis=1)
    F = F_dry + F_visc + F_bnd
    F_N = prep.p_face * geometry.rubber_area_mm2 * 1e-6
    lengths = geometry.element_lengths * 1e-3
    dry_len = agg["dry_length_m"].sum(axis=1)
    wet_len = lengths.sum() - dry_len
    w_eff = geometry.width_mm * 1e-3 * prep.phi
    p_local = prep.inp.pressure_local
    out = table.copy()
    out["mu"] = F / F_N
    out["mu_wet"] = np.where(
        wet_len > 0, (F_visc + F_bnd) / np.maximum(p_local * wet_len * w_eff, 1e-30), 0.0
    )
    F_run_in = (agg["run_in_length_m"] * (params.mu_dry * p_local * w_eff)[:, None]).sum(axis=1)
    out["dry_share"] = F_dry / F
    out["run_in_share"] = F_run_in / F
    out["viscous_share"] = F_visc / F
    out["regime"] = _regime(out["run_in_share"].to_numpy(), out["viscous_share"].to_numpy())
    out["run_in_length_first_mm"] = agg["run_in_length_m"][:, 0] * 1e3
    out["run_in_length_last_mm"] = agg["run_in_length_m"][:, -1] * 1e3
    out["dry_fraction"] = dry_len / lengths.sum()
    out["film_end_um"] = agg["film_end_m"][:, -1] * 1e6
    out["contact_fraction"] = prep.phi
    out["pressure_local_Pa"] = p_local
    return out


def simulate_block(
    geometry: BlockGeometry | str,
    conditions: Conditions,
    params: DryWetParameters | None = None,
) -> BlockFriction:
    """Friction of a (siped) tread block sliding on ice under one set of conditions.

    Implements Eq. 4.1 (contact split), Eq. 4.2-4.5 (dry plus viscous friction force) with
    Eq. 4.6/4.7 (Blok) for the heating of the dry run-in area, the film heat balance of the
    module docstring, and the element-by-element preheating of Fig. 4.25.

    Parameters
    ----------
    geometry : BlockGeometry or str
        The tread block (element 0 leads), or a reference sample's name (``"G3"``).
    conditions : Conditions
        Velocity, nominal pressure, temperature, humidity, salinity, optional measured
        real contact fraction.
    params : DryWetParameters, optional
        Model parameters; the calibrated defaults when omitted.

    Returns
    -------
    BlockFriction
        Per-element and block results; ``mu_wet <= mu <= mu_dry`` holds by construction.

    Examples
    --------
    >>> from friction_model.geometry import reference_block
    >>> r = simulate_block(reference_block("G3"), Conditions.from_bar(1.0, 2.5, -5.0))
    >>> bool(r.elements["run_in_length_mm"].is_monotonic_decreasing)
    True
    """
    if not isinstance(conditions, Conditions):
        raise TypeError(
            f"conditions must be a Conditions instance, got {type(conditions).__name__}; "
            "use friction_table for many conditions"
        )
    geometry = as_geometry(geometry)
    params = params or DryWetParameters()
    table = _as_table(conditions)
    prep, res, agg = _run(geometry, table, params)
    elements = _block_elements(geometry, conditions, params, prep, res, agg)
    return BlockFriction(
        conditions=conditions,
        geometry=geometry,
        elements=elements,
        block=_block_totals(geometry, elements, params, prep),
        profile=_block_profile(conditions, prep, res),
    )


def _block_elements(
    geometry: BlockGeometry,
    conditions: Conditions,
    params: DryWetParameters,
    prep: _Prepared,
    res: MarchOutput,
    agg: dict[str, np.ndarray],
) -> pd.DataFrame:
    """Per-element table of :func:`simulate_block` (one condition)."""
    lengths_mm = geometry.element_lengths
    w_eff_mm = geometry.width_mm * float(prep.phi[0])
    p_local = float(prep.inp.pressure_local[0])
    dry_len_mm = agg["dry_length_m"][0] * 1e3
    wet_len_mm = lengths_mm - dry_len_mm
    F_dry, F_visc, F_bnd = agg["F_dry"][0], agg["F_visc"][0], agg["F_bnd"][0]
    F = F_dry + F_visc + F_bnd
    F_N = float(prep.p_face[0]) * lengths_mm * geometry.width_mm * 1e-6
    mu_wet = np.where(
        wet_len_mm > 0,
        (F_visc + F_bnd) / np.maximum(p_local * wet_len_mm * w_eff_mm * 1e-6, 1e-30),
        0.0,
    )
    heating = res.heating_length[0] * 1e3
    elements = pd.DataFrame(
        {
            "element": np.arange(geometry.n_elements),
            "length_mm": lengths_mm,
            "heating_length_mm": np.where(np.isnan(heating), lengths_mm, heating),
            "run_in_length_mm": agg["run_in_length_m"][0] * 1e3,
            "dry_length_mm": dry_len_mm,
            "wet_length_mm": wet_len_mm,
            "dry_area_mm2": dry_len_mm * w_eff_mm,
            "wet_area_mm2": wet_len_mm * w_eff_mm,
            "film_mean_um": agg["film_mean_m"][0] * 1e6,
            "film_end_um": agg["film_end_m"][0] * 1e6,
            "entry_temperature_C": conditions.temperature_C + res.entry_theta[0],
            "normal_force_N": F_N,
            "dry_force_N": F_dry,
            "viscous_force_N": F_visc,
            "boundary_force_N": F_bnd,
            "friction_force_N": F,
            "mu": F / F_N,
            "mu_wet": mu_wet,
        }
    )
    F_run_in = params.mu_dry * p_local * elements["run_in_length_mm"].to_numpy() * w_eff_mm * 1e-6
    elements["run_in_force_N"] = F_run_in
    elements["regime"] = _regime(F_run_in / F, F_visc / F)
    return elements


def _block_totals(
    geometry: BlockGeometry, elements: pd.DataFrame, params: DryWetParameters, prep: _Prepared
) -> dict[str, Any]:
    """Block sums of :func:`simulate_block`: forces, areas, ``mu`` and the regime."""
    w_eff_mm = geometry.width_mm * float(prep.phi[0])
    p_local = float(prep.inp.pressure_local[0])
    F_visc = elements["viscous_force_N"].to_numpy()
    F_bnd = elements["boundary_force_N"].to_numpy()
    F_run_in = elements["run_in_force_N"].to_numpy()
    FN_tot = float(elements["normal_force_N"].to_numpy().sum())
    F_tot = float(elements["friction_force_N"].to_numpy().sum())
    wet_tot = float(elements["wet_length_mm"].to_numpy().sum())
    return {
        "mu": F_tot / FN_tot,
        "mu_dry": params.mu_dry,
        "mu_wet": float((F_visc.sum() + F_bnd.sum()) / (p_local * wet_tot * w_eff_mm * 1e-6))
        if wet_tot > 0
        else 0.0,
        "friction_force_N": F_tot,
        "normal_force_N": FN_tot,
        "dry_force_N": float(elements["dry_force_N"].to_numpy().sum()),
        "viscous_force_N": float(F_visc.sum()),
        "boundary_force_N": float(F_bnd.sum()),
        "dry_area_mm2": float(elements["dry_area_mm2"].sum()),
        "wet_area_mm2": float(elements["wet_area_mm2"].sum()),
        "contact_fraction": float(prep.phi[0]),
        "pressure_local_Pa": p_local,
        "melting_point_C": float(prep.melting_point_C[0]),
        "run_in_force_N": float(F_run_in.sum()),
        "regime": str(_regime(np.array(F_run_in.sum() / F_tot), np.array(F_visc.sum() / F_tot))),
    }


def _block_profile(conditions: Conditions, prep: _Prepared, res: MarchOutput) -> pd.DataFrame:
    """Per-cell profile along the block of :func:`simulate_block` (one condition)."""
    grid = prep.grid
    centres = 0.5 * (grid.nodes_m[1:] + grid.nodes_m[:-1]) * 1e3
    return pd.DataFrame(
        {
            "x_mm": centres,
            "element": grid.element_of_cell,
            "shear_stress_Pa": res.tau[0],
            "dry_fraction": res.dry_fraction[0],
            "film_um": res.film[0] * 1e6,
            "x_end_mm": grid.nodes_m[1:] * 1e3,
            "surface_temperature_C": conditions.temperature_C + res.theta[0],
        }
    )


def element_friction_table(
    geometry: BlockGeometry | str,
    conditions: Conditions | pd.DataFrame | list[Conditions],
    params: DryWetParameters | None = None,
) -> np.ndarray:
    """Friction coefficient of every element for many conditions at once.

    Parameters
    ----------
    geometry, conditions, params
        As for :func:`friction_table`.

    Returns
    -------
    ndarray, shape (n_conditions, n_elements)
        mu of each element (element 0 leads): its friction force over its normal force.
    """
    geometry = as_geometry(geometry)
    params = params or DryWetParameters()
    table = _as_table(conditions)
    prep, _res, agg = _run(geometry, table, params)
    F = agg["F_dry"] + agg["F_visc"] + agg["F_bnd"]
    F_N = prep.p_face[:, None] * geometry.element_lengths[None, :] * geometry.width_mm * 1e-6
    return F / F_N
