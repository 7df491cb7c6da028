"""A user's free-surface image (``--reference``) fitted to the footage before it is used.

A rig's own empty frame (no contact) is the best free surface there is, but it is rarely
taken with the very exposure and framing of the test: the exposure or the lamp differ by
some per cent, and the camera or the prism sit a few pixels elsewhere. Used as it is, a
reference 13 % darker than the footage takes 13 % of every contact's darkness away (a weak
contact falls below the threshold), and a shift of a few pixels leaves a dark crescent
along the lit zone's rim that counts as contact. :func:`fit_reference` therefore fits the
model

``T(x) = g * R(x - s)``

of the footage's free-surface image ``T`` (each pixel's median over the sampled frames of a
static scene; a passing block's bright percentile less its expected excess over the mean,
:func:`tir_contact.prepare.prepare_video`) by the reference ``R`` with a gain ``g`` and a
shift ``s`` (px, sub-pixel, bilinear), on the free surface: every pixel except those the
fit finds darker than the fitted reference (brighter for bright contact) by more than 5
noise standard deviations and 5 % of the light inside the lit zone (contact can only be
there), grown by 2 px for their blurred edges. Gain and shift are fitted on the free
surface of the lit zone and a margin around it (its rim tells the shift best); the
residual is judged on the free surface of the whole frame.

Method
------
1. The coarse shift (to 2 px, within :data:`SEARCH_PX`, 12 px) is the one that leaves
   the least median absolute residual after a median gain (a pyramid search on copies
   shrunk 4x, then 2x); medians are not moved by contact, a minority of the
   pixels. The gain starts as the ratio of the medians over the lit zone.
2. Gauss-Newton (Lucas-Kanade) steps on ``(g, s)``: the residual ``T - g R_s`` is
   linearised as ``dg R_s - g grad(R_s) . ds`` and solved by weighted least squares
   (weight: one over the expected residual variance, below), the contact pixels found
   anew after each step, until the shift changes by less than 0.001 px (at most 30 steps).
3. Residual: ``z = (T - g R_s) / sqrt(var_T + g^2 var_R + 1/12 (1 + g^2))`` with the
   grey-value noise of one frame (:class:`tir_contact.reference.NoiseModel`, ``a + b I``,
   at each image's level; the median of several frames is less noisy, so this errs
   towards a smaller ``z``) and the quantisation of both images. A reference that shows
   the footage's free surface leaves ``rms(z)`` about 1 or less; a reference of another
   scene (another lit shape, another rig, a frame with the block) leaves whole regions at
   tens of standard deviations. Contact only darkens (bright contact: brightens), and near
   a soft contact by less than the candidate test sees: the statistic is the larger of
   ``sqrt(2 mean(max(z, 0)^2))`` (the side contact cannot make; equal to ``rms(z)`` for
   symmetric noise) over the free surface and ``rms(z)`` over its part farther than
   :data:`FAR_FRACTION` (8 %) of the image's long side from any candidate (a fit that
   calls most of the lit zone contact is judged there). The fit is rejected when it
   exceeds :data:`MAX_NOISE_RATIO` (3): a wide margin on both sides (measured: 0.3-0.8 for
   fitting references on renders of several domain classes, 8-bit and JPEG included;
   about 36 for a lit band taken for a lit disc).

Pixels whose shifted reference would come from outside the image (``inside`` False: a
strip along the border as wide as the shift) hold the reference's nearest pixel (its edge,
replicated); the analysis takes the footage's own free-surface estimate there instead
where the footage's frames show each pixel free (a fixed camera, :mod:`tir_contact.tir_view`).

Examples
--------
>>> yy, xx = np.mgrid[:120, :160].astype(np.float32)
>>> def scene(dx, dy):
...     return 20 + 180 / (1 + np.exp(np.hypot(xx - 80 - dx, yy - 60 - dy) - 45))
>>> footage = scene(0.0, 0.0)
>>> footage[50:58, 70:78] *= 0.3          # a contact
>>> fit = fit_reference(0.9 * scene(-3.4, 2.2), footage)
>>> round(fit.gain, 2), tuple(round(v, 1) for v in fit.shift_px), fit.fits
(1.11, (3.4, -2.2), True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np

from tir_contact.reference import NoiseModel

__all__ = ["MAX_NOISE_RATIO", "ReferenceFit", "fit_reference"]

#: A fitted reference is rejected when the RMS of its noise-normalised residual on the free
#: surface exceeds this (module notes).
MAX_NOISE_RATIO = 3.0
#: Contact candidates: darker than the fitted reference by this many noise standard
#: deviations and by at least :data:`CONTACT_MIN_DARKNESS`.
CONTACT_SIGMAS = 5.0
CONTACT_MIN_DARKNESS = 0.05
#: Contact candidates are grown by this (px) to cover their blurred edges.
CONTACT_MARGIN_PX = 2
#: The lit zone is grown by this share of the image's long side before contact candidates
#: are restricted to it (a contact at the rim reaches beyond the half-light line).
LIT_MARGIN_FRACTION = 0.02
#: The whole-pixel search for the shift reaches this far (px) either way.
SEARCH_PX = 12
#: Both sides of the residual are judged farther than this share of the long side from
#: any contact candidate (nearer, a soft contact's faint edge darkens the footage).
FAR_FRACTION = 0.08
#: Gauss-Newton steps at most, and the shift change (px) that ends them.
MAX_STEPS = 30
STEP_TOL_PX = 1e-3


@dataclass(frozen=True)
class ReferenceFit:
    """Result of :func:`fit_reference`.

    Attributes
    ----------
    gain : float
        ``g``: the footage's free surface is ``g`` times the reference.
    shift_px : (float, float)
        ``(dx, dy)``: the reference's content moved by this (px, x right, y down) lies on
        the footage's.
    residual_rms : float
        RMS of the relative residual ``T / (g R_s) - 1`` on the lit free surface (darkness
        units: the darkness a free pixel keeps after the fit).
    noise_rms : float
        The RMS of that relative residual that noise alone gives (same pixels).
    noise_ratio : float
        The noise-normalised residual on the free surface, its side that contact cannot
        make (module notes).
    n_pixels : int
        Free-surface pixels the fit used.
    fits : bool
        ``noise_ratio <= MAX_NOISE_RATIO``.
    image : (M, N) ndarray of float32
        ``g R_s``: the reference in the footage's exposure and framing.
    inside : (M, N) ndarray of bool
        Pixels whose shifted reference comes from inside the image.
    free : (M, N) ndarray of bool
        The free surface the residual was judged on (inside, not contact).
    """

    gain: float
    shift_px: tuple[float, float]
    residual_rms: float
    noise_rms: float
    noise_ratio: float
    n_pixels: int
    fits: bool
    image: np.ndarray
    inside: np.ndarray
    free: np.ndarray

    def as_dict(self) -> dict[str, Any]:
        """The numbers of the fit (for ``summary.json``)."""
        return {
            "gain": self.gain,
            "shift_x_px": self.shift_px[0],
            "shift_y_px": self.shift_px[1],
            "residual_rms_darkness": self.residual_rms,
            "noise_rms_darkness": self.noise_rms,
            "residual_noise_ratio": self.noise_ratio,
            "max_noise_ratio": MAX_NOISE_RATIO,
            "n_pixels": self.n_pixels,
            "fits": self.fits,
        }


def _shifted(image: np.ndarray, dx: float, dy: float) -> np.ndarray:
    """``image(x - s)`` (bilinear; the border replicated)."""
    h, w = image.shape
    m = np.float32([[1, 0, dx], [0, 1, dy]])
    return cv2.warpAffine(image, m, (w, h), flags=cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_REPLICATE)


def _inside(shape: tuple[int, int], dx: float, dy: float) -> np.ndarray:
    h, w = shape
    ys, xs = np.arange(h)[:, None] - dy, np.arange(w)[None, :] - dx
    return (ys >= 0) & (ys <= h - 1) & (xs >= 0) & (xs <= w - 1)


def _overlap_cost(ref: np.ndarray, tgt: np.ndarray, dx: int, dy: int) -> float:
    """Median absolute residual of ``tgt`` against ``g ref(x - d)`` over their overlap,
    with ``g`` the median ratio (medians: contact, a minority, does not move them)."""
    h, w = tgt.shape
    t = tgt[max(0, dy):h + min(0, dy), max(0, dx):w + min(0, dx)]
    r = ref[max(0, -dy):h + min(0, -dy), max(0, -dx):w + min(0, -dx)]
    ok = r > 0
    if ok.sum() < 16:
        return math.inf
    g = float(np.median(t[ok] / r[ok]))
    return float(np.median(np.abs(t[ok] - g * r[ok])))


def _coarse_shift(ref: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """Shift of `target` against `ref` within :data:`SEARCH_PX`, to 2 px: the least robust
    residual (:func:`_overlap_cost`), searched on copies shrunk 4x, then refined on copies
    shrunk 2x by one of their pixels either way (the Gauss-Newton steps take it from
    there)."""
    best = (0, 0)
    for level in (4, 2):
        size = (max(8, ref.shape[1] // level), max(8, ref.shape[0] // level))
        r = cv2.resize(ref, size, interpolation=cv2.INTER_AREA)
        t = cv2.resize(target, size, interpolation=cv2.INTER_AREA)
        if level == 4:
            reach = math.ceil(SEARCH_PX / level) + 1
            grid = [(x, y) for y in range(-reach, reach + 1) for x in range(-reach, reach + 1)]
        else:
            grid = [(2 * best[0] + x, 2 * best[1] + y) for y in (-1, 0, 1) for x in (-1, 0, 1)]
        best = min(grid, key=lambda d: _overlap_cost(r, t, d[0], d[1]))
    return 2.0 * best[0], 2.0 * best[1]


def _variance(noise: NoiseModel | None, target: np.ndarray, ref_s: np.ndarray,
              gain: float) -> np.ndarray:
    """Expected variance of ``T - g R_s``: both images' noise and quantisation, DN²."""
    q = (1.0 + gain * gain) / 12.0
    if noise is None:
        return np.full(target.shape, q, np.float32)
    var_t = noise.sigma_grey(np.maximum(target, 0.0)) ** 2
    var_r = noise.sigma_grey(np.maximum(ref_s, 0.0)) ** 2  # the reference's own level
    return (var_t + gain * gain * var_r + q).astype(np.float32)


