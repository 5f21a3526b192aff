"""`winder simulate CONFIG PROGRAM`: what a winding program lays, read back from its text.

The program (any dialect winder writes, winder.readback.gcode) gives the eye at every
programmed point through the forward kinematics (docs/guide/conventions.md: with the mandrel turned by A the eye is
at mandrel-frame (Z cos(-A), Z sin(-A), X); robot poses: the position). The free fiber runs from the
eye to its contact point along the fiber's tangent there, so the contact point of an eye E is the
point p(u) of the planned pass whose tangent ray p + lambda d, lambda > 0, passes closest to E;
the samples of a pass are matched together, their contacts moving forward along it
(winder.readback.contacts: on a flat face one tangent line fits a whole stretch of points; a long pass, a
hoop of many turns, within a band along it: winder.readback.contact_bands). The pass is
the fiber the plan's points stand for: between two planned points of a geodesic the geodesic ODE
from the first (winder.readback.exact_paths, scipy's solve_ivp, independent of the program writer's
integration), elsewhere the smooth path through them (a cubic spline in (s, theta) over the point
index, docs/math/02-energy.md; in (s, f), f the perimeter fraction, on a non-circular section: docs/math/12 12.2). Its
distance from that ray is the deviation: an eye off every tangent line of the planned path by e
lays the fiber e off the planned path (to first order, the laid path follows the eye sideways).
Samples: every programmed point and the midpoint of every move within a pass (the eye the
controller interpolates in axis space), also of a move into a pass that continues where the last one
ended (its first row, the same move as the last pass's final one, is not written twice). Moves to a
pass that starts elsewhere (the way to a new layer, and its `approach` rows around the part) are
counted, not sampled: no planned tangent describes them (their deviation is written as nan).

The laid fiber's length is the arc length of the planned path between consecutive contact points;
the time comes from machine.dynamics (winder.machine.dynamics) over the program's rows.
"""

from __future__ import annotations

import dataclasses
import io

import numpy as np

from winder.readback.contact_bands import TableTooLarge, contact_points
from winder.readback.contacts import candidates, forward, ray_distance, refine, repair, widen_ends
from winder.readback.contact_windows import far_ties, unpin
from winder.readback.exact_paths import ExactPaths
from winder.config.machine import MachineConfig
from winder.errors import ConfigError
from winder.readback.gcode import ParsedProgram, parse_program
from winder.readback.parsed import layer_tensions
from winder.readback.program_file import ProgramFile
from winder.geometry.surface import SweepSurface
from winder.machine.collision import move_distances
from winder.machine.envelope import EyeEnvelope, eye_envelope
from winder.machine.kinematics import make_guide
from winder.machine.dynamics import move_times
from winder.machine.program import APPROACH
from winder.winding.results import WindingPlan, winding_angle_deg

# The largest program the work budget allows, 1.5 million points of about 60 bytes (a move of
# samples/pipe.yaml's program takes 62), is 90 MB; a larger file is no program winder wrote.
MAX_PROGRAM_BYTES = 256_000_000
INSIDE_TOL = 1e-6  # of the mandrel's radius: an eye centre this far inside the part is inside it
# simulate's own budget (issue 34), held before the work: a program of the job has about one move per
# planned point (the machine program adds turnaround and approach rows, and densifies long chords), so
# a program of many more moves is another job's, or no program of winder's.
MOVES_PER_POINT = 16
MOVES_SLACK = 10_000
# The contact search's table (winder.readback.contact_bands): a pass's samples times the candidates each is
# matched against (a long pass: a band along it), 4 bytes each; past this the program is refused, not allocated.
MAX_TABLE_ENTRIES = 100_000_000



