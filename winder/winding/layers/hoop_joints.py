"""A hoop traverse over the joints of a bent axis (a straight leg meeting a bend), smooth in space.

Where a line meets an arc the guide's curvature jumps, and with it the sweep's metric: |Phi_s|, the
surface distance across the circumference per unit station, is 1 on the leg and g = 1 - r kappa
cos(theta - toward) on the bend. A hoop of one constant pitch in (t, f) is smooth in the parameters
but kinked in space where it crosses the joint (1e-3 rad on a DN355 elbow: an eye 125 mm out along
the fiber jumps 0.19 mm, more than any chord tolerance). In space the fiber's direction is
Phi_s t' + Phi_f f' with Phi_s (of length g) square to Phi_f (of length L, the perimeter's rate), so it
is continuous across the joint where f' / g is: the traverse keeps a constant pitch on each piece of
the guide, the pieces' rates in that ratio at the angle theta_c where it crosses each joint.

Each piece must still close its band: across the circumference its turns lie g_max / f' apart (g_max
the piece's largest stretch), at most `spacing` (winder.winding.layers.hoop: B P / sqrt(P^2 - B^2)),
so all rates are scaled up together until the tightest piece closes; the others overlap a little.
The crossing angles depend on the rates (the turns before a joint, many of them: a rate 1 % off moves
the crossing by a hundredth of all the turns before it), so no fixed point is sought: the first
piece's rate is chosen among candidates, each fixing the others exactly (piece_rates).
"""

from __future__ import annotations

import math

import numpy as np

from winder.geometry.joints import joint_stations
from winder.geometry.measure import row_norms

RATE_STEP, RATE_CANDIDATES = 2e-3, 600  # the first piece's rates tried: up to 3.3 times its need
PIECE_ANGLES = 72  # angles round a section where a piece's largest stretch is sought
PIECE_STATIONS = 9  # stations along a piece where it is sought


def joints_in(surface, t0: float, t1: float) -> np.ndarray:
    """The joints' stations t strictly inside the traverse t0 -> t1, in the order it meets them."""
    joints = surface.t_of_s(joint_stations(surface))
    inside = joints[(joints > min(t0, t1)) & (joints < max(t0, t1))]
    return np.sort(inside) if t1 > t0 else np.sort(inside)[::-1]


def _stretch(surface, arcs, s: np.ndarray, th: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(g, L) at points (s, theta): |Phi_s| across the circumference and |d Phi / d f|."""
    ev = surface.evaluate(s, th, order=1, with_point=False)
    along = np.einsum("ij,ij->i", ev.ps, ev.pt) / np.einsum("ij,ij->i", ev.pt, ev.pt)
    return row_norms(ev.ps - along[:, None] * ev.pt), row_norms(ev.pt) * arcs.dtheta_dfrac(th)


def _largest(surface, arcs, a: float, b: float) -> float:
    """A piece's largest g / L (the stretch over the perimeter's rate) between stations a and b."""
    f = (np.arange(PIECE_ANGLES) + 0.5) / PIECE_ANGLES
    t = np.linspace(min(a, b), max(a, b), PIECE_STATIONS)[1:-1]
    s, ff = (x.ravel() for x in np.meshgrid(surface.s_of_t(t), f, indexing="ij"))
    g, length = _stretch(surface, arcs, s, arcs.theta(ff))
    return float(np.max(g / length))


def piece_rates(surface, arcs, breaks: np.ndarray, f0: float, spacing_frac: float) -> np.ndarray:
    """df/d|t| (q,) of each piece between the breaks (q + 1,) (the traverse's ends and joints, in its
    order) from the fraction f0 on (module docstring); spacing_frac : the allowed spacing across the
    circumference over the perimeter's rate, in fractions (spacing / L on a circle's uniform L).

    The first piece's rate r0 fixes the others in turn (each joint's crossing angle follows from the
    rates before it, and the ratio across it from that angle), so r0 is taken as the least of
    RATE_CANDIDATES steps of RATE_STEP above the first piece's own need for which every piece closes
    its band: all candidates at once."""
    q = breaks.size - 1
    need = np.array([_largest(surface, arcs, breaks[i], breaks[i + 1]) for i in range(q)]) / spacing_frac
    rates = need[0] * (1.0 + RATE_STEP * np.arange(RATE_CANDIDATES))[:, None] * np.ones(q)
    forward = breaks[-1] > breaks[0]
    f = np.full(RATE_CANDIDATES, f0)
    for i in range(q - 1):
        f = f + rates[:, i] * abs(breaks[i + 1] - breaks[i])
        s_joint = np.full(RATE_CANDIDATES, float(surface.s_of_t(np.array([breaks[i + 1]]))[0]))
        th = arcs.theta(f)
        below, _ = _stretch(surface, arcs, np.nextafter(s_joint, -np.inf), th)  # the piece before it in s
        above, _ = _stretch(surface, arcs, s_joint, th)  # at the joint: the piece after it (joint_stations)
        # A traverse running back meets the piece above a joint first: the ratio is read the other way.
        rates[:, i + 1:] = (rates[:, i] * (above / below if forward else below / above))[:, None]
    ok = np.all(rates >= need * (1.0 - 1e-12), axis=1)
    return rates[int(np.argmax(ok))] if ok.any() else rates[-1] * float(np.max(need / rates[-1]))


def traverse(surface, arcs, t0: float, t1: float, f0: float, spacing: float,
             step_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(t (m,), f (m,), df/d|t| (m,)) of a hoop traverse t0 -> t1 from the fraction f0 over the joints
    between them, a point on each joint (its rate the piece after it), about step_deg of turn apart;
    None where no joint lies between (a constant pitch is smooth there)."""
    joints = joints_in(surface, t0, t1)
    if joints.size == 0:
        return None
    breaks = np.concatenate([[t0], joints, [t1]])
    # The perimeter's rate L is the section's (uniform in f on a circle; its mean elsewhere).
    perimeter = float(surface.perimeter(surface.s_of_t(np.array([0.5 * (t0 + t1)])))[0])
    rates = piece_rates(surface, arcs, breaks, f0, spacing / perimeter)
    ts, fs, rs = [], [], []
    f_at = f0
    forward = t1 > t0
    last = rates.size - 1
    for i, rate in enumerate(rates.tolist()):
        a, b = breaks[i], breaks[i + 1]
        turns = rate * abs(b - a)
        lam = np.linspace(0.0, 1.0, max(2, int(math.ceil(turns * 360.0 / step_deg)) + 1))
        # A joint's point goes with the piece above it in s (where the surface is read at the joint):
        # the next piece's start going forward, this piece's end going back.
        if forward and i < last:
            lam = lam[:-1]
        elif not forward and i > 0:
            lam = lam[1:]
        ts.append(a + lam * (b - a))
        fs.append(f_at + lam * turns)
        rs.append(np.full(lam.size, rate))
        f_at += turns
    return np.concatenate(ts), np.concatenate(fs), np.concatenate(rs)
