"""winder.progress: the callback shape, and planning that reports per layer and per circuit."""

from __future__ import annotations

from pathlib import Path

from winder.config.job import load_config
from winder.progress import monotone, part
from winder.winding.plan import plan

ROOT = Path(__file__).resolve().parent.parent


def test_part_maps_a_sub_task_into_its_span():
    seen = []
    sub = part(lambda f, label: seen.append((f, label)), 0.5, 0.9)
    sub(0.0, "a")
    sub(0.5, "b")
    sub(2.0, "c")  # clamped
    assert seen == [(0.5, "a"), (0.7, "b"), (0.9, "c")]
    assert part(None, 0.0, 1.0) is None and monotone(None) is None


def test_monotone_never_steps_back():
    seen = []
    mono = monotone(lambda f, label: seen.append(f))
    for f in (0.1, 0.4, 0.2, 0.5):
        mono(f, "")
    assert seen == [0.1, 0.4, 0.4, 0.5]


def test_planning_reports_every_circuit_of_every_layer():
    job = load_config(ROOT / "samples" / "pipe.yaml")
    seen = []
    result = plan(job, progress=lambda f, label: seen.append((f, label)))
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0 and fractions[0] >= 0.0
    helical = result.layers[0]
    labels = [label for _, label in seen]
    for j in range(1, helical.circuits + 1):
        assert f"layer 1 of 2: circuit {j} of {helical.circuits}" in labels
    assert "layer 2 of 2: hoop traverse 2 of 2" in labels
    # The plan is the same with or without a callback.
    assert plan(job).total_fiber_length_mm == result.total_fiber_length_mm
