"""A chain of many lines and arcs (mandrel.axis type path): its frame stays orthonormal and its end
where the closed form puts it (issue 45: past ~90 pieces the carried frame grew 3x a piece to NaN, and
`check` of a 100-segment path ended in an internal error)."""

from __future__ import annotations

import math

import numpy as np

from winder.geometry.arcs import ArcSpec, chain

POSITION_TOL = 1e-8  # mm, on a chain ~1.6 m long
FRAME_TOL = 1e-12


def test_a_chain_of_600_pieces_ends_where_the_closed_form_says() -> None:
    """Lines of L and arcs of radius R and angle a, all bent toward e2: a planar curve whose heading
    turns by a per arc: a line adds L (sin psi, 0, cos psi), an arc R (cos psi - cos psi', 0,
    sin psi' - sin psi)."""
    length, radius, angle, n = 1.0, 200.0, 1.0, 300
    path = chain(tuple([length, ArcSpec(radius, angle)] * n))
    end = path.evaluate(np.array([path.length]))
    x, psi = np.zeros(3), 0.0
    for _ in range(n):
        x += length * np.array([math.sin(psi), 0.0, math.cos(psi)])
        nxt = psi + math.radians(angle)
        x += radius * np.array([math.cos(psi) - math.cos(nxt), 0.0, math.sin(nxt) - math.sin(psi)])
        psi = nxt
    assert np.allclose(end.x[0], x, atol=POSITION_TOL, rtol=0.0)
    assert np.allclose(end.d1[0], [math.sin(psi), 0.0, math.cos(psi)], atol=FRAME_TOL, rtol=0.0)
    for piece in path.pieces:
        assert abs(np.linalg.norm(piece.tangent) - 1.0) < FRAME_TOL and abs(np.linalg.norm(piece.e2) - 1.0) < FRAME_TOL
        assert abs(piece.tangent @ piece.e2) < FRAME_TOL
