"""A robot cell's motion (docs/math/10-robot-cell.md): from the eye poses of the one motion program,
the ring's station frame S(t*) in the mandrel frame, the ring's external axes (E1 turn, E2 eye yaw,
E3 eye radius), the flange poses in the arm's base frame, the arm's joints (winder.machine.reach) and
each move's time from the dynamics (the tool, the external axes and the joints).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from winder.config.arms import ARMS, Arm
from winder.config.machine import MachineConfig
from winder.config.robot import RobotCell
from winder.errors import ExportError
from winder.machine.bridges import JOINT_RAMP_S, Bridge, bridge_costs, make_bridges
from winder.machine.cell_frames import mandrel_in_base, ring_axes, station_frames
from winder.machine.dynamics import MoveTimes, move_times
from winder.machine.reach import Reach, configure

MAX_BRIDGE_ROUNDS = 8  # the configuration chosen again without a turnaround whose bridge cannot be made


@dataclasses.dataclass(frozen=True)
class CellMotion:
    """The cell's motion over the m program rows.

    station : (m,) t* (mm). frames : (m, 4, 4) S(t*), the ring's frame in the mandrel frame (what KRL's
    E6POS and RAPID's robtarget hold). external : (m, 3) E1 ring turn (deg, cumulative), E2 eye yaw
    (deg, continuous), E3 eye radius (mm). flange : (m, 4, 4) the flange in the arm's base frame.
    mandrel : (m, 4, 4) the mandrel frame in the arm's base frame (URScript's pose, TCP = tool).
    reach : the joints and margins. times : each move's time. tool_path : (m,) the ring centre's
    travel in the mandrel frame along each move (mm). bridges : the configuration changes
    (winder.machine.bridges), each after its row.
    """

    arm: Arm
    cell: RobotCell
    station: np.ndarray
    frames: np.ndarray
    external: np.ndarray
    flange: np.ndarray
    mandrel: np.ndarray
    reach: Reach
    times: MoveTimes
    tool_path: np.ndarray
    bridges: tuple[Bridge, ...] = ()

    @property
    def program_times(self) -> MoveTimes:
        """The moves' times with each bridge's time on its row (the summary's and the layers' times)."""
        extra = np.zeros_like(self.times.time_s)
        for bridge in self.bridges:
            extra[bridge.row] += bridge.time_s
        return MoveTimes(self.times.cruise_s, self.times.time_s + extra, self.times.feed)


def cell_motion(machine: MachineConfig, guide, values: np.ndarray, fiber: np.ndarray,
                where: Callable[[int], str], source: str | None = None,
                pass_start: np.ndarray | None = None, surface=None) -> CellMotion:
    """The motion of machine.cell over the program rows values (m, 6) (eye position, unit direction
    from the eye to its contact) that lay fiber (m,) mm each; pass_start (m,) bool the rows that start
    a pass (the turnarounds, where the arm may bridge); surface the part's outer surface (the mandrel
    with its laminate, which no link may touch); ExportError where the arm cannot follow or a link
    strikes the ring or the mandrel (winder.machine.links)."""
    from winder.machine.links import LinkChecker, check_links  # noqa: PLC0415 - the collision library

    cell = machine.cell
    assert cell is not None
    arm = ARMS[cell.arm]
    eye = np.asarray(values[:, :3], dtype=float)
    station, frames = station_frames(guide, eye)
    external = ring_axes(frames, eye, -np.asarray(values[:, 3:6], dtype=float))
    if cell.axes < 3 and external.shape[0]:
        spread = float(np.ptp(external[:, 2]))
        if spread > machine.chord_tolerance:
            raise ExportError(f"the eye's radius on the ring varies by {spread:.3f} mm along the program (the eye "
                              f"envelope follows the mandrel), more than the chord tolerance: positioner.axes: 3 "
                              f"(the eye's radial slide) is needed", file=source, key_path="machine.robot.positioner.axes")
        external[:, 2] = float(np.mean(external[:, 2]))
    if cell.axes < 2:
        external[:, 1] = 0.0
    mandrel = mandrel_in_base(cell, frames)
    flange = mandrel @ np.linalg.inv(cell.tool.matrix())
    starts = np.zeros(station.shape[0], dtype=bool) if pass_start is None else pass_start
    checker = LinkChecker(arm, cell, float(np.max(external[:, 2])) if external.size else 0.0, surface)
    reach, bridges = _configured(arm, cell, flange, bridge_costs(station.shape[0], starts), where, checker)
    check_links(checker, reach.joints, mandrel, where)
    dyn = machine.dynamics
    # The joints as one continuous motion: at a bridge the move in ends in the old configuration and
    # the move out starts in the new one (the joint move between them is the bridge's own time).
    swap = np.cumsum(reach.joints - reach.arrive, axis=0)
    columns = np.column_stack([frames[:, :3, 3], external, reach.joints - swap])
    speed = np.concatenate([np.full(3, dyn.carriage.speed / 60.0),
                            [dyn.rotation.speed / 60.0, dyn.yaw.speed / 60.0, dyn.cross_feed.speed / 60.0],
                            arm.speed])
    acc = np.concatenate([np.full(3, dyn.carriage.acceleration),
                          [dyn.rotation.acceleration, dyn.yaw.acceleration, dyn.cross_feed.acceleration],
                          arm.speed / JOINT_RAMP_S])
    times = move_times(columns, fiber, machine, True, limits=(speed, acc))
    tool_path = np.concatenate([[0.0], np.linalg.norm(np.diff(frames[:, :3, 3], axis=0), axis=1)])
    return CellMotion(arm, cell, station, frames, external, flange, mandrel, reach, times, tool_path, bridges)


def _configured(arm: Arm, cell: RobotCell, flange: np.ndarray, cost: np.ndarray, where: Callable[[int], str],
                checker) -> tuple[Reach, tuple[Bridge, ...]]:
    """The configuration sequence (winder.machine.reach) and its bridges (winder.machine.bridges); a row
    whose bridge cannot be made is taken off the rows a bridge may follow and the sequence chosen again."""
    cost = cost.copy()
    tool = cell.tool.matrix()
    for _ in range(MAX_BRIDGE_ROUNDS):
        reach, made = make_bridges(arm, configure(arm, cell, flange, cost, where), tool, checker)
        if reach is not None:
            return reach, made
        cost[made] = np.inf
    return configure(arm, cell, flange, np.full_like(cost, np.inf), where), ()
