"""Bridges: where no one arm configuration serves the whole program, the arm changes configuration
between two moves (docs/math/10-robot-cell.md 10.5).

Winding stops at the row: the ring's axes hold their values and the eye holds the fiber (the tensioner
keeps it taut); the arm, which holds the mandrel, makes a joint move from the configuration it reached
the row in to another configuration of the same pose, and winding goes on. The joint move swings the
mandrel (a 6-axis arm has no two configurations joined at one pose), so a bridge is made only where
the links and the mandrel with its laminate stay clear of the ring, and the links of the mandrel, along
the move (winder.machine.links.joint_move_clear); the configuration sequence is otherwise
chosen again without that row. A bridge at a turnaround (the last row of a pass) costs half as much
as one within a pass, so the stop falls where the fiber turns anyway where it can.

Its time: the slowest joint's move at its top speed, plus JOINT_RAMP_S to start and stop.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.config.arms import Arm

BRIDGE_COST = 1.0e4  # s: a bridge costs more than any travel it could save
JOINT_RAMP_S = 0.5  # s from rest to a joint's top speed (its acceleration; makers publish none)


@dataclasses.dataclass(frozen=True)
class Bridge:
    """One configuration change after program row `row`: the joints before and after (6,) (deg) and the
    joint move's time (s)."""

    row: int
    before: np.ndarray
    after: np.ndarray
    time_s: float


def bridge_costs(m: int, pass_start: np.ndarray) -> np.ndarray:
    """(m,) the cost of a bridge after each row: BRIDGE_COST, half at the last row of a pass, none
    (inf) at the first row of the program."""
    cost = np.full(m, BRIDGE_COST)
    last = np.flatnonzero(pass_start)[1:] - 1
    cost[last[last >= 0]] = 0.5 * BRIDGE_COST
    if m:
        cost[0] = np.inf
    return cost


def swap_time(arm: Arm, before: np.ndarray, after: np.ndarray) -> float:
    """The joint move's time from the joints before (6,) to after (6,)."""
    return float(np.max(np.abs(after - before) / arm.speed)) + JOINT_RAMP_S


def make_bridge(arm: Arm, reach, row: int, tool: np.ndarray, checker) -> Bridge | None:
    """The bridge after `row` from reach.arrive[row] to reach.joints[row], or None where a link or the
    mandrel strikes the ring, or a link the mandrel, along the joint move (checker:
    winder.machine.links.LinkChecker; tool (4, 4) the mandrel's mount on the flange)."""
    from winder.machine.links import joint_move_clear  # noqa: PLC0415 - the collision library

    before, after = reach.arrive[row], reach.joints[row]
    if not joint_move_clear(checker, tool, before, after):
        return None
    return Bridge(row, before, after, swap_time(arm, before, after))
