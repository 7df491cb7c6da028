"""Timoshenko beam model of one tread-block element sliding on ice (thesis section 5.3).

The element is a cantilever: clamped at the block base (x = 0), its free end x = d (the sipe
depth, element height) touches the ice. Deflection r(x, t) and cross-section rotation
phi(x, t) obey the Timoshenko equations with Kelvin-Voigt damping k_i and the axial (normal)
force N (Eq. 5.15/5.16, 5.25/5.26), discretised by finite differences in x
(:mod:`friction_model.dynamics._timoshenko_fdm`, second order) and integrated in time by a
stiff implicit solver (``scipy.integrate`` BDF or Radau) with an analytic sparse Jacobian.

Sign convention
---------------
* x runs from the clamped root (x = 0) to the tip (x = d).
* r is positive in the direction of the sliding velocity v0 as it enters Eq. 5.23: v0 > 0
  is the velocity of the ice surface relative to the element root (the block itself moves
  over the ice in -r). The friction force F_R = mu(v_rel) N drags the tip towards +r, so
  steady sliding with v0 > 0 gives r(d) > 0 (the 1.6 mm of Fig. 5.13).
* phi is the rotation of the cross-section, positive in the sense of a positive slope
  r' (pure bending: phi = r'); the shear strain is gamma = r' - phi. The thesis writes
  Eq. 5.15/5.16 with the opposite rotation, gamma = r' + phi_thesis, i.e.
  phi_thesis = -phi; the equations below are Eq. 5.25/5.26 rewritten in phi.
* N > 0 is the compressive contact force; the lever arm e > 0 puts it in front of the axis
  (towards -r, the leading edge of the sliding element).

Equations (Eq. 5.25-5.29 in this convention, default Haringx beam-column)::

    rho A r_tt   = kappa G A (1 + k_i d/dt) (r' - phi)' - N phi'
    rho I phi_tt = E I (1 + k_i d/dt) phi'' + kappa G A (1 + k_i d/dt) (r' - phi) + N (r' - phi)
    r(0) = 0, phi(0) = 0 or E I phi'(0) = k_theta phi(0) (elastic root)  (Eq. 5.27)
    E I (1 + k_i d/dt) phi'(d) = -M_R = -e N                         (Eq. 5.20, 5.28)
    kappa G A (1 + k_i d/dt) (r' - phi)(d) - N phi(d) = F_R = mu(v_rel) N   (Eq. 5.29)
    v_rel = v0(t) - dr/dt(d, t)                                     (Eq. 5.23, corrected)
    N = N(t) applied (default), or N = c_N max(0, y_N + d - delta(u) - y0(t)) (Eq. 5.1-5.3)

with the tip rise delta = u^T G u / 2 (Haringx: (1/2) int (r'^2 - (r' - phi)^2) dx; the beam
analogue of d cos(phi) in Eq. 5.3; switch off with ``foreshortening=False``), the lever arm
e(phi(d)) of Eq. 5.21/5.22 and the friction law of Eq. 5.24 (or any law of
:mod:`friction_model.contact.laws`, optionally relaxed by Eq. 5.12). Initial state Eq. 5.30: rest.
N is the vertical ice reaction, fixed in direction (a dead load); with the axial terms
derived from its potential the undamped, frictionless element conserves energy.

Thesis slips handled here
-------------------------
* Eq. 5.19 prints Cowper's shear coefficient of a rectangle as 10 (1 - nu) / (12 + 11 nu);
  Cowper's formula is 10 (1 + nu) / (12 + 11 nu), which is the printed value 6/7 for
  nu = 0.5 (the printed formula would give 5/17.5 = 0.286).
* Eq. 5.23 writes v_rel = v0 - dphi/dt(d, t), mixing a velocity with an angular velocity;
  the relative sliding velocity is v0 minus the tip velocity dr/dt(d, t), as in Eq. 5.5.
* Eq. 5.12 (relaxation) is used in its physical form tau dmu/dt + mu = mu_ss
  (see :class:`friction_model.contact.laws.RelaxedFriction`).

Modelling notes
---------------
* Eq. 5.25/5.26 as printed (``beam_column="thesis_literal"``) put ``- N (r' - phi)`` in the
  moment equation and leave ``N phi(d)`` out of the tip's transverse balance (Eq. 5.29): the
  normal force then follows the tip face, its operator is strongly non-symmetric
  (||G - G^T|| / ||G|| ~ 1.9) and it feeds energy into the element (a follower load); it
  has no static buckling. That is neither the Haringx nor the Engesser beam-column, and the
  ice reaction is vertical, not turning with the tip face. The default is therefore the
  Haringx form (force balance with the shear force normal to the rotated cross-section:
  ``+ N (r' - phi)``, tip balance with ``- N phi(d)``), conservative and with the buckling
  load N (1 + N / kGA) = pi^2 E I / (4 d^2); ``"engesser"`` is the other classical form.
  With rubber calibrated to the measured deflection N is a large fraction of the buckling
  load, so the form matters (the printed one gives a bending angle of 8.7-9.2 deg, thesis
  ~14 deg).
* The rig loads the block through a soft spring (nearly constant force); the default load
  is an applied normal force. A fixed preload distance (stiff penalty c_N, Eq. 5.1/5.2)
  unloads the element as its tip rises; it remains available (``preload=``).
* The block base under the sipes is not rigid: ``root_stiffness_Nm_per_rad`` adds a root
  rotation spring (identified from the measured 1.6 mm deflection in
  :mod:`friction_model.compound`).
* The lever arm of Eq. 5.21/5.22 is odd in the tip rotation; its sign switch at phi = 0 is
  smoothed over ``lever_arm_smoothing_rad`` (a jump of 2 e(0+) otherwise). Its moment
  e N acts against the tilt: the normal force moves to the leading edge as the element
  tilts and straightens it (Fig. 5.11). Taken literally in the thesis's rotation
  (phi_thesis = -phi, Eq. 5.28 with +M_R) Eq. 5.21/5.22 would make the moment reinforce the
  tilt. Default e1..e4 reproduce Fig. 5.12 a: e ~ 0 up to 10 deg, e -> 1.9 mm beyond 40 deg.
  A constant ``lever_arm_m`` models a fixed front-edge offset (a pressure peak at the
  leading edge, Fig. 5.11 a).
* Friction laws that are even in v (all laws but Eq. 5.24, which is odd and signed) get
  the direction of v_rel through a smoothed sign, mu(v) = v / sqrt(v^2 + eps^2) *
  mu_law(sqrt(v^2 + eps^2)) with eps = ``friction_smoothing_mps``.
"""

from __future__ import annotations

import logging
import math
import numbers
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg
from scipy.integrate import BDF, Radau
from scipy.optimize import brentq

from friction_model.compound import REFERENCE_COMPOUND
from friction_model.contact.laws import RelaxedFriction
from friction_model.dynamics._common import (
    Profile,
    SimulationError,
    SimulationResult,
    constant_preload,
    constant_velocity,
)
from friction_model.dynamics._timoshenko_fdm import (
    BEAM_COLUMN_FORMS,
    FdmSystem,
    assemble,
    tip_slope,
)
from friction_model.dynamics.solver import TIMOSHENKO_SOLVER, SolverOptions
from tir_common.validate import check_number, check_positive, check_range

logger = logging.getLogger(__name__)

__all__ = [
    "TimoshenkoParams",
    "beam_column_static",
    "buckling_load",
    "cowper_shear_coefficient",
    "fdm_buckling_load",
    "fdm_natural_frequencies",
    "fdm_static_deflection",
    "lever_arm",
    "natural_frequencies_timoshenko",
    "preload_for_normal_force",
    "simulate_timoshenko",
    "static_tip_deflection",
]

