"""Natural frequencies of the element on the ice: face sliding and face stuck.

Small vibrations about a solved state (the linear model's undeformed element, or the
neo-Hookean element's deformed state with its tangent, which holds the stress stiffening
by the normal force): the face nodes in contact keep to the ice (no vertical motion);
with the face *sliding* they move freely along it (the friction force does not change
with the motion: the mode of the sliding phase of stick-slip), with the face *stuck* they
do not move at all (the sticking phase). The pressure dofs carry no mass; the generalised
eigenproblem (K - omega^2 M) x = 0 of the saddle system is solved by shift-invert about 0.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from friction_model.continuum._assembly import linear_stiffness, mass_matrix
from friction_model.continuum.hyperelastic import neo_hookean_tangent
from friction_model.continuum.state import ElementState

__all__ = ["FACE_MOTIONS", "modal_frequencies", "own_modulus_frequency_Hz"]

#: How the face in contact may move in a mode.
FACE_MOTIONS = ("sliding", "stuck", "free")


def modal_frequencies(state: ElementState, *, face: str = "sliding",
                      n_modes: int = 3) -> np.ndarray:
    """Lowest natural frequencies of the element about ``state``, Hz.

    Parameters
    ----------
    state : ElementState
        The static state (its contact set decides which face nodes touch the ice).
    face : {"sliding", "stuck", "free"}
        Face nodes in contact free to slide along the ice, held, or the whole face free.
    n_modes : int
        Number of frequencies.

    Returns
    -------
    ndarray
        Ascending frequencies, Hz.
    """
    if face not in FACE_MOTIONS:
        raise ValueError(f"face must be one of {FACE_MOTIONS}, got face={face!r}")
    em = state.mesh
    z = np.concatenate([state.displacement, state.pressure])
    if state.model == "neo-hookean":
        K, _ = neo_hookean_tangent(em, z)
    else:
        K = linear_stiffness(em)
    M = mass_matrix(em)
    held = [em.fixed]
    if face != "free":
        held.append(em.face_y[state.active])
    if face == "stuck":
        held.append(em.face_x[state.active])
    free = np.setdiff1d(np.arange(K.shape[0]), np.concatenate(held))
    Kf = sp.csc_matrix(K[free][:, free])
    Mf = sp.csc_matrix(M[free][:, free])
    lu = spla.splu(Kf)
    op = spla.LinearOperator(Kf.shape, matvec=lambda x: lu.solve(Mf @ x))
    # eigenvalues of K^-1 M are 1 / omega^2 (and 0 for the massless pressure)
    vals = spla.eigs(op, k=n_modes, which="LM", return_eigenvectors=False)
    omega2 = 1.0 / np.sort(vals.real)[::-1]
    return np.sqrt(omega2) / (2.0 * math.pi)


def own_modulus_frequency_Hz(frequency_at_E0_Hz: float, modulus_exponent: float,
                             reference_frequency_Hz: float = 1.0) -> float:
    """Frequency of a mode whose stiffness scales with E(f) = E0 (f / f0)^n, Hz.

    A linear element's frequency is f0 sqrt(E / E0); with the compound's causal modulus
    (:meth:`friction_model.compound.Compound.storage_modulus_Pa`) the fixed point
    f = f_E0 (f / f_ref)^(n / 2) is f = f_E0^(1 / (1 - n / 2)) f_ref^(-(n / 2) / (1 - n / 2)).

    Examples
    --------
    >>> round(own_modulus_frequency_Hz(100.0, 0.0), 6)
    100.0
    """
    a = 0.5 * modulus_exponent
    return frequency_at_E0_Hz ** (1.0 / (1.0 - a)) * reference_frequency_Hz ** (-a / (1.0 - a))
