"""Helical layers at a given slip on open surfaces of revolution (cones, tables, tapered poles): `slip`
a number (docs/guide/config.md; docs/math/07-friction.md 7.4).

The passes keep lambda = k_g / k_n at the slip's magnitude, its sign the one that holds the angle
against Clairaut's drift (that of r' along the travel), so the angle follows

    d(alpha)/dt = lambda(t) [sin(alpha) tan(alpha) - r r'' cos(alpha) / (1 + r'^2)] / r - r' tan(alpha) / r

from the layer's angle on the reference section (the widest) to both ends of the region. Every pass is
a rotated copy of one quadrature of it (winder.winding.layers.friction_revolution). A fiber whose angle
reaches 90 deg turns around before the end, and one with k_n <= 0 bridges: both are refused with the
remedies that reach the end and press everywhere, each found by the same integration.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from winder.config.winding import LayerConfig
from winder.errors import SolverError
from winder.geometry.surface import SweepSurface
from winder.winding.layers.friction_revolution import NEED_SAMPLES, _profile, held_need, revolution_layer
from winder.winding.passes import PlanContext, winding_region
from winder.winding.results import LayerPlan

RTOL = 1e-10  # the angle's integration (relative and absolute, rad)
TURN_MARGIN = 1e-6  # rad below 90 deg where the angle counts as turned around
SEARCH_STEPS = 14  # bisection steps of a remedy (slip or angle): 6e-5 of its bracket
ANGLE_FLOOR_DEG = 1.0  # the least angle a remedy proposes
TAPER_FLOOR = 1e-9  # |r'| above which a profile tapers (a constant one's is 0 to round-off)


def _lam(r1: np.ndarray, slip: float) -> np.ndarray:
    """lambda along a forward pass: the slip's magnitude, the sign of r' (the one that holds the angle)."""
    return slip * np.sign(r1)


def _rate(surface: SweepSurface, slip: float) -> Callable[[float, np.ndarray], np.ndarray]:
    def fun(t: float, y: np.ndarray) -> np.ndarray:
        r, r1, r2 = _profile(surface, np.atleast_1d(t))
        a = y[0]
        press = math.sin(a) * math.tan(a) - r * r2 * math.cos(a) / (1.0 + r1 * r1)
        return _lam(r1, slip) * press / r - r1 * math.tan(a) / r
    return fun


def _leg(surface: SweepSurface, t0: float, t1: float, a0: float, slip: float):
    """The angle from (t0, a0) to t1: (dense solution or None, the station where it turned around or nan)."""
    from scipy.integrate import solve_ivp  # noqa: PLC0415 - slip layers only

    if t1 == t0:
        return None, math.nan

    def turned(_t: float, y: np.ndarray) -> float:
        return 0.5 * math.pi - TURN_MARGIN - y[0]

    turned.terminal = True
    res = solve_ivp(_rate(surface, slip), (t0, t1), [a0], method="DOP853", rtol=RTOL, atol=RTOL,
                    dense_output=True, events=(turned,))
    if res.status == 1:
        return None, float(res.t_events[0][0])
    if res.status != 0:
        raise SolverError(f"the slip's angle integration failed: {res.message}")
    return res.sol, math.nan


def angle_along(surface: SweepSurface, region: tuple[float, float], angle_deg: float,
                slip: float) -> tuple[Callable[[np.ndarray], np.ndarray] | None, float, float]:
    """(alpha(t) (rad) over the region or None, the station where the fiber turned around or nan, the
    least k_n-sign term `press` over the region), the angle angle_deg on the widest section."""
    t_a, t_b = region
    t = np.linspace(t_a, t_b, NEED_SAMPLES)
    r, r1, r2 = _profile(surface, t)
    t_ref = float(t[int(np.argmax(r))])
    a0 = math.radians(angle_deg)
    legs = []
    for end in (t_a, t_b):
        sol, turn = _leg(surface, t_ref, end, a0, slip)
        if not math.isnan(turn):
            return None, turn, math.nan
        legs.append(sol)

    def alpha(q: np.ndarray) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        out = np.full(q.shape, a0)
        for sol, side in zip(legs, (q < t_ref, q > t_ref)):
            if sol is not None and np.any(side):
                out[side] = sol(q[side])[0]
        return out

    a = alpha(t)
    press = np.sin(a) * np.tan(a) * (1.0 + r1 * r1) - r * r2 * np.cos(a)
    return alpha, math.nan, float(np.min(press))


def _plans(surface: SweepSurface, region: tuple[float, float], angle_deg: float, slip: float) -> bool:
    alpha, _, press = angle_along(surface, region, angle_deg, slip)
    return alpha is not None and press > 0.0


def _bisect(good: Callable[[float], bool], bad: float, ok: float) -> float:
    """The value next to `bad` (which fails) on the way to `ok` (which plans) where good turns true."""
    for _ in range(SEARCH_STEPS):
        mid = 0.5 * (bad + ok)
        bad, ok = (bad, mid) if good(mid) else (mid, ok)
    return ok


def remedies(surface: SweepSurface, region: tuple[float, float], angle_deg: float, slip: float,
             mu: float) -> list[str]:
    """The changes that lay the layer (each checked by the same integration): a larger slip up to the
    friction, slip: auto where friction mu holds the angle, another angle at this slip."""
    out = []
    if slip < mu and _plans(surface, region, angle_deg, mu):
        least = _bisect(lambda v: _plans(surface, region, angle_deg, v), slip, mu)
        out.append(f"slip: {math.ceil(least * 1000.0) / 1000.0:.3f} or more (up to winding.friction {mu:g})")
    need, _, presses = held_need(surface, *region, angle_deg)
    if presses and need <= mu:
        out.append(f"slip: auto (friction {need:.3g} holds {angle_deg:g} deg over the region)")
    for far in (ANGLE_FLOOR_DEG, 89.0):
        if _plans(surface, region, far, slip):
            best = _bisect(lambda v: _plans(surface, region, v, slip), angle_deg, far)
            below = far < angle_deg
            shown = (math.floor if below else math.ceil)(best * 10.0) / 10.0
            out.append(f"angle: {shown:g} (at this slip the angle {'below' if below else 'above'} {best:.2f} deg)")
            break
    return out


def tapers(surface: SweepSurface, t_a: float, t_b: float) -> bool:
    """An open surface of revolution whose radius changes over [t_a, t_b] (a cone, a table, a pole),
    where a slip number steers the angle (on a cylinder it would only bend a geodesic away)."""
    from winder.winding.layers.friction_revolution import is_open_revolution  # noqa: PLC0415

    if not is_open_revolution(surface):
        return False
    r1 = _profile(surface, np.linspace(t_a, t_b, NEED_SAMPLES))[1]
    return bool(np.max(np.abs(r1)) > TAPER_FLOOR)


def slip_layer(ctx: PlanContext, cfg: LayerConfig, index: int, theta0: float) -> LayerPlan:
    """The layer at slip cfg.slip (module docstring)."""
    surf, mu, slip = ctx.surface, ctx.winding.friction, float(cfg.slip)
    region = winding_region(ctx)
    alpha, turn, press = angle_along(surf, region, cfg.angle_deg, slip)
    if alpha is None or press <= 0.0:
        why = (f"at slip {slip:g} the fiber laid at {cfg.angle_deg:g} deg turns around at t = {turn:.5g} mm, "
               f"before the end of the winding region" if alpha is None else
               f"at slip {slip:g} the fiber laid at {cfg.angle_deg:g} deg bridges (k_n <= 0: the profile curves "
               f"away faster than the fiber)")
        fixes = remedies(surf, region, cfg.angle_deg, slip, mu)
        hint = "; what plans it: " + "; ".join(fixes) if fixes else "; no slip within the friction and no angle lays it"
        raise SolverError(f"{ctx.key(index)}: {why}{hint}")
    t = np.linspace(*region, NEED_SAMPLES)
    a = np.degrees(alpha(t))
    notes = [f"held at slip {slip:g} (lambda = k_g / k_n): the angle runs from {a[0]:.2f} deg at t = {t[0]:.4g} mm "
             f"to {a[-1]:.2f} deg at t = {t[-1]:.4g} mm ({cfg.angle_deg:g} deg on the widest section)"]
    return revolution_layer(ctx, cfg, index, theta0, alpha, notes)
