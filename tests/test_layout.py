"""The house rules of the package layout (STYLE, issue 9), checked on the source itself.

Stages in order: config < geometry < paths < winding < analysis < machine < export < readback < report < app < cli <
__main__ (the executable); errors.py, progress.py and escape.py are shared. A module imports nothing from a later stage (nor from its own stage's later siblings through
a circle), geometry reads config types only in build.py, only the cli package imports click, the library
never prints, and no module is over MAX_LINES.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "winder"
STAGES = ("errors", "progress", "escape", "config", "geometry", "paths", "winding", "analysis", "machine", "export", "readback",
          "report", "app",
          "cli", "__main__")
MAX_LINES = 400
# The one circle left (issue 28): two imports made for type annotations only, under TYPE_CHECKING,
# close a circle through winding's results, wall, buildup, growth, passes and slip. Untangling it moves
# a type (LayerLaminate, PlanContext) into a module of its own; no other edge may close a circle.
TYPE_ONLY_CIRCLE = {("winder.winding.results", "winder.winding.wall"), ("winder.winding.slip", "winder.winding.passes")}


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _imports(path: Path, top_level_only: bool = False) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    nodes = tree.body if top_level_only else list(ast.walk(tree))
    found: set[str] = set()
    for node in nodes:
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module)
            found.update(f"{node.module}.{a.name}" for a in node.names
                         if f"{node.module}.{a.name}" in MODULES)
    return found


def _stage(module: str) -> int:
    part = module.split(".")[1] if "." in module else "winder"
    return STAGES.index(part) if part in STAGES else -1


def test_every_module_is_in_a_stage():
    for module in MODULES:
        if module != "winder":
            assert _stage(module) >= 0, module


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_import_from_a_later_stage(module):
    mine = _stage(module)
    for imported in _imports(MODULES[module]):
        if imported.startswith("winder.") or imported == "winder":
            assert _stage(imported) <= mine, f"{module} imports {imported} (a later stage)"


def test_geometry_reads_config_only_in_build():
    for module, path in MODULES.items():
        if module.startswith("winder.geometry") and module != "winder.geometry.build":
            assert not any(i.startswith("winder.config") for i in _imports(path)), module


def test_only_the_cli_imports_click_and_the_library_never_prints():
    for module, path in MODULES.items():
        imports = _imports(path)
        if module != "winder.cli" and not module.startswith("winder.cli."):
            assert "click" not in imports and not any(i.startswith("click.") for i in imports), module
            calls = [n for n in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
                     if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "print"]
            assert not calls, f"{module} prints"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_modules_are_short(module):
    lines = MODULES[module].read_text(encoding="utf-8").count("\n")
    assert lines <= MAX_LINES, f"{module}: {lines} lines"


def test_no_import_circle():
    # every import: module level, inside functions and under TYPE_CHECKING (a deferred import is
    # still a dependency, and a circle through one breaks as soon as it moves to the top)
    graph = {m: {i for i in _imports(p) if i in MODULES and i != m and (m, i) not in TYPE_ONLY_CIRCLE}
             for m, p in MODULES.items()}
    done: set[str] = set()

    def visit(node: str, stack: list[str]) -> None:
        if node in stack:
            cycle = stack[stack.index(node):] + [node]
            pytest.fail("import circle: " + " -> ".join(cycle))
        if node in done:
            return
        for nxt in graph[node]:
            visit(nxt, stack + [node])
        done.add(node)

    for module in graph:
        visit(module, [])


def test_readme_table_lists_every_module():
    """docs/architecture.md: each stage row names exactly the modules of its folder."""
    readme = (PACKAGE.parent / "docs" / "architecture.md").read_text(encoding="utf-8")
    rows = {}
    for line in readme.splitlines():
        cells = line.split("|")
        if len(cells) > 3 and cells[1].strip().startswith("`") and cells[1].strip().endswith("/`"):
            folder = cells[1].strip().strip("`").rstrip("/")
            rows[folder] = {name for name in cells[2].split("`") if name.endswith(".py")}
    stages = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").is_file()}
    assert set(rows) == stages
    for folder, named in rows.items():
        files = {p.name for p in (PACKAGE / folder).rglob("*.py") if p.name != "__init__.py"}
        assert named == files, folder
