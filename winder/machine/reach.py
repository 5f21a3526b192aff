"""The arm's configuration along the whole program (docs/math/10-robot-cell.md 10.4): every inverse
kinematics solution of every pose, and the sequence of them chosen by dynamic programming.

A state is one closed-form branch (shoulder, elbow, wrist) with a whole number of turns added to each
joint whose range exceeds a turn (the wrist's A4 and A6, every UR joint). Along the rows a state's
joints are continuous (np.unwrap). A row is feasible in a state when its pose has that solution, every
joint is within its limits and the wrist is at least singularity_margin from its singularity. The
program may stay in a state from one row to the next when no joint moves more than max_joint_step (more
is a flip the controller's linear interpolation would not follow), at the cost of the joints' travel
(each joint's move over its top speed, s), plus at every row a penalty within LIMIT_ZONE of a joint
limit and within WRIST_ZONE of the wrist singularity. At any row the state may change by a bridge
(winder.machine.bridges), at a cost above any travel it could save (less at a turnaround). The cheapest
sequence over the whole program is found by the Viterbi recursion, one row at a time over all states.

A program no sequence serves is refused (ExportError, exit 1) before any file is written, at the first
row no state reaches, naming its layer, circuit and pass, the joint, its value and the limit.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable

import numpy as np

from winder.config.arms import Arm
from winder.config.robot import RobotCell
from winder.errors import ExportError
from winder.machine.arm_ik import ik

WRIST = 4  # the joint whose zero (and 180 deg) is the wrist singularity
LIMIT_ZONE = 20.0  # deg from a joint limit within which a row is penalised
WRIST_ZONE = 15.0  # deg from the wrist singularity (beyond the margin) within which a row is penalised
ZONE_WEIGHT = 1.0  # the penalty (s) of a row at a limit or at the margin, falling quadratically to 0
TURNS = range(-2, 3)  # whole turns tried on a joint whose range exceeds a turn
MAX_STATES = 1024  # states of one program (8 branches x turn choices)
CHUNK = 4096  # rows whose penalties are held at once


@dataclasses.dataclass(frozen=True)
class Reach:
    """The arm's joints along the program.

    joints : (m, 6) deg, the configuration each row leaves in. arrive : (m, 6) the configuration each
    row is reached in (joints but at a bridge, where the arm changes configuration). bridges : (k,) the
    rows after which the arm bridges. limit_margin : the least distance of a joint from its limits
    (deg). wrist_margin : the least |sin| of the wrist joint, as an angle (deg).
    """

    joints: np.ndarray
    arrive: np.ndarray
    bridges: np.ndarray
    limit_margin: float
    wrist_margin: float


def _continuous(q: np.ndarray) -> np.ndarray:
    """q (m, 6) made continuous along the rows (np.unwrap), the rows without a solution (NaN) bridged
    by the last solution before them, and left NaN."""
    bad = np.isnan(q)
    filled = q
    if bad.any():
        idx = np.where(~bad, np.arange(q.shape[0])[:, None], 0)
        np.maximum.accumulate(idx, axis=0, out=idx)
        filled = np.take_along_axis(np.where(bad, 0.0, q), idx, axis=0)
    out = np.unwrap(filled, period=360.0, axis=0) if q.shape[0] else filled
    return np.where(bad, np.nan, out)


def wrist_angle(q: np.ndarray) -> np.ndarray:
    """The wrist joint's distance from its singularity (deg): |sin| as an angle."""
    return np.degrees(np.arcsin(np.minimum(np.abs(np.sin(np.radians(q[..., WRIST]))), 1.0)))


def _states(arm: Arm, unwrapped: np.ndarray) -> list[tuple[int, np.ndarray]]:
    """(branch, turns (6,) deg) of every state worth trying: per joint the whole turns that bring some
    row within the limits."""
    lo, hi = arm.limits[:, 0], arm.limits[:, 1]
    out = []
    for b in range(unwrapped.shape[1]):
        u = unwrapped[:, b]
        if np.isnan(u).all():
            continue
        choices = []
        for j in range(6):
            ks = [360.0 * k for k in TURNS if np.any((u[:, j] + 360.0 * k >= lo[j]) & (u[:, j] + 360.0 * k <= hi[j]))]
            choices.append(ks)
        out.extend((b, np.array(turns)) for turns in itertools.product(*choices))
    return out[:MAX_STATES]


