"""Numerical core of the dry/wet model: a march along the block with exact heat conduction.

The ice is a semi-infinite solid; the block moves over it at ``v``, so a point of the ice
surface sees the block's cells one after the other, ``dt = dx / v`` each. With a
piecewise-constant heat flux ``q_k`` into the ice over cell ``k = [X_k, X_k+1)`` the surface
temperature rise at node ``X_m`` is exactly (Duhamel superposition of the constant-flux
solution that Eq. 4.6 is built on)::

    theta_m = 2 / sqrt(pi lambda rho c v) * sum_k q_k (sqrt(X_m - X_k) - sqrt(X_m - X_k+1))

Written in the position ``X`` the kernel does not depend on ``v``, so all conditions share
one kernel matrix and are marched together (vectorised over conditions).

Per cell the surface is either below the melting point (dry contact; flux = all frictional
heat ``K mu_dry p v``) or held at the melting point (the flux into the ice is what keeps it
there; the rest of the heat melts ice). At the melting point the contact is dry until the
film reaches the critical thickness ``h_c``, then wet with shear stress
``tau_b + eta v / h`` (Eq. 4.3 plus a boundary part). The film grows or refreezes by the
heat balance ``rho_w L dh/dt = K tau v - q_ice`` (Evans / Oksanen, section 2.6); when the
heat cannot hold the film at ``h_c`` the cell becomes a mix of dry patches and wet film whose
heat just balances conduction (Evans' conduction-limited friction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__: list[str] = []


@dataclass(frozen=True)
class Grid:
    """Cells along the block (elements and sipe gaps)."""

    nodes_m: np.ndarray  # (N+1,)
    element_of_cell: np.ndarray  # (N,) element index, -1 in a sipe
    kernel: np.ndarray  # (N+1, N) W[m, k] in sqrt(m)
    element_starts: np.ndarray  # first cell of each element
    element_ends: np.ndarray  # one past the last cell of each element
    element_front_m: np.ndarray  # node position of each element's leading edge

    @property
    def dx(self) -> np.ndarray:
        return np.diff(self.nodes_m)


def build_grid(
    element_lengths_m: np.ndarray,
    sipe_width_m: float,
    *,
    n_cells: int,
    grading: float,
    n_gap_cells: int = 4,
) -> Grid:
    """Nodes graded towards each element's leading edge (``x = l (j/n)^grading``)."""
    nodes = [0.0]
    owner: list[int] = []
    starts, ends, fronts = [], [], []
    x0 = 0.0
    frac = (np.arange(1, n_cells + 1) / n_cells) ** grading
    for i, length in enumerate(element_lengths_m):
        if i > 0 and sipe_width_m > 0:
            gap = x0 + sipe_width_m * np.arange(1, n_gap_cells + 1) / n_gap_cells
            nodes.extend(gap.tolist())
            owner.extend([-1] * n_gap_cells)
            x0 = nodes[-1]
        starts.append(len(owner))
        fronts.append(x0)
        nodes.extend((x0 + length * frac).tolist())
        owner.extend([i] * n_cells)
        ends.append(len(owner))
        x0 = nodes[-1]
    X = np.asarray(nodes)
    diff = X[:, None] - X[None, :]  # X_m - X_k
    root = np.sqrt(np.clip(diff, 0.0, None))
    kernel = root[:, :-1] - root[:, 1:]
    kernel = np.tril(kernel, k=-1)  # only cells k < m contribute to node m
    return Grid(
        nodes_m=X,
        element_of_cell=np.asarray(owner),
        kernel=kernel,
        element_starts=np.asarray(starts),
        element_ends=np.asarray(ends),
        element_front_m=np.asarray(fronts),
    )


@dataclass
class MarchInput:
    """Per-condition arrays, shape (n_c,), SI units."""

    velocity: np.ndarray
    pressure_local: np.ndarray  # contact pressure on the real contact area, Pa
    delta_T: np.ndarray  # melting point minus ice temperature, K
    h0: np.ndarray  # bound water layer left behind the wiping edge, m
    mu_dry: float
    heat_fraction: float
    boundary_shear: float
    critical_film: float
    viscous_strength: float
    preheating: float
    viscosity: float
    melt_energy: float  # rho_water * latent heat, J/m^3
    conduction_factor: float  # 2 / sqrt(pi lambda rho c)


