"""A whole job against fiberpath: the same cylinder, band and angle, both run as command-line
programs (fiberpath is AGPL: it is only ever run as a separate program, never imported), plus
winder's planner and G-code exporter timed in-process.

fiberpath needs its pattern number to divide its circuit count (19 for this cylinder, band and angle)
and a skip index below it; winder picks its pattern itself (pattern: auto). The two programs' other
options (fiberpath's lock and lead-in, winder's dwell) are not the same physical settings.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

from bench.fiberpath_jobs import FIBERPATH, compile_winder
from bench.settings import Settings
from bench.timing import interleaved

RADIUS, LENGTH, BAND, ANGLE, FEED = 50.0, 500.0, 10.0, 55.0, 3000.0

WIND = {
    "schemaVersion": "1.0",
    "mandrelParameters": {"diameter": 2 * RADIUS, "windLength": LENGTH},
    "towParameters": {"width": BAND, "thickness": 0.5},
    "defaultFeedRate": FEED,
    "layers": [{"windType": "helical", "windAngle": ANGLE, "patternNumber": 19, "skipIndex": 7,
                "lockDegrees": 180, "leadInMM": 10, "leadOutDegrees": 20}],
}

JOB_YAML = f"""name: bench_cylinder
mandrel:
  axis: {{type: line, length: {LENGTH:g}}}
  profile: {{type: constant, radius: {RADIUS:g}}}
winding:
  band_width: {BAND:g}
  points: 200
  dwell: {{start: 10, end: 10}}
  layers:
    - {{type: helical, angle: {ANGLE:g}, pattern: auto}}
machine:
  feed: {FEED:g}
"""


def _gcode_stats(text: str) -> dict[str, int]:
    return {"bytes": len(text.encode()), "lines": text.count("\n")}


def compare_job(settings: Settings, progress: Callable[[str], None]) -> dict[str, Any]:
    exe = str(FIBERPATH) if FIBERPATH.exists() else None  # one place says where fiberpath is
    compile_winder()  # both command lines from bytecode, as installed
    out: dict[str, Any] = {"job": {"radius_mm": RADIUS, "length_mm": LENGTH, "band_mm": BAND, "angle_deg": ANGLE,
                                   "feed_mm_min": FEED},
                           "fiberpath_wind": WIND, "winder_yaml": JOB_YAML, "notes": []}
    try:
        from winder.export.gcode import gcode_text  # noqa: PLC0415 - the exporter may be missing
        from winder.winding.plan import plan  # noqa: PLC0415
    except ImportError as exc:
        out["notes"].append(f"winder's planner or G-code exporter is missing ({exc}): whole-job comparison skipped")
        return out
    from winder.config.job import load_config  # noqa: PLC0415

    with tempfile.TemporaryDirectory(prefix="winder-bench-") as tmp:
        tmpd = Path(tmp)
        (tmpd / "cyl.wind").write_text(json.dumps(WIND, indent=2))
        (tmpd / "cyl.yaml").write_text(JOB_YAML)
        job = load_config(tmpd / "cyl.yaml")

        def in_process():
            p = plan(job)
            return p, gcode_text(p, job.machine)

        def command(args: list[str], what: str):
            def call():
                res = subprocess.run(args, capture_output=True, text=True, timeout=600, check=False)
                if res.returncode != 0:
                    raise RuntimeError(f"{what} failed: {(res.stderr or res.stdout).strip()[:300]}")
                return res
            return call

        winder_cli = command([sys.executable, "-m", "winder.cli", "run", str(tmpd / "cyl.yaml"), "-o",
                              str(tmpd / "w"), "--format", "gcode"], "winder run")
        # Start-up alone (interpreter and imports): --version prints and exits.
        winder_start = command([sys.executable, "-m", "winder.cli", "--version"], "winder --version")
        fiberpath_cli = command([str(exe), "plan", str(tmpd / "cyl.wind"), "-o", str(tmpd / "fp.gcode"), "--json"],
                                "fiberpath plan")
        fiberpath_start = command([str(exe), "--help"], "fiberpath --help")

        progress("job: winder plan + G-code (in-process)")
        t0 = time.perf_counter()
        p, text = in_process()
        first = time.perf_counter() - t0
        tasks = [("winder_in_process", in_process), ("winder_cli", winder_cli), ("winder_start", winder_start)]
        if exe is not None:
            tasks += [("fiberpath_cli", fiberpath_cli), ("fiberpath_start", fiberpath_start)]
        else:
            out["notes"].append("fiberpath is not installed (pip install fiberpath; AGPL, run only as a separate "
                                "program): its side of the comparison is skipped")
        progress("job: winder and fiberpath command lines, side by side")
        timed = interleaved(tasks, min(settings.repeats, 5), settings.min_repeats, settings.budget * 2)
        layer = p.layers[0]
        out["winder"] = {
            "first_run_seconds": first,
            "in_process_seconds": timed["winder_in_process"].median,
            "cli_seconds": timed["winder_cli"].median if timed["winder_cli"].ok else None,
            "cli_error": timed["winder_cli"].error,
            "startup_seconds": timed["winder_start"].median if timed["winder_start"].ok else None,
            "gcode": _gcode_stats(text),
            "circuits": layer.circuits, "pattern": layer.pattern, "angle_deg": layer.angle_deg,
            "fiber_length_m": sum(lp.fiber_length_mm for lp in p.layers) / 1000.0,
            "time_estimate_s": sum(lp.time_s for lp in p.layers),
        }
        wg = tmpd / "w" / "bench_cylinder.gcode"
        if wg.exists():
            out["winder"]["cli_gcode"] = _gcode_stats(wg.read_text())
        if exe is not None:
            t = timed["fiberpath_cli"]
            if t.ok:
                info = json.loads(t.value.stdout)
                gtext = (tmpd / "fp.gcode").read_text()
                st = timed["fiberpath_start"]
                out["fiberpath"] = {"cli_seconds": t.median, "gcode": _gcode_stats(gtext),
                                    "startup_seconds": st.median if st.ok else None,
                                    "fiber_length_m": info.get("towMeters"), "time_estimate_s": info.get("timeSeconds"),
                                    "commands": info.get("commands")}
            else:
                out["fiberpath"] = {"error": t.error}
                out["notes"].append(f"fiberpath failed: {t.error}")
    return out
