"""The axis values of every pass of a straight-axis program in one batch (winder.machine.program).

Pass by pass, the program's eye path costs a dozen array operations per pass, and a plan has a
thousand passes. Almost all of it does not depend on where a pass sits in the program: the eye, its
cross-feed, carriage and yaw are pointwise in the contact points (yaw made continuous per pass), so
every pass's points go in one call (kinematics.eye_frames). What is sequential is only the turn
count: A continues from pass to pass (_Turns), B keeps its turn count, and both rest on a pass's
first and last values alone, found from one-point evaluations of the same pointwise formulas. Then
A of all passes is one call (kinematics.rotation_deg). The values are those of pass by pass, to
round-off.
"""

from __future__ import annotations

import math

import numpy as np

from winder.config.machine import MachineConfig
from winder.errors import ExportError
from winder.machine.envelope import EyeEnvelope
from winder.machine.kinematics import EyePath, eye_frames, rotation_deg
from winder.machine.leads import eye_leads, unit_rows
from winder.machine.limits import check_limits
from winder.winding.results import FiberPass

TURN_BACK_DEG = 1.0  # moving to a new layer, the mandrel may turn back this much, not more
_CONTINUITY_TOL = 1e-9  # rad: two passes whose angles meet this closely are continuous
_TWO_PI = 2.0 * np.pi
_POINT_TOL = 1e-6  # mm: a pass starting this close to where the last one ended continues it


class _Turns:
    """Carries the contact angle over the whole program: each pass's unwrapped theta plus whole
    turns, so that A is cumulative. A pass continuing where the last one ended keeps its angles; a
    pass starting elsewhere (a new layer) is reached by turning on in the winding sense (that of the
    previous pass), less than a turn, never backwards."""

    def __init__(self) -> None:
        self.offset = 0.0
        self.end: float | None = None
        self.end_point: np.ndarray | None = None
        self.sense = 1.0

    def place(self, theta: np.ndarray, first: np.ndarray) -> tuple[np.ndarray, bool]:
        """(the pass's program angles, whether it starts away from where the last pass ended);
        first: the pass's first contact point."""
        jumped = False
        if self.end is not None:  # on Python floats: the same arithmetic as numpy's, without its per-call cost
            t0 = float(theta[0])
            self.offset += _TWO_PI * _rint((self.end - (t0 + self.offset)) / _TWO_PI)
            gap = t0 + self.offset - self.end
            jumped = abs(gap) > _CONTINUITY_TOL or float(np.linalg.norm(first - self.end_point)) > _POINT_TOL
            if abs(gap) > _CONTINUITY_TOL and gap * self.sense < 0.0:
                self.offset += _TWO_PI * self.sense
        return theta + self.offset, jumped

    def turn_on(self, theta: np.ndarray) -> np.ndarray:
        """One more turn in the winding sense (the eye, not only the contact, must not turn back)."""
        self.offset += _TWO_PI * self.sense
        return theta + self.offset

    def done(self, cum: np.ndarray, last: np.ndarray) -> None:
        lo, hi = float(cum[0]), float(cum[-1])
        if hi != lo:
            self.sense = float(np.sign(hi - lo)) if math.isnan(hi - lo) else math.copysign(1.0, hi - lo)
        self.end = hi
        self.end_point = np.asarray(last, dtype=float)


def _rint(x: float) -> float:
    """np.rint of one float (halves to even, the sign of a zero result kept): Python's round on a
    finite value, numpy's elsewhere."""
    return math.copysign(float(round(x)), x) if math.isfinite(x) else float(np.rint(x))