#: Frequency at which the default Kelvin-Voigt damping has the compound's loss factor, Hz.
_KV_REFERENCE_HZ = 1000.0
#: Lever arm reached at large tilt in Fig. 5.12 a (e ~ 1.9 mm beyond 40 deg), m.
LEVER_ARM_MAX_FIG_5_12_M = 1.9e-3
#: Minimum ratio height / length of a beam-like element (below it the element is a pad).
MIN_ASPECT_RATIO = 0.5
#: Probe speed used to classify a friction law as odd (signed) or even, m/s.
_PROBE_V = 1.0
_SOLVERS = {"BDF": BDF, "Radau": Radau}
#: Ranges (low, high, unit) of the scalar fields of :class:`TimoshenkoParams`, checked in
#: this order; the fields in :data:`_OPTIONAL` may also be None.
_BOUNDS: dict[str, tuple[float, float, str]] = {
    "E_Pa": (1e3, 1e12, "Pa"),
    "density_kg_m3": (100.0, 3e4, "kg/m^3"),
    "kelvin_voigt_s": (0.0, 1.0, "s"),
    "length_m": (1e-5, 1.0, "m"),
    "width_m": (1e-5, 10.0, "m"),
    "height_m": (1e-4, 1.0, "m"),
    "contact_stiffness_N_m": (1.0, 1e12, "N/m"),
    "spring_length_m": (0.0, 1.0, "m"),
    "e1": (-1e3, 1e3, ""),
    "e2_per_rad": (0.0, 1e4, "1/rad"),
    "lever_arm_smoothing_rad": (1e-12, 0.1, "rad"),
    "root_stiffness_Nm_per_rad": (1e-6, 1e9, "N m/rad"),
    "friction_smoothing_mps": (1e-12, 1.0, "m/s"),
}
_OPTIONAL = frozenset({"contact_stiffness_N_m", "root_stiffness_Nm_per_rad"})


def cowper_shear_coefficient(nu: float) -> float:
    """Cowper's shear coefficient of a rectangular cross-section (Eq. 5.19, corrected).

    kappa = 10 (1 + nu) / (12 + 11 nu); the thesis prints ``1 - nu`` in the numerator but
    the value 6/7 it gives for rubber (nu = 0.5) is that of the formula here.

    Parameters
    ----------
    nu : float
        Poisson's ratio, in [-1, 0.5].

    Returns
    -------
    float
        kappa, dimensionless.

    Examples
    --------
    >>> cowper_shear_coefficient(0.5) == 6 / 7
    True
    """
    nu = check_range("nu", nu, -1.0, 0.5)
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


@dataclass(frozen=True)
class TimoshenkoParams:
    """Geometry, material, contact and grid of one tread-block element (Eq. 5.14-5.22).

    Parameters
    ----------
    E_Pa : float
        Young's modulus E, Pa, in [1e3, 1e12]; default E0 of the one rubber
        (:data:`friction_model.compound.REFERENCE_COMPOUND`, Shore A 60, 3.61 MPa).
    density_kg_m3 : float
        Rubber density rho, kg/m^3, in [100, 30000]; default the compound's.
    kelvin_voigt_s : float
        Kelvin-Voigt damping k_i of Eq. 5.25/5.26, s, in [0, 1]; default the compound's
        loss factor at 1 kHz (the order of the element's first mode): tan(delta) / (2 pi
        1 kHz) = 32 us.
    contact_stiffness_N_m : float, optional
        Penalty stiffness c_N of the ice contact (Eq. 5.1), N/m, in [1, 1e12], used with a
        preload distance; default E A / d, the element's compression stiffness.
    height_m : float
        Element height d (sipe depth, beam length), m; default 6 mm as in section 5.3.
        Must be >= 1e-4 m and >= 0.5 length_m (a beam, not a pad).
    length_m : float
        Element length l in the sliding direction (beam thickness), m; default 4.55 mm,
        an element of the thesis's three-siped block G3 ((20 mm - 3 x 0.6 mm) / 4).
    width_m : float
        Element width w across the sliding direction, m; default 80 mm (thesis samples).
    G_Pa : float, optional
        Shear modulus, Pa; default E / 3 (rubber, nu = 0.5). Must give nu = E/(2G) - 1 in
        [-0.99, 0.5].
    shear_coefficient : float, optional
        kappa in (0, 1]; default Cowper's value for nu (6/7 for nu = 0.5, Eq. 5.19).
    spring_length_m : float
        Undeformed penalty-spring length y_N of Eq. 5.2, m, >= 0; default 0.
    e1 : float
        Lever-arm parameter e1 of Eq. 5.21/5.22, dimensionless, in [-1e3, 1e3].
    e2_per_rad : float
        Lever-arm parameter e2, 1/rad, in [0, 1e4].
    e3_m, e4_m : float, optional
        Lever-arm parameters e3, e4, m. Default: chosen so that e(0) = 0 and
        e -> 1.9 mm at large tilt (Fig. 5.12 a); give both or neither.
    lever_arm_m : float, optional
        A constant lever arm (front-edge offset of the normal force, m, in [-l/2, l/2])
        used instead of Eq. 5.21/5.22.
    lever_arm_smoothing_rad : float
        Angle over which the sign switch of Eq. 5.21/5.22 at phi = 0 is smoothed, rad, in
        (0, 0.1].
    foreshortening : bool
        Include the tip rise (1/2) int r'^2 dx in the penetration (default True).
    beam_column : {"haringx", "engesser", "thesis_literal", "none"}
        Form of the axial-force terms (N vertical, fixed in direction). ``"haringx"``
        (default): the conservative beam-column with the shear force normal to the rotated
        cross-section; ``"engesser"``: normal to the deflected axis; ``"thesis_literal"``:
        Eq. 5.25/5.26 as printed (non-conservative, see the module notes); ``"none"``: the
        plain Timoshenko equations 5.15/5.16 with N acting only through the contact.
    root_stiffness_Nm_per_rad : float, optional
        Rotational stiffness of an elastic root (the block base under the sipes), N m/rad,
        in [1e-6, 1e9]; None (default) clamps the root (Eq. 5.27).
    friction_smoothing_mps : float
        eps of the smoothed sign used with even friction laws, m/s, in (0, 1].
    n_nodes : int
        Grid nodes including the root, in [3, 2001].

    Notes
    -----
    SI units throughout. The defaults e1 = 12 and e2 = 28 / rad put the transition of the
    lever arm between 10 deg (e < 2 % of its maximum) and 40 deg (> 95 %), as Fig. 5.12 a
    describes.
    """

    E_Pa: float = REFERENCE_COMPOUND.E0_Pa
    density_kg_m3: float = REFERENCE_COMPOUND.density_kg_m3
    kelvin_voigt_s: float = REFERENCE_COMPOUND.kelvin_voigt_s(_KV_REFERENCE_HZ)
    contact_stiffness_N_m: float | None = None
    height_m: float = 6e-3
    length_m: float = 4.55e-3
    width_m: float = 80e-3
    G_Pa: float | None = None
    shear_coefficient: float | None = None
    spring_length_m: float = 0.0
    e1: float = 12.0
    e2_per_rad: float = 28.0
    e3_m: float | None = None
    e4_m: float | None = None
    lever_arm_m: float | None = None
    lever_arm_smoothing_rad: float = 1e-3
    foreshortening: bool = True
    beam_column: str = "haringx"
    root_stiffness_Nm_per_rad: float | None = None
    friction_smoothing_mps: float = 1e-3
    n_nodes: int = 40

    def __post_init__(self) -> None:
        for name, (low, high, unit) in _BOUNDS.items():
            value = getattr(self, name)
            if value is not None or name not in _OPTIONAL:
                object.__setattr__(self, name, check_range(name, value, low, high, unit=unit))
            if name == "height_m":  # the defaults below need E, w, l and d
                self._check_aspect_ratio()
                if self.contact_stiffness_N_m is None:
                    object.__setattr__(
                        self,
                        "contact_stiffness_N_m",
                        self.E_Pa * self.width_m * self.length_m / self.height_m,
                    )
        self._check_shear()
        self._check_lever_arm()
        self._check_choices()

    def _check_aspect_ratio(self) -> None:
        """A beam, not a pad: d >= :data:`MIN_ASPECT_RATIO` l (Eq. 5.14)."""
        if self.height_m < MIN_ASPECT_RATIO * self.length_m:
            raise ValueError(
                f"height_m must be >= {MIN_ASPECT_RATIO} * length_m = "
                f"{MIN_ASPECT_RATIO * self.length_m:g} m for a beam-like element (Eq. 5.14), "
                f"got height_m={self.height_m!r}"
            )

    def _check_shear(self) -> None:
        """G (Poisson's ratio nu = E/(2G) - 1 in [-0.99, 0.5]) and kappa in (0, 1]."""
        if self.G_Pa is not None:
            g = check_positive("G_Pa", self.G_Pa)
            nu = self.E_Pa / (2.0 * g) - 1.0
            if not -0.99 <= nu <= 0.5:
                raise ValueError(
                    f"G_Pa must lie in [E/3, E/0.02] = [{self.E_Pa / 3:g}, {self.E_Pa / 0.02:g}]"
                    f" Pa (Poisson's ratio nu = E/(2G) - 1 in [-0.99, 0.5]), got G_Pa={g!r}"
                )
            object.__setattr__(self, "G_Pa", g)
        if self.shear_coefficient is not None:
            k = check_number(
                "shear_coefficient", self.shear_coefficient, low=0.0, high=1.0, low_open=True
            )
            object.__setattr__(self, "shear_coefficient", k)

    def _check_lever_arm(self) -> None:
        """e3, e4 or a constant lever arm inside the contact, |e| <= l/2 (Eq. 5.21/5.22)."""
        half = 0.5 * self.length_m
        if (self.e3_m is None) != (self.e4_m is None):
            raise ValueError(
                f"e3_m and e4_m must be given together, got e3_m={self.e3_m!r}, e4_m={self.e4_m!r}"
            )
        if self.e3_m is not None:
            object.__setattr__(self, "e3_m", check_range("e3_m", self.e3_m, -half, half, unit="m"))
            object.__setattr__(self, "e4_m", check_range("e4_m", self.e4_m, -half, half, unit="m"))
        if self.lever_arm_m is not None:
            arm = check_range("lever_arm_m", self.lever_arm_m, -half, half, unit="m")
            object.__setattr__(self, "lever_arm_m", arm)
        elif self.e3_m is None and LEVER_ARM_MAX_FIG_5_12_M > half:
            raise ValueError(
                f"the default lever arm of Fig. 5.12 a (up to 1.9 mm) exceeds length_m / 2 = "
                f"{half:g} m (Eq. 5.21/5.22: e_max = l/2); give e3_m and e4_m or lever_arm_m"
            )
        else:
            e3, e4 = self.lever_arm_e3_e4
            phis = np.linspace(0.0, 0.5 * math.pi, 181)
            e_vals = _lever_magnitude(phis, self.length_m, self.e1, self.e2_per_rad, e3, e4)
            if np.any(np.abs(e_vals) > half * (1 + 1e-9)):
                raise ValueError(
                    "e1, e2_per_rad, e3_m, e4_m must keep the lever arm of Eq. 5.21/5.22 inside"
                    f" the contact area |e| <= l/2 = {half:g} m for |phi| <= 90 deg, got e "
                    f"ranging over [{e_vals.min():g}, {e_vals.max():g}] m"
                )

    def _check_choices(self) -> None:
        """``foreshortening`` (bool), ``beam_column`` (a form) and ``n_nodes`` (3-2001)."""
        if not isinstance(self.foreshortening, bool):
            raise TypeError(
                f"foreshortening must be a bool, got {type(self.foreshortening).__name__}"
            )
        if self.beam_column not in BEAM_COLUMN_FORMS:
            raise ValueError(
                f"beam_column must be one of {BEAM_COLUMN_FORMS}, "
                f"got beam_column={self.beam_column!r}"
            )
        if isinstance(self.n_nodes, bool) or not isinstance(self.n_nodes, numbers.Integral):
            raise TypeError(
                f"n_nodes must be an integer, got {type(self.n_nodes).__name__}: {self.n_nodes!r}"
            )
        if not 3 <= int(self.n_nodes) <= 2001:
            raise ValueError(f"n_nodes must lie in [3, 2001], got n_nodes={self.n_nodes!r}")
        object.__setattr__(self, "n_nodes", int(self.n_nodes))

    # -- derived quantities --------------------------------------------------------------
    @property
    def shear_modulus_Pa(self) -> float:
        """G, Pa (E / 3 unless given)."""
        return self.E_Pa / 3.0 if self.G_Pa is None else float(self.G_Pa)

    @property
    def poisson_ratio(self) -> float:
        """nu = E / (2 G) - 1."""
        return self.E_Pa / (2.0 * self.shear_modulus_Pa) - 1.0

    @property
    def kappa(self) -> float:
        """Shear coefficient kappa (Cowper, Eq. 5.19 corrected, unless given)."""
        if self.shear_coefficient is not None:
            return float(self.shear_coefficient)
        return cowper_shear_coefficient(min(self.poisson_ratio, 0.5))

    @property
    def area_m2(self) -> float:
        """Cross-section A = w l, m^2 (Eq. 5.18)."""
        return self.width_m * self.length_m

    @property
    def second_moment_m4(self) -> float:
        """I = w l^3 / 12, m^4 (Eq. 5.17)."""
        return self.width_m * self.length_m**3 / 12.0

    @property
    def EI(self) -> float:
        """Bending stiffness E I, N m^2."""
        return self.E_Pa * self.second_moment_m4

    @property
    def kGA(self) -> float:
        """Shear stiffness A_K G = kappa G A, N (Eq. 5.18)."""
        return self.kappa * self.shear_modulus_Pa * self.area_m2

    @property
    def rhoA(self) -> float:
        """Mass per length rho A, kg/m."""
        return self.density_kg_m3 * self.area_m2

    @property
    def rhoI(self) -> float:
        """Rotary inertia per length rho I, kg m."""
        return self.density_kg_m3 * self.second_moment_m4

    @property
    def lever_arm_e3_e4(self) -> tuple[float, float]:
        """(e3, e4) of Eq. 5.21/5.22, m: the given values or the Fig. 5.12 a defaults."""
        if self.e3_m is not None and self.e4_m is not None:
            return float(self.e3_m), float(self.e4_m)
        l_ = self.length_m
        span = LEVER_ARM_MAX_FIG_5_12_M / (0.5 + math.atan(self.e1) / math.pi)  # l/2 - e4
        e4 = 0.5 * l_ - span
        e3 = 0.25 * l_ + 0.5 * span - LEVER_ARM_MAX_FIG_5_12_M
        return e3, e4


