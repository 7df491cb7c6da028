"""Neo-Hookean large-strain element on the ice (mixed u-p, total Lagrangian, Newton).

Strain energy per reference volume (plane strain, F = I + grad u, J = det F)::

    W(F, p) = mu / 2 (tr F^T F + 1 - 3) - mu ln J + p (J - 1) - p^2 / (2 lambda)

so that P = mu (F - F^-T) + p J F^-T and J - 1 = p / lambda (J = 1 when incompressible).
It is the compressible neo-Hookean solid with the volumetric energy lambda (J - 1)^2 / 2
written in the pressure p; at small strain it is the linear model of
:mod:`friction_model.continuum.linear` (same mu, lambda). The face nodes in contact stay
on the flat ice (exact for a rigid plane), and carry the friction force mu lam in +x,
fixed in direction (the ice is flat). The normal force is applied in load steps; the
indentation is the unknown that makes the reactions add up to it.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from friction_model.continuum._assembly import select
from friction_model.continuum._skfem import require_skfem
from friction_model.continuum.linear import update_contact_set
from friction_model.continuum.model import ElementMesh
from friction_model.continuum.state import ElementState
from tir_common.validate import check_range

__all__ = ["neo_hookean_tangent", "solve_neo_hookean"]


def _kinematics(w):
    """F, F^-1, F^-T and J at the quadrature points of the current displacement."""
    from skfem.helpers import det, grad, identity, inv, transpose

    F = identity(w["u0"]) + grad(w["u0"])
    Fi = inv(F)
    return F, Fi, transpose(Fi), det(F)


def neo_hookean_tangent(em: ElementMesh, z: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """Tangent stiffness and internal force of the mixed neo-Hookean element at ``z``.

    Parameters
    ----------
    em : ElementMesh
    z : ndarray
        Displacement (m) then pressure (Pa) dofs.

    Returns
    -------
    K : scipy.sparse.csr_matrix
        d r / d z, per unit width; symmetric (the energy's Hessian).
    r : ndarray
        Internal force (displacement rows) and volume constraint (pressure rows).
    """
    skfem = require_skfem()
    from skfem.helpers import ddot, grad, mul, trace, transpose

    mu = em.spec.shear_modulus_Pa
    inv_lam = em.spec.inverse_lame_Pa
    fields = {
        "u0": em.basis_u.interpolate(z[: em.n_u]),
        "p0": em.basis_p.interpolate(z[em.n_u :]),
    }

    @skfem.LinearForm
    def r_u(v, w):
        F, _, FiT, J = _kinematics(w)
        P = mu * (F - FiT) + w["p0"] * J * FiT
        return ddot(P, grad(v))

    @skfem.LinearForm
    def r_p(q, w):
        _, _, _, J = _kinematics(w)
        return (J - 1.0 - inv_lam * w["p0"]) * q

    @skfem.BilinearForm
    def k_uu(du, v, w):
        _, Fi, FiT, J = _kinematics(w)
        G = grad(du)
        FGF = mul(FiT, mul(transpose(G), FiT))
        dP = mu * (G + FGF) + w["p0"] * J * (trace(mul(Fi, G)) * FiT - FGF)
        return ddot(dP, grad(v))

    @skfem.BilinearForm
    def k_pu(du, q, w):
        _, Fi, _, J = _kinematics(w)
        return J * trace(mul(Fi, grad(du))) * q

    @skfem.BilinearForm
    def k_pp(p, q, _):
        return -inv_lam * p * q

    Kuu = k_uu.assemble(em.basis_u, **fields)
    Kpu = k_pu.assemble(em.basis_u, em.basis_p, **fields)
    Kpp = k_pp.assemble(em.basis_p)
    K = sp.bmat([[Kuu, Kpu.T], [Kpu, Kpp]], format="csr")
    r = np.concatenate([r_u.assemble(em.basis_u, **fields), r_p.assemble(em.basis_p, **fields)])
    return K, r


def _newton(em, z, lam, delta, active, mu, force_per_m, tol, max_iter):
    """Newton iterations for a fixed contact set; returns (z, lam, delta, converged)."""
    n = z.size
    free = np.setdiff1d(np.arange(n), em.fixed)
    is_u = free < em.n_u
    By = select(em.face_y[active], n)
    Bx = select(em.face_x[active], n)
    m = By.shape[0]
    ones = sp.csr_matrix(np.ones((m, 1)))
    scale = force_per_m / em.spec.length_m  # a pressure: makes the residual dimensionless
    for _ in range(max_iter):
        K, r = neo_hookean_tangent(em, z)
        G = (By - mu * Bx).T
        R1 = (r + G @ lam[active])[free]
        R2 = By @ z + delta
        R3 = np.array([lam[active].sum() - force_per_m])
        J = sp.bmat(
            [[K[free][:, free], G[free], None], [By[:, free], None, ones], [None, ones.T, None]],
            format="csc",
        )
        step = spla.spsolve(J, -np.concatenate([R1, R2, R3]))
        z[free] += step[: free.size]
        lam[active] += step[free.size : free.size + m]
        delta += step[-1]
        du = np.abs(step[: free.size][is_u]).max()
        if du < tol * em.spec.length_m and np.abs(R1[is_u]).max() < tol * scale * em.spec.length_m:
            return z, lam, delta, True
    return z, lam, delta, False


def solve_neo_hookean(
    em: ElementMesh,
    *,
    normal_force_N: float,
    mu: float = 0.0,
    n_steps: int = 8,
    tol: float = 1e-9,
    max_iter: int = 30,
) -> ElementState:
    """Large-strain static solution of the element pressed on the ice and dragged.

    Parameters
    ----------
    em : ElementMesh
    normal_force_N : float
        N on the whole width, N, > 0.
    mu : float
        Friction coefficient of the sliding face; traction mu p in +x.
    n_steps : int
        Load steps from 0 to N (friction grows with the reactions).
    tol : float
        Newton stops when the displacement update is below ``tol * l``.
    max_iter : int
        Newton iterations per step and contact set.

    Returns
    -------
    ElementState
    """
    mu = check_range("mu", mu, 0.0, 5.0)
    N = check_range("normal_force_N", normal_force_N, 1e-12, 1e9, unit="N")
    n = em.n_u + em.n_p
    z = np.zeros(n)
    lam = np.zeros(em.face_x.size)
    active = np.ones(em.face_x.size, dtype=bool)
    delta = 0.0
    for k in range(1, n_steps + 1):
        force = N * k / n_steps / em.spec.width_m
        for _ in range(50):
            state = (z.copy(), lam.copy(), delta)
            z, lam, delta, ok = _newton(em, z, lam, delta, active, mu, force, tol, max_iter)
            if not ok:
                raise RuntimeError(
                    f"Newton did not converge at N = {force * em.spec.width_m:.3g} N "
                    f"(step {k} of {n_steps}); use more load steps"
                )
            penetrates = ~active & (z[em.face_y] + delta > 1e-9 * em.spec.length_m)
            new = update_contact_set(active, lam, penetrates)
            if np.array_equal(new, active):
                break
            active = new
            z, lam, delta = state
            lam[~active] = 0.0
        else:
            raise RuntimeError("the contact set did not settle")
    return ElementState(em, z[: em.n_u], z[em.n_u :], lam, active, delta, N, mu, "neo-hookean")
