"""Frustrated total internal reflection: the light a TIR camera sees over a gap of width g.

The camera of thesis section 4.3.6 looks through the acrylic prism and the ice at the ice
surface. Where the rubber is far from the ice, the light is totally reflected at the
ice-air surface (bright). Where the rubber comes within about a wavelength, the evanescent
wave in the gap reaches it and part of the light crosses into the rubber (frustrated TIR):
the reflected intensity falls continuously with the gap and is smallest at contact (g = 0).
This module gives that reflectance from the three-layer (substrate - gap - rubber) Fresnel
formula, so that near-contact zones come out grey, not as the black/white step of a
segmentation's picture of contact.

Optics (Born and Wolf, *Principles of Optics*, section 1.6; Zhu et al., *Appl. Opt.* 25,
1986, for frustrated TIR): with ``k_z,j = k0 sqrt(n_j^2 - (n_1 sin theta_1)^2)`` (the root with
non-negative imaginary part: evanescent in a layer where the tangential index exceeds
``n_j``), the interface coefficients ``r_ij`` (s: ``(k_i - k_j)/(k_i + k_j)``; p:
``(n_j^2 k_i - n_i^2 k_j)/(n_j^2 k_i + n_i^2 k_j)``) and the layer phase
``exp(2 i k_z,2 g)``, the reflection of the layered stack is the Airy sum

    r = (r12 + r23 exp(2 i k_z2 g)) / (1 + r12 r23 exp(2 i k_z2 g)),   R = |r|^2.

Unpolarised light (a LED through a diffuser) reflects ``(R_s + R_p) / 2``.

The rig (Table 4.5 of the thesis): acrylic n_A = 1.491, ice n_I = 1.31, water 1.333, air
1.0003. The thesis says TIR works "because n_A > n_I"; the physics is a window of angles:
the light must cross the acrylic-ice interface (angle in acrylic below
``asin(n_I / n_A)`` = 61.5 deg) and be totally reflected at the ice-air surface (angle in
ice above ``asin(1.0003 / n_I)`` = 49.8 deg). Water (1.333 > 1.31) cannot totally reflect
light coming from ice at any angle: a water film between ice and rubber frustrates the
reflection as contact does, so wet zones look dark. On glass (1.49-1.52) water still
reflects totally above 61-64 deg.

Examples
--------
>>> optics = FtirOptics()
>>> round(float(optics.reflectance(1e-3)), 6)  # a 1 mm gap: total reflection
1.0
>>> round(float(optics.reflectance(0.0)), 4)  # contact: the ice-rubber Fresnel loss only
0.0221
>>> round(optics.evanescent_depth_m * 1e9, 1)  # field 1/e depth in the air gap, nm
163.5
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tir_common.validate import check_number

__all__ = ["SUBSTRATE_INDEX", "FtirOptics"]

#: Refractive index of the surface the rubber touches (thesis Table 4.5 for acrylic and ice;
#: soda-lime glass 1.52 for lab photographs on glass).
SUBSTRATE_INDEX = {"ice": 1.31, "acrylic": 1.491, "glass": 1.52}
#: Refractive index of the gap medium (Table 4.5).
GAP_INDEX = {"air": 1.0003, "water": 1.333}


@dataclass(frozen=True)
class FtirOptics:
    """The optics of a TIR contact image: substrate, gap medium, rubber, light.

    Parameters
    ----------
    substrate : {"ice", "acrylic", "glass"}
        What the rubber touches, seen from below (its index from :data:`SUBSTRATE_INDEX`).
    gap : {"air", "water"}
        The medium between rubber and substrate outside contact.
    rubber_index : float
        Real refractive index of the rubber, in [1, 3]; 1.5 (filled natural/SBR rubber).
    rubber_extinction : float
        Imaginary part of the rubber's index, in [0, 1]; 0 by default. Carbon black makes
        tread rubber opaque over millimetres but leaves its surface reflectance near that
        of a dielectric; a larger value raises the light returned at contact.
    incidence_deg : float
        Angle of the light in the substrate against the surface normal, deg, in (0, 90); 60
        (inside the rig's window of 49.8-90 deg in ice, reached through acrylic at 49.5 deg).
    wavelength_nm : float
        Vacuum wavelength, nm, in [200, 2000]; 550 (the centre of a white LED's light as a
        monochrome sensor sees it).

    Raises
    ------
    ValueError
        For an unknown substrate or gap, or an angle at which the free surface does not
        reflect totally (then there is no TIR image).
    """

    substrate: str = "ice"
    gap: str = "air"
    rubber_index: float = 1.5
    rubber_extinction: float = 0.0
    incidence_deg: float = 60.0
    wavelength_nm: float = 550.0

    def __post_init__(self) -> None:
        if self.substrate not in SUBSTRATE_INDEX:
            raise ValueError(
                f"substrate must be one of {sorted(SUBSTRATE_INDEX)}, got {self.substrate!r}"
            )
        if self.gap not in GAP_INDEX:
            raise ValueError(f"gap must be one of {sorted(GAP_INDEX)}, got {self.gap!r}")
        check_number("rubber_index", self.rubber_index, low=1.0, high=3.0)
        check_number("rubber_extinction", self.rubber_extinction, low=0.0, high=1.0)
        check_number(
            "incidence_deg", self.incidence_deg, low=0.0, high=90.0, low_open=True,
            high_open=True, unit="deg",
        )
        check_number("wavelength_nm", self.wavelength_nm, low=200.0, high=2000.0, unit="nm")

    @property
    def n_substrate(self) -> float:
        """Refractive index of the substrate."""
        return SUBSTRATE_INDEX[self.substrate]

    @property
    def n_gap(self) -> float:
        """Refractive index of the gap medium."""
        return GAP_INDEX[self.gap]

    @property
    def tangential_index(self) -> float:
        """``n_1 sin(theta_1)``, conserved across the layers (Snell)."""
        return self.n_substrate * math.sin(math.radians(self.incidence_deg))

    @property
    def total_reflection(self) -> bool:
        """True when the free surface (an infinite gap) reflects totally."""
        return self.tangential_index > self.n_gap

    @property
    def evanescent_depth_m(self) -> float:
        """Depth over which the evanescent field in the gap falls by 1/e, m.

        ``d = lambda / (2 pi sqrt(n_1^2 sin^2 theta_1 - n_2^2))`` (the intensity falls over
        half of it). Infinite when the free surface does not reflect totally.
        """
        s = self.tangential_index**2 - self.n_gap**2
        if s <= 0.0:
            return math.inf
        return self.wavelength_nm * 1e-9 / (2.0 * math.pi * math.sqrt(s))

    @property
    def contact_darkness(self) -> float:
        """Darkness of full contact, ``1 - R(0)``: the light a gap of zero takes out."""
        return 1.0 - float(self.reflectance(0.0))

    def _kz(self, n: complex) -> complex:
        """Normal wave number of a layer of index ``n`` over k0 (root with Im >= 0)."""
        kz = np.sqrt(complex(n) ** 2 - self.tangential_index**2 + 0j)
        return complex(kz) if kz.imag >= 0 else -complex(kz)

    def reflectance(self, gap_m: np.ndarray | float) -> np.ndarray:
        """Unpolarised reflectance ``(R_s + R_p) / 2`` over a gap of width ``gap_m``.

        Parameters
        ----------
        gap_m : float or ndarray
            Gap between substrate and rubber, m, >= 0 (``inf`` for no rubber).

        Returns
        -------
        ndarray of float64
            Reflectance in [0, 1], same shape as ``gap_m``: 1 for an infinite gap under
            total reflection, ``|r13|^2`` at contact.
        """
        g = np.asarray(gap_m, dtype=np.float64)
        if np.any(g < 0):
            raise ValueError("gap_m must be >= 0 everywhere (a gap cannot be negative)")
        n1 = complex(self.n_substrate)
        n2 = complex(self.n_gap)
        n3 = complex(self.rubber_index, self.rubber_extinction)
        k1, k2, k3 = self._kz(n1), self._kz(n2), self._kz(n3)
        k0 = 2.0 * math.pi / (self.wavelength_nm * 1e-9)
        finite = np.isfinite(g)
        phase = np.zeros(g.shape, dtype=np.complex128)
        phase[finite] = np.exp(2j * k0 * k2 * g[finite])
        out = np.zeros(g.shape, dtype=np.float64)
        for pol in ("s", "p"):
            r12 = _fresnel(pol, n1, k1, n2, k2)
            r23 = _fresnel(pol, n2, k2, n3, k3)
            r = (r12 + r23 * phase) / (1.0 + r12 * r23 * phase)
            out += 0.5 * np.abs(r) ** 2
        return np.clip(out, 0.0, 1.0)


def _fresnel(pol: str, ni: complex, ki: complex, nj: complex, kj: complex) -> complex:
    """Fresnel amplitude reflection coefficient from layer i into layer j."""
    if pol == "s":
        return (ki - kj) / (ki + kj)
    return (nj**2 * ki - ni**2 * kj) / (nj**2 * ki + ni**2 * kj)
