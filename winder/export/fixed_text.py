"""Fixed-point text of numeric tables, vectorized: byte-identical to Python's "%.{d}f" per value.

A 14 MB job CSV has two million numbers; formatting them one by one (numpy.savetxt, or one large
%-format) costs ~0.5 s on these machines. Here the digits come from integer arithmetic on whole
columns, written into one character matrix of the whole table, each field right-aligned in its
columns; the places a shorter value leaves free hold NUL, so the text is the matrix with its NULs
dropped (one comparison and one gather over contiguous bytes). The matrix is filled transposed, one
contiguous character column at a time, and copied to row order once in cache-sized blocks: gluing
per-field blocks side by side, or writing character columns strided, costs several times that.
"""

from __future__ import annotations

import numpy as np

_ULPS = 8.0 * np.finfo(float).eps  # how close to a rounding half the scaled product may be trusted
_ZERO, _POINT, _MINUS, _COMMA = ord("0"), ord("."), ord("-"), ord(",")
_BLOCK = 4096  # table rows per block of the final transposed copy
SMALL = 200  # rows: fewer are formatted one by one (fixed_rows)


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


class _Field:
    """One column's numbers: their whole parts and decimals as integers, the signs, and width:
    the characters of the longest value, a minus sign included."""

    def __init__(self, values: np.ndarray, decimals: int) -> None:
        q = _scaled(np.asarray(values, dtype=float), decimals) if decimals else np.asarray(values).astype(np.int64)
        self.neg = q < 0  # a value that prints as zero has no sign (never "-0.000000")
        q = np.abs(q)
        self.decimals = decimals
        self.tail = 1 + decimals if decimals else 0  # the point and the decimals
        self.whole = q // 10**decimals
        self.frac = q - self.whole * 10**decimals
        top = int(self.whole.max(initial=0))
        if top < 2**31:  # int32 arithmetic is several times faster, and exact here
            self.whole, self.frac = self.whole.astype(np.int32), self.frac.astype(np.int32)
        self.width = 1 + len(str(top)) + self.tail  # + 1: room for the sign

    def write(self, rows: np.ndarray, end: int) -> None:
        """Its characters into the rows [end - width, end) of rows (w, m) (the table transposed, so
        that each character column is written contiguously), right-aligned; the leading places a
        value does not use keep their NUL."""
        rest, row = self.frac, end - 1
        for _ in range(self.decimals):
            nxt = rest // 10
            rows[row] = rest - 10 * nxt + _ZERO
            rest, row = nxt, row - 1
        if self.decimals:
            rows[row] = _POINT
            row -= 1
        # The whole part's k-th digit from the point is written where whole // 10^k > 0 (the units
        # digit always); the sign goes in the first place past the leading digit.
        rest = self.whole
        nxt = rest // 10
        rows[row] = rest - 10 * nxt + _ZERO
        rest, row, signed = nxt, row - 1, self.neg & (nxt == 0)
        while row >= end - self.width:
            nxt = rest // 10
            used = rest > 0
            # A place past the leading digit has rest = 0 (its digit 0) and holds the sign or NUL; the
            # sign's place is never a digit's, so digit + '0' where used + '-' where signed is the text.
            place = rows[row]
            place[...] = rest - 10 * nxt
            place += used.view(np.uint8) * np.uint8(_ZERO)
            place += signed.view(np.uint8) * np.uint8(_MINUS)
            signed = self.neg & used & (nxt == 0)
            rest, row = nxt, row - 1


def table_text(columns: list[tuple[np.ndarray, int]], tail: np.ndarray, tails: list[str]) -> str:
    """Lines "c_0,c_1,...,tails[tail[i]]": columns as (values (m,), decimals; 0 for integers),
    tail (m,) int indexing tails (text without a "%" rule, without NUL: written as is)."""
    m = tail.shape[0]
    fields = [_Field(values, decimals) for values, decimals in columns]
    t_width = max(len(t) for t in tails) + 1
    t_chars = np.zeros((len(tails), t_width), dtype=np.uint8)
    for i, t in enumerate(tails):
        b = (t + "\n").encode()
        t_chars[i, :len(b)] = np.frombuffer(b, dtype=np.uint8)
    width = sum(f.width + 1 for f in fields) + t_width
    rows = np.zeros((width, m), dtype=np.uint8)
    end = 0
    for f in fields:
        end += f.width
        f.write(rows, end)
        rows[end] = _COMMA
        end += 1
    rows[end:] = t_chars.T[:, tail]
    return _text(rows)


def _text(rows: np.ndarray) -> str:
    """The text of the transposed character matrix rows (w, m): its m lines in order, NULs dropped."""
    width, m = rows.shape
    chars = np.empty((m, width), dtype=np.uint8)
    for lo in range(0, m, _BLOCK):  # in blocks that stay in cache: a transposed copy is strided
        chars[lo:lo + _BLOCK] = rows[:, lo:lo + _BLOCK].T
    flat = chars.reshape(-1)
    return flat[flat != 0].tobytes().decode("ascii")


def printed(values: np.ndarray, decimals: int) -> np.ndarray:
    """The values as "%.{decimals}f" prints them, read back (float(text) of each, bit for bit): the
    printed digits as an integer over 10^decimals, both exact, one correctly rounded division."""
    return _scaled(np.asarray(values, dtype=float), decimals) / 10.0**decimals


def fixed_rows(columns: list[tuple[np.ndarray, int]], prefixes: list[str], sep: str = " ") -> list[str] | None:
    """Lines "p_0c_0 p_1c_1 ..." (prefixes[j] before column j's numbers, sep between the fields), each
    number as "%.{d}f" with d >= 1 decimals, "-0.000" written without its sign: a whole program's
    words at once. None where a value is not finite, or for fewer than SMALL rows (where one by one
    costs less than the arrays' set-up): the caller formats those one by one."""
    if not columns or len(columns[0][0]) < SMALL or any(d < 1 for _, d in columns):
        return None
    if any(not np.all(np.isfinite(v)) for v, _ in columns):
        return None
    m = len(columns[0][0])
    fields = [_Field(values, decimals) for values, decimals in columns]
    width = sum(len(p) + f.width + 1 for p, f in zip(prefixes, fields))
    rows = np.zeros((width, m), dtype=np.uint8)
    end = 0
    for p, f in zip(prefixes, fields):
        for ch in p.encode("ascii"):
            rows[end] = ch
            end += 1
        end += f.width
        f.write(rows, end)
        rows[end] = ord(sep)
        end += 1
    rows[end - 1] = ord("\n")
    return _text(rows).split("\n")[:-1]
