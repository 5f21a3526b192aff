"""The path CSV of `winder geodesic`: i,t,theta_deg,x,y,z (docs/guide/conventions.md), fixed precision."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from winder.export.atomic import write_atomic
from winder.paths.geodesic import GeodesicResult

HEADER = "i,t,theta_deg,x,y,z"


def path_csv_text(result: GeodesicResult) -> str:
    """The CSV text: one row per point, theta unwrapped, lengths in mm with 6 decimals."""
    buf = io.StringIO()
    buf.write(HEADER + "\n")
    table = np.column_stack([np.arange(result.t.shape[0]), result.t, np.degrees(result.theta), result.points])
    np.savetxt(buf, table, delimiter=",", fmt=["%d"] + ["%.6f"] * 5)
    # "-0.000000" and "0.000000" must not differ between platforms.
    return buf.getvalue().replace("-0.000000", "0.000000")


def write_path_csv(path: str | Path, result: GeodesicResult) -> None:
    write_atomic(path, path_csv_text(result))
