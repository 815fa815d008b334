"""The documentation site and the code it shows.

- the site (mkdocs.yml) builds in strict mode: a broken link or anchor, a page left out of the
  navigation or an API object that cannot be rendered fails;
- every public name of the Python package (the typed stub included) has a docstring;
- every ``python`` code block of the guide and the README runs, in order, file by file, on the
  shipped scenarios (a block preceded by ``<!-- not run: <reason> -->`` is skipped: it needs
  something CI does not have, e.g. a Ray cluster).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import griffe
import pytest

ROOT = Path(__file__).resolve().parent.parent
RUN_PAGES = sorted((ROOT / "docs" / "guide").glob("*.md")) + [ROOT / "README.md"]
BLOCK = re.compile(r"(<!-- not run: [^>]+-->\s*\n)?```python\n(.*?)^```", re.DOTALL | re.MULTILINE)
API_MODULES = ["sea_momentum"]


def test_the_docs_site_builds_in_strict_mode(tmp_path):
    command = [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(tmp_path / "site")]
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr[-4000:]
    api_page = (tmp_path / "site" / "reference" / "python_api" / "index.html").read_text()
    for name in ("Plant", "run_scenario", "ScenarioResult", "stiffness_estimates"):
        assert name in api_page, f"the API page lacks {name}"


def public_objects(obj: griffe.Object, prefix: str = ""):
    """Yields (dotted name, object) of every public member below obj, recursively."""
    for name, member in obj.members.items():
        if name.startswith("_") or member.is_alias:
            continue
        yield f"{prefix}{name}", member
        if member.is_class or member.is_module:
            yield from public_objects(member, f"{prefix}{name}.")


def test_every_public_name_has_a_docstring():
    package = griffe.load("sea_momentum", search_paths=[str(ROOT / "python")], allow_inspection=False)
    missing = [name for name, obj in public_objects(package, "sea_momentum.")
               if not obj.is_attribute and not (obj.docstring and obj.docstring.value.strip())]
    native = package.members["_native"]
    missing += [name for name, obj in public_objects(native, "sea_momentum._native.")
                if not obj.is_attribute and not (obj.docstring and obj.docstring.value.strip())]
    assert not missing, f"public names without a docstring: {missing}"


def code_blocks(page: Path) -> list[tuple[str, str | None]]:
    """The page's python blocks in order: (source, reason it is not run or None)."""
    return [(m.group(2), m.group(1)) for m in BLOCK.finditer(page.read_text())]


def test_the_pages_show_code():
    assert sum(len(code_blocks(page)) for page in RUN_PAGES) >= 8


@pytest.mark.parametrize("page", RUN_PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_the_code_blocks_of_a_page_run(page, tmp_path, monkeypatch):
    blocks = code_blocks(page)
    if not blocks:
        pytest.skip("no python block")
    for name in ("scenarios", "urdf", "robots"):
        (tmp_path / name).symlink_to(ROOT / name)
    (tmp_path / "out").mkdir()  # the pages write where the main job writes
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "__docs__"}
    for index, (source, not_run) in enumerate(blocks):
        if not_run:
            continue
        code = compile(source, f"{page.name}, block {index + 1}", "exec")
        exec(code, namespace)
