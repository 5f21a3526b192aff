"""Circuit pattern arithmetic (docs/math/05-winding.md): counts, skips, closure, slots."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.errors import ConfigError
from winder.winding.pattern import (circuits_for_coverage, close_open_pattern, close_vessel_pattern, coprime_skips,
                            slot_of_circuit, slots_filled)

CLOSE = 1e-12


@pytest.mark.parametrize("radius,angle,band", [(50.0, 55.0, 10.0), (40.0, 30.0, 10.0), (100.0, 10.0, 6.0)])
def test_circuits_closed_form(radius, angle, band):
    n = circuits_for_coverage(2 * math.pi * radius, math.radians(angle), band)
    need = 2 * math.pi * radius * math.cos(math.radians(angle)) / band
    assert n - 1 < need <= n


def test_coprime_skips():
    assert coprime_skips(1) == [1]
    assert coprime_skips(12) == [1, 5, 7, 11]
    assert all(math.gcd(k, 19) == 1 for k in coprime_skips(19)) and len(coprime_skips(19)) == 18


@pytest.mark.parametrize("circuits,natural", [(19, 1.37), (22, 0.5), (7, 3.999), (1, 0.25)])
def test_open_pattern_closes_with_least_extra_dwell(circuits, natural):
    pat = close_open_pattern(circuits, natural, 10 / 360, 5 / 360, None, "k")
    assert pat.dwell_start >= 10 / 360 - CLOSE and pat.dwell_end >= 5 / 360 - CLOSE
    frac = (pat.advance - pat.pattern / circuits) % 1.0
    assert min(frac, 1.0 - frac) < 1e-9
    # No other skip closes with less extra dwell.
    extra = pat.dwell_start + pat.dwell_end - 15 / 360
    for k in coprime_skips(circuits):
        assert (k / circuits - natural - 15 / 360) % 1.0 >= extra - 1e-9
    # Every slot is filled exactly once after N_c circuits.
    assert np.all(slots_filled(circuits, pat.pattern) == 1)
    starts = np.array([(j * pat.advance) % 1.0 for j in range(circuits)]) * circuits
    assert np.allclose(np.sort(np.round(starts)) % circuits, np.arange(circuits))


def test_given_pattern_must_be_coprime():
    with pytest.raises(ConfigError, match="pattern 4 shares a factor with the 10 circuits"):
        close_open_pattern(10, 0.3, 0.0, 0.0, 4, "layer 1 (helical 30 deg).pattern")
    assert close_open_pattern(10, 0.3, 0.0, 0.0, 3, "x").pattern == 3


def test_vessel_pattern_moves_c_least():
    # A smooth increasing advance (turns) of the turnaround radius: the closure picks the nearest root.
    def advance(c: float) -> float:
        return 0.8 + 0.02 * c + 1e-4 * c * c

    k, c = close_vessel_pattern(advance, 40.0, 20.0, 95.0, 59, None, "k")
    assert math.gcd(k, 59) == 1
    frac = (advance(c) - k / 59) % 1.0
    assert min(frac, 1 - frac) < 1e-10
    # Brute force: every c on a fine grid where some coprime skip closes the pattern; none is nearer.
    grid = np.linspace(20.0, 95.0, 750001)
    phase = np.array([advance(x) for x in grid]) * 59
    crossings = grid[1:][np.floor(phase[1:]) != np.floor(phase[:-1])]
    slots = np.floor(np.array([advance(x) for x in crossings]) * 59).astype(int) % 59
    closing = crossings[np.array([math.gcd(int(s), 59) == 1 for s in slots])]
    assert abs(c - 40.0) <= np.min(np.abs(closing - 40.0)) + 1e-3


def test_slot_of_circuit_permutation():
    assert sorted(slot_of_circuit(j, 9, 4) for j in range(9)) == list(range(9))
