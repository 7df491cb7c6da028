"""Material constants of ice and water (frozen dataclasses, SI units).

Thesis values (section 4.5.1, below Eq. 4.7): thermal conductivity of ice 2.2 W/(m K),
density 917 kg/m^3, specific heat capacity 2.09 kJ/(kg K), heat of fusion 334 kJ/kg.
The viscosity of water near 0 degC is 1.79 mPa s (tabulated value at 0 degC).
"""

from __future__ import annotations

from dataclasses import dataclass

from tir_common.validate import check_positive

__all__ = ["ICE", "WATER", "IceProperties", "WaterProperties"]


@dataclass(frozen=True)
class IceProperties:
    """Thermal properties of ice.

    Attributes
    ----------
    thermal_conductivity_W_mK : float
        lambda_ice in W/(m K).
    density_kg_m3 : float
        rho_ice in kg/m^3.
    specific_heat_J_kgK : float
        c_ice in J/(kg K).
    latent_heat_J_kg : float
        Heat of fusion q_ice in J/kg.
    melting_point_C : float
        Melting point of pure ice at atmospheric pressure, degC.
    """

    thermal_conductivity_W_mK: float = 2.2
    density_kg_m3: float = 917.0
    specific_heat_J_kgK: float = 2090.0
    latent_heat_J_kg: float = 334e3
    melting_point_C: float = 0.0

    def __post_init__(self) -> None:
        check_positive("thermal_conductivity_W_mK", self.thermal_conductivity_W_mK)
        check_positive("density_kg_m3", self.density_kg_m3)
        check_positive("specific_heat_J_kgK", self.specific_heat_J_kgK)
        check_positive("latent_heat_J_kg", self.latent_heat_J_kg)

    @property
    def thermal_inertia(self) -> float:
        """lambda * rho * c in W^2 s/(m^4 K^2), the group under the root of Eq. 4.6/4.7."""
        return self.thermal_conductivity_W_mK * self.density_kg_m3 * self.specific_heat_J_kgK


@dataclass(frozen=True)
class WaterProperties:
    """Properties of the melt water film.

    Attributes
    ----------
    viscosity_Pa_s : float
        Dynamic viscosity eta near 0 degC, Pa s.
    density_kg_m3 : float
        Density of water, kg/m^3.
    """

    viscosity_Pa_s: float = 1.79e-3
    density_kg_m3: float = 1000.0

    def __post_init__(self) -> None:
        check_positive("viscosity_Pa_s", self.viscosity_Pa_s)
        check_positive("density_kg_m3", self.density_kg_m3)


ICE = IceProperties()
WATER = WaterProperties()
