"""Rigid-body tread-block models (section 5.1): the SDOF element and the siped block.

* :func:`simulate_sdof`: one rigid bar on a torsional spring/damper with penalty normal
  contact, lift-off and velocity-dependent friction (Eq. 5.1-5.9, Fig. 5.1).
* :func:`simulate_block_dynamics`: a siped block of any number N of elements, each a chain of
  rigid bars (two by default: the two-mass oscillators of Fig. 5.3) joined by torsional
  springs/dampers, with penalty contact to the ground at the leading bottom edge of each
  element and one-sided penalty contact with Coulomb friction between neighbours across the
  sipes (section 5.1.2). The equations of motion are derived in general for N elements and
  ``n_bars`` bars by Lagrange's equations (:mod:`friction_model.dynamics._rigid_eom`); for
  N = 4, two bars, they are Eq. 5.10-5.11 term by term.

Sign convention (checked against the kinematics)
-----------------------------------------------
The block moves with v0 > 0 in +x over the ground; element 0 leads. The deflection angle
phi > 0 means the lower end trails (moves in -x relative to the joint), as in Fig. 5.1/5.3.
The tip sits at ``x_p = -d sin phi``, so ``dx_p/dt = -d cos phi dphi/dt`` (Eq. 5.6) and the
tip slides over the ground with ``v_rel = v0 + dx_p/dt = v0 - d cos phi dphi/dt``. Eq. 5.5 is
printed as ``v_rel = v0 - dx_p/dt``, which with Eq. 5.6 would add the tip's backward motion
to the sliding speed; the kinematics and the moment balance Eq. 5.8 (friction on the tip acts
in -x and drives phi > 0 with the lever ``d cos phi``; the normal force adds
``F_N d sin phi``) need ``v0 + dx_p/dt``, used here. Friction forces oppose the relative
sliding velocity: ``F_F = mu(|v_rel|) F_N sgn(v_rel)`` with a sign regularised over
``v_reg_mps``.

Default parameters (all derived, none fitted)
---------------------------------------------
Geometry of the reference sample G3 (Table 4.4, Fig. 4.4 b): block 20 mm x 80 mm, three
0.6 mm sipes, elements l = 4.55 mm long and d = 6 mm high (chapter 5). Rubber of the
reference compound REF, Shore A 60 (Table 4.3): Young's modulus E = 3.61 MPa from Gent's
relation, shear modulus G = E/3 (nu = 0.5) and shear coefficient 6/7 (Eq. 5.19); density
1150 kg/m^3 (carbon-black filled tread compound); loss factor tan(delta) = 0.2 (tread
compound near 0 degC). From these:

* torsional springs: the chain of rigid bars reproduces the static deflection of the
  element as a clamped-free bending and shear cantilever under a tip load at every joint;
* dampers: stiffness-proportional, giving the first mode the damping ratio tan(delta)/2;
* ground penalty stiffness c_N = E l w / d, the compression stiffness of the element (the
  bars are rigid, so the penalty spring carries the compliance in compression);
* sipe penalty stiffness c_S = E w d_bar / (l_i + l_i+1), the two bar segments compressed
  across their length in series.

Behaviour worth knowing
-----------------------
* Leading-edge contact (Fig. 5.3, ``contact_model="edge"``): the normal force acts ahead of
  the axis and tips the element forwards with the lever l/2, friction tips it backwards
  with the lever ~d. The elements deflect backwards (phi > 0, as in Fig. 5.4-5.7) only when
  roughly mu d > l/2, i.e. mu > ~0.4-0.6 for G3 elements; with rubber-ice values
  (mu ~ 0.1-0.3, Table 4.6) they tip forwards. The ``"face"`` contact (Winkler springs
  over the bottom face) deflects backwards for any mu > 0 and gives the contact fraction.
* The rigid chain buckles under F_N d ~ c_phi. With the default c_N the thesis preloads
  (y0 = 4.6-5.1 mm for d = 6 mm, i.e. 0.9-1.4 mm of penalty compression, 200-300 N) come
  close to that load; a softer penalty spring (or larger y0) keeps the elements in the
  small-deflection range.
* A decreasing mu(v) feeds energy into the elements (negative slope times F_N d^2 against
  d_phi); at low speed and tan(delta) = 0.2 steady sliding can turn into stick-slip.
* Neighbours touch when the deflection exceeds about arccos(l / (l + f)) (28 deg for G3).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd
import scipy.linalg
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp
from scipy.sparse import lil_matrix

from friction_model.compound import REFERENCE_COMPOUND, gent_youngs_modulus
from friction_model.contact.laws import RelaxedFriction
from friction_model.dynamics import _rigid_eom as eom
from friction_model.dynamics._common import (
    Profile,
    SimulationError,
    SimulationResult,
    batched_fd_jacobian,
    finite_rhs,
    output_times,
    raise_if_failed,
    surface_profile,
)
from friction_model.dynamics.solver import RIGID_SOLVER, SolverOptions
from friction_model.geometry import reference_block
from tir_common.validate import check_nonnegative, check_number, check_positive, check_range

logger = logging.getLogger(__name__)

__all__ = [
    "REFERENCE_DENSITY_KG_M3",
    "REFERENCE_LOSS_FACTOR",
    "REFERENCE_YOUNGS_MODULUS_PA",
    "BlockParams",
    "SdofParams",
    "element_surface_profiles",
    "gent_youngs_modulus",
    "simulate_block_dynamics",
    "simulate_sdof",
]

_G3 = reference_block("G3")
#: Element height d (sipe depth) of chapter 5, m.
_HEIGHT_M = _G3.height_mm * 1e-3
#: Element length l of G3, m (4.55 mm).
_G3_ELEMENT_LENGTH_M = float(_G3.element_lengths[0]) * 1e-3
_WIDTH_M = _G3.width_mm * 1e-3
_BLOCK_LENGTH_M = _G3.length_mm * 1e-3
_SIPE_WIDTH_M = _G3.sipe_width_mm * 1e-3
#: Shear coefficient of a rectangular section for nu = 0.5 (Cowper, Eq. 5.19).
_SHEAR_COEFFICIENT = 6.0 / 7.0
#: Standard gravity, m/s^2.
_STANDARD_GRAVITY = 9.80665


#: E of the reference compound REF (Shore A 60, Table 4.3) by Gent's relation, Pa
#: (:data:`friction_model.compound.REFERENCE_COMPOUND`, the one rubber of the package).
REFERENCE_YOUNGS_MODULUS_PA = REFERENCE_COMPOUND.E0_Pa
#: Density of a carbon-black filled tread compound, kg/m^3.
REFERENCE_DENSITY_KG_M3 = REFERENCE_COMPOUND.density_kg_m3
#: Loss factor tan(delta) of a tread compound near 0 degC (typically 0.15-0.3).
REFERENCE_LOSS_FACTOR = REFERENCE_COMPOUND.loss_factor


# -- parameter helpers ----------------------------------------------------------------------
def _cantilever_springs(
    height: float, n_bars: int, modulus: float, length: float, width: float
) -> np.ndarray:
    """Torsional springs that make a chain of ``n_bars`` rigid bars deflect like the element.

    The element is a clamped-free cantilever of height ``height`` with bending stiffness
    EI = E w l^3 / 12 and shear stiffness kappa G A (G = E/3, kappa = 6/7, Eq. 5.19). Under a
    tip load P its deflection is w(x) = P [(h x^2/2 - x^3/6) / EI + x / (kappa G A)]. The
    chain with bars of length h/nb deflects by the same amount at every joint when bar j
    rotates by (w(x_j) - w(x_j-1)) / (h/nb); spring j then carries the moment P (h - x_j-1)
    over the relative rotation of bar j. For one bar this is the tip stiffness times h^2.

    Returns
    -------
    (n_bars,) ndarray
        Spring constants, N m/rad, root spring first.
    """
    ei = modulus * width * length**3 / 12.0
    kga = _SHEAR_COEFFICIENT * (modulus / 3.0) * width * length
    x = np.linspace(0.0, height, n_bars + 1)
    w = (height * x**2 / 2 - x**3 / 6) / ei + x / kga
    rot = np.diff(w) / (height / n_bars)
    rel = np.diff(np.concatenate([[0.0], rot]))
    return (height - x[:-1]) / rel


def _chain_stiffness(springs: np.ndarray) -> np.ndarray:
    """Stiffness matrix of one chain in absolute angles, (nb, nb), N m/rad.

    From V = 1/2 sum_j c_j (phi_j - phi_j-1)^2 with phi_-1 = 0 (the base).
    """
    nb = springs.shape[0]
    upper = np.append(springs[1:], 0.0)
    k = np.diag(springs + upper)
    off = np.arange(nb - 1)
    k[off, off + 1] = k[off + 1, off] = -springs[1:]
    return k


def _first_frequency(springs: np.ndarray, L: np.ndarray) -> float:
    """Lowest undamped natural angular frequency of a free chain (no contact), rad/s."""
    vals = scipy.linalg.eigh(_chain_stiffness(springs), L, eigvals_only=True)
    return float(np.sqrt(vals[0]))


def _per_element(name: str, value: Any, n: int, unit: str, *, positive: bool) -> np.ndarray:
    """A scalar or a length-n sequence as an (n,) array, validated."""
    arr = np.atleast_1d(np.asarray(value, dtype=float))
    if arr.shape not in ((1,), (n,)):
        raise ValueError(f"{name} must be a scalar or have {n} entries, got shape {arr.shape}")
    for i, v in enumerate(arr):
        label = name if arr.size == 1 else f"{name}[{i}]"
        check_number(label, v, low=0.0, low_open=positive, unit=unit)
    return np.broadcast_to(arr, (n,)).copy()


def _per_bar(name: str, value: Any, n: int, nb: int, unit: str, *, positive: bool) -> np.ndarray:
    """A scalar, an (nb,) or an (n, nb) array as (n, nb), validated."""
    arr = np.asarray(value, dtype=float)
    try:
        out = np.broadcast_to(arr, (n, nb)).copy()
    except ValueError:
        raise ValueError(
            f"{name} must be a scalar, ({nb},) per bar or ({n}, {nb}) per element and bar, "
            f"got shape {arr.shape}"
        ) from None
    for idx, v in np.ndenumerate(out):
        check_number(f"{name}{list(idx)}", v, low=0.0, low_open=positive, unit=unit)
    return out


# -- parameters ------------------------------------------------------------------------------
@dataclass(frozen=True)
class SdofParams:
    """Single-DOF tread-block element: a rigid bar on a torsional spring (Fig. 5.1).

    Parameters left at None are derived from the rubber and the geometry (module notes).

    Parameters
    ----------
    length_m : float
        Bar length d (element height), m; 6 mm (chapter 5).
    element_length_m : float
        Element length l in the sliding direction, m; 4.55 mm (G3). Enters J_A (Eq. 5.9).
    width_m : float
        Element width w, m; 80 mm (G3).
    youngs_modulus_Pa, density_kg_m3, loss_factor : float
        Rubber: E (Pa), rho (kg/m^3), tan(delta); REF compound by default.
    mass_kg : float, optional
        Bar mass m; default rho l w d.
    inertia_kgm2 : float, optional
        J_A about the joint; default m d^2/3 + m l^2/12 (Eq. 5.9).
    spring_constant_Nm_rad : float, optional
        c_phi; default the bending-and-shear cantilever's tip stiffness times d^2.
    damping_constant_Nms_rad : float, optional
        d_phi; default tan(delta) c_phi / omega_0 with omega_0 = sqrt(c_phi / J_A).
    contact_stiffness_N_m : float, optional
        Penalty constant c_N (Eq. 5.1); default E l w / d.
    free_length_m : float
        Undeformed penalty-spring length y_N (Eq. 5.2), m; 0: contact starts when the bar's
        end reaches the ground.
    contact_offset_m : float
        Lateral offset of the contact point from the bar axis towards the leading edge, m;
        0 as in Fig. 5.1 ("at the bottom of the bar at the middle axis").
    gravity_mps2 : float
        Gravitational acceleration; adds the moment -m g (d/2) sin phi of the hanging bar to
        Eq. 5.8 (as in Eq. 5.10-5.11); 0 gives Eq. 5.8 exactly.
    """

    length_m: float = _HEIGHT_M
    element_length_m: float = _G3_ELEMENT_LENGTH_M
    width_m: float = _WIDTH_M
    youngs_modulus_Pa: float = REFERENCE_YOUNGS_MODULUS_PA
    density_kg_m3: float = REFERENCE_DENSITY_KG_M3
    loss_factor: float = REFERENCE_LOSS_FACTOR
    mass_kg: float | None = None
    inertia_kgm2: float | None = None
    spring_constant_Nm_rad: float | None = None
    damping_constant_Nms_rad: float | None = None
    contact_stiffness_N_m: float | None = None
    free_length_m: float = 0.0
    contact_offset_m: float = 0.0
    gravity_mps2: float = _STANDARD_GRAVITY

    def __post_init__(self) -> None:
        d = check_positive("length_m", self.length_m)
        ell = check_positive("element_length_m", self.element_length_m)
        w = check_positive("width_m", self.width_m)
        e_mod = check_positive("youngs_modulus_Pa", self.youngs_modulus_Pa)
        rho = check_positive("density_kg_m3", self.density_kg_m3)
        eta = check_range("loss_factor", self.loss_factor, 0.0, 2.0)
        check_nonnegative("free_length_m", self.free_length_m)
        check_range("contact_offset_m", self.contact_offset_m, 0.0, ell / 2, unit="m")
        check_range("gravity_mps2", self.gravity_mps2, 0.0, 100.0, unit="m/s^2")
        setv = object.__setattr__
        if self.mass_kg is None:
            setv(self, "mass_kg", rho * ell * w * d)
        m = check_positive("mass_kg", self.mass_kg)
        if self.inertia_kgm2 is None:
            setv(self, "inertia_kgm2", m * d**2 / 3 + m * ell**2 / 12)
        j = check_positive("inertia_kgm2", self.inertia_kgm2)
        if self.spring_constant_Nm_rad is None:
            setv(self, "spring_constant_Nm_rad", float(_cantilever_springs(d, 1, e_mod, ell, w)[0]))
        c = check_positive("spring_constant_Nm_rad", self.spring_constant_Nm_rad)
        if self.damping_constant_Nms_rad is None:
            setv(self, "damping_constant_Nms_rad", eta * c / math.sqrt(c / j))
        check_nonnegative("damping_constant_Nms_rad", self.damping_constant_Nms_rad)
        if self.contact_stiffness_N_m is None:
            setv(self, "contact_stiffness_N_m", e_mod * ell * w / d)
        check_positive("contact_stiffness_N_m", self.contact_stiffness_N_m)
        for name in self.__dataclass_fields__:
            setv(self, name, float(getattr(self, name)))

    @property
    def natural_frequency_Hz(self) -> float:
        """Undamped small-amplitude natural frequency sqrt(c_phi / J_A) / (2 pi), Hz."""
        return math.sqrt(self.spring_constant_Nm_rad / self.inertia_kgm2) / (2 * math.pi)

    def chain_model(self) -> eom.ChainModel:
        """The single bar as a one-element, one-bar :class:`_rigid_eom.ChainModel`."""
        d = self.length_m
        L = np.array([[[self.inertia_kgm2]]])
        grav = np.array([[self.gravity_mps2 * self.mass_kg * d / 2]])
        return eom.ChainModel(
            bar_length=np.array([d]),
            L=L,
            gravity=grav,
            spring=np.array([[self.spring_constant_Nm_rad]]),
            damper=np.array([[self.damping_constant_Nms_rad]]),
            elem_length=np.array([self.element_length_m]),
            width=self.width_m,
            root_x=np.zeros(1),
            ground_stiffness=np.array([self.contact_stiffness_N_m]),
            free_length=self.free_length_m,
            contact_model="edge",
            contact_offset=np.array([self.contact_offset_m]),
            sipe_stiffness=np.zeros(0),
        )


@dataclass(frozen=True)
class BlockParams:
    """Siped tread block of N elements, each a chain of rigid bars (Fig. 5.3).

    Parameters left at None are derived from the rubber and the geometry (module notes).

    Parameters
    ----------
    n_elements : int
        Number of elements N >= 1 (N - 1 sipes); 4 as in Fig. 5.3.
    height_m : float
        Element height d (sipe depth), m; split into ``n_bars`` equal bars.
    element_length_m : float or sequence of float, optional
        Element lengths l_i, m; default (block_length_m - (N-1) f) / N.
    block_length_m : float
        Overall block length L, m (20 mm), for the default element lengths.
    width_m : float
        Block width w, m (80 mm).
    sipe_width_m : float or sequence of float
        Sipe gaps f_i between elements i and i+1, m (0.6 mm).
    n_bars : int
        Rigid bars per element; 2: the two-mass oscillator of section 5.1.2.
    youngs_modulus_Pa, density_kg_m3, loss_factor : float
        Rubber: E (Pa), rho (kg/m^3), tan(delta); REF compound by default.
    spring_constants_Nm_rad : array_like, optional
        c_phi per bar (root first), shape (n_bars,) or (N, n_bars).
    damping_constants_Nms_rad : array_like, optional
        d_phi per bar, same shapes.
    contact_stiffness_N_m : float or sequence, optional
        Ground penalty constant c_N per element (Eq. 5.1); default E l w / d.
    sipe_stiffness_N_m : float or sequence, optional
        Penalty constant c_S per sipe; default E w (d / n_bars) / (l_i + l_i+1).
    free_length_m : float
        Undeformed penalty-spring length y_N (Eq. 5.2), m.
    contact_model : {"edge", "face"}
        ``"edge"``: ground force at the leading bottom edge (Fig. 5.3, Eq. 5.10-5.11);
        ``"face"``: penalty springs spread over the bottom face, which also gives the
        fraction of the face in contact.
    contact_offset_m : float, optional
        Offset of the ``"edge"`` contact point from the axis towards the leading edge, m;
        default l_i / 2 (the edge itself).
    gravity_mps2 : float
        Gravitational acceleration (the bars hang from the base), m/s^2.
    """

    n_elements: int = 4
    height_m: float = _HEIGHT_M
    element_length_m: float | tuple[float, ...] | None = None
    block_length_m: float = _BLOCK_LENGTH_M
    width_m: float = _WIDTH_M
    sipe_width_m: float | tuple[float, ...] = _SIPE_WIDTH_M
    n_bars: int = 2
    youngs_modulus_Pa: float = REFERENCE_YOUNGS_MODULUS_PA
    density_kg_m3: float = REFERENCE_DENSITY_KG_M3
    loss_factor: float = REFERENCE_LOSS_FACTOR
    spring_constants_Nm_rad: Any = None
    damping_constants_Nms_rad: Any = None
    contact_stiffness_N_m: Any = None
    sipe_stiffness_N_m: Any = None
    free_length_m: float = 0.0
    contact_model: str = "edge"
    contact_offset_m: float | None = None
    gravity_mps2: float = _STANDARD_GRAVITY

    def __post_init__(self) -> None:
        n, nb = self._counts()
        h = check_positive("height_m", self.height_m)
        w = check_positive("width_m", self.width_m)
        check_positive("youngs_modulus_Pa", self.youngs_modulus_Pa)
        rho = check_positive("density_kg_m3", self.density_kg_m3)
        check_range("loss_factor", self.loss_factor, 0.0, 2.0)
        check_nonnegative("free_length_m", self.free_length_m)
        check_range("gravity_mps2", self.gravity_mps2, 0.0, 100.0, unit="m/s^2")
        if self.contact_model not in ("edge", "face"):
            raise ValueError(
                f"contact_model must be 'edge' or 'face', got contact_model={self.contact_model!r}"
            )
        sipes = _per_element("sipe_width_m", self.sipe_width_m, max(n - 1, 1), "m", positive=False)
        sipes = sipes[: n - 1]
        ell = self._element_lengths(n, sipes)
        dbar = h / nb
        masses = rho * w * ell[:, None] * np.full((n, nb), dbar)
        inertias = masses * (dbar**2 + ell[:, None] ** 2) / 12.0
        bar_length = np.full(nb, dbar)
        L, grav = eom.bar_inertia_constants(masses, inertias, bar_length, self.gravity_mps2)
        springs, dampers = self._springs_and_dampers(ell, L, n, nb)
        c_n, c_s, offset = self._contact_constants(ell, n, nb)
        spacing = ell[:-1] / 2 + sipes + ell[1:] / 2
        chain = eom.ChainModel(
            bar_length=bar_length,
            L=L,
            gravity=grav,
            spring=springs,
            damper=dampers,
            elem_length=ell,
            width=w,
            root_x=-np.concatenate([[0.0], np.cumsum(spacing)]),
            ground_stiffness=c_n,
            free_length=float(self.free_length_m),
            contact_model=self.contact_model,
            contact_offset=offset,
            sipe_stiffness=c_s,
        )
        object.__setattr__(self, "_chain", chain)

    def _counts(self) -> tuple[int, int]:
        """``n_elements`` and ``n_bars``, checked to be integers >= 1."""
        for name in ("n_elements", "n_bars"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise ValueError(f"{name} must be an integer in [1, inf), got {name}={v!r}")
        return int(self.n_elements), int(self.n_bars)

    def _element_lengths(self, n: int, sipes: np.ndarray) -> np.ndarray:
        """Element lengths l_i, m: given, or the rubber of the block shared equally."""
        if self.element_length_m is not None:
            return _per_element("element_length_m", self.element_length_m, n, "m", positive=True)
        block = check_positive("block_length_m", self.block_length_m)
        rubber = block - sipes.sum()
        if rubber <= 0:
            raise ValueError(
                f"the sipes leave no rubber in block_length_m={block!r}: "
                f"sum(sipe_width_m)={sipes.sum()!r} must be < block_length_m"
            )
        return np.full(n, rubber / n)

    def _springs_and_dampers(
        self, ell: np.ndarray, L: np.ndarray, n: int, nb: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """Torsional springs c_phi and dampers d_phi per element and bar, (n, nb) each.

        Defaults: the cantilever-equivalent springs and stiffness-proportional dampers that
        give the first mode the damping ratio tan(delta)/2 (module notes).
        """
        e_mod, w, h = float(self.youngs_modulus_Pa), float(self.width_m), float(self.height_m)
        if self.spring_constants_Nm_rad is None:
            springs = np.stack([_cantilever_springs(h, nb, e_mod, li, w) for li in ell])
        else:
            springs = _per_bar(
                "spring_constants_Nm_rad",
                self.spring_constants_Nm_rad,
                n,
                nb,
                "N m/rad",
                positive=True,
            )
        if self.damping_constants_Nms_rad is None:
            omega = np.array([_first_frequency(springs[i], L[i]) for i in range(n)])
            dampers = float(self.loss_factor) * springs / omega[:, None]
        else:
            dampers = _per_bar(
                "damping_constants_Nms_rad",
                self.damping_constants_Nms_rad,
                n,
                nb,
                "N m s/rad",
                positive=False,
            )
        return springs, dampers

    def _contact_constants(
        self, ell: np.ndarray, n: int, nb: int
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Ground penalty c_N (n,), sipe penalty c_S (n-1,), N/m, and contact offsets (n,), m."""
        e_mod, w, h = float(self.youngs_modulus_Pa), float(self.width_m), float(self.height_m)
        if self.contact_stiffness_N_m is None:
            c_n = e_mod * ell * w / h
        else:
            c_n = _per_element(
                "contact_stiffness_N_m", self.contact_stiffness_N_m, n, "N/m", positive=True
            )
        if n > 1 and self.sipe_stiffness_N_m is None:
            c_s = e_mod * w * (h / nb) / (ell[:-1] + ell[1:])
        elif n > 1:
            c_s = _per_element(
                "sipe_stiffness_N_m", self.sipe_stiffness_N_m, n - 1, "N/m", positive=True
            )
        else:
            c_s = np.zeros(0)
        if self.contact_offset_m is None:
            return c_n, c_s, ell / 2
        off = check_range("contact_offset_m", self.contact_offset_m, 0.0, ell.min() / 2, unit="m")
        return c_n, c_s, np.full(n, off)

    def chain_model(self) -> eom.ChainModel:
        """The derived constants (masses, springs, dampers, stiffnesses) of all elements."""
        return self._chain  # type: ignore[attr-defined]

    @property
    def element_lengths_m(self) -> np.ndarray:
        """Element lengths l_i, m."""
        return self.chain_model().elem_length.copy()

    @property
    def element_offsets_m(self) -> np.ndarray:
        """Distance of each element's axis behind the leading element's axis, m."""
        return -self.chain_model().root_x


