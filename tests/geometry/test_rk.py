"""The Dormand-Prince 8(5,3) integrator (geometry.rk) against independent truths: the tableau's order
conditions (quadrature ones: b . c^q = 1 / (q + 1)); polynomials the step and the dense output must
reproduce exactly (orders 8 and 7); the harmonic oscillator's closed form and its zeros as event
times; a blow-up that must fail. Its use on fiber paths: tests/paths/test_friction_rk.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.geometry.rk import B, D, E3, E5, A, solve_rk
from winder.geometry.rk import _C as C

ORDER_TOL = 1e-15  # the tableau's conditions, in double precision
EXACT_TOL = 1e-12  # relative: a polynomial the method integrates exactly (rounding only)
OSCILLATOR_TOL = 1e-10  # the oscillator's state over 10 periods at rtol = atol = 1e-12
EVENT_TOL = 1e-11  # event times (the solution's own error, not the root finder's)
BLOW_UP_TOL = 1e-6  # where a failing integration stops short of the blow-up at t = 1


def oscillator(_t, y):
    return [y[1], -y[0]]


# -- the tableau ------------------------------------------------------------------------------------------
def test_order_conditions():
    assert np.max(np.abs(A.sum(axis=1) - C)) < ORDER_TOL  # row sums are the nodes
    for q in range(8):  # the 8th-order weights integrate c^q exactly up to q = 7
        assert abs(B @ C[:12] ** q - 1.0 / (q + 1)) < ORDER_TOL
    # both error estimates are differences of weights that each integrate a constant
    assert abs(E5.sum()) < ORDER_TOL and abs(E3.sum()) < ORDER_TOL
    assert np.max(np.abs(D.sum(axis=1))) < 1e-12  # the interpolant's corrections vanish on constants


@pytest.mark.parametrize("degree", [6, 7])
def test_polynomials_are_integrated_exactly(degree):
    """y' = (q + 1) t^q: the step (order 8) is exact for q <= 7, the dense output (order 7) for q <= 6."""
    res = solve_rk(lambda t, _y: [(degree + 1) * t**degree], (0.0, 2.0), [0.0], rtol=1e-3, atol=1e-3,
                   dense_output=True, first_step=0.7)
    assert abs(res.y[0, -1] - 2.0 ** (degree + 1)) < EXACT_TOL * 2.0 ** (degree + 1)
    if degree <= 6:
        t = np.linspace(0.0, 2.0, 57)
        assert np.max(np.abs(res.sol(t)[0] - t ** (degree + 1))) < EXACT_TOL * 2.0 ** (degree + 1)


# -- the oscillator -----------------------------------------------------------------------------------
def test_oscillator_closed_form_and_dense_output():
    t_end = 20.0 * math.pi
    res = solve_rk(oscillator, (0.0, t_end), [1.0, 0.0], rtol=1e-12, atol=1e-12, dense_output=True)
    assert res.success and res.status == 0 and res.t[-1] == t_end
    assert np.max(np.abs(res.y - np.stack([np.cos(res.t), -np.sin(res.t)]))) < OSCILLATOR_TOL
    t = np.random.default_rng(1).uniform(0.0, t_end, 500)
    assert res.sol(t).shape == (2, 500) and res.sol(1.0).shape == (2,)
    assert np.max(np.abs(res.sol(t) - np.stack([np.cos(t), -np.sin(t)]))) < OSCILLATOR_TOL
    assert np.array_equal(res.sol(res.t[:-1]), res.y[:, :-1])  # the interpolant passes through the steps


def test_event_times_and_directions():
    """cos t falls through zero at pi/2 + 2 pi j and rises at 3 pi/2 + 2 pi j."""
    def zero(_t, y):
        return y[0]

    zero.direction = -1.0
    res = solve_rk(oscillator, (0.0, 13.0), [1.0, 0.0], rtol=1e-12, atol=1e-12, events=[zero])
    assert res.status == 0 and res.sol is None
    assert np.max(np.abs(res.t_events[0] - (np.pi / 2 + 2 * np.pi * np.arange(2)))) < EVENT_TOL

    zero.direction, zero.terminal = 1.0, True
    res = solve_rk(oscillator, (0.0, 13.0), [1.0, 0.0], rtol=1e-12, atol=1e-12, events=[zero], dense_output=True)
    assert res.status == 1 and res.message == "A termination event occurred."
    assert abs(res.t[-1] - 1.5 * np.pi) < EVENT_TOL
    assert np.allclose(res.y[:, -1], [0.0, 1.0], atol=EVENT_TOL) and res.y_events[0].shape == (1, 2)
    assert np.array_equal(res.sol(res.t[-1]), res.y[:, -1])


def test_blow_up_fails():
    """y' = y^2, y(0) = 1 leaves every bound at t = 1: the steps shrink to nothing."""
    res = solve_rk(lambda _t, y: y * y, (0.0, 2.0), [1.0], rtol=1e-10, atol=1e-10)
    assert res.status == -1 and not res.success
    assert abs(res.t[-1] - 1.0) < BLOW_UP_TOL and np.isfinite(res.y).all()


# -- friction paths ---------------------------------------------------------------------------------------
