"""Linear plane-strain element on the ice: frictional contact by an active set.

The face nodes in contact follow the ice surface (non-penetration, enforced exactly by
Lagrange multipliers, which are the nodal normal reactions) and carry the tangential
traction mu p of a face sliding in +x. For a fixed contact set the problem is linear
and homogeneous in the indentation, so it is solved once for a unit indentation and
scaled to the normal force; the contact set is found by releasing nodes that pull and
adding nodes that penetrate.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from friction_model.continuum._assembly import linear_stiffness, select
from friction_model.continuum.model import ElementMesh
from friction_model.continuum.state import ElementState
from tir_common.validate import check_number, check_range

__all__ = ["FACE_CONDITIONS", "contact_solve", "solve_linear", "update_contact_set"]

#: Face conditions: on the ice (frictional contact) or free (applied uniform tractions).
FACE_CONDITIONS = ("ice", "free")


def update_contact_set(active: np.ndarray, lam: np.ndarray, penetrates: np.ndarray) -> np.ndarray:
    """Release the end node of the contact that pulls hardest, or else add penetrating nodes.

    Only a node at an end of a contact run (next to a node off the ice, or a face corner)
    may be released: a midside node of P2 carries a negative consistent nodal force next to
    a pressure singularity (at the leading corner) even when the pressure is positive, and
    releasing it would split the contact and cycle. One node at a time keeps the set from
    cycling while the lift-off grows from the rear edge.
    """
    out = active.copy()
    padded = np.concatenate([[False], active, [False]])
    at_end = active & ~(padded[:-2] & padded[2:])
    pulls = at_end & (lam < 0)
    if pulls.any():
        out[np.flatnonzero(pulls)[np.argmin(lam[pulls])]] = False
    else:
        out |= penetrates
    return out


def contact_solve(
    K: sp.spmatrix, em: ElementMesh, active: np.ndarray, mu: float, rhs: np.ndarray,
    gap: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Solve ``K z + (B_y - mu B_x)^T lam = rhs``, ``B_y z = -gap`` on the free dofs.

    B_y and B_x pick the y and x displacement of the ``active`` face nodes; lam are their
    normal reactions (compressive positive), mu lam the friction forces in +x.

    Returns
    -------
    z : ndarray
        All dofs (displacement then pressure), the clamped ones 0.
    lam : ndarray
        Reaction of every face node (0 where inactive), per unit width.
    """
    n = K.shape[0]
    free = np.setdiff1d(np.arange(n), em.fixed)
    By = select(em.face_y[active], n)[:, free]
    Bx = select(em.face_x[active], n)[:, free]
    G = (By - mu * Bx).T
    A = sp.bmat([[K[free][:, free], G], [By, None]], format="csc")
    b = np.concatenate([rhs[free], np.full(By.shape[0], -gap)])
    sol = spla.spsolve(A, b)
    z = np.zeros(n)
    z[free] = sol[: free.size]
    lam = np.zeros(em.face_x.size)
    lam[active] = sol[free.size :]
    return z, lam


def _free_face(em: ElementMesh, K: sp.spmatrix, normal_N: float, tangential_N: float):
    """Uniform tractions on a free face (no ice): the cantilever checks."""
    n = K.shape[0]
    w, l_ = em.spec.width_m, em.spec.length_m
    f = np.zeros(n)
    f[em.face_x] += tangential_N / w * em.face_weights_m / l_
    f[em.face_y] -= normal_N / w * em.face_weights_m / l_
    free = np.setdiff1d(np.arange(n), em.fixed)
    z = np.zeros(n)
    z[free] = spla.spsolve(K[free][:, free].tocsc(), f[free])
    return z


def solve_linear(
    em: ElementMesh,
    *,
    normal_force_N: float,
    mu: float = 0.0,
    face: str = "ice",
    tangential_force_N: float = 0.0,
    contact_halfwidth_m: float | None = None,
    max_iter: int = 100,
) -> ElementState:
    """Static linear solution of the element pressed on the ice and dragged.

    Parameters
    ----------
    em : ElementMesh
    normal_force_N : float
        N on the whole width, N, > 0 on the ice.
    mu : float
        Friction coefficient of the sliding face (Eq. 5.24 at the sliding speed); the
        tangential traction mu p acts in +x, the direction the ice moves.
    face : {"ice", "free"}
        ``"ice"``: frictional contact with a rigid flat ice surface; ``"free"``: no ice,
        uniform tractions ``tangential_force_N`` (+x) and ``normal_force_N`` (towards the
        root) on the face.
    tangential_force_N : float
        Tangential force on a free face, N.
    contact_halfwidth_m : float, optional
        Only face nodes with |x| <= this may touch (a flat punch narrower than the face).
    max_iter : int
        Largest number of active-set updates.

    Returns
    -------
    ElementState
    """
    if face not in FACE_CONDITIONS:
        raise ValueError(f"face must be one of {FACE_CONDITIONS}, got face={face!r}")
    mu = check_range("mu", mu, 0.0, 5.0)
    N = check_number("normal_force_N", normal_force_N)
    K = linear_stiffness(em)
    if face == "free":
        z = _free_face(em, K, N, check_number("tangential_force_N", tangential_force_N))
        zeros = np.zeros(em.face_x.size)
        return ElementState(em, z[: em.n_u], z[em.n_u :], zeros, zeros.astype(bool), 0.0,
                            N, mu, "linear")
    if not N > 0:
        raise ValueError(f"normal_force_N must be > 0 on the ice, got {normal_force_N!r}")
    candidates = np.ones(em.face_x.size, dtype=bool)
    if contact_halfwidth_m is not None:
        candidates = np.abs(em.face_x_m) <= contact_halfwidth_m * (1 + 1e-9)
    active = candidates.copy()
    rhs = np.zeros(K.shape[0])
    for _ in range(max_iter):
        z, lam = contact_solve(K, em, active, mu, rhs, 1.0)
        penetrates = candidates & ~active & (z[em.face_y] + 1.0 > 1e-9)
        new = update_contact_set(active, lam, penetrates)
        if np.array_equal(new, active):
            break
        active = new
    else:
        raise RuntimeError(f"the contact set did not settle in {max_iter} updates")
    scale = N / (em.spec.width_m * lam.sum())
    return ElementState(em, scale * z[: em.n_u], scale * z[em.n_u :], scale * lam, active,
                        scale, N, mu, "linear")