# -- inputs and friction ---------------------------------------------------------------------
def _as_profile(name: str, value: float | Profile) -> Profile:
    if callable(value):
        probe = value(0.0)
        if not np.isfinite(probe):
            raise ValueError(f"{name}(0) must be finite, got {probe!r}")
        return value
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {name}={value!r}")
    return lambda t: v


def _preloads(preload: Any, n: int) -> list[Profile]:
    if isinstance(preload, (list, tuple)):
        if len(preload) != n:
            raise ValueError(
                f"preload must be one value/profile or one per element ({n}), got {len(preload)}"
            )
        return [_as_profile(f"preload[{i}]", p) for i, p in enumerate(preload)]
    prof = _as_profile("preload", preload)
    return [prof] * n


class _FrictionSet:
    """Friction laws of N contacts: steady mu(|v|, p) and the relaxation of Eq. 5.12."""

    def __init__(self, name: str, friction: Any, n: int, *, allow_relaxed: bool) -> None:
        items = list(friction) if isinstance(friction, (list, tuple)) else [friction] * n
        if len(items) != n:
            raise ValueError(f"{name} must be one law or one per element ({n}), got {len(items)}")
        self.steady_laws: list[Any] = []
        self.relaxed: list[RelaxedFriction | None] = []
        for i, law in enumerate(items):
            if isinstance(law, RelaxedFriction):
                if not allow_relaxed:
                    raise TypeError(
                        f"{name}[{i}] is a RelaxedFriction; the relaxation of Eq. 5.12 is "
                        "modelled for the ground contact only, pass its .law"
                    )
                self.steady_laws.append(law.law)
                self.relaxed.append(law if law.tau_s > 0 else None)
            elif callable(getattr(law, "mu", None)):
                self.steady_laws.append(law)
                self.relaxed.append(None)
            else:
                raise TypeError(
                    f"{name} must provide mu(v_rel_mps, *, pressure_Pa=None, temperature_C=None)"
                    f" or be a RelaxedFriction, got {type(law).__name__}"
                )
        self.shared = all(law is self.steady_laws[0] for law in self.steady_laws)
        self.mask = np.array([r is not None for r in self.relaxed], dtype=bool)
        self.index = np.flatnonzero(self.mask)

    def steady(self, v_abs: np.ndarray, pressure: np.ndarray) -> np.ndarray:
        """|mu(|v|, p)| per contact, same shape as ``v_abs`` (last axis: contacts)."""
        if self.shared:
            out = self.steady_laws[0].mu(v_abs, pressure_Pa=pressure)
            return np.abs(np.broadcast_to(np.asarray(out, dtype=float), v_abs.shape))
        cols = [
            np.asarray(law.mu(v_abs[..., i], pressure_Pa=pressure[..., i]), dtype=float)
            for i, law in enumerate(self.steady_laws)
        ]
        return np.abs(np.stack(np.broadcast_arrays(*cols), axis=-1))

    def relax_rate(self, mu_r: np.ndarray, v_abs: np.ndarray, pressure: np.ndarray) -> np.ndarray:
        """dmu_R/dt of the relaxed contacts (Eq. 5.12, physical form), (..., n_relaxed), 1/s."""
        cols = []
        for k, i in enumerate(self.index):
            relaxed = self.relaxed[i]
            assert relaxed is not None
            rate = relaxed.rhs(mu_r[..., k], v_abs[..., i], pressure_Pa=pressure[..., i])
            cols.append(np.asarray(rate, dtype=float))
        return np.stack(cols, axis=-1)


