"""The sweep surface's fields on a guide curve that is one circular arc (a bend), written into a jet.

The arc's frame is fixed: its tangent T and in-plane normal N turn in the plane of the start tangent
T0 and the normal u, the binormal b is constant, and e2, e3 are fixed combinations of N and b. So
every field is a combination of a few constant columns with per-point factors, and fields that share
a factor are formed together on stacked rows: T and N in one pass ((2, 3, m)), n and m in another,
Phi_s and Phi_ss (both stretch times a column) in one, Phi_th and Phi_thth (both the radius times
one) in one. Each stacked pass computes the products and sums the separate ones did, so the fields
are theirs to round-off.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class ArcFrame(NamedTuple):
    """A one-arc guide curve's constants: origin, T0, u and b as (3, 1) columns, the curvature, the
    stacked columns [T0; u] and [u; -T0] ((2, 3, 1): T and N from cos and sin of the arc angle), and
    the frame components stacked so that cos(theta) e_c + sin(theta) e_s ((4, 1) each) gives the
    components of n and m along N and b as rows [n.N, m.N, n.b, m.b]."""

    origin: np.ndarray
    t0: np.ndarray
    u: np.ndarray
    b: np.ndarray
    kappa: float
    tn_cos: np.ndarray
    tn_sin: np.ndarray
    nm_cos: np.ndarray
    nm_sin: np.ndarray


def arc_frame(origin: np.ndarray, t0: np.ndarray, u: np.ndarray, b: np.ndarray, radius: float,
              e2u: float, e2b: float, e3u: float, e3b: float) -> ArcFrame:
    """The ArcFrame of an arc of this radius from its origin, start tangent, normal u and binormal b
    (3,) and the frame components e2 = e2u N + e2b b, e3 = e3u N + e3b b."""
    o, t, n, bb = (np.asarray(v, dtype=float).reshape(3, 1) for v in (origin, t0, u, b))
    return ArcFrame(o, t, n, bb, 1.0 / radius, np.stack([t, n]), np.stack([n, -t]),
                    np.array([[e2u], [e3u], [e2b], [e3b]]), np.array([[e3u], [-e2u], [e3b], [-e2b]]))


def is_zero(v) -> bool:
    """v is an exact scalar 0.0 (a term that vanishes on this surface), not an array."""
    return isinstance(v, float) and v == 0.0


def times(a, b):
    """a * b, or b itself where a is the scalar 1.0 (the same values)."""
    return b if isinstance(a, float) and a == 1.0 else a * b


def evaluate_arc(arc: ArcFrame, jet: np.ndarray, z, z1, z2, p, p1, p2, c: np.ndarray, sn: np.ndarray,
                 q, q1, q2, order: int, with_point: bool, zero=is_zero, times=times) -> None:
    """Fill jet ((1, 3 or 6), 3, m) with Phi and its derivatives up to order (jet[0] only with_point).

    z, z1, z2, p, p1, p2 : the profile's axial station and radius with their s-derivatives, (m,) or
    exact floats; c, sn : cos and sin of theta (m,); q, q1, q2 : the section's scaled radius and its
    theta-derivatives. K = kappa N and K' = -kappa^2 T: K.n, K.m from n's frame components, K'.n = 0.
    zero, times : the tests of a vanishing term and of a unit factor (the caller's, which a test may
    replace to compute every term).
    """
    kappa = arc.kappa
    # Everything from the half angle, two transcendentals: (1 - cos(phi)) / kappa = 2 sin(phi/2)^2
    # / kappa keeps its digits near the arc's start, where 1 - cos(phi) cancels.
    half = (0.5 * kappa) * z
    sh, ch = np.sin(half), np.cos(half)
    sh2 = sh * sh
    cp, sp = 1.0 - 2.0 * sh2, 2.0 * sh * ch
    tn = cp * arc.tn_cos + sp * arc.tn_sin  # [T; N] = [cp T0 + sp u; cp u - sp T0]
    tan, nrm = tn[0], tn[1]
    parts = c * arc.nm_cos + sn * arc.nm_sin  # [n.N, m.N, n.b, m.b]
    nm = parts[:2, None] * nrm + parts[2:, None] * arc.b  # [n; m]
    n, m = nm[0], nm[1]
    r = p * q
    if with_point:
        x = arc.origin + (sp / kappa) * arc.t0 + ((2.0 / kappa) * sh2) * arc.u
        np.add(x, r * n, out=jet[0])
    if order == 0:
        return
    knm = kappa * parts[:2]
    kn, km = knm[0], knm[1]  # indexing: unpacking iterates the array, slower
    r_s, r_t = p1 * q, p * q1
    stretch = times(z1, 1.0 - r * kn)  # Phi_s . T: the section's point runs faster outside a bend
    plain = zero(r_s) and zero(z2) and isinstance(z1, float) and z1 == 1.0 and zero(p2 * q)
    if order == 1 or not plain:
        if zero(r_s):
            np.multiply(stretch, tan, out=jet[1])
        else:
            np.add(stretch * tan, r_s * n, out=jet[1])
    # Phi_th = r m and Phi_thth = (p q2 - r) n on a circle of constant radius: one pass.
    thth = p * q2 - r if order == 2 else None  # q2 is None below order 2
    pair = zero(r_t) and isinstance(r, float) and isinstance(thth, float)
    if pair:  # the two factors as a (2, 1, 1) column
        np.multiply(np.array([[[r]], [[thth]]]), nm[::-1], out=jet[2:6:3])
    else:
        phi_theta(jet, r, r_t, n, m, zero)
    if order == 1:
        return
    np.multiply(kappa, nrm, out=nrm)  # K; N is not needed any more
    if plain:  # Phi_ss = stretch K and Phi_s = stretch T: one pass over [T; K]
        np.multiply(stretch, tn, out=jet[1:4:2])
    else:
        kdn = 0.0
        bend = times(z1, stretch) * nrm
        if not (zero(z2) and zero(r_s)):
            bend = (z2 * (1.0 - r * kn) - 2.0 * r_s * z1 * kn - r * z1 * z1 * kdn) * tan + bend
        if zero(p2 * q):
            jet[3] = bend
        else:
            np.add(bend, (p2 * q) * n, out=jet[3])
    if zero(r_s):  # r_s = p1 q = 0: p1 = 0, so the (p1 q1) n term is 0 too
        # -(z1 r km T) as (z1 (-r) km) T: negation is exact, and on a scalar r it costs no pass
        np.multiply(times(z1, (-r) * km if zero(r_t) else -(r_t * kn + r * km)), tan, out=jet[4])
    else:
        twist = times(z1, r * km if zero(r_t) else r_t * kn + r * km) * tan
        if zero(p1 * q1):
            np.subtract(r_s * m, twist, out=jet[4])
        else:
            np.subtract((p1 * q1) * n + r_s * m, twist, out=jet[4])
    if not pair:
        phi_theta_theta(jet, thth, r_t, n, m, zero)


def phi_theta(jet: np.ndarray, r, r_t, n: np.ndarray, m: np.ndarray, zero=is_zero) -> None:
    """jet[2] = Phi_th = r_t n + r m (r m alone where r_t is an exact 0) from the section point's
    direction n and its theta-derivative m, (3, m) each."""
    if zero(r_t):
        np.multiply(r, m, out=jet[2])
    else:
        np.add(r_t * n, r * m, out=jet[2])


def phi_theta_theta(jet: np.ndarray, thth, r_t, n: np.ndarray, m: np.ndarray, zero=is_zero) -> None:
    """jet[5] = Phi_thth = thth n + 2 r_t m, thth = p q2 - r (thth n alone where r_t is an exact 0)."""
    if zero(r_t):
        np.multiply(thth, n, out=jet[5])
    else:
        np.add(thth * n, (2.0 * r_t) * m, out=jet[5])
