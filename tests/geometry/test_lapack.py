"""winder.geometry.lapack: scipy's own LAPACK routines, loaded without importing scipy.linalg."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from winder.geometry.lapack import lapack


def test_the_routines_solve_a_tridiagonal_system():
    rng = np.random.default_rng(0)
    n = 50
    lower, upper = rng.uniform(-1.0, 1.0, n - 1), rng.uniform(-1.0, 1.0, n - 1)
    diag = 4.0 + rng.uniform(0.0, 1.0, n)
    rhs = rng.normal(size=n)
    *_, x, info = lapack().dgtsv(lower.copy(), diag.copy(), upper.copy(), rhs.copy())
    dense = np.diag(diag) + np.diag(lower, -1) + np.diag(upper, 1)
    assert info == 0
    np.testing.assert_allclose(dense @ x, rhs, atol=1e-12)


def test_loading_them_leaves_scipy_linalg_unimported():
    code = ("import sys; from winder.geometry.lapack import lapack; lapack().dpbsv; "
            "print('scipy.linalg' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
