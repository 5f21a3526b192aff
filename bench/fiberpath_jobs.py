"""Whole jobs against fiberpath on its own examples, and start-up (issue 14).

Each fiberpath example (the folder WINDER_FIBERPATH_EXAMPLES names; .ci/run sets it) is a pair NAME.wind (fiberpath) and NAME.yaml (winder, the
same job). Per repeat the two tools run back to back as a user runs them (a fresh process, each its
own console script, all of winder's output files written), alternating who goes first so that the
machine's noise falls on both; figures are medians over the repeats. fiberpath is AGPL and is only
ever run as a separate program; without it (or without the examples) the section is skipped with a
note. Start-up: `winder --help` and `winder check` against `fiberpath --help` and a bare interpreter,
and the slowest imports of `import winder.cli` (`python -X importtime`).
"""

from __future__ import annotations

import json
import os
import shutil
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
# fiberpath's examples are AGPL data, read where they lie: the environment names their folder.
EXAMPLES = Path(os.environ.get("WINDER_FIBERPATH_EXAMPLES") or ROOT / "bench" / "no-fiberpath-examples")
# fiberpath lives in its own environment (AGPL, a bench-only tool): WINDER_FIBERPATH, else on PATH.
FIBERPATH = Path(os.environ.get("WINDER_FIBERPATH") or shutil.which("fiberpath") or "fiberpath")
WINDER = Path(sys.executable).parent / "winder"
CHECK_SAMPLE = ROOT / "samples" / "pipe.yaml"
TARGETS = {"motor_tube": 5.0, "avbay_triple": 5.0, "main_chute": 5.0, "avbay_single": 3.0,
           "simple_cylinder": 1.5, "multi_layer": 1.5}  # fiberpath time / winder time, issue 14
STARTUP_TARGETS = {"winder --help": 0.25, "winder check": 0.35}  # seconds


@contextmanager
def installed_winder():
    """A `winder` command of this tree installed as `pip install .` leaves it, in a throwaway venv.

    A developer's editable install runs a path finder at every interpreter start (about 10-20 ms that
    no user's install pays); here winder's package is copied and byte-compiled into the venv's
    site-packages, its dependencies come from this interpreter's site-packages (a .pth line), and the
    console script is the one pip writes. Yields the script's path.
    """
    import compileall  # noqa: PLC0415
    import venv  # noqa: PLC0415

    with tempfile.TemporaryDirectory(prefix="winder-installed-") as tmp:
        env = Path(tmp) / "venv"
        venv.create(env, with_pip=False, symlinks=True)
        python = env / "bin" / "python"
        site = Path(subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                                   capture_output=True, text=True, check=True).stdout.strip())
        deps = {sysconfig.get_path("purelib"), sysconfig.get_path("platlib")}
        (site / "winder-bench-deps.pth").write_text("".join(f"{d}\n" for d in sorted(deps)))
        shutil.copytree(ROOT / "winder", site / "winder", ignore=shutil.ignore_patterns("__pycache__"))
        compileall.compile_dir(str(site / "winder"), quiet=1)
        script = env / "bin" / "winder"
        script.write_text(f"#!{python}\nimport sys\nfrom winder.__main__ import main\n"
                          "if __name__ == '__main__':\n    sys.exit(main())\n")
        script.chmod(0o755)
        yield script


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
    try:
        _pair_runs(name, wind, config, repeats, fp, wi)
    except RuntimeError as exc:  # one example that a tool refuses must not lose the others
        return {"name": name, "error": str(exc), "target": TARGETS.get(name)}
    f, w = statistics.median(fp), statistics.median(wi)
    return {"name": name, "fiberpath_s": f, "winder_s": w, "ratio": f / w, "target": TARGETS.get(name),
            "fiberpath_runs_s": fp, "winder_runs_s": wi}


def _pair_runs(name: str, wind: Path, config: Path, repeats: int, fp: list[float], wi: list[float]) -> None:
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


def startup(repeats: int) -> dict[str, float]:
    python = str(WINDER.parent / "python")  # the interpreter of the winder being timed
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
    proc = subprocess.run([str(WINDER.parent / "python"), "-X", "importtime", "-c", f"import {module}"], capture_output=True,
                          text=True)
    rows = []
    for line in proc.stderr.splitlines():
        if line.startswith("import time:") and "self [us]" not in line:
            own, cum, name = (part.strip() for part in line[len("import time:"):].split("|"))
            rows.append({"module": name, "cumulative_s": int(cum) / 1e6, "self_s": int(own) / 1e6})
    rows.sort(key=lambda r: -r["cumulative_s"])
    return rows[:top]


def compile_winder() -> int:
    """Write winder's bytecode (__pycache__), as `pip install .` does at install time: an editable
    install under PYTHONDONTWRITEBYTECODE=1 (as on these machines) would otherwise compile every
    module again in every run, about 0.3 s that no installed copy pays and fiberpath's install does
    not either. Returns 1 if every module compiled."""
    import compileall  # noqa: PLC0415

    return int(compileall.compile_dir(str(ROOT / "winder"), quiet=1))


def measure(repeats: int = 5, names: list[str] | None = None, jobs: bool = True) -> dict[str, Any]:
    """Everything of this section, for results.json (jobs False: start-up and imports only)."""
    global WINDER  # noqa: PLW0603 - the command every run of this section times
    compile_winder()
    developer = WINDER
    with installed_winder() as WINDER:
        try:
            return _measure(repeats, names, jobs)
        finally:
            WINDER = developer


def _measure(repeats: int, names: list[str] | None, jobs: bool) -> dict[str, Any]:
    out: dict[str, Any] = {"startup_s": startup(repeats), "startup_targets_s": STARTUP_TARGETS,
                           "imports": import_profile()}
    if not jobs:
        out["note"] = "whole jobs against fiberpath: not in this run's settings"
        return out
    if not (FIBERPATH.exists() and EXAMPLES.is_dir()):
        out["note"] = (f"fiberpath ({FIBERPATH}) or its examples ({EXAMPLES}; set WINDER_FIBERPATH_EXAMPLES) not found: "
                       "whole jobs skipped")
        return out
    names = names or sorted(p.stem for p in EXAMPLES.glob("*.wind") if p.with_suffix(".yaml").exists())
    out["jobs"] = [_job(name, repeats) for name in names]
    return out


def markdown(data: dict[str, Any]) -> list[str]:
    """The section of RESULTS.md."""
    lines = ["## Whole jobs against fiberpath, and start-up", "",
             "Each example run as a user runs it (a fresh process, all output files written), fiberpath and "
             "winder alternating; medians of the repeats. Ratio: fiberpath's time over winder's (> 1: winder "
             "is faster); target: issue 14's. Both run as installed, from their bytecode: winder from a "
             "throwaway venv holding a copy of this tree as `pip install .` leaves it (a developer's editable "
             "install adds a path finder to every start).", ""]
    if "jobs" in data:
        lines += ["| example | fiberpath | winder | fiberpath / winder | target |", "|---|---:|---:|---:|---:|"]
        for j in data["jobs"]:
            tgt = f">= {j['target']:g}x" if j.get("target") else "-"
            if "error" in j:
                lines.append(f"| {j['name']} | - | - | failed: `{j['error'][-160:]}` | {tgt} |")
                continue
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
