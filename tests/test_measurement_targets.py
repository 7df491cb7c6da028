"""Issue 21's measurement targets on a small fixed subset of the validation
(examples/validate_pipeline.py: the physical classes, the load series and the renders of the
issue's table, :mod:`synthetic.table`), held as strict xfails where today's pipeline misses
them (a strict xfail turns into a failure the day the pipeline passes, so the marker cannot
outlive the fix).

The truth is the renderer's: the true contact area (gap 0, inside the lit mask). The subset:
five clips of the physical classes drawn by :func:`synthetic.domain.sample_physical_specs`
(seed 0, fixed indices), short (4 frames static, 16 frames of the sliding block): the
shared fixture takes about 35 s, each render of the table under 10 s, the load series
(four rough-contact solves) about 5 s and its eight further draws about 40 s (2 cores). It
is a check, not the published figure (that is ``validate_pipeline.py --physical N
--table``).
"""

from __future__ import annotations

import dataclasses
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from _extras import needs_tamaas

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))

from _domain_validation import (
    MEASUREMENT_TARGETS,
    load_error_columns,
    load_series,
    load_series_draws,
    stray_light_spec,
    summarise,
    validate_clip,
    validate_table_clip,
)

pytestmark = pytest.mark.slow

#: Draws of sample_physical_specs(12, seed=0), the cheapest of each class (0.01-0.02
#: mm/px; rendered and analysed in 1-17 s each): rough pads (one textured), rough spheres,
#: one sliding block with physical real contact.
SUBSET = {"tir rough pad": (6, 11), "tir rough sphere": (5, 10), "tir physical block": (4,)}


def _short(spec):
    return dataclasses.replace(spec, n_frames=16 if spec.scene == "block" else 4)


@pytest.fixture(scope="module")
def physical_summary():
    import pandas as pd

    from synthetic.domain import sample_physical_specs

    specs = sample_physical_specs(12, seed=0)
    rows = []
    for case, indices in SUBSET.items():
        for i in indices:
            spec, drawn = specs[i]
            assert drawn == case  # the draws are fixed by the seed
            rows.append(validate_clip(_short(spec), case, i))
    table = pd.DataFrame(rows)
    return summarise(table).set_index("case")


def _all(summary, key):
    return float(summary.loc["all", key])


@needs_tamaas
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "issue 21: sub-pixel junctions beyond the zone of resolved contact in static scenes; "
    "measured on the ice of the thesis's flaw density: 3-57 % per clip over the subset "
    "(2-178 % on the crowded ice of the draws before, e61c71b)"))
def test_physical_area_error_median_within_2_percent(physical_summary):
    assert _all(physical_summary, "area_err_pct median") <= MEASUREMENT_TARGETS[
        "area_err_pct median"]


@needs_tamaas
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "issue 21: the worst physical clips are far off (rough pad draw 6: 57 % low, its fading "
    "junction field taken for light falling off)"))
def test_physical_area_error_p95_within_8_percent(physical_summary):
    assert _all(physical_summary, "area_err_pct p95") <= MEASUREMENT_TARGETS["area_err_pct p95"]


@needs_tamaas
def test_physical_truth_inside_the_error_bar_in_90_percent_of_frames(physical_summary):
    """Item 2's target on the subset: 31 of its 32 frames (96.9 %; rough pad draw 6, its
    junctions up to 30 px beyond the resolved ones, 3 of 4). On the crowded ice of the
    draws before their flaws were read as densities: 29 of 32 once a static scene's bar
    reached up to the significant seed clusters beyond the zone around resolved contact
    (draw 6 1 of 4; it was 0 of 4 and the subset 87.5 %; e61c71b: 75 %)."""
    assert "in_band_pct" in physical_summary, "frames.csv has no contact_area_low/high_mm2"
    assert _all(physical_summary, "in_band_pct") >= MEASUREMENT_TARGETS["in_band_pct"]


