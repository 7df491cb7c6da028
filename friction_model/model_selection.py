"""Information criteria for choosing between models fitted to the same data.

Two forms of the corrected Akaike criterion, named for what they assume:

* :func:`aicc_known_sigma` when each residual is divided by its known standard deviation
  (``-2 ln L = chi2`` up to a constant), as in the discrepancy workflow;
* :func:`aicc_rss` when the error scale is unknown and estimated from the residual sum of
  squares (``-2 ln L = n ln(RSS / n)`` up to a constant), as when a friction law is picked
  for a measured characteristic.

Only differences between models on the same data mean anything; the constants dropped cancel.
"""

from __future__ import annotations

import math

__all__ = ["aicc_known_sigma", "aicc_rss", "bic_known_sigma", "reduced_chi_square"]


def aicc_known_sigma(chi2: float, k: int, n: int) -> float:
    """Corrected Akaike criterion for Gaussian errors of known sigma.

    ``AICc = chi2 + 2 k + 2 k (k + 1) / (n - k - 1)``; infinite when ``n <= k + 1``.

    Parameters
    ----------
    chi2 : float
        Sum of squared residuals, each divided by its standard deviation.
    k : int
        Number of fitted parameters.
    n : int
        Number of data points.

    Examples
    --------
    >>> round(aicc_known_sigma(10.0, 2, 13), 12)
    15.2
    """
    if n - k - 1 <= 0:
        return math.inf
    # summed left to right, as the callers' earlier copies did: the same float to the bit
    return float(chi2 + 2.0 * k + 2.0 * k * (k + 1) / (n - k - 1))


def aicc_rss(rss: float, k: int, n: int) -> float:
    """Corrected Akaike criterion when sigma is unknown: ``n ln(RSS / n) + 2 k + ...``.

    Infinite when ``n <= k + 1`` or the fit is exact (``RSS <= 0``), which no comparison
    can rank.

    Parameters
    ----------
    rss : float
        Residual sum of squares (weighted residuals where the fit was weighted).
    k : int
        Number of fitted parameters.
    n : int
        Number of data points.

    Examples
    --------
    >>> round(aicc_rss(0.5, 1, 10), 6)  # 10 ln(0.05) + 2 + 4/8
    -27.457323
    """
    if n - k - 1 <= 0 or rss <= 0:
        return math.inf
    return float(n * math.log(rss / n) + 2.0 * k + 2.0 * k * (k + 1) / (n - k - 1))


def bic_known_sigma(chi2: float, k: int, n: int) -> float:
    """Bayesian information criterion for Gaussian errors of known sigma, ``chi2 + k ln n``.

    Examples
    --------
    >>> round(bic_known_sigma(10.0, 2, 100), 6)
    19.21034
    """
    return float(chi2 + k * math.log(n))


def reduced_chi_square(chi2: float, n: int, k: int = 0) -> float:
    """``chi2 / (n - k)`` (NaN when ``n <= k``).

    Examples
    --------
    >>> reduced_chi_square(8.0, 10, 2)
    1.0
    """
    return float(chi2 / (n - k)) if n > k else math.nan
