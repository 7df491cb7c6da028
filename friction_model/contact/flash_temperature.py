"""Flash temperature of a sliding heat source (Blok) and the dry run-in length.

Eq. 4.6 of the thesis gives the temperature rise of the ice surface under a dry contact of
length ``x`` sliding at ``v`` with frictional heat flux ``K mu_dry p v`` (the 1-D
semi-infinite-solid solution for a constant surface flux applied for the contact time
``x / v``); Eq. 4.7 solves it for the length ``epsilon`` after which the ice reaches its
melting point.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from friction_model._fitting import as_float_array
from friction_model.constants import ICE, IceProperties

__all__ = ["dry_run_in_length", "flash_temperature_rise"]


def _check_arrays(**arrays: ArrayLike) -> dict[str, np.ndarray]:
    """Every array as float, each checked finite by :func:`.as_float_array`."""
    return {name: as_float_array(name, value) for name, value in arrays.items()}


def _lowest(name: str, values: np.ndarray) -> str:
    """``name=value`` of a scalar, ``min(name)=value`` of an array, as plain numbers (not
    ``array(0.)``)."""
    low = float(np.min(values))
    return f"{name}={low:g}" if values.ndim == 0 else f"min({name})={low:g}"


def flash_temperature_rise(
    length_m: ArrayLike,
    pressure_Pa: ArrayLike,
    mu_dry: ArrayLike,
    velocity_mps: ArrayLike,
    *,
    heat_fraction: float = 1.0,
    ice: IceProperties = ICE,
) -> np.ndarray:
    """Ice surface temperature rise at distance ``length_m`` behind the leading edge.

    Implements Eq. 4.6 (Blok): ``dT = 2 K mu_dry p sqrt(x v / (pi lambda rho c))``.

    Parameters
    ----------
    length_m : float or ndarray
        Distance x behind the leading edge of the dry contact, m (>= 0).
    pressure_Pa : float or ndarray
        Contact pressure p, Pa (> 0).
    mu_dry : float or ndarray
        Dry friction coefficient (> 0).
    velocity_mps : float or ndarray
        Sliding velocity v, m/s (> 0).
    heat_fraction : float, optional
        K, the fraction of the frictional heat that flows into the ice (thesis: 1).
    ice : IceProperties, optional
        Material constants of ice.

    Returns
    -------
    ndarray
        Temperature rise in K.

    Examples
    --------
    >>> round(float(flash_temperature_rise(1.507e-3, 0.25e6, 1.5, 1.0)), 2)
    8.0
    """
    a = _check_arrays(
        length_m=length_m, pressure_Pa=pressure_Pa, mu_dry=mu_dry, velocity_mps=velocity_mps
    )
    if np.any(a["length_m"] < 0):
        raise ValueError(f"length_m must be >= 0, got {_lowest('length_m', a['length_m'])}")
    return (
        2.0
        * heat_fraction
        * a["mu_dry"]
        * a["pressure_Pa"]
        * np.sqrt(a["length_m"] * a["velocity_mps"] / (np.pi * ice.thermal_inertia))
    )


def dry_run_in_length(
    delta_T_K: ArrayLike,
    pressure_Pa: ArrayLike,
    mu_dry: ArrayLike,
    velocity_mps: ArrayLike,
    heat_fraction: float = 1.0,
    *,
    ice: IceProperties = ICE,
) -> np.ndarray | float:
    """Length of the dry run-in area in front of a sliding rubber element (Eq. 4.7).

    ``epsilon = (dT / (2 K mu_dry p))^2 * pi lambda_ice rho_ice c_ice / v``

    Parameters
    ----------
    delta_T_K : float or ndarray
        Temperature difference between the melting point and the ice, K (>= 0).
    pressure_Pa : float or ndarray
        Contact pressure p, Pa (> 0).
    mu_dry : float or ndarray
        Dry friction coefficient of the run-in area (> 0; thesis: about 1.5).
    velocity_mps : float or ndarray
        Sliding velocity v, m/s (> 0).
    heat_fraction : float, optional
        K, the fraction of the frictional heat conducted into the ice (thesis: K = 1 since
        rubber conducts 14 times less heat than ice).
    ice : IceProperties, optional
        Material constants of ice (thesis values by default).

    Returns
    -------
    float or ndarray
        Dry run-in length epsilon in m (broadcast shape of the inputs).

    Notes
    -----
    Scaling: epsilon ~ dT^2, ~ 1/p^2, ~ 1/mu_dry^2, ~ 1/v (Fig. 4.26).

    Examples
    --------
    The thesis example (section 4.5.1): dT = 8 K, p = 0.25 MPa, mu_dry = 1.5, v = 1 m/s.

    >>> round(dry_run_in_length(8.0, 0.25e6, 1.5, 1.0) * 1e3, 2)
    1.51
    """
    a = _check_arrays(
        delta_T_K=delta_T_K, pressure_Pa=pressure_Pa, mu_dry=mu_dry, velocity_mps=velocity_mps
    )
    for name in ("pressure_Pa", "mu_dry", "velocity_mps"):
        if np.any(a[name] <= 0):
            raise ValueError(f"{name} must be > 0, got {_lowest(name, a[name])}")
    if np.any(a["delta_T_K"] < 0):
        raise ValueError(f"delta_T_K must be >= 0, got {_lowest('delta_T_K', a['delta_T_K'])}")
    if not (0.0 < heat_fraction <= 1.0):
        raise ValueError(f"heat_fraction must lie in (0, 1], got heat_fraction={heat_fraction!r}")
    eps = (a["delta_T_K"] / (2.0 * heat_fraction * a["mu_dry"] * a["pressure_Pa"])) ** 2 * (
        np.pi * ice.thermal_inertia / a["velocity_mps"]
    )
    return float(eps) if eps.ndim == 0 else eps
