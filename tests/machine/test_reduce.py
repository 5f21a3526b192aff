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
