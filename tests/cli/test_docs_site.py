"""The README is the front door, the docs site the manual.

The site (mkdocs.yml, docs/) builds with ``mkdocs build --strict``: a broken link or
anchor, or a page missing from the navigation, fails here. The README stays short, links
every page of the manual, and agrees with the install page on the two commands and the
system-package table.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
DOCS = ROOT / "docs"
PAGES = sorted(p.name for p in DOCS.glob("*.md"))


def test_mkdocs_builds_the_site_strictly(tmp_path: Path) -> None:
    try:
        import mkdocs  # noqa: F401
    except ImportError:  # a missing extra is a failure, never a skip
        raise AssertionError("MkDocs is not installed: pip install -e '.[test]'") from None
    site = tmp_path / "site"
    command = [sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file"]
    build = subprocess.run(
        [*command, "mkdocs.yml", "--site-dir", str(site)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert build.returncode == 0, build.stdout + build.stderr
    for page in PAGES:
        name = page.removesuffix(".md")
        built = site / ("index.html" if name == "index" else f"{name}/index.html")
        assert built.is_file(), f"docs/{page} was not built"


def nav_pages(nav: list) -> list[str]:
    pages = []
    for entry in nav:
        for value in entry.values() if isinstance(entry, dict) else [entry]:
            pages += nav_pages(value) if isinstance(value, list) else [value]
    return pages


def test_every_page_is_in_the_navigation_once() -> None:
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))
    listed = nav_pages(config["nav"])
    assert sorted(listed) == PAGES, "mkdocs.yml nav and docs/*.md differ"
    assert config.get("strict") is True


def test_readme_is_at_most_300_lines() -> None:
    lines = README.count("\n") + (not README.endswith("\n"))
    assert lines <= 300, f"README.md has {lines} lines: move the rest to docs/"


def test_readme_links_every_page_of_the_manual() -> None:
    linked = set(re.findall(r"\]\(docs/([\w.-]+\.md)(?:#[\w-]*)?\)", README))
    missing = sorted(set(PAGES) - linked)
    assert not missing, f"README.md links no docs/{', docs/'.join(missing)}"


def test_readme_links_lead_somewhere() -> None:
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README):
        if "://" in target:
            continue
        assert (ROOT / target).exists(), f"README.md links {target}, which does not exist"


def fenced_command(text: str, after: str) -> str:
    """The one-line ```sh block following the text ``after``."""
    match = re.search(re.escape(after) + r".*?```sh\n(.+?)\n```", text, re.S)
    assert match, f"no ```sh block after {after!r}"
    return match.group(1)


def package_table(text: str) -> str:
    match = re.search(r"^\| Debian package \|.*?\n(?=\n)", text, re.M | re.S)
    assert match, "no system-package table"
    return match.group(0)


def test_install_page_repeats_the_readme_commands_and_package_table() -> None:
    page = (DOCS / "install.md").read_text(encoding="utf-8")
    for marker in ("main-command", "test-command"):
        command = fenced_command(README, f"<!-- {marker} -->")
        assert f"```sh\n{command}\n```" in page, f"docs/install.md lacks the README's {marker}"
    assert package_table(page) == package_table(README)
