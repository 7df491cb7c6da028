"""``report.html`` (issue 22): a batch to review in a browser, built from the results on disk.

The truths: the batch report and each clip's ``summary.json`` (written by the analysis, not
by the report), the files on disk (every link and image must exist, every thumbnail's size
attributes must be its real size), and in a real browser (Debian's chromium, driven by
Selenium): every image loads, nothing logs an error, clicking a column sorts it.
"""

from __future__ import annotations

import json
import os
import shutil
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote

import cv2
import numpy as np
import pandas as pd
import pytest
import tifffile

from tir_contact.analyze import AnalysisOptions
from tir_contact.batch import analyze_batch, find_footage
from tir_contact.io import open_footage

OPTIONS = AnalysisOptions(overlay_video=False, plots=False, parquet=False)


class Page(HTMLParser):
    """What a test reads from a report: links, images, ids, the first table's rows."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.links: list[str] = []
        self.images: list[dict[str, str]] = []
        self.ids: set[str] = set()
        self.rows: list[list[str]] = []
        self._table = 0  # tables seen
        self._cell: list[str] | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and "href" in a:
            self.links.append(a["href"])
        elif tag == "img":
            self.images.append(a)
        elif tag == "table":
            self._table += 1
        elif tag == "tr" and self._table == 1:
            self.rows.append([])
        elif tag == "td" and self._table == 1:
            self._cell = []

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)

    def handle_endtag(self, tag):
        if tag == "td" and self._cell is not None:
            self.rows[-1].append("".join(self._cell).strip())
            self._cell = None


@pytest.fixture(scope="module")
def batch(render_clip, copy_meta, tmp_path_factory) -> Path:
    """An analysed batch of five clips: two done, one failed (bad meta.json), black footage
    (warned), a TIFF stack cut short (partial)."""
    root = tmp_path_factory.mktemp("report")
    clips = root / "clips"
    good = render_clip(clips / "G3_a", n_frames=60)
    shutil.copytree(good, clips / "G3_b")
    shutil.copytree(good, clips / "bad_meta")
    text = (clips / "bad_meta" / "meta.json").read_text()
    (clips / "bad_meta" / "meta.json").write_text(text.replace('"fps":', '"fps"', 1))
    black = clips / "black"
    black.mkdir()
    # 120 frames: more digits than the others' (a column sorted as text would put it first)
    tifffile.imwrite(black / "black.tif", np.zeros((120, 128, 320), np.uint8))
    copy_meta(good, black, drop=["frame_pattern"])
    stack = clips / "cut"
    stack.mkdir()
    with open_footage(good / "frames") as reader:
        tifffile.imwrite(stack / "cut.tif", np.stack([reader.get_frame(i) for i in range(40)]))
    copy_meta(good, stack, drop=["frame_pattern"])
    with open(stack / "cut.tif", "r+b") as f:
        f.truncate(int((stack / "cut.tif").stat().st_size * 0.6))
    out = root / "out"
    paths = [clips / "G3_a", clips / "G3_b", clips / "bad_meta", black / "black.tif",
             stack / "cut.tif"]
    analyze_batch(find_footage(paths), out, options=OPTIONS, workers=1, progress=False)
    return out


def _page(out: Path) -> Page:
    return Page((out / "report.html").read_text(encoding="utf-8"))


def test_table_lists_every_clip_failed_and_warned_first(batch):
    page = _page(batch)
    truth = pd.read_csv(batch / "batch_report.csv")
    assert sorted(r[0] for r in page.rows[1:]) == sorted(truth["name"])
    statuses = [r[1] for r in page.rows[1:]]
    assert statuses == ["failed", "partial", "done (warned)", "done", "done"]
    by_name = {r[0]: r for r in page.rows[1:]}
    for name in ("G3_a", "G3_b"):
        summary = json.loads((batch / name / "summary.json").read_text())
        steady = summary["steady"]
        area = steady["contact_area_mm2"]["mean"]
        shown = by_name[name][6].split()
        assert float(shown[0]) == pytest.approx(area, rel=5e-4)  # 4 digits shown
        # the band, as summary.json holds it (issue 21: contact_area_low/high_mm2)
        low, high = (float(v) for v in shown[1].strip("()").split("–"))
        assert low == pytest.approx(steady["contact_area_low_mm2"]["mean"], rel=5e-4)
        assert high == pytest.approx(steady["contact_area_high_mm2"]["mean"], rel=5e-4)
        assert int(by_name[name][9]) == summary["n_frames_analysed"]
        assert float(by_name[name][5]) == pytest.approx(summary["lit_fraction"], rel=5e-3)


def test_every_link_and_image_exists_and_thumbnails_are_sized(batch):
    page = _page(batch)
    for href in page.links:
        if href.startswith("#"):
            assert href[1:] in page.ids, href
        else:
            assert (batch / unquote(href)).exists(), href
    thumbs = [img for img in page.images if img["src"].endswith(".jpg")]
    # three per clip (first, middle, last overlay), fewer where fewer were written (black
    # footage: one, no block in view)
    overlays = {p.name: len(list((p / "overlays").glob("*.png")))
                for p in batch.iterdir() if (p / "overlays").is_dir()}
    assert overlays["black"] == 1
    assert len(thumbs) == sum(min(3, n) for n in overlays.values())
    for img in page.images:
        assert img.get("loading") == "lazy", img
        path = batch / unquote(img["src"])
        assert path.is_file(), img
        if path.suffix == ".jpg":
            h, w = cv2.imread(str(path)).shape[:2]
            assert (int(img["width"]), int(img["height"])) == (w, h)
            assert w <= 240
            # the overlay's own shape, to the pixel the rounding allows
            full = cv2.imread(str(batch / path.parent.name / "overlays" / (path.stem + ".png")))
            assert abs(h - full.shape[0] * w / full.shape[1]) <= 0.5
    assert (batch / "G3_a" / "summary.json").as_posix().endswith("summary.json")
    assert "G3_a/summary.json" in page.links and "G3_a/frames.csv" in page.links


def test_rebuilt_from_disk_over_merged_folders(batch, tmp_path, run_cli, capsys):
    merged = tmp_path / "merged"
    shutil.copytree(batch, merged)
    (merged / "batch_report.json").unlink()  # results merged in by hand: folders only
    (merged / "report.html").unlink()
    shutil.copytree(batch / "G3_a", merged / "G3_other_day")
    summary = json.loads((merged / "G3_other_day" / "summary.json").read_text())
    summary["steady"]["contact_area_low_mm2"] = {"mean": 401.5}
    summary["steady"]["contact_area_high_mm2"] = {"mean": 512.25}
    older = json.loads((merged / "G3_a" / "summary.json").read_text())
    for key in ("contact_area_low_mm2", "contact_area_high_mm2"):  # a result from before
        older["steady"].pop(key, None)                                # the band existed
    (merged / "G3_a" / "summary.json").write_text(json.dumps(older))
    (merged / "G3_other_day" / "summary.json").write_text(json.dumps(summary))
    assert run_cli(["report", merged]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {merged / 'report.html'}"
    rows = {r[0]: r for r in _page(merged).rows[1:]}
    # the failed clip wrote no folder; without the batch report nothing knows it
    assert sorted(rows) == ["G3_a", "G3_b", "G3_other_day", "black", "cut"]  # no bad_meta
    assert rows["G3_other_day"][1] == "done" and rows["cut"][1] == "partial"
    assert "(401.5–512.2)" in rows["G3_other_day"][6]  # the band, when the summary has it
    assert "–" not in rows["G3_a"][6]


def test_report_of_a_folder_without_results_is_a_usage_error(run_cli, tmp_path, capsys):
    assert run_cli(["report", tmp_path]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(tmp_path) in err[0] and "no analysis results" in err[0]
    # it reads evaluate folders too, and says what it looked for there (helper-12)
    assert "no evaluation results (no provenance.json" in err[0]


def test_evaluate_writes_a_report_with_every_run(run_cli, write_ramp_run, tmp_path, capsys):
    runs = tmp_path / "runs"
    runs.mkdir()
    for k in (1, 2):
        write_ramp_run(runs / f"ramp_{k}.csv", rng=k)
    out = tmp_path / "eval"
    assert run_cli(["evaluate", runs, "--out", out, "--no-progress"]) == 0
    page = Page((out / "report.html").read_text(encoding="utf-8"))
    sources = [img["src"] for img in page.images]
    assert sources == ["mu_v.png", "mu_t/ramp_1.png", "mu_t/ramp_2.png"]
    for src in sources:
        assert (out / src).is_file()
    for href in page.links:
        assert (out / unquote(href)).is_file(), href
    assert "instationary_characteristic.csv" in page.links


# --------------------------------------------------------------------------------------------
# in a real browser

CHROMIUM, DRIVER = shutil.which("chromium"), shutil.which("chromedriver")


def _browser():
    """A headless Debian chromium driven by Selenium, or a skip saying what is missing
    (a failure where CI asks for the browser: ``TIR_CONTACT_REQUIRE_BROWSER=1``)."""
    missing = []
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.options import Options
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        missing.append("selenium (pip install 'tir-contact[browser]')")
    if CHROMIUM is None or DRIVER is None:
        missing.append("chromium and chromedriver (apt-get install chromium chromium-driver)")
    if missing:
        reason = "browser test needs " + " and ".join(missing)
        if os.environ.get("TIR_CONTACT_REQUIRE_BROWSER"):
            pytest.fail(reason)
        pytest.skip(reason)
    options = Options()
    options.binary_location = CHROMIUM
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=1200,900"):
        options.add_argument(arg)
    options.set_capability("goog:loggingOptions", {"browser": "ALL"})
    return webdriver.Chrome(options=options, service=Service(DRIVER))


_BROKEN_IMAGES = """
var imgs = Array.prototype.slice.call(document.images);
return imgs.filter(function(i){return !i.complete || i.naturalWidth === 0;})
           .map(function(i){return i.getAttribute('src');});
