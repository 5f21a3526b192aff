"""The Examples of the public API's docstrings (numpydoc), run as doctests: every module of winder whose
docstrings show `>>>` examples, found from the source, so that an example added anywhere runs here."""

from __future__ import annotations

import doctest
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