def straight_axes(passes: list[FiberPass], wheres: list[str], leads: list, dense: list, env: EyeEnvelope,
                  machine: MachineConfig, sense: float) -> tuple[np.ndarray, np.ndarray, list[bool]]:
    """The axis table of the non-empty passes in program order, one batch.

    leads : each pass's eye leads (None: found here, a refusal naming the pass); dense : each pass's
    densified (points, directions, theta, u, leads) or None (winder.machine.densify).
    Returns (table (k, 4): carriage, rotation, cross_feed, yaw of every point of every pass, the
    dense points where densified; sizes (n,) each pass's rows; jumped: per pass, whether it starts
    away from where the last one ended) plus, through the EyePath, the leads and on_envelope flags.
    Refuses axis values outside machine.limits, naming the first pass in program order.
    """
    points, dirs, base, lams, oks = [], [], [], [], []
    for fp, where, lead, dn in zip(passes, wheres, leads, dense):
        if dn is None:
            p, d, th, lead = fp.points, fp.direction, np.asarray(fp.theta, dtype=float), lead
        else:
            p, d, th, _, lead = dn
        if lead is None:  # the batch found no lead: pass by pass, so that the refusal names its pass
            lead = eye_leads(p, d, env, where)
        points.append(p)
        dirs.append(d)
        base.append(th)
        lams.append(lead[0])
        oks.append(lead[1])
    sizes = np.array([len(th) for th in base])
    p = np.concatenate(points).reshape(-1, 3).astype(float, copy=False)
    d = unit_rows(np.concatenate(dirs).reshape(-1, 3).astype(float, copy=False))
    path, phi_raw = eye_frames(p, d, (np.concatenate(lams), np.concatenate(oks)), sense, sizes)
    last = np.cumsum(sizes) - 1
    first = last - sizes + 1
    shift, b_shift, jumped = turn_counts(passes, [None if dn is None else dn[2][-1] for dn in dense],
                                         phi_raw[first], phi_raw[last], path.b_deg[first], path.b_deg[last])
    theta = np.concatenate(base) + np.repeat(shift, sizes)
    a_deg = rotation_deg(phi_raw, theta)
    b_deg = path.b_deg + np.repeat(b_shift, sizes)
    whole = EyePath(path.x, a_deg, path.z, b_deg, path.eye_xyz, path.lead, path.on_envelope)
    checked(whole, sizes, wheres, machine)
    return whole, sizes, jumped


def checked(whole: EyePath, sizes: np.ndarray, wheres: list[str], machine: MachineConfig) -> None:
    """Refuses axis values of the passes (consecutive runs of `sizes`) outside machine.limits, naming
    the first pass in program order that leaves them."""
    try:
        check_limits(whole, machine, "")
    except ExportError:
        last = np.cumsum(sizes) - 1
        first = last - sizes + 1
        for k, where in enumerate(wheres):
            run = slice(first[k], last[k] + 1)
            check_limits(EyePath(whole.x[run], whole.a_deg[run], whole.z[run], whole.b_deg[run],
                                 whole.eye_xyz[run], whole.lead[run], whole.on_envelope[run]), machine, where)
        raise


def turn_counts(passes: list[FiberPass], dense_last: list, phi_first: np.ndarray, phi_last: np.ndarray,
                b_first: np.ndarray, b_last: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[bool]]:
    """What each pass adds to its contact angles (rad) and to its yaw (deg) so that A and B continue
    over the program, and whether it jumped; from each pass's first and last eye angle phi_raw and
    yaw (deg, continuous within the pass). dense_last: per pass the last dense contact angle at the
    plan's turn count, None where the pass keeps its planned points."""
    turns = _Turns()
    a_end: tuple[float, float] | None = None  # (phi_raw, theta) of the last eye: A only where a pass jumps
    b_end: float | None = None
    shift, b_shift, jumped = np.zeros(len(passes)), np.zeros(len(passes)), []
    phi_first, phi_last = phi_first.tolist(), phi_last.tolist()
    b_first, b_last = b_first.tolist(), b_last.tolist()
    for k, (fp, dn) in enumerate(zip(passes, dense_last)):
        theta_k = fp.theta
        ends = np.array([theta_k[0], theta_k[-1]], dtype=float)
        theta, jump = turns.place(ends, np.asarray(fp.points[0], float))
        if jump and a_end is not None and (_a_at(phi_first[k], theta[0]) - _a_at(*a_end)) * turns.sense > TURN_BACK_DEG:
            # A runs against theta: the eye would turn back on the way to this pass.
            theta = turns.turn_on(ends)
        if dn is None:
            shift[k] = turns.offset
            a_end = (phi_last[k], ends[1] + turns.offset)
        else:  # the dense angles are at the plan's turn count: add the program's whole turns
            shift[k] = float(theta[0] - ends[0])
            a_end = (phi_last[k], dn + shift[k])
        # The first pass keeps its yaw: -0.0 adds nothing to any value, -0.0 included.
        b_shift[k] = -0.0 if b_end is None else 360.0 * _rint((b_end - b_first[k]) / 360.0)
        b_end = float(b_last[k] + b_shift[k])
        turns.done(theta, fp.points[-1])
        jumped.append(jump)
    return shift, b_shift, jumped


def _a_at(phi_raw: float, theta: float) -> float:
    """rotation_deg of one eye, by the same array arithmetic as the batch's."""
    return float(rotation_deg(np.array([phi_raw]), np.array([theta]))[0])
