"""Contact area as a measurement (:mod:`tir_contact.measure`) against truths made here.

Each image is built in the test from a stated model (supersampled discs block-averaged to
pixels, Gaussian noise, a Gaussian-filtered noise field), not by the renderer or the
pipeline, so the truth is exact: the covered area, the noise's spread, the field's
correlation area.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from tir_contact.measure import (
    ASSUMED_FULL_DARKNESS,
    MIN_FULL_PX,
    area_model,
    frame_area,
)

SHAPE = (160, 200)


def _noise(rng: np.random.Generator, sigma: float, shape=SHAPE) -> np.ndarray:
    return rng.normal(0.0, sigma, shape).astype(np.float32)


def _sigma_map(sigma: float, shape=SHAPE) -> np.ndarray:
    return np.full(shape, sigma, np.float32)


def _coverage(shape, discs, ss: int = 8) -> np.ndarray:
    """Covered fraction of each pixel by discs (cx, cy, r in px), supersampled ss x ss."""
    h, w = shape
    yy, xx = np.mgrid[0:h * ss, 0:w * ss]
    xx = (xx + 0.5) / ss
    yy = (yy + 0.5) / ss
    inside = np.zeros((h * ss, w * ss), bool)
    for cx, cy, r in discs:
        inside |= (xx - cx) ** 2 + (yy - cy) ** 2 < r * r
    return inside.reshape(h, ss, w, ss).mean(axis=(1, 3))


def test_free_surface_offset_spread_and_noise_only():
    """Gaussian noise of sigma 0.02 around an offset of 0.01: the offset, no texture, and
    the seed level (the noise's reach at 0.05 false pixels per frame) as the normal law
    gives it."""
    rng = np.random.default_rng(3)
    d = [_noise(rng, 0.02) + 0.01 for _ in range(3)]
    m = area_model(d, _sigma_map(0.02))
    assert m.offset == pytest.approx(0.01, abs=0.001)  # 96 000 values: 1e-4 standard error
    assert m.sigma_texture < 0.005  # the spread is the noise the noise map holds
    # z for 0.05 false pixels in 32 000: 4.67 (normal law), times sigma 0.02, plus offset
    assert m.seed_median == pytest.approx(0.01 + 4.67 * 0.02, abs=0.003)
    assert m.contact_source == "assumed"


def test_texture_beyond_the_noise_and_its_correlation_area():
    """A texture field: white noise filtered by a Gaussian of 1.5 px, scaled to sigma 0.05;
    its correlation area (the integral of its autocorrelation) is 4 pi 1.5^2 = 28 px."""
    rng = np.random.default_rng(4)
    fields = []
    for _ in range(4):
        f = cv2.GaussianBlur(rng.normal(size=(320, 400)).astype(np.float32), (0, 0), 1.5)
        fields.append((0.05 * f / f.std()).astype(np.float32))
    m = area_model(fields, _sigma_map(0.0, (320, 400)))
    assert m.sigma_texture == pytest.approx(0.05, rel=0.05)
    # blocks of 8 px hold the correlation area 28 px with a finite-block loss of about 30 %
    # (the autocorrelation's tail beyond the block): 15-30 px
    assert 15.0 <= m.corr_px <= 30.0


def test_resolved_contact_gives_its_darkness_and_half_of_it_as_threshold():
    rng = np.random.default_rng(5)
    d = _noise(rng, 0.02)
    d[40:100, 50:150] += 0.8
    m = area_model([d], _sigma_map(0.02))
    assert m.contact_source == "measured"
    assert m.contact_darkness == pytest.approx(0.8, abs=0.005)
    assert m.threshold == pytest.approx(0.4, abs=0.003)
    assert m.separation > 1.0 and not m.notes


def test_blurred_disc_area_is_its_geometric_area():
    """A disc of radius 20 px, darkness 0.8, Gaussian blur 1.5 px, noise 0.02: the area is
    pi r^2 (1257 px) to 1 % (the noise summed over the edge band: about 4 px), inside the
    bar."""
    rng = np.random.default_rng(6)
    cov = _coverage(SHAPE, [(100.0, 80.0, 20.0)])
    d = (0.8 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.5) + _noise(rng, 0.02))
    m = area_model([d], _sigma_map(0.02))
    a = frame_area(d, m)
    true = float(cov.sum())
    assert a.area_px == pytest.approx(true, rel=0.01)
    assert a.low_px <= true <= a.high_px


def test_full_darkness_of_small_blurred_contacts_is_their_plateau():
    """40 discs of radius 3-5 px, darkness 0.95, Gaussian blur 1.5 px: no pixel of the
    smaller ones reaches the plateau (a disc's centre under the blur: 0.95 (1 - exp(-r^2 /
    2 sigma^2)), 0.82 for r = 3, 0.946 for r = 5), and the first interior pixels' median is
    about 0.86. Full contact's darkness is taken deeper while the median still rises: 0.90-
    0.96 (the deepest pixels of the widest discs)."""
    from tir_contact.measure import _interiors

    for seed in (11, 12, 13):
        rng = np.random.default_rng(seed)
        discs = [(rng.uniform(15, 185), rng.uniform(15, 145), rng.uniform(3.0, 5.0))
                 for _ in range(40)]
        cov = _coverage(SHAPE, discs)
        d = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.5) + _noise(rng, 0.01)
        m = area_model([d], _sigma_map(0.01))
        assert float(np.median(_interiors([d], 0.485))) < 0.87  # the first interior
        assert 0.90 <= m.contact_darkness <= 0.96, seed
        a = frame_area(d, m)
        assert a.low_px <= float(cov.sum()) <= a.high_px


def test_full_darkness_of_a_wide_graded_contact_is_its_first_interior():
    """A 60 x 100 px contact graded from 0.80 to 0.85 across (a pressure grading): its
    median rises by under 1 % a pixel of depth, so the plateau is the first interior
    (median 0.825); full contact's level is read from its upper part: the upper decile of
    the grading (spread 0.05 / sqrt 12) with the noise (0.02), 0.825 + 1.28 x 0.0247,
    less 1.28 noise sigmas: 0.831, to 0.003 (the decile of 5700 pixels; the Gaussian
    approximation of the sum is off by under 0.001). A regression check of the rule's
    arithmetic rather than an independent truth: the median, 0.825, lies 2 tolerances
    below."""
    from tir_contact.measure import _interiors, _plateau

    rng = np.random.default_rng(3)
    d = _noise(rng, 0.02)
    d[40:100, 50:150] += np.linspace(0.80, 0.85, 100, dtype=np.float32)[None, :]
    m = area_model([d], _sigma_map(0.02))
    first = _interiors([d], 0.485)
    assert np.array_equal(_plateau([d], 0.485), first)
    assert float(np.median(first)) == pytest.approx(0.825, abs=0.005)
    grading = 0.05 / math.sqrt(12.0)
    expected = 0.825 + 1.2816 * (math.hypot(grading, 0.02) - 0.02)
    assert m.contact_darkness == pytest.approx(expected, abs=0.003)


def test_contacts_below_a_pixel_are_measured_by_their_darkness():
    """60 discs of radius 0.25-0.6 px (each covers at most a pixel's area), darkness 0.95,
    blur 0.7 px, noise 0.01, beside one resolved contact that shows the full darkness: the
    area is their covered area to 5 % (the noise summed over the unmixed pixels), where a
    pixel count at half darkness is off by far more."""
    rng = np.random.default_rng(7)
    small = [(rng.uniform(20, 180), rng.uniform(20, 140), rng.uniform(0.25, 0.6))
             for _ in range(60)]
    discs = [*small, (30.0, 30.0, 8.0)]
    cov = _coverage(SHAPE, discs)
    d = (0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 0.7) + _noise(rng, 0.01))
    m = area_model([d], _sigma_map(0.01))
    assert m.contact_source == "measured"
    a = frame_area(d, m)
    true = float(cov.sum())
    assert a.area_px == pytest.approx(true, rel=0.05)
    assert a.low_px <= true <= a.high_px
    counted = int((d >= m.threshold).sum())
    assert abs(counted / true - 1) > 0.1  # what a pixel count says: 13 % off


def test_full_darkness_is_a_wholly_covered_pixel_not_the_median_of_partial_clusters():
    """Rough contact: four resolved clusters of junctions (24 x 24 px) whose pixels are
    wholly covered with probability 0.4 and else covered 60-100 % (darkness 0.97 times the
    coverage, noise 0.01): their interiors' median is 0.91, full contact 0.97, and every
    area unmixed against the median would read 6 % high. Full contact is read to 0.015 (the
    decile of about 1900 interior pixels, and the noise correction taken at the noise's own
    sigma)."""
    rng = np.random.default_rng(21)
    d = _noise(rng, 0.01)
    for r0, c0 in ((20, 20), (20, 120), (100, 20), (100, 120)):
        cover = np.where(rng.random((24, 24)) < 0.4, 1.0, rng.uniform(0.6, 1.0, (24, 24)))
        d[r0:r0 + 24, c0:c0 + 24] += (0.97 * cover).astype(np.float32)
    m = area_model([d], _sigma_map(0.01))
    assert m.contact_source == "measured"
    assert m.contact_darkness == pytest.approx(0.97, abs=0.015)
    assert m.contact_low < 0.91 < m.contact_high  # the median stays in the range


def test_weak_flat_contact_is_full_contact_and_a_partial_spread_is_not():
    """A resolved contact of darkness 0.3 (full contact through stray light: a plateau)
    is measured as the darkness of full contact; a region whose darkness spreads from 0 to
    0.4 (contact covering part of each pixel) is not, and the darkness of full contact is
    then assumed."""
    rng = np.random.default_rng(8)
    flat = _noise(rng, 0.02)
    flat[40:100, 50:150] += 0.3
    m = area_model([flat], _sigma_map(0.02))
    assert m.contact_source == "measured"
    assert m.contact_darkness == pytest.approx(0.3, abs=0.01)
    # the same image is contact covering 0.3 of every pixel of the region (junctions far
    # below the pixel): the bar reaches down to that reading, 6000 x 0.3 = 1800 px, while
    # the area stays the stray-light reading's 6000 px (edges: 2 %)
    assert m.weak_plateau and any("weak plateau" in n for n in m.notes)
    a = frame_area(flat, m)
    assert a.area_px == pytest.approx(6000, rel=0.02)
    assert 1800 * 0.95 <= a.low_px <= 1800 * 1.02 and a.high_px >= 6000
    assert m.summary()["contact"]["weak_plateau"]
    spread = _noise(rng, 0.02)
    spread[40:100, 50:150] += rng.uniform(0.0, 0.4, (60, 100)).astype(np.float32)
    m2 = area_model([spread], _sigma_map(0.02))
    assert m2.contact_source == "assumed"
    assert m2.contact_darkness == ASSUMED_FULL_DARKNESS
    assert any("assumed full-contact darkness" in n for n in m2.notes)
    # the partial region, unmixed against the assumed darkness: mean 0.2 over 6000 px is
    # 1237 px of contact at 0.97; the bar spans the assumption's range (0.85-1)
    a = frame_area(spread, m2)
    true = float(np.sum(spread[40:100, 50:150])) / 0.97
    assert a.area_px == pytest.approx(true, rel=0.01)  # the noise summed: 0.3 %
    # the bar spans the assumption: from darkness 1 to darkness 0.85
    assert a.low_px <= 0.97 * true + 5 and a.high_px >= 0.97 * true / 0.85 - 5


#: Full contact's darkness from the optics in the tests of a measured free surface (rubber
#: on ice at 60 deg, :func:`tir_contact.optics.contact_darkness`).
OPTICS = (0.9779, "rubber on ice at 60 deg")


def test_measured_free_surface_reads_partly_covered_interiors_against_the_optics():
    """With the free surface measured (the rig's empty frame), four resolved clusters whose
    pixels are each covered 60-95 % (none wholly: darkness 0.9779 times the coverage, noise
    0.01) read their interiors' level at 0.88 (the upper decile less its noise); that
    is partial cover, not full contact, and full contact's darkness is the optics' value,
    with the interiors' reading kept in the range (the bar's high end). Without the measured
    free surface the level stands (stray light cannot be told from cover there)."""
    rng = np.random.default_rng(21)
    d = _noise(rng, 0.01)
    for r0, c0 in ((20, 20), (20, 120), (100, 20), (100, 120)):
        d[r0:r0 + 24, c0:c0 + 24] += (OPTICS[0] * rng.uniform(0.6, 0.95, (24, 24))
                                      ).astype(np.float32)
    own = area_model([d], _sigma_map(0.01), optics=OPTICS)
    assert own.contact_source == "measured"
    # the upper decile of 0.9779 x U(0.6, 0.95) (0.9779 x 0.915 = 0.895) less 1.28 noise
    # sigmas: 0.882 (the noise widens the decile by under 0.001; 2300 interior pixels)
    assert own.contact_darkness == pytest.approx(0.882, abs=0.01)
    m = area_model([d], _sigma_map(0.01), optics=OPTICS, free_measured=True)
    assert m.contact_source == "optics" and m.contact_darkness == OPTICS[0]
    assert m.contact_low <= own.contact_darkness and m.contact_high >= OPTICS[0]
    assert m.threshold == pytest.approx(OPTICS[0] / 2)
    assert any("optics' value" in n for n in m.notes)
    assert m.summary()["contact"]["source"] == "optics"


@pytest.mark.parametrize("level, taken", [(0.35, False), (0.50, False), (0.55, True)])
def test_measured_free_surface_keeps_weak_contact_the_optics_decision_would_drop(level,
                                                                               taken):
    """A flat contact of 6000 px at darkness 0.35 or 0.50 (contact through a water film,
    the thesis's wet zone; noise 0.02) with the free surface measured: half of the optics'
    darkness (0.489) would cut it away (at 0.50, 29 % of its pixels lie below it by their
    noise), so its own level stands and every pixel counts: 6000 px to 2 % (the edges:
    noise summed over 320 band pixels). At 0.55 its level clears that decision by 1.28
    noise sigmas or more (its lower decile does), the optics' value is taken and the area
    is still 6000 px (0.1 % of the pixels lie below 0.489), the bar reaching the
    interiors' own reading."""
    rng = np.random.default_rng(8)
    d = _noise(rng, 0.02)
    d[40:100, 50:150] += np.float32(level)
    m = area_model([d], _sigma_map(0.02), optics=OPTICS, free_measured=True)
    assert (m.contact_source == "optics") == taken
    assert m.contact_darkness == (OPTICS[0] if taken else pytest.approx(level, abs=0.01))
    a = frame_area(d, m)
    assert a.area_px == pytest.approx(6000, rel=0.02)
    assert a.low_px <= 6000 <= a.high_px


def test_measured_free_surface_reads_a_weak_plateau_of_partial_cover_by_its_cover():
    """A 60 x 100 px region whose pixels are each covered 20-50 % (junctions below the
    pixel; darkness 0.9779 times the cover, noise 0.01) is a weak plateau at 0.34, under
    half of the optics' darkness. Without a measured free surface it may be full contact
    through 65 % stray light and reads 6000 px. With one, its darkness varies between
    neighbouring pixels 8 times more than the noise lets it (a water film, the test
    before, varies by the noise alone): it is read as cover against the optics' value,
    the covered area to 1 % (the noise summed over 6000 px: 0.4 %), the stray-light
    reading kept in the bar."""
    rng = np.random.default_rng(0)
    d = _noise(rng, 0.01)
    cover = rng.uniform(0.2, 0.5, (60, 100))
    d[40:100, 50:150] += (OPTICS[0] * cover).astype(np.float32)
    true = float(cover.sum())
    own = area_model([d], _sigma_map(0.01), optics=OPTICS)
    assert own.weak_plateau and own.contact_source == "measured"
    assert frame_area(d, own).area_px == pytest.approx(6000, rel=0.02)
    m = area_model([d], _sigma_map(0.01), optics=OPTICS, free_measured=True)
    assert m.contact_source == "optics" and m.contact_darkness == OPTICS[0]
    a = frame_area(d, m)
    assert a.area_px == pytest.approx(true, rel=0.01)
    assert a.low_px <= true and a.high_px >= 6000


@pytest.mark.parametrize("radius_px", [10.0, 12.0])
def test_measured_free_surface_keeps_small_blurred_weak_contacts(radius_px):
    """Twelve smooth discs at darkness 0.35 (contact through a water film), blurred by
    2 px, noise 0.005, with the free surface measured: their interiors are a weak plateau
    whose darkness slopes with the blur over most of each disc. First differences of
    neighbouring pixels read that slope as pixel-to-pixel variation (2-9 times the noise's
    on such patches); second differences cancel it (1.1 here), so the discs are not taken
    for partial cover (a first-difference statistic took them for it and read them 64 %
    low) and read as without the measured free surface: within 10 % of their
    area (measured +5 and +7 %: the blur lowers their plateau to 0.27-0.30, against which
    the blurred rims are unmixed)."""
    rng = np.random.default_rng(int(radius_px))
    cov = _coverage(SHAPE, [(30 + 45 * (k % 4), 30 + 45 * (k // 4), radius_px)
                            for k in range(12)])
    d = 0.35 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 2.0) + _noise(rng, 0.005)
    own = area_model([d], _sigma_map(0.005), optics=OPTICS)
    m = area_model([d], _sigma_map(0.005), optics=OPTICS, free_measured=True)
    assert own.weak_plateau and m.contact_source == "measured"
    assert m.contact_darkness == own.contact_darkness
    a = frame_area(d, m)
    assert a.area_px == frame_area(d, own).area_px
    assert a.area_px == pytest.approx(float(cov.sum()), rel=0.10)


def test_a_field_that_tops_out_at_the_free_surfaces_reach_is_not_a_plateau():
    """A region of junctions below the pixel whose darkness spans the free surface's reach
    (uniform from 1.2 sigma below it to 1.8 sigma above; noise 0.025, reach 4.7 sigma):
    the 20 interiors past the reach pile up just above it (lower decile 0.3 sigma above),
    a narrow slice the spread test alone takes for a plateau of full contact (before the
    clearance rule: full contact 0.14, the area 6.9x the truth). It is unmixed against the
    assumed darkness of full contact instead: the truth is the region's darkness over
    0.97 (the darkness this test gives full contact), to 2 % (the noise summed over the
    region's 2400 px is 0.3 % of its darkness; the edges' share of the unmixed zone 1 %)."""
    from tir_contact.measure import _interiors

    rng = np.random.default_rng(12)
    sigma = 0.025
    d = _noise(rng, sigma)
    d[40:80, 50:110] = rng.uniform(3.5 * sigma, 6.5 * sigma, (40, 60)).astype(np.float32)
    m = area_model([d], _sigma_map(sigma))
    low = _interiors([d], float(np.nextafter(np.float32(m.seed_median), np.float32(1))))
    q10, q50, q90 = np.percentile(low, [10.0, 50.0, 90.0])
    assert low.size >= 9 and (q90 - q10) / q50 <= 1.0  # the spread test alone passes it
    assert not m.weak_plateau and m.contact_source == "assumed"
    a = frame_area(d, m)
    true = float(d[40:80, 50:110].sum()) / ASSUMED_FULL_DARKNESS
    assert a.area_px == pytest.approx(true, rel=0.02)
    assert a.low_px <= true <= a.high_px


def test_noise_alone_is_no_contact():
    rng = np.random.default_rng(9)
    d = [_noise(rng, 0.03) for _ in range(3)]
    m = area_model(d, _sigma_map(0.03))
    for f in d:
        a = frame_area(f, m)
        assert a.area_px == pytest.approx(0.0, abs=1.0)
        assert a.low_px == 0.0


def test_texture_past_half_contact_is_said_and_the_budget_holds_the_area():
    """A strong texture (sigma 0.15, correlated over 3 px) reaches past half of full
    contact: the note says the populations do not separate, and the area comes from the
    frame's darkness budget, whose bar holds the truth."""
    rng = np.random.default_rng(10)
    shape = (240, 240)

    def texture():
        f = cv2.GaussianBlur(rng.normal(size=shape).astype(np.float32), (0, 0), 3.0)
        return (0.15 * f / f.std()).astype(np.float32)

    samples = [texture() for _ in range(3)]
    discs = [(rng.uniform(60, 180), rng.uniform(60, 180), rng.uniform(0.3, 0.6))
             for _ in range(300)]
    cov = _coverage(shape, discs, ss=4)
    frame = texture() + 0.97 * cov.astype(np.float32)
    m = area_model(samples, _sigma_map(0.0, shape))
    assert m.separation <= 1.0
    assert any("do not separate" in n for n in m.notes)
    a = frame_area(frame, m)
    true = float(cov.sum())
    assert a.low_px <= true <= a.high_px
    # the budget's standard deviation: 0.15 sqrt(57600 x 113) / 0.97 = 395 px, against a
    # true area of about 250 px: the bar is wide, and says so
    assert a.high_px - a.low_px > true


def _bubbles(rng: np.random.Generator, shape, n: int, darkness: float) -> np.ndarray:
    """Darkness of `n` bubbles (discs of radius 10-30 px), each taking `darkness` of the
    light that reaches it: overlaps multiply, so the field is bounded by its deepest
    overlap (not Gaussian)."""
    h, w = shape
    yy, xx = np.mgrid[:h, :w]
    light = np.ones(shape)
    for _ in range(n):
        cx, cy, r = rng.uniform(0, w), rng.uniform(0, h), rng.uniform(10.0, 30.0)
        light[(xx - cx) ** 2 + (yy - cy) ** 2 < r * r] *= 1.0 - darkness
    return (1.0 - light).astype(np.float32)


@pytest.mark.parametrize("seed", [2, 4])
def test_bounded_texture_reach_is_read_off_the_free_pixels(seed):
    """Bubbles of darkness 0.10 (overlaps up to 0.41) and noise 0.01 around six resolved
    contacts (discs of 8 px, 0.95, blur 1 px). The Gaussian extrapolation of the bright
    half's spread puts the free surface's reach at 0.52-0.57, past half of full contact
    (0.475): the populations would not separate. The reach read off the free pixels is
    the texture's bound plus the largest noise among about 5 x 10^4 pixels (4.3 sigma):
    within 0.05 above the deepest overlap away from the contacts. The decision is then
    half of full contact, and the area is the discs' to 3 % (the bubbles under the edge
    bands add their darkness there: at most 0.41 over a band of about 2 x 50 px a disc,
    about 2 % of 1200 px on average), inside the bar."""
    rng = np.random.default_rng(seed)
    shape = (240, 240)
    texture = _bubbles(rng, shape, 40, 0.10)
    cov = _coverage(shape, [(rng.uniform(30, 210), rng.uniform(30, 210), 8.0)
                            for _ in range(6)], ss=4)
    contact = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.0)
    d = 1.0 - (1.0 - texture) * (1.0 - contact) + _noise(rng, 0.01, shape)
    m = area_model([d], _sigma_map(0.01, shape))
    away = cv2.dilate((cov > 0).astype(np.uint8), np.ones((15, 15), np.uint8)) == 0
    bound = float(texture[away].max())
    assert m.reach_measured
    assert bound <= m.seed_median <= bound + 0.05
    assert m.separation > 1.0 and not any("do not separate" in n for n in m.notes)
    assert m.threshold == pytest.approx(m.contact_darkness / 2)
    a = frame_area(d, m)
    true = float(cov.sum())
    assert a.area_px == pytest.approx(true, rel=0.03)
    assert a.low_px <= true <= a.high_px
    assert m.summary()["free_surface"]["reach_source"] == "measured"


def test_gaussian_texture_keeps_the_extrapolated_reach():
    """Where the free surface is Gaussian (noise 0.02 around a resolved contact), the
    extrapolation stays below half of full contact and is kept."""
    rng = np.random.default_rng(5)
    d = _noise(rng, 0.02)
    d[40:100, 50:150] += 0.8
    m = area_model([d], _sigma_map(0.02))
    assert not m.reach_measured
    assert m.summary()["free_surface"]["reach_source"] == "gaussian"


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_noise_that_reaches_the_core_level_keeps_the_extrapolated_reach(seed):
    """Dark footage: noise of sigma 0.18 around a resolved disc (0.95). The Gaussian reach
    (0.01 offset + 4.6 sigma: 0.84) passes half of full contact and is right: noise is
    Gaussian. The darkest pixel away from the cores reads 0.72, just under the core level
    (0.7275), because the noise's own pixels past that level are taken for cores and their
    surroundings left out; within three noise sigmas of the core level the reading is not
    taken, and the extrapolation stays."""
    rng = np.random.default_rng(seed)
    shape = (160, 200)
    cov = _coverage(shape, [(100.0, 80.0, 20.0)])
    blurred = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.0)
    d = [blurred + _noise(rng, 0.18, shape) for _ in range(3)]
    m = area_model(d, _sigma_map(0.18, shape))
    assert not m.reach_measured
    assert m.seed_median == pytest.approx(4.6 * 0.18, abs=0.03)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_static_scene_reads_junctions_over_a_bubble_against_its_local_free_surface(seed):
    """A static scene whose free surface kept a bubble (a plateau of 0.2, 60 px across)
    under a resolved contact (a disc of 6 px, 0.95, blur 1 px) and its junctions (40
    discs of 0.3-0.6 px within 14 px of it). Read against the video's free surface the
    bubble's plateau in the zone around the contact counts as contact (+100 %); against
    the local free surface (the darkness's grey opening) only the junctions rise above
    it. What is left: the resolved contact's edge band over the bubble (about 80 px read
    at 0.2) and its blur, about +15 % of 135 px: within 20 %, inside the bar."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:SHAPE[0], :SHAPE[1]]
    bubble = 0.2 * (((xx - 100) ** 2 + (yy - 80) ** 2) < 30 ** 2)
    spots = [(100 + rng.uniform(-14, 14), 80 + rng.uniform(-14, 14), rng.uniform(0.3, 0.6))
             for _ in range(40)]
    cov = _coverage(SHAPE, [(100.0, 80.0, 6.0), *spots])
    contact = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.0)
    d = (1.0 - (1.0 - bubble) * (1.0 - contact)).astype(np.float32) + _noise(rng, 0.01)
    m = area_model([d], _sigma_map(0.01), static=True)
    a = frame_area(d, m)
    true = float(cov.sum())
    assert a.area_px == pytest.approx(true, rel=0.20)
    assert a.low_px <= true <= a.high_px


def _textured_static_scene(seed: int, spots: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A static scene's darkness: a resolved contact (a disc of 10 px, 0.95, blur 1 px),
    `spots` junctions of 1.2 px radius 13-16 px from its centre, and within 30 px of it the
    light's texture the estimate continued over the contact cannot follow (white noise
    smoothed by a Gaussian of 2 px, scaled to 0.09 rms), noise 0.01; and its true cover."""
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(seed)
    ang, rad = rng.uniform(0, 2 * np.pi, spots), rng.uniform(13, 16, spots)
    discs = [(100 + r * np.cos(a), 80 + r * np.sin(a), 1.2)
             for a, r in zip(ang, rad, strict=True)]
    cov = _coverage(SHAPE, [(100.0, 80.0, 10.0), *discs])
    contact = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.0)
    field = gaussian_filter(rng.standard_normal(SHAPE), 2.0, mode="wrap")
    field /= field.std()
    yy, xx = np.mgrid[:SHAPE[0], :SHAPE[1]]
    tex = np.where((xx - 100) ** 2 + (yy - 80) ** 2 < 30 ** 2, 0.09 * field, 0.0)
    d = (1.0 - (1.0 - tex) * (1.0 - contact)).astype(np.float32) + _noise(rng, 0.01)
    return d, cov


