"""LAPACK's banded and tridiagonal solvers without importing scipy.linalg.

Why: `import scipy.linalg` takes about 0.17 s (its package pulls in scipy's array-API layer and
numpy.f2py), longer than a small job's whole plan, and winder calls only four Fortran routines of its
compiled `_flapack` extension (dgbsv, dgtsv, dpbsv, dpbtrs). That extension imports nothing but numpy;
loaded from its own file it takes about 6 ms. Its functions are the very objects `scipy.linalg.lapack`
re-exports, so every result is the same; where the file cannot be found or loaded (another scipy
layout), `scipy.linalg.lapack` itself is used.
"""

from __future__ import annotations

import functools
import importlib.machinery
import importlib.util
from pathlib import Path
from types import ModuleType

__all__ = ["lapack"]


@functools.cache
def lapack() -> ModuleType:
    """The module holding scipy's LAPACK wrappers (dgbsv, dgtsv, dpbsv, dpbtrs, ...)."""
    try:
        return _load_extension()
    except (ImportError, OSError, StopIteration, TypeError):
        from scipy.linalg import lapack as module  # noqa: PLC0415 - the slow, always-working way

        return module


def _load_extension() -> ModuleType:
    spec = importlib.util.find_spec("scipy")  # finds the package without running its __init__
    if spec is None or not spec.submodule_search_locations:
        raise ImportError("scipy is not installed")
    folder = Path(next(iter(spec.submodule_search_locations))) / "linalg"
    name = "scipy.linalg._flapack"
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = folder / f"_flapack{suffix}"
        if path.is_file():
            loader = importlib.machinery.ExtensionFileLoader(name, str(path))
            module = importlib.util.module_from_spec(importlib.util.spec_from_loader(name, loader))
            loader.exec_module(module)
            return module
    raise ImportError(f"no _flapack extension in {folder}")
