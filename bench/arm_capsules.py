"""The capsules of winder.config.arms (each link's body for the collision check, winder.machine.links)
fitted to ROS-Industrial's collision meshes: `python -m bench.arm_capsules ROOT` with ROOT holding
clones of ros-industrial/kuka_experimental, abb_experimental and universal_robot.

Each link's mesh is placed by its URDF chain at all joints zero, brought into the link's DH frame
(winder.machine.arm_ik.link_frames at zero), and bounded by a capsule: the segment along the vertices'
principal axis, the radius the farthest vertex from it (every vertex inside, the caps included).
Prints the numbers to copy into winder.config.arms.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np


def _rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def _t(xyz=(0, 0, 0), rpy=(0, 0, 0)) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = _rpy(*rpy), np.asarray(xyz, dtype=float) * 1000.0
    return out


PI = np.pi
# (mesh, the joint origins from the base (URDF <joint><origin>), the mesh's own origin), zero pose
CHAINS = {
    "kuka_kr16": ("kuka_experimental/kuka_kr16_support/meshes/kr16_2/collision/{}.stl",
                  [_t((0, 0, 0.675)), _t((0.26, 0, 0)), _t((0.68, 0, 0)), _t((0.67, 0, -0.035)), _t(), _t()],
                  [_t()] * 7, ["base_link"] + [f"link_{i}" for i in range(1, 7)]),
    "abb_irb4600": ("abb_experimental/abb_irb4600_support/meshes/{}.stl",
                    [_t((0, 0, 0.495)), _t((0.175, 0, 0)), _t((0, 0, 0.9)), _t((0, 0, 0.175)), _t((0.96, 0, 0)),
                     _t((0.135, 0, 0))], [_t()] * 7,
                    ["irb4600/collision/base_link", "irb4600/collision/link_1"]
                    + [f"irb4600_60_205/collision/link_{i}" for i in range(2, 7)]),
    # base_link_inertia is DH frame 0 (base_link, ROS's, is it turned 180 deg about z)
    "ur10e": ("universal_robot/ur_description/meshes/ur10e/collision/{}.stl",
              [_t((0, 0, 0.1807)), _t(rpy=(PI / 2, 0, 0)), _t((-0.6127, 0, 0)), _t((-0.57155, 0, 0.17415)),
               _t((0, -0.11985, 0), (PI / 2, 0, 0)), _t((0, 0.11655, 0), (PI / 2, PI, PI))],
              [_t(rpy=(0, 0, PI)), _t(rpy=(0, 0, PI)), _t((0, 0, 0.1762), (PI / 2, 0, -PI / 2)),
               _t((0, 0, 0.0393), (PI / 2, 0, -PI / 2)), _t((0, 0, -0.135), (PI / 2, 0, 0)), _t((0, 0, -0.12)),
               _t((0, 0, -0.1168), (PI / 2, 0, 0))],
              ["base", "shoulder", "upperarm", "forearm", "wrist1", "wrist2", "wrist3"]),
}


def capsule(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """(end a, end b, radius) of a capsule holding every point (n, 3)."""
    centre = points.mean(axis=0)
    axis = np.linalg.svd(points - centre, full_matrices=False)[2][0]
    s = (points - centre) @ axis
    a, b = centre + s.min() * axis, centre + s.max() * axis
    seg = b - a
    u = np.clip(((points - a) @ seg) / (seg @ seg), 0.0, 1.0)
    radius = float(np.max(np.linalg.norm(points - (a + u[:, None] * seg), axis=1)))
    return a, b, radius


def main(root: str) -> None:
    import trimesh

    from winder.config.arms import ARMS
    from winder.machine.arm_ik import link_frames

    for name, (pattern, joints, origins, meshes) in CHAINS.items():
        dh = link_frames(ARMS[name], np.zeros(6))
        frame = np.eye(4)
        print(name)
        for k, mesh in enumerate(meshes):
            if k:
                frame = frame @ joints[k - 1]
            v = trimesh.load(Path(root) / pattern.format(mesh), force="mesh").vertices * 1000.0
            v = (frame @ origins[k] @ np.column_stack([v, np.ones(len(v))]).T).T[:, :3]
            local = (np.linalg.inv(dh[k]) @ np.column_stack([v, np.ones(len(v))]).T).T[:, :3]
            a, b, r = capsule(local)
            print(f"  link {k}: capsule=({tuple(np.round(a).astype(int).tolist())}, "
                  f"{tuple(np.round(b).astype(int).tolist())}), radius={np.ceil(r):.0f}")


if __name__ == "__main__":
    main(sys.argv[1])