#: The texture's correlation area in :func:`_textured_static_scene`: 4 pi s^2 for a white
#: field smoothed by a Gaussian of s = 2 px.
_TEXTURE_CORR_PX = 4 * np.pi * 2.0 ** 2


def _zone_and_frame_level_readings(d: np.ndarray):
    """`d` read as a static scene with the zone's texture known (0.09 rms,
    :data:`_TEXTURE_CORR_PX`) and without it (the frame's seed level in the zone too)."""
    zone = frame_area(d, area_model([d], _sigma_map(0.01), static=True, zone_sigma=0.09,
                                    zone_corr_px=_TEXTURE_CORR_PX))
    return zone, frame_area(d, area_model([d], _sigma_map(0.01), static=True))


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_static_scene_keeps_the_lights_texture_beside_contact_out_of_the_area(seed):
    """Beside a static scene's resolved contact (314 px) the estimate cannot follow the
    light's texture (0.09 rms); read at the frame's seed level (the noise's: 0.05), the
    texture's dark side passes and its envelope is unmixed as contact (14-29 px, the area
    4-10 % high on seeds 1-8). At the zone's own level, the texture's spread added in
    quadrature at the same false-alarm rate, none of it is kept: the area is the resolved
    contact's, within 3 % (its edge band still reads the texture: -1.4 to +2.1 %)."""
    d, cov = _textured_static_scene(seed)
    a, plain = _zone_and_frame_level_readings(d)
    true = float(cov.sum())
    assert a.unmixed_px < 1.0
    assert a.area_px == pytest.approx(true, rel=0.03)
    assert a.low_px <= true <= a.high_px
    # without the zone's texture the frame's level takes the texture for contact
    assert plain.unmixed_px > 10.0


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_static_scene_junctions_beside_contact_on_texture_are_read_in_their_bar(seed):
    """The same scene with six junctions (1.2 px radius, 4.5 px each) in the textured
    zone: those above the zone's level are kept (3-21 px unmixed on seeds 1-8), dim ones on
    the texture's bright side are lost (the area -0.8 to -6.3 % on seeds 1-8; at the
    frame's level -0.9 to +6.5 %, the texture's dark side taken with them, 18-43 px
    unmixed): within the issue's 8 % p95 target, the truth in the bar."""
    d, cov = _textured_static_scene(seed, spots=6)
    a, plain = _zone_and_frame_level_readings(d)
    true = float(cov.sum())
    assert a.unmixed_px > 2.0  # junctions are kept
    assert a.area_px == pytest.approx(true, rel=0.08)
    assert a.low_px <= true <= a.high_px
    # the frame's level unmixes more: the texture's dark side with the junctions
    assert plain.unmixed_px > a.unmixed_px


