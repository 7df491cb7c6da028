"""The dry/wet model as a friction law mu(v) for the tread-block dynamics.

:class:`DryWetLaw` tabulates the model once over sliding velocity and pressure for fixed
climate conditions and then answers ``mu(v_rel_mps, pressure_Pa=...)`` by interpolation, so
that a simulation can call it at every time step. With ``element=i`` it gives the friction
of element ``i`` of a siped block, so that each element of a multi-element simulation can
have its own friction from the ice preheating of Fig. 4.25.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from friction_model.contact.drywet import DryWetParameters, element_friction_table, friction_table
from friction_model.geometry import BlockGeometry

__all__ = ["DryWetLaw"]


class DryWetLaw:
    """Friction coefficient of the dry/wet model as a callable law.

    Parameters
    ----------
    geometry : BlockGeometry
        The tread block.
    temperature_C, humidity_pct, salinity_pct : float
        Climate of the ice (held fixed; build one law per climate).
    params : DryWetParameters, optional
        Model parameters (calibrated defaults when omitted).
    element : int, optional
        Element index (0 leads) for a per-element law; the whole block when omitted.
    velocity_range_mps : (float, float)
        Tabulated sliding-velocity range; |v| outside it is clamped to it.
    pressure_range_Pa : (float, float)
        Tabulated nominal-pressure range; outside it is clamped.
    contact_fraction : float, optional
        Measured real contact fraction, passed to the model.

    Notes
    -----
    Same call signature as :class:`friction_model.contact.laws.FrictionLaw`:
    ``mu(v_rel_mps, *, pressure_Pa=None, temperature_C=None)``. The result is the magnitude
    of mu (even in v); ``pressure_Pa=None`` means the reference pressure 2.5 bar.
    Interpolation is linear in log(v) and log(p) on a 96 x 24 grid; the error against the
    model is below 1.5 % of mu (tested), largest where mu saturates at mu_dry at low v and p.

    Examples
    --------
    >>> from friction_model.geometry import reference_block
    >>> law = DryWetLaw(reference_block("G3"), temperature_C=-5.0, humidity_pct=40.0)
    >>> bool(law(1.0) > law(7.0))
    True
    """

    equation = "Eq. 4.1-4.7 (dry/wet model)"

    def __init__(
        self,
        geometry: BlockGeometry,
        *,
        temperature_C: float,
        humidity_pct: float = 50.0,
        salinity_pct: float = 0.0,
        params: DryWetParameters | None = None,
        element: int | None = None,
        velocity_range_mps: tuple[float, float] = (0.02, 30.0),
        pressure_range_Pa: tuple[float, float] = (2e4, 1e6),
        contact_fraction: float | None = None,
        n_velocity: int = 96,
        n_pressure: int = 24,
    ) -> None:
        if element is not None and not (0 <= element < geometry.n_elements):
            raise ValueError(
                f"element must lie in 0..{geometry.n_elements - 1}, got element={element!r}"
            )
        (v_lo, v_hi), (p_lo, p_hi) = velocity_range_mps, pressure_range_Pa
        if not (0 < v_lo < v_hi) or not (0 < p_lo < p_hi):
            raise ValueError(
                "velocity_range_mps and pressure_range_Pa must be increasing positive pairs, "
                f"got {velocity_range_mps!r} and {pressure_range_Pa!r}"
            )
        self.geometry = geometry
        self.params = params or DryWetParameters()
        self.element = element
        self.temperature_C = float(temperature_C)
        self._log_v = np.linspace(np.log(v_lo), np.log(v_hi), n_velocity)
        self._log_p = np.linspace(np.log(p_lo), np.log(p_hi), n_pressure)
        vv, pp = np.meshgrid(np.exp(self._log_v), np.exp(self._log_p), indexing="ij")
        table = pd.DataFrame(
            {
                "velocity_mps": vv.ravel(),
                "pressure_Pa": pp.ravel(),
                "temperature_C": temperature_C,
                "humidity_pct": humidity_pct,
                "salinity_pct": salinity_pct,
                "contact_fraction": np.nan if contact_fraction is None else contact_fraction,
            }
        )
        if element is None:
            mu = friction_table(geometry, table, self.params)["mu"].to_numpy()
        else:
            mu = element_friction_table(geometry, table, self.params)[:, element]
        self._table = mu.reshape(vv.shape)
        self._dlv = self._log_v[1] - self._log_v[0]
        self._dlp = self._log_p[1] - self._log_p[0]

    def mu(
        self,
        v_rel_mps: ArrayLike,
        *,
        pressure_Pa: ArrayLike | None = None,
        temperature_C: ArrayLike | None = None,
    ) -> np.ndarray | float:
        """Friction coefficient at |v_rel_mps| (m/s) and nominal pressure ``pressure_Pa``.

        ``temperature_C`` must be omitted or equal the law's temperature (build another law
        for another climate).
        """
        if temperature_C is not None and np.any(
            np.abs(np.asarray(temperature_C, float) - self.temperature_C) > 1e-9
        ):
            raise ValueError(
                f"this DryWetLaw is tabulated at temperature_C={self.temperature_C}; got "
                f"temperature_C={temperature_C!r} (build one law per temperature)"
            )
        if pressure_Pa is None and np.ndim(v_rel_mps) == 0:
            return self._scalar(abs(float(v_rel_mps)), 2.5e5)
        if np.ndim(v_rel_mps) == 0 and np.ndim(pressure_Pa) == 0:
            return self._scalar(abs(float(v_rel_mps)), float(pressure_Pa))
        v = np.abs(np.asarray(v_rel_mps, dtype=float))
        p = np.asarray(2.5e5 if pressure_Pa is None else pressure_Pa, dtype=float)
        v, p = np.broadcast_arrays(v, p)
        lv = np.clip(np.log(np.maximum(v, 1e-300)), self._log_v[0], self._log_v[-1])
        lp = np.clip(np.log(np.maximum(p, 1e-300)), self._log_p[0], self._log_p[-1])
        fi = np.minimum((lv - self._log_v[0]) / self._dlv, len(self._log_v) - 1 - 1e-9)
        fj = np.minimum((lp - self._log_p[0]) / self._dlp, len(self._log_p) - 1 - 1e-9)
        i, j = fi.astype(int), fj.astype(int)
        a, b = fi - i, fj - j
        T = self._table
        out = (1 - a) * ((1 - b) * T[i, j] + b * T[i, j + 1]) + a * (
            (1 - b) * T[i + 1, j] + b * T[i + 1, j + 1]
        )
        return out

    def _scalar(self, v: float, p: float) -> float:
        """Bilinear lookup for scalar input (the hot path inside ODE right-hand sides)."""
        lv = min(max(math.log(max(v, 1e-300)), self._log_v[0]), self._log_v[-1])
        lp = min(max(math.log(max(p, 1e-300)), self._log_p[0]), self._log_p[-1])
        fi = min((lv - self._log_v[0]) / self._dlv, len(self._log_v) - 1 - 1e-9)
        fj = min((lp - self._log_p[0]) / self._dlp, len(self._log_p) - 1 - 1e-9)
        i, j = int(fi), int(fj)
        a, b = fi - i, fj - j
        T = self._table
        return float(
            (1 - a) * ((1 - b) * T[i, j] + b * T[i, j + 1])
            + a * ((1 - b) * T[i + 1, j] + b * T[i + 1, j + 1])
        )

    __call__ = mu