def _check_options(
    *,
    t_end_s: float,
    solver: SolverOptions | None,
    output_step_s: float | None,
    v_reg_mps: float,
    max_angle_deg: float,
) -> tuple[float, float, SolverOptions]:
    """Validate the run options before any integration: t_end, output step and solver."""
    t_end = check_range("t_end_s", t_end_s, 1e-9, 1e4, unit="s")
    opts = RIGID_SOLVER.resolve(solver, t_end_s=t_end)
    out_step = t_end / 1000 if output_step_s is None else output_step_s
    out_step = check_range("output_step_s", out_step, 1e-12, t_end, unit="s")
    check_range("v_reg_mps", v_reg_mps, 1e-9, 1.0, unit="m/s")
    check_range("max_angle_deg", max_angle_deg, 1e-6, 90.0, unit="deg")
    return t_end, out_step, opts


# -- simulation core -------------------------------------------------------------------------
def _initial_state(name: str, value: ArrayLike, n: int, nb: int) -> np.ndarray:
    """Initial angles or rates broadcast to (n, nb), finite."""
    arr = np.asarray(value, dtype=float)
    try:
        out = np.broadcast_to(arr, (n, nb)).astype(float)
    except ValueError:
        raise ValueError(f"{name} must broadcast to ({n}, {nb}), got shape {arr.shape}") from None
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name} must be finite, got {arr!r}")
    return out


