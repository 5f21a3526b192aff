"""`python -m bench --parts N`: N generated parts (tests/part_generator.py, its NIGHTLY size) run as
whole jobs, each in a fresh interpreter (bench.parts.run_part: exit status, CPU time with the machine
stage's workers, peak memory), tabled per class: how many planned, refused for a physical reason,
refused numerically (a defect), refused by an invariant (a defect), refused otherwise, killed past
CPU_LIMIT_S of CPU (slow); the invariant
margins of the planned ones (least covered fraction, largest point and midpoint deviation, least
clearance margin: the eye body's least distance less the clearance); the median and 95th percentile
of CPU seconds and peak memory. Writes bench/results/generated.md and generated.json (or -o)."""

from __future__ import annotations

import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from bench.parts import _CHILD
from bench.tree_memory import run_sampled

ROOT = Path(__file__).resolve().parents[1]
RESULTS = Path(__file__).resolve().parent / "results"
KINDS = ("planned", "physical", "numerical", "invariant", "other", "slow")
CPU_LIMIT_S = 300  # a part killed past this much CPU is `slow` (these machines are shared: no wall limit)
# The job in a fresh interpreter (bench.parts' child), its CPU time limited.
CHILD = f"import resource\nresource.setrlimit(resource.RLIMIT_CPU, ({CPU_LIMIT_S}, {CPU_LIMIT_S + 10}))\n" + _CHILD


def run_part(cfg: Path, out: Path) -> dict:
    """One part in a fresh interpreter, as bench.parts.run_part, or a `slow` row where it was killed
    past CPU_LIMIT_S."""
    import subprocess  # noqa: PLC0415

    out.mkdir(parents=True, exist_ok=True)
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
    try:
        done, tree = run_sampled([sys.executable, "-c", CHILD, str(cfg), str(out)], cwd=ROOT, env=env)
    except subprocess.CalledProcessError as exc:
        return {"ok": False, "slow": True, "message": f"killed past {CPU_LIMIT_S} s of CPU ({exc.returncode})",
                "cpu_seconds": float(CPU_LIMIT_S), "peak_bytes": 0, "seconds": float("nan")}
    row = json.loads(done.stdout.strip().splitlines()[-1])
    row["peak_bytes"] = max(row["peak_bytes"], tree)
    return row


def _generator():
    sys.path.insert(0, str(ROOT / "tests"))
    import part_generator  # noqa: PLC0415 - the tests' generator, one source for both

    return part_generator


def run(count: int, seed: int = 0, log=sys.stderr, partial: Path | None = None) -> list[dict]:
    """The rows (one per part: class, seed, outcome, message, figures) of `count` generated parts;
    partial: a JSON file rewritten with the rows so far after each part (a long run stopped early
    keeps them)."""
    gen = _generator()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for cls, s, config in gen.parts(count, seed, gen.NIGHTLY):
            folder = Path(tmp) / config["name"]
            folder.mkdir()
            path = folder / f"{config['name']}.yaml"
            path.write_text(yaml.safe_dump(config, sort_keys=False), encoding="utf-8")
            row = run_part(path, folder / "out")
            kind = "slow" if row.get("slow") else gen.outcome(bool(row["ok"]), row.get("message", ""))
            out = {"class": cls, "seed": s, "outcome": kind, "message": row.get("message", ""),
                   "cpu_seconds": row["cpu_seconds"], "peak_bytes": row["peak_bytes"], "seconds": row["seconds"]}
            summary = folder / "out" / f"{config['name']}.summary.json"
            if row["ok"] and summary.exists():
                block = json.loads(summary.read_text(encoding="utf-8"))["invariants"]
                out.update(block)
                clearance = config["machine"]["eye"]["clearance"]
                if block.get("min_clearance_mm") is not None:
                    out["clearance_margin_mm"] = block["min_clearance_mm"] - clearance
            rows.append(out)
            if partial is not None:
                partial.write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")
            print(f"{cls}_{s}: {kind} {row['cpu_seconds']:.1f} s CPU {row['peak_bytes'] / 1e6:.0f} MB", file=log, flush=True)
    return rows


def _pct(values: list[float], q: float) -> float:
    return float(np.percentile(values, q)) if values else float("nan")


def table(rows: list[dict]) -> str:
    """The per-class table (module docstring), Markdown."""
    head = ("| class | parts | planned | physical | numerical | invariant | other | slow | least covered | "
            "max point dev (mm) | max midpoint dev (mm) | least clearance margin (mm) | CPU s median | CPU s p95 | "
            "peak MB median | peak MB p95 |")
    lines = [head, "|---|" + "---:|" * 15]
    classes = sorted({r["class"] for r in rows}, key=lambda c: _generator().CLASSES.index(c)) + ["all"]
    for cls in classes:
        mine = [r for r in rows if cls in ("all", r["class"])]
        planned = [r for r in mine if r["outcome"] == "planned"]
        counts = [sum(r["outcome"] == k for r in mine) for k in KINDS]

        def pick(key, fn):
            vals = [r[key] for r in planned if r.get(key) is not None]
            return f"{fn(vals):.4f}" if vals else ""

        cpu = [r["cpu_seconds"] for r in mine]
        peak = [r["peak_bytes"] / 1e6 for r in mine]
        lines.append(f"| {cls} | {len(mine)} | " + " | ".join(map(str, counts)) + " | "
                     f"{pick('min_covered_fraction', min)} | {pick('max_point_deviation_mm', max)} | "
                     f"{pick('max_midpoint_deviation_mm', max)} | {pick('clearance_margin_mm', min)} | "
                     f"{statistics.median(cpu):.1f} | {_pct(cpu, 95):.1f} | {statistics.median(peak):.0f} | "
                     f"{_pct(peak, 95):.0f} |")
    return "\n".join(lines) + "\n"


def defects(rows: list[dict]) -> str:
    """The parts refused numerically, by an invariant or otherwise: class, seed and message."""
    bad = [r for r in rows if r["outcome"] in ("numerical", "invariant", "other", "slow")]
    return "".join(f"- {r['class']} seed {r['seed']} ({r['outcome']}): {r['message']}\n" for r in bad)


def main(count: int, seed: int = 0, output: Path = RESULTS) -> int:
    start, load = time.time(), os.getloadavg()[0]
    output.mkdir(parents=True, exist_ok=True)
    rows = run(count, seed, partial=output / "generated.partial.json")
    text = (f"# Generated parts\n\n{(__doc__ or '').split(chr(10) + chr(10))[0]}\n\n{count} parts from seed {seed}, "
            f"{time.time() - start:.0f} s, load average (1 min) {load:.1f} at the start, {os.getloadavg()[0]:.1f} at "
            f"the end.\n\n" + table(rows) + "\n## Defects\n\n" + (defects(rows) or "none\n"))
    output.mkdir(parents=True, exist_ok=True)
    (output / "generated.md").write_text(text, encoding="utf-8")
    (output / "generated.json").write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")
    print(text)
    return 0
