"""Parameters of the rig evaluation: plateau detection and instationary binning.

Both are frozen dataclasses that check their values when made, so a bad value is reported
where it is given (the message names the field, the rule and the value).
"""

from __future__ import annotations

from dataclasses import dataclass

from tir_common.validate import check_nonnegative, check_positive

__all__ = ["InstationaryParams", "WindowParams"]


@dataclass(frozen=True)
class WindowParams:
    """Parameters of the constant-velocity phase detection.

    See :func:`find_constant_velocity_window` for the meaning of every field.

    Attributes
    ----------
    smoothing_s : float
        Length of the moving-average filter on the velocity (s).
    rel_tol : float
        Relative velocity tolerance about the plateau velocity (dimensionless).
    abs_tol_mps : float
        Absolute floor of the velocity tolerance (m/s).
    max_accel_mps2 : float
        Largest magnitude of the smoothed acceleration inside the plateau (m/s^2).
    settle_s : float
        Settling margin trimmed at both ends of the plateau (s).
    min_velocity_mps : float
        Smallest plateau speed; slower samples count as standstill (m/s).
    min_duration_s : float
        Shortest accepted window after trimming (s).
    """

    smoothing_s: float = 0.02
    rel_tol: float = 0.02
    abs_tol_mps: float = 0.01
    max_accel_mps2: float = 0.5
    settle_s: float = 0.05
    min_velocity_mps: float = 0.02
    min_duration_s: float = 0.05

    def __post_init__(self) -> None:
        for name in (
            "smoothing_s",
            "abs_tol_mps",
            "max_accel_mps2",
            "min_velocity_mps",
            "min_duration_s",
        ):
            check_positive(name, getattr(self, name))
        for name in ("rel_tol", "settle_s"):
            check_nonnegative(name, getattr(self, name))


@dataclass(frozen=True)
class InstationaryParams:
    """Parameters of the instationary evaluation (see :func:`instationary_characteristic`).

    Attributes
    ----------
    bin_width_mps : float
        Width of the velocity bins (m/s).
    smoothing_s : float
        Length of the moving-average filter applied to velocity and forces (s).
    min_velocity_mps : float
        Samples slower than this, and those whose filter window reaches such samples, are
        not evaluated (m/s).
    min_accel_mps2 : float
        Samples with a smoothed acceleration magnitude below this belong to no branch (m/s^2).
    min_samples : int
        Bins with fewer samples are dropped.
    """

    bin_width_mps: float = 0.25
    smoothing_s: float = 0.01
    min_velocity_mps: float = 0.05
    min_accel_mps2: float = 0.2
    min_samples: int = 20

    def __post_init__(self) -> None:
        for name in ("bin_width_mps", "smoothing_s", "min_velocity_mps", "min_accel_mps2"):
            check_positive(name, getattr(self, name))
        if not (isinstance(self.min_samples, int) and self.min_samples >= 1):
            raise ValueError(
                f"min_samples must be an int >= 1, got min_samples={self.min_samples!r}"
            )