# -- lever arm (Eq. 5.20-5.22) -----------------------------------------------------------
def _lever_magnitude(
    a: np.ndarray | float, length_m: float, e1: float, e2: float, e3: float, e4: float
) -> np.ndarray:
    """Bracket of Eq. 5.21 at the tilt a = |phi|: l/4 - e3 + atan(-e1 + e2 a) (l/2 - e4) / pi, m."""
    return (
        0.25 * length_m - e3 + np.arctan(-e1 + e2 * np.asarray(a)) / math.pi * (0.5 * length_m - e4)
    )


def _lever_and_slope(params: TimoshenkoParams, phi: float) -> tuple[float, float]:
    """Lever arm e(phi) (m) and de/dphi (m/rad) at a scalar tip rotation."""
    if params.lever_arm_m is not None:
        return float(params.lever_arm_m), 0.0
    e3, e4 = params.lever_arm_e3_e4
    l_, e1, e2 = params.length_m, params.e1, params.e2_per_rad
    a = abs(phi)
    arg = -e1 + e2 * a
    mag = 0.25 * l_ - e3 + math.atan(arg) / math.pi * (0.5 * l_ - e4)
    dmag = e2 / (math.pi * (1.0 + arg * arg)) * (0.5 * l_ - e4)
    th = math.tanh(phi / params.lever_arm_smoothing_rad)
    sgn = 1.0 if phi >= 0 else -1.0
    return mag * th, dmag * sgn * th + mag * (1.0 - th * th) / params.lever_arm_smoothing_rad


def lever_arm(params: TimoshenkoParams, phi_tip_rad: float | np.ndarray) -> np.ndarray | float:
    """Lever arm e of the normal force at the tip (Eq. 5.21/5.22), m.

    Parameters
    ----------
    params : TimoshenkoParams
        Supplies l, e1..e4 (or the constant ``lever_arm_m``) and the sign smoothing.
    phi_tip_rad : float or ndarray
        Tip rotation phi(d), rad (positive: tilted by friction under v0 > 0).

    Returns
    -------
    float or ndarray
        e, m; positive = in front of the axis (towards -r). Odd in phi: Eq. 5.21 for
        phi >= 0, Eq. 5.22 for phi < 0, the switch smoothed over
        ``params.lever_arm_smoothing_rad``.

    Examples
    --------
    >>> p = TimoshenkoParams(E_Pa=3e6, density_kg_m3=1150.0, kelvin_voigt_s=1e-4,
    ...                      contact_stiffness_N_m=1e6)
    >>> lever_arm(p, 0.0) == 0.0, round(lever_arm(p, math.radians(60)) * 1e3, 2)
    (True, 1.86)
    """
    phi = np.asarray(phi_tip_rad, dtype=float)
    if params.lever_arm_m is not None:
        out = np.full_like(phi, float(params.lever_arm_m))
    else:
        e3, e4 = params.lever_arm_e3_e4
        mag = _lever_magnitude(np.abs(phi), params.length_m, params.e1, params.e2_per_rad, e3, e4)
        out = mag * np.tanh(phi / params.lever_arm_smoothing_rad)
    return float(out) if out.ndim == 0 else out


