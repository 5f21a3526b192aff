"""The slip check of non-geodesic paths: friction holds a fiber where |k_g / k_n| <= mu (MATH.md 7).

Hoop layers use it today; friction-held paths will too.
"""

from __future__ import annotations

import numpy as np

from winder.errors import SolverError
from winder.geometry.surface import SweepSurface
from winder.winding.passes import PlanContext
from winder.winding.results import FiberPass

SLIP_SAMPLES_PER_TURN = 72


def slip_ratio(surface: SweepSurface, s: np.ndarray, th: np.ndarray) -> np.ndarray:
    """|k_g / k_n| at the points (s, theta) (m,) of a densely sampled path: friction mu holds the fiber
    where this is <= mu (MATH.md 7)."""
    ev = surface.evaluate(s, th, order=2)
    ds, dth = np.gradient(s), np.gradient(th)
    vel = ev.ps * ds[:, None] + ev.pt * dth[:, None]
    acc = ev.pss * (ds * ds)[:, None] + 2.0 * ev.pst * (ds * dth)[:, None] + ev.ptt * (dth * dth)[:, None]
    nrm = np.cross(ev.pt, ev.ps)
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    speed2 = np.einsum("ij,ij->i", vel, vel)
    k_n = np.einsum("ij,ij->i", acc, nrm) / speed2
    k_g = np.einsum("ij,ij->i", np.cross(vel, acc), nrm) / speed2**1.5
    return np.abs(k_g) / np.maximum(np.abs(k_n), 1e-300)


def check_slip(ctx: PlanContext, index: int, p: FiberPass, turns: float) -> None:
    """Refuse a path of layer `index` (0-based) that friction cannot hold: |k_g / k_n| <= mu."""
    surf = ctx.surface
    m = max(50, int(turns * SLIP_SAMPLES_PER_TURN))
    i = np.linspace(0.0, p.s.size - 1.0, m)
    idx = np.arange(p.s.size, dtype=float)
    s, th = np.interp(i, idx, p.s), np.interp(i, idx, p.theta)
    ratio = slip_ratio(surf, s, th)
    worst = int(np.argmax(ratio))
    if ratio[worst] > ctx.winding.friction:
        t = float(surf.t_of_s(s[worst:worst + 1])[0])
        raise SolverError(f"{ctx.key(index)}: a hoop layer would slip here: |k_g / k_n| reaches "
                          f"{ratio[worst]:.3g} at t = {t:.3f} mm, above the friction coefficient "
                          f"{ctx.winding.friction:g} (winding.friction); hoop layers hold on cylindrical "
                          f"regions")
