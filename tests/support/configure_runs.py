"""``spl configure`` run for real (a process serving on a free port) and a headless
Chromium driving its page through the system chromedriver (Debian ``chromium`` and
``chromium-driver``, installed by .ci/run)."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

CHROMEDRIVER = "/usr/bin/chromedriver"


@contextlib.contextmanager
def configurator(*arguments: str, cwd: Path | None = None) -> Iterator[str]:
    """The URL of a running ``spl configure ARGUMENTS --no-browser --port 0``; stopped
    with SIGINT (Ctrl-C) on exit, which must end it cleanly."""
    process = subprocess.Popen(
        [sys.executable, "-m", "spl", "configure", *arguments, "--no-browser", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=cwd,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    try:
        assert process.stdout is not None
        first = process.stdout.readline()
        if " at http://" not in first:
            process.kill()
            raise AssertionError(f"spl configure did not start: {first}{process.stderr.read()}")
        url = first.split(" at ", 1)[1].split()[0]
        yield url
    finally:
        if process.poll() is None:
            process.send_signal(signal.SIGINT)
            try:
                out, err = process.communicate(timeout=15)
            except subprocess.TimeoutExpired:
                process.kill()
                raise AssertionError("spl configure did not stop on Ctrl-C") from None
            # a clean stop: exit 0, a last line, no traceback
            assert process.returncode == 0, err
            assert "Traceback" not in err, err
            assert out.strip().endswith("spl configure: stopped"), out


def chromium(download_dir: Path | None = None):
    """A headless Chromium WebDriver (selenium), downloads going to ``download_dir``."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                     "--disable-gpu", "--window-size=1400,1000"):  # fmt: skip
        options.add_argument(argument)
    if download_dir is not None:
        options.add_experimental_option(
            "prefs", {"download.default_directory": str(download_dir),
                      "download.prompt_for_download": False}
        )  # fmt: skip
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


def settled(driver, timeout: float = 20.0) -> None:
    """Wait until the page has no request of its own in flight."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if driver.execute_script("return window.splConfigure && window.splConfigure.pending") == 0:
            time.sleep(0.05)  # an answer may start another request (count, architecture)
            if driver.execute_script("return window.splConfigure.pending") == 0:
                return
        time.sleep(0.02)
    raise AssertionError("the page kept waiting for the server")


def fetched(driver, url: str) -> bytes:
    """What the page's own session gets at ``url`` (a link's target: the bundle, the
    YAML), fetched by the page with its cookie."""
    import base64

    text = driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(arguments[0], {credentials: 'same-origin'}).then((r) => r.arrayBuffer())"
        ".then((b) => { let s = '';"
        "  new Uint8Array(b).forEach((c) => { s += String.fromCharCode(c); });"
        "  done(btoa(s)); });",
        url,
    )
    return base64.b64decode(text)


def states(driver) -> dict[str, str]:
    """Every row's data-state, by feature."""
    return driver.execute_script(
        "const out = {};"
        "document.querySelectorAll('[data-feature]').forEach("
        "  (row) => { out[row.dataset.feature] = row.dataset.state; });"
        "return out;"
    )


def click(driver, feature: str, action: str) -> None:
    """Press a row's control (select, deselect, clear, explain) and wait for the page."""
    row = driver.find_element("css selector", f'[data-feature="{feature}"]')
    row.find_element("css selector", f'[data-action="{action}"]').click()
    settled(driver)
