"""What every job proves before it writes (docs/guide/conventions.md).

A job's plan and its program are checked against truths of their own, not against the numbers that
built them, so that a defect anywhere upstream (a spline, a contact, a clearance model) is caught
before a shop winds it:

- coverage: every layer's covered fraction at least its `min_coverage` (winding.min_coverage, default
  MIN_COVERAGE; a layer may ask less, in its own entry, never silently);
- deviation: every programmed point and every move's midpoint, as written, within
  machine.chord_tolerance of the exact tangent ray of the planned path at its contact
  (winder.machine.deviation: the contact from the plan's own parameters, not a search);
- clearance: the eye's body along every move at least `machine.eye.clearance` (less the chord
  tolerance the moves may cut in by, as winder.machine.collision allows) from the part as wound by the
  layers up to the move's own (winder.machine.as_wound), or clear of it with `eye: {radius}`;
- limits: the axes as written (their decimals) within machine.limits.

A job that breaks one fails (exit 1) naming the layer, circuit and pass, the program move and the
figure, and writes nothing; the summary's `invariants` block gives the margins over the whole job.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import SolverError
from winder.machine.as_wound import wound_profiles
from winder.machine.collision import move_distances
from winder.machine.deviation import program_deviations
from winder.machine.envelope import EyeEnvelope
from winder.machine.limits import ROLE_UNITS, as_written
from winder.machine.mend import MEND_ROUNDS, mend
from winder.machine.program import AXES, MotionProgram
from winder.winding.results import WindingPlan

DEVIATION_SLACK = 1e-9  # mm: a deviation this far past the tolerance is round-off of the check itself


@dataclasses.dataclass(frozen=True)
class Invariants:
    """The job's margins: the least covered fraction of any layer; the largest distance of a written
    point and of a move's midpoint from their contacts' tangent rays (mm); the eye body's least
    distance from the part as wound (mm). The program's figures are None without a program."""

    min_covered_fraction: float
    max_point_deviation_mm: float | None = None
    max_midpoint_deviation_mm: float | None = None
    min_clearance_mm: float | None = None


def prove(plan: WindingPlan, job, program: MotionProgram | Exception | None) -> Invariants:
    """Check every invariant of a planned job and its program (module docstring); SolverError naming
    the first one broken. A program that could not be built (an Exception) is not checked here: the
    outputs that need it say why."""
    return mended_and_proved(plan, job, program, mending=False)[1]


def mended_and_proved(plan: WindingPlan, job, program: MotionProgram | Exception | None,
                      mending: bool = True) -> tuple[MotionProgram | Exception | None, Invariants]:
    """(the program, its invariants): prove's, the moves whose midpoints stray cut finer first
    (winder.machine.mend) where mending."""
    covered = prove_coverage(plan, job)
    if not isinstance(program, MotionProgram) or program.values.shape[0] == 0:
        return program, Invariants(covered)
    machine = program.machine
    tol = float(machine.chord_tolerance)
    dev = program_deviations(plan, program, tol)
    for _ in range(MEND_ROUNDS if mending else 0):
        stray = np.flatnonzero(dev.midpoint > tol + DEVIATION_SLACK)
        if stray.size == 0 or program.cell is not None:
            break
        program = mend(plan, program, stray)
        dev = program_deviations(plan, program, tol)
    _refuse_deviation(plan, job, program, dev.point, tol, "programmed point")
    _refuse_deviation(plan, job, program, dev.midpoint, tol, "midpoint of the move to")
    clearance = _prove_clearance(plan, job, program)
    _prove_limits(plan, job, program)
    return program, Invariants(covered, _largest(dev.point), _largest(dev.midpoint), clearance)


def _largest(values: np.ndarray) -> float | None:
    finite = values[np.isfinite(values)]
    return float(finite.max()) if finite.size else None


def prove_coverage(plan: WindingPlan, job) -> float:
    """The least covered fraction of the plan's layers; SolverError where a layer covers less than it
    asks (its own min_coverage, else winding.min_coverage)."""
    least = 1.0
    for i, layer in enumerate(plan.layers):
        cfg = job.winding.layers[i]
        need = job.winding.min_coverage_of(i)
        got = float(layer.coverage.covered_fraction)
        least = min(least, got)
        if got < need:
            own = cfg.min_coverage is not None
            raise SolverError(
                f"{plan.source}: {cfg.label(i)}: covers {got:.4f} of its surface (the widest gap "
                f"{layer.coverage.max_gap_mm:.3f} mm), less than {'its' if own else 'winding.'}min_coverage "
                f"{need:g}; a layer that is meant to leave gaps says so with its own min_coverage (at most "
                f"{np.floor(got * 1e4) / 1e4:g} here)")
    return least