@pytest.mark.parametrize("sigma", [0.01, 0.02, 0.05])
def test_local_free_surface_of_a_noisy_plateau_is_its_mean(sigma):
    """Over a bubble's plateau (0.2, 60 px across) with Gaussian noise, the darkness over
    the local free surface is noise about ``b``: its mean within half a sigma (the opening
    of the 5 x 5 mean lies on that mean's lower envelope, about 1.7 times its spread, a
    fifth of the noise's: 0.34 sigma; the opening of the noisy darkness itself lay 2.2
    sigma low and lifted every reading by that much), its spread about sigma."""
    from tir_contact.measure import _over_local_free

    rng = np.random.default_rng(7)
    yy, xx = np.mgrid[:SHAPE[0], :SHAPE[1]]
    inside = ((xx - 100) ** 2 + (yy - 80) ** 2) < 30 ** 2
    d = (0.2 * inside).astype(np.float32) + _noise(rng, sigma)
    u = _over_local_free(d, np.isfinite(d), 0.0)
    core = ((xx - 100) ** 2 + (yy - 80) ** 2) < 20 ** 2  # away from the plateau's rim
    assert abs(float(u[core].mean())) < 0.5 * sigma
    assert float(u[core].std()) == pytest.approx(sigma, rel=0.2)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_static_scene_counts_thin_contact_beyond_the_zone_not_faint_dust(seed):
    """A static scene: a resolved contact (a disc of 6 px, 113 px), and beyond the zone
    unresolved contact is sought in (:data:`ZONE_PX`) two thin junctions (lines 2 px wide
    and 14 px long at full darkness 0.95, too thin for the 3 x 3 opening: not resolved)
    and a faint out-of-focus dust spot (a Gaussian of 3 px, 0.25 deep: 14 px of area at
    full darkness if read as contact), all blurred by 1 px. The junctions reach half of
    full contact, which the free surface never does here (its reach is the noise's): by
    the segmentation's own decision they are contact, and their blur within the kept
    seeds' envelope (:data:`EDGE_PX`: 98 % of a 1 px blur) is unmixed with them. Before,
    they were left to the bar's high end with the dust (area 113 px against the truth's
    169). The dust stays out of the area (it never reaches half) and in the bar's high
    end. The truth, 113 + 56 px: the area within 3 % (the lines' blur tails beyond the
    envelope and the edge bands' noise: -0.6 % on seeds 1-5)."""
    rng = np.random.default_rng(seed)
    cov = _coverage(SHAPE, [(100.0, 80.0, 6.0)])
    lines = np.zeros(SHAPE, np.float32)
    lines[40:42, 140:154] = 1.0
    lines[120:134, 60:62] = 1.0
    cov = cov + lines
    yy, xx = np.mgrid[:SHAPE[0], :SHAPE[1]]
    dust = 0.25 * np.exp(-((xx - 150) ** 2 + (yy - 120) ** 2) / (2 * 3.0 ** 2))
    contact = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.0)
    d = (1.0 - (1.0 - dust) * (1.0 - contact)).astype(np.float32) + _noise(rng, 0.01)
    m = area_model([d], _sigma_map(0.01), static=True)
    assert m.threshold == pytest.approx(0.475, abs=0.01)
    a = frame_area(d, m)
    true = float(cov.sum())
    assert true == pytest.approx(169.0, abs=0.5)
    assert a.area_px == pytest.approx(true, rel=0.03)
    assert a.low_px <= true <= a.high_px
    # the dust is in the bar's high end: its 14 px of excess at full darkness
    assert a.high_px - a.area_px > 14.0


