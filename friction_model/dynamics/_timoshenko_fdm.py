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

The axial-force terms of Eq. 5.25/5.26 enter as ``N * G @ u`` (see :func:`assemble`).

Unknowns are ordered ``u = [r_1 .. r_m, phi_1 .. phi_m]`` with m = n_nodes - 1 (the clamped
root node 0 is eliminated, Eq. 5.27); the tip deflection is ``u[m - 1]``, the tip rotation
``u[2 m - 1]``.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

logger = logging.getLogger(__name__)

__all__ = ["FdmSystem", "assemble", "foreshortening", "tip_slope"]

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
    h : float
        Grid spacing, m.
    x : (n_nodes,) ndarray
        Node positions from the root, m.
    mass : (2 m,) ndarray
        Lumped masses: rho A h (rho A h / 2 at the tip) for r in kg, rho I h (rho I h / 2)
        for phi in kg m^2.
    K : (2 m, 2 m) sparse matrix
        Elastic stiffness (symmetric), N/m, N, N m per unit of r and phi.
    G : (2 m, 2 m) sparse matrix
        Axial-force operator: ``N * G @ u`` are the nodal forces of the N terms.
    B_gamma, B_kappa : (m, 2 m) sparse matrices
        Midpoint shear strain and curvature from ``u``.
    """

    n_nodes: int
    m: int
    h: float
    x: np.ndarray
    mass: np.ndarray
    K: sp.csr_matrix
    G: sp.csr_matrix
    B_gamma: sp.csr_matrix
    B_kappa: sp.csr_matrix

    @property
    def tip_r(self) -> int:
        """Index of the tip deflection in ``u``."""
        return self.m - 1

    @property
    def tip_phi(self) -> int:
        """Index of the tip rotation in ``u``."""
        return 2 * self.m - 1

    def operator(self, name: str) -> np.ndarray | sp.csr_matrix:
        """``K`` or ``G`` as the faster type for mat-vecs (dense for small systems)."""
        mat = getattr(self, name)
        return mat.toarray() if 2 * self.m <= _DENSE_LIMIT else mat


def _strain_operators(m: int, h: float) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """B_gamma and B_kappa of the module docstring, shape (m, 2 m) (cells 0 .. m - 1)."""
    e = np.arange(m)
    # cell e joins node e (unknown e - 1, absent for the root) and node e + 1 (unknown e)
    left = e - 1
    has_left = left >= 0
    rows_g = [e, e[has_left], e, e[has_left]]
    cols_g = [e, left[has_left], m + e, m + left[has_left]]
    vals_g = [
        np.full(m, 1.0 / h),
        np.full(int(has_left.sum()), -1.0 / h),
        np.full(m, -0.5),
        np.full(int(has_left.sum()), -0.5),
    ]
    B_g = sp.csr_matrix(
        (np.concatenate(vals_g), (np.concatenate(rows_g), np.concatenate(cols_g))),
        shape=(m, 2 * m),
    )
    rows_k = [e, e[has_left]]
    cols_k = [m + e, m + left[has_left]]
    vals_k = [np.full(m, 1.0 / h), np.full(int(has_left.sum()), -1.0 / h)]
    B_k = sp.csr_matrix(
        (np.concatenate(vals_k), (np.concatenate(rows_k), np.concatenate(cols_k))),
        shape=(m, 2 * m),
    )
    return B_g, B_k


def assemble(
    *,
    height_m: float,
    EI: float,
    kGA: float,
    rhoA: float,
    rhoI: float,
    n_nodes: int,
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
        Nodes including the clamped root, >= 3.

    Returns
    -------
    FdmSystem

    Notes
    -----
    Axial force (Eq. 5.25/5.26, written with gamma = r' - phi, N > 0 compressive): the
    transverse equation gets ``- N phi'``, discretised in flux form as the cell flux
    ``-N (phi_e + phi_{e+1}) / 2`` (at the tip ``-N phi(d)``, since Eq. 5.29 prescribes the
    shear force alone), and the moment equation gets ``- N gamma``, integrated like the
    shear term: ``-N (h / 2) (gamma_{j-1} + gamma_j)``.
    """
    m = n_nodes - 1
    h = height_m / m
    B_g, B_k = _strain_operators(m, h)
    K = (h * (kGA * (B_g.T @ B_g) + EI * (B_k.T @ B_k))).tocsr()

    mass = np.empty(2 * m)
    mass[:m] = rhoA * h
    mass[m:] = rhoI * h
    mass[m - 1] *= 0.5
    mass[2 * m - 1] *= 0.5

    # -- axial force: transverse part, flux H_e = -N phibar_e (tip flux -N phi_tip) ----------
    # flux matrix F (m, 2m): rows = cells 0..m-1 plus the tip "cell" m -> shape (m + 1, 2m)
    e = np.arange(m)
    left = e - 1
    has_left = left >= 0
    rows = np.concatenate([e, e[has_left], [m]])
    cols = np.concatenate([m + e, m + left[has_left], [2 * m - 1]])
    vals = np.concatenate([np.full(m, -0.5), np.full(int(has_left.sum()), -0.5), [-1.0]])
    flux = sp.csr_matrix((vals, (rows, cols)), shape=(m + 1, 2 * m))
    # nodal transverse force of node j (unknown j - 1 .. ) = flux_{right} - flux_{left}:
    # unknown i (node i + 1) has left cell i and right cell i + 1 (the tip flux for i = m - 1)
    i = np.arange(m)
    D = sp.csr_matrix(
        (np.concatenate([np.ones(m), -np.ones(m)]), (np.concatenate([i, i]), np.r_[i + 1, i])),
        shape=(m, m + 1),
    )
    G_r = D @ flux
    # moment part: -N (h/2)(gamma_{j-1} + gamma_j) = N [h B_g^T B_g u] on the phi rows
    G_phi = (h * (B_g.T @ B_g)).tocsr()[m:, :]
    G = sp.vstack([G_r, G_phi]).tocsr()
    x = np.linspace(0.0, height_m, n_nodes)
    logger.debug("assembled Timoshenko FDM: n_nodes=%d, h=%.3g m", n_nodes, h)
    return FdmSystem(
        n_nodes=n_nodes,
        m=m,
        h=h,
        x=x,
        mass=mass,
        K=K,
        G=G,
        B_gamma=B_g,
        B_kappa=B_k,
    )


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
