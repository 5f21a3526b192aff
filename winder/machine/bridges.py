"""Bridges: where no one arm configuration serves the whole program, the arm changes configuration
between two moves (docs/math/10-robot-cell.md 10.5).

Winding stops at the row: the ring's axes hold their values and the eye holds the fiber (the tensioner
keeps it taut); the arm, which holds the mandrel, makes a joint move from the configuration it reached
the row in to another configuration of the same pose, and winding goes on. The joint move swings the
mandrel (a 6-axis arm has no two configurations joined at one pose), so a bridge is made only where
the links and the mandrel with its laminate stay clear of the ring, and the links of the mandrel, along
the move (winder.machine.links.joint_move_clear); the configuration sequence is otherwise
chosen again without that row. The configuration after a bridge may take whole turns on the joints
whose range exceeds one (A4 and A6, the UR's joints) as the run after it allows: those that swing the
flange least along the move are tried first (a wrist flip whose A4 and A6 turn opposite ways keeps the
flange within about |A5| of its pose). A bridge at a turnaround (the last row of a pass) costs half as much
as one within a pass, so the stop falls where the fiber turns anyway where it can.

Its time: the slowest joint's move at its top speed, plus JOINT_RAMP_S to start and stop.
"""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np

from winder.config.arms import Arm

BRIDGE_COST = 1.0e4  # s: a bridge costs more than any travel it could save
MAX_SHIFTS = 4  # turn shifts tried per bridge, those that swing the flange least
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


def _turns(arm: Arm) -> list[np.ndarray]:
    """Whole turns (6,) a run after a bridge may be shifted by: of every joint whose range exceeds a
    turn, -1, 0 or +1 turn (no shift first)."""
    wide = [j for j in range(6) if arm.limits[j, 1] - arm.limits[j, 0] > 360.0]
    out = []
    for combo in itertools.product((0.0, -360.0, 360.0), repeat=len(wide)):
        shift = np.zeros(6)
        shift[wide] = combo
        out.append(shift)
    return out


def _swing(arm: Arm, before: np.ndarray, after: np.ndarray) -> float:
    """How far the flange turns off its pose halfway along the joint move (rad): a wrist flip whose
    A4 and A6 turn opposite ways keeps the flange nearly still, the same way turns it half a turn."""
    from winder.machine.arm_ik import fk  # noqa: PLC0415

    ends, mid = fk(arm, before), fk(arm, 0.5 * (before + after))
    return float(np.arccos(np.clip((np.trace(ends[:3, :3].T @ mid[:3, :3]) - 1.0) / 2.0, -1.0, 1.0)))


def make_bridges(arm: Arm, reach, tool: np.ndarray, checker):
    """(the Reach with each run after a bridge shifted by the whole turns that make its joint move
    clear, the bridges) or (None, the first row whose bridge no shift makes clear): a joint move where
    a link or the mandrel would strike the ring, or a link the mandrel (checker:
    winder.machine.links.LinkChecker; tool (4, 4) the mandrel's mount on the flange). Of the shifts
    that keep the run within the limits, those that swing the flange least are tried first."""
    from winder.machine.links import joint_move_clear  # noqa: PLC0415 - the collision library

    joints, arrive = reach.joints.copy(), reach.arrive.copy()
    rows = [int(r) for r in reach.bridges]
    lo, hi = arm.limits[:, 0], arm.limits[:, 1]
    made = []
    for k, row in enumerate(rows):
        end = rows[k + 1] if k + 1 < len(rows) else joints.shape[0]
        run = np.vstack([joints[row:end], arrive[row + 1:end + 1]])
        fits = [t for t in _turns(arm) if np.all(run + t >= lo) and np.all(run + t <= hi)]
        fits.sort(key=lambda t: _swing(arm, arrive[row], joints[row] + t))
        shift = next((t for t in fits[:MAX_SHIFTS] if joint_move_clear(checker, tool, arrive[row], joints[row] + t)), None)
        if shift is None:
            return None, row
        joints[row:end] += shift
        arrive[row + 1:end + 1] += shift
        made.append(Bridge(row, arrive[row].copy(), joints[row].copy(), swap_time(arm, arrive[row], joints[row])))
    return dataclasses.replace(reach, joints=joints, arrive=arrive), tuple(made)