@dataclass
class MarchOutput:
    """Per-condition, per-cell results, shape (n_c, N)."""

    tau: np.ndarray  # mean shear stress over the cell, Pa
    tau_dry: np.ndarray  # part of tau from dry contact, Pa
    tau_viscous: np.ndarray  # part from viscous shear, Pa
    tau_boundary: np.ndarray  # part from boundary shear, Pa
    dry_fraction: np.ndarray  # fraction of the cell in dry contact
    film: np.ndarray  # film thickness at the end of the cell, m
    flux: np.ndarray  # heat flux into the ice, W/m^2
    theta: np.ndarray  # surface temperature rise at the end of the cell, K
    run_in_part: np.ndarray  # contiguous dry fraction from the cell start (run-in)
    heating_length: np.ndarray  # (n_c, n_elements) where the surface first melts, m
    entry_theta: np.ndarray  # (n_c, n_elements) surface temperature rise at entry, K


def _crossing_fraction(
    q_hist: np.ndarray,
    X: np.ndarray,
    k: int,
    q_dry: np.ndarray,
    target: np.ndarray,
    scale: np.ndarray,
) -> np.ndarray:
    """Fraction f of cell k at which history + new dry flux reach ``target`` (bisection)."""
    dx = X[k + 1] - X[k]
    lo = np.zeros(len(q_dry))
    hi = np.ones(len(q_dry))
    xk = X[: k + 1]
    for _ in range(40):
        f = 0.5 * (lo + hi)
        xm = X[k] + f * dx
        d = xm[:, None] - xk[None, :]
        root = np.sqrt(np.clip(d, 0.0, None))
        w = root[:, :-1] - root[:, 1:]
        theta = scale * (np.einsum("ck,ck->c", q_hist, w) + q_dry * np.sqrt(f * dx))
        above = theta >= target
        hi = np.where(above, f, hi)
        lo = np.where(above, lo, f)
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class _Fixed:
    """Per-condition quantities fixed for the whole march, shape (n_c,)."""

    v: np.ndarray  # sliding velocity, m/s
    dT: np.ndarray  # melting point minus ice temperature, K
    scale: np.ndarray  # K per (W/m^2 * sqrt(m))
    tau_dry_full: np.ndarray  # dry shear stress mu_dry p, Pa
    q_dry: np.ndarray  # frictional heat flux of dry contact K mu_dry p v, W/m^2
    tol: np.ndarray  # margin below the melting point at an element's entry, K

    @classmethod
    def of(cls, inp: MarchInput) -> _Fixed:
        """The fixed quantities of ``inp``."""
        v = inp.velocity
        tau_dry_full = inp.mu_dry * inp.pressure_local
        return cls(
            v=v,
            dT=inp.delta_T,
            scale=inp.conduction_factor / np.sqrt(v),
            tau_dry_full=tau_dry_full,
            q_dry=inp.heat_fraction * tau_dry_full * v,
            tol=1e-12 * np.maximum(inp.delta_T, 1e-9),
        )


@dataclass
class _Melting:
    """The part of one cell at the melting point, per condition (n_c,)."""

    at_melt: np.ndarray  # bool: some of the cell is at the melting point
    rem: np.ndarray  # fraction of the cell at the melting point
    g: np.ndarray  # fraction of that part in dry melting contact (run-in)
    dry_in_rem: np.ndarray  # fraction of that part in dry contact
    lost: np.ndarray  # bool: the cell cannot stay at the melting point, dry again
    h: np.ndarray  # film thickness at the end of the cell, m
    tau_w: np.ndarray  # wet shear stress, Pa
    q_cell: np.ndarray  # mean heat flux into the ice over the cell, W/m^2


