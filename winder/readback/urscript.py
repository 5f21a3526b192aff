"""URScript read back (winder.export.dialects.urscript writes it): every line one of the statements
below, a comment or a line of the ring's helper functions as written, anything else refused naming its
line (winder.readback.cells).

`def name():`, the helpers (winder.export.dialects.urscript.PROLOGUE), `set_tcp(p[...])` (the mandrel's
mount), `movej([6 joints], a=.., v=..)` (the start), `ring(e1, e2, e3, t)`, `ring_wait()`,
`movel(p[x, y, z, rx, ry, rz], a=.., v=.., t=.., r=..)` (metres, a rotation vector; t at least the
2 ms cycle; r at least 0), `movej([...], a=.., v=.., t=.., r=0)` after a movel with r=0 (a bridge),
`end`. Each blend radius is checked as the writer bounds it (winder.machine.blends: within
BLEND_FRACTION of both moves it joins, its eye deviation within BLEND_SHARE of the chord tolerance), and
the ring's axes are those its lines drive it to, on the schedule the blends give the lines: the eye at
each waypoint and halfway along each move is where the arm's pose and the ring's axes then put it.
"""

from __future__ import annotations

import re

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ConfigError
from winder.machine.blends import BLEND_FRACTION, CYCLE_S, blend_radii, line_times
from winder.machine.cell_frames import mandrel_in_base
from winder.readback.cells import NUMBER, CellRead, Rows, frames_of, midpoints, numbers, same_frame, seconds
from winder.readback.subprograms import URSCRIPT, in_order

_N = NUMBER
_DEF = re.compile(r"^def ([A-Za-z][A-Za-z0-9_]{0,62})\(\):$")
_TCP = re.compile(r"^set_tcp\(p\[([^\]]*)\]\)$")
_START = re.compile(rf"^movej\(\[([^\]]*)\], a=({_N}), v=({_N})\)$")
_RING = re.compile(r"^ring\(([^()]*)\)$")
_MOVEL = re.compile(r"^movel\(p\[([^\]]*)\], a=(\S+), v=(\S+), t=(\S+), r=(\S+)\)$")
_BRIDGE = re.compile(r"^movej\(\[([^\]]*)\], a=(\S+), v=(\S+), t=(\S+), r=0\)$")
RADIUS_TOL = 1e-6  # m: a written radius may pass its bound by its rounding


