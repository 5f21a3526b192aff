"""Forward and closed-form inverse kinematics of the arms of winder.machine.arms (docs/math/10-robot-cell.md).

fk: joint angles (controller's convention, deg) -> the flange pose in the robot's base frame.
ik: flange poses -> every closed-form solution, 8 branches per pose (shoulder, elbow, wrist), NaN
where a branch has no solution. Both vectorized over poses.
"""

from __future__ import annotations

import numpy as np

from winder.config.arms import SPHERICAL, Arm

BRANCHES = 8  # shoulder (2) x elbow (2) x wrist (2)
_CLIP = 1.0 + 1e-12  # cosines this far past 1 are rounding


def _dh(theta: np.ndarray, d: float, a: float, alpha: float) -> np.ndarray:
    """DH transforms (..., 4, 4) at the angles theta (...) rad; alpha rad."""
    ct, st = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(alpha), np.sin(alpha)
    out = np.zeros(theta.shape + (4, 4))
    out[..., 0, 0], out[..., 0, 1], out[..., 0, 2], out[..., 0, 3] = ct, -st * ca, st * sa, a * ct
    out[..., 1, 0], out[..., 1, 1], out[..., 1, 2], out[..., 1, 3] = st, ct * ca, -ct * sa, a * st
    out[..., 2, 1], out[..., 2, 2], out[..., 2, 3] = sa, ca, d
    out[..., 3, 3] = 1.0
    return out


def theta_of(arm: Arm, q_deg: np.ndarray) -> np.ndarray:
    """DH angles (rad) of controller joint angles (deg)."""
    return np.radians(np.asarray(q_deg, dtype=float) * arm.sign + arm.offset)


def joints_of(arm: Arm, theta: np.ndarray) -> np.ndarray:
    """Controller joint angles (deg) of DH angles (rad)."""
    return arm.sign * (np.degrees(theta) - arm.offset)


def fk(arm: Arm, q_deg: np.ndarray) -> np.ndarray:
    """Flange poses (..., 4, 4) in the robot's base frame (mm) of joint angles (..., 6) (deg)."""
    theta = theta_of(arm, q_deg)
    t = np.broadcast_to(np.eye(4), theta.shape[:-1] + (4, 4)).copy()
    t[..., :3, :3] = arm.base
    for i in range(6):
        d, a, alpha = arm.dh[i]
        t = t @ _dh(theta[..., i], d, a, np.radians(alpha))
    flange = np.eye(4)
    flange[:3, :3] = arm.flange
    return t @ flange


def _acos(x: np.ndarray) -> np.ndarray:
    """arccos, NaN beyond rounding outside [-1, 1]."""
    return np.where(np.abs(x) <= _CLIP, np.arccos(np.clip(x, -1.0, 1.0)), np.nan)


def ik(arm: Arm, pose: np.ndarray) -> np.ndarray:
    """Joint angles (m, 8, 6) (deg, controller's convention, each in (-180, 180] before any turn is
    added) of the flange poses (m, 4, 4) in the robot's base frame; a branch without a solution is NaN."""
    pose = np.asarray(pose, dtype=float).reshape(-1, 4, 4)
    r = np.einsum("ji,mjk,lk->mil", arm.base, pose[:, :3, :3], arm.flange)  # base^T R flange^T
    p = np.einsum("ji,mj->mi", arm.base, pose[:, :3, 3])
    theta = _spherical(arm, r, p) if arm.kind == SPHERICAL else _ur(arm, r, p)
    q = joints_of(arm, theta)
    return (q + 180.0) % 360.0 - 180.0 + np.where(np.isnan(q), np.nan, 0.0)