@dataclasses.dataclass(frozen=True)
class Simulation:
    """What a program lays.

    moves : programmed points. transitions : moves between passes (not sampled).
    time_s : machine time from the dynamics. fiber_length_mm : laid along the contact points.
    max_deviation_mm : largest distance of an eye (programmed point or move midpoint) from the planned
        tangent line at its contact point. max_point_deviation_mm : the same over programmed points.
    samples : per sample (n,) arrays: layer, circuit, pass, i (row), kind, t, theta_deg, xyz (n, 3),
        alpha_deg, eye (n, 3), deviation_mm, mid (bool: a move midpoint).
    """

    dialect: str
    moves: int
    transitions: int
    time_s: float
    fiber_length_mm: float
    planned_fiber_length_mm: float
    max_deviation_mm: float
    max_point_deviation_mm: float
    samples: dict
    tensions: tuple = ()  # per layer the tension read back (winder.readback.parsed.layer_tensions)

    def summary(self) -> dict:
        return {"dialect": self.dialect, "moves": self.moves, "transitions": self.transitions,
                "time_s": round(self.time_s, 2), "fiber_length_mm": round(self.fiber_length_mm, 3),
                "planned_fiber_length_mm": round(self.planned_fiber_length_mm, 3),
                "max_deviation_mm": round(self.max_deviation_mm, 6),
                "max_point_deviation_mm": round(self.max_point_deviation_mm, 6),
                **({"layers": list(self.tensions)} if self.tensions else {})}


def eye_positions(parsed: ParsedProgram) -> np.ndarray:
    """The eye in the mandrel frame for each row (docs/guide/conventions.md forward kinematics; robot: the position)."""
    v = parsed.values
    if parsed.robot:
        return v[:, :3].copy()
    a = np.radians(v[:, 1])
    return np.column_stack([v[:, 2] * np.cos(-a), v[:, 2] * np.sin(-a), v[:, 0]])


def _refuse_entering(parsed: ParsedProgram, env: EyeEnvelope, surface: SweepSurface, source: str) -> None:
    """Refuse a program whose eye centre enters the mandrel along a move: a collision machine.limits
    need not show. The moves are measured as the program writer measures them (machine.collision)."""
    guide = make_guide(surface, env) if parsed.robot else None
    dist, frac = move_distances(parsed.values, env, guide)
    row = int(np.argmin(dist)) if dist.size else 0
    if not dist.size or dist[row] >= -INSIDE_TOL * env.max_radius:
        return
    where = ("" if frac[row] == 1.0 else " halfway along the move to" if frac[row] == 0.5
             else f" {frac[row]:g} of the way along the move to")
    at = parsed.values[row - 1] + frac[row] * (parsed.values[row] - parsed.values[row - 1])
    v = parsed.values[row]
    if guide is not None:
        station, got = float(guide.project(at[None, :3])[0][0]), f"pose X{v[0]:g} Y{v[1]:g} Z{v[2]:g}"
    else:
        station, got = float(at[0]), f"cross-feed {v[2]:g}"
    raise ConfigError(f"{source}: line {parsed.line[row]}: the eye enters the mandrel{where} this point, "
                      f"{-dist[row]:.3f} mm inside its surface at t = {station:.3f} mm, got {got}")


def _refuse_large_table(exc: TableTooLarge, parsed: ParsedProgram, source: str) -> ConfigError:
    """The refusal of a layer whose contact search would allocate a table past MAX_TABLE_ENTRIES: a pass
    whose samples keep their contacts within no narrow band along it (winder.readback.contact_bands)."""
    return ConfigError(f"{source}: a pass read from {exc.samples:,} samples, each against a band of up to "
                       f"{exc.points:,} points of its plan, would need a table of {exc.entries:,} entries, more "
                       f"than simulate's limit of {MAX_TABLE_ENTRIES:,}: its moves do not follow this job's "
                       f"passes, the program is not this job's ({parsed.values.shape[0]:,} moves)")