def _empty_output(n_c: int, n_cells: int, n_elements: int, flux: np.ndarray) -> MarchOutput:
    """A :class:`MarchOutput` of zeros (heating lengths NaN: not yet melted)."""
    return MarchOutput(
        tau=np.zeros((n_c, n_cells)),
        tau_dry=np.zeros((n_c, n_cells)),
        tau_viscous=np.zeros((n_c, n_cells)),
        tau_boundary=np.zeros((n_c, n_cells)),
        dry_fraction=np.zeros((n_c, n_cells)),
        film=np.zeros((n_c, n_cells)),
        flux=flux,
        theta=np.zeros((n_c, n_cells)),
        run_in_part=np.zeros((n_c, n_cells)),
        heating_length=np.full((n_c, n_elements), np.nan),
        entry_theta=np.zeros((n_c, n_elements)),
    )


def _enter_element(
    grid: Grid,
    inp: MarchInput,
    fx: _Fixed,
    k: int,
    owner: int,
    q: np.ndarray,
    q_eff: np.ndarray,
    out: MarchOutput,
) -> tuple[np.ndarray, np.ndarray]:
    """Start element ``owner`` at cell ``k``; return which conditions are below melting, and h.

    The edge wipes the melt water down to the bound layer h0, and the ice carries the
    (scaled by ``preheating``) heat history of everything that slid over it.
    """
    q_eff[:, :k] = inp.preheating * q[:, :k]
    theta_start = fx.scale * (q_eff[:, :k] @ grid.kernel[k, :k]) if k > 0 else np.zeros(len(fx.v))
    out.entry_theta[:, owner] = theta_start
    below = theta_start < fx.dT - fx.tol
    out.heating_length[~below, owner] = 0.0
    return below, inp.h0.copy()


def _dry_heating(
    grid: Grid,
    fx: _Fixed,
    k: int,
    owner: int,
    q_eff: np.ndarray,
    below: np.ndarray,
    theta_end: np.ndarray,
    dx_k: float,
    out: MarchOutput,
) -> tuple[np.ndarray, np.ndarray]:
    """Fraction of cell ``k`` below the melting point, and where all of it stays below.

    ``theta_end`` is the temperature rise at the cell's end were the whole cell dry. Where the
    surface reaches the melting point inside the cell, the crossing is found by bisection
    (or in closed form in the first cell) and the element's heating length recorded.
    """
    X = grid.nodes_m
    f_below = np.zeros(len(fx.v))
    stays_below = below & (theta_end < fx.dT)
    f_below[stays_below] = 1.0
    crossing = below & ~stays_below
    if np.any(crossing):
        idx = np.flatnonzero(crossing)
        f = (
            _crossing_fraction(q_eff[idx, :k], X, k, fx.q_dry[idx], fx.dT[idx], fx.scale[idx])
            if k > 0
            else (((fx.dT[idx] - 0.0) / (fx.scale[idx] * fx.q_dry[idx])) ** 2 / dx_k)
        )
        f = np.clip(f, 0.0, 1.0)
        f_below[idx] = f
        first = np.isnan(out.heating_length[idx, owner])
        x_local = X[k] - grid.element_front_m[owner]
        out.heating_length[idx[first], owner] = x_local + f[first] * dx_k
    return f_below, stays_below


