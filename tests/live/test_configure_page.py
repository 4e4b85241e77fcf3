"""``spl configure``'s page driven in headless Chromium (Selenium, the system
chromedriver): a real ``spl configure`` process per test, stopped with Ctrl-C, which
must end it cleanly. Propagation, the explanation, the count, attribute errors, undo
from the keyboard, YAML export and import into another session, the architecture
drawing, the bundle equal to ``spl resolve -o``, a bare UVL model and fleet mode
(docs/configure.md)."""

from __future__ import annotations

import io
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys

from support.configure_runs import chromium, click, configurator, fetched, settled, states

ROOT = Path(__file__).resolve().parents[2]
MAPPING = ROOT / "product_lines" / "mapping3d"


@pytest.fixture(scope="module")
def browser():
    driver = chromium()
    yield driver
    driver.quit()


def text(driver, selector: str) -> str:
    return driver.find_element(By.CSS_SELECTOR, selector).text


def test_mapping3d_propagation_explanation_count_architecture_and_bundle(
    browser, tmp_path: Path
) -> None:
    with configurator(str(MAPPING)) as url:
        assert url.startswith("http://127.0.0.1:")  # this machine only, unless told
        browser.get(url)
        settled(browser)
        assert text(browser, "[data-products]") == "12 products"
        assert states(browser)["Roomba"] == "open"
        # every control is labelled
        controls = browser.find_elements(By.CSS_SELECTOR, "[data-feature] button")
        assert controls and all(c.get_attribute("aria-label") for c in controls)
        click(browser, "AdditionalPC", "select")
        now = states(browser)
        assert now["AdditionalPC"] == "selected"
        assert now["Roomba"] == "implied-deselected" and now["YouBot"] == "implied-selected"
        assert text(browser, "[data-products]") == "4 products"
        # the control that would leave no product says so
        roomba_select = browser.find_element(
            By.CSS_SELECTOR, '[data-feature="Roomba"] [data-action="select"]'
        )
        assert roomba_select.get_attribute("aria-disabled") == "true"
        assert "no product would be left" in roomba_select.get_attribute("title")
        click(browser, "Roomba", "explain")
        why = text(browser, "[data-explanation]")
        assert why.startswith("Roomba: feature not selected")
        assert "Roomba excludes AdditionalPC" in why and "mapping.fm:29" in why
        # an impossible decision is refused with its reason; nothing changes
        click(browser, "Roomba", "select")
        assert "refused" in text(browser, "[data-message]")
        assert "mapping.fm:29" in text(browser, "[data-explanation]")
        assert states(browser) == now
        assert not browser.find_element(By.CSS_SELECTOR, 'a[data-action="bundle"]').is_displayed()
        click(browser, "Stereo", "select")
        click(browser, "Room", "select")
        assert text(browser, "[data-products]") == "1 product"
        svg = browser.find_element(By.CSS_SELECTOR, "[data-architecture] svg")
        assert svg.find_elements(By.CSS_SELECTOR, '[data-node="MapOptimizer"][data-migrated]')
        link = browser.find_element(By.CSS_SELECTOR, 'a[data-action="bundle"]')
        assert link.is_displayed()
        bundle = fetched(browser, link.get_attribute("href"))
        selection = tmp_path / "chosen.yaml"
        selection.write_bytes(fetched(browser, url + "api/selection.yaml"))
    out = tmp_path / "out"
    subprocess.run(
        [sys.executable, "-m", "spl", "resolve", str(MAPPING), "--features", str(selection),
         "-o", str(out)],
        check=True, capture_output=True,
    )  # fmt: skip
    written = {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    with zipfile.ZipFile(io.BytesIO(bundle)) as archive:
        assert {name: archive.read(name) for name in archive.namelist()} == written


def test_undo_and_redo_from_the_keyboard(browser) -> None:
    with configurator(str(MAPPING)) as url:
        browser.get(url)
        settled(browser)
        row = browser.find_element(By.CSS_SELECTOR, '[data-feature="AdditionalPC"]')
        select = row.find_element(By.CSS_SELECTOR, '[data-action="select"]')
        select.send_keys(Keys.ENTER)  # a focused button pressed with the keyboard
        settled(browser)
        assert states(browser)["Roomba"] == "implied-deselected"
        undo = browser.find_element(By.CSS_SELECTOR, '[data-action="undo"]')
        undo.send_keys(Keys.SPACE)
        settled(browser)
        assert states(browser)["Roomba"] == "open"
        assert text(browser, "[data-products]") == "12 products"
        browser.find_element(By.CSS_SELECTOR, '[data-action="redo"]').send_keys(Keys.ENTER)
        settled(browser)
        assert states(browser)["Roomba"] == "implied-deselected"


def test_a_malformed_attribute_shows_an_inline_error_and_changes_nothing(browser) -> None:
    with configurator(str(ROOT / "product_lines" / "orchard")) as url:
        browser.get(url)
        settled(browser)
        click(browser, "CloudDetection", "select")
        before = states(browser)
        field = browser.find_element(By.CSS_SELECTOR, '[data-attribute="CloudDetection.threshold"]')
        field.send_keys("high", Keys.TAB)
        settled(browser)
        error = browser.find_element(By.CSS_SELECTOR, '[data-error-for="CloudDetection.threshold"]')
        assert error.text == "attribute CloudDetection.threshold is double, got 'high'"
        assert states(browser) == before
        assert b"attributes" not in fetched(browser, url + "api/selection.yaml")
        field.clear()
        field.send_keys("0.8", Keys.TAB)
        settled(browser)
        assert error.text == ""
        assert b"CloudDetection.threshold: 0.8" in fetched(browser, url + "api/selection.yaml")


def test_yaml_exported_by_one_session_imports_into_another(browser, tmp_path: Path) -> None:
    with configurator(str(MAPPING)) as url:
        browser.get(url)
        settled(browser)
        click(browser, "AdditionalPC", "select")
        click(browser, "Depth", "select")
        exported = fetched(browser, url + "api/selection.yaml")
        other = chromium()
        try:
            other.get(url)
            settled(other)
            assert states(other)["AdditionalPC"] == "open"  # its own session
            path = tmp_path / "chosen.yaml"
            path.write_bytes(exported)
            other.find_element(By.CSS_SELECTOR, '[data-action="import"]').send_keys(str(path))
            settled(other)
            assert states(other) == states(browser)
            assert fetched(other, url + "api/selection.yaml") == exported
            bad = tmp_path / "bad.yaml"
            bad.write_text("product: p\nfeatures: [YouBot, Wheels]\n")
            other.find_element(By.CSS_SELECTOR, '[data-action="import"]').send_keys(str(bad))
            settled(other)
            assert "bad.yaml:2:20: error: unknown feature 'Wheels'" in text(other, "[data-message]")
            assert states(other) == states(browser)
        finally:
            other.quit()


def test_a_bare_uvl_model_propagates_and_counts(browser) -> None:
    with configurator(str(ROOT / "tests" / "data" / "feature-models" / "berkeleydb.uvl")) as url:
        browser.get(url)
        settled(browser)
        if (
            browser.find_element(By.CSS_SELECTOR, "[data-products]").get_attribute("data-exact")
            == "false"
        ):  # not counted within the quick budgets (a loaded machine)
            browser.find_element(By.CSS_SELECTOR, '[data-action="count"]').click()
            settled(browser)
        assert text(browser, "[data-products]") == "4080389785 products"
        assert not browser.find_elements(By.CSS_SELECTOR, "[data-architecture]")
        opens = sorted(name for name, state in states(browser).items() if state == "open")
        click(browser, opens[0], "select")
        assert states(browser)[opens[0]] == "selected"
        count = text(browser, "[data-products]")
        assert count.endswith(" products") and int(count.split()[0]) < 4080389785


def test_fleet_mode_offers_only_what_the_shared_instances_allow(browser) -> None:
    fleet = MAPPING / "fleets" / "lab.yaml"
    with configurator("--fleet", str(fleet), "--robot", "youbot_4", "--group", "lab") as url:
        browser.get(url)
        settled(browser)
        assert "robot youbot_4 joining fleet lab, group lab" in text(browser, "[data-fleet]")
        now = states(browser)
        assert now["Room"] == "implied-selected" and now["Corridor"] == "implied-deselected"
        click(browser, "Corridor", "explain")
        assert "the fleet forbids it" in text(browser, "[data-explanation]")
        click(browser, "Corridor", "select")
        assert "decided by the fleet" in text(browser, "[data-message]")
        assert states(browser) == now
