"""The vectorized fixed-point table text against Python's own "%.{d}f" formatting, value by value."""

from __future__ import annotations

import numpy as np
import pytest

from winder.export.fixed_text import table_text


def _python_text(columns, tail, tails) -> str:
    """The independent truth: each value through Python's "%" formatting, a zero's sign dropped."""
    lines = []
    for i in range(tail.shape[0]):
        words = []
        for values, decimals in columns:
            word = f"%.{decimals}f" % float(values[i]) if decimals else str(int(values[i]))
            words.append(word[1:] if word.strip("-0.") == "" and word.startswith("-") else word)
        lines.append(",".join(words + [tails[tail[i]]]) + "\n")
    return "".join(lines)


def _values(rng: np.random.Generator, m: int) -> np.ndarray:
    """Numbers of every size and sign, with exact halves and values that print as -0."""
    scale = 10.0 ** rng.integers(-8, 8, m)
    v = rng.standard_normal(m) * scale
    v[: m // 8] = np.round(v[: m // 8], 7) + 5e-7 * rng.choice([-1.0, 1.0], m // 8)  # near a rounding half
    v[m // 8: m // 4] = -rng.uniform(0.0, 4.9e-7, m // 4 - m // 8)  # prints as -0.000000 in Python
    v[m // 4: m // 4 + 4] = [0.0, -0.0, 0.5, -2.5]
    return v


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_table_text_matches_python_formatting(seed):
    rng = np.random.default_rng(seed)
    m = 4000
    columns = [(rng.integers(-5, 100000, m), 0), (_values(rng, m), 6), (_values(rng, m), 3),
               (rng.integers(0, 10, m), 0), (_values(rng, m) * 1e4, 1)]
    tails = ["forward", "return", "turnaround"]
    tail = rng.integers(0, len(tails), m)
    assert table_text(columns, tail, tails) == _python_text(columns, tail, tails)


def test_table_text_single_and_wide_rows():
    columns = [(np.array([7]), 0), (np.array([-123456789.25]), 6), (np.array([0.0]), 0)]
    assert table_text(columns, np.array([0]), ["hoop"]) == "7,-123456789.250000,0,hoop\n"


@pytest.mark.parametrize("decimals", [1, 3, 6])
def test_fixed_rows_and_printed_match_python(decimals):
    from winder.export.fixed_text import fixed_rows, printed

    rng = np.random.default_rng(decimals)
    cols = [_values(rng, 4000) for _ in range(3)]
    cols[1][:50] = np.round(cols[1][:50], decimals) + 0.5 * 10.0**-decimals  # exact-looking halves
    got = fixed_rows([(c, decimals) for c in cols], ["X", "AB", ""])
    for i, line in enumerate(got):
        words = []
        for prefix, c in zip(["X", "AB", ""], cols):
            word = f"%.{decimals}f" % float(c[i])
            words.append(prefix + (word[1:] if word.strip("-0.") == "" and word.startswith("-") else word))
        assert line == " ".join(words)
    for c in cols:
        want = np.array([float(f"%.{decimals}f" % v) for v in c.tolist()])
        assert np.array_equal(np.abs(printed(c, decimals)).view(np.int64), np.abs(want).view(np.int64))
        assert np.array_equal(printed(c, decimals), want)
    assert len(got) == 4000 and fixed_rows([(np.r_[np.ones(500), np.nan], 3)], [""]) is None
