"""Operating conditions of a friction measurement or simulation."""

from __future__ import annotations

from dataclasses import dataclass

from tir_common.validate import check_nonnegative, check_positive, check_range

__all__ = [
    "HUMIDITY_RANGE_PCT",
    "PRESSURE_RANGE_PA",
    "SALINITY_RANGE_PCT",
    "TEMPERATURE_RANGE_C",
    "Conditions",
]

#: Nominal pressures the model takes, Pa: 0.01-1000 bar. A tread block's lies at 0.5-10 bar
#: (the thesis's tests 1-5 bar); a factor 100 either side leaves any real one and refuses a
#: pressure given in the other unit (2.5 bar given as Pa is 2.5e-5 bar: mu 1.5, all dry;
#: 2.5e5 Pa given as bar: mu 4e-6; helper-12).
PRESSURE_RANGE_PA = (1e3, 1e8)
#: Ambient (bulk ice) temperatures the model takes, degC: ice below its melting point.
TEMPERATURE_RANGE_C = (-60.0, 0.0)
#: Relative humidities, %.
HUMIDITY_RANGE_PCT = (0.0, 100.0)
#: Salinities of the water the ice was made of, % by mass (sea water: 3.5 %).
SALINITY_RANGE_PCT = (0.0, 3.5)


@dataclass(frozen=True)
class Conditions:
    """Sliding velocity, load and climate of one friction state.

    Parameters
    ----------
    velocity_mps : float
        Sliding velocity v, m/s (> 0).
    pressure_Pa : float
        Nominal normal pressure p = F_N / (L w), Pa (> 0). 1 bar = 1e5 Pa.
    temperature_C : float
        Ambient (= bulk ice) temperature, degC (< 0 and above -60).
    humidity_pct : float
        Relative humidity of the air, % (0..100).
    salinity_pct : float
        Salinity K of the water the ice was made of, % by mass (thesis: 0.05 %).
    contact_fraction : float, optional
        Real contact area as a fraction of the rubber face area, e.g. measured by TIR
        (Fig. 4.21: about 0.7 for G0, 0.25 for G7). ``None``: the model's contact law.
    """

    velocity_mps: float
    pressure_Pa: float
    temperature_C: float
    humidity_pct: float = 50.0
    salinity_pct: float = 0.0
    contact_fraction: float | None = None

    def __post_init__(self) -> None:
        check_positive("velocity_mps", self.velocity_mps)
        check_positive("pressure_Pa", self.pressure_Pa)
        low, high = PRESSURE_RANGE_PA
        if not low <= self.pressure_Pa <= high:
            p = float(self.pressure_Pa)
            raise ValueError(
                f"pressure_Pa must lie in [{low:g}, {high:g}] (0.01-1000 bar, a tread block's "
                f"nominal pressure), got pressure_Pa={p:g}, which is {p / 1e5:g} bar; a "
                "pressure in bar goes through Conditions.from_bar or a pressure_bar column"
            )
        check_range("temperature_C", self.temperature_C, *TEMPERATURE_RANGE_C)
        check_range("humidity_pct", self.humidity_pct, *HUMIDITY_RANGE_PCT)
        check_nonnegative("salinity_pct", self.salinity_pct)
        check_range("salinity_pct", self.salinity_pct, *SALINITY_RANGE_PCT)
        if self.contact_fraction is not None:
            if not (0.0 < float(self.contact_fraction) <= 1.0):
                raise ValueError(
                    "contact_fraction must lie in (0, 1], got "
                    f"contact_fraction={self.contact_fraction!r}"
                )

    @property
    def pressure_bar(self) -> float:
        """Nominal pressure in bar."""
        return self.pressure_Pa / 1e5

    @classmethod
    def from_bar(cls, velocity_mps: float, pressure_bar: float, temperature_C: float, **kw):
        """Build conditions with the pressure given in bar.

        Examples
        --------
        >>> Conditions.from_bar(1.0, 2.5, -5.0).pressure_Pa
        250000.0
        """
        return cls(velocity_mps, pressure_bar * 1e5, temperature_C, **kw)
