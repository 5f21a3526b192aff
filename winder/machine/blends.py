"""A UR arm's continuous motion and the ring's drive in step with it (docs/math/10-robot-cell.md 10.7).

URScript's movel blends into the next move within its radius r of the waypoint (the TCP's distance),
so the arm never stops there. The blend stays within the triangle of the waypoint and the points r
before and after it on the two moves; in the pose space whose metric bounds the eye's motion relative
to the mandrel (the TCP's position, and its rotation times the lever from the TCP to the eye, the ring
centre's distance plus the eye's radius) that triangle lies within max(a, b) sin(turn) of the
polyline, a and b its sides, turn the angle between the two moves (at most 90 deg counted). Each radius
is the largest that keeps this within BLEND_SHARE of the chord tolerance, the ring's own corner (below)
within RING_SHARE, and the blend within BLEND_FRACTION of both moves it joins (there the chord's own
bow is at most 4 f (1 - f) = 0.36 of its largest: together within the tolerance; and no two blends
overlap). No blend at the program's ends and at a bridge (a stop).

The ring follows by a schedule of its own: the line before a movel runs when the arm enters the blend
into it, h = r / v before the waypoint (v the move's speed), or at the waypoint where there is no blend,
or after a bridge's joint move. It sends the ring's drive the ring's axes as they must be when the next
line runs (the piecewise-linear axes of the program at that time) and the time until then; the drive
moves linearly to them in that time. So the ring is on the program's schedule at every line; between
two lines it runs the chord across the waypoint's corner, at most |w2 - w1| h off the schedule there
(w1, w2 its turn rates before and after), which moves the eye by E3 |w2 - w1| h (radians): the radius
keeps that within RING_SHARE of the tolerance.
"""

from __future__ import annotations

import numpy as np

CYCLE_S = 0.002  # s: the UR e-Series controller's cycle (500 Hz); no move is shorter
BLEND_FRACTION = 0.1  # of the shorter of the two moves a blend joins
BLEND_SHARE = 0.3  # of the chord tolerance the arm's blend may add
RING_SHARE = 0.3  # of the chord tolerance the ring's chord across a waypoint may add


def _rotvecs(r: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation  # noqa: PLC0415 - slow to import

    return Rotation.from_matrix(r).as_rotvec()


def blend_radii(poses: np.ndarray, lever: np.ndarray, tol: float, stops: np.ndarray, ring: np.ndarray | None,
                move_s: np.ndarray) -> np.ndarray:
    """(k,) blend radii (mm) at the waypoints of the TCP poses (k, 4, 4) (module docstring); lever (k,)
    mm; stops (k,) bool the waypoints without a blend (besides the first and the last); ring (k, 3)
    the ring's axes (None: the arm's bound alone); move_s (k,) the moves' times (move_s[0] none)."""
    k = poses.shape[0]
    out = np.zeros(k)
    if k < 3:
        return out
    dp = np.diff(poses[:, :3, 3], axis=0)  # (k - 1, 3)
    turn = _rotvecs(np.einsum("kij,klj->kil", poses[1:, :3, :3], poses[:-1, :3, :3]))  # R1 R0^T, base frame
    six = np.column_stack([dp, lever[1:, None] * turn])
    length = np.linalg.norm(dp, axis=1)
    norm6 = np.linalg.norm(six, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(length > 0.0, norm6 / length, np.inf)
        u = six / np.where(norm6 > 0.0, norm6, 1.0)[:, None]
        cos = np.einsum("ij,ij->i", u[:-1], u[1:])
        sin = np.where(cos > 0.0, np.sqrt(np.clip(1.0 - cos * cos, 0.0, 1.0)), 1.0)
        dev = BLEND_SHARE * tol / (np.maximum(ratio[:-1], ratio[1:]) * sin)
    inner = np.minimum(np.minimum(BLEND_FRACTION * length[:-1], BLEND_FRACTION * length[1:]), dev)
    if ring is not None:  # h = r t / length before the waypoint; the eye's arc off by E3 |w2 - w1| h
        rate = np.radians(np.diff(ring[:, 0])) / np.maximum(move_s[1:], CYCLE_S)
        with np.errstate(divide="ignore", invalid="ignore"):
            ring_r = RING_SHARE * tol * length[:-1] / (move_s[1:-1] * ring[1:-1, 2] * np.abs(np.diff(rate)))
        inner = np.minimum(inner, np.where(np.isnan(ring_r), np.inf, ring_r))
    out[1:-1] = np.where(np.isfinite(inner), inner, 0.0)
    out[stops] = 0.0
    return out


def line_times(move_s: np.ndarray, radii: np.ndarray, poses: np.ndarray, pause_s: np.ndarray) -> tuple:
    """(T (k,) the arrival at each waypoint, S (k,) when the line of the move to each waypoint runs;
    S[0] = 0) of move times (k,) (move_s[0]: none), blend radii (k,) mm, the TCP poses (k, 4, 4) and
    the pause after each waypoint (k,) s (a bridge's joint move)."""
    arrive = np.cumsum(move_s + np.concatenate([[0.0], pause_s[:-1]]))
    length = np.concatenate([[0.0], np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1)])
    with np.errstate(divide="ignore", invalid="ignore"):
        lead = np.where(radii > 0.0, radii * move_s / np.where(length > 0.0, length, 1.0), 0.0)
    starts = np.concatenate([[0.0], arrive[:-1] + pause_s[:-1] - lead[:-1]])
    return arrive, starts


def schedule(arrive: np.ndarray, external: np.ndarray, pause_s: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The ring's axes (n, 3) at times at (n,) on the program's schedule: linear between waypoints
    (arrive (k,), external (k, 3)), held through each pause (k,) after a waypoint."""
    held = np.flatnonzero(pause_s > 0.0)
    knots = np.concatenate([arrive, arrive[held] + pause_s[held]])
    values = np.vstack([external, external[held]])
    order = np.argsort(knots, kind="stable")
    return np.column_stack([np.interp(at, knots[order], values[order, c]) for c in range(3)])


def ring_targets(arrive: np.ndarray, external: np.ndarray, starts: np.ndarray,
                 pause_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(targets (k, 3), durations (k,)) each line before the move to waypoint j (j >= 1) sends: the
    ring's axes on the program's schedule (arrive (k,), external (k, 3), pause_s (k,)) at the next
    line's time (the end for the last), and the time until then."""
    until = np.concatenate([starts[2:], arrive[-1:]]) if starts.size > 1 else arrive[-1:]
    targets = schedule(arrive, external, pause_s, until)
    return np.vstack([external[:1], targets]), np.concatenate([[0.0], until - starts[1:]])