def _melting_part(
    inp: MarchInput,
    fx: _Fixed,
    h: np.ndarray,
    f_below: np.ndarray,
    stays_below: np.ndarray,
    hist: np.ndarray,
    w_last: np.ndarray,
    dt: np.ndarray,
) -> _Melting:
    """The part of a cell at the melting point: dry melting up to ``h_c``, then a wet film."""
    v = fx.v
    at_melt = ~stays_below
    q_hold = np.clip((fx.dT - hist) / w_last, 0.0, None)
    rem = 1.0 - f_below  # fraction of the cell at the melting point
    dt_rem = rem * dt
    # flux into the ice during the part at the melting point: the cell's mean flux is
    # q_hold, of which the part below melting already took q_dry for f_below of the time
    has_rem = rem > 1e-12
    q_rem = np.where(
        has_rem,
        np.divide(q_hold - f_below * fx.q_dry, rem, out=q_hold.copy(), where=has_rem),
        q_hold,
    )
    q_rem = np.clip(q_rem, 0.0, None)
    tau_w = inp.boundary_shear + inp.viscous_strength * inp.viscosity * v / np.maximum(
        h, inp.critical_film
    )
    tau_w = np.minimum(tau_w, fx.tau_dry_full)
    q_cell = np.where(stays_below, fx.q_dry, q_hold)
    a = inp.melt_energy

    # phase 1, dry and melting (film thinner than critical): the heat surplus over the
    # conduction loss melts ice until the film reaches h_c, at the sub-cell time t_need
    melting = at_melt & (h < inp.critical_film)
    surplus = fx.q_dry - q_rem
    lost = melting & (surplus < 0)  # cannot stay at the melting point: dry again
    t_need = (inp.critical_film - h) * a / np.maximum(surplus, 1e-300)
    t_need = np.clip(t_need, 0.0, dt_rem)
    g = np.where(melting, t_need / np.maximum(dt_rem, 1e-300), 0.0)
    g = np.where(lost, 1.0, g)
    grows = melting & ~lost
    h = np.where(grows, np.minimum(h + surplus * g * dt_rem / a, inp.critical_film), h)
    h = np.where(grows & (g < 1.0), inp.critical_film, h)
    q_cell = np.where(lost, fx.q_dry, q_cell)
    cell = _Melting(at_melt, rem, g, g.copy(), lost, h, tau_w, q_cell)

    # phase 2, wet for the rest of the cell
    wet = at_melt & ~lost & (g < 1.0)
    if np.any(wet):
        _wet_film(inp, fx, cell, wet, (1.0 - g) * dt_rem, q_rem)
    return cell


def _wet_film(
    inp: MarchInput,
    fx: _Fixed,
    cell: _Melting,
    wet: np.ndarray,
    dt_w: np.ndarray,
    q_rem: np.ndarray,
) -> None:
    """Implicit film update of the wet part of a cell (``dt_w``), updating ``cell`` in place.

    ``rho L (h' - h) = (K (tau_b + s eta v / h') v - q) dt``; where the film falls below
    ``h_c`` it collapses (:func:`_film_collapse`).
    """
    v, h, a, K = fx.v, cell.h, inp.melt_energy, inp.heat_fraction
    b = a * h + (K * inp.boundary_shear * v - q_rem) * dt_w
    c = K * inp.viscous_strength * inp.viscosity * v**2 * dt_w
    disc = np.sqrt(b * b + 4.0 * a * c)
    h_new = np.where(c > 0, (b + disc) / (2.0 * a), b / a)
    # where the wet stress would exceed mu_dry p it is capped there, and so is its
    # heat: then the balance is linear in h'
    capped = (
        inp.boundary_shear + inp.viscous_strength * inp.viscosity * v / np.maximum(h_new, 1e-300)
        > fx.tau_dry_full
    )
    h_new = np.where(capped, h + (fx.q_dry - q_rem) * dt_w / a, h_new)
    keeps = wet & (h_new >= inp.critical_film)
    h = np.where(keeps, h_new, h)
    cell.h = h
    cell.tau_w = np.where(
        keeps,
        np.minimum(
            inp.boundary_shear + inp.viscous_strength * inp.viscosity * v / np.maximum(h, 1e-12),
            fx.tau_dry_full,
        ),
        cell.tau_w,
    )
    collapse = wet & ~keeps
    if np.any(collapse):
        _film_collapse(inp, fx, cell, collapse, q_rem)


def _film_collapse(
    inp: MarchInput, fx: _Fixed, cell: _Melting, collapse: np.ndarray, q_rem: np.ndarray
) -> None:
    """Mix of dry patches and wet film at ``h_c`` whose heat balances the conduction loss.

    Conduction-limited friction (Evans); updates ``cell`` in place.
    """
    v, g = fx.v, cell.g
    tau_c = np.minimum(
        inp.boundary_shear + inp.viscous_strength * inp.viscosity * v / inp.critical_film,
        fx.tau_dry_full,
    )
    need = q_rem / (inp.heat_fraction * v)
    span = np.maximum(fx.tau_dry_full - tau_c, 1e-30)
    phi = np.clip((need - tau_c) / span, 0.0, 1.0)
    lost2 = collapse & (need > fx.tau_dry_full)
    cell.dry_in_rem = np.where(collapse, g + (1.0 - g) * phi, cell.dry_in_rem)
    cell.h = np.where(collapse, inp.critical_film, cell.h)
    cell.tau_w = np.where(collapse, tau_c, cell.tau_w)
    cell.q_cell = np.where(lost2, fx.q_dry, cell.q_cell)
    cell.lost = cell.lost | lost2