def _where(plan: WindingPlan, job, program: MotionProgram, row: int) -> str:
    """`file: layer 3 (helical 20 deg), circuit 2, pass 4 (return), move 1234` of a program row."""
    for i, segments in enumerate(program.segments):
        for seg in segments:
            if seg.start <= row < seg.stop:
                return (f"{plan.source}: {job.winding.layers[i].label(i)}, circuit {seg.circuit}, pass "
                        f"{seg.number} ({seg.kind.value}), program move {row + 1}")
    return f"{plan.source}: program move {row + 1}"


def _refuse_deviation(plan: WindingPlan, job, program: MotionProgram, dev: np.ndarray, tol: float,
                      what: str) -> None:
    bad = np.flatnonzero(dev > tol + DEVIATION_SLACK)
    if bad.size == 0:
        return
    row = int(bad[np.argmax(dev[bad])])
    raise SolverError(f"{_where(plan, job, program, row)}: the eye at the {what} this move lies {dev[row]:.4f} mm "
                      f"off the fiber's tangent at its contact, more than machine.chord_tolerance ({tol:g} mm); "
                      f"{bad.size} move(s) so: the program does not lay the planned path")


def _prove_clearance(plan: WindingPlan, job, program: MotionProgram) -> float:
    """The eye body's least distance (mm) from the part as wound by each move's layer, along every
    move as written; SolverError where it comes closer than the clearance allows."""
    machine: MachineConfig = program.machine
    from winder.machine.program import as_written as rows_written  # noqa: PLC0415

    values = rows_written(program.values, program.robot)
    need = (0.0 if machine.eye_clearance is None or machine.eye_radius is not None
            else float(machine.eye_clearance) - float(machine.chord_tolerance))
    guide = None
    least = np.inf
    for i, (segments, part) in enumerate(zip(program.segments, wound_profiles(plan))):
        if not segments or segments[-1].stop <= segments[0].start:
            continue
        lo, hi = segments[0].start, segments[-1].stop
        stations, radius = part.table()
        env = EyeEnvelope(stations, radius, radius, None, None)
        if program.robot and guide is None:
            from winder.machine.kinematics import make_guide  # noqa: PLC0415

            guide = make_guide(plan.outer_surface, env)
        window = values[max(lo - 1, 0):hi]
        dist = move_distances(window, env, guide)[0][(1 if lo > 0 else 0):] - 0.5 * float(machine.eye_size)
        if program.robot:  # a robot's pass-to-pass joins need only keep off the part
            firsts = np.array([seg.start - lo for seg in segments if seg.stop > seg.start and seg.approach == 0])
            dist_need = np.full(dist.size, need)
            dist_need[firsts] = 0.0  # a layer's first move too: from the last layer's last pose
        else:
            dist_need = np.full(dist.size, need)
        bad = np.flatnonzero(dist < dist_need - 1e-9)
        if bad.size:
            k = int(bad[np.argmin(dist[bad] - dist_need[bad])])
            raise SolverError(f"{_where(plan, job, program, lo + k)}: the payout eye's body comes within "
                              f"{dist[k]:.3f} mm of the part as wound so far (layers 1 to {i + 1}), closer than "
                              f"machine.eye.clearance allows ({max(dist_need[k], 0.0):.3f} mm)")
        kept = dist[dist_need > 0.0] if np.any(dist_need > 0.0) else dist  # a robot's joins need only keep off
        least = min(least, float(kept.min())) if kept.size else least
    return float(least) if np.isfinite(least) else None


def _prove_limits(plan: WindingPlan, job, program: MotionProgram) -> None:
    """Every written axis value within machine.limits (a robot's poses have none)."""
    if program.robot:
        return
    machine = program.machine
    for role, (lo, hi) in machine.limits.items():
        col = AXES.index(role)
        values = as_written(program.values[:, col], (lo, hi))
        bad = np.flatnonzero((values < lo) | (values > hi))
        if bad.size:
            row = int(bad[np.argmax(np.maximum(lo - values[bad], values[bad] - hi))])
            unit = ROLE_UNITS[role]
            raise SolverError(f"{_where(plan, job, program, row)}: axis {getattr(machine.axes, role)} "
                              f"({role.replace('_', '-')}) is written {values[row]:.3f} {unit}, outside "
                              f"machine.limits.{role} [{lo:g}, {hi:g}] {unit}")
