"""Comparing a binary PLY with its reference (winder.app.compare for the other formats).

The PLY stores vertex coordinates as float32: the computation's round-off (REL_NOISE, about 1e-12 of
a segment across numpy releases and BLAS builds) flips the last bit of a few of them (7 of 31,060 on
the vessel_hemi sample between the oldest and the newest releases pyproject.toml allows). So the
header, the faces and every integer property must match exactly, and each float property within one
unit in the last place of the vertex's largest coordinate (the float's spacing there), as the text formats are compared at
their printed digits. A file whose header cannot be read is compared byte for byte.
"""

from __future__ import annotations

import numpy as np

from winder.app.compare import MAX_SHOWN, PRINT_SLACK, REL_NOISE, Difference, _Collector

_END = b"end_header\n"
_TYPES = {"char": "i1", "uchar": "u1", "short": "<i2", "ushort": "<u2", "int": "<i4", "uint": "<u4",
          "float": "<f4", "double": "<f8", "int8": "i1", "uint8": "u1", "int16": "<i2", "uint16": "<u2",
          "int32": "<i4", "uint32": "<u4", "float32": "<f4", "float64": "<f8"}


def _vertices(data: bytes) -> tuple[bytes, np.ndarray, bytes] | None:
    """(header, vertex records, the rest) of a little-endian binary PLY whose first element is the
    vertices with scalar properties; None for anything else."""
    end = data.find(_END)
    if end < 0:
        return None
    head = data[:end + len(_END)]
    try:
        lines = head.decode("ascii").splitlines()
    except UnicodeDecodeError:
        return None
    if "format binary_little_endian 1.0" not in lines:
        return None
    fields, count, in_vertex = [], None, False
    for line in lines:
        words = line.split()
        if words[:2] == ["element", "vertex"] and len(words) == 3 and count is None and words[2].isdigit():
            count, in_vertex = int(words[2]), True
        elif words[:1] == ["element"]:
            in_vertex = False
        elif in_vertex and words[:1] == ["property"]:
            if len(words) != 3 or words[1] not in _TYPES or any(words[2] == name for name, _ in fields):
                return None  # a list property in the vertices, or one named twice: compare the bytes
            fields.append((words[2], _TYPES[words[1]]))
    if count is None or not fields:
        return None
    dtype = np.dtype(fields)
    size = count * dtype.itemsize
    if len(data) < len(head) + size:
        return None
    return head, np.frombuffer(data, dtype, count, len(head)), data[len(head) + size:]


def compare_ply(expected: bytes, got: bytes, limit: int = MAX_SHOWN) -> tuple[list[Difference], int]:
    """Differences between two PLY files: header and faces exact, vertex floats within one unit in
    their last place plus REL_NOISE relative, other vertex properties exact (module docstring)."""
    if expected == got:
        return [], 0
    a, b = _vertices(expected), _vertices(got)
    out = _Collector(limit)
    if a is None or b is None:
        at = next((i for i, (x, y) in enumerate(zip(expected, got)) if x != y), min(len(expected), len(got)))
        out.add(f"byte {at}", f"{len(expected)} bytes", f"{len(got)} bytes", "binary files differ")
        return out.shown, out.count
    if a[0] != b[0]:
        out.add("header", a[0].decode("ascii", "replace").strip(), b[0].decode("ascii", "replace").strip())
        return out.shown, out.count
    va, vb = a[1], b[1]
    floats = [name for name in va.dtype.names if va[name].dtype.kind == "f"]
    # A coordinate's round-off is relative to the point's size, not to the coordinate: a rounded
    # zero comes out as -1.3e-12 or -3.8e-12 on a vertex 100 mm from the axis.
    scale = np.zeros(len(va), va[floats[0]].dtype if floats else np.float32)
    for name in floats:
        scale = np.maximum(scale, np.maximum(np.abs(va[name]), np.abs(vb[name])))
    with np.errstate(invalid="ignore"):
        tol = np.spacing(scale).astype(np.float64) * PRINT_SLACK + REL_NOISE * scale.astype(np.float64)
    for name in va.dtype.names:
        x, y = va[name], vb[name]
        if name in floats:
            xf, yf = x.astype(np.float64), y.astype(np.float64)
            bad = ~((np.abs(xf - yf) <= tol) | (np.isnan(xf) & np.isnan(yf)))
        else:
            bad = x != y
        for i in np.flatnonzero(bad):
            out.add(f"vertex {i}, property {name}", repr(x[i].item()), repr(y[i].item()))
    if a[2] != b[2]:
        at = next((i for i, (x, y) in enumerate(zip(a[2], b[2])) if x != y), min(len(a[2]), len(b[2])))
        out.add(f"faces, byte {at}", f"{len(a[2])} bytes", f"{len(b[2])} bytes", "the faces differ")
    return out.shown, out.count
