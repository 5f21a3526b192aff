"""The job CSV `<name>.csv` of `winder run` (docs/guide/conventions.md): every point of every pass.

Columns: layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg,kind
- layer, circuit: 1-based; pass: FiberPass.number (1-based, the pass within its layer, in winding
  order); i: the point's index within its pass (0-based).
- t: axial station (mm); theta_deg: the planned contact angle, unwrapped (never reduced modulo 360);
  x, y, z: mandrel-frame point (mm); alpha_deg: signed winding angle from the meridian (deg), a
  line angle in (-90, 90]: a value that prints as -90.000000 is written as 90.000000 (the same
  line), so the file never depends on the round-off sign of a fiber running along a parallel.
- kind: forward, return, turnaround, dwell or hoop (winder.winding.turnaround: the fiber past the
  winding region of an open mandrel, and the dwell where an end holds it).
Rows in winding order; numbers with 6 decimals, "-0.000000" written as "0.000000".
"""

from __future__ import annotations

import numpy as np

from winder.export.fixed_text import table_text
from winder.winding.results import WindingPlan

HEADER = "layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg,kind"
DECIMALS = 6
PERIODIC_COLUMNS = {"alpha_deg": 180.0}  # line angles: alpha and alpha + 180 are the same fiber line


def line_angle_deg(alpha_deg: np.ndarray, decimals: int) -> np.ndarray:
    """alpha (m,) deg with the values that round to -90 at `decimals` moved to +90: (-90, 90]."""
    alpha = np.asarray(alpha_deg, dtype=float)
    return np.where(np.round(alpha, decimals) <= -90.0, alpha + 180.0, alpha)


def job_csv_text(plan: WindingPlan) -> str:
    """The CSV text: the header, then one row per point of every pass, in winding order.

    All passes are formatted at once (winder.export.fixed_text: the same text as "%.6f" per value,
    at a fraction of the cost of formatting two million numbers one by one)."""
    passes = [fp for layer in plan.layers for fp in layer.passes if len(fp.t)]
    if not passes:
        return HEADER + "\n"
    sizes = np.array([len(fp.t) for fp in passes])
    kinds = sorted({fp.kind.value for fp in passes})
    per_pass = lambda values: np.repeat(np.asarray(values), sizes)  # noqa: E731
    points = np.concatenate([fp.points for fp in passes])
    columns = [
        (per_pass([fp.layer for fp in passes]), 0), (per_pass([fp.circuit for fp in passes]), 0),
        (per_pass([fp.number for fp in passes]), 0),
        (np.arange(sizes.sum()) - np.repeat(np.cumsum(sizes) - sizes, sizes), 0),
        (np.concatenate([fp.t for fp in passes]), DECIMALS),
        (np.degrees(np.concatenate([fp.theta for fp in passes])), DECIMALS),
        (points[:, 0], DECIMALS), (points[:, 1], DECIMALS), (points[:, 2], DECIMALS),
        (line_angle_deg(np.concatenate([fp.alpha_deg for fp in passes]), DECIMALS), DECIMALS),
    ]
    tail = per_pass([kinds.index(fp.kind.value) for fp in passes])
    return HEADER + "\n" + table_text(columns, tail, kinds)


def export(plan: WindingPlan, job) -> str:
    """The registry's entry (winder.export.registry)."""
    return job_csv_text(plan)