def _rotations(rv: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation  # noqa: PLC0415

    return Rotation.from_rotvec(rv).as_matrix() if rv.shape[0] else np.zeros((0, 3, 3))


def _prologue() -> set[str]:
    from winder.export.dialects.urscript import PROLOGUE  # noqa: PLC0415 - the helpers exactly as written

    return {line.strip() for line in PROLOGUE}


def read_urscript(text: str, machine: MachineConfig, source: str) -> CellRead:  # noqa: C901, PLR0912, PLR0915
    """The program's rows, frames and ring axes (module docstring)."""
    cell = machine.cell
    rows = Rows.of(source, machine)
    lines = text.splitlines()
    if not lines or lines[-1].strip() != "end":
        raise ConfigError(f"{source}: the script does not end with its function's end: cut short?")
    helpers = _prologue()
    name, start, start_line, tcp = None, None, 0, False
    poses, move_s, radii, ring_lines, bridges, pause = [], [], [], [], {}, []
    ring_at: list[tuple[int, list[float], float]] = []  # (the move it precedes, targets, time)
    for n, raw in in_order(list(enumerate(lines[:-1], start=1)), URSCRIPT, source):  # each layer's function where called
        line = raw.strip()
        if not line or rows.comment(line, n):
            continue
        if name is None:
            hit = _DEF.match(line)
            if not hit:
                raise ConfigError(f"{source}: line {n}: the script must start with def name():, got {line[:60]!r}")
            name = hit[1]
        elif (line in helpers and not tcp) or (line == "ring_wait()" and len(ring_at) == 1 and not poses):  # noqa: PLR2004
            continue
        elif hit := _TCP.match(line):
            if tcp or start is not None:
                raise ConfigError(f"{source}: line {n}: set_tcp comes once, before any motion")
            v = numbers(hit[1], source, n, "the TCP", 6)
            frame = frames_of(np.array([v[:3]]) * 1000.0, _rotations(np.array([v[3:]])))[0]
            same_frame(cell.tool, frame, source, n, "the TCP", "machine.robot.tool")
            tcp = True
        elif (hit := _START.match(line)) and start is None:
            if not tcp:
                raise ConfigError(f"{source}: line {n}: the start movej before set_tcp")
            start, start_line = np.degrees(numbers(hit[1], source, n, "the start joints (rad)", 6)), n
        elif hit := _RING.match(line):
            values = numbers(hit[1], source, n, "ring(e1, e2, e3, t)", 4)
            if start is not None and poses and values[3] <= 0.0:
                raise ConfigError(f"{source}: line {n}: the ring's time must be positive, got {values[3]:g}")
            if values[3] < 0.0 or values[3] > 3600.0:
                raise ConfigError(f"{source}: line {n}: the ring's time must be within [0, 3600] s, got {values[3]:g}")
            ring_at.append((len(poses) if ring_at else -1, values[:3], values[3]))
            ring_lines.append(n)
        elif hit := _MOVEL.match(line):
            if start is None or len(ring_at) < 2 or ring_at[-1][0] != len(poses):
                raise ConfigError(f"{source}: line {n}: a movel needs the start movej and its ring(...) line before it")
            v = numbers(hit[1], source, n, "the pose", 6)
            seconds(hit[2], source, n, "a")
            seconds(hit[3], source, n, "v")
            t = seconds(hit[4], source, n, "t (s, the controller's cycle at least)", CYCLE_S)
            r = seconds(hit[5], source, n, "r") if hit[5] not in ("0", "0.0000000") else 0.0
            poses.append(v)
            move_s.append(t)
            radii.append(r * 1000.0)
            pause.append(0.0)
            rows.add(n, t if len(poses) > 1 else 0.0, raw)
        elif (hit := _BRIDGE.match(line)) and poses:
            if radii[-1] != 0.0 or len(poses) - 1 in bridges:
                raise ConfigError(f"{source}: line {n}: a bridge's movej must follow a movel with r=0")
            bridges[len(poses) - 1] = (np.degrees(numbers(hit[1], source, n, "the joints (rad)", 6)), n)
            pause[-1] = seconds(hit[4], source, n, "t")
        else:
            raise ConfigError(f"{source}: line {n}: not a statement of winder's URScript programs, got {line[:60]!r}")
    if start is None:
        raise ConfigError(f"{source}: the script has no start movej")
    table = np.array(poses, dtype=float).reshape(-1, 6)
    mandrel = frames_of(1000.0 * table[:, :3], _rotations(table[:, 3:]))
    ring_in_base = mandrel_in_base(cell, np.eye(4)[None])[0]
    frames = np.linalg.inv(mandrel) @ ring_in_base
    radii_a = np.array(radii)
    arrive, starts = line_times(np.array(move_s), radii_a, mandrel, np.array(pause))
    external, mid_ext = _ring(ring_at, arrive, starts, np.array(pause), ring_lines, source)
    mids = midpoints(frames, external, mid_ext)
    return CellRead(rows, frames, external, start, start_line, bridges, mids, lambda: _check_blends(
        machine, mandrel, frames, external, radii_a, np.array(rows.lines), source, np.array(move_s)))


def _check_blends(machine: MachineConfig, mandrel: np.ndarray, frames: np.ndarray, ring: np.ndarray,
                  radii: np.ndarray, lines: np.ndarray, source: str, move_s: np.ndarray) -> None:
    """Every blend radius within the arm's share of the bound the writer keeps (module docstring): the
    ring's own corner is read as its lines drive it (ring (k, 3) its axes at the waypoints)."""
    lever = np.linalg.norm(frames[:, :3, 3], axis=1) + ring[:, 2]
    bound = blend_radii(mandrel, lever, machine.chord_tolerance, np.zeros(mandrel.shape[0], dtype=bool), None, move_s)
    step = np.linalg.norm(np.diff(mandrel[:, :3, 3], axis=0), axis=1)
    bound[-1] = 0.0
    over = np.flatnonzero(radii > np.maximum(bound, 0.0) + 1000.0 * RADIUS_TOL)
    if over.size:
        k = int(over[0])
        near = min(step[k - 1], step[k]) if 0 < k < step.size else 0.0
        raise ConfigError(f"{source}: line {lines[k]}: the blend radius {radii[k]:.4f} mm is more than the "
                          f"{bound[k]:.4f} mm that keeps the eye within the chord tolerance and the blend within "
                          f"{BLEND_FRACTION:g} of its moves ({near:.4f} mm)")


def _ring(ring_at: list, arrive: np.ndarray, starts: np.ndarray, pause: np.ndarray, ring_lines: list,
          source: str) -> tuple[np.ndarray, np.ndarray]:
    """The ring's axes at each waypoint (k, 3) and halfway along each move (k, 3), as its lines drive it:
    from the start's axes, each line's targets reached linearly in its time from when it runs (the
    line before the move to waypoint j runs at starts[j])."""
    k = arrive.size
    if len(ring_at) != k + 1 or any(at != j - 1 for j, (at, _, _) in enumerate(ring_at)):
        line = ring_lines[min(len(ring_lines), k + 1) - 1] if ring_lines else 0
        raise ConfigError(f"{source}: line {line}: one ring(...) line must precede the start's wait and each movel")
    # knots: the start's axes at 0 (its own line, before the wait); each movel's line: the axes where the
    # ring is when it runs, its targets its time later
    times, values = [0.0], [np.asarray(ring_at[0][1], dtype=float)]
    ring_at = ring_at[1:]
    now = values[0]
    for j in range(k):
        if j > 0:  # where the last line's linear move has got to when this one runs
            t0, span = times[-2], ring_at[j - 1][2]
            share = 1.0 if span <= 0.0 else min(max((starts[j] - t0) / span, 0.0), 1.0)
            now = values[-2] + share * (values[-1] - values[-2])
        times += [starts[j], starts[j] + ring_at[j][2]]
        values += [now, np.asarray(ring_at[j][1], dtype=float)]
    t_sorted, v_sorted = np.array(times), np.array(values)
    order = np.argsort(t_sorted, kind="stable")
    t_sorted, v_sorted = t_sorted[order], v_sorted[order]
    mid_t = np.concatenate([[0.5 * arrive[0]], 0.5 * (arrive[:-1] + pause[:-1] + arrive[1:])])

    def at(t: np.ndarray) -> np.ndarray:
        return np.column_stack([np.interp(t, t_sorted, v_sorted[:, c]) for c in range(3)])

    return at(arrive), at(mid_t)
