"""LAPACK's banded and tridiagonal solvers without importing scipy.linalg.

Why: `import scipy.linalg` takes about 0.17 s (its package pulls in scipy's array-API layer and
numpy.f2py), longer than a small job's whole plan, and winder calls only four LAPACK routines (dgbsv,
dgtsv, dpbsv, dpbtrs). Even scipy's compiled `_flapack` extension alone, loaded from its own file,
brings its own OpenBLAS: about 4 ms of wall time (measured: 3.9-4.5 ms against 0.7 ms), some 3 % of
a small job. numpy's wheels carry OpenBLAS too, LAPACK included (64-bit integers, symbols
`scipy_<name>_64_`), and numpy has loaded it already: called there through ctypes (which numpy
imports too) the routines cost nothing to load, and a process goes over to scipy's extension only
once it has made enough calls for its faster calls to pay for the load (EXTENSION_AFTER). Where numpy carries no OpenBLAS of its own (built against
another BLAS), the extension is used from the start, and where it cannot be loaded from its file,
`scipy.linalg.lapack` itself.

`lapack()` answers with the f2py wrappers' calls and results, for the arguments winder passes:
  dgtsv(dl, d, du, b, overwrite_b=0) -> (dl, d, du, x, info)
  dpbsv(ab, b, lower=0, overwrite_ab=0, overwrite_b=0) -> (c, x, info)
  dpbtrs(ab, b, lower=0, overwrite_b=0) -> (x, info)
  dgbsv(kl, ku, ab, b) -> (lu, piv, x, info)
As f2py does, an argument is copied into Fortran order unless it may be overwritten and already is.
"""

from __future__ import annotations

import ctypes
import functools
import importlib.machinery
import importlib.util
import threading
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

__all__ = ["NumpyLapack", "lapack", "numpy_lapack", "scipy_lapack"]

ROUTINES = ("dgbsv", "dgtsv", "dpbsv", "dpbtrs")
_int = ctypes.c_int64
_byref = ctypes.byref
_from_buffer = ctypes.c_double.from_buffer
_ONE_CHAR = ctypes.c_size_t(1)  # gfortran's hidden length of a CHARACTER argument, after the others


# Calls through ctypes cost about 5 us more than scipy's f2py wrappers, which cost about 4 ms to
# load: a process that has made this many calls (a large job, a solver loop) loads them and goes on
# there. The two run the same LAPACK code (tests/geometry/test_lapack.py: bit for bit).
EXTENSION_AFTER = 1000
_calls = 0


def lapack() -> Any:
    """The four routines: numpy's OpenBLAS, or scipy's `_flapack` once EXTENSION_AFTER calls were made
    (or numpy's is not found)."""
    global _calls  # noqa: PLW0603 - a process-wide call count
    _calls += 1
    if _calls <= EXTENSION_AFTER:
        routines = numpy_lapack()
        if routines is not None:
            return routines
    return scipy_lapack()


@functools.cache
def numpy_lapack() -> NumpyLapack | None:
    """The routines in numpy's own OpenBLAS, None where numpy carries none."""
    try:
        return NumpyLapack(_numpy_openblas())
    except (ImportError, OSError, AttributeError):
        return None


@functools.cache
def scipy_lapack() -> Any:
    """scipy's `_flapack` extension, loaded from its file, else `scipy.linalg.lapack`."""
    try:
        return _load_extension()
    except (ImportError, OSError, StopIteration, TypeError):
        from scipy.linalg import lapack as module  # noqa: PLC0415 - the slow, always-working way

        return module


def _numpy_openblas() -> ctypes.CDLL:
    """The OpenBLAS library numpy's wheel loaded (Linux and Windows: numpy.libs; macOS: numpy/.dylibs)."""
    root = Path(np.__file__).parent
    for folder in (root.parent / "numpy.libs", root / ".dylibs"):
        for path in sorted(folder.glob("libscipy_openblas64_*")):
            library = ctypes.CDLL(str(path))
            for name in ROUTINES:
                getattr(library, f"scipy_{name}_64_")  # AttributeError: another build
            return library
    raise ImportError("numpy carries no OpenBLAS of its own")


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


def _fortran(a: np.ndarray, overwrite: Any = 0) -> np.ndarray:
    """a itself where it may be overwritten and is a writable Fortran-ordered float64 array, else
    a copy that is (f2py's intent(in, out, copy))."""
    if overwrite and a.dtype == np.float64:
        flags = a.flags
        if flags.f_contiguous and flags.writeable:
            return a
    return a.copy() if a.ndim == 1 and a.dtype == np.float64 else np.array(a, dtype=np.float64, order="F")