def _wrist(r: np.ndarray, flip: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(theta4, theta5, theta6) of R = Rz(t4) Rx(90) Rz(t5) Rx(-90) Rz(t6) (..., 3, 3); flip: the
    branch with theta5 < 0."""
    s = np.where(flip, -1.0, 1.0)
    t5 = np.arctan2(s * np.hypot(r[..., 0, 2], r[..., 1, 2]), r[..., 2, 2])
    t4 = np.arctan2(-s * r[..., 1, 2], -s * r[..., 0, 2])
    t6 = np.arctan2(-s * r[..., 2, 1], s * r[..., 2, 0])
    return t4, t5, t6


def _spherical(arm: Arm, r: np.ndarray, p: np.ndarray) -> np.ndarray:
    """DH angles (m, 8, 6) of a spherical-wrist arm (alpha -90, 0, -90, 90, -90, 0)."""
    (d1, a1, _), (_, a2, _), (_, a3, _), (d4, _, _), _, (d6, _, _) = arm.dh
    m = p.shape[0]
    w = p - d6 * r[:, :, 2]  # the wrist centre
    out = np.full((m, 2, 2, 2, 6), np.nan)
    big = np.hypot(a3, d4)
    beta = np.arctan2(d4, a3)  # frame 3: the wrist at Rz(t3) (a3, d4) from frame 2's origin
    for i, t1 in enumerate((np.arctan2(w[:, 1], w[:, 0]), np.arctan2(w[:, 1], w[:, 0]) + np.pi)):
        c1, s1 = np.cos(t1), np.sin(t1)
        x = c1 * w[:, 0] + s1 * w[:, 1] - a1  # the wrist in frame 1 (alpha1 = -90: frame 1's y is -z)
        y = -(w[:, 2] - d1)
        k = (x * x + y * y - a2 * a2 - big * big) / (2.0 * a2 * big)
        for j, sgn in enumerate((1.0, -1.0)):
            t3 = sgn * _acos(k) - beta
            vx = a2 + a3 * np.cos(t3) - d4 * np.sin(t3)
            vy = a3 * np.sin(t3) + d4 * np.cos(t3)
            t2 = np.arctan2(y, x) - np.arctan2(vy, vx)
            r03 = _r03(arm, t1, t2, t3)
            r36 = np.einsum("mji,mjk->mik", r03, r)
            for f in range(2):
                t4, t5, t6 = _wrist(r36, np.full(m, f == 1))
                out[:, i, j, f] = np.column_stack([t1, t2, t3, t4, t5, t6])
    return out.reshape(m, BRANCHES, 6)


def _r03(arm: Arm, t1: np.ndarray, t2: np.ndarray, t3: np.ndarray) -> np.ndarray:
    """The rotation (m, 3, 3) of DH frame 3 at the angles of the first three joints."""
    t = np.broadcast_to(np.eye(4), t1.shape + (4, 4))
    for i, th in enumerate((t1, t2, t3)):
        d, a, alpha = arm.dh[i]
        t = t @ _dh(th, d, a, np.radians(alpha))
    return t[..., :3, :3]


def _ur(arm: Arm, r: np.ndarray, p: np.ndarray) -> np.ndarray:
    """DH angles (m, 8, 6) of a UR arm (alpha 90, 0, 0, 90, -90, 0)."""
    (d1, _, _), (_, a2, _), (_, a3, _), (d4, _, _), (d5, _, _), (d6, _, _) = arm.dh
    m = p.shape[0]
    p5 = p - d6 * r[:, :, 2]  # frame 5's origin
    phi, rho = np.arctan2(p5[:, 1], p5[:, 0]), np.hypot(p5[:, 0], p5[:, 1])
    ratio = np.where(rho > 0.0, d4 / np.where(rho > 0.0, rho, 1.0), np.nan)
    ok = np.abs(ratio) <= _CLIP
    lean = np.arcsin(np.clip(ratio, -1.0, 1.0))
    out = np.full((m, 2, 2, 2, 6), np.nan)
    for i, t1 in enumerate((phi + lean, phi + np.pi - lean)):
        t1 = np.where(ok, t1, np.nan)
        z1 = np.column_stack([np.sin(t1), -np.cos(t1), np.zeros(m)])  # frame 1's z in the base
        c5 = (np.einsum("mi,mi->m", p, z1) - d4) / d6
        r01 = _dh(t1, d1, 0.0, np.pi / 2)[:, :3, :3]
        r16 = np.einsum("mji,mjk->mik", r01, r)
        p16 = np.einsum("mji,mj->mi", r01, p - np.array([0.0, 0.0, d1]))
        for f in range(2):
            s = 1.0 if f == 0 else -1.0
            t5 = s * _acos(c5)
            s5 = np.sin(t5)
            small = np.abs(s5) < 1e-12
            s5 = np.where(small, np.nan, s5)
            t6 = np.arctan2(-r16[:, 2, 1] / s5, r16[:, 2, 0] / s5)
            t234 = np.arctan2(-r16[:, 1, 2] / s5, -r16[:, 0, 2] / s5)
            p14 = (p16 - d6 * r16[:, :, 2]
                   - d5 * np.column_stack([np.sin(t234), -np.cos(t234), np.zeros(m)]))
            x, y = p14[:, 0], p14[:, 1]
            c3 = (x * x + y * y - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
            for j, sgn in enumerate((1.0, -1.0)):
                t3 = sgn * _acos(c3)
                t2 = np.arctan2(y, x) - np.arctan2(a3 * np.sin(t3), a2 + a3 * np.cos(t3))
                out[:, i, j, f] = np.column_stack([t1, t2, t3, t234 - t2 - t3, t5, t6])
    return out.reshape(m, BRANCHES, 6)


def link_frames(arm: Arm, q_deg: np.ndarray) -> np.ndarray:
    """The DH frames 0..6 (..., 7, 4, 4) in the robot's base frame (mm) of joint angles (..., 6) (deg):
    frame i moves with link i (frame 0 the base's)."""
    theta = theta_of(arm, q_deg)
    t = np.broadcast_to(np.eye(4), theta.shape[:-1] + (4, 4)).copy()
    t[..., :3, :3] = arm.base
    out = [t]
    for i in range(6):
        d, a, alpha = arm.dh[i]
        t = t @ _dh(theta[..., i], d, a, np.radians(alpha))
        out.append(t)
    return np.stack(out, axis=-3)
