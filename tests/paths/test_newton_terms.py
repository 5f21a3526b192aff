"""The Newton step's fused terms (energy.newton_terms, newton_banded) and the lengths of several solves
in one evaluation (measure.smooth_lengths), to round-off against the plain per-field computations."""

from __future__ import annotations

import numpy as np
import pytest

from winder.geometry.measure import smooth_length, smooth_lengths
from winder.paths.energy import banded, chain_segments, newton_banded, newton_terms
from winder.paths.geodesic import geodesic, straight_path
from roundoff import assert_roundoff


def _wavy(surface, n: int):
    s, th = straight_path(0.2 * surface.length, 0.1, 0.8 * surface.length, 4.0, n)
    th[1:-1] += 0.05 * np.sin(np.arange(1, n + 1))
    return s, th


@pytest.mark.parametrize("surface_name", ["quarter_bend", "elliptic_tube", "cone"])
@pytest.mark.parametrize("n", [1, 2, 31, 1000])
def test_newton_terms_are_the_row_wise_dot_products(request, surface_name, n):
    surface = request.getfixturevalue(surface_name)
    s, th = _wavy(surface, n)
    ev = surface.evaluate(s[1:-1], th[1:-1], order=2)
    ends = surface.evaluate(s[[0, -1]], th[[0, -1]], order=0).p
    e, grad, y, gram, curv, off = newton_terms(ev, ends)
    chain = np.concatenate([ends[:1], ev.p, ends[1:]])
    d = np.diff(chain, axis=0)
    a = d[:-1] - d[1:]
    dot = lambda u, v: np.einsum("ij,ij->i", u, v)  # noqa: E731
    assert_roundoff(e, float(np.einsum("ij,ij->", d, d)))
    np.testing.assert_array_equal(y, chain)
    assert_roundoff(grad, 2.0 * np.stack([dot(ev.ps, a), dot(ev.pt, a)], axis=1))
    assert_roundoff(gram, [[dot(ev.ps, ev.ps), dot(ev.ps, ev.pt)],
                          [dot(ev.pt, ev.ps), dot(ev.pt, ev.pt)]])
    assert_roundoff(curv, [dot(a, ev.pss), dot(a, ev.pst), dot(a, ev.ptt)])
    assert_roundoff(off, [[dot(ev.ps[:-1], ev.ps[1:]), dot(ev.ps[:-1], ev.pt[1:])],
                         [dot(ev.pt[:-1], ev.ps[1:]), dot(ev.pt[:-1], ev.pt[1:])]])
    # the trial point's chain, handed on, gives the same terms
    again = newton_terms(ev, ends, chain_segments(ev.p, ends))
    for x, z in zip(again, (e, grad, y, gram, curv, off)):
        assert_roundoff(x, z)
    # the banded matrix written in place is banded() of the scaled entries
    for c in (curv, None):
        diag = 4.0 * np.array([gram[0, 0], gram[0, 1], gram[1, 1]]) + (0.0 if c is None else 2.0 * c)
        want = banded(4.0 * np.array([gram[0, 0], gram[0, 1], gram[1, 1]]) if c is None else diag,
                      -2.0 * off.reshape(4, -1))
        got = newton_banded(gram, c, off)
        assert got.flags.f_contiguous
        assert_roundoff(got, want)


@pytest.mark.parametrize("lobatto", [False, True])
def test_lengths_of_several_paths_in_one_evaluation_are_each_alone(quarter_bend, elliptic_tube, lobatto):
    for surface in (quarter_bend, elliptic_tube):
        sols = [geodesic(surface, (20.0, 0.0), (180.0, 2.0), n=n, estimate=False) for n in (31, 63, 300)]
        paths = [(r.s, r.theta, None) for r in sols]
        gauss = 0 if lobatto else 256
        alone = [smooth_length(surface, s, th, gauss_segments=gauss) for s, th, _ in paths]
        assert smooth_lengths(surface, paths, gauss) == alone
