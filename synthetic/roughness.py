"""Rough elastic contact from an established solver: the true contact of the physical scenes.

The rubber face is not flat: a self-affine rough surface (Hurst exponent H, power spectrum
``C(q) ~ q^(-2(1+H))`` between the long and the short wavelength cut-off) is pressed
against the flat ice or prism by the nominal pressure. Because ice and glass are some
thousand times stiffer than rubber, the contact is that of a rough elastic half-space on a
rigid flat, with the composite modulus ``E* = E / (1 - nu^2)`` of the one rubber
(:data:`friction_model.compound.REFERENCE_COMPOUND`: E0 = 3.61 MPa, nu = 0.5, so
E* = 4.81 MPa). The boundary-element problem (non-penetration, no adhesion, frictionless
normal contact on a periodic tile) is solved by `tamaas` (Frérot, Anciaux, Rey and
Molinari, *J. Open Source Softw.* 2020): its spectral surface generator and the
Polonsky-Keer constrained conjugate gradient (``PolonskyKeerRey``). tamaas is an optional
extra (``pip install "tir-contact[contact]"``); :func:`require_tamaas` names it in one line
when it is missing.

What comes out is the pressure and the gap at every grid point: the true contact area is
where the gap is zero, and the optics (:mod:`synthetic.ftir`) turn the gap into grey
levels. Two classic results hold and are tested: Hertz's contact radius of a smooth sphere
``a = (3 F R / (4 E*))^(1/3)``, and at small loads the real contact area grows in
proportion to load, ``A_r / A_0 = kappa p / (E* h')`` with ``h'`` the rms slope and
``kappa`` near 2 (Hyun et al., *Phys. Rev. E* 70, 2004; Yastrebov et al., *Tribol. Lett.*
65, 2017).

Examples
--------
>>> rough = ROUGHNESS_PRESETS["abraded_rubber"]
>>> rough.hurst, rough.rms_slope, round(rough.rms_height_m * 1e6, 1)
(0.8, 1.2, 35.8)
>>> round(e_star_Pa() / 1e6, 2)
4.81
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from types import ModuleType

import numpy as np
from scipy.integrate import trapezoid

from friction_model.compound import REFERENCE_COMPOUND, Compound
from tir_common.validate import check_number

__all__ = [
    "ROUGHNESS_PRESETS",
    "ContactField",
    "MissingExtraError",
    "Roughness",
    "e_star_Pa",
    "hertz_contact_radius_m",
    "require_tamaas",
    "rough_heights",
    "solve_contact",
]

#: Relative tolerance of the Polonsky-Keer solver (its convergence criterion on the
#: complementarity of gap and pressure). At 1e-10 the counted contact area equals the one at
#: 1e-12 in tamaas 2.7.1 and 2.9 alike; tamaas 2.7.1's criterion is looser than 2.9's, and at
#: 1e-8 it still moves the area by 1.5 % (at 1e-6 by 50 %), where 2.9 is converged.
SOLVER_TOLERANCE = 1e-10


class MissingExtraError(ImportError):
    """An optional extra the call needs is not installed (the message names it)."""


def require_tamaas() -> ModuleType:
    """Import tamaas, or raise :class:`MissingExtraError` with the install line.

    Returns
    -------
    module
        The ``tamaas`` module, its log level set to errors only.
    """
    try:
        import tamaas
    except ImportError as err:  # pragma: no cover - depends on the environment
        raise MissingExtraError(
            "the physical contact scenes need the contact-mechanics solver tamaas: "
            'pip install "tir-contact[contact]" (wheels for CPython 3.11 and 3.12)'
        ) from err
    tamaas.set_log_level(tamaas.LogLevel.error)
    return tamaas


@dataclass(frozen=True)
class Roughness:
    """A self-affine, isotropic, Gaussian rough surface.

    Parameters
    ----------
    hurst : float
        Hurst exponent H, in [0.5, 1]; the power spectrum falls as ``q^(-2(1+H))``.
    rms_slope : float
        Root-mean-square slope ``h'`` of the whole surface (all wavelengths), in (0, 5].
    long_wavelength_mm : float
        Roll-off (long-wavelength cut-off) ``lambda_L``, mm: the spectrum is flat above it.
    short_wavelength_mm : float
        Short-wavelength cut-off ``lambda_s``, mm (< ``long_wavelength_mm``): no roughness
        below it. The solver grid resolves it with :attr:`points_per_short_wavelength`.
    name : str
        A label for ``meta.json``.
    """

    hurst: float = 0.8
    rms_slope: float = 1.2
    long_wavelength_mm: float = 0.5
    short_wavelength_mm: float = 0.04
    name: str = "custom"

    #: Grid points per short wavelength: 8 resolves the smallest asperities' contacts well
    #: enough that the counted area at small loads gives kappa within 10-20 % of its
    #: converged value (Yastrebov et al. 2017, Fig. 6).
    points_per_short_wavelength = 8

    def __post_init__(self) -> None:
        check_number("hurst", self.hurst, low=0.5, high=1.0)
        check_number("rms_slope", self.rms_slope, low=0.0, high=5.0, low_open=True)
        check_number(
            "long_wavelength_mm", self.long_wavelength_mm, low=0.0, high=100.0, low_open=True,
            unit="mm",
        )
        check_number(
            "short_wavelength_mm",
            self.short_wavelength_mm,
            low=0.0,
            high=self.long_wavelength_mm,
            low_open=True,
            high_open=True,
            unit="mm (< long_wavelength_mm)",
        )

    @property
    def grid_spacing_mm(self) -> float:
        """Solver grid spacing, mm."""
        return self.short_wavelength_mm / self.points_per_short_wavelength

    @property
    def rms_height_m(self) -> float:
        """Root-mean-square height of the surface, m (from the spectrum's moments).

        For ``C(q) ~ q^(-2(1+H))`` on ``[q_L, q_s]`` (zero outside, as generated), the
        height and slope variances are the moments ``m0 = int C q dq`` and
        ``m2 = int C q^3 dq`` (times 2 pi); ``h_rms = h' sqrt(m0 / m2)``.
        """
        q_l = 2 * math.pi / (self.long_wavelength_mm * 1e-3)
        q_s = 2 * math.pi / (self.short_wavelength_mm * 1e-3)
        q = np.geomspace(q_l, q_s, 20001)
        c = (q / q_l) ** (-2.0 * (1.0 + self.hurst))
        m0 = trapezoid(c * q, q)
        m2 = trapezoid(c * q**3, q)
        return float(self.rms_slope * math.sqrt(m0 / m2))


#: Plausible rough surfaces of tread rubber on ice and of elastomers on glass. The slopes are
#: of the whole spectrum down to the short cut-off (they are dominated by the short
#: wavelengths). Sources: Persson's measured tread-rubber and sandblasted-PDMS spectra
#: (H 0.8-0.9, slopes 0.5-1.3 at 10-20 um cut-offs); polished ice after a few passes is
#: smoother than the rubber (thesis section 2.2: the ice's roughness "is melted away during
#: the first passages"), so the composite is the rubber's.
ROUGHNESS_PRESETS: dict[str, Roughness] = {
    "abraded_rubber": Roughness(0.8, 1.2, 0.5, 0.04, "abraded_rubber"),
    "moulded_rubber": Roughness(0.9, 0.4, 0.5, 0.04, "moulded_rubber"),
    "sandblasted_elastomer": Roughness(0.7, 1.5, 0.3, 0.03, "sandblasted_elastomer"),
    "rough_ice": Roughness(0.6, 0.6, 1.0, 0.08, "rough_ice"),
}


def e_star_Pa(compound: Compound = REFERENCE_COMPOUND) -> float:
    """Contact modulus ``E* = E0 / (1 - nu^2)`` of the rubber on a rigid flat, Pa.

    Ice (about 9 GPa) and acrylic (3 GPa) are three orders stiffer than the rubber; their
    compliance changes E* by under 0.2 %.
    """
    nu = compound.poisson_ratio
    return float(compound.E0_Pa / (1.0 - nu * nu))


def hertz_contact_radius_m(load_N: float, radius_m: float, e_star: float) -> float:
    """Hertz contact radius of an elastic sphere on a flat, ``a = (3 F R / (4 E*))^(1/3)``, m."""
    return float((3.0 * load_N * radius_m / (4.0 * e_star)) ** (1.0 / 3.0))


@functools.lru_cache(maxsize=8)
def _heights_cached(
    roughness: Roughness, size_mm: float, n_grid: int, seed: int
) -> np.ndarray:
    tm = require_tamaas()
    spectrum = tm.Isopowerlaw2D()
    # tamaas's wavenumbers count wavelengths per tile side.
    q_l = size_mm / roughness.long_wavelength_mm
    q_s = size_mm / roughness.short_wavelength_mm
    if q_s > n_grid / 2:
        raise ValueError(
            f"the grid of {n_grid} points on {size_mm} mm does not resolve the short "
            f"wavelength {roughness.short_wavelength_mm} mm (needs at least 2 points)"
        )
    spectrum.q0 = max(1, round(q_l))
    spectrum.q1 = max(1, round(q_l))
    spectrum.q2 = round(q_s)
    spectrum.hurst = roughness.hurst
    gen = tm.SurfaceGeneratorFilter2D([n_grid, n_grid])
    gen.spectrum = spectrum
    gen.random_seed = int(seed) % (2**31)
    h = np.array(gen.buildSurface(), dtype=np.float64)
    h -= h.mean()
    dx = size_mm * 1e-3 / n_grid
    slope = _spectral_rms_slope(h, dx)
    out = h * (roughness.rms_slope / slope)
    out.setflags(write=False)
    return out


def _spectral_rms_slope(h: np.ndarray, dx_m: float) -> float:
    """RMS slope of a periodic surface from its Fourier coefficients (exact derivative)."""
    n0, n1 = h.shape
    f = np.fft.fft2(h)
    qx = 2 * np.pi * np.fft.fftfreq(n1, d=dx_m)
    qy = 2 * np.pi * np.fft.fftfreq(n0, d=dx_m)
    q2 = qy[:, None] ** 2 + qx[None, :] ** 2
    return float(np.sqrt(np.sum(q2 * np.abs(f) ** 2)) / h.size)


def rough_heights(roughness: Roughness, size_mm: float, n_grid: int, seed: int) -> np.ndarray:
    """Heights of a periodic rough tile, m (mean 0), scaled to ``roughness.rms_slope``.

    Parameters
    ----------
    roughness : Roughness
    size_mm : float
        Side of the square periodic tile, mm (at least the long wavelength).
    n_grid : int
        Grid points per side (a power of two is fastest).
    seed : int
        Seed of tamaas's random phases.

    Returns
    -------
    (n_grid, n_grid) ndarray of float64, read-only
        Heights, m; its spectral rms slope equals ``roughness.rms_slope``.
    """
    check_number("size_mm", size_mm, low=roughness.long_wavelength_mm, high=1000.0, unit="mm")
    return _heights_cached(roughness, float(size_mm), int(n_grid), int(seed))


@dataclass(frozen=True)
class ContactField:
    """The solution of one contact problem on a periodic tile.

    Attributes
    ----------
    pressure_Pa : (N, N) ndarray
        Contact pressure, Pa (0 outside contact).
    gap_m : (N, N) ndarray
        Gap between rubber and flat, m (0 in contact).
    size_mm : float
        Tile side, mm.
    mean_pressure_Pa : float
        The nominal (mean) pressure over the tile, Pa.
    """

    pressure_Pa: np.ndarray
    gap_m: np.ndarray
    size_mm: float
    mean_pressure_Pa: float

    @property
    def grid_spacing_mm(self) -> float:
        """Grid spacing, mm."""
        return self.size_mm / self.pressure_Pa.shape[0]

    @property
    def in_contact(self) -> np.ndarray:
        """Grid points in contact (pressure > 0)."""
        return self.pressure_Pa > 0.0

    @property
    def contact_fraction(self) -> float:
        """Real contact area over the tile area."""
        return float(np.mean(self.in_contact))


def solve_contact(
    profile_m: np.ndarray,
    size_mm: float,
    mean_pressure_Pa: float,
    e_star: float,
    *,
    tolerance: float = SOLVER_TOLERANCE,
) -> ContactField:
    """Press an elastic half-space with surface ``profile_m`` on a rigid flat (tamaas).

    Parameters
    ----------
    profile_m : (N, N) ndarray
        Height of the rubber surface towards the flat, m (higher points touch first), on a
        periodic square tile.
    size_mm : float
        Tile side, mm.
    mean_pressure_Pa : float
        Nominal pressure (total load over the tile area), Pa, > 0.
    e_star : float
        Contact modulus E*, Pa.
    tolerance : float
        Solver tolerance (:data:`SOLVER_TOLERANCE`).

    Returns
    -------
    ContactField
        Pressure and gap; the gap is the surface separation after the elastic
        deformation, zero where the pressure is positive.
    """
    tm = require_tamaas()
    check_number("mean_pressure_Pa", mean_pressure_Pa, low=0.0, low_open=True, unit="Pa")
    check_number("e_star", e_star, low=0.0, low_open=True, unit="Pa")
    h = np.array(profile_m, dtype=np.float64, order="C", copy=True)  # tamaas writes to it
    n0, n1 = h.shape
    if n0 != n1:
        raise ValueError(f"profile_m must be square, got shape {h.shape}")
    side = size_mm * 1e-3
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [side, side], [n0, n1])
    # tamaas takes E and nu; with nu = 0 its Hertz modulus E / (1 - nu^2) is E* itself.
    model.E = float(e_star)
    model.nu = 0.0
    solver = tm.PolonskyKeerRey(model, h, float(tolerance))
    solver.solve(float(mean_pressure_Pa))
    pressure = np.array(model.traction, dtype=np.float64).reshape(n0, n1)
    disp = np.array(model.displacement, dtype=np.float64).reshape(n0, n1)
    contact = pressure > 0.0
    # Separation = displacement - height + approach; the approach makes it zero on contact.
    sep = disp - h
    sep -= float(np.mean(sep[contact])) if contact.any() else float(sep.min())
    gap = np.where(contact, 0.0, np.maximum(sep, 0.0))
    pressure.setflags(write=False)
    gap.setflags(write=False)
    return ContactField(pressure, gap, float(size_mm), float(mean_pressure_Pa))