@needs_tamaas
def test_junction_field_in_the_dim_rim_of_a_dark_jpeg_is_measured():
    """A physical block (G7, 6.5 % real contact: a field of junctions below the pixel, none
    resolved) in an 8-bit JPEG at a white level of 0.11 whose lit disc has a wide dim rim
    (held-out draw 11 of seed 7). Before the plateau clearance rule it read 280 % high (nine
    interiors just past the free surface's reach taken for full contact behind stray
    light); with it, but the pixels cut as too noisy at the first contrast estimate (18 %
    of the frame, up to 63 % of the contact while the block enters), 19.7 % low with the
    truth in its bar in 28 of 56 frames; measured at the model's own decision, 4.4 % high
    with the truth in the bar in 45 of 56. Tolerances: 8 %, the issue's p95; in the bar 70 %
    of the frames (the misses are frames read 5-10 % high, their bar's low end a few
    percent above the truth)."""
    from synthetic.domain import sample_physical_specs

    spec, case = sample_physical_specs(12, seed=7)[11]
    assert case == "tir physical block" and spec.camera.bit_depth == 8
    row = validate_clip(spec, case, 11)
    assert abs(row["area_err_pct"]) <= 8.0, row
    assert row["frames_in_band"] >= 0.7 * row["frames_scored"], row


@pytest.fixture(scope="module")
def series():
    return load_series(n_frames=3)


@needs_tamaas
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "issue 21: this draw's line meets zero load at -20.3 % of the 0.5 bar area (truth -0.7 %): "
    "its 0.5 bar area reads 9 % low (29 draws at 0.5 bar: 5.7 % low on average, 7.1 % sd, "
    "about 2 % lower for each % the texture under the junctions, which the static estimate "
    "cannot follow there, is brighter; here 1.4 %); on eight further draws the line follows "
    "the true one to 13 points (test_load_series_draws_follow_the_true_line). 0.3 point "
    "over the target; the lowest and the newest versions pyproject.toml allows read -20.315 "
    "and -20.321 % (numpy 1.24 / 2.4, scipy 1.10 / 1.17, OpenCV 4.8 / 5.1), so no package "
    "version is expected to move it across"))
def test_load_series_is_proportional_to_load(series):
    """Rough pad on a textured field at 0.5/1/2/4 bar (no empty frame): the line through
    (load, measured area) meets zero load within 20 % of the lowest load's area."""
    _, fit = series
    # the truth itself passes by far (about 1 %: real contact grows as p^0.9-1)
    assert abs(fit["true_intercept_pct"]) < 5.0
    assert abs(fit["intercept_pct"]) < MEASUREMENT_TARGETS["intercept_pct"]


@pytest.fixture(scope="module")
def draws():
    return load_series_draws(n_frames=3)


@needs_tamaas
def test_load_series_draws_follow_the_true_line(draws):
    """Eight further draws of the load series (seeds 100-107, each its own rough face and
    texture): the line through (load, measured area) meets zero load within 20 points of
    the true line's intercept (the target's 20 %, applied to the reading's departure from
    the truth: the true line itself meets zero load at -2 to +38 % of the lowest load's
    area on these draws)."""
    off = draws.intercept_off_pts.abs()
    assert (off < MEASUREMENT_TARGETS["intercept_pct"]).all(), draws


def _draw_errors(draws) -> np.ndarray:
    return np.abs(draws[load_error_columns(draws)].to_numpy())


@needs_tamaas
def test_load_series_draws_area_error_p95_and_bar(draws):
    """The 32 loads of the further draws: |area error| p95 within the 8 % target, and the
    truth inside [low, high] in at least 90 % of their frames."""
    e = _draw_errors(draws).ravel()
    assert np.percentile(e, 95) <= MEASUREMENT_TARGETS["area_err_pct p95"], draws
    share = 100 * draws.frames_in_band.sum() / draws.frames_scored.sum()
    assert share >= MEASUREMENT_TARGETS["in_band_pct"], draws