@dataclass(frozen=True)
class _Inputs:
    velocity: Profile
    preloads: list[Profile]
    friction: _FrictionSet
    sipe_friction: _FrictionSet | None
    v_reg: float

    def at(self, t: float) -> tuple[float, np.ndarray]:
        return float(self.velocity(t)), np.array([p(t) for p in self.preloads], dtype=float)


def _sgn(v: np.ndarray, v_reg: float) -> np.ndarray:
    """Sign of v regularised over v_reg (tanh), so that friction is continuous at v = 0."""
    return np.tanh(v / v_reg)


def _forces(
    model: eom.ChainModel,
    phi: np.ndarray,
    dphi: np.ndarray,
    mu_r: np.ndarray,
    v0: np.ndarray,
    y0: np.ndarray,
    inputs: _Inputs,
) -> dict[str, Any]:
    """Generalised forces at a state (broadcasting over leading axes of ``phi``).

    Ground: penalty normal force with lift-off (Eq. 5.1-5.3), friction F_F = mu F_N
    (Eq. 5.4) opposing v_rel = v0 + dx_p/dt (Eq. 5.5-5.6, sign in the module notes), mu from
    the law at |v_rel| and the nominal pressure, or the relaxed state mu_R (Eq. 5.12). Sipes:
    penalty force S and Coulomb friction R_S = mu_S S (section 5.1.2.1). Mapped to the bar
    angles by the contact points' Jacobians (Eq. 5.8, 5.10-5.11).
    """
    direction = np.where(np.asarray(v0) >= 0, 1.0, -1.0)
    kin = eom.Kinematics(model, phi)
    ground = eom.ground_contact(model, kin, dphi, y0, direction)
    v_rel = np.asarray(v0)[..., None] + ground.tip_velocity_x
    area = model.elem_length * model.width
    pressure = ground.normal_force / area
    mu = inputs.friction.steady(np.abs(v_rel), pressure)
    if inputs.friction.index.size:
        mu = mu.copy()
        mu[..., inputs.friction.index] = mu_r
    friction = mu * ground.normal_force * _sgn(v_rel, inputs.v_reg)
    q = eom.internal_forces(model, phi, dphi) + eom.generalized_force(
        ground.jac_x, ground.jac_y, -friction, ground.normal_force
    )
    out: dict[str, Any] = {
        "ground": ground,
        "kin": kin,
        "v_rel": v_rel,
        "pressure": pressure,
        "mu": mu,
        "friction": friction,
    }
    if model.n_elements > 1:
        sipe = eom.sipe_contacts(model, kin, dphi)
        s_force = model.sipe_stiffness[:, None] * sipe.penetration
        if inputs.sipe_friction is not None:
            face_area = model.width * model.bar_length  # (nb,)
            p_s = s_force / face_area
            # one law per sipe: contacts axis -2; bring it last for the law evaluation
            mu_s = inputs.sipe_friction.steady(
                np.moveaxis(np.abs(sipe.slip_velocity), -2, -1), np.moveaxis(p_s, -2, -1)
            )
            mu_s = np.moveaxis(mu_s, -1, -2)
            r_force = -mu_s * s_force * _sgn(sipe.slip_velocity, inputs.v_reg)
        else:
            r_force = np.zeros_like(s_force)
        q = q + eom.sipe_forces(sipe, s_force, r_force)
        out.update(sipe_normal=s_force, sipe_friction=r_force)
    out["q"] = q
    return out


