"""winder's marlin programs through fiberpath's own `simulate`, on fiberpath's examples.

For each example pair NAME.wind / NAME.yaml (the same job for both tools) in the bench folder:
winder plans NAME.yaml with machine.dialect marlin (an eye at a fixed radius where the config's
clearance envelope would move it: the mandrel's largest radius plus that clearance), writes its
program, and `fiberpath simulate --json` reads it. Reported side by side: whether fiberpath read
it, fiberpath's tow length against winder's planned fiber and the fiber `winder simulate` lays from
the same program, and the times (fiberpath's estimate of winder's program, fiberpath's own plan,
winder's winding_time_s from the dynamics). fiberpath counts every line as tow on a cylinder of the
header's diameter, so the length matches on cylinders only, and every eye move that lays no fiber
(an approach to a new layer) counts too.

fiberpath (AGPL) is only ever run as a separate program; it is optional: without it the script says
so and exits 0.

    python -m bench.fiberpath_simulate [--bench DIR] [--fiberpath EXE] [--json FILE] [NAME ...]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

from bench.fiberpath_jobs import EXAMPLES as BENCH  # one place says where fiberpath and its examples are
from bench.fiberpath_jobs import FIBERPATH


def fiberpath_exe(given: str | None) -> str | None:
    for cand in (given, str(FIBERPATH)):
        if cand and Path(cand).exists():
            return cand
    return None


def marlin_config(config: Path, out: Path) -> Path:
    """A copy of the job with machine.dialect marlin and a fixed eye radius."""
    from winder.config.job import load_config  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415

    data = yaml.safe_load(config.read_text())
    machine = data.setdefault("machine", {}) or {}
    data["machine"] = machine
    machine["dialect"] = "marlin"
    eye = machine.get("eye", {"clearance": 20.0})
    if "clearance" in eye:
        job = load_config(config)
        surface = build_surface(job.mandrel, job.source, job.name)
        s = np.linspace(0.0, surface.length, 2001)
        r = max(float(np.max(surface.radius(s, np.full(s.shape, a)))) for a in np.linspace(0, 2 * np.pi, 73))
        machine["eye"] = {"radius": round(r + float(eye["clearance"]), 3)}
    path = out / config.name
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def fiberpath_json(exe: str, *args: str) -> dict:
    proc = subprocess.run([exe, *args], capture_output=True, text=True)
    if proc.returncode != 0:
        return {"ok": False, "message": (proc.stderr.strip().splitlines() or ["?"])[-1]}
    return {"ok": True, **json.loads(proc.stdout)}


def measure(name: str, bench: Path, exe: str) -> dict:
    from winder.app.simulate import simulate  # noqa: PLC0415
    from winder.config.job import load_config  # noqa: PLC0415
    from winder.export.gcode import gcode_text  # noqa: PLC0415
    from winder.machine.program import build_program  # noqa: PLC0415
    from winder.winding.plan import plan  # noqa: PLC0415

    with tempfile.TemporaryDirectory(prefix=f"fpjobs-{name}-") as tmp:
        work = Path(tmp)
        job = load_config(marlin_config(bench / f"{name}.yaml", work))
        p = plan(job)
        text = gcode_text(p, job.machine, job.winding.band_width)
        program = work / f"{name}.gcode"
        program.write_text(text)
        sim = fiberpath_json(exe, "simulate", "--json", str(program))
        own = fiberpath_json(exe, "plan", str(bench / f"{name}.wind"), "-o", str(work / "fp.gcode"), "--json")
        laid = simulate(job.machine, p, text, str(program))
        row = {"name": name, "fiberpath_read": sim["ok"], "winder_fiber_mm": p.total_fiber_length_mm,
               "winder_simulate_fiber_mm": laid.fiber_length_mm,
               "winder_winding_time_s": build_program(p, job.machine).times.total_s,
               "fiberpath_own_plan_time_s": own.get("timeSeconds"),
               "fiberpath_own_plan_tow_mm": own["towMeters"] * 1000.0 if own.get("ok") else None}
        if sim["ok"]:
            row.update(fiberpath_tow_mm=sim["tow_length_mm"], fiberpath_time_s=sim["estimated_time_s"],
                       tow_ratio=sim["tow_length_mm"] / p.total_fiber_length_mm)
        else:
            row["fiberpath_message"] = sim["message"]
        return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*")
    ap.add_argument("--bench", type=Path, default=BENCH)
    ap.add_argument("--fiberpath", default=None)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    exe = fiberpath_exe(args.fiberpath)
    if exe is None:
        print("fiberpath is not installed: nothing to compare (pip install fiberpath in its own venv)")
        return 0
    names = args.names or sorted(p.stem for p in args.bench.glob("*.wind") if p.with_suffix(".yaml").exists())
    rows = [measure(n, args.bench, exe) for n in names]
    print("| example | fiberpath reads it | fiberpath tow mm | winder fiber mm | ratio | winder simulate mm "
          "| winder winding_time_s | fiberpath estimate of it s | fiberpath own plan s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        ok = "yes" if r["fiberpath_read"] else f"no: {r.get('fiberpath_message')}"
        tow = f"{r['fiberpath_tow_mm']:.1f}" if r["fiberpath_read"] else "-"
        ratio = f"{r['tow_ratio']:.4f}" if r["fiberpath_read"] else "-"
        fpt = f"{r['fiberpath_time_s']:.1f}" if r["fiberpath_read"] else "-"
        own = "-" if r["fiberpath_own_plan_time_s"] is None else f"{r['fiberpath_own_plan_time_s']:.1f}"
        print(f"| {r['name']} | {ok} | {tow} | {r['winder_fiber_mm']:.1f} | {ratio} "
              f"| {r['winder_simulate_fiber_mm']:.1f} | {r['winder_winding_time_s']:.1f} | {fpt} | {own} |")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0 if all(r["fiberpath_read"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
