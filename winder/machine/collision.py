"""The payout eye never comes closer to the part than its clearance, along every move (not only at
the programmed points): the controller moves the axes linearly between two points, so each move is
sampled at SAMPLES_PER_MOVE points and the eye's centre (forward kinematics: mandrel-frame
(Z cos(-A), Z sin(-A), X)) measured against the mandrel.

The part is taken as the solid of revolution of the largest section radius r_max(t) over
0 <= t <= T (for a circular section exactly the mandrel; otherwise a conservative hull), its ends
closed: the distance of a point (rho, z) is that to the meridian polyline (r_max(t), t) and to the end
discs. Required: distance - size / 2 >= clearance - chord_tolerance with `eye: {clearance}` (the
envelope puts the body exactly at the clearance; the programmed chords may cut in by the
tolerance), distance - size / 2 > 0 with `eye: {radius}`.
"""

from __future__ import annotations

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.envelope import EyeEnvelope

SAMPLES_PER_MOVE = 8


def part_distance(rho: np.ndarray, z: np.ndarray, env: EyeEnvelope) -> np.ndarray:
    """Distance (mm) of meridian points (rho, z) from the part (module docstring); < 0 inside."""
    t, r = env.stations, env.mandrel_radius
    from scipy.spatial import cKDTree  # noqa: PLC0415 - scipy.spatial is slow to import

    tree = cKDTree(np.column_stack([t, r]))
    q = np.column_stack([z, rho])
    _, k = tree.query(q)
    best = np.full(q.shape[0], np.inf)
    for j in (k - 1, k):  # the two segments around the nearest vertex
        j = np.clip(j, 0, t.size - 2)
        a = np.column_stack([t[j], r[j]])
        seg = np.column_stack([t[j + 1], r[j + 1]]) - a
        u = np.clip(np.einsum("ij,ij->i", q - a, seg) / np.einsum("ij,ij->i", seg, seg), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(q - a - u[:, None] * seg, axis=1))
    # End discs: a point beyond an end within the end radius is that far from the disc.
    for end, radius in ((t[0], r[0]), (t[-1], r[-1])):
        beyond = (z - end) * (1.0 if end == t[-1] else -1.0)
        on_disc = (beyond > 0.0) & (rho <= radius)
        best = np.where(on_disc, np.minimum(best, beyond), best)
    inside = (z >= t[0]) & (z <= t[-1]) & (rho < np.interp(z, t, r))
    return np.where(inside, -best, best)


def check_collision(values: np.ndarray, env: EyeEnvelope, machine: MachineConfig, where) -> None:
    """Refuse a program (rows (m, 4): carriage, rotation, cross_feed, yaw) whose eye comes too close
    to the part anywhere along a move; where(row) names the move's pass."""
    if values.shape[0] == 0:
        return
    f = np.linspace(0.0, 1.0, SAMPLES_PER_MOVE + 1)[1:]
    start = np.vstack([values[:1], values[:-1]])
    x = start[:, None, 0] + f * (values[:, None, 0] - start[:, None, 0])
    z = start[:, None, 2] + f * (values[:, None, 2] - start[:, None, 2])
    gap = part_distance(np.abs(z).ravel(), x.ravel(), env).reshape(x.shape) - 0.5 * machine.eye_size
    # env.clearance holds the centre's distance, c + size / 2: the body must keep c, less the chords' cut.
    need = 0.0 if env.clearance is None else env.clearance - 0.5 * machine.eye_size - machine.chord_tolerance
    worst = np.min(gap, axis=1)
    bad = np.flatnonzero(worst < need - 1e-9)
    if bad.size:
        row = int(bad[np.argmin(worst[bad])])
        raise ExportError(f"{where(row)}: the payout eye (size {machine.eye_size:g} mm) comes within "
                          f"{worst[row]:.3f} mm of the mandrel on the move to X{values[row, 0]:.3f} "
                          f"A{values[row, 1]:.3f}, closer than {max(need, 0.0):.3f} mm")