def _jac_sparsity(n: int, nb: int, n_relaxed_index: np.ndarray) -> lil_matrix:
    """Sparsity of the Jacobian: element i couples to i-1, i, i+1 (sipe contact)."""
    nq = n * nb
    size = 2 * nq + n_relaxed_index.size
    sp = lil_matrix((size, size), dtype=int)
    relax_pos = {int(e): 2 * nq + k for k, e in enumerate(n_relaxed_index)}
    for i in range(n):
        rows = list(range(nq + i * nb, nq + (i + 1) * nb))
        for j in range(max(0, i - 1), min(n, i + 2)):
            cols = list(range(j * nb, (j + 1) * nb)) + list(range(nq + j * nb, nq + (j + 1) * nb))
            for r in rows:
                sp[r, cols] = 1
            if i in relax_pos:
                sp[relax_pos[i], cols] = 1
        for r in range(i * nb, (i + 1) * nb):
            sp[r, nq + r] = 1
        if i in relax_pos:
            for r in rows:
                sp[r, relax_pos[i]] = 1
            sp[relax_pos[i], relax_pos[i]] = 1
    return sp


def _make_inputs(
    model: eom.ChainModel,
    velocity: float | Profile,
    preload: Any,
    friction: Any,
    sipe_friction: Any,
    v_reg_mps: float,
) -> _Inputs:
    """Velocity and preload profiles and the friction laws of the ground and the sipes."""
    n = model.n_elements
    sfr = None
    if sipe_friction is not None and n > 1:
        sfr = _FrictionSet("sipe_friction", sipe_friction, n - 1, allow_relaxed=False)
    return _Inputs(
        _as_profile("velocity", velocity),
        _preloads(preload, n),
        _FrictionSet("friction", friction, n, allow_relaxed=True),
        sfr,
        float(v_reg_mps),
    )