def _ptr(a: np.ndarray) -> Any:
    """A pointer to the first element of a Fortran-ordered array (its transpose is C-ordered)."""
    return _byref(_from_buffer(a.T if a.ndim == 2 else a)) if a.size else _byref(ctypes.c_double())


class _Scratch(threading.local):
    """A thread's integer arguments (INFO last), written before each call: ctypes releases the GIL
    during the call, so each thread has its own; building them per call cost more than the solve."""

    def __init__(self) -> None:
        self.block = (_int * 8)()
        self.ptrs = tuple(_byref(self.block, 8 * k) for k in range(8))


def _set(scratch: _Scratch, *values: int) -> tuple[Any, ...]:
    """scratch's pointers, the first len(values) slots set to values (the INFO slot last, 0)."""
    block = scratch.block
    for k, v in enumerate(values):
        block[k] = v
    return scratch.ptrs


def _rhs(b: np.ndarray) -> tuple[int, int]:
    """(rows, right-hand sides) of b, (n,) or (n, k)."""
    return b.shape[0], (b.shape[1] if b.ndim == 2 else 1)


class NumpyLapack:
    """dgbsv, dgtsv, dpbsv and dpbtrs of a loaded LAPACK with 64-bit integers, as f2py calls them."""

    def __init__(self, library: ctypes.CDLL) -> None:
        self._gbsv, self._gtsv, self._pbsv, self._pbtrs = (getattr(library, f"scipy_{name}_64_") for name in ROUTINES)
        for f in (self._gbsv, self._gtsv, self._pbsv, self._pbtrs):
            f.restype = None
        self._scratch = _Scratch()

    def dgtsv(self, dl: np.ndarray, d: np.ndarray, du: np.ndarray, b: np.ndarray, overwrite_dl: Any = 0,
              overwrite_d: Any = 0, overwrite_du: Any = 0, overwrite_b: Any = 0) -> tuple:
        dl, d, du, b = (_fortran(dl, overwrite_dl), _fortran(d, overwrite_d), _fortran(du, overwrite_du),
                        _fortran(b, overwrite_b))
        n, nrhs = _rhs(b)
        p = _set(self._scratch, n, nrhs, max(n, 1), 0)
        self._gtsv(p[0], p[1], _ptr(dl), _ptr(d), _ptr(du), _ptr(b), p[2], p[3])
        return dl, d, du, b, self._scratch.block[3]

    def dpbsv(self, ab: np.ndarray, b: np.ndarray, lower: Any = 0, overwrite_ab: Any = 0,
              overwrite_b: Any = 0) -> tuple:
        ab, b = _fortran(ab, overwrite_ab), _fortran(b, overwrite_b)
        return ab, b, self._banded(self._pbsv, ab, b, lower)

    def dpbtrs(self, ab: np.ndarray, b: np.ndarray, lower: Any = 0, overwrite_b: Any = 0) -> tuple:
        b = _fortran(b, overwrite_b)
        # ab is only read (f2py's intent(in)): used as it is wherever it is Fortran-ordered and writable
        # (ctypes points into writable buffers only).
        return b, self._banded(self._pbtrs, _fortran(ab, overwrite=True), b, lower)

    def _banded(self, routine: Any, ab: np.ndarray, b: np.ndarray, lower: Any) -> int:
        """pbsv or pbtrs (the same arguments) on the Fortran-ordered ab and b; their INFO."""
        n, nrhs = _rhs(b)
        p = _set(self._scratch, n, ab.shape[0] - 1, nrhs, ab.shape[0], max(n, 1), 0)
        routine(b"L" if lower else b"U", p[0], p[1], p[2], _ptr(ab), p[3], _ptr(b), p[4], p[5], _ONE_CHAR)
        return self._scratch.block[5]

    def dgbsv(self, kl: int, ku: int, ab: np.ndarray, b: np.ndarray, overwrite_ab: Any = 0,
              overwrite_b: Any = 0) -> tuple:
        ab, b = _fortran(ab, overwrite_ab), _fortran(b, overwrite_b)
        n, nrhs = _rhs(b)
        piv = np.zeros(max(n, 1), dtype=np.int64)
        p = _set(self._scratch, n, kl, ku, nrhs, ab.shape[0], max(n, 1), 0)
        self._gbsv(p[0], p[1], p[2], p[3], _ptr(ab), p[4], _byref(_int.from_buffer(piv)), _ptr(b), p[5], p[6])
        return ab, (piv[:n] - 1).astype(np.int32), b, self._scratch.block[6]
