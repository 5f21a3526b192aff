"""A `contour` dome's points (docs/math/17-vessels-as-built.md 17.1): given in the config, or read from a
CSV of `z,r` or a DXF meridian (LINE, ARC, LWPOLYLINE, SPLINE, ELLIPSE entities chained end to end, x = z,
y = r), a `file:` relative to the config's own folder.

The points are checked here, before any computation, each refusal naming the point: the first at the
junction with the cylinder (z = 0, r = R), z increasing strictly, r never rising toward the pole by more
than the tolerance (a fold), the first stretch meeting the cylinder within KINK_DEG. The smoothing to a C2
meridian is winder.geometry.contour's.
"""

from __future__ import annotations

import csv
import io
import math
import os
from typing import Any

import numpy as np

from winder.config.files import checked_size, read_text
from winder.config.reader import Reader, show_value

CONTOUR_TOLERANCE = 0.01  # mm: default largest distance of a smoothed contour from its points
MAX_CONTOUR_TOLERANCE = 5.0  # mm: beyond, the smoothing would be redrawing the liner
KINK_DEG = 0.5  # the largest angle at which a contour may meet the cylinder (SPEC: tangentially)
MIN_POINTS = 4
MAX_POINTS = 20_000
JOIN_TOL = 1e-3  # mm: DXF entities whose ends are this close are one chain
ARC_STEP = 1.0 / 40.0  # rad: points along a DXF arc or ellipse, at most this far apart
ARC_MM = 1.0  # mm: and at most this far apart
SPLINE_POINTS = 16  # points per control point along a DXF spline
MAX_DXF_BYTES = 20_000_000

Points = tuple[tuple[float, float], ...]


def parse_contour(rd: Reader, m: dict[str, Any], path: str, radius: float, radius_path: str,
                  opening: float | None, shaft: float | None) -> tuple[Points, tuple[str, ...], float]:
    """(points, labels, tolerance) of a contour dome (module docstring)."""
    tolerance = CONTOUR_TOLERANCE
    if "tolerance" in m:
        tolerance = rd.positive(m["tolerance"], rd.at(path, "tolerance"))
        if tolerance > MAX_CONTOUR_TOLERANCE:
            raise rd.error(rd.at(path, "tolerance"), f"must be <= {MAX_CONTOUR_TOLERANCE:g} mm (the largest "
                           f"distance of the smoothed meridian from the drawing's points)", m["tolerance"])
    if ("points" in m) == ("file" in m):
        raise rd.error(rd.at(path, "points"), "give points or file (a .csv of z,r or a .dxf), exactly one")
    if "layer" in m and not str(m.get("file", "")).lower().endswith(".dxf"):
        raise rd.error(rd.at(path, "layer"), "names a DXF layer: only with file: a .dxf", m["layer"])
    if "points" in m:
        key = rd.at(path, "points")
        items = rd.listing(m["points"], key, MIN_POINTS, "point")
        if len(items) > MAX_POINTS:
            raise rd.error(key, f"must have at most {MAX_POINTS} points", f"{len(items)} points")
        pts = []
        for i, item in enumerate(items):
            where = rd.at(key, i)
            if not isinstance(item, list) or len(item) != 2:
                raise rd.error(where, "must be a pair [z, r] (mm)", item)
            pts.append((rd.number(item[0], where), rd.number(item[1], where)))
        labels = tuple(rd.at(key, i) for i in range(len(pts)))
        where_key = key
    else:
        where_key = rd.at(path, "file")
        name = rd.text(m["file"], where_key)
        full = os.path.join(os.path.dirname(rd.source), name) if not os.path.isabs(name) else name
        if name.lower().endswith(".csv"):
            pts, labels = _read_csv(rd, full, name, where_key)
        elif name.lower().endswith(".dxf"):
            layer = rd.text(m["layer"], rd.at(path, "layer")) if "layer" in m else None
            pts, labels = _read_dxf(rd, full, name, where_key, layer)
        else:
            raise rd.error(where_key, "must be a .csv (columns z,r) or a .dxf (the meridian)", name)
    _check(rd, np.asarray(pts, dtype=float), labels, where_key, "points" in m, radius, radius_path, tolerance,
           opening, shaft)
    return tuple(pts), tuple(labels), tolerance


def _refuse(rd: Reader, key: str, labels, i: int, pts: np.ndarray, in_config: bool, what: str):
    """The error naming point i: its key path in the config, or its place in the file."""
    if in_config:
        return rd.error(labels[i], what, [float(v) for v in pts[i]])
    return rd.error(key, f"{labels[i]} (z = {pts[i, 0]:.6g}, r = {pts[i, 1]:.6g}): {what}")


