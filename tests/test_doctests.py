"""The Examples of the public API's docstrings (numpydoc), run as doctests: every module of winder whose
docstrings show `>>>` examples, found from the source, so that an example added anywhere runs here."""

from __future__ import annotations

import doctest
import inspect
import importlib
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "winder"
MODULES = sorted(".".join(p.relative_to(PACKAGE.parent).with_suffix("").parts) for p in PACKAGE.rglob("*.py")
                 if ">>> " in p.read_text(encoding="utf-8"))
# The main stages' entry points must keep examples (issue 47: Parameters, Returns, Examples).
DOCUMENTED = ("winder.config.job", "winder.config.schema", "winder.geometry.build", "winder.paths.geodesic",
              "winder.winding.plan", "winder.machine.program", "winder.export.registry")


def test_the_main_stages_have_examples():
    assert set(DOCUMENTED) <= set(MODULES), sorted(set(DOCUMENTED) - set(MODULES))


@pytest.mark.parametrize("name", MODULES)
def test_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
                             verbose=False, report=True)
    assert result.attempted > 0
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed (printed above)"


# The entry points whose docstrings carry numpydoc's Parameters, Returns and Examples sections.
ENTRY_POINTS = ("winder.config.job.load_config", "winder.config.job.parse_config", "winder.config.schema.job_schema",
                "winder.geometry.build.build_surface", "winder.paths.geodesic.geodesic", "winder.winding.plan.plan",
                "winder.machine.program.build_program", "winder.export.registry.chosen")


def _sections(doc: str) -> dict[str, str]:
    """numpydoc sections of a docstring: heading -> body (a heading is a line over a line of dashes)."""
    lines = inspect.cleandoc(doc).splitlines()
    heads = [i for i in range(len(lines) - 1) if lines[i].strip() and set(lines[i + 1].strip()) == {"-"}]
    return {lines[i].strip(): "\n".join(lines[i + 2:j - 1 if j < len(lines) else j])
            for i, j in zip(heads, [*heads[1:], len(lines) + 1])}


@pytest.mark.parametrize("dotted", ENTRY_POINTS)
def test_entry_points_document_every_parameter(dotted):
    module, name = dotted.rsplit(".", 1)
    function = getattr(importlib.import_module(module), name)
    sections = _sections(function.__doc__ or "")
    assert {"Returns", "Examples"} <= set(sections), f"{dotted}: sections {sorted(sections)}"
    params = [p for p in inspect.signature(function).parameters if p not in ("self",)]
    if params:
        documented = {n.strip() for line in sections.get("Parameters", "").splitlines()
                      if line and not line[0].isspace() for n in line.split(":")[0].split(",")}
        assert set(params) <= documented, f"{dotted}: undocumented {sorted(set(params) - documented)}"
