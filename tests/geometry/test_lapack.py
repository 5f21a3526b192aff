"""winder.geometry.lapack: LAPACK's routines from numpy's OpenBLAS or scipy's extension, the same
results bit for bit, without importing scipy.linalg."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from winder.geometry import lapack as lapack_module
from winder.geometry.lapack import NumpyLapack, lapack, numpy_lapack, scipy_lapack

BOTH = [pytest.param(numpy_lapack, id="numpy's OpenBLAS"), pytest.param(scipy_lapack, id="scipy's extension")]


def _needs(source):
    routines = source()
    if routines is None:
        pytest.skip("numpy carries no OpenBLAS of its own here")
    return routines


@pytest.mark.parametrize("source", BOTH)
def test_the_routines_solve_their_systems(source):
    routines = _needs(source)
    rng = np.random.default_rng(0)
    n = 50
    lower, upper = rng.uniform(-1.0, 1.0, n - 1), rng.uniform(-1.0, 1.0, n - 1)
    diag = 4.0 + rng.uniform(0.0, 1.0, n)
    rhs = rng.normal(size=(n, 2))
    dense = np.diag(diag) + np.diag(lower, -1) + np.diag(upper, 1)
    *_, x, info = routines.dgtsv(lower, diag, upper, rhs)
    assert info == 0
    np.testing.assert_allclose(dense @ x, rhs, atol=1e-12)
    # the same matrix, symmetrized, in lower band storage (kd = 1) for pbsv and pbtrs
    sym = np.diag(diag) + np.diag(lower, -1) + np.diag(lower, 1)
    ab = np.zeros((2, n), order="F")
    ab[0], ab[1, :-1] = diag, lower
    factor, x, info = routines.dpbsv(ab, rhs[:, 0], lower=1)
    assert info == 0
    np.testing.assert_allclose(sym @ x, rhs[:, 0], atol=1e-12)
    x, info = routines.dpbtrs(factor, rhs, lower=1)
    assert info == 0
    np.testing.assert_allclose(sym @ x, rhs, atol=1e-12)
    kl = ku = 1  # gbsv's storage: kl rows for the fill, then the bands from the top
    gb = np.zeros((2 * kl + ku + 1, n), order="F")
    gb[kl, 1:], gb[kl + 1], gb[kl + 2, :-1] = upper, diag, lower
    _, _, x, info = routines.dgbsv(kl, ku, gb, rhs)
    assert info == 0
    np.testing.assert_allclose(dense @ x, rhs, atol=1e-12)


def test_numpy_openblas_and_scipy_extension_agree_bit_for_bit():
    ours, theirs = _needs(numpy_lapack), scipy_lapack()
    rng = np.random.default_rng(1)
    for trial in range(200):
        n, k = int(rng.integers(2, 200)), int(rng.integers(1, 4))
        dl, du = rng.normal(size=n - 1), rng.normal(size=n - 1)
        d = 4.0 + rng.random(n) + (trial % 3 == 0) * 3.0 * rng.normal(size=n)  # some rows pivot
        rhs = rng.normal(size=(n, k)) if trial % 2 else rng.normal(size=n)
        a, b = (r.dgtsv(dl.copy(), d.copy(), du.copy(), rhs.copy(), overwrite_b=True) for r in (ours, theirs))
        assert a[4] == b[4] and np.array_equal(a[3], b[3], equal_nan=True)
        assert a[3].flags.f_contiguous == b[3].flags.f_contiguous
        ab = np.zeros((2 * n, 4)).T
        ab[0], ab[1:] = 5.0 + rng.random(2 * n), 0.5 * rng.normal(size=(3, 2 * n))
        ab[1, -1] = ab[2, -2:] = ab[3, -3:] = 0.0
        g = rng.normal(size=2 * n)
        a, b = (r.dpbsv(ab.copy(order="F"), g.copy(), lower=1, overwrite_ab=1, overwrite_b=1) for r in (ours, theirs))
        assert a[2] == b[2] and np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
        if a[2] == 0:
            x, y = ours.dpbtrs(a[0], g, lower=1), theirs.dpbtrs(b[0], g, lower=1)
            assert x[1] == y[1] and np.array_equal(x[0], y[0])
        kl, ku = 2, 1
        gb = np.zeros((2 * kl + ku + 1, n), order="F")
        gb[kl:] = rng.normal(size=(kl + ku + 1, n))
        gb[kl + ku] += 4.0
        y = rng.normal(size=(n, k))
        a, b = ours.dgbsv(kl, ku, gb, y), theirs.dgbsv(kl, ku, gb, y)
        assert a[3] == b[3] and all(np.array_equal(u, v) for u, v in zip(a[:3], b[:3]))


def test_inputs_are_kept_unless_they_may_be_overwritten():
    routines = _needs(numpy_lapack)
    dl, d, du, b = np.full(3, -1.0), np.full(4, 4.0), np.full(3, -1.0), np.ones(4)
    kept = [a.copy() for a in (dl, d, du, b)]
    routines.dgtsv(dl, d, du, b)
    assert all(np.array_equal(a, c) for a, c in zip((dl, d, du, b), kept))
    *_, x, _ = routines.dgtsv(dl, d, du, b, overwrite_b=1)
    assert x is b


def test_a_process_goes_over_to_the_extension_after_enough_calls(monkeypatch):
    _needs(numpy_lapack)
    monkeypatch.setattr(lapack_module, "_calls", 0)
    assert isinstance(lapack(), NumpyLapack)
    monkeypatch.setattr(lapack_module, "_calls", lapack_module.EXTENSION_AFTER)
    assert lapack() is scipy_lapack()


def test_without_numpy_openblas_the_extension_serves(monkeypatch):
    monkeypatch.setattr(lapack_module, "_calls", 0)
    monkeypatch.setattr(lapack_module, "numpy_lapack", lambda: None)
    assert lapack() is scipy_lapack()


def test_loading_them_leaves_scipy_linalg_unimported():
    code = ("import sys; from winder.geometry.lapack import lapack, scipy_lapack; lapack().dpbsv; "
            "scipy_lapack().dpbsv; print('scipy.linalg' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
