"""Fixed-point text of numeric tables, vectorized: byte-identical to Python's "%.{d}f" per value.

A 14 MB job CSV has two million numbers; formatting them one by one (numpy.savetxt, or one large
%-format) costs ~0.5 s on these machines. Here the digits come from integer arithmetic on whole
columns into a character matrix, and a mask drops each field's unused leading columns, so the text
is one boolean gather of that matrix.
"""

from __future__ import annotations

import numpy as np

_DIGITS = np.frombuffer(b"0123456789", dtype=np.uint8)
_POW10 = 10 ** np.arange(19, dtype=np.int64)
_ULPS = 8.0 * np.finfo(float).eps  # how close to a rounding half the scaled product may be trusted


def _scaled(v: np.ndarray, decimals: int) -> np.ndarray:
    """v * 10^decimals rounded as "%.{decimals}f" rounds v (exact binary value, ties to even): int64."""
    p = v * 10.0**decimals
    out = np.rint(p).astype(np.int64)
    # The product carries a rounding error of its own: within a few ulp of a half, Python's exact
    # conversion decides (a handful of values in a million).
    close = np.abs(np.abs(p - np.floor(p)) - 0.5) <= _ULPS * np.maximum(np.abs(p), 1.0)
    for k in np.flatnonzero(close):
        out[k] = int(f"{v[k]:.{decimals}f}".replace(".", ""))
    return out


def _field(v: np.ndarray, decimals: int) -> tuple[np.ndarray, np.ndarray]:
    """Right-aligned characters (m, w) uint8 of each value, and the mask (m, w) of those used.

    A value that prints as zero has no sign (never "-0.000000")."""
    q = _scaled(np.asarray(v, dtype=float), decimals) if decimals else np.asarray(v).astype(np.int64)
    neg = q < 0
    q = np.abs(q)
    whole, frac = np.divmod(q, _POW10[decimals])
    digits = np.maximum(1, np.searchsorted(_POW10, whole, side="right"))
    tail = 1 + decimals if decimals else 0  # the point and the decimals
    w = 1 + int(digits.max(initial=1)) + tail
    chars = np.empty((q.shape[0], w), dtype=np.uint8)
    col = w - 1
    for _ in range(decimals):
        frac, d = np.divmod(frac, 10)
        chars[:, col] = _DIGITS[d]
        col -= 1
    if decimals:
        chars[:, col] = ord(".")
        col -= 1
    while col >= 0:
        whole, d = np.divmod(whole, 10)
        chars[:, col] = _DIGITS[d]
        col -= 1
    start = w - tail - digits - neg
    rows = np.flatnonzero(neg)
    chars[rows, start[rows]] = ord("-")
    return chars, np.arange(w)[None, :] >= start[:, None]


def table_text(columns: list[tuple[np.ndarray, int]], tail: np.ndarray, tails: list[str]) -> str:
    """Lines "c_0,c_1,...,tails[tail[i]]": columns as (values (m,), decimals; 0 for integers),
    tail (m,) int indexing tails (text without a "%" rule: written as is)."""
    m = tail.shape[0]
    comma = np.full((m, 1), ord(","), dtype=np.uint8)
    on = np.ones((m, 1), dtype=bool)
    chars, masks = [], []
    for values, decimals in columns:
        c, k = _field(values, decimals)
        chars += [c, comma]
        masks += [k, on]
    width = max(len(t) for t in tails) + 1
    t_chars = np.zeros((len(tails), width), dtype=np.uint8)
    t_mask = np.zeros((len(tails), width), dtype=bool)
    for i, t in enumerate(tails):
        b = (t + "\n").encode()
        t_chars[i, :len(b)] = np.frombuffer(b, dtype=np.uint8)
        t_mask[i, :len(b)] = True
    chars.append(t_chars[tail])
    masks.append(t_mask[tail])
    return np.concatenate(chars, axis=1)[np.concatenate(masks, axis=1)].tobytes().decode("ascii")
