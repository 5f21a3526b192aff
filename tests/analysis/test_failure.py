"""First-ply failure pressures (docs/math/09-structure.md 9.4): a ply the held loads alone break fails at
pressure 0 by maximum stress and by Tsai-Wu alike, whichever way the pressure then moves its stresses; and
for any stresses, an index of 1 or more at a pressure means a failure pressure no higher."""

from __future__ import annotations

import numpy as np

from winder.analysis.failure import max_stress_index, max_stress_pressure, tsai_wu_index, tsai_wu_pressure
from winder.analysis.materials import MATERIALS

PLY = MATERIALS["eglass_epoxy"]
STRENGTHS = (PLY.Xt, PLY.Xc, PLY.Yt, PLY.Yc, PLY.S)
ROUND_OFF = 1e-9


def test_held_loads_that_break_the_ply_give_zero_whatever_the_pressure_does():
    # the class: a torque's shear past S that the pressure eases (its shear per MPa is negative)
    held = np.array([[0.0, 0.0, 1.05 * PLY.S], [0.0, 1.02 * PLY.Yt, 0.0], [-1.1 * PLY.Xc, 0.0, 0.0]])
    per_p = np.array([[1.0, 0.5, -3.0], [2.0, -1.5, 0.0], [4.0, 0.0, 0.0]])
    assert np.all(max_stress_pressure(per_p, held, STRENGTHS) == 0.0)
    assert np.all(tsai_wu_pressure(per_p, held, STRENGTHS) == 0.0)
    assert np.all(max_stress_index(held, STRENGTHS) > 1.0)


def test_an_index_past_one_means_failure_at_or_below_that_pressure():
    rng = np.random.default_rng(44)
    per_p = rng.normal(0.0, 20.0, (4000, 3))
    held = rng.normal(0.0, 40.0, (4000, 3))
    p = 3.0
    stress = p * per_p + held
    for index, pressure in ((max_stress_index, max_stress_pressure), (tsai_wu_index, tsai_wu_pressure)):
        failed = index(stress, STRENGTHS) >= 1.0
        at = pressure(per_p, held, STRENGTHS)
        assert failed.any() and np.all(at[failed] <= p * (1.0 + ROUND_OFF)), index.__name__
        # and the failure pressure is where the index first reaches 1 (else 0: broken already)
        fine = np.isfinite(at) & (at > 0.0)
        reached = index(at[fine, None] * per_p[fine] + held[fine], STRENGTHS)
        assert np.allclose(reached, 1.0, atol=1e-6), index.__name__