def _penalty(arm: Arm, cell: RobotCell, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(feasible (..., ), penalty (...)) of joints q (..., 6) (module docstring)."""
    lo, hi = arm.limits[:, 0], arm.limits[:, 1]
    with np.errstate(invalid="ignore"):
        room = np.minimum(q - lo, hi - q)
        wrist = wrist_angle(q)
        ok = ~np.isnan(q).any(axis=-1) & (room >= 0.0).all(axis=-1) & (wrist >= cell.singularity_margin)
        near = np.clip(1.0 - room / LIMIT_ZONE, 0.0, None) ** 2
        close = np.clip(1.0 - (wrist - cell.singularity_margin) / WRIST_ZONE, 0.0, None) ** 2
        cost = ZONE_WEIGHT * (np.nansum(near, axis=-1) + close)
    return ok, np.where(ok, cost, np.inf)


def configure(arm: Arm, cell: RobotCell, flange: np.ndarray, bridge_cost: np.ndarray,
              where: Callable[[int], str]) -> Reach:
    """The configuration sequence of the flange poses (m, 4, 4) in the arm's base frame (module
    docstring); bridge_cost (m,): what changing configuration at a row costs (inf: not there)."""
    m = flange.shape[0]
    unwrapped = np.stack([_continuous(s) for s in np.moveaxis(ik(arm, flange), 1, 0)], axis=1)  # (m, 8, 6)
    states = _states(arm, unwrapped)
    if m == 0 or not states:
        raise _refusal(arm, cell, unwrapped, 0, where, [(b, np.zeros(6)) for b in range(8)])
    branch = np.array([b for b, _ in states])
    turns = np.array([t for _, t in states])  # (S, 6)
    step = np.abs(np.diff(unwrapped, axis=0))  # (m - 1, 8, 6)
    with np.errstate(invalid="ignore"):
        travel = np.sum(step / arm.speed, axis=2)  # s per move, per branch
        jump = ~(step <= cell.max_joint_step).all(axis=2)
    travel = np.where(jump | np.isnan(travel), np.inf, travel)
    count = len(states)
    came = np.zeros((m, count), dtype=bool)  # the row's state was entered by a bridge at the row
    best_prev = np.zeros(m, dtype=int)
    cost = np.full(count, np.inf)
    for lo_row in range(0, m, CHUNK):
        q = unwrapped[lo_row:lo_row + CHUNK, branch] + turns  # (rows, S, 6)
        _, pen = _penalty(arm, cell, q)
        for k in range(q.shape[0]):
            r = lo_row + k
            stay = pen[k] if r == 0 else cost + travel[r - 1, branch] + pen[k]
            if r and np.isfinite(bridge_cost[r]):
                j = int(np.argmin(stay))
                swap = np.isfinite(pen[k]) & (stay[j] + bridge_cost[r] < stay)
                came[r] = swap
                best_prev[r] = j
                stay = np.where(swap, stay[j] + bridge_cost[r], stay)
            if not np.isfinite(stay).any():
                alive = np.flatnonzero(np.isfinite(cost)) if r else np.arange(count)
                raise _refusal(arm, cell, unwrapped, r, where, [states[i] for i in alive])
            cost = stay
    return _backtrack(arm, unwrapped, branch, turns, came, best_prev, cost)


def _backtrack(arm: Arm, unwrapped: np.ndarray, branch: np.ndarray, turns: np.ndarray, came: np.ndarray,
               best_prev: np.ndarray, cost: np.ndarray) -> Reach:
    """The Reach of the cheapest sequence (the states read back from the last row)."""
    m = unwrapped.shape[0]
    state = np.empty(m, dtype=int)
    before = np.empty(m, dtype=int)
    s = int(np.argmin(cost))
    for r in range(m - 1, -1, -1):
        state[r] = s
        if came[r, s]:
            s = int(best_prev[r])
        before[r] = s
    rows = np.arange(m)
    joints = unwrapped[rows, branch[state]] + turns[state]
    arrive = unwrapped[rows, branch[before]] + turns[before]
    lo, hi = arm.limits[:, 0], arm.limits[:, 1]
    both = np.vstack([joints, arrive])
    margin = float(np.min(np.minimum(both - lo, hi - both)))
    return Reach(joints, arrive, np.flatnonzero(state != before), margin, float(np.min(wrist_angle(both))))


def _refusal(arm: Arm, cell: RobotCell, unwrapped: np.ndarray, row: int, where: Callable[[int], str],
             alive: list[tuple[int, np.ndarray]]) -> ExportError:
    """Why none of the states alive before the row (alive: (branch, turns)) reaches it: the one nearest
    its joint limits (the joint, its value and the limit), else the wrist's singularity, else a flip;
    where the pose has no solution at all, it is out of reach."""
    lo, hi = arm.limits[:, 0], arm.limits[:, 1]
    names = arm.joint_names
    found: dict[str, tuple[float, str]] = {}
    for b, turns in alive:
        q = unwrapped[row, b] + turns if unwrapped.shape[0] else np.full(6, np.nan)
        if np.isnan(q).any():
            continue
        excess = np.maximum(lo - q, q - hi)
        wrist = float(wrist_angle(q))
        if excess.max() > 0.0:
            j = int(np.argmax(excess))
            bound = lo[j] if q[j] < lo[j] else hi[j]
            found.setdefault("limit", (np.inf, ""))
            if excess[j] < found["limit"][0]:
                found["limit"] = (float(excess[j]), f"joint {names[j]} at {q[j]:.2f} deg, beyond its limit {bound:g} deg")
        elif wrist < cell.singularity_margin:
            found["wrist"] = (0.0, f"joint {names[WRIST]} at {q[WRIST]:.2f} deg, within {cell.singularity_margin:g} deg "
                                   f"of the wrist singularity (machine.robot.singularity_margin)")
        elif row:
            jumps = np.abs(q - (unwrapped[row - 1, b] + turns))
            j = int(np.nanargmax(jumps))
            found["jump"] = (0.0, f"joint {names[j]} jumps {jumps[j]:.2f} deg from the pose before, more than "
                                  f"{cell.max_joint_step:g} deg (machine.robot.max_joint_step)")
    what = next((found[k][1] for k in ("limit", "wrist", "jump") if k in found),
                f"the pose has no solution, beyond the arm's reach (joint {names[2]}, the elbow, would have to stretch "
                "past straight)")
    return ExportError(f"{where(row)}, program row {row}: the {arm.name} cannot reach the pose: {what}; move the ring "
                       f"(machine.robot.positioner.origin), the arm's base or the mandrel's mount (machine.robot.tool)")
