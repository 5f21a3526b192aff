"""A job's peak memory, estimated from its work budget before any path (docs/math/14-work-estimates.md 14.2).

Vessel: the interpreter, bytes per planned point, per helical pass (the program's rows and the dense
turnarounds the machine stage holds per pass), per mm of the vessel (larger domes, larger turnarounds)
and the largest Newton solve. Open mandrel: per planned point and per point of the largest solve (the
solve and the machine stage's arrays of a pass both follow the points of a pass). Robot on an open axis:
per planned point (poses, the whole plan in one batch). Where the machine stage takes the whole plan in
one batch (a robot, rotation or yaw limits), the dense points of every layer beyond its largest group's;
otherwise those of the next largest groups, which the machine stage's other workers build at the same time.
Coefficients fitted on the parts of parts/ and the hostile budget vessels (the measured peak: docs/math/14
14.2), scaled to hold every measured peak from above (h2_tank's but by up to 6 %: its budget counts a
fifth fewer points than it plans).
"""

from __future__ import annotations

from collections.abc import Sequence

from winder.winding.layer_batches import point_groups

__all__ = ["BASE_BYTES", "MACHINE_WORKERS", "PROGRAM_CHUNK_POINTS", "SOLVER_BYTES_PER_POINT", "peak_bytes",
           "solve_bytes_per_point"]

BASE_BYTES = 90_000_000  # the interpreter with numpy and scipy: 84 MiB before any work
SOLVER_BYTES_PER_POINT = 2_500  # the Newton solve of a pass
VESSEL_BYTES_PER_POINT = 640
VESSEL_BYTES_PER_PASS = 104_000  # per helical pass (2 per circuit)
VESSEL_BYTES_PER_MM = 83_000  # of the vessel's axial length
OPEN_BYTES_PER_POINT = 100  # per point of the budget, which counts the most the planner may lay
OPEN_BYTES_PER_SOLVE_POINT = 7_200  # the solve and the machine stage's arrays of a pass
ROBOT_BYTES_PER_POINT = 1_510
DENSE_POINTS_PER_PASS = 650  # dense points of a helical pass's two turnarounds beyond the planned ones
DENSE_BYTES = 450  # per dense point of a batch (vessels built whole: 450 to 500 measured)
# per dense point of the groups another worker holds beside the largest: 160 to 240 B measured on the
# vessel parts (h2_tank 470: its budget counts a fifth fewer points than it plans). Whether the two
# workers' peaks meet is a matter of timing (type4_tank: 296 to 328 MiB from run to run), so 300 B:
# every estimate within 1.5x of every measured peak, h2_tank's 6 % below it at worst. Counted wherever
# the groups are several, also where one process builds them (a batch's job, one core): on the safe side
WORKER_DENSE_BYTES = 300
OPEN_BATCH_BYTES_PER_POINT = 600  # per planned point of an open plan built whole, beyond one group
PROGRAM_CHUNK_POINTS = 16_000  # planned points of the layers the machine stage takes in one batch
MACHINE_WORKERS = 2  # processes building the machine stage's groups at once (winder.app.machine_pool)


def solve_bytes_per_point(vessel: bool, robot: bool) -> int:
    """The estimate's bytes per point of the largest solve (peak_bytes)."""
    return SOLVER_BYTES_PER_POINT if vessel or robot else OPEN_BYTES_PER_SOLVE_POINT


def _dense(points: Sequence[int], passes: Sequence[int], layers) -> int:
    return sum(points[i] + DENSE_POINTS_PER_PASS * passes[i] for i in layers)


def peak_bytes(points: Sequence[int], passes: Sequence[int], solve: int, length: float, *, vessel: bool,
               robot: bool, whole: bool) -> int:
    """The estimated peak memory (bytes) of a job.

    Parameters
    ----------
    points : (k,) planned points of each layer (the work budget's).
    passes : (k,) helical passes of each layer (0 for a hoop).
    solve : points of the largest single solve.
    length : the mandrel's axial length (mm); the vessel model's.
    vessel, robot : the mandrel is a vessel; the program is a robot's (poses).
    whole : the machine stage takes the whole plan in one batch (a robot, rotation or yaw limits).
    """
    total = sum(points)
    base = BASE_BYTES + solve_bytes_per_point(vessel, robot) * solve
    groups = point_groups(points, PROGRAM_CHUNK_POINTS)
    if vessel:
        dense = sorted((_dense(points, passes, g) for g in groups), reverse=True)
        if whole and groups:
            extra = DENSE_BYTES * (_dense(points, passes, range(len(points))) - dense[0])
        else:  # the groups after the largest that other workers hold at the same time
            extra = WORKER_DENSE_BYTES * sum(dense[1:MACHINE_WORKERS])
        return int(base + VESSEL_BYTES_PER_POINT * total + VESSEL_BYTES_PER_PASS * sum(passes)
                   + VESSEL_BYTES_PER_MM * length + extra)
    if robot:
        return int(base + ROBOT_BYTES_PER_POINT * total)
    sizes = sorted((sum(points[i] for i in g) for g in groups), reverse=True)
    if whole and groups:
        extra = OPEN_BATCH_BYTES_PER_POINT * (total - sizes[0])
    else:
        extra = OPEN_BATCH_BYTES_PER_POINT * sum(sizes[1:MACHINE_WORKERS])
    return int(base + OPEN_BYTES_PER_POINT * total + extra)
