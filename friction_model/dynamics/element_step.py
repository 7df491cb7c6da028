"""Linearised tread-block element through a velocity step (Eq. 5.8 linearised, Eq. 5.12).

The leading element of a block is the rigid bar on a torsional spring and damper of Eq. 5.8,
linearised about phi = 0 with the normal force held at its preload value and driven by the
friction moment ``F_N d mu_R(t)``::

    J phi'' + d_phi phi' + (c_phi - F_N d + m g d/2) phi + sum_k q_k = F_N d mu_R   (Eq. 5.8)
    q_k' = s w_k c_phi phi' - 2 pi f_k q_k                 (frequency-dependent modulus)
    tau mu_R' + mu_R = mu_ss(v0(t))                                                (Eq. 5.12)

Two dynamic effects extend the bare element, each reducing to it exactly at its null value:

``friction_relaxation`` (Eq. 5.12)
    mu lags the steady mu_ss(v) with time constant ``tau_s`` (0: mu = mu_ss at once). The
    thesis added it to match the velocity step of Fig. 5.7.
``frequency_dependent_modulus``
    The rubber modulus follows ``E(f) = E0 (1 + s MODULUS_ALPHA log10(f / MODULUS_F0_HZ))``
    (:func:`modulus_ratio`), realised in the time domain by Maxwell arms q_k on the element's
    spring (:func:`arm_storage_ratio`); strength s = 0 leaves the constant modulus E0. The
    thesis names it as missing from the stick-slip simulation (1111 Hz against 1500 Hz
    measured, end of section 5.3.2; :func:`modulus_scaled_frequency_Hz`).

:func:`step_response` gives the deflection angle through a step of the steady friction from
``mu_before`` to ``mu_after`` (the dry/wet model's mu_ss at the two velocities, or any other
steady characteristic); :mod:`synthetic.measurements` builds its transient table on it and
:mod:`friction_model.discrepancy.transient` fits it to measured angles.

Notes
-----
Units: time s, angle degrees (rad inside), moment N m, stiffness N m/rad, frequency Hz,
pressure bar at the interface (Pa inside), modulus Pa. Time 0 of a response is arbitrary;
the element is in steady sliding (equilibrium at ``mu_before``) before ``t_step_s``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.optimize

from friction_model.dynamics.rigid import (
    REFERENCE_LOSS_FACTOR,
    REFERENCE_YOUNGS_MODULUS_PA,
    SdofParams,
)
from friction_model.geometry import BlockGeometry, as_geometry
from tir_common.validate import check_nonnegative, check_positive

__all__ = [
    "MODULUS_ALPHA",
    "MODULUS_F0_HZ",
    "TAU_REF_S",
    "StepElement",
    "arm_storage_ratio",
    "element_natural_frequency_Hz",
    "linear_step_states",
    "modulus_ratio",
    "modulus_scaled_frequency_Hz",
    "sipe_block",
    "step_element",
    "step_response",
]


#: Reference time constant of Eq. 5.12, s. The thesis identifies tau from the velocity step
#: of Fig. 5.7 but prints no value; the lag it shows there is tens of ms, far longer than the
#: element's own response (about 1 ms: natural frequency near 1 kHz, stick-slip 1111-1500 Hz
#: in section 5.3.2), which is what makes it visible to the high-speed camera. 20 ms is that
#: order and lies between the 4 ms and 30 ms used in ``examples/rough_surface.py`` and
#: ``examples/velocity_step.py``.
TAU_REF_S = 0.020
#: Slope of the rubber modulus per decade of frequency at strength 1 (dimensionless). A
#: linear viscoelastic solid whose loss factor tan(delta) does not depend on frequency (a
#: good description of filled rubber over a few decades) must by causality (Kramers-Kronig,
#: Bode's gain-phase relation) have E'(f) ~ f^n with tan(delta) = tan(n pi / 2); expanded to
#: first order in log10(f), E(f) = E0 (1 + n ln(10) log10(f / f0)). With the loss factor of
#: the reference compound, tan(delta) = 0.2 (``REFERENCE_LOSS_FACTOR`` of the dynamics),
#: n = 0.1257 and alpha = n ln 10 = 0.2894. Check against section 5.3.2: at 1.5 kHz this gives
#: E / E0 = 1.92, a frequency ratio sqrt(1.92) = 1.39 next to the measured / simulated
#: stick-slip ratio 1500 / 1111 = 1.35; the thesis names the frequency dependence of the
#: modulus as missing from that simulation.
MODULUS_ALPHA = 2.0 * math.atan(REFERENCE_LOSS_FACTOR) / math.pi * math.log(10.0)
#: Frequency at which E = E0, Hz. E0 (3.61 MPa) comes from Gent's relation with the Shore A
#: hardness, a reading taken 1-3 s after the indenter touches (ISO 7619-1, ASTM D2240): a
#: quasi-static time scale of about 1 s.
MODULUS_F0_HZ = 1.0

# Largest relative change of the natural frequency accepted as converged in the fixed point
# f = f_n(E(f)); far below any measurable difference.
_FIXED_POINT_RTOL = 1e-12
_FIXED_POINT_MAX_ITER = 200
# Maxwell arms that realise E(f) in the time domain (a Prony series): relaxation frequencies
# two per decade from MODULUS_F0_HZ to 31.6 kHz, fitted over f0 to 10 kHz, the band the
# transient table resolves (its default 10 kHz sampling; the element rings at 0.6-1 kHz).
_ARM_FREQUENCIES_HZ = MODULUS_F0_HZ * 10.0 ** (np.arange(10) / 2.0)
_ARM_FIT_MAX_HZ = 1.0e4


# -- rubber modulus and element frequency ----------------------------------------------------
def modulus_ratio(frequency_Hz: float | np.ndarray, *, strength: float) -> float | np.ndarray:
    """E(f) / E0 of the ``frequency_dependent_modulus`` effect.

    ``E(f) / E0 = 1 + strength * MODULUS_ALPHA * log10(f / MODULUS_F0_HZ)``.

    Parameters
    ----------
    frequency_Hz : float or ndarray
        Excitation frequency f, Hz, > 0.
    strength : float
        Effect strength, >= 0 (0 gives 1 exactly).

    Returns
    -------
    float or ndarray
        The ratio, dimensionless.

    Raises
    ------
    ValueError
        If f <= 0 or the ratio is not positive (far below ``MODULUS_F0_HZ`` at large strength).

    Examples
    --------
    >>> round(modulus_ratio(1000.0, strength=1.0), 4)
    1.8681
    """
    strength = check_nonnegative("frequency_dependent_modulus", strength)
    f = np.asarray(frequency_Hz, dtype=float)
    if np.any(~np.isfinite(f)) or np.any(f <= 0):
        raise ValueError(f"frequency_Hz must be finite and > 0, got {frequency_Hz!r}")
    ratio = 1.0 + strength * MODULUS_ALPHA * np.log10(f / MODULUS_F0_HZ)
    if np.any(ratio <= 0):
        raise ValueError(
            f"the modulus ratio must stay > 0, got {ratio.min():.3g} at frequency_Hz="
            f"{frequency_Hz!r} and strength={strength!r}"
        )
    return float(ratio) if ratio.ndim == 0 else ratio


def _fixed_point(fn, f_start: float) -> float:
    f = f_start
    for _ in range(_FIXED_POINT_MAX_ITER):
        f_new = fn(f)
        if abs(f_new - f) <= _FIXED_POINT_RTOL * f_new:
            return f_new
        f = f_new
    raise ValueError(
        f"the natural frequency does not converge with the frequency-dependent modulus "
        f"(last {f:.6g} Hz); lower the strength"
    )


def modulus_scaled_frequency_Hz(frequency_constant_Hz: float, *, strength: float) -> float:
    """Frequency of a mode computed with the constant modulus E0, with E = E(f) instead.

    A mode whose stiffness is proportional to E has ``f = f_c sqrt(E(f) / E0)``; this solves
    that fixed point (e.g. the stick-slip frequency of section 5.3.2).

    Parameters
    ----------
    frequency_constant_Hz : float
        Frequency f_c with the modulus E0, Hz, > 0.
    strength : float
        Strength of ``frequency_dependent_modulus``.

    Returns
    -------
    float
        The frequency, Hz.

    Examples
    --------
    >>> round(modulus_scaled_frequency_Hz(1111.0, strength=1.0))  # measured: 1500 Hz
    1540
    """
    f_c = float(frequency_constant_Hz)
    if not math.isfinite(f_c) or f_c <= 0:
        raise ValueError(f"frequency_constant_Hz must be finite and > 0, got {f_c!r}")
    return _fixed_point(lambda f: f_c * math.sqrt(modulus_ratio(f, strength=strength)), f_c)


@functools.cache
def _arm_weights() -> np.ndarray:
    """Stiffness of each Maxwell arm per unit strength, relative to the static spring.

    Non-negative least squares of ``sum_k w_k x_k^2 / (1 + x_k^2)`` (x_k = f / f_k, the
    storage stiffness of arm k) against ``MODULUS_ALPHA log10(f / MODULUS_F0_HZ)`` in relative
    terms on 401 log-spaced frequencies from MODULUS_F0_HZ to _ARM_FIT_MAX_HZ.
    """
    f = np.geomspace(MODULUS_F0_HZ, _ARM_FIT_MAX_HZ, 401)
    x = f[:, None] / _ARM_FREQUENCIES_HZ[None, :]
    basis = x**2 / (1.0 + x**2)
    target = MODULUS_ALPHA * np.log10(f / MODULUS_F0_HZ)
    weight = 1.0 / (1.0 + target)
    w, _ = scipy.optimize.nnls(basis * weight[:, None], target * weight)
    return w


def arm_storage_ratio(frequency_Hz: float | np.ndarray, *, strength: float) -> np.ndarray:
    """Storage modulus E'(f) / E0 of the time-domain model of the modulus effect.

    The transient model realises E(f) as a static spring plus Maxwell arms (a Prony series,
    two per decade from MODULUS_F0_HZ to 31.6 kHz); this is their storage modulus. From 10 Hz
    to 10 kHz it follows :func:`modulus_ratio` within 0.004 E0 per unit strength (0.3 % of E
    at strength 1); at f0, where the stated law has a kink, within 0.025 E0; below f0 it
    tends to 1. The arms also carry the loss that causality ties to the rising modulus,
    about (pi / 2) (strength alpha / ln 10) E0 = 0.2 E0 at strength 1.

    Parameters
    ----------
    frequency_Hz : float or ndarray
        Frequency, Hz, >= 0.
    strength : float
        Strength of ``frequency_dependent_modulus``.

    Returns
    -------
    ndarray
        E'(f) / E0.

    Examples
    --------
    >>> round(float(arm_storage_ratio(1000.0, strength=1.0)), 3)
    1.868
    """
    strength = check_nonnegative("frequency_dependent_modulus", strength)
    x = np.asarray(frequency_Hz, dtype=float)[..., None] / _ARM_FREQUENCIES_HZ
    return 1.0 + strength * (x**2 / (1.0 + x**2)) @ _arm_weights()


@dataclass(frozen=True)
class StepElement:
    """Linearised single element of Eq. 5.8 (small angles, constant normal force) with a
    viscoelastic torsional spring: static spring c_phi(E0), damper d_phi and Maxwell arms.

    Made by :func:`step_element`; the constants are those of
    :class:`friction_model.dynamics.rigid.SdofParams` for the leading element.

    Attributes
    ----------
    inertia_kgm2 : float
        J_A, moment of inertia about the root, kg m^2.
    spring_Nm_rad : float
        c_phi at the static modulus E0, N m/rad.
    damper_Nms_rad : float
        d_phi, N m s/rad.
    geometric_Nm_rad : float
        F_N d - m g d / 2, the softening of the normal force on the deflected tip less the
        stiffening of the bar's weight, N m/rad.
    lever_m : float
        d, the element height, m.
    normal_force_N : float
        F_N on the element, N.
    modulus_strength : float
        Strength of ``frequency_dependent_modulus`` (0: constant modulus E0).
    natural_frequency_Hz : float
        Undamped natural frequency, at the fixed point f = f_n(E(f)) with the modulus effect.
    """

    inertia_kgm2: float
    spring_Nm_rad: float
    damper_Nms_rad: float
    geometric_Nm_rad: float
    lever_m: float
    normal_force_N: float
    modulus_strength: float
    natural_frequency_Hz: float

    @property
    def stiffness_Nm_rad(self) -> float:
        """Static effective stiffness c_phi - F_N d + m g d / 2, N m/rad."""
        return self.spring_Nm_rad - self.geometric_Nm_rad

    @property
    def dynamic_modulus_Pa(self) -> float:
        """E at the natural frequency, Pa."""
        return REFERENCE_YOUNGS_MODULUS_PA * modulus_ratio(
            self.natural_frequency_Hz, strength=self.modulus_strength
        )

    @property
    def angle_per_mu_deg(self) -> float:
        """Static deflection per unit steady friction, F_N d / c_eff in degrees."""
        return math.degrees(self.normal_force_N * self.lever_m / self.stiffness_Nm_rad)

    def system(self, tau_s: float) -> tuple[np.ndarray, np.ndarray]:
        """State matrix A and input vector B (input: the steady mu) of Eq. 5.8 linearised,
        with Eq. 5.12 for tau_s > 0.

        States: phi (rad), dphi/dt (rad/s), the arm moments q_k (N m, only with the modulus
        effect) and mu_R (only with tau_s > 0)::

            J phi'' = -c_eff phi - d_phi phi' - sum q_k + F_N d mu_R
            q_k' = s w_k c_phi phi' - q_k / tau_k,   tau_k = 1 / (2 pi f_k)
            tau mu_R' = mu_ss - mu_R
        """
        j = self.inertia_kgm2
        moment = self.normal_force_N * self.lever_m
        arms = (
            self.modulus_strength * _arm_weights() * self.spring_Nm_rad
            if self.modulus_strength > 0
            else np.zeros(0)
        )
        n_arm = arms.size
        relaxed = tau_s > 0
        n = 2 + n_arm + int(relaxed)
        a = np.zeros((n, n))
        b = np.zeros(n)
        a[0, 1] = 1.0
        a[1, 0] = -self.stiffness_Nm_rad / j
        a[1, 1] = -self.damper_Nms_rad / j
        a[1, 2 : 2 + n_arm] = -1.0 / j
        rates = 2.0 * np.pi * _ARM_FREQUENCIES_HZ
        for k in range(n_arm):
            a[2 + k, 1] = arms[k]
            a[2 + k, 2 + k] = -rates[k]
        if relaxed:
            a[1, -1] = moment / j
            a[-1, -1] = -1.0 / tau_s
            b[-1] = 1.0 / tau_s
        else:
            b[1] = moment / j
        return a, b


def _element(geometry: BlockGeometry, pressure_bar: float, modulus_strength: float) -> StepElement:
    """The element of :func:`step_element` from already validated values."""
    ell = float(geometry.element_lengths[0]) * 1e-3
    width = geometry.width_mm * 1e-3
    height = geometry.height_mm * 1e-3
    # the nominal load shares equally over the elements (the sipes carry none)
    normal_force = pressure_bar * 1e5 * geometry.nominal_area_mm2 * 1e-6 / geometry.n_elements
    base = SdofParams(length_m=height, element_length_m=ell, width_m=width)
    c_phi = base.spring_constant_Nm_rad  # proportional to E (bending and shear)
    # F_N d sin(phi) (normal force on the deflected tip) softens, the hanging bar's weight
    # m g (d/2) sin(phi) stiffens (Eq. 5.8 with gravity, as in simulate_sdof)
    geometric = normal_force * height - base.mass_kg * base.gravity_mps2 * height / 2.0
    if c_phi - geometric <= 0:
        raise ValueError(
            f"the element buckles: F_N d = {normal_force * height:.4g} N m at pressure_bar="
            f"{pressure_bar:g} exceeds its rotational stiffness {c_phi:.4g} N m/rad; lower "
            "pressure_bar (is it in bar?)"
        )

    def frequency(ratio: float) -> float:
        return math.sqrt((c_phi * ratio - geometric) / base.inertia_kgm2) / (2.0 * math.pi)

    f_n = frequency(1.0)
    if modulus_strength > 0:
        f_n = _fixed_point(lambda f: frequency(modulus_ratio(f, strength=modulus_strength)), f_n)
    return StepElement(
        inertia_kgm2=base.inertia_kgm2,
        spring_Nm_rad=c_phi,
        damper_Nms_rad=base.damping_constant_Nms_rad,
        geometric_Nm_rad=geometric,
        lever_m=height,
        normal_force_N=normal_force,
        modulus_strength=float(modulus_strength),
        natural_frequency_Hz=f_n,
    )


def sipe_block(n_sipes: int) -> BlockGeometry:
    """The 20 mm x 80 mm block with ``n_sipes`` sipes, the block family of the transient model.

    Parameters
    ----------
    n_sipes : int
        Number of sipes, >= 0 (3: G3, the block of chapter 5).

    Returns
    -------
    BlockGeometry

    Examples
    --------
    >>> sipe_block(3).n_elements
    4
    """
    if isinstance(n_sipes, bool) or int(n_sipes) != n_sipes or n_sipes < 0:
        raise ValueError(f"n_sipes must be an integer >= 0, got n_sipes={n_sipes!r}")
    return BlockGeometry(n_sipes=int(n_sipes))


def element_natural_frequency_Hz(
    *, n_sipes: int = 3, pressure_bar: float = 1.2, modulus_strength: float = 0.0
) -> float:
    """Natural frequency of one loaded element of the transient model, Hz.

    ``f = sqrt((c_phi(E) - F_N d + m g d / 2) / J_A) / (2 pi)`` with the SDOF constants of
    :class:`friction_model.dynamics.rigid.SdofParams` for the leading element of a 20 mm x
    80 mm block with ``n_sipes`` sipes; with ``modulus_strength`` > 0, ``E = E(f)`` at this
    frequency (fixed point).

    Parameters
    ----------
    n_sipes : int
        Sipes of the block (3: G3, the block of chapter 5).
    pressure_bar : float
        Nominal pressure, bar; F_N = p L w / (n_sipes + 1).
    modulus_strength : float
        Strength of ``frequency_dependent_modulus``.

    Returns
    -------
    float
        Undamped natural frequency, Hz.

    Examples
    --------
    >>> f0 = element_natural_frequency_Hz()
    >>> bool(element_natural_frequency_Hz(modulus_strength=1.0) > f0)
    True
    """
    modulus_strength = check_nonnegative("frequency_dependent_modulus", modulus_strength)
    check_positive("pressure_bar", pressure_bar)
    return _element(sipe_block(n_sipes), pressure_bar, modulus_strength).natural_frequency_Hz


# -- step response ---------------------------------------------------------------------------
def linear_step_states(
    a: np.ndarray, b: np.ndarray, u1: float, u2: float, t: np.ndarray, t_step: float, dt: float
) -> np.ndarray:
    """States of x' = A x + B u through a step of u from u1 to u2 at t_step (exact).

    Starts in equilibrium with u1; after the step x = x2 + expm(A (t - t_step)) (x1 - x2),
    stepped sample by sample with expm(A dt) on a uniform axis of spacing ``dt``. This is the
    form :func:`synthetic.measurements.make_transient_table` uses (its output bytes depend on
    it); :func:`step_response` gives the same within 1e-10 deg on any axis.

    Parameters
    ----------
    a, b : ndarray
        State matrix (n, n) and input vector (n,) of :meth:`StepElement.system`.
    u1, u2 : float
        Input (the steady friction coefficient) before and after the step.
    t : (n_t,) ndarray
        Uniformly spaced sample times, s.
    t_step : float
        Time of the step, s.
    dt : float
        Spacing of ``t``, s.

    Returns
    -------
    (n_t, n) ndarray
        The states at ``t``; column 0 is the deflection angle, rad.
    """
    x1 = -np.linalg.solve(a, b * u1)
    x2 = -np.linalg.solve(a, b * u2)
    out = np.tile(x1, (t.size, 1))
    after = np.flatnonzero(t >= t_step)
    if after.size:
        phi = scipy.linalg.expm(a * dt)
        e = scipy.linalg.expm(a * (t[after[0]] - t_step)) @ (x1 - x2)
        dev = np.empty((after.size, x1.size))
        for k in range(after.size):
            dev[k] = e
            e = phi @ e
        out[after] = x2 + dev
    return out


# Largest condition number of the eigenvector matrix for which _deviation uses the modal
# solution (relative error about cond * 1e-16, so below 1e-10); a state matrix closer to
# defective (repeated eigenvalues) takes one matrix exponential per sample instead.
_EIG_COND_MAX = 1e6
# Rows per batch of the modal and matrix-exponential solutions (bounds the memory).
_BATCH = 65536


def step_element(
    *,
    n_sipes: int = 3,
    pressure_bar: float = 1.2,
    modulus_strength: float = 0.0,
    geometry: BlockGeometry | str | None = None,
) -> StepElement:
    """The linearised leading element of a block (Eq. 5.8) under a nominal pressure.

    Parameters
    ----------
    n_sipes : int
        Sipes of a 20 mm x 80 mm block (3: G3, the block of chapter 5); ignored when
        ``geometry`` is given.
    pressure_bar : float
        Nominal pressure, bar; the load shares equally over the elements,
        F_N = p L w / (n_sipes + 1).
    modulus_strength : float
        Strength of ``frequency_dependent_modulus``, >= 0.
    geometry : BlockGeometry or str, optional
        Any block, or a reference sample's name (``"G3"``); its first element is modelled.

    Returns
    -------
    StepElement

    Raises
    ------
    ValueError
        If the element buckles (F_N d >= c_phi + m g d / 2) or a value is out of range.

    Examples
    --------
    >>> el = step_element()
    >>> round(el.natural_frequency_Hz), round(el.angle_per_mu_deg, 1)
    (585, 35.5)
    """
    modulus_strength = check_nonnegative("frequency_dependent_modulus", modulus_strength)
    pressure_bar = check_positive("pressure_bar", pressure_bar)
    geometry = sipe_block(n_sipes) if geometry is None else as_geometry(geometry)
    return _element(geometry, pressure_bar, modulus_strength)


def _deviation(a: np.ndarray, e0: np.ndarray, since_s: np.ndarray) -> np.ndarray:
    """First state of expm(A s_k) e0 for times s_k >= 0 since the step, shape (len(s),).

    Modal solution ``Re(sum_j V_0j c_j exp(lambda_j s))`` with ``V c = e0`` (a few ms for
    thousands of samples, any sampling); a near-defective A (ill-conditioned eigenvectors)
    takes the matrix exponential at each sample.
    """
    out = np.empty(since_s.size)
    lam, vec = np.linalg.eig(a)
    if np.linalg.cond(vec) <= _EIG_COND_MAX:
        weights = vec[0] * np.linalg.solve(vec, e0.astype(complex))
        for start in range(0, since_s.size, _BATCH):
            s = since_s[start : start + _BATCH]
            modes = np.exp(np.outer(s, lam))
            # real parts by einsum: complex and threaded BLAS products stall on some machines
            out[start : start + s.size] = np.einsum(
                "ij,j->i", modes.real, weights.real
            ) - np.einsum("ij,j->i", modes.imag, weights.imag)
        return out
    for start in range(0, since_s.size, _BATCH // 64):
        s = since_s[start : start + _BATCH // 64]
        out[start : start + s.size] = (scipy.linalg.expm(a[None] * s[:, None, None]) @ e0)[:, 0]
    return out


def step_response(
    time_s: np.ndarray,
    t_step_s: float,
    *,
    mu_before: float,
    mu_after: float,
    n_sipes: int = 3,
    pressure_bar: float = 1.2,
    geometry: BlockGeometry | None = None,
    tau_s: float = 0.0,
    modulus_strength: float = 0.0,
) -> np.ndarray:
    """Deflection angle of the leading element through a step of the steady friction.

    Eq. 5.8 linearised (small angles, normal force at its preload, the tip's own speed left
    out of the sliding velocity), driven by ``F_N d mu_R``; mu_R follows Eq. 5.12,
    ``tau mu_R' + mu_R = mu_ss``, with mu_ss stepping from ``mu_before`` to ``mu_after`` at
    ``t_step_s`` (the velocity step from v1 to v2 enters only through mu_ss(v1), mu_ss(v2)).
    The element is in equilibrium at ``mu_before`` until the step; after it the states are
    ``x2 + expm(A (t - t_step)) (x1 - x2)``, exact for any sampling.

    Parameters
    ----------
    time_s : (n,) array_like
        Strictly increasing times, s.
    t_step_s : float
        Time of the step, s.
    mu_before, mu_after : float
        Steady friction coefficient before and after the step.
    n_sipes, pressure_bar, geometry
        The element, as in :func:`step_element`.
    tau_s : float
        Relaxation time of Eq. 5.12, s, >= 0 (0: no relaxation; ``TAU_REF_S`` = 20 ms is
        strength 1 of ``friction_relaxation``).
    modulus_strength : float
        Strength of ``frequency_dependent_modulus``, >= 0 (0: constant modulus E0).

    Returns
    -------
    (n,) ndarray
        Deflection angle, degrees, > 0 when the tip trails.

    Notes
    -----
    The angle is linear in (mu_before, mu_after): a response to (1, 0) scaled and shifted
    gives every other. Static levels are ``angle_per_mu_deg * mu`` of the
    :class:`StepElement`, whatever tau_s and modulus_strength (both change only the path).

    Examples
    --------
    Relaxation alone, without the element's own ringing, is ``1 - exp(-t / tau)``; with it
    the angle has covered about 63 % of the change one tau after the step:

    >>> import numpy as np
    >>> t = np.array([0.0, 0.2, 0.22, 1.0])
    >>> a = step_response(t, 0.2, mu_before=0.2, mu_after=0.1, tau_s=0.02)
    >>> el = step_element()
    >>> [round(float(x), 3) for x in a / el.angle_per_mu_deg]
    [0.2, 0.2, 0.137, 0.1]
    """
    t = np.asarray(time_s, dtype=float)
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)):
        raise ValueError(
            f"time_s must be a non-empty 1-D array of finite times, got shape {t.shape}"
        )
    if t.size > 1 and np.any(np.diff(t) <= 0):
        raise ValueError("time_s must be strictly increasing")
    t_step = float(t_step_s)
    if not math.isfinite(t_step):
        raise ValueError(f"t_step_s must be finite, got t_step_s={t_step_s!r}")
    mu1, mu2 = float(mu_before), float(mu_after)
    if not (math.isfinite(mu1) and math.isfinite(mu2)):
        raise ValueError(f"mu_before and mu_after must be finite, got {mu_before!r}, {mu_after!r}")
    tau = check_nonnegative("tau_s", tau_s)
    el = step_element(
        n_sipes=n_sipes,
        pressure_bar=pressure_bar,
        modulus_strength=modulus_strength,
        geometry=geometry,
    )
    a, b = el.system(tau)
    x1 = -np.linalg.solve(a, b * mu1)
    x2 = -np.linalg.solve(a, b * mu2)
    angle = np.full(t.size, x1[0])
    after = t >= t_step
    angle[after] = x2[0] + _deviation(a, x1 - x2, t[after] - t_step)
    return np.degrees(angle)
