"""Equations of motion of N elements made of chains of rigid bars (section 5.1, Eq. 5.1-5.11).

Private engine behind :mod:`friction_model.dynamics.rigid`. Every function is vectorised with
numpy and broadcasts over leading axes, so the same code serves one right-hand-side
evaluation (``phi`` of shape ``(N, nb)``) and the post-processing of a whole time series
(``(T, N, nb)``).

Kinematics (block frame, origin at the joint of each element with the block base)
---------------------------------------------------------------------------------
* x points in the sliding direction of the block over the ground (the block moves with
  v0 > 0 in +x, the ground is at rest), y points up; the ground surface lies at depth y0
  below the joints.
* Element ``i`` is a chain of ``nb`` rigid bars hanging from its joint at
  ``(root_x[i], 0)``; element 0 leads (largest x), element i+1 follows behind it.
* Bar ``j`` has the absolute angle ``phi[..., i, j]`` from the vertical, positive when its
  lower end trails (clockwise, the deflection of Fig. 5.1 and 5.3). Its axis unit vector
  is ``a = (-sin phi, -cos phi)`` (pointing down the bar), its lateral unit vector
  ``n = (cos phi, -sin phi)`` (towards the leading face). A material point of bar ``j``
  at axial distance ``s`` from the bar's upper joint and lateral offset ``e`` lies at
  ``P = J_j + s a_j + e n_j`` with the joints ``J_0 = 0``, ``J_{k+1} = J_k + d_k a_k``.

Equations of motion (Lagrange, absolute bar angles)
--------------------------------------------------
The kinetic energy of a planar chain is ``T = 1/2 sum_jk L_jk cos(phi_j - phi_k) dphi_j
dphi_k`` with the constants ``L_jk = sum_b m_b r_bj r_bk + delta_jk J_cj``, where ``r_bj`` is
the lever of bar ``j``'s rotation on the centre of mass of bar ``b`` (``d_j`` for j < b,
``d_j / 2`` for j = b, 0 otherwise) and ``J_cj`` the inertia of bar ``j`` about its centre
of mass. Lagrange's equations give, per element,

    sum_k L_jk cos(phi_j - phi_k) ddphi_k + sum_k L_jk sin(phi_j - phi_k) dphi_k**2 = Q_j,

with the generalised forces ``Q`` of the joint springs and dampers (root spring on
``phi_0``, joint spring ``j`` on ``phi_j - phi_{j-1}``), of gravity
(``-g sum_b m_b r_bj sin phi_j``, the bars hang) and of the contact forces, mapped through
the Jacobians of their points of application: ``Q_k = F . dP/dphi_k``. For two equal bars
this is term for term Eq. 5.10-5.11; for one bar with the contact on its axis it is
Eq. 5.8 with Eq. 5.9.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

logger = logging.getLogger(__name__)

__all__ = [
    "ChainModel",
    "GroundContact",
    "Kinematics",
    "SipeContact",
    "accelerations",
    "bar_inertia_constants",
    "energy",
    "generalized_force",
    "ground_contact",
    "internal_forces",
    "mass_matrix",
    "sipe_contacts",
    "sipe_forces",
    "velocity_terms",
]


@dataclass(frozen=True)
class ChainModel:
    """Constants of N elements of ``nb`` rigid bars each (SI units).

    Attributes
    ----------
    bar_length : (nb,) ndarray
        Bar lengths d_j, m (the same chain for every element).
    L : (N, nb, nb) ndarray
        Inertia constants L_jk, kg m^2 (the mass matrix is ``L * cos(phi_j - phi_k)``).
    gravity : (N, nb) ndarray
        ``g sum_b m_b r_bj``, N m (the gravity moment on bar j is ``-gravity_j sin phi_j``).
    spring : (N, nb) ndarray
        Torsional spring constants c_phi, N m/rad: root spring first, then the joints.
    damper : (N, nb) ndarray
        Torsional damping constants d_phi, N m s/rad, same order.
    elem_length : (N,) ndarray
        Element lengths l in the sliding direction, m (the bar width in the figures).
    width : float
        Element width w across the sliding direction, m.
    root_x : (N,) ndarray
        x position of each element's joint with the base, m (element 0 leads).
    ground_stiffness : (N,) ndarray
        Penalty constant c_N of the ground contact, N/m (Eq. 5.1); for the ``"face"``
        contact the stiffness of the whole face.
    free_length : float
        Undeformed length y_N of the penalty spring, m (Eq. 5.2).
    contact_model : {"edge", "face"}
        ``"edge"``: one penalty spring at the leading bottom edge of the last bar, offset
        ``contact_offset`` from its axis (Fig. 5.3; 0 gives the axis point of Fig. 5.1).
        ``"face"``: penalty springs spread evenly over the bottom face (Winkler
        foundation), resultant at the pressure centroid.
    contact_offset : (N,) ndarray
        Lateral offset of the ``"edge"`` contact point towards the leading face, m.
    sipe_stiffness : (N-1,) ndarray
        Penalty constant c_S of the contact between neighbours, N/m.
    """

    bar_length: np.ndarray
    L: np.ndarray
    gravity: np.ndarray
    spring: np.ndarray
    damper: np.ndarray
    elem_length: np.ndarray
    width: float
    root_x: np.ndarray
    ground_stiffness: np.ndarray
    free_length: float
    contact_model: str
    contact_offset: np.ndarray
    sipe_stiffness: np.ndarray

    @property
    def n_elements(self) -> int:
        """Number of elements N."""
        return int(self.L.shape[0])

    @property
    def n_bars(self) -> int:
        """Bars per element nb."""
        return int(self.bar_length.shape[0])


def bar_inertia_constants(
    masses: np.ndarray, inertias_c: np.ndarray, bar_length: np.ndarray, g: float
) -> tuple[np.ndarray, np.ndarray]:
    """Inertia constants L_jk and gravity coefficients of a chain of bars.

    Parameters
    ----------
    masses, inertias_c : (N, nb) ndarray
        Bar masses, kg, and inertias about the bars' centres of mass, kg m^2.
    bar_length : (nb,) ndarray
        Bar lengths, m; the centre of mass of each bar lies at its middle.
    g : float
        Gravitational acceleration, m/s^2.

    Returns
    -------
    L : (N, nb, nb) ndarray
        ``L_jk = sum_b m_b r_bj r_bk + delta_jk J_cj``, kg m^2. For two equal bars
        (mass m, length d) ``L = [[J_B + m d^2, m d^2/2], [m d^2/2, J_C2 + m d^2/4]]`` with
        ``J_B = J_C1 + m d^2/4``, the coefficients of Eq. 5.10-5.11.
    gravity : (N, nb) ndarray
        ``g sum_b m_b r_bj``, N m (3/2 m g d and 1/2 m g d in Eq. 5.10-5.11).
    """
    nb = bar_length.shape[0]
    b = np.arange(nb)
    # r[b, j]: lever of bar j's rotation on the centre of mass of bar b
    r = np.where(b[None, :] < b[:, None], bar_length[None, :], 0.0)
    r = r + np.diag(bar_length / 2.0)
    L = np.einsum("nb,bj,bk->njk", masses, r, r) + inertias_c[:, :, None] * np.eye(nb)
    gravity = g * np.einsum("nb,bj->nj", masses, r)
    return L, gravity


_TRIL_CACHE: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _tril_eye(nb: int) -> tuple[np.ndarray, np.ndarray]:
    """(strictly lower-triangular ones, identity) of size nb: k < j and k == j masks."""
    if nb not in _TRIL_CACHE:
        _TRIL_CACHE[nb] = (np.tril(np.ones((nb, nb)), -1), np.eye(nb))
    return _TRIL_CACHE[nb]


class Kinematics:
    """Sines, cosines and joint positions of all bars at one state (computed once).

    Parameters
    ----------
    model : ChainModel
    phi : (..., N, nb) ndarray
        Bar angles, rad.

    Attributes
    ----------
    sin, cos : (..., N, nb) ndarray
    jx, jy : (..., N, nb+1) ndarray
        Joint coordinates relative to each element's root, m (``J_0 = 0``).
    colx, coly : (..., N, nb) ndarray
        ``d_k * d(axis)/dphi_k = -d_k n_k``: the Jacobian column of bar k for every point
        below bar k, m/rad.
    """

    __slots__ = ("colx", "coly", "cos", "jx", "jy", "model", "sin")

    def __init__(self, model: ChainModel, phi: np.ndarray) -> None:
        self.model = model
        self.sin = np.sin(phi)
        self.cos = np.cos(phi)
        d = model.bar_length
        self.colx = -d * self.cos
        self.coly = d * self.sin
        zero = np.zeros((*phi.shape[:-1], 1))
        self.jx = np.concatenate([zero, np.cumsum(-d * self.sin, axis=-1)], axis=-1)
        self.jy = np.concatenate([zero, np.cumsum(-d * self.cos, axis=-1)], axis=-1)

    def point(self, bar: int, s: ArrayLike, e: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Coordinates (x, y) of the material point (s, e) of bar ``bar``, (..., N) each, m.

        ``P = J_bar + s a + e n`` with ``a = (-sin, -cos)``, ``n = (cos, -sin)``.
        """
        sn, cs = self.sin[..., bar], self.cos[..., bar]
        x = self.jx[..., bar] - s * sn + e * cs
        y = self.jy[..., bar] - s * cs - e * sn
        return x, y

    def jacobian(self, bar: int, s: ArrayLike, e: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """dP/dphi_k of the point (s, e) of bar ``bar`` as (x, y) parts, (..., N, nb) each.

        ``-d_k n_k`` for k < bar, ``-s n + e a`` for k = bar, 0 for k > bar.
        """
        nb = self.model.n_bars
        lower = (np.arange(nb) < bar).astype(float)
        own = np.zeros(nb)
        own[bar] = 1.0
        sn, cs = self.sin[..., bar], self.cos[..., bar]
        jx = self.colx * lower + ((-s * cs - e * sn)[..., None]) * own
        jy = self.coly * lower + ((s * sn - e * cs)[..., None]) * own
        return jx, jy

    def bar_points(
        self, s: np.ndarray, e: np.ndarray, elements: np.ndarray
    ) -> tuple[np.ndarray, ...]:
        """Points (s_j, e) on every bar j of the ``elements`` and their Jacobians.

        Parameters
        ----------
        s : (..., *E, nb) ndarray
            Axial coordinate on each bar, m.
        e : E-shaped ndarray
            Lateral offset per element, m.
        elements : int ndarray of shape E
            Element indices (any shape E, e.g. (2, N-1) for the two sides of the sipes).

        Returns
        -------
        x, y : (..., *E, nb) ndarray
            Coordinates relative to each element's root, m.
        jac_x, jac_y : (..., *E, nb, nb) ndarray
            ``[..., j, k]``: derivative of the point on bar j by phi_k.
        """
        tril, eye = _tril_eye(self.model.n_bars)
        sn, cs = self.sin[..., elements, :], self.cos[..., elements, :]
        e = e[..., None]
        x = self.jx[..., elements, :-1] - s * sn + e * cs
        y = self.jy[..., elements, :-1] - s * cs - e * sn
        colx, coly = self.colx[..., elements, :], self.coly[..., elements, :]
        jac_x = colx[..., None, :] * tril + (-s * cs - e * sn)[..., :, None] * eye
        jac_y = coly[..., None, :] * tril + (s * sn - e * cs)[..., :, None] * eye
        return x, y, jac_x, jac_y


def generalized_force(
    jac_x: np.ndarray, jac_y: np.ndarray, fx: np.ndarray, fy: np.ndarray
) -> np.ndarray:
    """Q_k = F . dP/dphi_k for forces (fx, fy) (..., N) at points with Jacobians (..., N, nb)."""
    return fx[..., None] * jac_x + fy[..., None] * jac_y


def mass_matrix(model: ChainModel, phi: np.ndarray) -> np.ndarray:
    """M_jk = L_jk cos(phi_j - phi_k), (..., N, nb, nb), kg m^2 (left side of Eq. 5.10-5.11)."""
    diff = phi[..., :, None] - phi[..., None, :]
    return model.L * np.cos(diff)


def velocity_terms(model: ChainModel, phi: np.ndarray, dphi: np.ndarray) -> np.ndarray:
    """Centrifugal terms sum_k L_jk sin(phi_j - phi_k) dphi_k^2, (..., N, nb), N m.

    They appear with the opposite sign on the right of Eq. 5.10-5.11
    (``+1/2 m d^2 sin(phi_4 - phi_3) dphi_4^2``).
    """
    diff = phi[..., :, None] - phi[..., None, :]
    return np.sum(model.L * np.sin(diff) * (dphi**2)[..., None, :], axis=-1)


def internal_forces(model: ChainModel, phi: np.ndarray, dphi: np.ndarray) -> np.ndarray:
    """Generalised forces of the torsional springs, dampers and gravity, (..., N, nb), N m.

    Spring j acts on the relative angle ``phi_j - phi_{j-1}`` (``phi_{-1} = 0``, the base):
    ``-(c_3 + c_4) phi_3 + c_4 phi_4`` in Eq. 5.10 and the same for the dampers; gravity
    ``-3/2 m g d sin phi_3`` and ``-1/2 m g d sin phi_4``.
    """
    rel = phi.copy()
    rel[..., 1:] -= phi[..., :-1]
    drel = dphi.copy()
    drel[..., 1:] -= dphi[..., :-1]
    torque = model.spring * rel + model.damper * drel
    q = -torque
    q[..., :-1] += torque[..., 1:]
    return q - model.gravity * np.sin(phi)


@dataclass(frozen=True)
class GroundContact:
    """Ground contact of every element at one state (arrays over (..., N)).

    Attributes
    ----------
    normal_force : ndarray
        F_N >= 0, N (Eq. 5.1).
    penetration : ndarray
        u_N at the contact point (edge) or the deepest point of the face, m (Eq. 5.2).
    jac_x, jac_y : ndarray
        Jacobian of the point of application, (..., N, nb) each, m/rad.
    tip_velocity_x : ndarray
        Horizontal velocity of that point relative to the block, m/s.
    fraction : ndarray
        Fraction of the bottom face in contact (``"face"``); for ``"edge"`` 1 in contact,
        else 0.
    potential : ndarray
        Energy stored in the penalty springs, J.
    """

    normal_force: np.ndarray
    penetration: np.ndarray
    jac_x: np.ndarray
    jac_y: np.ndarray
    tip_velocity_x: np.ndarray
    fraction: np.ndarray
    potential: np.ndarray


def ground_contact(
    model: ChainModel,
    kin: Kinematics,
    dphi: np.ndarray,
    y0: np.ndarray,
    direction: np.ndarray,
) -> GroundContact:
    """Penalty contact with the ground, Eq. 5.1-5.3 (generalised to a chain of bars).

    Parameters
    ----------
    model : ChainModel
    kin : Kinematics
        Kinematics of the bar angles phi (..., N, nb).
    dphi : (..., N, nb) ndarray
        Bar angular velocities, rad/s.
    y0 : (..., N) ndarray
        Preload distance from the joints to the ground, m.
    direction : float or (...,) ndarray
        +1 or -1, the sign of the sliding velocity: the ``"edge"`` contact sits on the
        leading edge.

    Notes
    -----
    ``"edge"``: u_N = y_N + depth(P) - y0 at the point P at the bottom of the last bar,
    ``direction * contact_offset`` towards the leading face; depth(P) = d cos phi for one bar
    with zero offset (Eq. 5.3). F_N = c_N max(u_N, 0) acts vertically at P (Eq. 5.1).
    ``"face"``: u(xi) = u_c + xi sin(phi_last) over the face -l/2 <= xi <= l/2 with the
    pressure (c_N / l) max(u, 0) (a Winkler foundation); the resultant acts at the
    pressure centroid, which gives the same generalised forces as the distributed load
    because the face is straight.
    """
    last = model.n_bars - 1
    s = model.bar_length[last]
    direction = np.asarray(direction, dtype=float)
    if direction.ndim and direction.ndim < y0.ndim:
        direction = direction[..., None]
    c_n = model.ground_stiffness
    if model.contact_model == "edge":
        e = direction * model.contact_offset
        _, y = kin.point(last, s, e)
        u = model.free_length - y - y0
        up = np.maximum(u, 0.0)
        fn = c_n * up
        fraction = (u > 0).astype(float)
        potential = 0.5 * c_n * up**2
    else:
        half = 0.5 * model.elem_length
        _, yc = kin.point(last, s, 0.0)
        uc = model.free_length - yc - y0
        slope = kin.sin[..., last]  # du/dxi
        small = np.abs(slope) < 1e-12
        xi_star = -uc / np.where(small, 1.0, slope)
        clipped = np.clip(xi_star, -half, half)
        lo = np.where(small | (slope < 0), -half, clipped)
        hi = np.where(small | (slope > 0), half, clipped)
        empty = (hi <= lo) | (small & (uc <= 0))
        lo = np.where(empty, 0.0, lo)
        hi = np.where(empty, 0.0, hi)
        k = c_n / model.elem_length  # stiffness per unit face length, N/m^2
        d1, d2, d3 = hi - lo, (hi**2 - lo**2) / 2, (hi**3 - lo**3) / 3
        i0 = uc * d1 + slope * d2
        i1 = uc * d2 + slope * d3
        i2 = uc**2 * d1 + 2 * uc * slope * d2 + slope**2 * d3
        positive = i0 > 0
        fn = k * np.where(positive, i0, 0.0)
        e = np.where(positive, i1 / np.where(positive, i0, 1.0), 0.0)
        u = uc + half * np.abs(slope)
        fraction = d1 / model.elem_length
        potential = 0.5 * k * np.where(positive, i2, 0.0)
    jac_x, jac_y = kin.jacobian(last, s, e)
    tip_vx = np.sum(jac_x * dphi, axis=-1)
    return GroundContact(fn, u, jac_x, jac_y, tip_vx, fraction, potential)


@dataclass(frozen=True)
class SipeContact:
    """Contacts between neighbouring elements (arrays over (..., 2, N-1, nb)).

    Axis -3 is the side: 0 = the trailing bottom corner of each bar of the element in front
    (i) against the leading face of the element behind (i+1), the case of Fig. 5.3;
    1 = the leading corner of element i+1 against the trailing face of element i.

    Attributes
    ----------
    penetration : ndarray
        Overlap normal to the face, m (0 when the gap is open).
    normal_x, normal_y : ndarray
        Outward unit normal of the face.
    tangent_x, tangent_y : ndarray
        Unit vector along the face (down the bar).
    corner_jac_x, corner_jac_y, face_jac_x, face_jac_y : ndarray
        Jacobians of the corner and of the face point under it, (..., 2, N-1, nb, nb).
    slip_velocity : ndarray
        Velocity of the corner relative to the face point along the tangent, m/s.
    """

    penetration: np.ndarray
    normal_x: np.ndarray
    normal_y: np.ndarray
    tangent_x: np.ndarray
    tangent_y: np.ndarray
    corner_jac_x: np.ndarray
    corner_jac_y: np.ndarray
    face_jac_x: np.ndarray
    face_jac_y: np.ndarray
    slip_velocity: np.ndarray


def sipe_contacts(model: ChainModel, kin: Kinematics, dphi: np.ndarray) -> SipeContact:
    """Penalty contact between neighbouring elements across the sipes (section 5.1.2.1).

    The bottom corner of bar j of one element is tested against the face of bar j of its
    neighbour (the thesis pairs the springs S_i with the bars in this way). The gap is
    measured along the face's outward normal nu, ``g = (C - F) . nu`` for any face point F,
    and the foot point ``M = C - g nu`` is the material point of the face that receives the
    reaction. The thesis takes S horizontal; the normal gap is the same for vertical faces
    and keeps the penalty force conservative when the faces tilt.
    """
    n = model.n_elements
    half = 0.5 * model.elem_length
    front, behind = np.arange(n - 1), np.arange(1, n)
    # side 0: trailing corners of the element in front against the leading face behind it
    c_idx = np.stack([front, behind])
    f_idx = np.stack([behind, front])
    sign_f = np.array([1.0, -1.0])[:, None]  # outward normal of the face: +n or -n
    e_c = -sign_f * half[c_idx]
    e_f = sign_f * half[f_idx]
    s_c = np.broadcast_to(model.bar_length, (*kin.sin.shape[:-2], 2, n - 1, model.n_bars))
    xc, yc, jcx, jcy = kin.bar_points(s_c, e_c, c_idx)
    sn, cs = kin.sin[..., f_idx, :], kin.cos[..., f_idx, :]
    sf = sign_f[:, :, None]
    nux, nuy = sf * cs, -sf * sn
    rx = xc + (model.root_x[c_idx] - model.root_x[f_idx])[..., None] - kin.jx[..., f_idx, :-1]
    ry = yc - kin.jy[..., f_idx, :-1]
    gap = rx * nux + ry * nuy - half[f_idx][..., None]
    s_foot = -(rx * sn + ry * cs)
    _, _, jfx, jfy = kin.bar_points(s_foot, e_f, f_idx)
    dc, df = dphi[..., c_idx, None, :], dphi[..., f_idx, None, :]
    dvx = np.sum(jcx * dc, axis=-1) - np.sum(jfx * df, axis=-1)
    dvy = np.sum(jcy * dc, axis=-1) - np.sum(jfy * df, axis=-1)
    slip = -(dvx * sn + dvy * cs)
    return SipeContact(np.maximum(-gap, 0.0), nux, nuy, -sn, -cs, jcx, jcy, jfx, jfy, slip)


def sipe_forces(
    contact: SipeContact, normal_force: np.ndarray, friction_force: np.ndarray
) -> np.ndarray:
    """Generalised forces of given sipe contact forces, (..., N, nb), N m.

    Parameters
    ----------
    contact : SipeContact
    normal_force : (..., 2, N-1, nb) ndarray
        Contact force S along the face normal, pushing the corner away from the face, N.
    friction_force : (..., 2, N-1, nb) ndarray
        Friction force R_S on the corner along the face tangent (down the face bar), N; the
        face receives the opposite forces.
    """
    fx = normal_force * contact.normal_x + friction_force * contact.tangent_x
    fy = normal_force * contact.normal_y + friction_force * contact.tangent_y
    q_c = np.sum(fx[..., None] * contact.corner_jac_x + fy[..., None] * contact.corner_jac_y, -2)
    q_f = -np.sum(fx[..., None] * contact.face_jac_x + fy[..., None] * contact.face_jac_y, -2)
    n_pairs = q_c.shape[-2]
    q = np.zeros((*q_c.shape[:-3], n_pairs + 1, q_c.shape[-1]))
    # side 0: corner on the element in front (0..N-2), face behind (1..N-1); side 1: reverse
    q[..., :-1, :] += q_c[..., 0, :, :] + q_f[..., 1, :, :]
    q[..., 1:, :] += q_f[..., 0, :, :] + q_c[..., 1, :, :]
    return q


def accelerations(
    model: ChainModel, phi: np.ndarray, dphi: np.ndarray, q: np.ndarray
) -> np.ndarray:
    """Solve M(phi) ddphi = Q - centrifugal terms for ddphi, (..., N, nb), rad/s^2."""
    m = mass_matrix(model, phi)
    rhs = q - velocity_terms(model, phi, dphi)
    if model.n_bars == 1:
        return rhs / m[..., 0]
    if model.n_bars == 2:
        a, b, c, d = m[..., 0, 0], m[..., 0, 1], m[..., 1, 0], m[..., 1, 1]
        det = a * d - b * c
        r0, r1 = rhs[..., 0], rhs[..., 1]
        return np.stack([(d * r0 - b * r1) / det, (a * r1 - c * r0) / det], axis=-1)
    return np.linalg.solve(m, rhs[..., None])[..., 0]


def energy(
    model: ChainModel, phi: np.ndarray, dphi: np.ndarray, y0: np.ndarray, direction: np.ndarray
) -> np.ndarray:
    """Total mechanical energy (kinetic, springs, gravity, penalty springs), (...,), J.

    Computed from the potentials, independently of the force code, so that its
    conservation in an undamped, frictionless run checks the equations of motion.
    """
    kin = Kinematics(model, phi)
    m = mass_matrix(model, phi)
    kinetic = 0.5 * np.einsum("...j,...jk,...k->...", dphi, m, dphi).sum(axis=-1)
    rel = phi.copy()
    rel[..., 1:] -= phi[..., :-1]
    springs = 0.5 * np.sum(model.spring * rel**2, axis=(-1, -2))
    gravity = -np.sum(model.gravity * kin.cos, axis=(-1, -2))
    ground = ground_contact(model, kin, dphi, y0, direction).potential.sum(axis=-1)
    total = kinetic + springs + gravity + ground
    if model.n_elements > 1:
        pen = sipe_contacts(model, kin, dphi).penetration
        total = total + 0.5 * np.sum(model.sipe_stiffness[:, None] * pen**2, axis=(-1, -2, -3))
    return total