def test_static_scene_leaves_the_lit_rims_fall_off_out_of_thin_contact():
    """A static scene in a found lit disc (radius 70 px, rim band 6 px) whose light falls
    off in the band's inner 2 px ring inside the found edge to 0.6 darkness (past half of
    full contact, thin: not resolved), and a resolved contact (a disc of 6 px, 113 px) at
    the centre. Thin contact beyond the zone is counted where it reaches half of full
    contact, but not in the rim band, where the light's own fall-off reaches as dark (the
    ring would add about 550 px): the area is the disc's, within 2 % (its edge band's
    noise)."""
    from tir_contact.illumination import LitZone, _rim
    from tir_contact.tir_view import _rim_band

    h, w = SHAPE
    yy, xx = np.mgrid[:h, :w]
    r = np.hypot(xx - w / 2, yy - h / 2)
    found = r < 70
    rng = np.random.default_rng(5)
    cov = _coverage(SHAPE, [(100.0, 80.0, 6.0)])
    d = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.0) + _noise(rng, 0.01)
    ring = found & (r >= 68)
    d[ring] += 0.6
    d[~found] = np.nan
    lit = LitZone(found, _rim(found, 6), "found", rim_px=6)
    m = area_model([d], _sigma_map(0.01), static=True, rim=_rim_band(lit))
    assert m.rim[ring].all()
    a = frame_area(d, m)
    assert a.area_px == pytest.approx(float(cov.sum()), rel=0.02)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_static_junctions_with_their_contrast_given_are_counted(seed):
    """A static scene of junctions only (80 discs of 0.4-0.7 px, none resolved) with the
    darkness of full contact given (--contrast 0.95): a given contrast does not show where
    contact is, so the significant clusters are contact. The area was 0 (every seed taken
    for dust beside resolved contact that is not there); now the junctions' area to 3 % (the
    blur tail beyond the clusters' envelope), inside the bar."""
    rng = np.random.default_rng(seed)
    spots = [(100 + rng.uniform(-20, 20), 80 + rng.uniform(-20, 20), rng.uniform(0.4, 0.7))
             for _ in range(80)]
    cov = _coverage(SHAPE, spots)
    d = 0.95 * cv2.GaussianBlur(cov.astype(np.float32), (0, 0), 1.0) + _noise(rng, 0.01)
    m = area_model([d], _sigma_map(0.01), static=True, contrast=0.95)
    assert m.contact_source == "given" and m.n_full_px < MIN_FULL_PX
    a = frame_area(d, m)
    true = float(cov.sum())
    assert a.area_px == pytest.approx(true, rel=0.03)
    assert a.low_px <= true <= a.high_px


