"""The README's validation table, held to the code (examples/validate_pipeline.py).

The README publishes the pipeline's errors on 200 random real-footage clips (seed 0) and
the targets they meet; the full run takes 5-8 minutes on 2 cores. The per-clip errors of
that run are frozen in ``tests/data/validation_domain_seed0.csv`` (the columns below of the
``validation_domain.csv`` that ``python examples/validate_pipeline.py --domain 200
--no-ratio --no-fixed`` writes; regenerate both together). Then:

* default run: the example's ``summarise`` of the frozen clips is the README's table, cell
  by cell to its printed rounding, and it meets the README's targets, which are the
  example's ``DOMAIN_TARGETS``;
* slow: the example's code (``_domain_validation.validate_clip``, as ``validate_pipeline``
  calls it) reruns a fixed subset of the same clips, the first three of each case class,
  and must give the frozen errors, so a change of the renderer or the pipeline cannot leave
  the published table standing; the subset meets the area and angle targets itself (the
  length median is left to the full table: only 6 of the 21 clips measure a length, and
  its per-clip errors are bimodal, 0.003-0.1 mm or 0.2-1.2 mm).
"""

from __future__ import annotations

import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))

import _domain_validation as dv  # noqa: E402
import validate_pipeline as vp  # noqa: E402

from synthetic.domain import CASE_CLASSES, sample_specs  # noqa: E402

#: The README's targets, typed from its "Targets:" sentence.
README_TARGETS = {"area_err_pct median": 3.0, "area_err_pct p95": 10.0,
                  "length_err_mm median": 0.1, "angle_err_deg median": 0.5}
PER_CLASS = 3
FROZEN = Path(__file__).resolve().parent / "data" / "validation_domain_seed0.csv"
METRICS = ["area_err_pct", "outside_lit_pct", "beyond_rim_pct", "length_err_mm",
           "angle_err_deg"]
# per-clip agreement with the frozen run: the renderer and the pipeline are deterministic;
# other package versions may move a threshold by a grey level or a JPEG block, which moves
# the errors by a small fraction of the README's targets: 0.3 % points of area (a tenth of
# the 3 % target), 0.01 mm of length (a tenth of 0.1 mm), 0.05 deg of angle (a tenth of
# 0.5 deg)
TOL = {"area_err_pct": 0.3, "outside_lit_pct": 0.3, "beyond_rim_pct": 0.3,
       "length_err_mm": 0.01, "angle_err_deg": 0.05}
#: Outcomes known to differ between machines, by (clip, metric): the value this machine
#: kind gives instead of the frozen one, held to the same tolerance. Clip 3 (a passing G
#: block, 0.103 mm/px, 58 element-frames) reads a length-error median of 0.3087 mm on an
#: AMD EPYC without AVX-512 (stop 55) against the frozen 0.3371 (0.28 px), at every commit
#: back to the one that froze it and at the newest and the lowest package versions alike;
#: 1 DN of noise on 1 % of its pixels moves it by under 0.0001 mm, so it is a discrete
#: branch taken otherwise on the other CPU, not a drift (not found which); the other 20
#: clips and every other metric agree within 5e-5. Named here rather than loosening the
#: 0.01 mm for every clip.
OTHER_MACHINE = {(3, "length_err_mm"): 0.308729}


def readme_text() -> str:
    return (ROOT / "README.md").read_text(encoding="utf-8")


def test_band_counts_scores_the_bar_and_its_width():
    """Hand-made bars: frame 0 holds the truth (1.0 in [0.9, 1.1], 20 % wide), frame 1 misses
    it (low 1.2), 40 % wide, frame 2 has no truth row (ignored): median width 30 %."""
    import pandas as pd

    frames = pd.DataFrame({"frame": [0, 1, 2], "contact_area_low_mm2": [0.9, 1.2, 0.0],
                           "contact_area_high_mm2": [1.1, 1.6, 9.0]})
    got = dv.band_counts(frames, pd.Series([1.0, 1.0], index=[0, 1]))
    assert got["frames_scored"] == 2 and got["frames_in_band"] == 1
    assert got["band_width_pct"] == pytest.approx(30.0, abs=1e-9)
    assert dv.band_counts(frames.drop(columns="contact_area_low_mm2"),
                          pd.Series([1.0], index=[0])) == {}
    # the summary: frames in the bar over frames scored, against the optical contact over
    # the clips that have one (case "b" has none)
    table = pd.DataFrame({"case": ["a", "a", "b"], "frames_scored": [10, 10, 5],
                          "frames_in_band": [10, 5, 5],
                          "frames_in_band_optical": [10, 9, np.nan],
                          "band_width_pct": [5.0, 7.0, 9.0]})
    summary = dv.summarise(table).set_index("case")
    assert summary.loc["a", "in_band_pct"] == pytest.approx(75.0)
    assert summary.loc["a", "in_band_optical_pct"] == pytest.approx(95.0)
    assert summary.loc["all", "in_band_optical_pct"] == pytest.approx(95.0)
    assert np.isnan(summary.loc["b", "in_band_optical_pct"])
    assert summary.loc["all", "band_width_pct median"] == pytest.approx(7.0)