@needs_tamaas
@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "issue 21: |area error| median 2.6 % over the further draws' 32 loads (target 2 %): the "
    "texture under each draw's junctions, which the static estimate cannot follow, moves "
    "the area by about 2 % per % of it"))
def test_load_series_draws_area_error_median(draws):
    assert np.median(_draw_errors(draws)) <= MEASUREMENT_TARGETS["area_err_pct median"], draws


@needs_tamaas
def test_load_series_area_grows_with_load_within_25_percent(series):
    table, _ = series
    assert np.all(np.diff(table.measured_mm2.to_numpy()) > 0), table
    # 25 %: the band tests/test_segmentation_targets.py allows sub-pixel junctions
    assert np.allclose(table.measured_mm2, table.true_area_mm2, rtol=0.25), table


# -- the renders of issue 21's table --------------------------------------------------------
def _table(name: str, *, reference: bool = False) -> dict:
    from synthetic.table import table_specs

    return validate_table_clip(name, table_specs(0, n_frames=3)[name], reference=reference)


def _check(row: dict, tolerance_pct: float) -> None:
    assert abs(row["measured_mm2"] / row["true_area_mm2"] - 1) * 100 <= tolerance_pct, row
    assert row.get("frames_in_band") == row.get("frames_scored"), row


# Tolerances. Resolved contacts, one large disc (round pad r = 77 px, smooth sphere r = 80 px,
# bright patches r = 60 px): 2 %, the median target (the edge placed to 0.5 px is
# 1.3 % of a 77 px disc's area, patchy edges add little at these patch sizes). The three
# small contacts (r = 32 px each, patchy): 3 %, their perimeter-to-area ratio is 2.4x the
# round pad's.
def test_table_round_pad():
    _check(_table("round pad"), 2.0)


def test_table_smooth_sphere_on_glass():
    _check(_table("smooth sphere on glass"), 2.0)


def test_table_bright_patches():
    _check(_table("bright patches"), 2.0)


def test_table_three_points_with_a_fold():
    """Item 3: the fold's fall-off is not contact (e61c71b, before the edge-sharpness rule:
    24.6 mm2 measured for 8.0 mm2)."""
    _check(_table("three points, fold"), 3.0)


@pytest.mark.parametrize("seed", [6, 12, 13])
def test_table_three_points_with_a_fold_on_other_seeds(seed):
    """The same render on seeds the step test (tir_contact.reference.EDGE_RATIO) was not
    built on: before it, the foot width alone read the fold as contact on these three
    (175, 201 and 188 % high); seeds 7-11 read right either way."""
    from synthetic.table import table_specs

    spec = table_specs(seed, n_frames=3)["three points, fold"]
    _check(validate_table_clip("three points, fold", spec), 3.0)


@pytest.mark.parametrize("seed", [4, 5])
def test_table_three_points_with_a_fold_across_a_contact(seed):
    """The fold moved to the disc's centre and widened to 1.5 mm: it crosses the 100 deg
    contact. Before, the fold's inside and the contact were judged as one soft core (24
    and 39 % low on these seeds; 19-40 % low or 279 % high on seeds 0-3, which the rule
    was built on); the contact is now judged against the fold's light. Tolerance 5 %: the
    part of the contact under the fold's edge is read against the light continued from
    beside it over a 6 px margin (2.1-3.8 % on seeds 4-8)."""
    from synthetic.table import table_specs

    spec = table_specs(seed, n_frames=3)["three points, fold"]
    camera = dataclasses.replace(spec.camera, fold_x_mm=0.0, fold_width_mm=1.5)
    _check(validate_table_clip("three points, fold", dataclasses.replace(spec, camera=camera)),
           5.0)


