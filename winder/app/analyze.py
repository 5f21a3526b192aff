"""`winder analyze CONFIG [-o DIR] [--json]` (docs/guide/will-it-hold.md; docs/math/09-structure.md
9.9): plan the job, write its shell model, solve it with CalculiX `ccx`, read the meridian's ply stresses
back and set them beside the laminate analysis; write `<name>.inp`, `<name>.frd` (ccx's results, for a
viewer), `<name>.fe.dat` (its printed results), `<name>.summary.json` (with the `fe` block) and
`<name>.html` (the report, where plotly is installed) into DIR, all or nothing.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

from winder.errors import ConfigError, SolverError

SOLVE_LIMIT_S = 3600.0  # a deck past an hour of ccx is not one winder writes (MAX_ROWS x NTHETA elements)
CCX_NAMES = ("ccx",) + tuple(f"ccx_2.{k}" for k in range(30, 10, -1))  # Debian's ccx, upstream's ccx_2.NN


def find_ccx() -> str | None:
    """CalculiX's solver on PATH, or None."""
    return next((found for name in CCX_NAMES if (found := shutil.which(name))), None)


def solve(deck: str, name: str, ccx: str, limit_s: float = SOLVE_LIMIT_S) -> tuple[str, bytes, float]:
    """Run ccx on the deck in a scratch folder: (.dat text, .frd bytes, seconds); SolverError where it fails."""
    with tempfile.TemporaryDirectory(prefix="winder-ccx-") as tmp:
        (Path(tmp) / f"{name}.inp").write_text(deck, encoding="utf-8")
        env = {**os.environ, "OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS", "1")}
        started = time.perf_counter()
        try:
            run = subprocess.run([ccx, "-i", name], cwd=tmp, capture_output=True, text=True, timeout=limit_s, env=env)
        except subprocess.TimeoutExpired as exc:
            raise SolverError(f"CalculiX did not finish within {limit_s:g} s") from exc
        seconds = time.perf_counter() - started
        dat, frd = Path(tmp) / f"{name}.dat", Path(tmp) / f"{name}.frd"
        if run.returncode != 0 or "Job finished" not in run.stdout or not dat.exists():
            said = " ".join((run.stdout + run.stderr).split()[-40:])
            raise SolverError(f"CalculiX failed on the shell model (exit {run.returncode}): {said}")
        return dat.read_text(encoding="utf-8", errors="replace"), frd.read_bytes() if frd.exists() else b"", seconds


def analyze_files(config: str, out_dir: str, as_json: bool, refine: float = 1.0, around: int = 48) -> str:
    """What `winder analyze` prints, after writing its files; ConfigError (exit 2) without ccx or a load case."""
    from winder.analysis.fe_compare import compare, fe_block  # noqa: PLC0415
    from winder.analysis.fe_results import read_meridian  # noqa: PLC0415
    from winder.analysis.job import check_analysis  # noqa: PLC0415
    from winder.analysis.structure import analyze  # noqa: PLC0415
    from winder.app.jobs import _plan, motion_program  # noqa: PLC0415
    from winder.app.writes import write_outputs  # noqa: PLC0415
    from winder.config.job import load_config  # noqa: PLC0415
    from winder.config.winding import layer_label  # noqa: PLC0415
    from winder.export.abaqus import deck_text, job_model, require_analysis  # noqa: PLC0415
    from winder.export.summary import summary_dict  # noqa: PLC0415

    ccx = find_ccx()
    if ccx is None:
        raise ConfigError("CalculiX (ccx) is not installed: winder analyze solves the shell model with it (Debian, "
                          "Ubuntu: apt-get install calculix-ccx); `winder run --format abaqus` writes the deck alone",
                          file=config)
    job = load_config(config)
    require_analysis(job)
    plan = _plan(job)
    structure = analyze(plan, job)  # on a bent or non-circular tube no laminate analysis: the FE alone
    laminae = check_analysis(job)
    model = job_model(plan, job, refine, around)
    plies = {int(k): laminae[int(k) - 1] for k in set(model.ply_layer.tolist())}
    deck = deck_text(model, plies, job.analysis.pressure, job.name)
    dat, frd, seconds = solve(deck, job.name, ccx)
    strengths = {k: (p.Xt, p.Xc, p.Yt, p.Yc, p.S) for k, p in plies.items()}
    cmp = compare(read_meridian(model, dat, strengths), structure, model, refine, seconds)
    program = motion_program(job, plan)
    summary = summary_dict(plan, job.machine, program, job)
    summary["fe"] = fe_block(cmp)
    files = {f"{job.name}.inp": deck.encode(), f"{job.name}.frd": frd, f"{job.name}.fe.dat": dat.encode(),
             f"{job.name}.summary.json": (json.dumps(summary, sort_keys=True, indent=2, allow_nan=False) + "\n").encode()}
    page = _report(plan, summary, structure, cmp)
    if page is not None:
        files[f"{job.name}.html"] = page.encode()
    write_outputs(out_dir, files)
    if as_json:
        return json.dumps(summary["fe"], allow_nan=False)
    labels = {layer.index: layer_label(layer.index - 1, layer.type.value, round(layer.angle_deg, 2)) for layer in plan.layers}
    return "\n".join(_lines(job.name, summary, cmp, page is not None, out_dir, labels))


def _report(plan, summary: dict, structure, cmp) -> str | None:
    """The report page with the FE beside the CLT, or None without plotly (the plot extra)."""
    try:
        import plotly  # noqa: F401, PLC0415
    except ImportError:
        return None
    from winder.report.html import report_html  # noqa: PLC0415

    return report_html(plan, summary, structure=structure, fe=cmp)


def _lines(name: str, summary: dict, cmp, report: bool, out_dir: str, labels: dict[int, str]) -> list[str]:
    fe = summary["fe"]
    lines = [f"{name}: CalculiX solved {fe['elements']} shells ({fe['meridian_elements']} along the mandrel x "
             f"{fe['around']} around) in {cmp.seconds:.1f} s"]
    for lay in fe["layers"]:
        clt = lay["gauge_clt_max_fiber_stress_mpa"]
        lines.append(f"  {labels[lay['layer']]}: fiber stress in the gauge {lay['gauge_max_fiber_stress_mpa']} MPa FE"
                     + (f", {clt} MPa CLT" if clt is not None else " (no laminate analysis on this mandrel)")
                     + f"; largest anywhere {lay['all_max_fiber_stress_mpa']} MPa FE at t = "
                     f"{lay['all_max_fiber_stress_t']} mm; Tsai-Wu index {lay['all_max_tsai_wu_index']} FE"
                     + (f", {lay['all_clt_max_tsai_wu_index']} CLT" if clt is not None else ""))
    lines.append(f"  wrote {name}.inp, .frd, .fe.dat, .summary.json" + (", .html" if report else
                                                                         " (no report: plotly is not installed)")
                 + f" in {out_dir}")
    return lines
