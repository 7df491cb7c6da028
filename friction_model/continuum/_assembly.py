"""Matrices of the mixed u-p plane-strain element: linear elasticity and the mass."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from friction_model.continuum._skfem import require_skfem
from friction_model.continuum.model import ElementMesh

__all__ = ["linear_stiffness", "mass_matrix"]


def linear_stiffness(em: ElementMesh) -> sp.csr_matrix:
    """Mixed u-p stiffness of plane-strain linear elasticity, per unit width (N/m).

    With sigma = 2 mu eps(u) + p I and p = lambda div u enforced weakly, the symmetric
    saddle matrix is ``[[A, B^T], [B, -C / lambda]]``: ``A = int 2 mu eps(u) : eps(v)``,
    ``B = int q div u``, ``C = int p q``. Taylor-Hood P2-P1 satisfies the inf-sup
    condition, so nothing locks as nu -> 0.5 (1 / lambda = 0 is allowed).

    Parameters
    ----------
    em : ElementMesh

    Returns
    -------
    scipy.sparse.csr_matrix
        (n_u + n_p) square; the displacement dofs first.
    """
    skfem = require_skfem()
    from skfem.helpers import ddot, div, sym_grad

    mu = em.spec.shear_modulus_Pa
    inv_lam = em.spec.inverse_lame_Pa

    @skfem.BilinearForm
    def a(u, v, _):
        return 2.0 * mu * ddot(sym_grad(u), sym_grad(v))

    @skfem.BilinearForm
    def b(u, q, _):
        return div(u) * q

    @skfem.BilinearForm
    def c(p, q, _):
        return p * q

    A = a.assemble(em.basis_u)
    B = b.assemble(em.basis_u, em.basis_p)
    C = c.assemble(em.basis_p)
    return sp.bmat([[A, B.T], [B, -inv_lam * C]], format="csr")


def mass_matrix(em: ElementMesh) -> sp.csr_matrix:
    """Consistent mass of the displacement field, per unit width (kg/m), padded with zeros.

    Returns
    -------
    scipy.sparse.csr_matrix
        (n_u + n_p) square: the pressure carries no mass.
    """
    skfem = require_skfem()
    from skfem.helpers import dot

    rho = em.spec.density_kg_m3

    @skfem.BilinearForm
    def m(u, v, _):
        return rho * dot(u, v)

    M = m.assemble(em.basis_u)
    Z = sp.csr_matrix((em.n_p, em.n_p))
    return sp.bmat([[M, None], [None, Z]], format="csr")


def select(rows: np.ndarray, n: int) -> sp.csr_matrix:
    """The 0/1 matrix picking the dofs ``rows`` out of ``n``."""
    rows = np.asarray(rows, dtype=int)
    return sp.csr_matrix((np.ones(rows.size), (np.arange(rows.size), rows)), shape=(rows.size, n))