def _initial_vector(
    model: eom.ChainModel,
    inputs: _Inputs,
    initial_angles_rad: ArrayLike | None,
    initial_rates_rad_s: ArrayLike | None,
    initial_mu: float | None,
    max_angle_deg: float,
) -> np.ndarray:
    """State at t = 0: bar angles, rates and mu_R of the relaxed contacts (Eq. 5.12).

    mu_R starts at ``initial_mu`` or at the steady value of the initial state.
    """
    n, nb = model.n_elements, model.n_bars
    fr = inputs.friction
    phi0 = np.zeros((n, nb))
    dphi0 = np.zeros((n, nb))
    if initial_angles_rad is not None:
        phi0 = _initial_state("initial_angles_rad", initial_angles_rad, n, nb)
        if np.any(np.abs(phi0) >= math.radians(max_angle_deg)):
            raise ValueError(
                f"initial_angles_rad must lie within +-max_angle_deg={max_angle_deg:g} deg, "
                f"got max |angle| = {math.degrees(np.abs(phi0).max()):.3g} deg"
            )
    if initial_rates_rad_s is not None:
        dphi0 = _initial_state("initial_rates_rad_s", initial_rates_rad_s, n, nb)
    v_start, y_start = inputs.at(0.0)
    if fr.index.size:
        if initial_mu is None:
            f0 = _forces(model, phi0, dphi0, np.zeros(fr.index.size), v_start, y_start, inputs)
            mu_ss = fr.steady(np.abs(f0["v_rel"]), f0["pressure"])
            mu0 = mu_ss[fr.index]
        else:
            mu0 = np.full(fr.index.size, check_range("initial_mu", initial_mu, 0.0, 10.0))
    else:
        mu0 = np.zeros(0)
    return np.concatenate([phi0.ravel(), dphi0.ravel(), mu0])


def _batched_rhs(
    model: eom.ChainModel, inputs: _Inputs
) -> Callable[[float, np.ndarray], np.ndarray]:
    """Right-hand side ``F(t, Y)`` for a batch of states ``Y`` (k, n_state) at one time."""
    n, nb = model.n_elements, model.n_bars
    nq = n * nb
    fr = inputs.friction

    def rhs_batch(t: float, ys: np.ndarray) -> np.ndarray:
        k = ys.shape[0]
        phi = ys[:, :nq].reshape(k, n, nb)
        dphi = ys[:, nq : 2 * nq].reshape(k, n, nb)
        mu_r = ys[:, 2 * nq :]
        v0, y0 = inputs.at(t)
        f = _forces(model, phi, dphi, mu_r, v0, y0, inputs)
        ddphi = eom.accelerations(model, phi, dphi, f["q"])
        parts = [dphi.reshape(k, nq), ddphi.reshape(k, nq)]
        if fr.index.size:
            parts.append(fr.relax_rate(mu_r, np.abs(f["v_rel"]), f["pressure"]))
        return np.concatenate(parts, axis=1)

    return rhs_batch


def _integrate(
    model: eom.ChainModel,
    inputs: _Inputs,
    y_init: np.ndarray,
    *,
    name: str,
    t_end: float,
    out_step: float,
    opts: SolverOptions,
    max_angle_deg: float,
) -> tuple[Any, float]:
    """Integrate until ``t_end``; stop with :class:`SimulationError` at ``max_angle_deg``.

    Returns the :func:`scipy.integrate.solve_ivp` solution and the wall time, s.
    """
    n, nb = model.n_elements, model.n_bars
    nq = n * nb
    fr = inputs.friction
    rhs_batch = _batched_rhs(model, inputs)
    rhs = finite_rhs(
        rhs_batch,
        name,
        "non-finite accelerations or friction; reduce the load or the time step",
    )
    # Forward-difference Jacobian, all columns in one batched evaluation (the engine
    # broadcasts over a leading axis), returned sparse for large blocks (element i couples
    # only to i-1, i, i+1 through the sipe contacts).
    floor = np.concatenate([np.full(nq, 1e-3), np.full(nq, 1.0), np.full(fr.index.size, 1e-3)])
    pattern = _jac_sparsity(n, nb, fr.index).toarray().astype(bool)
    sparse_jac = opts.method != "LSODA" and pattern.shape[0] > 60  # LSODA takes dense only
    jac = batched_fd_jacobian(rhs_batch, floor, name, pattern=pattern if sparse_jac else None)
    limit = math.radians(max_angle_deg)

    def too_large(t: float, y: np.ndarray) -> float:
        return limit - float(np.max(np.abs(y[:nq])))

    too_large.terminal = True  # type: ignore[attr-defined]

    t_eval = output_times(t_end, out_step)
    start = time.perf_counter()
    sol = solve_ivp(
        rhs,
        (0.0, t_end),
        y_init,
        t_eval=t_eval,
        events=too_large,
        jac=jac,
        **opts.solve_ivp_options(),
    )
    runtime = time.perf_counter() - start
    if sol.status == 1:
        t_hit = float(sol.t_events[0][0])
        y_hit = sol.y_events[0][0][:nq].reshape(n, nb)
        i, j = np.unravel_index(int(np.argmax(np.abs(y_hit))), (n, nb))
        raise SimulationError(
            f"{name}: deflection angle of element {i}, bar {j} reached {max_angle_deg:g} deg "
            f"at t={t_hit:.6g} s: the element buckled under the normal force or the "
            "integration diverged (the rigid-bar model is meaningless beyond this angle)"
        )
    raise_if_failed(sol, name)
    logger.debug("%s: %d rhs evaluations in %.2f s", name, sol.nfev, runtime)
    return sol, runtime


