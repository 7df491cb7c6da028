"""Camera and sensor model shared by the footage views (private helpers of
:mod:`synthetic.footage`).

The renderers produce a noise-free *signal* image in units of the sensor's full scale (1.0 =
full well at gain 1). :class:`Sensor` turns it into digital numbers: photo-electrons with
shot noise, read noise, gain, rounding and clipping to the bit depth. The static
illumination (gradient and vignetting) and dust are computed once per clip by
:func:`illumination_field` and :func:`dust_field`.

Notes
-----
Image coordinates: x to the right along the image columns, y down along the rows, both in
mm from the top-left corner of the image; pixel ``(r, c)`` spans
``[c, c + 1) * mm_per_px`` in x and ``[r, r + 1) * mm_per_px`` in y.
"""

from __future__ import annotations

import logging
import math

import numpy as np
from scipy.special import ndtri

__all__ = [
    "POISSON_EXACT_BELOW_E",
    "Sensor",
    "box_blur_x",
    "dust_field",
    "illumination_field",
    "interval_coverage",
    "max_dn",
]

logger = logging.getLogger(__name__)

#: Standard normal deviates at the 65536 midpoint quantiles (i + 1/2) / 65536, scaled to unit
#: variance: indexed by uniform 16-bit integers they give normal noise 4x faster than
#: ``Generator.standard_normal``; the tails are cut at 4.3 sigma (probability 1.5e-5).
_NORMAL_TABLE = ndtri((np.arange(65536) + 0.5) / 65536.0)
_NORMAL_TABLE = (_NORMAL_TABLE / _NORMAL_TABLE.std()).astype(np.float32)

#: Mean photo-electron count below which shot noise is drawn from the exact Poisson law.
#: Above it a Gaussian of the same mean and variance is used: its skewness 1/sqrt(50) = 0.14
#: is the only difference, and it is below 0.01 at the usual 1e4 e- of the free surface.
POISSON_EXACT_BELOW_E = 50.0


def max_dn(bit_depth: int) -> int:
    """Largest digital number of a ``bit_depth``-bit sample (255, 4095 or 65535)."""
    return (1 << int(bit_depth)) - 1


def illumination_field(
    height_px: int,
    width_px: int,
    *,
    gradient: float,
    vignetting: float,
) -> np.ndarray:
    """Relative illumination of the field of view (1.0 on average over the centre row).

    Parameters
    ----------
    height_px, width_px : int
        Image size, px.
    gradient : float
        Linear rise of the illumination from the left to the right image edge, as a fraction
        of the centre level (0.15: the right edge is 15 % brighter than the left one).
    vignetting : float
        Fall-off towards the corners: the factor ``1 - vignetting * rho**2`` with ``rho`` the
        distance from the image centre over the half diagonal (corners at
        ``1 - vignetting``).

    Returns
    -------
    (height_px, width_px) ndarray of float32
        Multiplicative illumination factor, dimensionless.
    """
    x = (np.arange(width_px, dtype=np.float64) + 0.5) / width_px - 0.5
    y = (np.arange(height_px, dtype=np.float64) + 0.5) / height_px - 0.5
    half_diag2 = 0.25 * (width_px**2 + height_px**2)
    rho2 = ((x * width_px)[None, :] ** 2 + (y * height_px)[:, None] ** 2) / half_diag2
    field = (1.0 + gradient * x)[None, :] * (1.0 - vignetting * rho2)
    return field.astype(np.float32)


def dust_field(
    height_px: int,
    width_px: int,
    *,
    n_dust: int,
    rng: np.random.Generator,
) -> np.ndarray:
    """Transmission of out-of-focus dust on the prism face or the lens (static in the image).

    Each particle is a Gaussian shadow with a standard deviation drawn from [1, 3] px
    (a 10-50 um particle blurred by the shallow depth of field) that removes a fraction
    drawn from [0.1, 0.3] of the light at its centre.

    Returns
    -------
    (height_px, width_px) ndarray of float32
        Transmission in (0, 1], dimensionless.
    """
    out = np.ones((height_px, width_px), dtype=np.float64)
    if n_dust == 0:
        return out.astype(np.float32)
    cx = rng.uniform(0.0, width_px, n_dust)
    cy = rng.uniform(0.0, height_px, n_dust)
    sigma = rng.uniform(1.0, 3.0, n_dust)
    depth = rng.uniform(0.1, 0.3, n_dust)
    xs = np.arange(width_px) + 0.5
    ys = np.arange(height_px) + 0.5
    for x0, y0, s, a in zip(cx, cy, sigma, depth, strict=True):
        r = math.ceil(4 * s)
        c0, c1 = max(int(x0) - r, 0), min(int(x0) + r + 1, width_px)
        r0, r1 = max(int(y0) - r, 0), min(int(y0) + r + 1, height_px)
        gx = np.exp(-0.5 * ((xs[c0:c1] - x0) / s) ** 2)
        gy = np.exp(-0.5 * ((ys[r0:r1] - y0) / s) ** 2)
        out[r0:r1, c0:c1] *= 1.0 - a * gy[:, None] * gx[None, :]
    return out.astype(np.float32)


