"""`python -m bench.vessel_series`: how time and peak memory grow with the fiber length (issue 29).

A series of vessels of radius 100 to 400 mm, each the same job scaled (cylinder 2 R, isotensoid domes
with openings of 0.2 R, a 12 mm band: a helical layer at 13 deg and one at 20 deg, `slip: auto` with
friction 0.2, two hoops between them), as the issue's large vessel: the fiber length grows as R^2. Each job runs `winder run` in its own process
(every output written), which reports its wall time and peak memory (VmHWM, or the summed PSS of it
and its machine-stage workers where larger: bench.tree_memory); beside them
the work budget's memory estimate (winder.winding.budget) and the bytes written. The fitted exponents
say whether memory follows the output (the issue: peak memory grew as R^1.44 against the output's
R^1.07, 32x the bytes written at R 400). Writes bench/results/vessel_series.md (or -o) and prints it.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

from bench.tree_memory import run_sampled

RADII = (100, 200, 300, 400)
ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).resolve().parent / "results" / "vessel_series.md"

_CHILD = r"""
import json, os, resource, sys, time
from pathlib import Path
t0 = time.perf_counter()
from winder.app.jobs import run_job
from winder.app.validate import validate
cfg, out = sys.argv[1], sys.argv[2]
_, _, budget = validate(cfg)
report = run_job(cfg, out)
seconds = time.perf_counter() - t0
written = sum(p.stat().st_size for p in Path(out).iterdir())
# VmHWM: this process's own high-water mark (ru_maxrss of a spawned child also counts its parent's); the
# machine stage's forked workers: bench.tree_memory
peak_kb = next((int(line.split()[1]) for line in open("/proc/self/status") if line.startswith("VmHWM:")),
               resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
print(json.dumps({"status": report.status, "seconds": seconds, "fiber_mm": report.fiber_length_mm,
                  "peak_bytes": peak_kb * 1024,
                  "estimate_bytes": budget.memory_bytes, "points": budget.points, "written_bytes": written}))
"""


def vessel_config(radius: float) -> str:
    """The series' job at one radius (module docstring), as YAML."""
    r = float(radius)
    return (f"name: vessel_r{radius:g}\n"
            f"mandrel:\n  profile:\n    type: vessel\n    radius: {r:g}\n    cylinder_length: {2 * r:g}\n"
            f"    dome: {{type: isotensoid, polar_opening: {0.2 * r:g}}}\n"
            "winding:\n  band_width: 12\n  friction: 0.2\n  layers:\n"
            "    - {type: helical, angle: 13, slip: auto}\n    - {type: hoop, passes: 2}\n"
            "    - {type: helical, angle: 20, slip: auto}\n")


def run_one(radius: float, folder: Path) -> dict:
    """One job of the series in a fresh interpreter: its figures (module docstring)."""
    cfg = folder / f"vessel_r{radius:g}.yaml"
    cfg.write_text(vessel_config(radius), encoding="utf-8")
    out = folder / f"out_r{radius:g}"
    out.mkdir(exist_ok=True)
    done, tree = run_sampled([sys.executable, "-c", _CHILD, str(cfg), str(out)], cwd=ROOT,
                             env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    row = {"radius": radius, **json.loads(done.stdout.strip().splitlines()[-1])}
    row["peak_bytes"] = max(row["peak_bytes"], tree)
    return row


def slope(x: list[float], y: list[float]) -> float:
    """The exponent b of y = a x^b, least squares in logs."""
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def table(rows: list[dict]) -> str:
    """The series as a Markdown table, with the fitted growth exponents against the radius."""
    lines = ["| R (mm) | fiber (m) | time (s) | peak memory (MB) | budget estimate (MB) | estimate / peak | "
             "written (MB) | peak / written |", "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['radius']:g} | {r['fiber_mm'] / 1e3:.1f} | {r['seconds']:.2f} | "
                     f"{r['peak_bytes'] / 1e6:.0f} | {r['estimate_bytes'] / 1e6:.0f} | "
                     f"{r['estimate_bytes'] / r['peak_bytes']:.2f} | {r['written_bytes'] / 1e6:.1f} | "
                     f"{r['peak_bytes'] / r['written_bytes']:.1f} |")
    radii = [r["radius"] for r in rows]
    if len(rows) >= 2:
        grow = {name: slope(radii, [r[key] for r in rows]) for name, key in
                (("fiber", "fiber_mm"), ("time", "seconds"), ("peak memory", "peak_bytes"),
                 ("written", "written_bytes"))}
        lines.append("")
        lines.append("Growth with the radius (R^b, least squares): " +
                     ", ".join(f"{name} R^{b:.2f}" for name, b in grow.items()) + ".")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m bench.vessel_series", description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default=str(RESULTS), help="the Markdown file to write")
    p.add_argument("--radii", default=",".join(map(str, RADII)), help="comma-separated radii (mm)")
    args = p.parse_args(argv)
    radii = [float(v) for v in args.radii.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        rows = []
        for r in radii:
            rows.append(run_one(r, Path(tmp)))
            print(f"R {r:g}: {rows[-1]['seconds']:.2f} s, {rows[-1]['peak_bytes'] / 1e6:.0f} MB", file=sys.stderr)
    text = ("# Time and memory against fiber length: a vessel series\n\n" + (__doc__ or "").split("\n\n")[1] +
            "\n\n" + table(rows))
    Path(args.output).write_text(text, encoding="utf-8")
    print(text)
    return 0 if all(r["status"] == "ok" for r in rows) and not any(math.isnan(r["seconds"]) for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