def test_box_limits_the_search():
    rng = np.random.default_rng(11)
    d = _noise(rng, 0.02)
    d[40:100, 50:150] += 0.8
    m = area_model([d], _sigma_map(0.02))
    whole = frame_area(d, m)
    boxed = frame_area(d, m, (slice(30, 110), slice(40, 160)))
    assert boxed.resolved_px == whole.resolved_px
    assert boxed.area_px == pytest.approx(whole.area_px, rel=0.002)
    assert math.isfinite(boxed.high_px)


def test_contact_plot_draws_the_error_bar(tmp_path, monkeypatch):
    """contact.png shades the band between contact_area_low_mm2 and _high_mm2."""
    import matplotlib.collections
    import pandas as pd

    from tir_contact import plots

    t = np.arange(5) / 1000.0
    frames = pd.DataFrame({"time_s": t, "contact_area_mm2": [1.0, 2, 3, 2, 1],
                           "contact_area_low_mm2": [0.9, 1.8, 2.7, 1.8, 0.9],
                           "contact_area_high_mm2": [1.2, 2.4, 3.6, 2.4, 1.2],
                           "contact_ratio": 0.5, "block_fully_in_view": True})
    drawn = {}
    real_save = plots._save

    def keep(fig, path):
        drawn[path.name] = fig
        return real_save(fig, path)

    monkeypatch.setattr(plots, "_save", keep)
    plots.plot_video_results(frames, pd.DataFrame(), tmp_path)
    ax = drawn["contact.png"].axes[0]
    bands = [c for c in ax.collections if isinstance(c, matplotlib.collections.PolyCollection)
             and c.get_label() == "error bar (low-high)"]
    assert len(bands) == 1
    ys = bands[0].get_paths()[0].vertices[:, 1]
    assert ys.min() == pytest.approx(0.9) and ys.max() == pytest.approx(3.6)


def test_overlay_writes_the_area_with_its_error_bar(monkeypatch):
    import pandas as pd

    from tir_contact import overlay

    written = []
    real = overlay.cv2.putText

    def spy(img, text, *args, **kw):
        written.append(text)
        return real(img, text, *args, **kw)

    monkeypatch.setattr(overlay.cv2, "putText", spy)
    frame = np.full((40, 60), 200, np.uint8)
    overlay.draw_tir_overlay(frame, np.zeros((40, 60), bool), pd.DataFrame(),
                             {"contact_area_mm2": 12.34, "contact_area_low_mm2": 11.0,
                              "contact_area_high_mm2": 13.52}, mm_per_px=0.1, label="clip")
    assert written[-1] == "clip  area 12.3 mm2 (11.0-13.5)"


