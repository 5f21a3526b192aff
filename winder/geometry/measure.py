"""Measurements of a path given by parameter points: lengths and quality checks (docs/math/02-energy.md, docs/math/04-checks.md)."""

from __future__ import annotations

import numpy as np

from winder.geometry.index_spline import LOBATTO_T, LOBATTO_W_END, LOBATTO_W_MID, knot_slopes, segment_nodes
from winder.geometry.joints import SplitNodes, joint_stations, split_nodes
from winder.geometry.surface import SweepSurface

GAUSS_NODES = 5  # Gauss-Legendre nodes per segment on short paths
GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(GAUSS_NODES)
GAUSS_SEGMENTS = 256  # paths of up to this many segments use them (see smooth_length)
GAUSS_T = 0.5 + 0.5 * GAUSS_X  # the nodes as fractions of a segment


def pair_columns(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The (m, 2) columns a, b of two (m,) arrays."""
    return np.stack([a, b], axis=1)


def row_norms(v: np.ndarray) -> np.ndarray:
    """The Euclidean norm of each row of v (m, k): (m,)."""
    return np.linalg.norm(v, axis=1)


def grid_groups(keys: np.ndarray, grid: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, group) of the rows of keys (n, c) that round to the same cell of a grid of spacing `grid`
    (a float, or (c,) one per column): each group's lowest row (g,) and each row's group (n,). Rows i
    and first[group[i]] differ by less than the grid in every column."""
    cells = np.round(np.asarray(keys, dtype=float) / grid)
    order = np.lexsort(cells.T[::-1])  # stable: each group's rows in ascending order
    ranked = cells[order]
    new = np.ones(order.size, dtype=bool)
    new[1:] = np.any(ranked[1:] != ranked[:-1], axis=1)
    group = np.empty(order.size, dtype=np.intp)
    group[order] = np.cumsum(new) - 1
    return order[new], group


def polyline_length(points: np.ndarray) -> float:
    """Length of the polyline through points (m, 3)."""
    return float(np.sum(row_norms(points[1:] - points[:-1])))


def smooth_length(surface: SweepSurface, s: np.ndarray, theta: np.ndarray,
                  knots: tuple[np.ndarray, np.ndarray] | None = None, gauss_segments: int = GAUSS_SEGMENTS) -> float:
    """Length of the smooth surface curve through the vertices (the super-convergent length).

    A cubic spline through (s_i, theta_i) against the index i, mapped onto the surface; its speed
    |Phi_s s' + Phi_theta theta'| is integrated per segment. Because a geodesic's length is
    stationary, vertices within O(h^2) of it give a length within O(h^4).
    Paths of up to GAUSS_SEGMENTS segments may be coarse against the surface's curvature: 5-point
    Gauss-Legendre (exact to degree 9). Longer ones: 4-point Gauss-Lobatto (exact to degree 5), whose
    nodes include the knots, so a segment costs two new surface evaluations instead of five; its
    O(h^6) error is then below 1e-12 of the length (measured against 5-point Gauss on the reference
    mandrels: elliptic tube, two rounds, 400 segments: 5e-13).
    s, theta : (m,) float. knots : (Phi_s, Phi_theta) at the m vertices, each (m, 3), when the
    caller has them (the solver does); otherwise they are evaluated here. gauss_segments : the
    longest path given the 5-point rule (0: Gauss-Lobatto at every n).
    """
    return smooth_lengths(surface, [(s, theta, knots)], gauss_segments)[0]


def smooth_lengths(surface: SweepSurface, paths: list[tuple[np.ndarray, np.ndarray, tuple | None]],
                   gauss_segments: int = GAUSS_SEGMENTS) -> list[float]:
    """smooth_length of each path (s, theta, knots), the nodes of all of them in one surface
    evaluation: the evaluation is per point, so every length is the one smooth_length gives alone."""
    plans, s_nodes, th_nodes = [], [], []
    joints = joint_stations(surface)
    for s, theta, knots in paths:
        gauss = s.shape[0] - 1 <= gauss_segments
        split = _split(surface, joints, s, theta, gauss, knots is not None) if joints.size else None
        if split is not None:  # the chain crosses a joint of the guide curve (joints.py)
            s_nodes.append(split.s)
            th_nodes.append(split.theta)
            plans.append((split, None, None, knots, split.s.shape[0]))
            continue
        y = pair_columns(s, theta)
        dy = knot_slopes(y)
        u, du = segment_nodes(y, dy, GAUSS_T if gauss else LOBATTO_T)
        with_knots = not gauss and knots is None
        if with_knots:
            s_nodes.append(s)
            th_nodes.append(theta)
        s_nodes.append(u[:, 0])
        th_nodes.append(u[:, 1])
        plans.append((gauss, dy, du, knots, du.shape[0] + (s.shape[0] if with_knots else 0)))
    one = len(s_nodes) == 1
    ev = surface.evaluate(s_nodes[0] if one else np.concatenate(s_nodes),
                          th_nodes[0] if one else np.concatenate(th_nodes), order=1, with_point=False)
    ps_all, pt_all = ev.ps.T, ev.pt.T
    lengths, start = [], 0
    for gauss, dy, du, knots, count in plans:
        ps, pt = ps_all[:, start:start + count], pt_all[:, start:start + count]
        start += count
        if isinstance(gauss, SplitNodes):
            lengths.append(_split_length(gauss, ps, pt, knots))
            continue
        if gauss:
            speed = _speed(ps, pt, du.T).reshape(-1, GAUSS_NODES)
            lengths.append(float(0.5 * np.sum(speed @ GAUSS_W)))
            continue
        if knots is not None:
            ps, pt = np.concatenate([knots[0].T, ps], axis=1), np.concatenate([knots[1].T, pt], axis=1)
        m = dy.shape[0]
        speed = _speed(ps, pt, np.concatenate([dy.T, du.T], axis=1))
        lengths.append(float(LOBATTO_W_END * (2.0 * np.sum(speed[:m]) - speed[0] - speed[m - 1])
                             + LOBATTO_W_MID * np.sum(speed[m:])))
    return lengths


def _split(surface: SweepSurface, joints: np.ndarray, s: np.ndarray, theta: np.ndarray, gauss: bool,
           with_knots: bool) -> SplitNodes | None:
    """split_nodes with the rule smooth_length uses: Gauss's nodes per segment, or Lobatto's inner two
    and its ends."""
    if gauss:
        return split_nodes(surface, joints, s, theta, GAUSS_T, 0.5 * GAUSS_W, 0.0, with_knots)
    return split_nodes(surface, joints, s, theta, LOBATTO_T, np.full(2, LOBATTO_W_MID), LOBATTO_W_END, with_knots)


def _split_length(split: SplitNodes, ps: np.ndarray, pt: np.ndarray, knots: tuple | None) -> float:
    """The length of a split path from its nodes' fields ps, pt (3, q) (and the vertex knots')."""
    total = float(np.sum(split.w * _speed(ps, pt, split.du)))
    if split.knot_index.size:
        idx = split.knot_index
        total += float(np.sum(split.knot_w * _speed(knots[0][idx].T, knots[1][idx].T, split.knot_du)))
    return total


def _speed(ps: np.ndarray, pt: np.ndarray, du: np.ndarray) -> np.ndarray:
    """|Phi_s s' + Phi_theta theta'| from (3, q) rows ps, pt and (2, q) rows du (s', theta'): (q,)."""
    vel = ps * du[0] + pt * du[1]
    return np.sqrt(np.einsum("ji,ji->i", vel, vel))


def tangent_coordinates(ps: np.ndarray, pt: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(a, b), each (q,): the least-squares a Phi_s + b Phi_theta ~ v of (3, q) rows ps, pt, v, from
    the 2 x 2 Gram systems G (a, b) = (Phi_s . v, Phi_theta . v), solved by np.linalg.solve (which
    refuses a singular one)."""
    basis = np.stack([ps.T, pt.T], axis=2)  # (q, 3, 2)
    gram = np.einsum("nki,nkj->nij", basis, basis)
    ab = np.linalg.solve(gram, np.einsum("nki,nk->ni", basis, v.T)[..., None])[..., 0]
    return ab[:, 0], ab[:, 1]


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise a x b of two (m, 3) arrays."""
    return np.cross(a, b)


def geodesic_curvature(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, points: np.ndarray,
                       jac: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """Discrete geodesic curvature at the interior vertices (paper 4.4), in 1/mm.

    (d_{i-1} x d_i) . N(p_i) with unit segment directions d, divided by the mean of the two
    segment lengths so that it approximates the curvature. jac : (Phi_s, Phi_theta) at the interior
    vertices, each (m - 2, 3), when the caller has them. Returns (m - 2,) float.
    """
    seg = points[1:] - points[:-1]
    return _curvature(surface, s, theta, seg, row_norms(seg), jac)


def _curvature(surface: SweepSurface, s: np.ndarray, theta: np.ndarray, seg: np.ndarray, lens: np.ndarray,
               jac: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray:
    """geodesic_curvature from the segments seg (m - 1, 3) and their lengths lens (m - 1,)."""
    d = seg / lens[:, None]
    if jac is None:
        nrm = surface.normals(s[1:-1], theta[1:-1])
    else:
        nrm = cross(jac[1], jac[0])
        nrm /= row_norms(nrm)[:, None]
    turn = np.einsum("ij,ij->i", cross(d[:-1], d[1:]), nrm)
    return turn / (0.5 * (lens[:-1] + lens[1:]))


def spacing_deviation(points: np.ndarray) -> float:
    """max |segment length / mean - 1|: 0 for an exactly equally spaced polyline."""
    return _spacing(row_norms(points[1:] - points[:-1]))


def _spacing(lens: np.ndarray) -> float:
    return float(np.max(np.abs(lens / lens.mean() - 1.0)))


def segment_measures(points: np.ndarray) -> tuple[float, float]:
    """(polyline_length, spacing_deviation) of the polyline through points (m, 3), from one set of
    segment lengths."""
    lens = row_norms(points[1:] - points[:-1])
    return float(np.sum(lens)), _spacing(lens)


def richardson(l_n: float, l_2n: float) -> tuple[float, float]:
    """Richardson extrapolation of O(1/n^2) polyline lengths at n and 2n + 1 interior points.

    Returns (extrapolated length, error estimate |L_2n - L_n| / 3), both mm.
    """
    return l_2n + (l_2n - l_n) / 3.0, abs(l_2n - l_n) / 3.0