def test_readme_states_the_targets_the_example_checks():
    text = " ".join(readme_text().split())
    assert ("Targets: contact area median <= 3 %, 95th percentile <= 10 %; element contact "
            "length median <= 0.1 mm; side-view angle median <= 0.5 deg") in text
    for key, value in README_TARGETS.items():
        assert vp.DOMAIN_TARGETS[key] == value, key


def readme_table() -> dict[str, dict[str, tuple[float, float] | None]]:
    """The README's domain table: case -> metric -> (median, p95) or None (empty cell)."""
    lines = readme_text().splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith("Random real-footage domain"))
    out = {}
    for ln in lines[start + 4:]:
        if not ln.startswith("|"):
            break
        cells = [c.strip() for c in ln.strip().strip("|").split("|")]
        out[cells[0]] = {"clips": int(cells[1])} | {
            m: (tuple(float(x) for x in c.split("/")) if c else None)
            for m, c in zip(METRICS, cells[2:], strict=True)}
    return out


@pytest.fixture(scope="module")
def frozen():
    import pandas as pd

    return pd.read_csv(FROZEN)


def test_readme_table_is_the_frozen_clips(frozen):
    published = readme_table()
    summary = dv.summarise(frozen).set_index("case")
    assert set(published) == set(summary.index)
    for case, row in published.items():
        assert summary.loc[case, "clips"] == row["clips"], case
        for m in METRICS:
            cell = row[m]
            if cell is None:
                assert f"{m} median" not in summary or np.isnan(summary.loc[case, f"{m} median"])
                continue
            got = (summary.loc[case, f"{m} median"], summary.loc[case, f"{m} p95"])
            # printed to 2 decimals: half a unit of the last digit (plus round-off)
            np.testing.assert_allclose(got, cell, atol=0.005 + 1e-9, err_msg=f"{case} {m}")


def test_readme_table_meets_its_targets(frozen):
    summary = dv.summarise(frozen).set_index("case")
    overall = summary.loc["all"]
    for key, target in README_TARGETS.items():
        assert overall[key] <= target, key
    for case in ("side fixed", "side follow"):  # "in both camera modes"
        assert summary.loc[case, "angle_err_deg median"] <= 0.5, case
    # "Contact more than two pixels outside: none in 134 of the 143 TIR clips, under 0.25 %
    # in 7, and 2.2 % and 3.5 % in two static contacts"
    beyond = frozen.loc[frozen["case"].str.startswith("tir"), "beyond_rim_pct"].dropna()
    assert len(beyond) == 143 and (beyond == 0).sum() == 134
    assert np.sort(beyond)[-2:] == pytest.approx([2.2, 3.5], abs=0.05)
    assert ((beyond > 0) & (beyond < 0.25)).sum() == 7


@pytest.fixture(scope="module")
def subset_table():
    """Per-clip errors of the first PER_CLASS clips of each case class among the README's
    200 clips (seed 0), by the example's own code, 2 workers."""
    draws = sample_specs(200, seed=0)
    chosen = []
    for case in CASE_CLASSES:
        idx = [i for i, (_, c) in enumerate(draws) if c == case][:PER_CLASS]
        chosen.extend(idx)
    chosen.sort()
    with ProcessPoolExecutor(2) as pool:
        rows = list(pool.map(dv.validate_clip, [draws[i][0] for i in chosen],
                             [draws[i][1] for i in chosen], chosen))
    import pandas as pd

    return pd.DataFrame(rows)


@pytest.mark.slow
def test_subset_of_the_published_clips_gives_the_frozen_errors(subset_table, frozen):
    table = subset_table.set_index("clip").sort_index()
    assert len(table) == PER_CLASS * len(CASE_CLASSES)
    want = frozen.set_index("clip").loc[table.index]
    assert (table["case"] == want["case"]).all()
    assert (table["camera_found"] == want["camera_found"]).all()
    for m in METRICS:
        got, ref = table[m].to_numpy(float), want[m].to_numpy(float)
        assert (np.isnan(got) == np.isnan(ref)).all(), m
        ok = ~np.isnan(ref)
        other = np.array([OTHER_MACHINE.get((int(c), m), np.nan) for c in table.index])
        near = (np.abs(got - ref) <= TOL[m]) | (np.abs(got - other) <= TOL[m])
        bad = ok & ~near
        assert not bad.any(), (m, table.index[bad].tolist(), got[bad], ref[bad])
    # the subset on its own meets the README's area and angle targets
    summary = dv.summarise(subset_table).set_index("case")
    assert summary.loc["all", "area_err_pct median"] <= README_TARGETS["area_err_pct median"]
    assert summary.loc["all", "area_err_pct p95"] <= README_TARGETS["area_err_pct p95"]
    for case in ("side fixed", "side follow"):
        assert summary.loc[case, "angle_err_deg median"] <= README_TARGETS[
            "angle_err_deg median"], case