def simulate(machine: MachineConfig, plan: WindingPlan, text: str | ProgramFile,
             source: str = "program") -> Simulation:
    """Read the program (its text, or its file, read line by line) written for a job planned as `plan`
    on `machine` and reconstruct what it lays (module docstring)."""
    by_key = {(fp.layer, fp.circuit, fp.number): fp for layer in plan.layers for fp in layer.passes}
    planned_points = sum(len(fp.points) for fp in by_key.values())
    parsed = parse_program(text, machine, source, max_moves=MOVES_PER_POINT * planned_points + MOVES_SLACK)
    order = {key: j for j, key in enumerate(by_key)}
    passes = list(by_key.values())
    m = parsed.values.shape[0]
    other = parsed.job is not None and (parsed.job.upper() != plan.name.upper() if parsed.case_blind
                                        else parsed.job != plan.name)
    unknown = next((r for r, k in enumerate(parsed.keys) if tuple(k) not in order), None)
    if unknown is not None:
        layer, circuit, number = (int(v) for v in parsed.keys[unknown])
        named = f" ({parsed.job!r}, by its job line; this config plans {plan.name!r})" if other else ""
        raise ConfigError(f"{source}: line {parsed.line[unknown]}: layer {layer} circuit {circuit} pass {number} "
                          f"is not in the plan of {plan.source}: the program was written for another job{named}")
    if other:  # its passes fit this plan's, but its job line names another job
        raise ConfigError(f"{source}: line {parsed.job_line}: the program was written for another job: its job "
                          f"line names {parsed.job!r}, this config ({plan.source}) plans {plan.name!r}")
    eye = eye_positions(parsed)
    final_key = tuple(by_key)[-1] if by_key else None
    pass_of = np.array([order[tuple(k)] for k in parsed.keys])
    # The approach to a pass that starts elsewhere lays no planned fiber: counted, not sampled.
    laying = np.array([kind != APPROACH for kind in parsed.kinds], dtype=bool)
    same = np.concatenate([[False], (pass_of[1:] == pass_of[:-1]) & laying[1:] & laying[:-1]])
    # A pass that starts where the last one ended has its first row dropped (the same move): the move
    # from the last pass's final row lays the new pass from its first point on.
    starts = np.flatnonzero(~same & laying)[1:]
    starts = starts[laying[starts - 1]]
    first_p = np.array([passes[j].points[0] if len(passes[j].points) else np.zeros(3) for j in pass_of[starts]])
    first_d = np.array([passes[j].direction[0] if len(passes[j].points) else np.zeros(3) for j in pass_of[starts]])
    joined = np.zeros(m, dtype=bool)
    if starts.size:
        # Within the chord tolerance (the printed values round the eye by up to ~1e-3 mm).
        near = ray_distance(eye[starts - 1], first_p.reshape(-1, 3), first_d.reshape(-1, 3))
        joined[starts] = near <= machine.chord_tolerance
    mid_rows = np.flatnonzero(same | joined)
    # Samples: the rows, then the midpoints of the moves within a pass.
    mid_values = 0.5 * (parsed.values[mid_rows - 1] + parsed.values[mid_rows])
    mid_eye = (parsed.mids[mid_rows] if parsed.mids is not None else  # a robot cell's eye moves on the ring
               eye_positions(ParsedProgram(parsed.dialect, mid_values, parsed.keys[mid_rows], (), np.zeros(0))))
    all_eye = np.vstack([eye, mid_eye])
    _refuse_entering(parsed, eye_envelope(plan.surface, machine), plan.surface, source)
    all_pass = np.concatenate([pass_of, pass_of[mid_rows]])
    # The samples of each pass in the order the machine lays them (a move's midpoint between its rows):
    # their contacts move forward along the pass together (winder.readback.contacts).
    chain = np.cumsum(~same)
    chain = np.concatenate([chain, chain[mid_rows]])
    position = np.concatenate([2 * np.arange(m), 2 * mid_rows - 1])
    n = all_eye.shape[0]
    s, th, t = np.zeros(n), np.zeros(n), np.zeros(n)
    p, d, alpha, arc = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n), np.zeros(n)
    short = 0.0
    arc0, arc1 = np.zeros(n), np.zeros(n)  # the arc at the first and the last point of the sample's pass
    layer_of = np.array([fp.layer for fp in passes])
    for layer in np.unique(layer_of[all_pass]):
        # Each layer's paths lie on the surface it was wound on (the mandrel grown by the layers below).
        surface = plan.surface_of(int(layer))
        mine = np.flatnonzero(layer_of[all_pass] == layer)
        local = np.flatnonzero(layer_of == layer)
        paths = ExactPaths(surface, [passes[j] for j in local])
        where = np.searchsorted(local, all_pass[mine])
        first, last = paths.offset[where], paths.last[where]
        cand = candidates(paths)
        cu, cp, cd, cstart = cand
        try:
            pick = contact_points(all_eye[mine], chain[mine], position[mine], where, cp, cd, cstart,
                                  machine.chord_tolerance, MAX_TABLE_ENTRIES)
        except TableTooLarge as exc:
            raise _refuse_large_table(exc, parsed, source) from None
        # From the candidate before the one picked to the end of the segment after its own (the dynamic
        # program scores the segment from each candidate to the next, its offsets taken linear between
        # them: parts/tank_20.yaml near a polar opening picked u = 78 where the ray that fits lies at
        # 78.64, past the next candidate, 78.5, which read 0.018 mm off), within the pass.
        lo = cu[np.maximum(pick - 1, cstart[where])]
        hi = cu[np.minimum(pick + 2, cstart[where + 1] - 1)]
        u = forward(refine(paths, all_eye[mine], lo, cu[pick], hi), chain[mine], position[mine])
        # A move's midpoint may bow off the tangents by up to the chord tolerance; more is searched again.
        u = repair(paths, all_eye[mine], u, chain[mine], position[mine], machine.chord_tolerance)
        u = unpin(paths, all_eye[mine], u, chain[mine], position[mine], machine.chord_tolerance)
        u = widen_ends(paths, all_eye[mine], u, chain[mine], position[mine], where, cand)
        u = far_ties(paths, all_eye[mine], u, chain[mine], position[mine], cand)
        s[mine], th[mine], p[mine], d[mine] = paths.point(u)
        toward = all_eye[mine] - p[mine]
        toward /= np.maximum(np.linalg.norm(toward, axis=1), 1e-300)[:, None]
        alpha[mine] = winding_angle_deg(surface, s[mine], th[mine], toward)
        t[mine] = surface.t_of_s(s[mine])
        arc[mine] = paths.arc_at(u)
        if m - 1 in mine:  # the program's last row: how many planned points short of its pass's end
            short = float((last - u)[np.searchsorted(mine, m - 1)])
        arc0[mine], arc1[mine] = paths.arc[first], paths.arc[last]
    if tuple(parsed.keys[-1]) != final_key or short > 1.0:
        # The program must lay the plan to its end: a file cut short (marlin writes no end of its own).
        line = int(parsed.line[-1]) if parsed.line is not None else m
        # A complete program of another config that plans more passes ends here too: say both.
        raise ConfigError(f"{source}: line {line}: the program stops before the end of the plan of {plan.source} "
                          f"(layer {final_key[0]} circuit {final_key[1]} pass {final_key[2]}): cut short, or "
                          f"written for another config? got its last "
                          f"move in layer {parsed.keys[-1][0]} circuit {parsed.keys[-1][1]} pass {parsed.keys[-1][2]}"
                          f"{f', {short:.1f} points before its end' if short > 1.0 else ''}")
    dev = ray_distance(all_eye, p, d)
    dev = np.where(np.concatenate([laying, laying[mid_rows]]), dev, np.nan)  # approach rows lay nothing
    arc, arc0, arc1 = arc[:m], arc0[:m], arc1[:m]
    fiber = np.where(same, np.abs(np.diff(arc, prepend=arc[0])), 0.0)
    # A joined move lays the rest of the last pass and the new one up to its contact point.
    rest = np.concatenate([[0.0], np.abs(arc1[:-1] - arc[:-1])])
    fiber = np.where(joined, rest + np.abs(arc - arc0), fiber)
    times = move_times(parsed.values[:, :3] if parsed.robot else parsed.values, fiber, machine,
                       parsed.robot)
    keys = np.vstack([parsed.keys, parsed.keys[mid_rows]])
    rows_i = np.concatenate([np.arange(m), mid_rows])
    kinds = list(parsed.kinds) + [parsed.kinds[r] for r in mid_rows]
    samples = {"layer": keys[:, 0], "circuit": keys[:, 1], "pass": keys[:, 2], "i": rows_i, "kind": kinds,
               "t": t, "theta_deg": np.degrees(th), "xyz": p, "alpha_deg": alpha,
               "eye": all_eye, "deviation_mm": dev, "mid": np.arange(n) >= m}
    return Simulation(dialect=parsed.dialect, moves=m, transitions=int(m - 1 - mid_rows.size),
                      time_s=float(np.sum(parsed.move_s)) if parsed.move_s is not None else times.total_s,
                      fiber_length_mm=float(np.sum(fiber)),
                      planned_fiber_length_mm=plan.total_fiber_length_mm,
                      max_deviation_mm=float(np.nanmax(dev)), max_point_deviation_mm=float(np.nanmax(dev[:m])),
                      samples=samples, tensions=layer_tensions(parsed))