def _simulate(
    model: eom.ChainModel,
    *,
    name: str,
    velocity: float | Profile,
    preload: Any,
    friction: Any,
    sipe_friction: Any,
    t_end_s: float,
    solver: SolverOptions | None,
    output_step_s: float | None,
    v_reg_mps: float,
    max_angle_deg: float,
    initial_angles_rad: ArrayLike | None,
    initial_rates_rad_s: ArrayLike | None,
    initial_mu: float | None,
    params: dict[str, Any],
) -> SimulationResult:
    """Check the options, integrate the chain model and tabulate the result."""
    t_end, out_step, opts = _check_options(
        t_end_s=t_end_s,
        solver=solver,
        output_step_s=output_step_s,
        v_reg_mps=v_reg_mps,
        max_angle_deg=max_angle_deg,
    )
    inputs = _make_inputs(model, velocity, preload, friction, sipe_friction, v_reg_mps)
    y_init = _initial_vector(
        model, inputs, initial_angles_rad, initial_rates_rad_s, initial_mu, max_angle_deg
    )
    sol, runtime = _integrate(
        model,
        inputs,
        y_init,
        name=name,
        t_end=t_end,
        out_step=out_step,
        opts=opts,
        max_angle_deg=max_angle_deg,
    )
    data, fields = _tidy(model, sol.t, sol.y, inputs)
    n, nb = model.n_elements, model.n_bars
    meta = {
        "model": name,
        "params": params,
        "method": opts.method,
        "rtol": opts.rtol,
        "atol": opts.atol,
        "nfev": int(sol.nfev),
        "njev": int(sol.njev),
        "nlu": int(sol.nlu),
        "runtime_s": runtime,
        "equations": "Eq. 5.1-5.12" if n > 1 or nb > 1 else "Eq. 5.1-5.9, 5.12",
    }
    return SimulationResult(data=data, fields=fields, meta=meta)


def _tidy(
    model: eom.ChainModel, t: np.ndarray, y: np.ndarray, inputs: _Inputs
) -> tuple[pd.DataFrame, dict[str, np.ndarray]]:
    """Evaluate every force at the output times and build the tidy table."""
    n, nb = model.n_elements, model.n_bars
    nq = n * nb
    phi = y[:nq].T.reshape(-1, n, nb)
    dphi = y[nq : 2 * nq].T.reshape(-1, n, nb)
    mu_r = y[2 * nq :].T
    vy = [inputs.at(float(tt)) for tt in t]
    v0 = np.array([a for a, _ in vy])
    y0 = np.stack([b for _, b in vy]) if len(vy) else np.zeros((0, n))
    f = _forces(model, phi, dphi, mu_r, v0, y0, inputs)
    ground: eom.GroundContact = f["ground"]
    tip_x, tip_y = f["kin"].point(nb - 1, model.bar_length[-1], 0.0)
    tip_depth = -tip_y
    cols: dict[str, np.ndarray] = {
        "time_s": np.repeat(t, n),
        "element": np.tile(np.arange(n), t.size),
        "angle_deg": np.degrees(np.arctan2(-tip_x, tip_depth)).ravel(),
    }
    if nb == 2:
        cols["angle_upper_deg"] = np.degrees(phi[..., 0]).ravel()
        cols["angle_lower_deg"] = np.degrees(phi[..., 1]).ravel()
    elif nb > 2:
        for j in range(nb):
            cols[f"angle_bar{j}_deg"] = np.degrees(phi[..., j]).ravel()
    cols.update(
        tip_deflection_mm=(-tip_x * 1e3).ravel(),
        normal_force_N=ground.normal_force.ravel(),
        friction_force_N=f["friction"].ravel(),
        v_rel_mps=f["v_rel"].ravel(),
        mu=f["mu"].ravel(),
        contact=(ground.normal_force > 0).ravel(),
    )
    if model.contact_model == "face":
        cols["contact_fraction"] = ground.fraction.ravel()
    sipe_n = np.zeros((t.size, n))
    sipe_r = np.zeros((t.size, n))
    if n > 1:
        pair_n = f["sipe_normal"].sum(axis=(-3, -1))  # (T, N-1)
        pair_r = np.abs(f["sipe_friction"]).sum(axis=(-3, -1))
        sipe_n[:, :-1] += pair_n
        sipe_n[:, 1:] += pair_n
        sipe_r[:, :-1] += pair_r
        sipe_r[:, 1:] += pair_r
    cols.update(
        sipe_force_N=sipe_n.ravel(),
        sipe_friction_N=sipe_r.ravel(),
        v0_mps=np.repeat(v0, n),
        preload_mm=(y0 * 1e3).ravel(),
    )
    fields = {"time_s": t, "phi_rad": phi, "dphi_rad_s": dphi}
    return pd.DataFrame(cols), fields


# -- public API ------------------------------------------------------------------------------
def simulate_sdof(
    params: SdofParams,
    *,
    velocity: float | Profile,
    preload: float | Profile,
    friction: Any,
    t_end_s: float,
    solver: SolverOptions | None = None,
    output_step_s: float | None = None,
    v_reg_mps: float = 1e-3,
    max_angle_deg: float = 80.0,
    initial_angle_rad: float = 0.0,
    initial_rate_rad_s: float = 0.0,
    initial_mu: float | None = None,
) -> SimulationResult:
    """Simulate the single-DOF element (Eq. 5.1-5.9) sliding over the ground.

    Equation of motion (Eq. 5.8 with Eq. 5.9, plus the gravity of the hanging bar)::

        J_A ddphi = -d_phi dphi - c_phi phi + F_F d cos phi + F_N d sin phi
                    - m g (d/2) sin phi

    with F_N = c_N max(u_N, 0), u_N = y_N + d cos phi - y0 (Eq. 5.1-5.3, lift-off when
    u_N <= 0), F_F = mu F_N (Eq. 5.4) and v_rel = v0 - d cos phi dphi (module notes on the
    sign of Eq. 5.5/5.6).

    Parameters
    ----------
    params : SdofParams
    velocity : float or callable
        Sliding velocity v0 (m/s) or a profile v0(t) (:func:`~._common.velocity_step`, ...).
    preload : float or callable
        Preload distance y0 (m) from the joint to the ground, or a profile y0(t)
        (:func:`~._common.surface_profile`).
    friction : friction law or RelaxedFriction
        Anything with ``mu(v_rel_mps, *, pressure_Pa=None, temperature_C=None)``; a
        :class:`~friction_model.contact.laws.RelaxedFriction` adds the state mu_R of Eq. 5.12. The
        law gets the nominal pressure F_N / (l w).
    t_end_s : float
        Simulated time, s.
    solver : SolverOptions, optional
        Implicit solver of :func:`scipy.integrate.solve_ivp` (the penalty contact is stiff),
        its tolerances (angles in rad, rates in rad/s) and largest step; unset fields take
        :data:`~friction_model.dynamics.solver.RIGID_SOLVER` (LSODA, rtol 1e-6, atol 1e-9).
        Set ``max_step_s`` below the shortest feature of the input profiles.
    output_step_s : float, optional
        Spacing of the output times, s; default t_end_s / 1000.
    v_reg_mps : float
        Velocity over which the friction direction is regularised, m/s.
    max_angle_deg : float
        The integration stops with :class:`SimulationError` when |phi| reaches this angle.
    initial_angle_rad, initial_rate_rad_s : float
        Initial state.
    initial_mu : float, optional
        Initial mu_R of a relaxed law; default the steady value at t = 0.

    Returns
    -------
    SimulationResult
        ``data`` columns: time_s, element (0), angle_deg, tip_deflection_mm, normal_force_N,
        friction_force_N, v_rel_mps, mu, contact, sipe_force_N (0), sipe_friction_N (0),
        v0_mps, preload_mm.

    Raises
    ------
    ValueError
        For out-of-range options (before any integration).
    SimulationError
        If the integration fails or |phi| reaches ``max_angle_deg`` (buckling, divergence).
    """
    if not isinstance(params, SdofParams):
        raise TypeError(f"params must be SdofParams, got {type(params).__name__}")
    return _simulate(
        params.chain_model(),
        name="SDOF rigid bar (Eq. 5.1-5.9)",
        velocity=velocity,
        preload=preload,
        friction=friction,
        sipe_friction=None,
        t_end_s=t_end_s,
        solver=solver,
        output_step_s=output_step_s,
        v_reg_mps=v_reg_mps,
        max_angle_deg=max_angle_deg,
        initial_angles_rad=np.array([[initial_angle_rad]], dtype=float),
        initial_rates_rad_s=np.array([[initial_rate_rad_s]], dtype=float),
        initial_mu=initial_mu,
        params=asdict(params),
    )