def _check(rd: Reader, pts: np.ndarray, labels, key: str, in_config: bool, radius: float, radius_path: str,
           tol: float, opening: float | None, shaft: float | None) -> None:
    if pts.shape[0] < MIN_POINTS:
        raise rd.error(key, f"a contour needs at least {MIN_POINTS} points", f"{pts.shape[0]}")
    if abs(pts[0, 0]) > tol or abs(pts[0, 1] - radius) > tol:
        raise _refuse(rd, key, labels, 0, pts, in_config, f"the first point must be the dome's junction with the "
                      f"cylinder, z = 0 and r = {radius_path} ({show_value(radius)}), within the tolerance {tol:g} mm")
    dz = np.diff(pts[:, 0])
    if np.any(dz <= 0.0):
        i = int(np.argmax(dz <= 0.0)) + 1
        raise _refuse(rd, key, labels, i, pts, in_config, f"not monotone in z: z must increase from point to point "
                      f"toward the pole (the previous point has z = {pts[i - 1, 0]:.6g})")
    if np.any(pts[:, 1] < 0.0):
        i = int(np.argmax(pts[:, 1] < 0.0))
        raise _refuse(rd, key, labels, i, pts, in_config, "r must be >= 0")
    rise = pts[1:, 1] - np.minimum.accumulate(pts[:-1, 1])
    if np.any(rise > tol):
        i = int(np.argmax(rise > tol)) + 1
        raise _refuse(rd, key, labels, i, pts, in_config, f"the contour folds back outward: r rises toward the pole "
                      f"by {rise[i - 1]:.4g} mm (a dome's radius must fall from the cylinder to the opening)")
    kink = equator_angle_deg(pts)
    if kink > KINK_DEG:
        raise _refuse(rd, key, labels, 1, pts, in_config, f"meets the cylinder at a kink of {kink:.3g} deg (the "
                      f"dome must leave the cylinder tangentially, within {KINK_DEG:g} deg)")
    stop = shaft if shaft is not None else opening
    last = float(pts[-1, 1])
    if stop is not None and last > stop + tol:
        what = "the shaft_radius" if shaft is not None else "the polar_opening"
        raise _refuse(rd, key, labels, pts.shape[0] - 1, pts, in_config, f"the contour ends at r = {last:.6g}, "
                      f"outside {what} ({stop:g}): it must reach it")
    if stop is None and last <= 0.0:
        raise _refuse(rd, key, labels, pts.shape[0] - 1, pts, in_config, "the contour reaches the axis: a closed "
                      "end needs polar_opening: 0 and shaft_radius (the shaft the fibers turn around)")


def equator_angle_deg(pts: np.ndarray) -> float:
    """The angle (deg) between the axis and the contour's tangent at its first point: the slope dr/dz of
    the parabola through the first three points (second-order one-sided; z is the natural abscissa
    next to the cylinder, where the meridian runs along the axis)."""
    z, r = np.asarray(pts[:3], dtype=float).T
    h1, h2 = z[1] - z[0], z[2] - z[1]
    w = np.array([-(2.0 * h1 + h2) / (h1 * (h1 + h2)), (h1 + h2) / (h1 * h2), -h1 / (h2 * (h1 + h2))])
    return math.degrees(math.atan(abs(float(w @ r))))


def _read_csv(rd: Reader, full: str, name: str, key: str) -> tuple[list, list]:
    text = read_text(full, f"{rd.source}: {key}: {name}", kind="contour file")
    rows = list(csv.reader(io.StringIO(text)))
    rows = [(n, row) for n, row in enumerate(rows, start=1) if row and any(c.strip() for c in row)]
    if not rows or [c.strip().lower() for c in rows[0][1]] != ["z", "r"]:
        raise rd.error(key, f"{name}: the first line must be the header z,r", name)
    pts, labels = [], []
    for n, row in rows[1:]:
        try:
            if len(row) != 2:
                raise ValueError
            z, r = float(row[0]), float(row[1])
            if not (math.isfinite(z) and math.isfinite(r)):
                raise ValueError
        except ValueError as exc:
            raise rd.error(key, f"{name} line {n}: must be two finite numbers z,r", ",".join(row)) from exc
        pts.append((z, r))
        labels.append(f"{name} line {n}")
    if len(pts) > MAX_POINTS:
        raise rd.error(key, f"{name}: must have at most {MAX_POINTS} points", f"{len(pts)} points")
    return pts, labels


