"""The project's documentation lives in the repository: no citation of a file outside it, every cited
docs/ page and math section exists, the math chapters are numbered as their files, and the generated
reference pages (docs/gen/reference.py, which the docs build runs) cover every command and every key.

The docs site itself is built with warnings as errors by .ci/run (`mkdocs build --strict`).
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCANNED = ("winder", "tests", "bench", "docs", "configs", "samples", "parts")
SUFFIXES = {".py", ".md", ".yaml", ".yml", ".txt", ".toml", ".cfg"}
# Files outside the repository that the code once cited, and the ways a path leaves it. Written in
# pieces so that this file does not match itself.
OUTSIDE = re.compile("|".join((r"\b(MATH|SPEC|STYLE)\.md\b", r"(?<![\w.])shar" "ed/", "/" + "work/",
                               r"""["']shared["']""", r"\.\./\.\./\.\./")))
MATH = ROOT / "docs" / "math"


def _files() -> list[Path]:
    return sorted(p for d in SCANNED for p in (ROOT / d).rglob("*")
                  if p.suffix in SUFFIXES and p.is_file() and "__pycache__" not in p.parts)


def test_nothing_cites_a_file_outside_the_repository():
    found = [f"{p.relative_to(ROOT)}:{i}: {line.strip()[:100]}" for p in _files()
             for i, line in enumerate(p.read_text(encoding="utf-8", errors="replace").splitlines(), 1)
             if OUTSIDE.search(line)]
    assert found == [], "cite the repository's docs/ instead:\n" + "\n".join(found)


def _chapters() -> dict[str, Path]:
    return {p.name[:2]: p for p in MATH.glob("[0-9][0-9]-*.md")}


def test_each_chapter_has_a_number_of_its_own():
    numbers = sorted(p.name[:2] for p in MATH.glob("[0-9][0-9]-*.md"))
    assert len(numbers) == len(set(numbers)), f"two chapters share a number: {numbers}"


def test_each_math_chapter_is_headed_with_its_number():
    chapters = _chapters()
    assert set(chapters) >= {f"{k:02d}" for k in range(1, 15)}, sorted(chapters)
    for number, path in chapters.items():
        first = path.read_text(encoding="utf-8").splitlines()[0]
        assert re.match(rf"# {int(number)}\. ", first), f"{path.name} is headed {first!r}"
        for heading in re.findall(r"^## (\d+)\.\d+ ", path.read_text(encoding="utf-8"), flags=re.M):
            assert heading == str(int(number)), f"{path.name}: section {heading}.x"


_CITED_PAGE = re.compile(r"\bdocs/[\w./-]+\.md\b")
_CITED_SECTION = re.compile(r"\bdocs/math/(\d\d)(?:-[\w-]+\.md)?,? (\d+\.\d+)\b")


def test_every_cited_docs_page_and_math_section_exists():
    sections = {number: set(re.findall(r"^##+ (\d+\.\d+) ", path.read_text(encoding="utf-8"), flags=re.M))
                for number, path in _chapters().items()}
    missing = []
    for p in _files():
        text = p.read_text(encoding="utf-8", errors="replace")
        missing += [f"{p.relative_to(ROOT)}: {page}" for page in _CITED_PAGE.findall(text)
                    if not (ROOT / page).exists()]
        for number, section in _CITED_SECTION.findall(text):
            if number not in sections or section not in sections[number]:
                missing.append(f"{p.relative_to(ROOT)}: docs/math/{number} {section}")
        missing += [f"{p.relative_to(ROOT)}: docs/math/{n}" for n in re.findall(r"\bdocs/math/(\d\d)\b", text)
                    if n not in sections]
        for number, section in re.findall(r"\bchapter (\d+), (\d+\.\d+)\b", text):  # the chapters' own prose
            if section not in sections.get(f"{int(number):02d}", ()):
                missing.append(f"{p.relative_to(ROOT)}: chapter {number}, {section}")
    assert missing == [], "\n".join(missing)


def _reference():
    spec = importlib.util.spec_from_file_location("docs_reference", ROOT / "docs" / "gen" / "reference.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_command_reference_has_every_command_and_option():
    from winder.cli import main  # noqa: PLC0415

    page = _reference().command_reference()
    for name, command in main.commands.items():
        assert f"## winder {name}\n" in page
        for param in command.params:
            for opt in getattr(param, "opts", ()):
                if opt.startswith("-"):
                    assert f"`{opt}" in page or f" {opt}" in page, (name, opt)


def test_the_config_reference_names_classes_that_exist():
    import importlib  # noqa: PLC0415

    for target in _reference().READ_INTO.values():
        module, name = target.rsplit(".", 1)
        assert hasattr(importlib.import_module(f"winder.config.{module}"), name), target


def test_the_config_reference_has_every_key_of_the_schema():
    from winder.config.schema import job_schema  # noqa: PLC0415

    page = _reference().config_reference()

    def keys(node):
        if isinstance(node, dict):
            yield from node.get("properties", {})
            for value in node.values():
                yield from keys(value)
        elif isinstance(node, list):
            for value in node:
                yield from keys(value)

    for key in set(keys(job_schema())):
        assert f"| `{key}`" in page, key


@pytest.mark.parametrize("path", sorted((ROOT / "docs").rglob("*.md")), ids=lambda p: p.name)
def test_markdown_links_inside_docs_resolve(path):
    """Relative links to other pages of docs/ (the site build checks the rest, anchors included)."""
    generated = {ROOT / "docs" / uri for uri in _reference().PAGES}
    for target in re.findall(r"\]\((?!https?:|#|mailto:)([^)\s#]+)", _prose(path.read_text(encoding="utf-8"))):
        resolved = (path.parent / target).resolve()
        if resolved.is_relative_to(ROOT / "docs") and resolved not in generated:
            assert resolved.exists(), f"{path.relative_to(ROOT)} links {target}"


def _prose(text: str) -> str:
    """Markdown without its code (fenced and indented blocks, inline spans), where brackets are math."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.M | re.S)
    text = re.sub(r"^(?: {4}|\t).*$", "", text, flags=re.M)
    return re.sub(r"`[^`]*`", "", text)


def test_the_tutorials_config_passes_check():
    """docs/tutorial.md runs every command on docs/tutorial/tank.yaml (and includes the file itself)."""
    from click.testing import CliRunner  # noqa: PLC0415

    from winder.cli import main  # noqa: PLC0415

    result = CliRunner().invoke(main, ["check", str(ROOT / "docs" / "tutorial" / "tank.yaml")])
    assert result.exit_code == 0, result.output
    assert '--8<-- "tutorial/tank.yaml"' in (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")
