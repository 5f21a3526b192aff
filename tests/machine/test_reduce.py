"""The batched Douglas-Peucker (winder.machine.reduce) against a plain recursive one, pass by pass."""

from __future__ import annotations

import numpy as np

from winder.machine.reduce import reduce_many, reduce_points


def _recursive(q: np.ndarray, tol: float) -> list[int]:
    """Textbook Douglas-Peucker, recursing into each half (the reference)."""
    m = len(q)
    if m <= 2:
        return list(range(m))
    keep = {0, m - 1}

    def split(i: int, k: int) -> None:
        if k - i < 2:
            return
        seg = q[k] - q[i]
        rel = q[i + 1:k] - q[i]
        len2 = seg @ seg
        u = np.clip(rel @ seg / len2, 0.0, 1.0) if len2 > 0 else np.zeros(k - i - 1)
        dist = np.linalg.norm(rel - u[:, None] * seg, axis=1)
        j = int(np.argmax(dist))
        if dist[j] > tol:
            keep.add(i + 1 + j)
            split(i, i + 1 + j)
            split(i + 1 + j, k)

    split(0, m - 1)
    return sorted(keep)


def test_batch_matches_one_pass_reference():
    rng = np.random.default_rng(3)
    sizes = [0, 1, 2, 3, 5, 40, 400, 1200, 7]
    lines = [np.cumsum(rng.normal(size=(n, 4)) * 0.03, axis=0) for n in sizes]
    lines.append(np.zeros((9, 4)))  # all points on one spot: zero-length chords
    lines.append(np.column_stack([np.linspace(0, 1, 50)] * 4))  # straight: ends only
    tols = rng.uniform(0.01, 0.1, size=len(lines))
    got = reduce_many(lines, tols)
    assert len(got) == len(lines)
    for q, tol, keep in zip(lines, tols, got):
        assert keep.tolist() == _recursive(q, tol)
        assert np.array_equal(keep, reduce_points(q, tol))
    assert got[-1].tolist() == [0, 49]
    assert got[-2].tolist() == [0, 8]
    assert reduce_many([], []) == []


def test_table_is_the_polylines_one_after_the_other():
    from winder.machine.reduce import reduce_table

    rng = np.random.default_rng(8)
    sizes = [3, 0, 250, 1, 2, 97, 600]
    lines = [np.cumsum(rng.normal(size=(n, 6)) * 0.03, axis=0) for n in sizes]
    tols = rng.uniform(0.01, 0.1, size=len(lines))
    got = reduce_table(np.concatenate(lines), np.array(sizes), tols)
    for q, tol, keep in zip(lines, tols, got):
        assert keep.tolist() == _recursive(q, tol)


def _chord_distances(q: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """Each point's distance from the chord between the kept points around it (brute force)."""
    out = np.zeros(len(q))
    for a, b in zip(keep[:-1], keep[1:]):
        seg = q[b] - q[a]
        for k in range(a + 1, b):
            u = np.clip((q[k] - q[a]) @ seg / (seg @ seg), 0.0, 1.0) if seg @ seg > 0 else 0.0
            out[k] = np.linalg.norm(q[k] - q[a] - u * seg)
    return out


def test_translated_copies_are_reduced_once_within_the_tolerance():
    """Polylines that are translates of one another up to round-off noise (turned circuits: A shifted)
    share one reduction: each copy keeps the first's points, and each of its dropped points still lies
    within tol + 4 TRANSLATE_TOL of its chord; a copy moved by more than TRANSLATE_TOL is reduced on its own."""
    from winder.machine.reduce import TRANSLATE_TOL, reduce_table

    rng = np.random.default_rng(12)
    base = np.cumsum(rng.normal(size=(300, 4)) * 0.03, axis=0)
    shifts = rng.uniform(-1e4, 1e4, size=(20, 4)) * np.array([0.0, 0.0, 1.0, 0.0])
    lines = [base + s + rng.uniform(-1e-12, 1e-12, base.shape) for s in shifts]
    moved = base.copy()
    moved[150, 0] += 0.02  # no copy: its own reduction
    lines.append(moved)
    tol = 0.05
    got = reduce_table(np.concatenate(lines), np.full(len(lines), 300), np.full(len(lines), tol))
    for q, keep in zip(lines[:-1], got[:-1]):
        assert np.array_equal(keep, got[0])
        assert np.all(_chord_distances(q, keep) <= tol + 4.0 * TRANSLATE_TOL)
    assert got[-1].tolist() == _recursive(moved, tol)