def _read_dxf(rd: Reader, full: str, name: str, key: str, layer: str | None) -> tuple[list, list]:
    checked_size(full, f"{rd.source}: {key}: {name}", kind="DXF drawing", limit=MAX_DXF_BYTES)
    import ezdxf  # noqa: PLC0415 - only a DXF contour needs it

    try:
        doc = ezdxf.readfile(full)
    except (OSError, ezdxf.DXFError) as exc:
        raise rd.error(key, f"{name}: not a readable DXF drawing ({exc})") from exc
    pieces = []
    for entity in doc.modelspace():
        if layer is not None and entity.dxf.layer != layer:
            continue
        pieces.extend(_entity_points(entity))
    if not pieces:
        where = f"on layer {layer!r}" if layer is not None else "in the model space"
        raise rd.error(key, f"{name}: no LINE, ARC, LWPOLYLINE, SPLINE or ELLIPSE {where}")
    chain = _chain(rd, key, name, pieces)
    if chain.shape[0] > MAX_POINTS:
        raise rd.error(key, f"{name}: the meridian has more than {MAX_POINTS} points", f"{chain.shape[0]}")
    return [tuple(map(float, p)) for p in chain], [f"{name} point {i}" for i in range(chain.shape[0])]


def _entity_points(entity) -> list[np.ndarray]:
    """The points of one entity in its own order, (m, 2) each (a polyline: one piece per segment)."""
    kind = entity.dxftype()
    if kind == "LINE":
        return [np.array([_xy(entity.dxf.start), _xy(entity.dxf.end)])]
    if kind == "LWPOLYLINE":
        out = []
        for sub in entity.virtual_entities():
            out.extend(_entity_points(sub))
        return out
    if kind in ("ARC", "ELLIPSE"):
        if kind == "ARC":
            span = math.radians((entity.dxf.end_angle - entity.dxf.start_angle) % 360.0 or 360.0)
        else:
            span = (entity.dxf.end_param - entity.dxf.start_param) % (2.0 * math.pi) or 2.0 * math.pi
        tool = entity.construction_tool()
        size = entity.dxf.radius if kind == "ARC" else float(np.linalg.norm(np.asarray(entity.dxf.major_axis)[:2]))
        n = max(8, int(math.ceil(span / ARC_STEP)), int(math.ceil(span * size / ARC_MM)))
        if kind == "ARC":
            angles = np.degrees(math.radians(entity.dxf.start_angle) + np.linspace(0.0, span, n + 1))
            return [np.array([_xy(p) for p in tool.vertices(angles)])]
        params = entity.dxf.start_param + np.linspace(0.0, span, n + 1)
        return [np.array([_xy(p) for p in tool.vertices(params)])]
    if kind == "SPLINE":
        tool = entity.construction_tool()
        n = max(64, SPLINE_POINTS * len(tool.control_points))
        return [np.array([_xy(p) for p in tool.approximate(n)])]
    return []


def _xy(p) -> tuple[float, float]:
    return (float(p[0]), float(p[1]))


def _chain(rd: Reader, key: str, name: str, pieces: list[np.ndarray]) -> np.ndarray:
    """The pieces joined end to end into one chain from its end of least x (the junction, z = 0)."""
    ends = [(p[0, 0], i, False) for i, p in enumerate(pieces)] + [(p[-1, 0], i, True) for i, p in enumerate(pieces)]
    _, first, flip = min(ends)
    chain = [pieces[first][::-1] if flip else pieces[first]]
    left = set(range(len(pieces))) - {first}
    while left:
        tip = chain[-1][-1]
        gap, i, flip = min([(float(np.hypot(*(pieces[i][0] - tip))), i, False) for i in left]
                           + [(float(np.hypot(*(pieces[i][-1] - tip))), i, True) for i in left])
        if gap > JOIN_TOL:
            raise rd.error(key, f"{name}: the entities are not one chain: the meridian stops at (x, y) = "
                           f"({tip[0]:.6g}, {tip[1]:.6g}), {gap:.4g} mm from the nearest other entity")
        chain.append((pieces[i][::-1] if flip else pieces[i])[1:])
        left.remove(i)
    pts = np.concatenate(chain)
    keep = np.concatenate([[True], np.hypot(*np.diff(pts, axis=0).T) > JOIN_TOL])
    return pts[keep]
