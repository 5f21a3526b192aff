<<<<<<< HEAD
"""Whole jobs against fiberpath on its own examples, and start-up (issue 14).

Each example of shared/bench/fiberpath is a pair NAME.wind (fiberpath) and NAME.yaml (winder, the
same job). Per repeat the two tools run back to back as a user runs them (a fresh process, each its
own console script, all of winder's output files written), alternating who goes first so that the
machine's noise falls on both; figures are medians over the repeats. fiberpath is AGPL and is only
ever run as a separate program; without it (or without the examples) the section is skipped with a
note. Start-up: `winder --help` and `winder check` against `fiberpath --help` and a bare interpreter,
and the slowest imports of `import winder.cli` (`python -X importtime`).
=======
"""winder's marlin programs through fiberpath's own `simulate`, on fiberpath's examples.

For each example pair NAME.wind / NAME.yaml (the same job for both tools) in the bench folder:
winder plans NAME.yaml with machine.dialect marlin (an eye at a fixed radius where the config's
clearance envelope would move it: the mandrel's largest radius plus that clearance), writes its
program, and `fiberpath simulate --json` reads it. Reported side by side: whether fiberpath read
it, fiberpath's tow length against winder's planned fiber and the fiber `winder simulate` lays from
the same program, and the times (fiberpath's estimate of winder's program, fiberpath's own plan,
winder's winding_time_s from the dynamics). fiberpath counts every line as tow on a cylinder of the
header's diameter, so the length matches on cylinders only, and every eye move that lays no fiber
(the step back at a stop-and-go turnaround) counts too.

fiberpath (AGPL) is only ever run as a separate program; it is optional: without it the script says
so and exits 0.

    python -m bench.fiberpath_jobs [--bench DIR] [--fiberpath EXE] [--json FILE] [NAME ...]
>>>>>>> 76eabb9 (bench/fiberpath_jobs.py: winder's marlin programs through fiberpath's own simulate)
"""

from __future__ import annotations

<<<<<<< HEAD
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = Path(os.environ.get("WINDER_FIBERPATH_EXAMPLES", ROOT.parent / "shared" / "bench" / "fiberpath"))
FIBERPATH = Path(os.environ.get("WINDER_FIBERPATH", "/work/venv-fp/bin/fiberpath"))
WINDER = Path(sys.executable).parent / "winder"
CHECK_SAMPLE = ROOT / "samples" / "pipe.yaml"
TARGETS = {"motor_tube": 5.0, "avbay_triple": 5.0, "main_chute": 5.0, "avbay_single": 3.0,
           "simple_cylinder": 1.5, "multi_layer": 1.5}  # fiberpath time / winder time, issue 14
STARTUP_TARGETS = {"winder --help": 0.25, "winder check": 0.35}  # seconds


def _timed(argv: list[str]) -> tuple[float, str]:
    t0 = time.perf_counter()
    proc = subprocess.run(argv, capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} exited {proc.returncode}: {proc.stderr.strip()[-300:]}")
    return seconds, proc.stdout


def _job(name: str, repeats: int) -> dict[str, Any]:
    wind, config = EXAMPLES / f"{name}.wind", EXAMPLES / f"{name}.yaml"
    fp, wi = [], []
    with tempfile.TemporaryDirectory(prefix=f"winder-fp-{name}-") as tmp:
        out = Path(tmp)
        for k in range(repeats):
            for tool in (("fp", "w") if k % 2 == 0 else ("w", "fp")):
                if tool == "fp":
                    sec, _ = _timed([str(FIBERPATH), "plan", str(wind), "-o", str(out / f"{name}.gcode"), "--json"])
                    fp.append(sec)
                else:
                    shutil.rmtree(out / "w", ignore_errors=True)
                    sec, _ = _timed([str(WINDER), "run", str(config), "-o", str(out / "w")])
                    wi.append(sec)
    f, w = statistics.median(fp), statistics.median(wi)
    return {"name": name, "fiberpath_s": f, "winder_s": w, "ratio": f / w, "target": TARGETS.get(name),
            "fiberpath_runs_s": fp, "winder_runs_s": wi}


def startup(repeats: int) -> dict[str, float]:
    python = str(Path(sys.executable))
    runs = {"winder --help": [str(WINDER), "--help"], "winder check": [str(WINDER), "check", str(CHECK_SAMPLE)],
            "python -c pass": [python, "-c", "pass"], "python -c 'import numpy'": [python, "-c", "import numpy"]}
    if FIBERPATH.exists():
        runs["fiberpath --help"] = [str(FIBERPATH), "--help"]
    times: dict[str, list[float]] = {k: [] for k in runs}
    for _ in range(repeats):
        for key, argv in runs.items():
            times[key].append(_timed(argv)[0])
    return {k: statistics.median(v) for k, v in times.items()}


def import_profile(module: str = "winder.cli", top: int = 12) -> list[dict[str, Any]]:
    """The slowest imports of `module` by cumulative time: name, cumulative and self seconds."""
    proc = subprocess.run([sys.executable, "-X", "importtime", "-c", f"import {module}"], capture_output=True,
                          text=True)
    rows = []
    for line in proc.stderr.splitlines():
        if line.startswith("import time:") and "self [us]" not in line:
            own, cum, name = (part.strip() for part in line[len("import time:"):].split("|"))
            rows.append({"module": name, "cumulative_s": int(cum) / 1e6, "self_s": int(own) / 1e6})
    rows.sort(key=lambda r: -r["cumulative_s"])
    return rows[:top]


def measure(repeats: int = 5, names: list[str] | None = None, jobs: bool = True) -> dict[str, Any]:
    """Everything of this section, for results.json (jobs False: start-up and imports only)."""
    out: dict[str, Any] = {"startup_s": startup(repeats), "startup_targets_s": STARTUP_TARGETS,
                           "imports": import_profile()}
    if not jobs:
        out["note"] = "whole jobs against fiberpath: not in this run's settings"
        return out
    if not (FIBERPATH.exists() and EXAMPLES.is_dir()):
        out["note"] = f"fiberpath ({FIBERPATH}) or its examples ({EXAMPLES}) not found: whole jobs skipped"
        return out
    names = names or sorted(p.stem for p in EXAMPLES.glob("*.wind") if p.with_suffix(".yaml").exists())
    out["jobs"] = [_job(name, repeats) for name in names]
    return out


def markdown(data: dict[str, Any]) -> list[str]:
    """The section of RESULTS.md."""
    lines = ["## Whole jobs against fiberpath, and start-up", "",
             "Each example run as a user runs it (a fresh process, all output files written), fiberpath and "
             "winder alternating; medians of the repeats. Ratio: fiberpath's time over winder's (> 1: winder "
             "is faster); target: issue 14's.", ""]
    if "jobs" in data:
        lines += ["| example | fiberpath | winder | fiberpath / winder | target |", "|---|---:|---:|---:|---:|"]
        for j in data["jobs"]:
            tgt = f">= {j['target']:g}x" if j.get("target") else "-"
            lines.append(f"| {j['name']} | {j['fiberpath_s']:.3f} s | {j['winder_s']:.3f} s | {j['ratio']:.2f}x | {tgt} |")
        lines.append("")
    else:
        lines += [data.get("note", ""), ""]
    lines += ["| start-up | median | target |", "|---|---:|---:|"]
    for k, v in data["startup_s"].items():
        tgt = data["startup_targets_s"].get(k)
        lines.append(f"| `{k}` | {v:.3f} s | {'<= %.2f s' % tgt if tgt else '-'} |")
    lines += ["", "`python -X importtime -c 'import winder.cli'`, slowest by cumulative time:", "",
              "| module | cumulative | self |", "|---|---:|---:|"]
    lines += [f"| {r['module']} | {r['cumulative_s'] * 1e3:.1f} ms | {r['self_s'] * 1e3:.1f} ms |"
              for r in data["imports"]]
    return lines + [""]


if __name__ == "__main__":
    print("\n".join(markdown(measure(int(sys.argv[1]) if len(sys.argv) > 1 else 3))))
=======
import argparse
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

BENCH = Path("/work/shared/bench/fiberpath")
FIBERPATH = "/work/venv-fp/bin/fiberpath"


def fiberpath_exe(given: str | None) -> str | None:
    for cand in (given, FIBERPATH, shutil.which("fiberpath")):
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
>>>>>>> 76eabb9 (bench/fiberpath_jobs.py: winder's marlin programs through fiberpath's own simulate)