def _store_cell(
    out: MarchOutput, k: int, inp: MarchInput, fx: _Fixed, f_below: np.ndarray, cell: _Melting
) -> None:
    """Shear stress parts, dry fraction, film and run-in part of cell ``k``."""
    dry_frac = f_below + cell.rem * cell.dry_in_rem
    # contiguous dry part from the cell start: below melting, then dry melting (g)
    out.run_in_part[:, k] = np.where(cell.lost, 1.0, f_below + cell.rem * cell.g)
    wet_frac = 1.0 - dry_frac
    visc = np.minimum(
        inp.viscous_strength * inp.viscosity * fx.v / np.maximum(cell.h, 1e-12),
        np.maximum(fx.tau_dry_full - inp.boundary_shear, 0.0),
    )
    bnd = np.minimum(inp.boundary_shear, fx.tau_dry_full)
    # the wet stress tau_w = bnd + visc (both capped so that tau_w <= mu_dry p)
    visc_share = np.where(bnd + visc > 0, visc / np.maximum(bnd + visc, 1e-30), 0.0)
    out.tau_dry[:, k] = dry_frac * fx.tau_dry_full
    out.tau_viscous[:, k] = wet_frac * cell.tau_w * visc_share
    out.tau_boundary[:, k] = wet_frac * cell.tau_w * (1.0 - visc_share)
    out.tau[:, k] = out.tau_dry[:, k] + out.tau_viscous[:, k] + out.tau_boundary[:, k]
    out.dry_fraction[:, k] = dry_frac
    out.film[:, k] = np.where(cell.at_melt, cell.h, 0.0)


def march(grid: Grid, inp: MarchInput) -> MarchOutput:
    """March all conditions along the block; see the module docstring for the physics.

    Per cell: a new element starts from the wiped bound layer and the preheated ice
    (:func:`_enter_element`); a sipe cell carries no flux; a contact cell is dry below the
    melting point (:func:`_dry_heating`) and then at the melting point
    (:func:`_melting_part`), and its results are stored (:func:`_store_cell`).
    """
    fx = _Fixed.of(inp)
    n_c = len(fx.v)
    N = len(grid.element_of_cell)
    W = grid.kernel
    dx = grid.dx
    q = np.zeros((n_c, N))
    q_eff = np.zeros((n_c, N))
    out = _empty_output(n_c, N, len(grid.element_starts), q)
    element = -2
    below = np.ones(n_c, dtype=bool)
    h = inp.h0.copy()
    for k in range(N):
        owner = grid.element_of_cell[k]
        if owner != element and owner >= 0:
            element = owner
            below, h = _enter_element(grid, inp, fx, k, owner, q, q_eff, out)
        hist = fx.scale * (q_eff[:, :k] @ W[k + 1, :k])
        if owner < 0:  # sipe: no contact, no flux; the ice cools
            out.theta[:, k] = hist
            below = np.ones(n_c, dtype=bool)
            continue
        w_last = fx.scale * W[k + 1, k]
        f_below, stays_below = _dry_heating(
            grid, fx, k, owner, q_eff, below, hist + w_last * fx.q_dry, dx[k], out
        )
        cell = _melting_part(inp, fx, h, f_below, stays_below, hist, w_last, dx[k] / fx.v)
        h = cell.h
        _store_cell(out, k, inp, fx, f_below, cell)
        q[:, k] = cell.q_cell
        q_eff[:, k] = cell.q_cell
        out.theta[:, k] = hist + w_last * cell.q_cell
        below = stays_below | cell.lost
    return out
