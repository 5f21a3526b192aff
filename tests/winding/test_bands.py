"""Band unions on a circle: many sets at once against one at a time (to round-off), and closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from winder.winding.bands import union_stats, union_stats_many
from roundoff import ROUNDOFF_RTOL

EVEN_ABS = 1e-9  # mm: N abutting bands of P / N cover P (round-off of the edges only)


def _sets(rng):
    p = np.float64(2.0 * np.pi * 50.0)
    sets = [(rng.uniform(0, p, 30), rng.uniform(1, 6, 30), p),  # scattered: gaps and overlaps
            (np.zeros(0), np.zeros(0), p),  # no bands
            (np.array([p - 1.0]), np.array([4.0]), p),  # one band across the seam
            (np.array([10.0]), np.array([p]), p),  # wider than the perimeter
            (np.arange(40) * p / 40, np.full(40, p / 80), p),  # abutting exactly, as hoop turns
            (rng.uniform(0, 100.0, 12), np.full(12, 30.0), np.float64(100.0)),  # all doubly covered
            (np.array([20.0, 60.0]), np.array([5.0, 5.0]), np.float64(100.0))]  # two bands, two gaps
    return sets


def test_many_is_one_at_a_time():
    sets = _sets(np.random.default_rng(5))
    got = union_stats_many([s[0] for s in sets], [s[1] for s in sets], [s[2] for s in sets])
    for (c, h, p), g in zip(sets, got):
        want = union_stats(c, h, p)
        assert g == pytest.approx(want, rel=ROUNDOFF_RTOL, abs=EVEN_ABS) and [type(v) for v in g] == [type(v) for v in want]


def test_even_bands_cover_once():
    p = 300.0
    (covered, gap, overlap, lo, hi), = union_stats_many([np.arange(25) * p / 25 + 3.0], [np.full(25, p / 50)], [p])
    assert covered == pytest.approx(p, abs=EVEN_ABS) and gap == 0.0 and overlap == 0.0 and lo == hi == 1


def test_two_bands_closed_form():
    (covered, gap, overlap, lo, hi), = union_stats_many([np.array([20.0, 60.0])], [np.array([5.0, 5.0])], [100.0])
    # bands [15, 25] and [55, 65] on a circle of 100: 20 covered, gaps 30 and 50, no overlap
    assert covered == pytest.approx(20.0) and gap == pytest.approx(50.0) and overlap == 0.0
    assert (lo, hi) == (0, 1)


@pytest.mark.parametrize("centres, halves, widest", [
    ([5.0, 3.0, 8.5], [5.0, 1.0, 3.5], 5.0),  # [0, 10], [2, 4], [5, 12]: the third shares [5, 10] with the first
    (list(np.arange(10) * 10.0 + 5.0), [10.0] * 10, 10.0),  # 10 bands of 20 on 100: twice covered all round
    ([97.0, 50.0], [5.0, 5.0], 0.0),  # one across the seam, none shared
    ([98.0, 3.0], [4.0, 4.0], 3.0),  # [94, 102] and [-1, 7]: [-1, 2] shared across the seam
    ([95.0, 1.0, 8.0], [25.0, 1.0, 5.0], 10.0),  # [70, 120] wraps over [3, 13] whole, past the first band
])
def test_the_overlap_is_the_widest_stretch_bands_share(centres, halves, widest):
    """The overlap is what a band shares with others (at most its width), not the longest run covered
    twice (the whole perimeter in the second case)."""
    for got in (union_stats(np.array(centres), np.array(halves), 100.0)[2],
                union_stats_many([np.array(centres)], [np.array(halves)], [100.0])[0][2]):
        assert got == pytest.approx(widest, abs=EVEN_ABS)


def test_a_circle_too_small_to_resolve_is_refused_alike():
    args = ([np.array([1e-8])], [np.array([1e-8])], [1e-7])
    with pytest.raises(ValueError):
        union_stats(args[0][0], args[1][0], args[2][0])
    with pytest.raises(ValueError):
        union_stats_many(*args)


def test_many_random_sets_are_one_at_a_time():
    rng = np.random.default_rng(11)
    sets = []
    for _ in range(300):
        k = int(rng.integers(0, 40))
        p = np.float64(rng.uniform(50.0, 500.0))
        sets.append((rng.uniform(-p, 2 * p, k), rng.uniform(0.0, 0.2 * p, k) ** rng.uniform(0.5, 1.5), p))
    got = union_stats_many([s[0] for s in sets], [s[1] for s in sets], [s[2] for s in sets])
    for (c, h, p), g in zip(sets, got):
        assert g == pytest.approx(union_stats(c, h, p), rel=ROUNDOFF_RTOL, abs=EVEN_ABS)
