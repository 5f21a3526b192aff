"""`winder geodesic --json`'s `seconds` time the solve alone (docs/guide/conventions.md): not the interpreter's start, not
the first import of the routines the solver calls."""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

from winder.config.job import load_config
from winder.geometry.build import build_surface
from winder.paths.geodesic import geodesic

ROOT = Path(__file__).resolve().parent.parent.parent
ELBOW = ROOT / "configs" / "elbow.yaml"
START, END = (10.0, 0.0), (300.0, 90.0)  # t mm, deg: across the bend
POINTS = 1000
SECONDS_FACTOR = 2.0  # the reported time within this factor of the warm solve's (the bound)
REPEATS = 3


def _reported() -> float:
    args = [sys.executable, "-m", "winder", "geodesic", str(ELBOW), "--start", "10,0", "--end", "300,90",
            "--points", str(POINTS), "--json"]
    proc = subprocess.run(args, capture_output=True, text=True, check=True, cwd=ROOT)
    return float(json.loads(proc.stdout)["seconds"])


def _warm() -> float:
    surface = build_surface(load_config(ELBOW).mandrel)
    a, b = (START[0], START[1] * 3.141592653589793 / 180), (END[0], END[1] * 3.141592653589793 / 180)
    geodesic(surface, a, b, n=POINTS)  # the warm-up: imports and caches
    times = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        geodesic(surface, a, b, n=POINTS)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def test_reported_seconds_time_the_solve_alone():
    warm = _warm()
    reported = statistics.median(_reported() for _ in range(REPEATS))
    assert reported <= SECONDS_FACTOR * warm, (reported, warm)
