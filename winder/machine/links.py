"""The arm's links against the winding ring and the mandrel (docs/math/10-robot-cell.md 10.6), with the
Flexible Collision Library (python-fcl, through trimesh's CollisionManager).

Bodies, each a triangle mesh:
- every link (the base and links 1-6) a capsule in its DH frame (winder.config.arms: fitted to
  ROS-Industrial's collision meshes), grown by LINK_CLEARANCE plus half the sampling step below;
- the ring: an annulus about the ring's axis, its inner face RING_EYE beyond the eye's largest radius,
  machine.robot.positioner's depth (radial) and width (axial);
- the mandrel with its laminate (the outer surface of the finished part), carried by the flange.

The links are checked against the ring at every sampled row, and against the mandrel except the two
wrist links that carry its mount (links 5 and 6: the mount is part of them). Rows are sampled so that
no point of an arm's link moves more than SAMPLE_STEP between two samples (the joints' moves, in
radians, times the arm's span: a bound on any point's displacement), and the capsules are grown by
half of it. A collision is refused (ExportError) naming the link, the body, the layer and the pass.
"""

from __future__ import annotations

import numpy as np

from winder.config.arms import Arm
from winder.config.robot import RobotCell
from winder.machine.arm_ik import link_frames

LINK_CLEARANCE = 5.0  # mm every link keeps from the ring and the mandrel
SAMPLE_STEP = 20.0  # mm: the most any point of a link moves between two checked rows
RING_EYE = 20.0  # mm from the eye's largest radius to the ring's inner face (the eye's mount)
MANDREL_STEP = 10.0  # mm between the mandrel mesh's stations
MANDREL_ANGLES = 48
WRIST_LINKS = (5, 6)  # carry the mandrel's mount


