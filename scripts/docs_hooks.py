"""MkDocs hooks of the documentation site (mkdocs.yml).

The pages live in ``docs/``; a few pages of the repository outside it (the README, the
changelog, the examples' and the benchmarks' READMEs) are added under ``_repo/``. Links are
written for the repository (they work on a forge and in an editor), so each link is mapped:
into ``docs/`` -> the page, to an added page -> its ``_repo/`` copy, to anything else (source
files, scenarios, scripts) -> the path as inline code, since the site does not serve sources.
"""

from __future__ import annotations

import posixpath
import re
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parent.parent
ADDED_PAGES = ("README.md", "CHANGELOG.md", "examples/README.md", "benchmarks/README.md")
LINK = re.compile(r"(!?)\[([^\]]*)\]\(([^)\s]+)\)")
FENCE = re.compile(r"^```.*?^```", re.MULTILINE | re.DOTALL)


def on_files(files, config):
    """Adds the repository pages outside ``docs/`` as ``_repo/<path>``."""
    for path in ADDED_PAGES:
        files.append(File.generated(config, f"_repo/{path}", abs_src_path=str(ROOT / path)))
    return files


def repository_path(src_uri: str) -> str:
    """The repository path of a page given by its site source path."""
    return src_uri[len("_repo/"):] if src_uri.startswith("_repo/") else f"docs/{src_uri}"


def site_target(target: str, page_repo_path: str) -> str | None:
    """The site path a repository-relative link points to, or None when it is not a page."""
    resolved = posixpath.normpath(posixpath.join(posixpath.dirname(page_repo_path), target))
    if resolved.startswith("docs/"):
        inside = resolved[len("docs/"):]
        if (ROOT / resolved).is_dir():
            inside = posixpath.join(inside, "README.md")
        return inside
    if resolved in ADDED_PAGES:
        return f"_repo/{resolved}"
    return None


def map_link(match: re.Match, src_uri: str) -> str:
    """One Markdown link, rewritten for the site."""
    bang, text, target = match.groups()
    if re.match(r"^[a-z]+:", target) or target.startswith("#"):
        return match.group(0)
    path, _, anchor = target.partition("#")
    page_repo_path = repository_path(src_uri)
    site_path = site_target(path, page_repo_path)
    if site_path is None:
        resolved = posixpath.normpath(posixpath.join(posixpath.dirname(page_repo_path), path))
        return text if text.strip("`") == resolved else f"{text} (`{resolved}`)"
    relative = posixpath.relpath(site_path, posixpath.dirname(src_uri) or ".")
    return f"{bang}[{text}]({relative}{'#' + anchor if anchor else ''})"


def on_page_markdown(markdown, page, config, files):
    """Maps the links of a page (outside its fenced code blocks)."""
    src_uri = page.file.src_uri
    pieces, last = [], 0
    for fence in FENCE.finditer(markdown):
        pieces.append(LINK.sub(lambda m: map_link(m, src_uri), markdown[last:fence.start()]))
        pieces.append(fence.group(0))
        last = fence.end()
    pieces.append(LINK.sub(lambda m: map_link(m, src_uri), markdown[last:]))
    return "".join(pieces)