def simulate_block_dynamics(
    params: BlockParams,
    *,
    velocity: float | Profile,
    preload: float | Profile | Sequence[float | Profile],
    friction: Any,
    sipe_friction: Any = None,
    t_end_s: float,
    solver: SolverOptions | None = None,
    output_step_s: float | None = None,
    v_reg_mps: float = 1e-3,
    max_angle_deg: float = 80.0,
    initial_angles_rad: ArrayLike | None = None,
    initial_rates_rad_s: ArrayLike | None = None,
    initial_mu: float | None = None,
) -> SimulationResult:
    """Simulate the siped block of N multi-bar elements (section 5.1.2, Eq. 5.10-5.12).

    Parameters
    ----------
    params : BlockParams
    velocity : float or callable
        Sliding velocity v0 (m/s) or a profile v0(t), e.g. a step (Fig. 5.7).
    preload : float, callable or sequence
        Preload distance y0 (m) or profile y0(t), shared or one per element (a rough
        surface reaches the elements one after another: :func:`element_surface_profiles`).
    friction : law, RelaxedFriction or sequence of them
        Ground friction, one shared or one per element (e.g. per-element
        :class:`~friction_model.DryWetLaw`, Fig. 4.25); RelaxedFriction adds Eq. 5.12.
    sipe_friction : law or sequence of laws, optional
        Friction between neighbours in each sipe (R_S = mu S, e.g. snow in the sipe); None:
        frictionless sipes (R_S = 0, as in Fig. 5.4-5.5). The law gets the contact pressure
        S / (w d_bar).
    t_end_s, solver, output_step_s, v_reg_mps, max_angle_deg
        As in :func:`simulate_sdof`.
    initial_angles_rad, initial_rates_rad_s : array_like, optional
        Initial bar angles (rad) and rates (rad/s), broadcast to (N, n_bars); default 0.
    initial_mu : float, optional
        Initial mu_R of relaxed laws; default the steady value at t = 0.

    Returns
    -------
    SimulationResult
        ``data`` columns per time and element: time_s, element, angle_deg (angle of the
        chord from the joint to the bottom centre of the element, positive trailing),
        angle_upper_deg / angle_lower_deg (bars at the base / at the ground, two-bar
        elements), tip_deflection_mm (backward displacement of the bottom centre),
        normal_force_N, friction_force_N, v_rel_mps, mu, contact, contact_fraction
        (``"face"`` contact only), sipe_force_N and sipe_friction_N (contact with both
        neighbours), v0_mps, preload_mm. ``fields``: phi_rad (T, N, n_bars), dphi_rad_s.

    Raises
    ------
    ValueError
        For out-of-range options (before any integration).
    SimulationError
        If the integration fails or an angle reaches ``max_angle_deg``.
    """
    if not isinstance(params, BlockParams):
        raise TypeError(f"params must be BlockParams, got {type(params).__name__}")
    return _simulate(
        params.chain_model(),
        name=f"siped block, {params.n_elements} x {params.n_bars}-bar elements (Eq. 5.10-5.12)",
        velocity=velocity,
        preload=preload,
        friction=friction,
        sipe_friction=sipe_friction,
        t_end_s=t_end_s,
        solver=solver,
        output_step_s=output_step_s,
        v_reg_mps=v_reg_mps,
        max_angle_deg=max_angle_deg,
        initial_angles_rad=initial_angles_rad,
        initial_rates_rad_s=initial_rates_rad_s,
        initial_mu=initial_mu,
        params=asdict(params),
    )


def element_surface_profiles(
    params: BlockParams,
    y0_m: float,
    heights_m: ArrayLike,
    positions_m: ArrayLike,
    velocity: Callable[[float], float],
    *,
    t_max_s: float,
    dt_s: float = 1e-5,
) -> list[Profile]:
    """Preload profiles y0_i(t) of every element crossing a rough surface (Fig. 5.6).

    Element i sits ``params.element_offsets_m[i]`` behind the leading element, so it meets
    a surface feature when the block has travelled that much further:
    ``y0_i(t) = y0_m - z(s(t) - offset_i)`` with :func:`~._common.surface_profile`. The
    shift of the contact point by the element's deflection (< 1 mm) is neglected.

    Parameters
    ----------
    params : BlockParams
    y0_m : float
        Preload distance on a flat surface, m.
    heights_m, positions_m : array_like
        Surface heights z (m) at distances s (m) travelled by the leading element.
    velocity : callable
        v0(t), m/s.
    t_max_s, dt_s : float
        Span and step of the tabulated travel s(t), s.

    Returns
    -------
    list of callable
        One y0_i(t) per element.
    """
    pos = np.asarray(positions_m, dtype=float)
    return [
        surface_profile(y0_m, heights_m, pos + off, velocity, t_max_s=t_max_s, dt_s=dt_s)
        for off in params.element_offsets_m
    ]