def _noise_ratio(z: np.ndarray, use: np.ndarray, cand: np.ndarray) -> float:
    """The larger of ``sqrt(2 mean(max(z, 0)^2))`` over the free surface and ``rms(z)``
    over its part farther than :data:`FAR_FRACTION` of the long side from any contact
    candidate (`z` positive where the footage is brighter than the fit for dark contact)."""
    if not use.any():
        return math.inf
    zp = np.maximum(z[use], 0.0)
    ratio = math.sqrt(2.0 * float(np.mean(zp * zp)))
    reach = 2 * max(1, round(FAR_FRACTION * max(z.shape))) + 1
    far = use & ~(cv2.dilate(cand.astype(np.uint8), np.ones((reach, reach), np.uint8)) > 0)
    if far.any():
        ratio = max(ratio, math.sqrt(float(np.mean(z[far] ** 2))))
    return ratio


def fit_reference(
    reference: np.ndarray,
    target: np.ndarray,
    *,
    noise: NoiseModel | None = None,
    lit: np.ndarray | None = None,
    contact_is: str = "dark",
) -> ReferenceFit:
    """Fit gain and shift of a user's free-surface image to the footage (module notes).

    Parameters
    ----------
    reference : (M, N) ndarray
        The user's image of the free surface (no contact), grey values.
    target : (M, N) ndarray
        The footage's free surface where it shows: each pixel's median over sampled
        frames (a static scene), a bright percentile (a passing block), or one frame.
    noise : NoiseModel, optional
        Grey-value noise of one frame; quantisation only when omitted.
    lit : (M, N) ndarray of bool, optional
        The footage's lit zone (contact can be only near it); the whole frame by default.
    contact_is : {"dark", "bright"}

    Returns
    -------
    ReferenceFit

    Raises
    ------
    ValueError
        Images of different shapes or not 2-D.
    """
    ref = np.asarray(reference, np.float32)
    tgt = np.asarray(target, np.float32)
    if ref.ndim != 2 or ref.shape != tgt.shape:
        raise ValueError(f"reference and target must be 2-D of one shape, got {ref.shape} "
                         f"and {tgt.shape}")
    if contact_is not in ("dark", "bright"):
        raise ValueError(f"contact_is must be 'dark' or 'bright', got {contact_is!r}")
    sign = 1.0 if contact_is == "dark" else -1.0
    near_lit = np.ones(tgt.shape, bool)
    if lit is not None and np.asarray(lit, bool).any():
        grow = 2 * max(1, round(LIT_MARGIN_FRACTION * max(tgt.shape))) + 1
        near_lit = cv2.dilate(np.asarray(lit, np.uint8), np.ones((grow, grow), np.uint8)) > 0
    dx, dy = _coarse_shift(ref, tgt)
    ref_s = _shifted(ref, dx, dy)
    sel = near_lit & (ref_s > 0)
    gain = float(np.median(tgt[sel]) / max(float(np.median(ref_s[sel])), 1e-6))
    cand = np.zeros(tgt.shape, bool)
    grow_c = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * CONTACT_MARGIN_PX + 1,) * 2)
    for _ in range(MAX_STEPS):
        ref_s = _shifted(ref, dx, dy)
        inside = _inside(tgt.shape, dx, dy)
        var = _variance(noise, tgt, ref_s, gain)
        model = gain * ref_s
        dark = sign * (model - tgt)
        cand = ((dark > CONTACT_SIGMAS * np.sqrt(var))
                & (dark > CONTACT_MIN_DARKNESS * np.abs(model)) & near_lit)
        cand = cv2.dilate(cand.astype(np.uint8), grow_c) > 0
        use = inside & ~cand & near_lit
        smooth = cv2.GaussianBlur(ref_s, (0, 0), 0.7)
        gx = cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=3) / 8.0
        gy = cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=3) / 8.0
        w = 1.0 / var[use]
        a = np.stack([ref_s[use], -gain * gx[use], -gain * gy[use]], axis=1)
        r = (tgt - model)[use]
        aw = a * w[:, None]
        try:
            step = np.linalg.solve(aw.T @ a, aw.T @ r)
        except np.linalg.LinAlgError:
            break
        gain += float(step[0])
        dx, dy = dx + float(step[1]), dy + float(step[2])
        if math.hypot(step[1], step[2]) < STEP_TOL_PX:
            break
    ref_s = _shifted(ref, dx, dy)
    inside = _inside(tgt.shape, dx, dy)
    model = gain * ref_s
    var = _variance(noise, tgt, ref_s, gain)
    use = inside & ~cand
    ratio = _noise_ratio(sign * (tgt - model) / np.sqrt(var), use, cand)
    free = use & (lit if lit is not None else True) & (model > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = tgt[free] / model[free] - 1.0
        rel_noise = var[free] / model[free] ** 2
    residual = float(np.sqrt(np.mean(rel * rel))) if rel.size else math.inf
    expected = float(np.sqrt(np.mean(rel_noise))) if rel.size else math.inf
    return ReferenceFit(gain, (dx, dy), residual, expected, ratio, int(use.sum()),
                        bool(ratio <= MAX_NOISE_RATIO), model.astype(np.float32), inside, use)