"""


def test_report_in_a_real_browser(batch, tmp_path):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    driver = _browser()
    try:
        driver.get((batch / "report.html").as_uri())
        n_images = driver.execute_script("return document.images.length")
        assert n_images == 10 + 4  # thumbnails and one plot per clip with results
        for img in driver.find_elements(By.TAG_NAME, "img"):  # lazy: each loads in view
            driver.execute_script("arguments[0].scrollIntoView();", img)
        WebDriverWait(driver, 20).until(lambda d: not d.execute_script(_BROKEN_IMAGES))
        driver.execute_script("window.scrollTo(0, 0);")

        def column(k: int) -> list[str]:
            return [r.find_elements(By.TAG_NAME, "td")[k].text
                    for r in driver.find_elements(By.CSS_SELECTOR, "table.sortable tbody tr")]

        names = column(0)
        headers = driver.find_elements(By.CSS_SELECTOR, "table.sortable th")
        headers[0].click()
        assert column(0) == sorted(names, key=str.lower)
        headers[0].click()
        assert column(0) == sorted(names, key=str.lower, reverse=True)
        headers[9].click()  # frames: as numbers (120 last), the failed clip's empty cell last
        frames = column(9)
        truth = sorted(json.loads((batch / n / "summary.json").read_text())["n_frames_analysed"]
                       for n in names if (batch / n).is_dir())
        assert frames == [str(n) for n in truth] + [""]
        shot = tmp_path / "report.png"
        driver.save_screenshot(str(shot))
        assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "WARNING")]
        assert not errors, errors
    finally:
        driver.quit()
