"""The initial water layer on the ice surface and the melting point of saline ice.

Sections 4.5.1 and 4.5.2 of the thesis state the trends but no formula; the choices here:

* Initial (bound) water layer, the quasi-liquid layer of Döppenschmidt (section 2.2.2) plus
  the layer exchanged with humid air: ``h0 = h_qll * (1 K / dT)^(1/3) * (1 + g * rH/100)``.
  The exponent 1/3 is the growth law of a premelted layer held by van-der-Waals forces
  (Dash et al.); ``g`` (``humidity_gain``) scales the humidity part
  (effect ``humidity_water_layer``). Neither ``h_qll`` nor ``g`` is fitted (Table 4.6
  cannot separate humidity from temperature); see :class:`DryWetParameters`.
* Melting point of saline ice: the surface brine is richer in salt than the bulk water the
  ice was frozen from (salt is rejected from the growing ice lattice), by the factor
  ``salt_enrichment``; the freezing-point depression of the surface brine is interpolated in
  the tabulated NaCl(aq) data (CRC Handbook, 'Concentrative properties of aqueous
  solutions'), limited at the eutectic (23.3 wt %, -21.1 degC).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from friction_model.conditions import HUMIDITY_RANGE_PCT

__all__ = ["freezing_point_depression_K", "initial_water_layer_m"]

# NaCl(aq): mass fraction in % -> freezing-point depression in K (CRC Handbook).
_NACL_WT_PCT = np.array(
    [0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 14.0, 16.0, 18.0, 20.0, 22.0, 23.3]
)
_NACL_DT_K = np.array(
    [
        0.0,
        0.30,
        0.59,
        1.19,
        1.79,
        2.41,
        3.05,
        3.70,
        5.08,
        6.56,
        8.18,
        9.94,
        11.89,
        14.04,
        16.46,
        19.18,
        21.1,
    ]
)


def freezing_point_depression_K(salinity_pct: ArrayLike, *, enrichment: float = 1.0) -> np.ndarray:
    """Freezing-point depression of the ice surface for ice made of saline water.

    Parameters
    ----------
    salinity_pct : float or ndarray
        Salinity K of the water the ice was made of, mass %, >= 0.
    enrichment : float, optional
        Ratio of the surface-brine salinity to the bulk salinity (>= 0; 0 switches the
        effect off, 1 uses the bulk salinity).

    Returns
    -------
    ndarray
        Depression of the melting point in K (>= 0).

    Examples
    --------
    >>> float(freezing_point_depression_K(1.0))
    0.59
    """
    s = np.asarray(salinity_pct, dtype=float)
    if np.any(~np.isfinite(s)) or np.any(s < 0):
        raise ValueError(f"salinity_pct must be finite and >= 0, got {salinity_pct!r}")
    if enrichment < 0:
        raise ValueError(f"enrichment must be >= 0, got enrichment={enrichment!r}")
    surface = np.minimum(s * enrichment, _NACL_WT_PCT[-1])
    return np.interp(surface, _NACL_WT_PCT, _NACL_DT_K)


def initial_water_layer_m(
    delta_T_K: ArrayLike,
    humidity_pct: ArrayLike,
    *,
    qll_thickness_m: float,
    humidity_gain: float,
) -> np.ndarray:
    """Thickness of the bound water layer on the free ice surface.

    Parameters
    ----------
    delta_T_K : float or ndarray
        Distance of the ice temperature below its melting point, K (> 0; values below
        0.05 K are treated as 0.05 K to keep the premelting law finite).
    humidity_pct : float or ndarray
        Relative humidity, % (0..100; :data:`friction_model.conditions.HUMIDITY_RANGE_PCT`).
    qll_thickness_m : float
        Layer thickness at 1 K below the melting point in dry air, m.
    humidity_gain : float
        Relative growth of the layer from 0 % to 100 % humidity (0 = no humidity effect).

    Returns
    -------
    ndarray
        h0 in m.

    Raises
    ------
    ValueError
        A humidity outside 0..100 % or not finite.

    Examples
    --------
    >>> float(initial_water_layer_m(8.0, 0.0, qll_thickness_m=1e-7, humidity_gain=0.0))
    5e-08
    """
    dT = np.maximum(np.asarray(delta_T_K, dtype=float), 0.05)
    rh = np.asarray(humidity_pct, dtype=float)
    lo, hi = HUMIDITY_RANGE_PCT
    if np.any(~np.isfinite(rh)) or np.any(rh < lo) or np.any(rh > hi):
        # a relative humidity beyond saturation (helper-12: 140 % grew the layer 1.4x
        # without a word) or a fraction given for a percentage is not air
        raise ValueError(f"humidity_pct must be a relative humidity in % ({lo:g}..{hi:g}), "
                         f"got {humidity_pct!r}")
    return qll_thickness_m * dT ** (-1.0 / 3.0) * (1.0 + humidity_gain * rh / 100.0)