def interval_coverage(lo: float, hi: float, n: int, pitch: float) -> np.ndarray:
    """Fraction of each of ``n`` cells ``[k, k + 1) * pitch`` covered by ``[lo, hi]``.

    Examples
    --------
    >>> interval_coverage(0.5, 2.25, 4, 1.0).tolist()
    [0.5, 1.0, 0.25, 0.0]
    """
    edges = np.arange(n + 1, dtype=np.float64) * pitch
    return np.clip(np.minimum(edges[1:], hi) - np.maximum(edges[:-1], lo), 0.0, None) / pitch


def box_blur_x(image: np.ndarray, length_px: float) -> np.ndarray:
    """Centred box blur of length ``length_px`` along x (rows), exact for pixel-constant rows.

    The image is treated as constant over each pixel; the result at pixel ``c`` is the mean
    of the image over ``[c + 0.5 - L/2, c + 0.5 + L/2]`` (px), the edge values extended.

    Parameters
    ----------
    image : (M, N) ndarray
    length_px : float
        Blur length L >= 0, px (the distance travelled during the exposure).

    Returns
    -------
    (M, N) ndarray of float32
    """
    if length_px <= 1e-9:
        return image.astype(np.float32, copy=False)
    pad = math.ceil(length_px / 2) + 1
    padded = np.pad(image.astype(np.float64), ((0, 0), (pad, pad)), mode="edge")
    cum = np.concatenate([np.zeros((image.shape[0], 1)), np.cumsum(padded, axis=1)], axis=1)
    n = image.shape[1]
    centres = np.arange(n) + 0.5 + pad
    lo, hi = centres - 0.5 * length_px, centres + 0.5 * length_px
    xp = np.arange(cum.shape[1], dtype=np.float64)
    # The cumulative sum of a piecewise-constant row is piecewise linear in x: interpolate.
    out = np.empty(image.shape, dtype=np.float64)
    for r in range(image.shape[0]):
        row = cum[r]
        out[r] = np.interp(hi, xp, row) - np.interp(lo, xp, row)
    return (out / length_px).astype(np.float32)


class Sensor:
    """Digitises signal images: shot noise, read noise, gain, rounding and clipping.

    Shot noise: the exact Poisson law below :data:`POISSON_EXACT_BELOW_E` mean electrons,
    above it a normal deviate of the same mean and variance (added to the read noise in one
    draw). Normal deviates come from a 65536-entry inverse-CDF table indexed by uniform
    16-bit integers of the generator. Keeps work buffers between frames (the temporaries of
    a 640 x 256 frame would otherwise be fresh memory pages on every frame).

    Parameters
    ----------
    shape : (int, int)
        Image shape (rows, columns).
    bit_depth : {8, 12, 16}
        Bits per sample; 12-bit values are returned in uint16 (0..4095, not shifted).
    gain : float
        Gain: digital numbers per electron relative to the unity setting, at which the full
        well maps to the largest digital number.
    full_well_e : float
        Full-well capacity, electrons.
    read_noise_dn : float
        Standard deviation of the read noise, DN of the output bit depth.
    shot_noise : bool
        Draw the photo-electron count (Poisson) instead of using its mean.
    """

    def __init__(
        self,
        shape: tuple[int, int],
        *,
        bit_depth: int,
        gain: float,
        full_well_e: float,
        read_noise_dn: float,
        shot_noise: bool,
    ) -> None:
        self.top = max_dn(bit_depth)
        self.dtype = np.uint8 if bit_depth == 8 else np.uint16
        self.full_well_e = np.float32(full_well_e)
        self.dn_per_e = np.float32(gain * self.top / full_well_e)
        self.read_noise_dn = np.float32(read_noise_dn)
        self.shot_noise = bool(shot_noise)
        self._e = np.empty(shape, dtype=np.float32)
        self._z = np.empty(shape, dtype=np.float32)
        self._dn = np.empty(shape, dtype=np.float32)
        self._sd = np.empty(shape, dtype=np.float32)

    def __call__(self, signal: np.ndarray, rng: np.random.Generator | None) -> np.ndarray:
        """Digitise ``signal`` (units of the full well) with noise from ``rng`` (None: none).

        Returns
        -------
        ndarray of uint8 (8-bit) or uint16 (12- and 16-bit), a new array.
        """
        e, z, dn = self._e, self._z, self._dn
        np.maximum(signal, np.float32(0.0), out=e)
        e *= self.full_well_e  # mean photo-electrons
        np.multiply(e, self.dn_per_e, out=dn)
        noisy = rng is not None and (self.shot_noise or self.read_noise_dn > 0)
        if noisy:
            np.take(_NORMAL_TABLE, rng.integers(0, 65536, z.shape, dtype=np.uint16), out=z)
            if self.shot_noise:
                # Gaussian with the Poisson variance plus the read-noise variance, in DN.
                sd = self._z_scale(e)
                sd *= z
                dn += sd
                low = e < POISSON_EXACT_BELOW_E
                if low.any():
                    counts = rng.poisson(e[low].astype(np.float64)).astype(np.float32)
                    dn[low] = counts * self.dn_per_e + self.read_noise_dn * z[low]
            else:
                z *= self.read_noise_dn
                dn += z
        np.rint(dn, out=dn)
        np.clip(dn, 0, self.top, out=dn)
        return dn.astype(self.dtype)

    def _z_scale(self, e: np.ndarray) -> np.ndarray:
        sd = np.multiply(e, self.dn_per_e * self.dn_per_e, out=self._sd)
        sd += self.read_noise_dn * self.read_noise_dn
        np.sqrt(sd, out=sd)
        return sd