@pytest.mark.parametrize("seed", [4, 5])
def test_table_three_points_with_a_fold_joined_with_a_contact(seed):
    """The fold, 1.5 mm wide, moved over the 140 deg contact near the lit rim: the two are
    one region whose foot is mostly the contact's sharp edge and whose half-depth band is
    the fold's flat inside. Before, the whole region was contact (108 and 122 % high on
    these seeds); now the contact and its margin stay and the rest, soft by its own foot,
    goes (tir_contact.reference._split_light). Tolerance 5 %, as for the fold across a
    contact (0.4-2.1 % on seeds 4-8; held out, seeds 9-12: 1.6-3.1 %, and with a 0.8 mm
    fold 2.8-13.8 %: more of a narrow fold lies in the contact's 6 px margin)."""
    from synthetic.table import table_specs

    spec = table_specs(seed, n_frames=3)["three points, fold"]
    cam = spec.camera
    disc_r = math.sqrt(cam.lit_fraction * cam.width_px * cam.height_px / math.pi) * cam.mm_per_px
    camera = dataclasses.replace(cam, fold_x_mm=0.8 * disc_r * math.cos(math.radians(140)),
                                 fold_width_mm=1.5)
    _check(validate_table_clip("three points, fold", dataclasses.replace(spec, camera=camera)),
           5.0)


def test_table_three_points_with_a_fold_and_its_own_empty_frame():
    _check(_table("three points, fold", reference=True), 3.0)


@needs_tamaas
def test_table_rough_pad_under_stray_light():
    """Rough pad at 1 bar on the load series' textured field, 15 % stray light: full
    contact is 1 - R at most 0.87 dark instead of 0.98; the measured area must not
    assume otherwise. Tolerance 8 %: the issue's p95 for sub-pixel junctions. It reads
    7.9 % low (0.069 mm2 of 0.075, 3 and 6 frames alike): within the target by 0.1 point,
    since its thin junctions beyond the zone are counted (d261b92; 23 % low before, 27 %
    at e61c71b, a strict xfail until then)."""
    row = validate_table_clip("rough pad, stray light", stray_light_spec())
    _check(row, 8.0)


#: Rough pad draw 11 on bubbly ice: the 33 bubbles and 4 scratches the domain's counts put
#: into its 1.3 mm view before they were read as densities of the thesis's ice
#: (synthetic.domain._ice_flaws_in_view), kept here as the case an empty frame is for.
BUBBLY_ICE = {"n_bubbles": 33, "n_scratches": 4}


@needs_tamaas
@pytest.mark.parametrize("index, flaws", [(6, None), (11, BUBBLY_ICE)])
def test_static_rough_pad_with_its_empty_frame_reads_its_optical_contact(index, flaws):
    """The rig's own empty frame (synthetic.table.empty_reference: one frame, 0.87x
    exposure, shifted by 3, -2 px) as ``--reference``: the free surface under the pad is
    measured instead of estimated from the image. Two static pads read far off without it
    (the short clips' 4 frames, measured against their optical contact): draw 6 59 % low,
    its fading junction field taken for light falling off; draw 11 on bubbly ice 188 %
    high, its bubbles read as contact. With it: 0.3 % and 0.1 % (9.4 % and 0.1 % before
    partly covered interiors were read against the optics' darkness, stop 51). Tolerance
    6.25 %: a quarter above the largest p95 against the optical contact of the static
    draws of seeds 0, 7 and 29 with their empty frames (3.5, 5.0 and 3.6 %)."""
    from synthetic.domain import sample_physical_specs

    spec, case = sample_physical_specs(12, seed=0)[index]
    assert case == "tir rough pad"
    if flaws is not None:
        spec = dataclasses.replace(spec, camera=dataclasses.replace(spec.camera, **flaws))
    row = validate_clip(_short(spec), case, index, reference=True)
    assert row["case"] == "tir rough pad, empty frame"
    assert abs(row["optical_err_pct"]) <= 6.25, row
