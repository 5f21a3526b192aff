"""`python -m bench.parts`: the realistic parts of parts/ as whole jobs (issue 29), one table.

Each part runs `winder run` in its own process (every default output written) and reports its exit
status, wall time, CPU time (user + system, the machine stage's workers included: less sensitive to
other load on the machine than the wall time) and peak memory (the larger of the process's own
high-water mark, VmHWM, and the peak PSS summed with its workers', bench.tree_memory), with the
summary's fiber length, the least
covered fraction of its layers, the largest lift-off over a concave stretch and the largest slip
|k_g / k_n| any fiber needs (against the friction the config allows), and on vessels the wall at the
bosses (each dome's thickest laminate and the bare radius there: the summary's `domes`). `folded_spline.yaml` is a
config `check` must refuse: its row is the refusal's time. Each part runs --repeat times (default
3) and the table gives the medians of time, CPU and peak (these machines are noisy: one run's CPU
time varies by 20 %). Writes bench/results/parts.md (or -o) and prints it. Wall times depend on the
machine's load: run it alone.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench.tree_memory import run_sampled

ROOT = Path(__file__).resolve().parents[1]
PARTS = ROOT / "parts"
RESULTS = Path(__file__).resolve().parent / "results" / "parts.md"
REFUSED_BY_CHECK = ("folded_spline",)

_CHILD = r"""
import json, resource, sys, time
t0 = time.perf_counter()
from winder.app.jobs import run_job
report = run_job(sys.argv[1], sys.argv[2])
usage = resource.getrusage(resource.RUSAGE_SELF)
workers = resource.getrusage(resource.RUSAGE_CHILDREN)  # the machine stage's workers, if any
# VmHWM: this process's own high-water mark (ru_maxrss of a spawned child also counts its parent's); the
# machine stage's forked workers: bench.tree_memory
peak_kb = next((int(line.split()[1]) for line in open("/proc/self/status") if line.startswith("VmHWM:")),
               usage.ru_maxrss)
print(json.dumps({"ok": report.ok, "exit": report.exit_code, "message": report.message,
                  "seconds": time.perf_counter() - t0, "cpu_seconds": usage.ru_utime + usage.ru_stime + workers.ru_utime + workers.ru_stime,
                  "peak_bytes": peak_kb * 1024}))
"""


def run_part(cfg: Path, out: Path) -> dict:
    """One part in a fresh interpreter: its figures (module docstring)."""
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
    if cfg.stem in REFUSED_BY_CHECK:
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "winder", "check", str(cfg)], capture_output=True, text=True,
                              cwd=ROOT, env=env)
        return {"name": cfg.stem, "exit": done.returncode, "seconds": time.perf_counter() - t0, "check": True}
    out.mkdir(parents=True, exist_ok=True)
    done, tree = run_sampled([sys.executable, "-c", _CHILD, str(cfg), str(out)], cwd=ROOT, env=env)
    row = {"name": cfg.stem, **json.loads(done.stdout.strip().splitlines()[-1])}
    row["peak_bytes"] = max(row["peak_bytes"], tree)
    summaries = list(out.glob("*.summary.json"))
    if row["ok"] and summaries:
        s = json.loads(summaries[0].read_text(encoding="utf-8"))
        layers = s["layers"]
        row.update(layers=len(layers), fiber_m=s["total_fiber_length_mm"] / 1e3,
                   coverage=min(layer["coverage"]["covered_fraction"] for layer in layers),
                   lift_off=max((layer.get("max_lift_off_mm") or 0.0) for layer in layers),
                   slip=max((layer.get("max_slip") or 0.0) for layer in layers),
                   walls=" / ".join(f"{d['max_wall_mm']:.1f} at r {d['max_wall_radius_mm']:.0f}"
                                    for d in s.get("domes", [])))
    return row


def median_run(cfg: Path, out: Path, repeat: int) -> dict:
    """run_part `repeat` times: the last run's row with the medians of its time, CPU and peak."""
    runs = [run_part(cfg, out) for _ in range(max(1, repeat))]
    row = dict(runs[-1])
    for key in ("seconds", "cpu_seconds", "peak_bytes"):
        if key in row:
            row[key] = statistics.median(r[key] for r in runs)
    return row


def table(rows: list[dict]) -> str:
    lines = ["| part | exit | layers | time (s) | CPU (s) | peak memory (MB) | fiber (m) | least coverage | "
             "max lift-off (mm) | max slip | wall at the bosses (mm) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        if r.get("check"):
            lines.append(f"| {r['name']} (check) | {r['exit']} | | {r['seconds']:.2f} | | | | | | | |")
            continue
        figures = (f"{r['layers']} | {r['seconds']:.1f} | {r['cpu_seconds']:.1f} | {r['peak_bytes'] / 1e6:.0f} | "
                   f"{r['fiber_m']:.1f} | {r['coverage']:.4f} | {r['lift_off']:.3f} | {r['slip']:.3f} | {r['walls']}") \
            if "layers" in r else \
            f" | {r['seconds']:.1f} | {r['cpu_seconds']:.1f} | {r['peak_bytes'] / 1e6:.0f} | | | | |"
        lines.append(f"| {r['name']} | {r['exit']} | {figures} |")
    failed = [r for r in rows if not r.get("check") and not r["ok"]]
    for r in failed:
        lines.append(f"\n{r['name']}: {r['message']}")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m bench.parts", description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default=str(RESULTS), help="the Markdown file to write")
    p.add_argument("-r", "--repeat", type=int, default=3, help="runs of each part (the table: their medians)")
    p.add_argument("names", nargs="*", help="parts to run (default: every parts/*.yaml)")
    args = p.parse_args(argv)
    configs = [PARTS / f"{n}.yaml" for n in args.names] or sorted(PARTS.glob("*.yaml"))
    rows = []
    start_load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        for cfg in configs:
            rows.append(median_run(cfg, Path(tmp) / cfg.stem, args.repeat))
            print(f"{cfg.stem}: exit {rows[-1]['exit']}, {rows[-1]['seconds']:.1f} s", file=sys.stderr)
    load = (f"Medians of {max(1, args.repeat)} runs. Load average (1 min) at the start {start_load:.2f}, "
            f"at the end {os.getloadavg()[0]:.2f}.\n\n")
    text = "# The realistic parts as whole jobs\n\n" + (__doc__ or "").split("\n\n")[1] + "\n\n" + load + table(rows)
    Path(args.output).write_text(text, encoding="utf-8")
    print(text)
    return 0 if all(r.get("check") and r["exit"] == 2 or r.get("ok") for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