def simulation_csv(sim: Simulation) -> str:
    """The laid path as a job CSV (the `run` columns, then kind, sample, eye_x/y/z, deviation_mm)."""
    sm = sim.samples
    order = np.lexsort((sm["mid"], sm["i"]))
    buf = io.StringIO()
    buf.write("layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg,kind,sample,eye_x,eye_y,eye_z,deviation_mm\n")
    for k in order:
        x, y, z = sm["xyz"][k]
        ex, ey, ez = sm["eye"][k]
        buf.write(f"{sm['layer'][k]},{sm['circuit'][k]},{sm['pass'][k]},{sm['i'][k]},{sm['t'][k]:.6f},"
                  f"{sm['theta_deg'][k]:.6f},{x:.6f},{y:.6f},{z:.6f},{sm['alpha_deg'][k]:.6f},{sm['kind'][k]},"
                  f"{'mid' if sm['mid'][k] else 'move'},{ex:.6f},{ey:.6f},{ez:.6f},{sm['deviation_mm'][k]:.6f}\n")
    return buf.getvalue()


def simulate_files(config: str, program: str, output: str | None = None, as_json: bool = False,
                   seconds: float | None = None) -> str:
    """`winder simulate`: plan CONFIG, read PROGRAM, write the laid path CSV to `output` (if given);
    the text to show (one JSON object with as_json, else one line)."""
    import json  # noqa: PLC0415

    from winder.app.wall_clock import TimeUp, time_limit  # noqa: PLC0415
    from winder.app.validate import validate_job  # noqa: PLC0415
    from winder.config.job import load_config  # noqa: PLC0415
    from winder.errors import SolverError  # noqa: PLC0415
    from winder.export.atomic import check_output_file, write_atomic  # noqa: PLC0415
    from winder.export.paths import shown  # noqa: PLC0415
    from winder.progress import doing  # noqa: PLC0415
    from winder.winding.plan import plan as plan_job  # noqa: PLC0415

    if output is not None:
        check_output_file(output, {"CONFIG": config, "PROGRAM": program})
    job = load_config(config)
    # Checked before planning (a program that is not a file, /dev/zero, a FIFO, is refused at once), read
    # line by line after it, within the plan's move budget. One edited on another system may carry
    # other bytes in its comments (a Latin-1 accent, a byte-order mark): the codes are ASCII, so such
    # bytes are read as replacements, not refused.
    source = ProgramFile(program, MAX_PROGRAM_BYTES)
    validate_job(job)  # run's work budget: a job `check` refuses is not planned here either
    try:
        with time_limit(seconds):  # and run's time limit, over the plan and the reading
            with doing(f"planning the job of {shown(config)}, as run does"):
                plan = plan_job(job)
            with doing(f"reading {shown(program)} back and matching it to the plan"):
                sim = simulate(job.machine, plan, source, program)
    except TimeUp as exc:
        where = f": stopped while {exc.activity}" if exc.activity else ""
        raise SolverError(f"{config}: the simulation did not finish within its time limit of {seconds:g} s "
                          f"(--time-limit){where}") from exc
    if output is not None:
        write_atomic(output, simulation_csv(sim))
    if as_json:
        return json.dumps(sim.summary())
    return (f"{job.name}: {sim.moves} moves ({sim.dialect}), {sim.time_s:.1f} s, fiber {sim.fiber_length_mm:.3f} mm "
            f"(planned {sim.planned_fiber_length_mm:.3f} mm), largest deviation {sim.max_deviation_mm:.4f} mm")
