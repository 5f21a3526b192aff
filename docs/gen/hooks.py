"""MkDocs hooks of the docs site (mkdocs.yml `hooks:`): the generated pages, and the repository's own files
the pages link to.

- on_files adds the command and config references (docs/gen/reference.py) and mirrors the repository
  files the guide links to (the commented configs, the parts' notes, the benchmark page with its figures),
  so that a link such as `../../configs/` works on the site as it does on the repository.
- on_page_markdown points each link that leaves docs/ at that mirror; a link to a file not mirrored is left
  as written, and the strict build fails on it.
"""

from __future__ import annotations

import posixpath
import re
import sys
from pathlib import Path

from mkdocs.structure.files import File, Files

sys.path.insert(0, str(Path(__file__).parent))
from reference import PAGES  # noqa: E402 - beside this file, not a package

ROOT = Path(__file__).resolve().parents[2]
MIRROR = "repo"  # the mirrored repository files live under this folder of the site
# (folder, pattern): repository files the docs link to, mirrored as pages (YAML in a code block) or as is.
MIRRORED = (("configs", "*.yaml"), ("samples", "*.yaml"), ("parts", "*.yaml"), ("parts", "README.md"),
            ("samples", "README.md"), ("bench/results", "*.md"), ("bench/results", "*.png"),
            ("bench/results", "*.json"))


def _yaml_page(path: Path) -> str:
    rel = path.relative_to(ROOT).as_posix()
    return f"# {rel}\n\n```yaml\n{path.read_text(encoding='utf-8')}```\n"


def _index(folder: str, names: list[str]) -> str:
    links = "\n".join(f"- [{n}]({n.removesuffix('.yaml')}.md)" for n in names if n.endswith(".yaml"))
    return f"# {folder}/\n\nThe configs of the repository's `{folder}/` folder, as shipped.\n\n{links}\n"


def on_files(files: Files, config) -> Files:
    for uri, make in PAGES.items():
        files.append(File.generated(config, uri, content=make()))
    folders: dict[str, list[str]] = {}
    for folder, pattern in MIRRORED:
        for path in sorted((ROOT / folder).glob(pattern)):
            uri = f"{MIRROR}/{folder}/{path.name}"
            if path.suffix == ".yaml":
                files.append(File.generated(config, uri.removesuffix(".yaml") + ".md", content=_yaml_page(path)))
                folders.setdefault(folder, []).append(path.name)
            else:
                files.append(File.generated(config, uri, abs_src_path=str(path)))
    for folder, names in folders.items():
        if not (ROOT / folder / "README.md").exists():
            files.append(File.generated(config, f"{MIRROR}/{folder}/index.md", content=_index(folder, names)))
    return files


_LINK = re.compile(r"\]\((?!https?:|#|mailto:)([^)\s#]+)(#[^)\s]*)?\)")


def _mirrored(target: str, page_dir: str, files: Files) -> str | None:
    """The site path of the mirror of a repository path (relative to the repository), if there is one."""
    for candidate in (target, target.rstrip("/") + "/index.md", target.rstrip("/") + "/README.md",
                      target.removesuffix(".yaml") + ".md"):
        uri = posixpath.normpath(f"{MIRROR}/{candidate}")
        if files.get_file_from_path(uri) is not None:
            return posixpath.relpath(uri, page_dir)
    return None


def on_page_markdown(markdown: str, page, config, files: Files) -> str:
    page_dir = posixpath.dirname(page.file.src_uri)
    mirrored_page = page.file.src_uri.startswith(MIRROR + "/")
    # Where the page's own source lies in the repository: docs/<uri>, or the mirrored file's own folder.
    home = posixpath.dirname(page.file.src_uri.removeprefix(MIRROR + "/")) if mirrored_page else f"docs/{page_dir}"

    def point(match: re.Match) -> str:
        target, anchor = match.group(1), match.group(2) or ""
        in_repo = posixpath.normpath(posixpath.join(home, target))
        if in_repo.startswith("docs/") or in_repo == "docs" or in_repo.startswith(".."):
            return match.group(0)
        mirror = _mirrored(in_repo, page_dir, files)
        return f"]({mirror}{anchor})" if mirror else match.group(0)

    return _LINK.sub(point, markdown)


# Sections of the nav that take every page of a docs folder: a page added to docs/guide/ or docs/math/
# joins its section without an edit of mkdocs.yml (listed pages keep their place and title), and one added
# to docs/ itself joins the end of the nav.
SECTION_FOLDERS = {"Guide": "guide", "Math": "math"}


def on_config(config):
    docs = Path(config["docs_dir"])
    listed_anywhere = {_page(entry) for entry in _entries(config["nav"] or [])}
    config["nav"] += [p.name for p in sorted(docs.glob("*.md")) if p.name not in listed_anywhere]  # top-level pages
    for entry in config["nav"] or []:
        if not isinstance(entry, dict):
            continue
        for title, children in entry.items():
            folder = SECTION_FOLDERS.get(title)
            if folder is None or not isinstance(children, list):
                continue
            listed = {next(iter(c.values())) if isinstance(c, dict) else c for c in children}
            children += [f"{folder}/{p.name}" for p in sorted((docs / folder).glob("*.md"))
                         if f"{folder}/{p.name}" not in listed]
    return config


def _entries(nav: list):
    """Every page entry of the nav, sections opened."""
    for entry in nav:
        value = next(iter(entry.values())) if isinstance(entry, dict) else entry
        if isinstance(value, list):
            yield from _entries(value)
        else:
            yield entry


def _page(entry) -> str:
    return next(iter(entry.values())) if isinstance(entry, dict) else entry
