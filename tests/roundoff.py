"""Floats computed two ways (another summation order, another BLAS kernel, a batched and a
one-at-a-time evaluation of the same formula) agree to round-off, never bit for bit: the kernel
numpy's OpenBLAS picks depends on the processor (OPENBLAS_CORETYPE)."""

from __future__ import annotations

import numpy as np

# Relative to the values' scale: a few dozen ulps of sums and products over at most a few thousand
# terms, with room for cancellation in the smaller entries of an array.
ROUNDOFF_RTOL = 1e-12


def assert_roundoff(got, want, rtol: float = ROUNDOFF_RTOL, err_msg: str = "") -> None:
    """got equals want (same shape, NaN where want has NaN) within rtol of want's largest magnitude:
    round-off is relative to the scale of the terms, not to an entry that cancelled to near zero."""
    got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
    assert got.shape == want.shape, (got.shape, want.shape, err_msg)
    finite = want[np.isfinite(want)]
    scale = float(np.max(np.abs(finite))) if finite.size else 0.0
    np.testing.assert_allclose(got, want, rtol=rtol, atol=rtol * scale, equal_nan=True, err_msg=err_msg)