def _capsule_meshes(arm: Arm, grow: float) -> list:
    """trimesh capsules (7) of the base and links 1-6, each along z from the origin, with the
    transforms (7, 4, 4) that put them on their segments in their DH frames."""
    import trimesh  # noqa: PLC0415

    meshes, local = [], []
    ends = [arm.body] + [k.capsule for k in arm.links]
    radii = [arm.body_radius] + [k.radius for k in arm.links]
    for (a, b), r in zip(ends, radii):
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        length = float(np.linalg.norm(b - a))
        meshes.append(trimesh.creation.capsule(height=length, radius=r + grow, count=(8, 8)))
        z = (b - a) / length if length > 0.0 else np.array([0.0, 0.0, 1.0])
        x = np.cross(z, [1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.cross(z, [0.0, 1.0, 0.0])
        x /= np.linalg.norm(x)
        t = np.eye(4)
        t[:3, :3] = np.column_stack([x, np.cross(z, x), z])
        t[:3, 3] = a  # trimesh's capsule runs from z = 0 to z = height
        local.append(t)
    return meshes, np.array(local)


def ring_mesh(cell: RobotCell, eye_radius: float):
    """The ring's annulus in the arm's base frame (module docstring)."""
    import trimesh  # noqa: PLC0415

    inner = eye_radius + RING_EYE
    ring = trimesh.creation.annulus(r_min=inner, r_max=inner + cell.ring_depth, height=cell.ring_width, sections=64)
    ring.apply_transform(np.linalg.inv(cell.base.matrix()) @ cell.ring.matrix())
    return ring


def mandrel_mesh(surface):
    """The outer surface of the part (mandrel and laminate) as a closed-in-angle grid, mandrel frame."""
    import trimesh  # noqa: PLC0415

    ns = max(int(np.ceil(surface.length / MANDREL_STEP)) + 1, 2)
    s = np.linspace(0.0, surface.length, ns)
    th = np.linspace(0.0, 2.0 * np.pi, MANDREL_ANGLES, endpoint=False)
    verts = surface.grid_points(s, th)
    row = (np.arange(ns - 1) * MANDREL_ANGLES)[:, None]
    j = np.arange(MANDREL_ANGLES)
    v00, v01 = (row + j).ravel(), (row + (j + 1) % MANDREL_ANGLES).ravel()
    faces = np.vstack([np.column_stack([v00, v01, v00 + MANDREL_ANGLES]),
                       np.column_stack([v01, v01 + MANDREL_ANGLES, v00 + MANDREL_ANGLES])])
    return trimesh.Trimesh(verts, faces, process=False)


def sampled_rows(frames: np.ndarray, lengths: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """The rows checked of the capsules' frames (m, 7, 4, 4) (each capsule along its z, lengths (7,),
    radii (7,)): the first, the last, and every row where the capsules' largest move since the last
    checked row would pass SAMPLE_STEP. A rigid capsule's points move at most as far as its axis's
    farther end, plus its radius times the angle it turns."""
    m = frames.shape[0]
    if m == 0:
        return np.zeros(0, dtype=int)
    a = frames[:, :, :3, 3]
    b = a + lengths[None, :, None] * frames[:, :, :3, 2]
    ends = np.maximum(np.linalg.norm(np.diff(a, axis=0), axis=2), np.linalg.norm(np.diff(b, axis=0), axis=2))
    turn = np.einsum("mkij,mkij->mk", frames[:-1, :, :3, :3], frames[1:, :, :3, :3])  # trace of R0^T R1
    angle = np.arccos(np.clip(0.5 * (turn - 1.0), -1.0, 1.0))
    moved = np.concatenate([[0.0], np.max(ends + radii[None, :] * angle, axis=1)])
    ticks = np.floor(np.cumsum(moved) / SAMPLE_STEP)
    rows = np.flatnonzero(np.diff(ticks, prepend=-1.0) > 0.0)
    return np.unique(np.concatenate([rows, [m - 1]]))


class LinkChecker:
    """The links, the ring and the mandrel in FCL; hits(joints, mandrel pose) names what touches."""

    def __init__(self, arm: Arm, cell: RobotCell, eye_radius: float, surface) -> None:  # noqa: PLR0914
        from trimesh.collision import CollisionManager  # noqa: PLC0415 - python-fcl

        self.arm = arm
        meshes, self.local = _capsule_meshes(arm, LINK_CLEARANCE + 0.5 * SAMPLE_STEP)
        self.lengths = np.array([np.linalg.norm(np.subtract(b, a)) for a, b in [arm.body] + [k.capsule for k in arm.links]])
        self.radii = np.array([arm.body_radius] + [k.radius for k in arm.links]) + LINK_CLEARANCE
        self.names = ["base"] + [f"link {k + 1} ({name})" for k, name in enumerate(arm.joint_names)]
        self.links = CollisionManager()
        self.carrying = CollisionManager()  # the links the mandrel is checked against
        for k, mesh in enumerate(meshes):
            self.links.add_object(self.names[k], mesh)
            if k not in WRIST_LINKS:
                self.carrying.add_object(self.names[k], mesh)
        self.ring = CollisionManager()
        self.ring.add_object("ring", ring_mesh(cell, eye_radius))
        self.mandrel = CollisionManager()
        extent = 0.0
        if surface is not None:
            mesh = mandrel_mesh(surface)
            self.mandrel.add_object("mandrel", mesh)
            extent = float(np.max(np.linalg.norm(mesh.vertices, axis=1)))
        # the farthest any carried point can be from the base's origin: every link, the mount, the mandrel
        self.span = float(np.sum(np.abs(arm.dh[:, :2]))) + float(np.linalg.norm(cell.tool.matrix()[:3, 3])) + extent

    def capsule_frames(self, joints: np.ndarray) -> np.ndarray:
        """The capsules' frames (..., 7, 4, 4) at joints (..., 6)."""
        return link_frames(self.arm, joints) @ self.local

    def hits(self, joints: np.ndarray, mandrel: np.ndarray | None, frames: np.ndarray | None = None,
             swing: bool = False) -> tuple[str, str] | None:
        """(link, body) of the first contact at joints (6,) (or the capsules' frames (7, 4, 4)) with the
        mandrel at its pose (4, 4) in the base frame (None: the mandrel not checked), or None; swing:
        also the mandrel against the ring (off the winding's poses, which keep it in the ring's bore)."""
        frames = self.capsule_frames(joints) if frames is None else frames
        for k, name in enumerate(self.names):
            self.links.set_transform(name, frames[k])
            if k not in WRIST_LINKS:
                self.carrying.set_transform(name, frames[k])
        touch, pairs = self.links.in_collision_other(self.ring, return_names=True)
        if touch:
            return sorted(pairs)[0][0], "the ring"
        if mandrel is not None and self.mandrel._objs:
            self.mandrel.set_transform("mandrel", mandrel)
            touch, pairs = self.carrying.in_collision_other(self.mandrel, return_names=True)
            if touch:
                return sorted(pairs)[0][0], "the mandrel (with its laminate)"
            if swing and self.mandrel.in_collision_other(self.ring):
                return "the mandrel (with its laminate)", "the ring"
        return None


def check_links(checker: LinkChecker, joints: np.ndarray, mandrel: np.ndarray, where) -> None:
    """ExportError at the first sampled row (joints (m, 6), the mandrel's poses (m, 4, 4) in the base
    frame) where a link touches the ring or the mandrel; where(row) names the row's pass."""
    from winder.errors import ExportError  # noqa: PLC0415

    frames = checker.capsule_frames(joints)
    for row in sampled_rows(frames, checker.lengths, checker.radii).tolist():
        hit = checker.hits(joints[row], mandrel[row], frames[row])
        if hit is not None:
            link, body = hit
            raise ExportError(f"{where(row)}, program row {row}: the {checker.arm.name}'s {link} comes within "
                              f"{LINK_CLEARANCE:g} mm of {body} (its capsule, {checker.arm.capsule_source}); move "
                              f"the ring (machine.robot.positioner.origin), the arm's base or the mandrel's mount "
                              f"(machine.robot.tool)")


def joint_move_clear(checker: LinkChecker, tool: np.ndarray, before: np.ndarray, after: np.ndarray) -> bool:
    """Whether the joint move from before (6,) to after (6,) keeps every link clear of the ring and the
    mandrel (carried by the flange, its mount tool (4, 4)), and the mandrel clear of the ring, at poses
    along it no point of which moves more than SAMPLE_STEP between two (the joints' move in radians
    times the farthest a carried point can be from the base)."""
    from winder.machine.arm_ik import fk  # noqa: PLC0415

    samples = int(np.ceil(np.sum(np.abs(np.radians(after - before))) * checker.span / SAMPLE_STEP)) + 2
    for f in np.linspace(0.0, 1.0, samples):
        q = before + f * (after - before)
        if checker.hits(q, fk(checker.arm, q) @ tool, swing=True) is not None:
            return False
    return True