def test_static_scene_bar_spans_dust_next_to_contact():
    # A static scene whose ice carries dust spots (darkness 0.28, blurred), some of them
    # beside resolved contacts: the seeds there are kept as contact, so the local
    # estimate is high by their darkness; the budget (every pixel's excess over the free
    # surface's mean, dust included) is the truth to its noise, and the bar spans it.
    rng = np.random.default_rng(5)
    h, w = 200, 240
    d = rng.normal(0, 0.02, (h, w)).astype(np.float32)
    dust = np.zeros((h, w), np.float32)
    for _ in range(260):
        y, x = rng.integers(0, h), rng.integers(0, w)
        cv2.circle(dust, (int(x), int(y)), int(rng.integers(1, 3)), 0.28, -1)
    d += cv2.GaussianBlur(dust, (0, 0), 0.7)
    contact = np.zeros((h, w), np.uint8)
    for k in range(12):
        y, x = 30 + 35 * (k // 4) + rng.integers(-5, 5), 30 + 55 * (k % 4) + rng.integers(-5, 5)
        cv2.circle(contact, (int(x), int(y)), 4, 1, -1)
    truth = int(contact.sum())  # 588 px
    d = np.where(contact > 0, 0.95 + rng.normal(0, 0.02, (h, w)), d).astype(np.float32)
    m = area_model([d], np.full(d.shape, 0.02, np.float32), static=True)
    a = frame_area(d, m)
    assert a.area_px > 1.1 * truth  # the local estimate keeps the dust beside contact
    assert a.low_px <= truth <= a.high_px


def test_static_scene_bar_reaches_the_resolved_contact_alone():
    """A static scene whose only dust (darkness 0.28, blurred) lies beside its contacts
    (12 discs of 4 px radius, darkness 0.95): the budget holds the dust too, so only the
    reading where every seed beside resolved contact is dust brings the bar's low end
    down to the contacts' own area."""
    rng = np.random.default_rng(6)
    h, w = 200, 240
    d = rng.normal(0, 0.02, (h, w)).astype(np.float32)
    dust = np.zeros((h, w), np.float32)
    contact = np.zeros((h, w), np.uint8)
    for k in range(12):
        y, x = 30 + 45 * (k // 4), 30 + 60 * (k % 4)
        cv2.circle(contact, (x, y), 4, 1, -1)
        for _ in range(4):  # dust spots 6-8 px from the contact's centre
            a = rng.uniform(0, 2 * math.pi)
            r = rng.uniform(6, 8)
            cv2.circle(dust, (int(x + r * math.cos(a)), int(y + r * math.sin(a))), 2, 0.28, -1)
    d += cv2.GaussianBlur(dust, (0, 0), 0.7)
    truth = int(contact.sum())
    d = np.where(contact > 0, 0.95 + rng.normal(0, 0.02, (h, w)), d).astype(np.float32)
    m = area_model([d], np.full(d.shape, 0.02, np.float32), static=True)
    a = frame_area(d, m)
    assert a.area_px > 1.1 * truth  # the dust beside contact is kept as contact
    assert a.low_px <= truth <= a.high_px


def _disc_with_stripe(h: int, w: int, radius: int, stripe_end: int, rim_px: int):
    """A lit disc (found edge at `radius`, centred) whose rim band is `rim_px` wide, a contact
    stripe (darkness 0.9, 23 px wide) from the frame's top to row `stripe_end` across its
    rim, noise 0.02, NaN outside the disc; returns the darkness, the area model with the
    rim band, the disc's squared-radius image and the stripe."""
    from tir_contact.illumination import LitZone, _rim
    from tir_contact.tir_view import _rim_band

    yy, xx = np.mgrid[:h, :w]
    r2 = (xx - w // 2) ** 2 + (yy - h // 2) ** 2
    found = r2 < radius ** 2
    stripe = (np.abs(xx - w // 2) < 12) & (yy < stripe_end)
    rng = np.random.default_rng(3)
    d = rng.normal(0.0, 0.02, found.shape).astype(np.float32)
    d[stripe] += 0.9
    d[~found] = np.nan
    lit = LitZone(found, _rim(found, rim_px), "found", rim_px=rim_px)
    m = area_model([d], np.full(d.shape, 0.02, np.float32), rim=_rim_band(lit))
    return d, m, r2, stripe


def test_contact_at_the_rim_may_go_on_past_the_found_edge():
    # A lit disc whose found edge lies 2 px inside the true half-light line (the rim band,
    # 4 px, is the edge's stated tolerance); a contact stripe crosses the rim. The truth
    # counts the stripe up to the true line: the bar's high end holds it, the area (what
    # is seen) is the stripe inside the found zone.
    d, m, r2, stripe = _disc_with_stripe(160, 200, 60, 60, rim_px=4)
    a = frame_area(d, m)
    found, true_zone = r2 < 60 ** 2, r2 < 62 ** 2
    seen, truth = int((stripe & found).sum()), int((stripe & true_zone).sum())
    assert abs(a.area_px - seen) < 0.02 * seen  # 1 px of blur-free edge: 2 %
    assert a.high_px >= truth > seen
    assert a.high_px < truth + 2 * (truth - seen) + 0.1 * seen  # about the band, not more


def test_rim_term_is_the_same_in_the_contact_box():
    # the analysis reads a box round the contact (grown by 11 px); a rim band wider than
    # that (19 px: 1 % of a 1900 px frame) still counts its whole reach past the box
    d, m, _, _ = _disc_with_stripe(300, 400, 120, 100, rim_px=19)
    box = (slice(19, 111), slice(177, 224))  # the stripe's box in the lit zone, grown 11 px
    whole = frame_area(d, m, (slice(0, 300), slice(0, 400)))
    boxed = frame_area(d, m, box)
    assert boxed.area_px == pytest.approx(whole.area_px, rel=1e-9)
    assert boxed.high_px == pytest.approx(whole.high_px, rel=1e-9)


def test_rim_band_is_as_wide_as_the_zones_rim():
    # the band a found zone was made with is its width; a zone built without it reads the
    # width from the rim's depth, up to a pixel over (the distance transform's rounding)
    from tir_contact.illumination import LitZone, find_lit_zone
    from tir_contact.tir_view import _rim_band

    yy, xx = np.mgrid[:400, :640]
    disc = np.where((xx - 320) ** 2 + (yy - 200) ** 2 < 150 ** 2, 100.0, 5.0)
    zone = find_lit_zone(disc.astype(np.float32))
    assert zone.rim_px == 6  # 1 % of the long side
    rim, beyond, width = _rim_band(zone)
    assert width == 6
    assert np.array_equal(rim, zone.rim)
    out = cv2.distanceTransform((~zone.mask).view(np.uint8), cv2.DIST_L2, 5)
    assert beyond.any() and out[beyond].max() <= 6.5  # the unlit pixels within the width
    assert _rim_band(LitZone(zone.mask, zone.rim, "found"))[2] in (6, 7)


def _junction_field(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Covered share of each pixel by junctions far below it (an 8 x 8 subgrid, each
    point covered with a probability falling as a Gaussian from 0.25 at (100, 80) px,
    sigma 15 px), and its darkness at 0.97 with noise 0.01."""
    ss = 8
    h, w = SHAPE
    yy, xx = np.mgrid[0:h * ss, 0:w * ss]
    r2 = ((xx + 0.5) / ss - 100.0) ** 2 + ((yy + 0.5) / ss - 80.0) ** 2
    share = 0.25 * np.exp(-r2 / (2 * 15.0**2))
    cov = (rng.random(share.shape) < share).reshape(h, ss, w, ss).mean(axis=(1, 3))
    return cov, (0.97 * cov).astype(np.float32) + _noise(rng, 0.01)


def test_junction_field_below_the_seed_level_is_counted_in_the_box():
    """A field of junctions far below a pixel (the share of each pixel in contact drawn on
    an 8 x 8 subgrid with a probability that falls as a Gaussian from 0.25 at the centre,
    sigma 15 px, as on a rough block face), darkness 0.97, noise 0.01, no resolved contact:
    read in the box a fixed camera reads, its area is the covered area to 3 % (the noise
    summed over the box's 32000 pixels is 0.5 % of it, the offset's error over them 1 %).
    The seeds' zone alone, which holds the field only where its darkness passes the seed
    level, misses its faint edge (10 %)."""
    import dataclasses

    rng = np.random.default_rng(5)
    cov, d = _junction_field(rng)
    # the video's sampled frames: one before the block arrives, and this one (the free
    # surface's offset from this frame alone is lifted by the field's faint fifth of it:
    # -4 % over the box)
    m = area_model([_noise(rng, 0.01), d], _sigma_map(0.01))
    assert m.contact_source == "assumed"
    box = (slice(0, SHAPE[0]), slice(0, SHAPE[1]))
    a = frame_area(d, m, box)
    true = float(cov.sum())
    assert a.resolved_px == 0
    assert a.area_px == pytest.approx(true, rel=0.03)
    assert a.low_px <= true <= a.high_px
    # as where the sampled frames showed resolved contact: the seeds' zone alone
    zone_only = frame_area(d, dataclasses.replace(m, n_full_px=MIN_FULL_PX), box)
    assert zone_only.area_px < 0.93 * true


def test_junction_field_with_its_contrast_given_and_a_frame_of_noise_alone():
    """The field reading rests on the sampled frames showing no resolved contact, not on an
    assumed full darkness: with the contrast given (0.97, the field's own) the field of the
    test above reads its covered area to 3 % as well. A frame of noise alone with one
    stray seed (0.08, which the cluster test rejects) reads no contact, not the box's noise
    summed (which is below zero about as often as above)."""
    rng = np.random.default_rng(5)
    cov, d = _junction_field(rng)
    m = area_model([_noise(rng, 0.01), d], _sigma_map(0.01), contrast=0.97)
    assert m.contact_source == "given"
    box = (slice(0, SHAPE[0]), slice(0, SHAPE[1]))
    assert frame_area(d, m, box).area_px == pytest.approx(float(cov.sum()), rel=0.03)
    assumed = area_model([_noise(rng, 0.01), d], _sigma_map(0.01))
    for k in range(20):
        e = _noise(np.random.default_rng(100 + k), 0.01)
        e[60, 60] = 0.08
        for model in (m, assumed):
            a = frame_area(e, model, (slice(40, 81), slice(40, 81)))
            assert a.area_px == a.low_px == 0.0


def test_pixels_are_measured_again_at_the_models_own_decision(monkeypatch):
    """TirView.prepare's second cut (tir_view._remeasured): the pixels too noisy for the
    first contrast estimate's half (0.15) are cut again at the model's decision (0.485)
    where the populations separate, and the model made on the wider set is kept only
    where it still separates and its decision is no lower; otherwise the first cut and
    model stand."""
    from types import SimpleNamespace as NS

    import tir_contact.tir_view as tv

    def ref(n_valid):
        valid = np.zeros(100, bool)
        valid[:n_valid] = True
        return NS(reference=NS(valid=valid))

    cuts = []

    def measurable(whole, threshold, n_sigma, sigma=None):
        cuts.append(threshold)
        return ref(int(threshold * 100))  # a higher decision keeps more pixels

    again = {}
    monkeypatch.setattr(tv, "measurable", measurable)
    monkeypatch.setattr(tv.TirView, "population_model",
                        staticmethod(lambda samples, tref, contact_is, options, sigma=None,
                                     optics=None: again["m"]))
    first, model = ref(15), NS(threshold=0.485, separation=3.0)
    options = NS(noise_sigmas=5.0)
    args = ([], ref(100), first, model, 0.15, "dark", options)
    again["m"] = NS(threshold=0.485, separation=2.5)
    tref, m = tv._remeasured(*args)
    assert cuts == [0.485] and m is again["m"]
    assert np.count_nonzero(tref.reference.valid) == 48
    for kept in (NS(threshold=0.40, separation=2.5),    # a lower decision
                 NS(threshold=0.60, separation=0.9)):   # no longer separating
        again["m"] = kept
        assert tv._remeasured(*args) == (first, model)
    # a first model that does not separate, or whose decision is the first cut's: no cut
    cuts.clear()
    for m0 in (NS(threshold=0.485, separation=0.8), NS(threshold=0.15, separation=3.0)):
        assert tv._remeasured([], ref(100), first, m0, 0.15, "dark", options) == (first, m0)
    assert cuts == []


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_junction_field_box_is_read_against_the_free_surfaces_mean(seed):
    """A junction field (no resolved contact: every pixel of the box round it is summed)
    on a free surface whose noise is skewed (mean 0.0026 above its median, as 8-bit steps
    and JPEG make it): against the median every free pixel of the box adds 0.0026, about
    14 px over this box; against the free surface's mean away from contact the sum holds
    the drawn coverage. Two of the sampled frames are free, the block passes in the rest."""
    rng = np.random.default_rng(seed)

    def frame(col: int | None) -> tuple[np.ndarray, float]:
        d = 0.01 + rng.gamma(2.0, 0.008, SHAPE).astype(np.float32)  # skewed free surface
        if col is None:
            return d, 0.0
        # 40 x 60 px of junctions: a third of the pixels 30 % covered (none past half)
        cov = np.where(rng.random((40, 60)) < 1 / 3, 0.3, 0.0).astype(np.float32)
        d[50:90, col:col + 60] += 0.97 * cov
        return d, float(cov.sum())

    samples = [frame(None)[0], frame(None)[0]] + [frame(c)[0] for c in (10, 40, 70, 100)]
    noise = 0.0113  # the gamma's standard deviation
    m = area_model(samples, _sigma_map(noise))
    assert m.n_full_px < 9 and m.contact_source == "assumed"
    assert m.graded  # nothing resolved: whatever contact there is lies below the pixel
    assert m.field_offset - m.offset == pytest.approx(0.0026, abs=0.0008)
    d, true = frame(70)
    box = (slice(39, 101), slice(59, 141))  # the contact grown by the analysis's zone
    a = frame_area(d, m, box)
    n_box = 62 * 82
    # tolerance: the free surface's noise summed over the box (0.0113 sqrt(5084) / 0.97 =
    # 0.8 px) and the mean's own uncertainty (about 0.0002 over the box: 1 px), 3 sigma
    assert a.area_px == pytest.approx(true, abs=4.0)
    # the median's reading, (mean - median) x the box's pixels higher, lies in the bar
    median_reading = a.area_px + (m.field_offset - m.offset) * n_box / m.contact_darkness
    assert median_reading - true > 8.0
    assert a.low_px <= true <= a.high_px and a.high_px >= median_reading


def test_dense_junction_clusters_are_not_taken_for_full_contact_alone():
    """A face of junctions (pixels 45 % covered, nine in ten at its front, one in ten
    behind it) with three dense clusters (5 x 5 px, 64 % covered): the clusters' interiors
    pass as resolved contact at 0.62 darkness, which a block seen through 36 % stray light
    would show too. The contact is graded, so the error bar reaches down to full contact
    without stray light, where the truth (the drawn coverage, full contact 0.97) lies;
    read at 0.62 the area is 1.33 times the truth."""
    rng = np.random.default_rng(5)

    def frame(col: int | None) -> tuple[np.ndarray, float]:
        d = _noise(rng, 0.01) + 0.01
        if col is None:
            return d, 0.0
        share = 0.1 + 0.8 * np.exp(-np.arange(60) / 4.0)  # the front on the left
        cov = np.where(rng.random((40, 60)) < share, 0.45, 0.0).astype(np.float32)
        for r, c in ((5, 15), (20, 30), (30, 50)):
            cov[r:r + 5, c:c + 5] = 0.64
        d[50:90, col:col + 60] += 0.97 * cov
        return d, float(cov.sum())

    samples = [frame(None)[0]] + [frame(c)[0] for c in (10, 40, 70, 100)]
    m = area_model(samples, _sigma_map(0.01))
    assert m.contact_source == "measured" and m.contact_darkness < 0.7
    assert m.graded and m.contact_high == 1.0
    d, true = frame(70)
    a = frame_area(d, m, (slice(39, 101), slice(59, 141)))
    assert a.area_px / true > 1.2  # read at 0.62 (the clusters counted whole)
    assert a.low_px <= true <= a.high_px


def test_free_surface_offset_spread_between_places():
    """The free surface's offset between tiles (`_free_tiles`): eight frames of 2 % noise
    whose offset is 0 on the left half of the frame and 0.003 on the right; a junction
    field (a 40 x 60 px block, 10 % of its pixels at 0.3) in a different place in each
    frame, which the tile test leaves out. Truths: the mean, 0.0015 (half the tiles at
    each offset), within 0.0003 (the tiles left out with the field may tip the halves'
    balance by a few tiles: 0.0003 is a tenth of the tiles moving sides); the spread,
    0.0015 (the standard deviation of two equal halves 0.003 apart), within 0.0003 (the
    tiles' noise, 0.02 / sqrt(8 x 256) = 0.0004 each, taken out to a few per cent of it).
    A uniform offset's spread is noise alone: under 0.0003 (the noise's removal leaves
    its estimate's scatter, 0.0004 / sqrt(2 x 120 tiles) x a few)."""
    from tir_contact.measure import _free_tiles

    rng = np.random.default_rng(11)

    def frames(step: float) -> list[np.ndarray]:
        out = []
        for k in range(8):
            d = _noise(rng, 0.02)
            d[:, SHAPE[1] // 2:] += step
            field = np.where(rng.random((40, 60)) < 0.1, 0.3, 0.0).astype(np.float32)
            r, c = 20 + 12 * k, 10 + 16 * k
            d[r:r + 40, c:c + 60] += field
            out.append(d)
        return out

    mean, spread = _free_tiles(frames(0.003), 0.02)
    assert mean == pytest.approx(0.0015, abs=0.0003)
    assert spread == pytest.approx(0.0015, abs=0.0003)
    assert _free_tiles(frames(0.0), 0.02)[1] < 0.0003


def _static_field(seed: int, n_spots: int, texture: float, noise: float = 1.0):
    """A static scene of `n_spots` junctions (0.6-1.4 px radius, darkness 0.97, blurred by
    1 px) on light of 200 grey values with a `texture` rms at 6 px, `noise` grey values: its five
    frames' darkness against the free surface estimated from their median
    (:func:`tir_contact.reference.free_surface`), the estimate, and the junctions' covered
    share of each pixel."""
    from scipy.ndimage import gaussian_filter

    from tir_contact.reference import free_surface

    rng = np.random.default_rng(seed)
    tex = gaussian_filter(rng.normal(0.0, 1.0, SHAPE), 6.0)
    light = 200.0 * (1.0 + texture * tex / tex.std())
    spots = [(rng.uniform(40, 160), rng.uniform(30, 130), rng.uniform(0.6, 1.4))
             for _ in range(n_spots)]
    cov = _coverage(SHAPE, spots) if spots else np.zeros(SHAPE)
    dark = 0.97 * gaussian_filter(cov, 1.0)
    frames = [(light * (1.0 - dark) + rng.normal(0.0, noise, SHAPE)).astype(np.float32)
              for _ in range(5)]
    surface = free_surface(np.median(frames, axis=0))
    d = [(1.0 - f / surface.image).astype(np.float32) for f in frames]
    return d, surface, cov


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_static_junction_field_the_estimate_follows_is_inside_the_bar(seed):
    """A static junction field without an empty frame: 60 junctions (185-209 px covered)
    on light with an 8 % rms texture at 6 px (:func:`_static_field`). The free surface is
    estimated from the image, which is the image itself beyond its few contact
    candidates: it follows most junctions, and the area reads 11-54 % of the covered
    area. Before, the bar's high end read the frame against that estimate too (29-80 % of
    the truth); now it also reads it against the estimate without the dark spots narrower
    than the local free surface's disc, less the closing's median lift over the noise
    (:func:`tir_contact.measure.with_absorbed`), which may be junctions or the light's own
    texture: the truth lies in the bar, whose high end is 3.0-3.7 times it (the same light
    without junctions reads 480-610 px there: the image cannot tell the two apart; the
    model's notes say so).

    Truth: the junctions' covered share of each pixel (supersampled 8 x 8)."""
    from tir_contact.measure import with_absorbed
    from tir_contact.reference import absorbed_darkness

    d, surface, cov = _static_field(seed, 60, 0.08)
    m = area_model(d, _sigma_map(1.0 / 200.0), static=True,
                   zone_sigma=surface.texture_sigma, zone_corr_px=surface.texture_corr_px)
    assert m.junction_field
    old = frame_area(d[0], m)
    m = with_absorbed(m, absorbed_darkness(surface.image, np.ones(SHAPE, bool)))
    assert any("narrower than 17 px" in n for n in m.notes)
    true = float(cov.sum())
    a = frame_area(d[0], m)
    assert a.area_px == old.area_px < 0.6 * true  # the estimate followed most junctions
    assert old.high_px < true
    assert a.low_px <= true <= a.high_px


@pytest.mark.parametrize("seed", [0, 1])
def test_static_scene_without_contact_keeps_its_high_end_at_the_noise(seed):
    """The same reading on flat light without junctions or texture, noise 2 % of the light:
    the closing lifts every pixel of the estimate to its noise's upper envelope, which
    summed over the frame's 32000 px read 122-124 px of contact; its median over the frame
    is taken out, and the high end reads 40-45 px (7-12 px without the reading): under
    0.2 % of the frame above it."""
    from tir_contact.measure import with_absorbed
    from tir_contact.reference import absorbed_darkness

    d, surface, _ = _static_field(seed, 0, 0.0, noise=4.0)
    m = area_model(d, _sigma_map(4.0 / 200.0), static=True)
    old = frame_area(d[0], m)
    a = frame_area(d[0], with_absorbed(m, absorbed_darkness(surface.image,
                                                            np.ones(SHAPE, bool))))
    assert a.high_px < old.high_px + 0.002 * d[0].size, (a.high_px, old.high_px)


def test_absorbed_reading_needs_a_static_junction_field_and_notes_a_given_contrast():
    """The reading is for a static scene without resolved contact only; with the contrast
    given (no assumed-darkness note to add to) it is a note of its own."""
    from tir_contact.measure import with_absorbed
    from tir_contact.reference import absorbed_darkness

    d, surface, _ = _static_field(0, 60, 0.08)
    a = absorbed_darkness(surface.image, np.ones(SHAPE, bool))
    with pytest.raises(ValueError, match="static scene without resolved contact"):
        with_absorbed(area_model(d, _sigma_map(1.0 / 200.0)), a)
    m = with_absorbed(area_model(d, _sigma_map(1.0 / 200.0), static=True, contrast=0.97), a)
    note = m.notes[-1]
    assert note.startswith("no contact is resolved in this static scene: the error bar's "
                           "high end reads")
    assert "--reference" in note


def test_contact_at_the_rim_may_lie_past_the_true_edge():
    # The same disc, its found edge now 2 px outside the true half-light line (within the
    # rim band, 4 px, the edge's stated tolerance): the stripe is seen up to the found edge,
    # but the truth counts it only up to the true line. The bar's low end holds it: the
    # contact in the band may lie past the true line.
    d, m, r2, stripe = _disc_with_stripe(160, 200, 60, 60, rim_px=4)
    a = frame_area(d, m)
    found, true_zone = r2 < 60 ** 2, r2 < 58 ** 2
    seen, truth = int((stripe & found).sum()), int((stripe & true_zone).sum())
    assert abs(a.area_px - seen) < 0.02 * seen
    assert a.low_px <= truth < seen
    assert a.low_px > truth - 2 * (seen - truth) - 0.1 * seen  # about the band, not more
