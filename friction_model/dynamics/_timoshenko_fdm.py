"""Finite-difference operators of the Timoshenko tread-block element (private helper).

The beam x in [0, d] (clamped root x = 0, tip x = d) is cut into ``n_nodes - 1`` cells of
width h = d / (n_nodes - 1). Deflection r and rotation phi live on the nodes; the strains on
the cell midpoints (a staggered, flux-conservative scheme):

    gamma_e = (r_{e+1} - r_e) / h - (phi_e + phi_{e+1}) / 2      (shear strain r' - phi)
    kappa_e = (phi_{e+1} - phi_e) / h                           (curvature phi')

Shear force Q_e = kappa G A gamma_e and bending moment M_e = E I kappa_e on the midpoints;
node j balances its cell of width h (h / 2 at the tip, lumped mass)::

    rho A h r_j''   = Q_j - Q_{j-1}
    rho I h phi_j'' = M_j - M_{j-1} + (h / 2) (Q_{j-1} + Q_j)

which is the stiffness ``K = h (kappa G A B_g^T B_g + E I B_k^T B_k)`` of the strain operators
``B_g``, ``B_k`` (the linear Timoshenko element with one-point shear quadrature, free of
shear locking). For a static tip load the midpoint moments are exact and the tip deflection
carries the trapezoidal-rule error F d h^2 / (12 E I): second order in h.

The axial-force terms enter as ``N * G @ u`` (Haringx, Engesser or Eq. 5.25/5.26 as
printed; see :func:`assemble`).

Unknowns are ordered ``u = [r_1 .. r_m, phi_1 .. phi_m]`` with m = n_nodes - 1 (the clamped
root node 0 is eliminated, Eq. 5.27), followed by the root rotation phi_0 for an elastic root;
the tip deflection is ``u[m - 1]``, the tip rotation ``u[2 m - 1]``.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

logger = logging.getLogger(__name__)

__all__ = ["BEAM_COLUMN_FORMS", "FdmSystem", "assemble", "foreshortening", "tip_slope"]

#: Up to this many unknowns the operators are applied as dense matrices (faster for small
#: systems, where a sparse mat-vec costs more in call overhead than it saves in flops).
_DENSE_LIMIT = 400


@dataclass(frozen=True, eq=False)
class FdmSystem:
    """Assembled operators of one discretised element.

    Attributes
    ----------
    n_nodes, m : int
        Grid nodes including the root; unknown nodes m = n_nodes - 1.
    n_u : int
        Unknowns: 2 m (clamped root) or 2 m + 1 (elastic root, phi_0 last).
    h : float
        Grid spacing, m.
    x : (n_nodes,) ndarray
        Node positions from the root, m.
    mass : (n_u,) ndarray
        Lumped masses: rho A h (rho A h / 2 at the tip) for r in kg, rho I h (rho I h / 2)
        for phi in kg m^2.
    K : (n_u, n_u) sparse matrix
        Elastic stiffness (symmetric), N/m, N, N m per unit of r and phi.
    G : (n_u, n_u) sparse matrix
        Axial-force operator: ``N * G @ u`` are the nodal forces of the N terms.
    S : (n_u, n_u) sparse matrix
        Tip rise delta = u^T S u / 2 used in the contact penetration (``G`` for the
        conservative forms).
    B_gamma, B_kappa : (m, n_u) sparse matrices
        Midpoint shear strain and curvature from ``u``.
    beam_column : str
        Form of ``G`` (see :func:`assemble`).
    """

    n_nodes: int
    m: int
    n_u: int
    h: float
    x: np.ndarray
    mass: np.ndarray
    K: sp.csr_matrix
    G: sp.csr_matrix
    S: sp.csr_matrix
    B_gamma: sp.csr_matrix
    B_kappa: sp.csr_matrix
    beam_column: str

    @property
    def tip_r(self) -> int:
        """Index of the tip deflection in ``u``."""
        return self.m - 1

    @property
    def tip_phi(self) -> int:
        """Index of the tip rotation in ``u``."""
        return 2 * self.m - 1

    @property
    def has_root_rotation(self) -> bool:
        """True for an elastic root (phi_0 is the last unknown)."""
        return self.n_u == 2 * self.m + 1

    def operator(self, name: str) -> np.ndarray | sp.csr_matrix:
        """``K`` or ``G`` as the faster type for mat-vecs (dense for small systems)."""
        mat = getattr(self, name)
        return mat.toarray() if self.n_u <= _DENSE_LIMIT else mat


def _strain_operators(
    m: int, h: float, n_u: int
) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
    """B_slope, B_gamma and B_kappa of the module docstring, shape (m, n_u) (cells 0 .. m-1).

    ``n_u = 2 m`` for a clamped root, ``2 m + 1`` with the root rotation phi_0 as the last
    unknown (elastic root, :func:`assemble`).
    """
    e = np.arange(m)
    root = n_u == 2 * m + 1
    # cell e joins node e (unknown e - 1, absent for the root) and node e + 1 (unknown e)
    left = e - 1
    has_left = left >= 0
    nl = int(has_left.sum())
    B_s = sp.csr_matrix(
        (
            np.concatenate([np.full(m, 1.0 / h), np.full(nl, -1.0 / h)]),
            (np.concatenate([e, e[has_left]]), np.concatenate([e, left[has_left]])),
        ),
        shape=(m, n_u),
    )
    # phibar_e = (phi_e + phi_{e+1}) / 2, phi_0 = 0 (clamped) or the root unknown
    rows_a = [e, e[has_left]]
    cols_a = [m + e, m + left[has_left]]
    vals_a = [np.full(m, 0.5), np.full(nl, 0.5)]
    rows_k = [e, e[has_left]]
    cols_k = [m + e, m + left[has_left]]
    vals_k = [np.full(m, 1.0 / h), np.full(nl, -1.0 / h)]
    if root:
        rows_a.append(np.array([0]))
        cols_a.append(np.array([2 * m]))
        vals_a.append(np.array([0.5]))
        rows_k.append(np.array([0]))
        cols_k.append(np.array([2 * m]))
        vals_k.append(np.array([-1.0 / h]))
    A_phi = sp.csr_matrix(
        (np.concatenate(vals_a), (np.concatenate(rows_a), np.concatenate(cols_a))),
        shape=(m, n_u),
    )
    B_k = sp.csr_matrix(
        (np.concatenate(vals_k), (np.concatenate(rows_k), np.concatenate(cols_k))),
        shape=(m, n_u),
    )
    return B_s, (B_s - A_phi).tocsr(), B_k


#: Beam-column forms of the axial (normal) force, see :func:`assemble`.
BEAM_COLUMN_FORMS = ("haringx", "engesser", "thesis_literal", "none")


def assemble(
    *,
    height_m: float,
    EI: float,
    kGA: float,
    rhoA: float,
    rhoI: float,
    n_nodes: int,
    beam_column: str = "haringx",
    root_stiffness_Nm_per_rad: float | None = None,
    root_inertia_kg_m2: float = 0.0,
) -> FdmSystem:
    """Assemble mass, stiffness and axial-force operators (Eq. 5.25-5.29 in space).

    Parameters
    ----------
    height_m : float
        Element height d (beam length), m.
    EI, kGA : float
        Bending stiffness E I (N m^2) and shear stiffness kappa G A (N).
    rhoA, rhoI : float
        Mass per length (kg/m) and rotary inertia per length (kg m).
    n_nodes : int
        Nodes including the root, >= 3.
    beam_column : {"haringx", "engesser", "thesis_literal", "none"}
        Form of the axial-force operator ``G`` (see Notes).
    root_stiffness_Nm_per_rad : float, optional
        Rotational stiffness k_theta of an elastic root (the compliance of the block base
        under the sipes), N m/rad; None clamps the root (Eq. 5.27). With it the root
        rotation phi_0 is the last unknown: EI phi'(0) = k_theta phi_0.
    root_inertia_kg_m2 : float
        Rotary inertia lumped on phi_0 in addition to the half cell rho I h / 2, kg m^2.

    Returns
    -------
    FdmSystem

    Notes
    -----
    N > 0 is compressive and keeps its (vertical) direction: a dead load, the ice reaction.
    The conservative forms derive ``N G u`` from the load potential ``-N delta(u)`` with the
    tip rise ``delta = u^T G u / 2``:

    * ``haringx`` (shear force normal to the rotated cross-section): delta = (1/2)
      int (r'^2 - gamma^2) dx, i.e. the strong form ``rho A r_tt = (kGA gamma)' - N phi'``,
      ``rho I phi_tt = EI phi'' + kGA gamma + N gamma`` and the tip balance
      ``kGA gamma(d) - N phi(d) = F_R``. Buckling at N (1 + N / kGA) = pi^2 EI / (4 d^2).
    * ``engesser`` (shear force normal to the deflected axis): delta = (1/2) int r'^2 dx,
      ``rho A r_tt = (kGA gamma)' - N r''``, tip ``kGA gamma(d) - N r'(d) = F_R``.
      Buckling at N / (1 - N / kGA) = pi^2 EI / (4 d^2).
    * ``thesis_literal``: Eq. 5.25/5.26 as printed, ``-N phi'`` (flux form, at the tip
      ``-N phi(d)``, since Eq. 5.29 prescribes the shear force alone) and ``-N gamma`` in the
      moment equation. ``G`` is not symmetric: the load follows the tip face and does work
      on closed paths (not the default; kept to reproduce the thesis).
    * ``none``: G = 0 (Eq. 5.15/5.16).

    ``S`` is the quadratic form of the tip rise used for the contact penetration: ``G`` for
    the conservative forms, the Engesser form (1/2) int r'^2 dx otherwise.
    """
    if beam_column not in BEAM_COLUMN_FORMS:
        raise ValueError(
            f"beam_column must be one of {BEAM_COLUMN_FORMS}, got beam_column={beam_column!r}"
        )
    m = n_nodes - 1
    h = height_m / m
    root = root_stiffness_Nm_per_rad is not None
    n_u = 2 * m + (1 if root else 0)
    B_s, B_g, B_k = _strain_operators(m, h, n_u)
    K = h * (kGA * (B_g.T @ B_g) + EI * (B_k.T @ B_k))
    if root:
        K = K + sp.csr_matrix(
            ([float(root_stiffness_Nm_per_rad)], ([n_u - 1], [n_u - 1])), shape=(n_u, n_u)
        )
    K = K.tocsr()

    mass = np.empty(n_u)
    mass[:m] = rhoA * h
    mass[m : 2 * m] = rhoI * h
    mass[m - 1] *= 0.5
    mass[2 * m - 1] *= 0.5
    if root:
        mass[-1] = 0.5 * rhoI * h + root_inertia_kg_m2

    S_eng = (h * (B_s.T @ B_s)).tocsr()
    if beam_column == "haringx":
        G = (S_eng - h * (B_g.T @ B_g)).tocsr()
    elif beam_column == "engesser":
        G = S_eng.copy()
    elif beam_column == "none":
        G = sp.csr_matrix((n_u, n_u))
    else:
        G = _printed_operator(m, h, n_u, B_s, B_g)
    S = G if beam_column in ("haringx", "engesser") else S_eng
    x = np.linspace(0.0, height_m, n_nodes)
    logger.debug("assembled Timoshenko FDM: n_nodes=%d, h=%.3g m, %s", n_nodes, h, beam_column)
    return FdmSystem(
        n_nodes=n_nodes,
        m=m,
        n_u=n_u,
        h=h,
        x=x,
        mass=mass,
        K=K,
        G=G.tocsr(),
        S=S.tocsr(),
        B_gamma=B_g,
        B_kappa=B_k,
        beam_column=beam_column,
    )


def _printed_operator(
    m: int, h: float, n_u: int, B_s: sp.csr_matrix, B_g: sp.csr_matrix
) -> sp.csr_matrix:
    """Axial-force operator of Eq. 5.25/5.26 as printed (non-symmetric)."""
    A_phi = (B_s - B_g).tocsr()  # phibar_e
    # transverse part: flux H_e = -N phibar_e on cells 0..m-1, the tip "cell" m: -N phi_tip
    tip = sp.csr_matrix(([-1.0], ([0], [2 * m - 1])), shape=(1, n_u))
    flux = sp.vstack([-A_phi, tip]).tocsr()
    # nodal transverse force of unknown i (node i + 1) = flux_{i + 1} - flux_i
    i = np.arange(m)
    D = sp.csr_matrix(
        (np.concatenate([np.ones(m), -np.ones(m)]), (np.concatenate([i, i]), np.r_[i + 1, i])),
        shape=(m, m + 1),
    )
    G_r = D @ flux
    # moment part: -N (h/2)(gamma_{j-1} + gamma_j) = N [h B_g^T B_g u] on the phi rows
    G_phi = (h * (B_g.T @ B_g)).tocsr()[m:, :]
    return sp.vstack([G_r, G_phi]).tocsr()


def foreshortening(r: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Tip rise delta = (1/2) int_0^d r'^2 dx and its gradient with respect to r.

    Parameters
    ----------
    r : (..., m) ndarray
        Deflection of the unknown nodes 1 .. m, m (root r_0 = 0).
    h : float
        Grid spacing, m.

    Returns
    -------
    delta : (...) ndarray
        Vertical rise of the tip towards the root due to the deflection, m (second-order
        shortening of an inextensible axis, the beam analogue of d (1 - cos phi) in Eq. 5.3;
        midpoint rule with the cell slopes).
    grad : (..., m) ndarray
        d delta / d r_j, dimensionless.
    """
    r_full = np.concatenate([np.zeros((*r.shape[:-1], 1)), r], axis=-1)
    s = np.diff(r_full, axis=-1) / h
    delta = 0.5 * h * np.sum(s * s, axis=-1)
    grad = s.copy()
    grad[..., :-1] -= s[..., 1:]
    return delta, grad


def tip_slope(r_full: np.ndarray, h: float) -> np.ndarray:
    """Slope r'(d) of the deflection at the tip, second-order one-sided difference.

    Parameters
    ----------
    r_full : (..., n_nodes) ndarray
        Deflection at all nodes including the root, m.
    h : float
        Grid spacing, m.

    Returns
    -------
    (...) ndarray
        r'(d), dimensionless.
    """
    return (3.0 * r_full[..., -1] - 4.0 * r_full[..., -2] + r_full[..., -3]) / (2.0 * h)
