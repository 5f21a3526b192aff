"""The job CSV `<name>.csv` of `winder run` (SPEC.md "Output files"): every point of every pass.

Columns: layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg,kind
- layer, circuit: 1-based; pass: FiberPass.number (1-based, the pass within its layer, in winding
  order); i: the point's index within its pass (0-based).
- t: axial station (mm); theta_deg: the planned contact angle, unwrapped (never reduced modulo 360);
  x, y, z: mandrel-frame point (mm); alpha_deg: signed winding angle from the meridian (deg), a
  line angle in (-90, 90]: a value that prints as -90.000000 is written as 90.000000 (the same
  line), so the file never depends on the round-off sign of a fiber running along a parallel.
- kind: forward, return, dwell or hoop.
Rows in winding order; numbers with 6 decimals, "-0.000000" written as "0.000000".
"""

from __future__ import annotations

import io
import re

import numpy as np

from winder.winding.results import WindingPlan

HEADER = "layer,circuit,pass,i,t,theta_deg,x,y,z,alpha_deg,kind"
DECIMALS = 6
PERIODIC_COLUMNS = {"alpha_deg": 180.0}  # line angles: alpha and alpha + 180 are the same fiber line
_NEG_ZERO = re.compile(r"(?<![0-9])-(0\.0+)(?![0-9])")


def line_angle_deg(alpha_deg: np.ndarray, decimals: int) -> np.ndarray:
    """alpha (m,) deg with the values that round to -90 at `decimals` moved to +90: (-90, 90]."""
    alpha = np.asarray(alpha_deg, dtype=float)
    return np.where(np.round(alpha, decimals) <= -90.0, alpha + 180.0, alpha)


def job_csv_text(plan: WindingPlan) -> str:
    """The CSV text: the header, then one row per point of every pass, in winding order."""
    buf = io.StringIO()
    buf.write(HEADER + "\n")
    num = f"%.{DECIMALS}f"
    for layer in plan.layers:
        for fp in layer.passes:
            m = len(fp.t)
            if m == 0:
                continue
            table = np.column_stack([np.full(m, fp.layer), np.full(m, fp.circuit), np.full(m, fp.number),
                                     np.arange(m), fp.t, np.degrees(fp.theta), fp.points,
                                     line_angle_deg(fp.alpha_deg, DECIMALS)])
            fmt = ",".join(["%d"] * 4 + [num] * 6) + "," + fp.kind.value.replace("%", "%%")
            np.savetxt(buf, table, fmt=fmt)
    return _NEG_ZERO.sub(r"\1", buf.getvalue())


def export(plan: WindingPlan, job) -> str:
    """The registry's entry (winder.export.registry)."""
    return job_csv_text(plan)
