"""bench.solver_speed's like-for-like column: winder's fixed n in hindsight follows solve_bvp's rule (the
level met at that n and at every larger n measured), and such an n is a real solve whose error meets it;
the side-by-side timing gives each task its samples."""

from __future__ import annotations

from bench.cases import cases
from bench.solver_speed import _hindsight_ns, _side_by_side
from winder.geometry.build import build_surface
from winder.paths.geodesic import geodesic


def test_hindsight_takes_only_ns_whose_larger_ns_meet_the_level_too():
    case = next(c for c in cases() if c.key == "bend")
    surface = build_surface(case.mandrel, "bench", case.key)
    truth = geodesic(surface, case.start, case.end, rounds=case.rounds, n=4000, estimate=False).length
    errors = {31: 5e-7, 40: 2e-6, 63: 4e-7, 127: 1e-7, 255: 3e-8}  # 31 meets 1e-6, but 40 does not
    assert _hindsight_ns(errors, 1e-6) == [63]  # up to twice the least n that counts (127 > 126)
    assert _hindsight_ns(errors, 3e-8) == [255]
    assert _hindsight_ns(errors, 1e-9) == []
    res = geodesic(surface, case.start, case.end, rounds=case.rounds, n=63, estimate=False)
    assert abs(res.length - truth) / truth < 1e-6


def test_side_by_side_times_every_task_with_its_value():
    calls = {"a": 0, "b": 0}

    def task(key):
        calls[key] += 1
        return key

    timed = _side_by_side([("a", lambda: task("a")), ("b", lambda: task("b"))], repeats=5)
    assert {k: t.value for k, t in timed.items()} == {"a": "a", "b": "b"}
    assert all(len(t.samples) >= 5 and t.median >= 0.0 for t in timed.values())
    assert calls["a"] == calls["b"]  # round-robin: the two sides ran alike
