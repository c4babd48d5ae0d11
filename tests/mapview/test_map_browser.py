"""The map page in a real browser: Debian's Chromium, headless, driven by selenium through
Debian's chromedriver (``.ci/run`` installs both). Markers, selection both ways, pan, zoom,
search, hover, and a screenshot."""

from __future__ import annotations

import importlib.util
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest
from lxml import etree
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.remote.webdriver import WebDriver
from selenium.webdriver.support.ui import WebDriverWait

from tests.cli.test_cli import BROKEN, CLEAN, cli
from tests.conftest import CORPUS_RAIL, REPO

CHROMIUM = Path("/usr/bin/chromium")
CHROMEDRIVER = Path("/usr/bin/chromedriver")


def _screenshots_script() -> ModuleType:
    """docs/screenshots.py, whose Chromium flags the test shares."""
    spec = importlib.util.spec_from_file_location("screenshots", REPO / "docs" / "screenshots.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


FLAGS: tuple[str, ...] = (*_screenshots_script().HEADLESS_FLAGS, "--window-size=1400,900")
STATION = CORPUS_RAIL / "ASAM-1.7.0_Ex_Railway-Station.xodr"

pytestmark = [
    pytest.mark.skipif(
        not (CHROMIUM.is_file() and CHROMEDRIVER.is_file()),
        reason="Debian's chromium and chromium-driver are not installed (.ci/run installs them)",
    ),
    pytest.mark.loopback,
]


@pytest.fixture
def browser(tmp_path: Path) -> Iterator[WebDriver]:
    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in (*FLAGS, f"--user-data-dir={tmp_path / 'chromium-profile'}"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
    try:
        yield driver
    finally:
        driver.quit()


def _open(driver: WebDriver, source: Path, out: Path, code: int) -> None:
    cli("map", source, "-o", out, code=code)
    driver.get(out.as_uri())
    WebDriverWait(driver, 20).until(
        lambda d: d.find_element(By.TAG_NAME, "body").get_attribute("data-ready") == "true"
    )


def _count(driver: WebDriver, css: str) -> int:
    return len(driver.find_elements(By.CSS_SELECTOR, css))


def _view_box(driver: WebDriver) -> list[float]:
    raw = driver.find_element(By.ID, "map").get_dom_attribute("viewBox") or ""
    return [float(part) for part in raw.split()]


def _classes(driver: WebDriver, css: str) -> list[str]:
    return (driver.find_element(By.CSS_SELECTOR, css).get_attribute("class") or "").split()


def _settle(driver: WebDriver) -> None:
    """Wait for the repaint the page schedules on the next animation frame."""
    driver.execute_async_script("requestAnimationFrame(() => requestAnimationFrame(arguments[0]))")


def test_markers_selection_pan_zoom_search_and_screenshot(
    browser: WebDriver, tmp_path: Path
) -> None:
    _open(browser, BROKEN, tmp_path / "broken.html", code=1)
    counts = [_count(browser, f"#map {css}") for css in (".switch-mark", ".platform", ".finding")]
    assert counts == [2, 1, 6]
    assert _count(browser, "#findings-table tbody tr") == 6
    assert browser.find_element(By.ID, "summary").text == (
        "2 roads, 2 track pieces, 2 switches, 1 platform segment. "
        "6 findings (5 errors, 1 warning, 0 info)."
    )

    # a row centres the view on its marker and highlights it
    browser.find_elements(By.CSS_SELECTOR, "#findings-table tbody tr")[3].click()  # RL003
    _settle(browser)
    assert "selected" in _classes(browser, '#map .finding[data-finding="3"]')
    marker = browser.find_element(By.CSS_SELECTOR, '#map .finding[data-finding="3"]')
    x, y, width, height = _view_box(browser)
    centre = (x + width / 2, y + height / 2)
    assert centre == pytest.approx(
        (float(marker.get_attribute("cx") or 0), float(marker.get_attribute("cy") or 0))
    )
    radius = browser.execute_script("return arguments[0].getBoundingClientRect().width", marker)
    assert radius > 20  # the selected marker is drawn larger: 12 px radius on screen

    # a marker selects its row
    browser.find_element(By.ID, "zoom-fit").click()
    _settle(browser)
    browser.find_element(By.CSS_SELECTOR, '#map .finding[data-finding="2"]').click()  # SW006
    assert "selected" in _classes(browser, '#findings-table tr[data-finding="2"]')
    assert "selected" not in _classes(browser, '#findings-table tr[data-finding="3"]')

    # zoom by button and by wheel, pan by dragging
    before = _view_box(browser)
    browser.find_element(By.ID, "zoom-in").click()
    _settle(browser)
    assert _view_box(browser)[2] == pytest.approx(before[2] / 2)
    svg = browser.find_element(By.ID, "map")
    ActionChains(browser).scroll_to_element(svg).scroll_by_amount(0, 300).perform()
    _settle(browser)
    zoomed_out = _view_box(browser)
    assert zoomed_out[2] > before[2] / 2
    ActionChains(browser).move_to_element_with_offset(
        svg, -200, 200
    ).click_and_hold().move_by_offset(100, 0).move_by_offset(100, 0).release().perform()
    _settle(browser)
    assert _view_box(browser)[0] < zoomed_out[0]  # dragged right: the view moved west

    # search by switch id; hover shows its label
    box = browser.find_element(By.ID, "search-box")
    box.send_keys("102", Keys.ENTER)
    _settle(browser)
    assert _count(browser, "#map .switch.found") == 1
    assert "switch '102'" in browser.find_element(By.ID, "search-result").text
    box.clear()
    box.send_keys("2", Keys.ENTER)
    assert "rail road '2'" in browser.find_element(By.ID, "search-result").text

    screenshot = tmp_path / "broken.png"
    assert browser.save_screenshot(str(screenshot))
    assert screenshot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _shown(driver: WebDriver) -> tuple[list[str], int]:
    """The codes of the rows shown, and how many markers are drawn."""
    rows = driver.find_elements(By.CSS_SELECTOR, "#findings-table tbody tr")
    codes = [row.find_element(By.TAG_NAME, "td").text for row in rows if row.is_displayed()]
    markers = driver.find_elements(By.CSS_SELECTOR, "#map .finding")
    return codes, sum(1 for marker in markers if marker.is_displayed())


def test_findings_are_filtered_by_severity_and_rule(browser: WebDriver, tmp_path: Path) -> None:
    _open(browser, BROKEN, tmp_path / "broken.html", code=1)
    labels = [label.text for label in browser.find_elements(By.CSS_SELECTOR, "#filters label")]
    assert labels == [
        *["error (5)", "warning (1)", "info (0)"],
        *["RL003 (1)", "ST004 (1)", "SW006 (1)", "XS006 (3)"],
    ]
    assert _shown(browser) == (["XS006", "XS006", "SW006", "RL003", "ST004", "XS006"], 6)
    assert browser.find_element(By.ID, "filter-count").text == "showing all 6 findings"

    browser.find_element(By.CSS_SELECTOR, '#rule-filter input[data-code="XS006"]').click()
    assert _shown(browser) == (["SW006", "RL003", "ST004"], 3)
    assert browser.find_element(By.ID, "filter-count").text == "showing 3 of 6 findings"
    browser.find_element(By.CSS_SELECTOR, '#severity-filter input[data-severity="error"]').click()
    assert _shown(browser) == (["SW006"], 1)  # the one warning
    assert browser.find_element(
        By.CSS_SELECTOR, '#severity-filter input[data-severity="info"]'
    ).get_property("disabled")

    browser.find_element(By.ID, "rules-none").click()
    assert _shown(browser) == ([], 0)
    browser.find_element(By.ID, "rules-all").click()
    browser.find_element(By.CSS_SELECTOR, '#severity-filter input[data-severity="error"]').click()
    assert _shown(browser) == (["XS006", "XS006", "SW006", "RL003", "ST004", "XS006"], 6)


def test_a_clean_map_shows_no_filters(browser: WebDriver, tmp_path: Path) -> None:
    _open(browser, CLEAN, tmp_path / "clean.html", code=0)
    assert not browser.find_element(By.ID, "filters").is_displayed()


def test_hovering_a_road_names_it(browser: WebDriver, tmp_path: Path) -> None:
    source = tmp_path / "roads.xodr"
    source.write_text(
        '<OpenDRIVE><header revMajor="1" revMinor="7"/>'
        '<road id="77" name="Main Street" length="100" junction="-1"><planView>'
        '<geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>'
        "</planView></road></OpenDRIVE>",
        "utf-8",
    )
    _open(browser, source, tmp_path / "roads.html", code=0)
    svg = browser.find_element(By.ID, "map")
    # the road runs along the middle of the drawing, west to east
    ActionChains(browser).move_to_element(svg).move_by_offset(5, 1).perform()
    label = browser.find_element(By.ID, "hover")
    assert label.is_displayed() and label.text == "road '77' (Main Street)"


@pytest.mark.skipif(
    not STATION.is_file(), reason="../shared/corpus (ASAM's station example) is absent"
)
def test_asam_station_example_shows_each_switch_and_platform_segment(
    browser: WebDriver, tmp_path: Path
) -> None:
    root = etree.parse(str(STATION)).getroot()
    _open(browser, STATION, tmp_path / "station.html", code=0)
    assert _count(browser, "#map .switch-mark") == len(root.findall("road/railroad/switch"))
    assert _count(browser, "#map .platform") == len(root.findall("station/platform/segment"))
    assert _count(browser, "#map .finding") == 0
    assert browser.find_element(By.ID, "not-drawn-section").is_displayed() is False
