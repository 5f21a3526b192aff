"""The report's view of a robot cell (docs/math/10-robot-cell.md), in the cell frame: the arm's base,
the winding ring (the eye's circle), the flange's path over the program, and the mandrel's guide curve
as the arm holds it at the program's first pose and at its last."""

from __future__ import annotations

from typing import Any

import numpy as np

from winder.machine.cell import CellMotion
from winder.report.plotting import base_layout

MAX_PATH_POINTS = 4000  # of the flange's path drawn
RING_POINTS = 121
GUIDE_POINTS = 200


def _line(points: np.ndarray, name: str, color: str, width: float = 3.0, mode: str = "lines") -> dict[str, Any]:
    return {"type": "scatter3d", "mode": mode, "name": name, "x": points[:, 0].tolist(), "y": points[:, 1].tolist(),
            "z": points[:, 2].tolist(), "line": {"color": color, "width": width}, "marker": {"size": 6, "color": color}}


def cell_figure(motion: CellMotion, guide_x: np.ndarray) -> dict[str, Any]:
    """The figure (plotly dict) of a cell's motion; guide_x (n, 3) the guide curve in the mandrel frame."""
    cell = motion.cell
    base = cell.base.matrix()
    ring = cell.ring.matrix()
    radius = float(np.mean(motion.external[:, 2])) if motion.external.size else 0.0
    a = np.linspace(0.0, 2.0 * np.pi, RING_POINTS)
    circle = ring[:3, 3] + radius * (np.cos(a)[:, None] * ring[:3, 0] + np.sin(a)[:, None] * ring[:3, 1])
    step = max(1, motion.flange.shape[0] // MAX_PATH_POINTS)
    flange = (base @ motion.flange[::step])[:, :3, 3]
    data = [_line(base[None, :3, 3], f"{motion.arm.name} base", "#333333", mode="markers"),
            _line(circle, "winding ring: the eye's circle (E1)", "#d62728"),
            _line(flange, "flange path", "#1f77b4", 2.0)]
    for k, label in ((0, "first"), (-1, "last")):
        if motion.mandrel.shape[0]:
            held = base @ motion.mandrel[k]
            pts = guide_x @ held[:3, :3].T + held[:3, 3]
            data.append(_line(pts, f"mandrel axis at the {label} pose", "#2ca02c" if k == 0 else "#98df8a"))
    axis = {"showbackground": True, "backgroundcolor": "#f4f6f8", "gridcolor": "#d8dde3"}
    layout = base_layout("Robot cell: the arm carries the mandrel through the winding ring (cell frame, mm)", 640,
                         margin={"l": 0, "r": 0, "t": 60, "b": 0},
                         scene={"aspectmode": "data", "xaxis": dict(axis, title={"text": "x (mm)"}),
                                "yaxis": dict(axis, title={"text": "y (mm)"}),
                                "zaxis": dict(axis, title={"text": "z (mm)"})})
    return {"data": data, "layout": layout}
