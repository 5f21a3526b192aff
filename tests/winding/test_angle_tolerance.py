"""Closing a vessel layer's pattern within winding.angle_tolerance (docs/math/17 17.7; SPEC "Invariants"):
on a hemisphere vessel (R 100, cylinder 200, band 10) the geodesic closure of a 32 deg layer's own circuit
count moves the angle by 1.78 deg. Within the tolerance the planner takes another circuit count or closes
the pattern by friction at the angle; a refusal lists the choices, and the first one, written as it says,
plans within the tolerance."""

from __future__ import annotations

import re

import pytest

from winder.config.job import parse_config
from winder.errors import SolverError
from winder.winding.plan import plan

OWN_MOVE = 1.78  # deg: the 32 deg layer's own closure (54 circuits)


def _job(layer: dict, **winding):
    return parse_config({"name": "v", "mandrel": {"profile": {"type": "vessel", "radius": 100, "cylinder_length": 200,
                                                               "dome": {"type": "hemisphere", "polar_opening": 20}}},
                         "winding": {"band_width": 10, "points": 24, "layers": [layer], **winding}}, "v.yaml")


def test_another_circuit_count_within_the_tolerance():
    layer = plan(_job({"type": "helical", "angle": 32})).layers[0]
    assert abs(layer.angle_deg - 32.0) <= 0.5
    assert layer.coverage.covered_fraction >= 0.999
    assert any("circuits instead of" in n or "closed by friction" in n for n in layer.notes)


def test_a_wider_tolerance_keeps_the_planners_own_closure():
    layer = plan(_job({"type": "helical", "angle": 32}, angle_tolerance=5)).layers[0]
    assert layer.angle_deg - 32.0 == pytest.approx(OWN_MOVE, abs=0.01)


def test_refusal_lists_the_choices_and_the_first_plans():
    # the count fixed and little friction (the closure at the angle needs 0.085): neither is open
    job = _job({"type": "helical", "angle": 32, "circuits": 54}, friction=0.05)
    with pytest.raises(SolverError) as info:
        plan(job)
    message = str(info.value)
    assert "layer 1 (helical 32 deg).angle: closing the pattern of 54 circuits moves the angle +1.784 deg" in message
    assert "beyond winding.angle_tolerance (0.5 deg)" in message and "the choices (winder patterns): " in message
    found = re.search(r"write one as \{type: helical, angle: ([\d.]+), circuits: (\d+), pattern: (\d+)\}", message)
    assert found, message
    angle, circuits, pattern = float(found[1]), int(found[2]), int(found[3])
    layer = plan(_job({"type": "helical", "angle": angle, "circuits": circuits, "pattern": pattern},
                      friction=0.05)).layers[0]
    assert abs(layer.angle_deg - angle) <= 0.5 and (layer.circuits, layer.pattern) == (circuits, pattern)
    assert layer.coverage.covered_fraction >= 0.999