def preload_for_normal_force(params: TimoshenkoParams, normal_force_N: float) -> float:
    """Preload distance y0 giving ``normal_force_N`` on the undeformed element (Eq. 5.1/5.2), m.

    y0 = y_N + d - F_N / c_N: the distance from the element root to the ice surface.

    Examples
    --------
    >>> p = TimoshenkoParams(E_Pa=3e6, density_kg_m3=1150.0, kelvin_voigt_s=1e-4,
    ...                      contact_stiffness_N_m=1e6)
    >>> round(preload_for_normal_force(p, 50.0) * 1e3, 6)
    5.95
    """
    f = check_range("normal_force_N", normal_force_N, 0.0, 1e9, unit="N")
    return params.spring_length_m + params.height_m - f / params.contact_stiffness_N_m


# -- statics and modes -------------------------------------------------------------------
def static_tip_deflection(
    params: TimoshenkoParams, force_N: float, *, moment_Nm: float = 0.0
) -> float:
    """Exact static tip deflection of the clamped-free Timoshenko beam, m.

    r(d) = P d^3 / (3 E I) + P d / (kappa G A) + M d^2 / (2 E I) for a transverse tip force P
    and a tip moment M (positive: bending towards +r; the offset moment of Eq. 5.20 is
    M = -e N). Solves Eq. 5.15/5.16 with q = 0 and the boundary conditions Eq. 5.27-5.29
    at rest without axial force. An elastic root (``root_stiffness_Nm_per_rad`` k) adds the
    rigid rotation of the beam: d (M + P d) / k.

    Examples
    --------
    >>> p = TimoshenkoParams(E_Pa=3e6, density_kg_m3=1150.0, kelvin_voigt_s=0.0,
    ...                      contact_stiffness_N_m=1e6)
    >>> round(static_tip_deflection(p, 10.0) * 1e3, 4)
    0.5745
    """
    P = check_number("force_N", force_N)
    M = check_number("moment_Nm", moment_Nm)
    d = params.height_m
    out = P * d**3 / (3.0 * params.EI) + P * d / params.kGA + M * d**2 / (2.0 * params.EI)
    if params.root_stiffness_Nm_per_rad is not None:
        out += d * (M + P * d) / params.root_stiffness_Nm_per_rad
    return out


def beam_column_static(
    params: TimoshenkoParams,
    force_N: float,
    *,
    axial_force_N: float,
    moment_Nm: float = 0.0,
) -> tuple[float, float]:
    """Closed-form static tip deflection and rotation of the loaded beam-column, (m, rad).

    The cantilever (clamped, or on the elastic root of ``params``) carries at its tip a
    transverse force P, a moment M and a compressive axial force N > 0 that keeps its
    vertical direction (dead load). With the moment M(x) = M + P (d - x) + N (r(d) - r(x))
    and the shear force of the chosen form (Haringx: kGA gamma = P + N phi; Engesser:
    kGA gamma = P + N r'), phi obeys phi'' + a^2 phi = -a^2 P / N with

    * Haringx: a^2 = N (1 + N / kGA) / EI, r' = (1 + N / kGA) phi + P / kGA,
    * Engesser: a^2 = N / (EI (1 - N / kGA)), r' = (phi + P / kGA) / (1 - N / kGA),

    and EI phi'(0) = k_theta phi(0) (phi(0) = 0 when clamped), EI phi'(d) = M. This is
    the static form of the conservative beam-column of section 5.3 (Eq. 5.25/5.26 with
    the Haringx or Engesser axial terms, Eq. 5.27-5.29); an independent truth for the
    finite differences of :func:`fdm_static_deflection`.

    Parameters
    ----------
    params : TimoshenkoParams
        Beam; ``beam_column`` must be ``"haringx"`` or ``"engesser"``.
    force_N : float
        Transverse tip force P, N (+r).
    axial_force_N : float
        Compressive axial force N, N, > 0 and below the buckling load.
    moment_Nm : float
        Tip moment M, N m (positive bends towards +r).

    Returns
    -------
    r_tip_m, phi_tip_rad : float
        r(d) and phi(d).
    """
    if params.beam_column not in ("haringx", "engesser"):
        raise ValueError(
            "beam_column_static needs beam_column 'haringx' or 'engesser', "
            f"got {params.beam_column!r}"
        )
    P = check_number("force_N", force_N)
    M = check_number("moment_Nm", moment_Nm)
    N = check_number("axial_force_N", axial_force_N)
    if not 0.0 < N < buckling_load(params):
        raise ValueError(
            f"axial_force_N must lie in (0, buckling load {buckling_load(params):g} N), got {N!r}"
        )
    EI, kGA, d = params.EI, params.kGA, params.height_m
    haringx = params.beam_column == "haringx"
    a_fac = 1.0 + N / kGA if haringx else 1.0 / (1.0 - N / kGA)
    a = math.sqrt(N * a_fac / EI)
    # phi = A sin(a x) + B cos(a x) - P / N
    k_root = params.root_stiffness_Nm_per_rad
    sa, ca = math.sin(a * d), math.cos(a * d)
    # rows: root condition, tip moment condition
    if k_root is None:
        mat = np.array([[0.0, 1.0], [a * ca, -a * sa]])
    else:
        mat = np.array([[-EI * a / k_root, 1.0], [a * ca, -a * sa]])
    rhs = np.array([P / N, M / EI])
    A, B = np.linalg.solve(mat, rhs)
    int_phi = A * (1.0 - ca) / a + B * sa / a - P / N * d
    phi_tip = A * sa + B * ca - P / N
    r_tip = a_fac * int_phi + P * d / kGA if haringx else a_fac * (int_phi + P * d / kGA)
    return float(r_tip), float(phi_tip)


def buckling_load(params: TimoshenkoParams) -> float:
    """Closed-form buckling load of the cantilever beam-column under a dead load, N.

    With the Euler load P_E of the column (clamped: pi^2 EI / (4 d^2); on an elastic root
    of stiffness k: P_E = EI z^2 / d^2 with z tan(z) = k d / EI), Haringx gives
    N (1 + N / kGA) = P_E, i.e. N = kGA (sqrt(1 + 4 P_E / kGA) - 1) / 2, and Engesser
    N / (1 - N / kGA) = P_E, i.e. N = P_E / (1 + P_E / kGA) (Bazant & Cedolin, Stability of
    Structures, section 1.7). ``"none"`` and ``"thesis_literal"`` have no static buckling
    under N (the printed form treats N as a follower load): inf.

    Parameters
    ----------
    params : TimoshenkoParams

    Returns
    -------
    float
        Critical compressive force, N.
    """
    if params.beam_column not in ("haringx", "engesser"):
        return math.inf
    EI, kGA, d = params.EI, params.kGA, params.height_m
    if params.root_stiffness_Nm_per_rad is None:
        z = 0.5 * math.pi
    else:
        beta = params.root_stiffness_Nm_per_rad * d / EI
        z = brentq(lambda z: z * math.tan(z) - beta, 1e-12, 0.5 * math.pi - 1e-12, xtol=1e-15)
    P_E = EI * z * z / d**2
    if params.beam_column == "haringx":
        return 0.5 * kGA * (math.sqrt(1.0 + 4.0 * P_E / kGA) - 1.0)
    return P_E / (1.0 + P_E / kGA)


def fdm_buckling_load(params: TimoshenkoParams) -> float:
    """Smallest compressive N with (K - N G) singular in the finite differences, N.

    Parameters
    ----------
    params : TimoshenkoParams
        Beam and grid; ``beam_column`` ``"haringx"`` or ``"engesser"`` (symmetric G).

    Returns
    -------
    float
        The buckling load of the discretised element, N (second order in the grid).
    """
    if params.beam_column not in ("haringx", "engesser"):
        raise ValueError(
            f"fdm_buckling_load needs a conservative beam_column, got {params.beam_column!r}"
        )
    sysm = _system(params)
    # K x = N G x  <=>  G x = (1/N) K x with K positive definite: largest 1/N
    lam = scipy.linalg.eigh(sysm.G.toarray(), sysm.K.toarray(), eigvals_only=True)
    return float(1.0 / lam.max())


def _system(params: TimoshenkoParams, n_nodes: int | None = None) -> FdmSystem:
    return assemble(
        height_m=params.height_m,
        EI=params.EI,
        kGA=params.kGA,
        rhoA=params.rhoA,
        rhoI=params.rhoI,
        n_nodes=params.n_nodes if n_nodes is None else n_nodes,
        beam_column=params.beam_column,
        root_stiffness_Nm_per_rad=params.root_stiffness_Nm_per_rad,
    )


