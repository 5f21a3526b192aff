"""The layup `<name>.layup.csv` of `winder run --format layup` (docs/math/08-laminate-edges.md), for
finite-element models: each layer's thickness and fiber angle over the surface it was wound on.

Columns: layer,t,theta_deg,x,y,z,angle_deg,thickness_mm
- layer: 1-based. t: axial station (mm); theta_deg: angle around the axis, [0, 360).
- x, y, z: the point on the surface the layer was wound on (the mandrel grown by the layers below:
  the layer's inner face); the layer's material lies outward along the surface normal from there.
- angle_deg: the fiber's winding angle from the meridian there (deg, [0, 90]): the layer is a
  +angle / -angle pair of plies (one ply direction for hoops); the mean over the bands crossing
  the station, weighted by fiber length.
- thickness_mm: the layer's thickness there (docs/math/08-laminate-edges.md; at a vessel turnaround the band-width
  average). On surfaces of revolution it is the same all around a section; on others (bends,
  non-circular sections) the section's mean times the share of bands over that angle
  (buildup.share_around), so its mean around the section is the section's.
Stations every LAYUP_STEP_BANDS band widths (the laminate's cells, from the layer's own surface),
only where the layer lays fiber, placed symmetrically about the middle of its laid span (a mirrored part is
sampled alike at both ends); LAYUP_ANGLES angles around. Numbers with 6 decimals.
"""

from __future__ import annotations

import io
import re

import numpy as np

from winder.analysis.layup import station_rows
from winder.errors import ConfigError
from winder.export.job_csv import DECIMALS
from winder.winding.buildup import share_around
from winder.winding.results import WindingPlan

HEADER = "layer,t,theta_deg,x,y,z,angle_deg,thickness_mm"
LAYUP_ANGLES = 24  # 15 deg apart
_NEG_ZERO = re.compile(r"(?<![0-9])-(0\.0+)(?![0-9])")  # "-0.000000" is written "0.000000"


def _no_material(source: str) -> ConfigError:
    return ConfigError("required for --format layup (the layup needs the band's material for its "
                       "thickness)", file=source, key_path="winding.material")


def require_material(job) -> None:
    """Refuse `--format layup` of a job without a material before it is planned: ConfigError."""
    if not job.winding.has_laminate:
        raise _no_material(job.source)


def layup_csv_text(plan: WindingPlan, band_width: float) -> str:
    """The layup CSV text. A plan without a laminate (no winding.material) has none: ConfigError."""
    if not any(layer.laminate is not None for layer in plan.layers):
        raise _no_material(plan.source)
    buf = io.StringIO()
    buf.write(HEADER + "\n")
    num = f"%.{DECIMALS}f"
    theta = np.arange(LAYUP_ANGLES) * 2.0 * np.pi / LAYUP_ANGLES
    for layer in plan.layers:
        lam = layer.laminate
        if lam is None:
            continue
        pick = station_rows(lam.s, lam.thickness, band_width)
        if pick.size == 0:
            continue
        surface = plan.surface_of(layer.index)
        s = np.repeat(lam.s[pick], theta.size)
        th = np.tile(theta, pick.size)
        thick = np.repeat(lam.thickness[pick], theta.size)
        if not surface.is_revolution:  # bands bunch around bends and flat sides: count them
            thick = thick * share_around(surface, layer.passes, band_width, lam.s[pick], theta).ravel()
        table = np.column_stack([np.full(s.size, layer.index), np.repeat(lam.t[pick], theta.size),
                                 np.degrees(th), surface.points(s, th),
                                 np.repeat(np.nan_to_num(lam.angle_deg[pick]), theta.size),
                                 thick])
        np.savetxt(buf, table, fmt=",".join(["%d"] + [num] * 7))
    return _NEG_ZERO.sub(r"\1", buf.getvalue())


def export(plan: WindingPlan, job) -> str:
    """The registry's entry (winder.export.registry)."""
    return layup_csv_text(plan, job.winding.band_width)
