"""The clearance of the programmed moves by construction (docs/math/13-clearance-chords.md): how far
each straight move between consecutive rows of a pass cuts into the eye's clearance, and how many
points each planned interval needs so that the dense polyline cuts at most winder.machine.densify's
DENSE_SHARE of the chord tolerance (the point reduction and the rounding take the rest, winder.machine.program).

On a straight-axis winder the eye's distance from the part depends on the carriage X and the
cross-feed Z only, both linear along a move: a move's eye runs along the segment between its ends in
the (X, Z) half-plane, measured here against the part (winder.machine.collision.part_distance) at
CUT_SAMPLES + 1 points. Moves with both ends on or outside the envelope and no bend of the envelope
table over their X range have no cut (13.1) and are not measured: on a vessel only those near the domes.
"""

from __future__ import annotations

import numpy as np

from winder.machine.collision import sampled_moves
from winder.machine.dilation import turn
from winder.machine.envelope import EyeEnvelope

CUT_SAMPLES = 16  # pieces a measured move is sampled in (ends included)
CUT_BLOCK = 1 << 15  # moves measured at once (memory stays bounded)
ON_ENVELOPE = 1e-6  # mm: an eye this little inside the envelope counts as on it (the lead's round-off)
BENT = 1e-11  # mm: an envelope vertex this far off its neighbours' chord bends the table there
CLEAR_ROUNDS = 4  # times the dense polyline is measured again and cut finer (13.3)
CLEAR_MAX_FACTOR = 1024  # pieces per planned interval, at most, for the clearance


def _bends(env: EyeEnvelope) -> np.ndarray:
    """The stations where the envelope table bends (sorted), its two ends included (the table goes on
    with its end slopes past them)."""
    x = env.stations if env.radius_stations is None else env.radius_stations
    z = env.radius
    i = np.arange(x.size)
    cross = np.abs(turn(x, z, i[:-2], i[1:-1], i[2:]))
    bent = cross > BENT * np.hypot(x[2:] - x[:-2], z[2:] - z[:-2])
    return np.concatenate([x[:1], x[1:-1][bent], x[-1:]])


def _move_firsts(sizes: np.ndarray, rows: int) -> np.ndarray:
    """The first row of each move (sum(sizes - 1),) of runs of sizes (k,) rows stored one after the
    other, rows in all."""
    last = np.cumsum(sizes) - 1
    inner = np.ones(rows, dtype=bool)
    inner[last[sizes > 0]] = False
    return np.flatnonzero(inner)


def move_cuts(x: np.ndarray, z: np.ndarray, sizes: np.ndarray, env: EyeEnvelope) -> np.ndarray:
    """The cut (mm, >= 0) of each move between consecutive rows of each run: (sum(sizes - 1),) for
    runs of sizes (k,) rows stored one after the other in x (carriage) and z (cross-feed), (m,) each.
    Zero everywhere in radius mode (`eye: {radius}`: no clearance to keep)."""
    x, z = np.asarray(x, dtype=float), np.asarray(z, dtype=float)
    first = _move_firsts(np.asarray(sizes, dtype=np.int64), x.size)
    cuts = np.zeros(first.size)
    if env.clearance is None or first.size == 0:
        return cuts
    on = z >= env.at(x) - ON_ENVELOPE
    lo, hi = np.minimum(x[first], x[first + 1]), np.maximum(x[first], x[first + 1])
    bends = _bends(env)
    straight = np.searchsorted(bends, hi, side="left") <= np.searchsorted(bends, lo, side="right")
    todo = np.flatnonzero(~(on[first] & on[first + 1] & straight))
    f = np.linspace(0.0, 1.0, CUT_SAMPLES + 1)
    c = float(env.clearance)
    for chunk in np.array_split(todo, max(1, -(-todo.size // CUT_BLOCK))):
        if chunk.size == 0:
            continue
        a = first[chunk]
        dist = sampled_moves(x[a], z[a], x[a + 1], z[a + 1], f, env)
        cuts[chunk] = np.maximum(c - dist.min(axis=1), 0.0)
    return cuts


def pieces(errors: np.ndarray, share: float, most: int) -> np.ndarray:
    """(k,) int: the pieces each planned interval whose chord errs by `errors` (k,) (its bow off the
    eye's path, or its cut into the clearance) is cut in so that each piece errs by about `share` at
    most, at most `most`: a smooth curve's error falls as 1 / K^2 in K pieces (13.3; 1 where the
    error is within share or not finite)."""
    errors = np.asarray(errors, dtype=float)
    out = np.ones(errors.size, dtype=np.int64)
    big = np.isfinite(errors) & (errors > share)
    out[big] = np.minimum(most, np.ceil(np.sqrt(errors[big] / share))).astype(np.int64)
    return out


def refine(x: np.ndarray, z: np.ndarray, sizes: np.ndarray, u: np.ndarray, planned: np.ndarray,
           env: EyeEnvelope, share: float, least: list | None) -> tuple[list | None, np.ndarray]:
    """Measure the dense polyline of every pass (rows x, z, u (m,) in runs of sizes (k,); u each row's
    fractional planned point index, planned (k,) each pass's planned points) and say where it needs more
    points: (least, worst). least : per pass None or (planned - 1,) int, the pieces each planned
    interval must be cut in at least (the given least raised where a move still cuts more than
    share (mm; densify.DENSE_SHARE of the chord tolerance), 13.3), or None where no move does (or
    none can be cut finer). worst : (k,) each pass's largest cut (mm)."""
    sizes = np.asarray(sizes, dtype=np.int64)
    cuts = move_cuts(x, z, sizes, env)
    moves = np.maximum(sizes - 1, 0)
    owner = np.repeat(np.arange(sizes.size), moves)
    worst = np.zeros(sizes.size)
    np.maximum.at(worst, owner, cuts)
    bad = np.flatnonzero(cuts > share)
    if bad.size == 0:
        return None, worst
    row = _move_firsts(sizes, u.size)[bad]
    step = u[row + 1] - u[row]
    interval = np.floor(u[row]).astype(np.int64)
    now = np.maximum(np.rint(1.0 / step), 1.0)
    want = np.minimum(CLEAR_MAX_FACTOR, np.maximum(2.0 * now, np.ceil(now * cuts[bad] / share)))
    out = [None if least is None else least[k] for k in range(sizes.size)]
    grew = False
    for k in np.unique(owner[bad]).tolist():  # per pass that still cuts in (few), not per point
        mine = owner[bad] == k
        floor = np.ones(int(planned[k]) - 1, dtype=np.int64) if out[k] is None else out[k].copy()
        before = floor.copy()
        np.maximum.at(floor, interval[mine], want[mine].astype(np.int64))
        grew |= bool(np.any(floor > before))
        out[k] = floor
    return (out if grew else None), worst
