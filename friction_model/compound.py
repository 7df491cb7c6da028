"""One rubber for every model: the reference tread compound REF (thesis Table 4.3).

The thesis characterises its compound by Shore A hardness only (REF: Shore A 60). Every
model of the package (rigid block, Euler-Bernoulli, Timoshenko, contact ratio, stick-slip,
the synthetic footage) takes its rubber from :data:`REFERENCE_COMPOUND`:

* E0 from Gent's relation for the Shore A reading, taken 1-3 s after the indenter
  touches (ISO 7619-1): the modulus at ``reference_frequency_Hz`` = 1 Hz;
* a frequency-independent loss factor tan(delta) (filled tread rubber over a few decades),
  which by causality (Kramers-Kronig; Kjartansson's constant-Q model) fixes the frequency
  dependence of the modulus: E(f) = E0 (f / f0)^n with tan(delta) = tan(n pi / 2);
* density of a carbon-black filled tread compound, Poisson's ratio 0.5 (G = E / 3).

The elastic root of the element (the block base's rotational stiffness identified from the
measured deflection of Fig. 5.14) is element physics and lives in
:mod:`friction_model.dynamics.root` (``identify_root_stiffness``, ``steady_beam_column``), so
that this module stays a leaf that every model imports.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from tir_common.validate import check_range

logger = logging.getLogger(__name__)

__all__ = [
    "REFERENCE_COMPOUND",
    "Compound",
    "gent_youngs_modulus",
]


def gent_youngs_modulus(shore_a: float) -> float:
    """Young's modulus of rubber from its Shore A hardness (Gent's relation), Pa.

    ``E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S))`` MPa.

    Parameters
    ----------
    shore_a : float
        Shore A hardness, in [20, 80] where the relation holds.

    Returns
    -------
    float
        E, Pa.

    Examples
    --------
    >>> round(gent_youngs_modulus(60.0) / 1e6, 2)
    3.61
    """
    s = check_range("shore_a", shore_a, 20.0, 80.0)
    return 0.0981 * (56.0 + 7.62336 * s) / (0.137505 * (254.0 - 2.54 * s)) * 1e6


@dataclass(frozen=True)
class Compound:
    """A tread rubber: hardness, loss factor, density; E(f) by a causal constant-loss model.

    Parameters
    ----------
    shore_a : float
        Shore A hardness, in [20, 80].
    loss_factor : float
        tan(delta), frequency independent, in (0, 2].
    density_kg_m3 : float
        Density, kg/m^3.
    reference_frequency_Hz : float
        Frequency at which E = E0 (the Shore reading's ~1 s time scale), Hz.
    poisson_ratio : float
        nu; 0.5 (incompressible) for rubber.
    """

    shore_a: float = 60.0
    loss_factor: float = 0.2
    density_kg_m3: float = 1150.0
    reference_frequency_Hz: float = 1.0
    poisson_ratio: float = 0.5

    def __post_init__(self) -> None:
        check_range("shore_a", self.shore_a, 20.0, 80.0)
        check_range("loss_factor", self.loss_factor, 1e-6, 2.0)
        check_range("density_kg_m3", self.density_kg_m3, 100.0, 3e4)
        check_range(
            "reference_frequency_Hz", self.reference_frequency_Hz, 1e-6, 1e6
        )
        check_range("poisson_ratio", self.poisson_ratio, 0.0, 0.5)

    @property
    def E0_Pa(self) -> float:
        """Young's modulus at ``reference_frequency_Hz`` (Gent), Pa."""
        return gent_youngs_modulus(self.shore_a)

    @property
    def modulus_exponent(self) -> float:
        """n of E(f) ~ f^n, with tan(delta) = tan(n pi / 2) (causality)."""
        return 2.0 * math.atan(self.loss_factor) / math.pi

    def storage_modulus_Pa(self, frequency_Hz: float | np.ndarray) -> float | np.ndarray:
        """E'(f) = E0 (f / f0)^n of the constant-loss (Kjartansson) model, Pa.

        Parameters
        ----------
        frequency_Hz : float or ndarray
            f, Hz, > 0.

        Returns
        -------
        float or ndarray
            E'(f), Pa.
        """
        f = np.asarray(frequency_Hz, dtype=float)
        if np.any(~(f > 0)):
            raise ValueError(f"frequency_Hz must be > 0, got {frequency_Hz!r}")
        out = self.E0_Pa * (f / self.reference_frequency_Hz) ** self.modulus_exponent
        return float(out) if out.ndim == 0 else out

    def kelvin_voigt_s(self, frequency_Hz: float) -> float:
        """Kelvin-Voigt time k_i with the compound's loss factor at ``frequency_Hz``, s.

        A Kelvin-Voigt solid E (1 + k_i d/dt) has tan(delta) = 2 pi f k_i.
        """
        f = check_range("frequency_Hz", frequency_Hz, 1e-9, 1e9)
        return self.loss_factor / (2.0 * math.pi * f)


#: The reference compound REF of the thesis (Table 4.3, Shore A 60); E0 = 3.61 MPa.
REFERENCE_COMPOUND = Compound()
