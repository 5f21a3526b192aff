"""Axis dynamics: how long the machine takes over each move of a motion program (docs/math/06-machine.md
 6.4).

A move is the straight line in axis space from one programmed point to the next, all axes
synchronous. Its speed is a scalar sigma along that line in the speed-scaled axis space
y_k = q_k / v_k (q_k the axis value, v_k its top speed per second), so an axis at its top speed moves
y_k by 1 per second. For move j with scaled displacement D_j (length l_j, unit direction n_j):
- cruise: every axis within its top speed, sigma <= 1 / max_k |n_jk|, and the fiber laid no faster
  than the feed: sigma <= l_j feed / f_j (f_j the fiber length of the move, mm; no limit when 0);
- acceleration: dsigma/dt <= min_k (a_k / v_k) / |n_jk| (a_k the axis' acceleration).
Each move runs a trapezoidal profile (accelerate, cruise, decelerate) between its entry and exit
speeds. How consecutive moves are joined: at the junction the speed is limited by the direction
change, as a controller's classic jerk limit does: no axis' velocity may jump by more than
JUNCTION_JUMP of its top speed, sigma_junction = JUNCTION_JUMP / max_k |n_jk - n_(j+1)k| (and
within both moves' cruise). A reversal or a corner therefore nearly stops the machine, a smooth
path runs through. The program starts and ends at rest. Entry and exit speeds come from the usual
forward and backward passes (v^2 grows by at most 2 a l over a move), computed in closed form with
running minima (no loop over moves).

Robot poses are timed the same way on the eye position, each coordinate with the carriage's
dynamics (the direction columns are not axes).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.config.machine import MACHINE_ROLES, MachineConfig
from winder.geometry.measure import row_norms

JUNCTION_JUMP = 0.02  # fraction of an axis' top speed its velocity may jump at a junction
_EPS = 1e-12


@dataclasses.dataclass(frozen=True, eq=False)
class MoveTimes:
    """Timing of the m rows of a program; row i is the move from row i - 1 (row 0: none, 0 s).

    cruise_s : (m,) the move's time at its cruise speed, no acceleration. time_s : (m,) with the
        trapezoidal profile (what a controller is asked for: F of the marlin and linuxcnc dialects).
    feed : (m,) fiber feed of the move (mm/min): machine.feed, lower where an axis' top speed
        limits it (robot poses: machine.feed; the robot's controller keeps its own limits).
    """

    cruise_s: np.ndarray
    time_s: np.ndarray
    feed: np.ndarray

    @property
    def total_s(self) -> float:
        return float(np.sum(self.time_s))


def axis_limits(machine: MachineConfig, robot: bool) -> tuple[np.ndarray, np.ndarray]:
    """(speed per second, acceleration per second^2) of the program's columns."""
    if robot:
        c = machine.dynamics.carriage
        v, a = np.full(3, c.speed / 60.0), np.full(3, c.acceleration)
        return v, a
    dyn = [machine.dynamics.get(role) for role in MACHINE_ROLES]
    return (np.array([d.speed / 60.0 for d in dyn]), np.array([d.acceleration for d in dyn]))


def _trapezoid(length, v0, v1, vc, acc):
    """Time over a move of `length` from speed v0 to v1, cruise vc, acceleration acc (arrays)."""
    peak2 = np.maximum(0.5 * (2.0 * acc * length + v0 * v0 + v1 * v1), 0.0)
    peak = np.minimum(np.sqrt(peak2), vc)
    ramps = (2.0 * peak - v0 - v1) / acc
    cruise_len = np.maximum(length - (2.0 * peak * peak - v0 * v0 - v1 * v1) / (2.0 * acc), 0.0)
    return np.maximum(ramps, 0.0) + cruise_len / np.maximum(peak, _EPS)


def move_times(values: np.ndarray, fiber: np.ndarray, machine: MachineConfig, robot: bool,
               limits: tuple[np.ndarray, np.ndarray] | None = None) -> MoveTimes:
    """Timing of the program rows `values` (m, k) whose moves lay `fiber` (m,) mm (module docstring);
    limits: (speed per second, acceleration) of the columns, instead of axis_limits' (a robot cell)."""
    values = np.asarray(values, dtype=float)
    m = values.shape[0]
    if m < 2:
        return MoveTimes(np.zeros(m), np.zeros(m), np.full(m, float(machine.feed)))
    speed, acc = axis_limits(machine, robot) if limits is None else limits
    cols = speed.size
    delta = np.diff(values[:, :cols], axis=0) / speed  # (m - 1, k) scaled displacement
    length = row_norms(delta)
    moving = length > _EPS
    n = np.where(moving[:, None], delta / np.where(moving, length, 1.0)[:, None], 0.0)
    big = np.max(np.abs(n), axis=1)
    v_axes = 1.0 / np.where(moving, big, 1.0)
    f = np.asarray(fiber, dtype=float)[1:]
    feed_s = float(machine.feed) / 60.0
    with np.errstate(divide="ignore", invalid="ignore"):
        v_feed = np.where(f > _EPS, length * feed_s / np.where(f > _EPS, f, 1.0), np.inf)
        a_move = np.min(np.where(np.abs(n) > _EPS, (acc / speed) / np.abs(n), np.inf), axis=1)
    vc = np.minimum(v_axes, v_feed)
    # Zero-length moves take no time and do not join anything: plan over the moving ones.
    idx = np.flatnonzero(moving)
    time = np.zeros(m - 1)
    cruise = np.zeros(m - 1)
    if idx.size:
        L, V, A, N = length[idx], vc[idx], a_move[idx], n[idx]
        jump = np.max(np.abs(N[1:] - N[:-1]), axis=1) if idx.size > 1 else np.zeros(0)
        with np.errstate(divide="ignore"):
            v_join = np.minimum(np.minimum(V[1:], V[:-1]), JUNCTION_JUMP / jump)
        limit2 = np.concatenate([[0.0], v_join**2, [0.0]])  # speed^2 at the nodes, at most
        gain = np.concatenate([[0.0], np.cumsum(2.0 * A * L)])  # forward: w_i <= w_(i-1) + 2 a l
        fwd = gain + np.minimum.accumulate(limit2 - gain)
        back_gain = np.concatenate([np.cumsum((2.0 * A * L)[::-1])[::-1], [0.0]])
        bwd = back_gain + np.minimum.accumulate((limit2 - back_gain)[::-1])[::-1]
        w = np.sqrt(np.maximum(np.minimum(fwd, bwd), 0.0))
        time[idx] = _trapezoid(L, w[:-1], w[1:], V, A)
        cruise[idx] = L / V
    with np.errstate(divide="ignore", invalid="ignore"):
        fiber_feed = np.where((f > _EPS) & (cruise > 0.0), 60.0 * f / np.where(cruise > 0, cruise, 1.0),
                              float(machine.feed))
    feed = np.full(m - 1, float(machine.feed)) if robot else np.minimum(fiber_feed, float(machine.feed))
    return MoveTimes(np.concatenate([[0.0], cruise]), np.concatenate([[0.0], time]),
                     np.concatenate([[float(machine.feed)], feed]))