def fdm_static_deflection(
    params: TimoshenkoParams,
    force_N: float,
    *,
    moment_Nm: float = 0.0,
    axial_force_N: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Static deflection of the FDM model under a tip force, moment and axial force.

    Solves (K - N G) u = f with the operators of ``params.beam_column``.

    Parameters
    ----------
    params : TimoshenkoParams
        Beam and grid (``n_nodes``).
    force_N : float
        Transverse tip force P, N (+r).
    moment_Nm : float
        Tip moment M, N m (positive bends towards +r).
    axial_force_N : float
        Compressive axial force N on the tip, N (vertical dead load; 0: none).

    Returns
    -------
    x_m, r_m, phi_rad : (n_nodes,) ndarray
        Node positions, deflection and rotation (root included).
    """
    P = check_number("force_N", force_N)
    M = check_number("moment_Nm", moment_Nm)
    N = check_number("axial_force_N", axial_force_N)
    sysm = _system(params)
    f = np.zeros(sysm.n_u)
    f[sysm.tip_r] = P
    f[sysm.tip_phi] = M
    u = sp.linalg.spsolve((sysm.K - N * sysm.G).tocsc(), f)
    m = sysm.m
    r = np.concatenate([[0.0], u[:m]])
    phi0 = u[2 * m] if sysm.has_root_rotation else 0.0
    phi = np.concatenate([[phi0], u[m : 2 * m]])
    return sysm.x.copy(), r, phi


def _check_n_modes(n_modes: int) -> int:
    if isinstance(n_modes, bool) or not isinstance(n_modes, numbers.Integral):
        raise TypeError(f"n_modes must be an integer, got {type(n_modes).__name__}")
    if not 1 <= int(n_modes) <= 50:
        raise ValueError(f"n_modes must lie in [1, 50], got n_modes={n_modes!r}")
    return int(n_modes)


def fdm_natural_frequencies(params: TimoshenkoParams, n_modes: int = 3) -> np.ndarray:
    """Undamped natural frequencies of the FDM model without contact, Hz.

    Eigenvalues omega^2 of K x = omega^2 M x with the stiffness and lumped mass of
    :mod:`friction_model.dynamics._timoshenko_fdm` (Eq. 5.15/5.16 with Eq. 5.27-5.29 free),
    ``params.n_nodes`` nodes.

    Returns
    -------
    (n_modes,) ndarray
        f_k = omega_k / (2 pi), ascending, Hz.
    """
    n_modes = _check_n_modes(n_modes)
    sysm = _system(params)
    if n_modes > 2 * sysm.m:
        raise ValueError(
            f"n_modes must be <= 2 (n_nodes - 1) = {2 * sysm.m} for this grid, got {n_modes}"
        )
    s = 1.0 / np.sqrt(sysm.mass)
    A = sysm.K.toarray() * s[:, None] * s[None, :]
    w2 = scipy.linalg.eigh(A, eigvals_only=True, subset_by_index=[0, n_modes - 1])
    return np.sqrt(np.maximum(w2, 0.0)) / (2.0 * math.pi)


def _frequency_determinant(omega: float, params: TimoshenkoParams) -> float:
    """Clamped-free boundary determinant of the Timoshenko beam at circular frequency omega.

    Harmonic solutions r, phi ~ exp(s x) of Eq. 5.15/5.16 (q = 0) have s^2 = S with
    S^2 + omega^2 rho (1/E + 1/(kappa G)) S + rho A omega^2 (rho I omega^2 - kappa G A)
    / (kappa G A E I) = 0 (two real roots S1 > S2). With C_S(x) = cosh(sqrt(S) x) (cos for
    S < 0), f_S(x) = sinh(sqrt(S) x) / sqrt(S) (sin .. for S < 0) and q = rho omega^2 /
    (kappa G), the solutions are R = C_S, Phi = (S + q) f_S and R = S f_S / (S + q),
    Phi = C_S (entire in S, so no spurious root at the cut-off frequency where S1 = 0).
    r(0) = phi(0) = 0 leaves a 2x2 determinant of phi'(d) = 0, r'(d) - phi(d) = 0.
    """
    rho, E, G, kap = params.density_kg_m3, params.E_Pa, params.shear_modulus_Pa, params.kappa
    A, I2, d = params.area_m2, params.second_moment_m4, params.height_m
    kGA, EI = kap * G * A, E * I2
    w2 = omega * omega
    c1 = w2 * rho * (1.0 / E + 1.0 / (kap * G))
    c0 = rho * A * w2 * (rho * I2 * w2 - kGA) / (kGA * EI)
    root = math.sqrt(c1 * c1 - 4.0 * c0)
    q = rho * w2 / (kap * G)
    cols = []
    for S in (0.5 * (-c1 + root), 0.5 * (-c1 - root)):
        if S > 0:
            a = math.sqrt(S)
            C, f = math.cosh(a * d), math.sinh(a * d) / a
        elif S < 0:
            b = math.sqrt(-S)
            C, f = math.cos(b * d), math.sin(b * d) / b
        else:
            C, f = 1.0, d
        # (phi'(d), r'(d) - phi(d)) of the solutions (R = C_S, Phi = (S + q) f_S) and
        # (R = S f_S / (S + q), Phi = C_S)
        cols.append(((S + q) * C, -q * f, S * f, -q * C / (S + q)))
    (a1, b1, c1_, d1), (a2, b2, c2, d2) = cols
    # r(0) = 0 and phi(0) = 0 give A2 = -A1, B2 = -B1
    m11, m21, m12, m22 = a1 - a2, b1 - b2, c1_ - c2, d1 - d2
    return m11 * m22 - m12 * m21


def natural_frequencies_timoshenko(params: TimoshenkoParams, n_modes: int = 3) -> np.ndarray:
    """Natural frequencies of the clamped-free Timoshenko beam from its frequency equation, Hz.

    Roots of the boundary determinant of the exact harmonic solution of Eq. 5.15/5.16
    (clamped at x = 0, free at x = d; see :func:`_frequency_determinant`), bracketed on a
    frequency grid and refined with Brent's method. This is the clamped-free frequency
    equation of Huang (1961, J. Appl. Mech. 28, 579-584) in the form of Han, Benaroya & Wei
    (1999, J. Sound Vib. 225, 935-988, section 6), valid below and above the cut-off
    frequency sqrt(kappa G A / (rho I)).

    Parameters
    ----------
    params : TimoshenkoParams
        Geometry and material (the grid is not used).
    n_modes : int
        Number of frequencies, in [1, 50].

    Returns
    -------
    (n_modes,) ndarray
        Ascending natural frequencies, Hz.
    """
    n_modes = _check_n_modes(n_modes)
    if params.root_stiffness_Nm_per_rad is not None:
        raise ValueError(
            "natural_frequencies_timoshenko solves the clamped-free beam; with "
            "root_stiffness_Nm_per_rad use fdm_natural_frequencies"
        )
    d = params.height_m
    # Euler-Bernoulli first circular frequency as the scale of the grid
    w_eb = 1.8751040687**2 * math.sqrt(params.EI / (params.rhoA * d**4))
    step = 0.01 * w_eb
    w_lo = 1e-3 * w_eb
    f_lo = _frequency_determinant(w_lo, params)
    roots: list[float] = []
    w_max = w_eb * (4.0 * n_modes + 4.0) ** 2
    while len(roots) < n_modes:
        w_hi = w_lo + step
        if w_hi > w_max:
            raise RuntimeError(
                f"found only {len(roots)} of {n_modes} frequencies below {w_max / 2 / math.pi:g} Hz"
            )
        f_hi = _frequency_determinant(w_hi, params)
        if f_lo == 0.0:
            roots.append(w_lo)
        elif f_lo * f_hi < 0.0:
            roots.append(
                brentq(_frequency_determinant, w_lo, w_hi, args=(params,), xtol=1e-12, rtol=1e-14)
            )
        w_lo, f_lo = w_hi, f_hi
    return np.asarray(roots[:n_modes]) / (2.0 * math.pi)


# -- friction ----------------------------------------------------------------------------
class _Friction:
    """Signed friction coefficient mu(v_rel, p) with the derivatives the Jacobian needs."""

    def __init__(
        self, law: Any, *, smoothing_mps: float, temperature_C: float | None, contact_area_m2: float
    ) -> None:
        if not callable(getattr(law, "mu", None)):
            raise TypeError(
                "friction must be a friction law with mu(v_rel_mps, *, pressure_Pa, "
                f"temperature_C) or a RelaxedFriction, got {type(law).__name__}"
            )
        self.law = law
        self.eps = smoothing_mps
        self.temperature_C = temperature_C
        self.area = contact_area_m2
        p_ref = 2.5e5
        mu_p = float(self._raw(_PROBE_V, p_ref))
        mu_m = float(self._raw(-_PROBE_V, p_ref))
        scale = max(abs(mu_p), abs(mu_m), 1e-300)
        if not (math.isfinite(mu_p) and math.isfinite(mu_m)):
            raise ValueError(f"friction law gives non-finite mu at v = +-{_PROBE_V} m/s")
        if abs(mu_p + mu_m) <= 1e-9 * scale and mu_p != 0.0:
            self.signed = True
        elif abs(mu_p - mu_m) <= 1e-9 * scale:
            self.signed = False
        else:
            raise ValueError(
                "friction law must be odd in v (signed, like Eq. 5.24) or even (a magnitude), "
                f"got mu(+{_PROBE_V}) = {mu_p!r} and mu(-{_PROBE_V}) = {mu_m!r}"
            )
        mu_p2 = float(self._raw(_PROBE_V, 2.0 * p_ref))
        self.pressure_dependent = mu_p2 != mu_p

    def _raw(self, v: Any, p: Any) -> Any:
        return self.law.mu(v, pressure_Pa=p, temperature_C=self.temperature_C)

    def mu(self, v: Any, normal_force: Any) -> Any:
        """Signed mu at relative velocity v (m/s) and normal force (N); numpy-vectorised."""
        p = np.asarray(normal_force, dtype=float) / self.area
        if self.signed:
            return self._raw(v, p)
        v = np.asarray(v, dtype=float)
        vs = np.sqrt(v * v + self.eps * self.eps)
        return v / vs * np.asarray(self._raw(vs, p), dtype=float)

    def scalar(self, v: float, normal_force: float) -> float:
        return float(self.mu(v, normal_force))

    def dmu_dv(self, v: float, normal_force: float) -> float:
        dv = 1e-7 + 1e-6 * abs(v)
        return (self.scalar(v + dv, normal_force) - self.scalar(v - dv, normal_force)) / (2 * dv)

    def dmu_dN(self, v: float, normal_force: float) -> float:
        if not self.pressure_dependent:
            return 0.0
        dn = 1e-6 * max(abs(normal_force), 1.0)
        lo = max(normal_force - dn, 0.0)
        return (self.scalar(v, normal_force + dn) - self.scalar(v, lo)) / (normal_force + dn - lo)


def _as_profile(name: str, value: Profile | float, factory: Callable[[float], Profile]) -> Profile:
    if callable(value):
        out = value
    else:
        factory_value = check_range(name, value, -1e6, 1e6)
        out = factory(factory_value)
    v = out(0.0)
    if not math.isfinite(float(v)):
        raise ValueError(f"{name}(0) must be finite, got {v!r}")
    return out


# -- the ODE system ----------------------------------------------------------------------
class _TimoshenkoProblem:
    """First-order ODE y' = f(t, y) of the discretised element with its analytic Jacobian.

    State ``y = [u, v, (mu_R)]``: u = [r_1..r_m, phi_1..phi_m] (m, rad), v = du/dt and, for
    a :class:`RelaxedFriction` with tau > 0, the relaxed friction coefficient mu_R (Eq. 5.12).
    The Jacobian is sparse CSC with a fixed pattern (see :meth:`jac`).
    """

    def __init__(
        self,
        params: TimoshenkoParams,
        *,
        velocity: Profile,
        preload: Profile | None,
        friction: Any,
        normal_force: Profile | None = None,
        temperature_C: float | None = None,
        mu_initial: float | None = None,
        initial_tip_force_N: float = 0.0,
    ) -> None:
        self.params = params
        self.v0 = velocity
        self.y0 = preload
        self.applied = normal_force
        if (preload is None) == (normal_force is None):
            raise ValueError("give exactly one of preload and normal_force")
        law, tau = friction, 0.0
        if isinstance(friction, RelaxedFriction):
            law, tau = friction.law, float(friction.tau_s)
        self.tau = tau
        self.relaxed = tau > 0.0
        self.fr = _Friction(
            law,
            smoothing_mps=params.friction_smoothing_mps,
            temperature_C=temperature_C,
            contact_area_m2=params.area_m2,
        )
        sysm = _system(params)
        self.sys = sysm
        m = sysm.m
        self.m, self.n2 = m, sysm.n_u
        self.dim = 2 * sysm.n_u + (1 if self.relaxed else 0)
        G = sysm.G
        self.G_sparse = G.tocsr()
        self.K = sysm.operator("K")
        self.G = G.toarray() if isinstance(self.K, np.ndarray) else self.G_sparse
        self.S = sysm.operator("S")
        # N depends on the deflection only through the tip rise of a fixed preload distance
        self.coupled = params.foreshortening and normal_force is None
        self.minv = 1.0 / sysm.mass
        self.k = params.kelvin_voigt_s
        self.cN = params.contact_stiffness_N_m
        self.base_gap = params.spring_length_m + params.height_m
        self.h = sysm.h
        self.ir, self.ip = sysm.tip_r, sysm.tip_phi
        self.nfev = 0
        self.njev = 0

        y = np.zeros(self.dim)
        f_init = check_number("initial_tip_force_N", initial_tip_force_N)
        if f_init != 0.0:
            f = np.zeros(self.n2)
            f[self.ir] = f_init
            y[: self.n2] = scipy.sparse.linalg.spsolve(sysm.K.tocsc(), f)
        if self.relaxed:
            if mu_initial is None:
                n0 = self.normal_force(0.0, y[: self.n2])[0]
                mu_initial = self.fr.scalar(self.v0(0.0) - y[self.n2 + self.ir], n0)
            y[-1] = check_range("mu_initial", mu_initial, -10.0, 10.0)
        self.y_init = y
        self._build_pattern()

    # -- pieces ----------------------------------------------------------------------
    def normal_force(self, t: float, u: np.ndarray) -> tuple[float, np.ndarray | None]:
        """Normal force N (N) and dN/du (None if N does not depend on u).

        An applied force (``normal_force``) is used as given (clipped at 0). A preload
        distance gives the penalty contact of Eq. 5.1/5.2, N = c_N max(0, y_N + d - delta(u)
        - y0(t)), with the tip rise delta = u^T S u / 2 (with ``foreshortening``).
        """
        if self.applied is not None:
            return max(float(self.applied(t)), 0.0), None
        pen = self.base_gap - float(self.y0(t))
        Su = None
        if self.params.foreshortening:
            Su = np.asarray(self.S @ u, dtype=float)
            pen -= 0.5 * float(u @ Su)
        if pen <= 0.0:
            return 0.0, None
        if Su is None:
            return self.cN * pen, None
        return self.cN * pen, -self.cN * Su

    def fun(self, t: float, y: np.ndarray) -> np.ndarray:
        """Right-hand side dy/dt (Eq. 5.25-5.29 in space, Eq. 5.12 for mu_R)."""
        self.nfev += 1
        n2 = self.n2
        u = y[:n2]
        v = y[n2 : 2 * n2]
        N, _ = self.normal_force(t, u)
        v_rel = float(self.v0(t)) - v[self.ir]
        out = np.empty_like(y)
        out[:n2] = v
        mu_law = self.fr.scalar(v_rel, N)
        if not math.isfinite(mu_law):
            raise SimulationError(
                f"friction law gave mu = {mu_law!r} at t = {t:.6g} s (v_rel = {v_rel:.6g} m/s, "
                f"N = {N:.6g} N)"
            )
        if self.relaxed:
            mu = y[-1]
            out[-1] = (mu_law - mu) / self.tau
        else:
            mu = mu_law
        F = self.K @ (u + self.k * v)
        np.negative(F, out=F)
        if N != 0.0:
            F += N * (self.G @ u)
            e, _ = _lever_and_slope(self.params, u[self.ip])
            F[self.ir] += mu * N
            F[self.ip] -= e * N
        np.multiply(F, self.minv, out=out[n2 : 2 * n2])
        return out

    def _tip_terms(
        self, t: float, y: np.ndarray
    ) -> tuple[float, np.ndarray | None, float, float, float, float, float]:
        """N, dN/dr, mu, dmu/dv_rel, dmu/dN, e, de/dphi at the state y."""
        n2 = self.n2
        u = y[:n2]
        N, dN = self.normal_force(t, u)
        v_rel = float(self.v0(t)) - y[n2 + self.ir]
        mu = y[-1] if self.relaxed else self.fr.scalar(v_rel, N)
        dmu_dv = self.fr.dmu_dv(v_rel, N)
        dmu_dN = self.fr.dmu_dN(v_rel, N)
        e, de = _lever_and_slope(self.params, u[self.ip])
        return N, dN, mu, dmu_dv, dmu_dN, e, de

    def _build_pattern(self) -> None:
        """Fixed CSC pattern of the Jacobian and the constant parts of its data."""
        n2, dim, ir, ip = self.n2, self.dim, self.ir, self.ip
        K = self.sys.K.tocsr()
        G = self.G_sparse
        minv = sp.diags(self.minv)
        eye = sp.identity(n2, format="csr")
        tip = sp.csr_matrix(([1.0, 1.0], ([ir, ip], [ir, ip])), shape=(n2, n2))
        ones_u = abs(K) + abs(G) + tip
        ones_v = abs(K) + tip
        blocks: list[list[Any]] = [[None, eye], [ones_u, ones_v]]
        if self.relaxed:
            col = sp.csr_matrix(([1.0], ([ir], [0])), shape=(n2, 1))
            row_u = sp.csr_matrix(np.ones((1, n2)) if self.coupled else np.zeros((1, n2)))
            row_v = sp.csr_matrix(([1.0], ([0], [ir])), shape=(1, n2))
            blocks = [
                [None, eye, None],
                [ones_u, ones_v, col],
                [row_u, row_v, sp.csr_matrix([[1.0]])],
            ]
        pattern = sp.bmat(blocks, format="csc")
        if self.coupled:
            dense_block = sp.bmat(
                [
                    [sp.csr_matrix((n2, dim))],
                    [sp.hstack([sp.csr_matrix(np.ones((n2, n2))), sp.csr_matrix((n2, dim - n2))])],
                    [sp.csr_matrix((dim - 2 * n2, dim))],
                ],
                format="csc",
            )
            pattern = (abs(pattern) + dense_block).tocsc()
        pattern.data[:] = 1.0
        pattern.sort_indices()
        self._indices, self._indptr = pattern.indices, pattern.indptr
        self._rows = pattern.indices
        self._cols = np.repeat(np.arange(dim), np.diff(pattern.indptr))
        lookup = {
            (int(r), int(c)): k for k, (r, c) in enumerate(zip(self._rows, self._cols, strict=True))
        }
        self._lookup = lookup

        def data_of(mat: sp.spmatrix, r0: int, c0: int) -> np.ndarray:
            out = np.zeros(self._rows.size)
            coo = mat.tocoo()
            idx = [
                lookup[(int(r) + r0, int(c) + c0)] for r, c in zip(coo.row, coo.col, strict=True)
            ]
            np.add.at(out, np.asarray(idx, dtype=int), coo.data)
            return out

        self._data0 = (
            data_of(eye, 0, n2)
            + data_of(minv @ (-K), n2, 0)
            + data_of(minv @ (-self.k * K), n2, n2)
        )
        self._dataG = data_of(minv @ G, n2, 0)
        self._pos_fric = lookup[(n2 + ir, n2 + ir)]
        self._pos_lever = lookup[(n2 + ip, ip)]
        if self.relaxed:
            self._pos_mu_col = lookup[(n2 + ir, dim - 1)]
            self._pos_mu_mu = lookup[(dim - 1, dim - 1)]
            self._pos_mu_v = lookup[(dim - 1, n2 + ir)]
        if self.coupled:
            rr, cc = np.meshgrid(np.arange(n2), np.arange(n2), indexing="ij")
            self._pos_block = np.array(
                [lookup[(int(r) + n2, int(c))] for r, c in zip(rr.ravel(), cc.ravel(), strict=True)]
            ).reshape(n2, n2)
            if self.relaxed:
                self._pos_mu_r = np.array([lookup[(dim - 1, j)] for j in range(n2)])

    def jac(self, t: float, y: np.ndarray) -> sp.csc_matrix:
        """Analytic Jacobian df/dy, sparse CSC with a fixed pattern.

        The pattern is the banded stencil of K and G (interleaved r, phi: bandwidth 3 per
        node pair), the identity block du/dt = v, the tip entries (friction slope, lever
        arm, relaxed mu_R) and, with ``foreshortening``, the rank-one block of the contact
        force's dependence on all deflections (dN/dr, rows c = dF/dN). That block is needed:
        it is a third of the static tip stiffness, and Newton stalls at large steps without it.
        """
        self.njev += 1
        n2, ir, ip = self.n2, self.ir, self.ip
        N, dN, mu, dmu_dv, dmu_dN, e, de = self._tip_terms(t, y)
        data = self._data0.copy()
        if N != 0.0:
            data += N * self._dataG
            data[self._pos_lever] -= de * N * self.minv[ip]
            if not self.relaxed:
                data[self._pos_fric] -= N * dmu_dv * self.minv[ir]
            if self.relaxed:
                data[self._pos_mu_col] = N * self.minv[ir]
            if dN is not None:
                c = np.asarray(self.G_sparse @ y[:n2], dtype=float).copy()
                c[ir] += mu + (0.0 if self.relaxed else N * dmu_dN)
                c[ip] -= e
                data[self._pos_block] += np.outer(c * self.minv, dN)
                if self.relaxed and self.fr.pressure_dependent:
                    data[self._pos_mu_r] = dmu_dN * dN / self.tau
        if self.relaxed:
            data[self._pos_mu_mu] = -1.0 / self.tau
            data[self._pos_mu_v] = -dmu_dv / self.tau
        return sp.csc_matrix((data, self._indices, self._indptr), shape=(self.dim, self.dim))

    # -- outputs ---------------------------------------------------------------------
    def columns(self, t: np.ndarray, Y: np.ndarray) -> tuple[pd.DataFrame, dict[str, np.ndarray]]:
        """Result table and fields from states ``Y`` (n_t, dim) at times ``t``."""
        m, n2, h = self.m, self.n2, self.h
        zeros = np.zeros((len(t), 1))
        r_full = np.hstack([zeros, Y[:, :m]])
        phi0 = Y[:, 2 * m : 2 * m + 1] if self.sys.has_root_rotation else zeros
        phi_full = np.hstack([phi0, Y[:, m : 2 * m]])
        v_tip = Y[:, n2 + self.ir]
        v0 = np.array([float(self.v0(ti)) for ti in t])
        N = np.array([self.normal_force(ti, Y[i, :n2])[0] for i, ti in enumerate(t)])
        v_rel = v0 - v_tip
        mu = Y[:, -1] if self.relaxed else np.asarray(self.fr.mu(v_rel, N), dtype=float)
        slope = tip_slope(r_full, h)
        phi_tip = phi_full[:, -1]
        e = np.asarray(lever_arm(self.params, phi_tip), dtype=float)
        data = pd.DataFrame(
            {
                "time_s": t,
                "element": np.zeros(len(t), dtype=int),
                "angle_deg": np.degrees(np.arctan(slope)),
                "tip_deflection_mm": r_full[:, -1] * 1e3,
                "bending_angle_deg": np.degrees(phi_tip),
                "shear_angle_deg": np.degrees(slope - phi_tip),
                "normal_force_N": N,
                "friction_force_N": mu * N,
                "v0_mps": v0,
                "v_rel_mps": v_rel,
                "mu": mu,
                "lever_arm_mm": e * 1e3,
                "contact": N > 0.0,
            }
        )
        fields = {
            "x_m": self.sys.x.copy(),
            "t_s": np.asarray(t, dtype=float).copy(),
            "r_m": r_full,
            "phi_rad": phi_full,
        }
        return data, fields


# -- simulation --------------------------------------------------------------------------
def simulate_timoshenko(
    params: TimoshenkoParams,
    *,
    velocity: Profile | float,
    friction: Any,
    t_end_s: float,
    normal_force: Profile | float | None = None,
    preload: Profile | float | None = None,
    n_output: int = 1001,
    solver: SolverOptions | None = None,
    temperature_C: float | None = None,
    mu_initial: float | None = None,
    initial_tip_force_N: float = 0.0,
) -> SimulationResult:
    """Simulate one Timoshenko tread-block element sliding on ice (section 5.3).

    Parameters
    ----------
    params : TimoshenkoParams
        Element, material, contact and grid.
    velocity : callable or float
        Sliding velocity v0(t) of the ice relative to the element root, m/s (Eq. 5.23); a
        number means constant.
    normal_force : callable or float, optional
        Applied normal force N(t) on the tip, N (a number means constant): the default load,
        the rig's soft loading spring (nearly constant force). Vertical, fixed in direction.
    preload : callable or float, optional
        Instead of ``normal_force``: the preload distance y0(t) from the root to the ice
        surface, m (Eq. 5.2, a stiff contact spring c_N: N falls as the element bends); a
        number means constant. See :func:`preload_for_normal_force`. Give exactly one of
        ``normal_force`` and ``preload``.
    friction : friction law or RelaxedFriction
        mu(v_rel, pressure_Pa=N/(l w), temperature_C=...) (Eq. 5.24 or any law of
        :mod:`friction_model.contact.laws`); a
        :class:`~friction_model.contact.laws.RelaxedFriction` with
        tau > 0 adds mu_R as a state (Eq. 5.12).
    t_end_s : float
        Simulated time, s, in (0, 100].
    n_output : int
        Output samples, uniformly spaced over [0, t_end_s], in [2, 10^6].
    solver : SolverOptions, optional
        Implicit integrator of :mod:`scipy.integrate` (``"BDF"`` or ``"Radau"``), relative
        tolerance in [1e-10, 0.1], absolute tolerance in [1e-14, 0.01] in units of the
        scales d (deflection), 1 rad (rotation), v_s (velocity, v_s = max(1 m/s, |v0(0)|)),
        v_s / d (rad/s) and 1 (mu), and largest time step (s); unset fields take
        :data:`~friction_model.dynamics.solver.TIMOSHENKO_SOLVER` (BDF, rtol 1e-5, atol 1e-7).
    temperature_C : float, optional
        Passed to the friction law.
    mu_initial : float, optional
        Initial mu_R of a relaxed law; default the steady value at t = 0.
    initial_tip_force_N : float
        Start from the static deflection under this tip force instead of rest (release test
        of section 5.4); default 0, the rest state of Eq. 5.30.

    Returns
    -------
    SimulationResult
        ``data``: time_s, element (0), angle_deg (tip slope alpha = atan r'(d)),
        tip_deflection_mm, bending_angle_deg (phi(d)), shear_angle_deg (r'(d) - phi(d)),
        normal_force_N, friction_force_N, v0_mps, v_rel_mps, mu, lever_arm_mm, contact;
        ``fields``: x_m (n_x,), t_s (n_t,), r_m and phi_rad (n_t, n_x); ``meta``: model,
        params, solver statistics and wall time.

    Raises
    ------
    ValueError, TypeError
        For invalid options (messages name the parameter).
    SimulationError
        If the integration fails, produces non-finite values, or the deflection leaves the
        physical bound |r| <= d (or |phi| >= 90 deg); the message gives the time.

    Notes
    -----
    Units SI; x from the clamped root. The sign convention is in the module docstring.
    """
    if not isinstance(params, TimoshenkoParams):
        raise TypeError(f"params must be a TimoshenkoParams, got {type(params).__name__}")
    t_end = check_range("t_end_s", t_end_s, 1e-9, 100.0, unit="s")
    if isinstance(n_output, bool) or not isinstance(n_output, numbers.Integral):
        raise TypeError(f"n_output must be an integer, got {type(n_output).__name__}")
    if not 2 <= int(n_output) <= 1_000_000:
        raise ValueError(f"n_output must lie in [2, 1000000], got n_output={n_output!r}")
    opts = TIMOSHENKO_SOLVER.resolve(solver, t_end_s=t_end)
    if temperature_C is not None:
        temperature_C = check_range("temperature_C", temperature_C, -273.15, 1e3, unit="degC")
    v0 = _as_profile("velocity", velocity, constant_velocity)
    if (preload is None) == (normal_force is None):
        raise ValueError(
            "give exactly one of normal_force (applied force, N) and preload (distance, m), "
            f"got normal_force={normal_force!r}, preload={preload!r}"
        )
    prob = _TimoshenkoProblem(
        params,
        velocity=v0,
        preload=None if preload is None else _as_profile("preload", preload, constant_preload),
        normal_force=(
            None
            if normal_force is None
            else _as_profile("normal_force", normal_force, constant_preload)
        ),
        friction=friction,
        temperature_C=temperature_C,
        mu_initial=mu_initial,
        initial_tip_force_N=initial_tip_force_N,
    )
    t_out = np.linspace(0.0, t_end, int(n_output))
    wall0 = time.perf_counter()
    Y, stepper, n_steps = _integrate(
        prob, t_out, opts, velocity_scale=max(1.0, abs(float(v0(0.0))))
    )
    wall = time.perf_counter() - wall0
    data, fields = prob.columns(t_out, Y)
    meta = {
        "model": "timoshenko",
        "params": asdict(params),
        "load": "preload distance" if preload is not None else "applied normal force",
        "friction": repr(friction),
        "method": opts.method,
        "rtol": opts.rtol,
        "atol": opts.atol,
        "n_steps": n_steps,
        "nfev": prob.nfev,
        "njev": prob.njev,
        "nlu": int(getattr(stepper, "nlu", 0)),
        "wall_time_s": wall,
    }
    logger.debug("Timoshenko simulation: %d steps, %d f-evals, %.3g s", n_steps, prob.nfev, wall)
    return SimulationResult(data=data, fields=fields, meta=meta)


def _integrate(
    prob: _TimoshenkoProblem, t_out: np.ndarray, opts: SolverOptions, *, velocity_scale: float
) -> tuple[np.ndarray, Any, int]:
    """Step ``prob`` to ``t_out[-1]``, filling the states at ``t_out`` from the dense output.

    The absolute tolerance is scaled per state (``solver`` of :func:`simulate_timoshenko`);
    every step is checked by :func:`_check_step`. Returns the states (n_out, dim), the
    stepper and the number of steps.
    """
    m, n2, d = prob.m, prob.n2, prob.params.height_m
    v_s = velocity_scale
    scale = np.concatenate(
        [
            np.full(m, d),
            np.ones(n2 - m),
            np.full(m, v_s),
            np.full(n2 - m, v_s / d),
            np.ones(prob.dim - 2 * n2),
        ]
    )
    Y = np.empty((t_out.size, prob.dim))
    Y[0] = prob.y_init
    k_out = 1
    stepper = _SOLVERS[opts.method](
        prob.fun,
        0.0,
        prob.y_init.copy(),
        float(t_out[-1]),
        rtol=opts.rtol,
        atol=opts.atol * scale,
        jac=prob.jac,
        max_step=np.inf if opts.max_step_s is None else opts.max_step_s,
    )
    n_steps = 0
    while stepper.status == "running":
        try:
            message = stepper.step()
        except SimulationError:
            raise
        except (ArithmeticError, ValueError, RuntimeError, np.linalg.LinAlgError) as exc:
            raise SimulationError(
                f"Timoshenko integration failed at t = {float(stepper.t):.6g} s: "
                f"{type(exc).__name__}: {exc}"
            ) from exc
        n_steps += 1
        t_now = float(stepper.t)
        _check_step(stepper, message, m, n2, d)
        if k_out < t_out.size and t_out[k_out] <= t_now:
            k_end = int(np.searchsorted(t_out, t_now, side="right"))
            dense = stepper.dense_output()
            Y[k_out:k_end] = dense(t_out[k_out:k_end]).T
            k_out = k_end
    return Y, stepper, n_steps


def _check_step(stepper: Any, message: str | None, m: int, n2: int, d: float) -> None:
    """Raise :class:`SimulationError` if the step failed, is not finite or left the bounds.

    The bounds are physical: |r| <= d and |phi| < 90 deg.
    """
    t_now = float(stepper.t)
    if stepper.status == "failed":
        raise SimulationError(f"Timoshenko integration failed at t = {t_now:.6g} s: {message}")
    y = stepper.y
    if not np.all(np.isfinite(y)):
        raise SimulationError(
            f"Timoshenko integration produced non-finite values at t = {t_now:.6g} s"
        )
    r_max = float(np.max(np.abs(y[:m])))
    phi_max = float(np.max(np.abs(y[m:n2])))
    if r_max > d or phi_max >= 0.5 * math.pi:
        raise SimulationError(
            f"Timoshenko integration diverged at t = {t_now:.6g} s: max |r| = "
            f"{r_max * 1e3:.4g} mm (bound d = {d * 1e3:g} mm), max |phi| = "
            f"{math.degrees(phi_max):.4g} deg (bound 90 deg)"
        )
