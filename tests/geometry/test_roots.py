"""winder.geometry.roots.bracketed_root against closed-form roots."""

from __future__ import annotations

import math

import pytest

from winder.geometry.roots import bracketed_root

ROOT_TOL = 1e-12


@pytest.mark.parametrize(("f", "a", "b", "root"), [
    (lambda x: x * x - 2.0, 0.0, 2.0, math.sqrt(2.0)),
    (lambda x: math.cos(x) - x, 0.0, 1.0, 0.7390851332151607),
    (lambda x: math.atan(50.0 * (x - 0.3)), -1.0, 2.0, 0.3),  # flat far off: the Illinois halving closes both ends
    (lambda x: math.exp(x) - 10.0, -5.0, 5.0, math.log(10.0)),
    (lambda x: math.tan(x) - 1.0, 0.0, 1.5, math.pi / 4.0),
])
def test_closed_form_roots(f, a, b, root) -> None:
    assert abs(bracketed_root(f, a, b) - root) < ROOT_TOL + 4e-16 * abs(root)


def test_given_end_values_are_used_and_ends_can_be_roots() -> None:
    calls = []

    def f(x: float) -> float:
        calls.append(x)
        return x - 0.25

    assert abs(bracketed_root(f, 0.0, 1.0, fa=-0.25, fb=0.75) - 0.25) < ROOT_TOL
    assert 0.0 not in calls and 1.0 not in calls
    assert bracketed_root(f, 0.25, 1.0) == 0.25


def test_same_signs_are_refused() -> None:
    with pytest.raises(ValueError, match="different signs"):
        bracketed_root(lambda x: x * x + 1.0, -1.0, 1.0)
