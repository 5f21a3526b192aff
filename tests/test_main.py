"""The executable (winder/__main__.py): what it sets up before the command line runs.

Truths used: the environment and collector settings a child interpreter reports after main() ran.
"""

from __future__ import annotations

import os
import subprocess
import sys

from winder.__main__ import BLAS_THREAD_VARIABLES, GC_YOUNG_THRESHOLD

# Run main() on `--version`, then report what the process looks like after it.
PROBE = """
import gc, json, os, sys
import winder.__main__ as m
sys.argv = ["winder", "--version"]
try:
    m.main()
except SystemExit:
    pass
print(json.dumps({"env": {k: os.environ.get(k) for k in m.BLAS_THREAD_VARIABLES},
                  "threshold": gc.get_threshold()[0], "frozen": gc.get_freeze_count()}))
"""


def _probe(env: dict[str, str]) -> dict:
    import json  # noqa: PLC0415

    proc = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _clean_env() -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if k not in BLAS_THREAD_VARIABLES}


def test_blas_runs_one_thread_unless_the_user_says_otherwise():
    assert _probe(_clean_env())["env"] == {k: "1" for k in BLAS_THREAD_VARIABLES}
    mine = {**_clean_env(), "OPENBLAS_NUM_THREADS": "2"}
    assert _probe(mine)["env"]["OPENBLAS_NUM_THREADS"] == "2"


def test_collector_runs_less_often_and_what_is_alive_at_the_end_is_frozen():
    out = _probe(_clean_env())
    assert out["threshold"] == GC_YOUNG_THRESHOLD
    assert out["frozen"] > 1000  # the interpreter's, click's and winder's objects, left to the exit


# Run main() on the given arguments, then list the heavy packages the process imported.
IMPORTS_PROBE = """
import json, sys
import winder.__main__ as m
sys.argv = ["winder", *json.loads(sys.argv[1])]
try:
    m.main()
except SystemExit:
    pass
heavy = ("scipy", "trimesh", "plotly")
print(json.dumps(sorted({n.split(".")[0] for n in sys.modules if n.split(".")[0] in heavy})))
"""


def _heavy_imports(*args: str) -> list[str]:
    import json  # noqa: PLC0415
    from pathlib import Path  # noqa: PLC0415

    root = Path(__file__).resolve().parent.parent
    env = {**_clean_env(), "PYTHONPATH": str(root)}
    proc = subprocess.run([sys.executable, "-c", IMPORTS_PROBE, json.dumps(list(args))], capture_output=True,
                          text=True, env=env, check=True, cwd=root)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_help_and_a_tube_check_import_nothing_heavy():
    """scipy, trimesh and plotly load where a job first needs them, never for --help or a tube's check."""
    assert _heavy_imports("--help") == []
    assert _heavy_imports("check", "samples/pipe.yaml") == []


# What a plain pipe job (helical and hoop layers, friction-held turnarounds on a cylinder) may import in
# its own process: the splines' and LAPACK's parts of scipy, never an ODE solver (its turnarounds have a
# closed form: winder.paths.friction_cylinder), the mesh library (its PLY is rendered aside, on a forked
# process: winder.app.machine_pool.aside) or the plot library. MODULE_BUDGET bounds everything loaded
# (877 with scipy 1.17, numpy 2.4, trimesh 4 and click 8.3 when it was set).
PIPE_JOB_FORBIDDEN = ("scipy.integrate", "trimesh", "plotly")
MODULE_BUDGET = 1000

JOB_IMPORTS_PROBE = """
import json, sys
import winder.__main__ as m
sys.argv = ["winder", *json.loads(sys.argv[1])]
try:
    m.main()
except SystemExit:
    pass
print(json.dumps(sorted(sys.modules)))
"""


def test_a_plain_pipe_job_keeps_to_its_import_budget(tmp_path):
    import json  # noqa: PLC0415
    from pathlib import Path  # noqa: PLC0415

    root = Path(__file__).resolve().parent.parent
    args = ["run", "samples/pipe.yaml", "-o", str(tmp_path)]
    proc = subprocess.run([sys.executable, "-c", JOB_IMPORTS_PROBE, json.dumps(args)], capture_output=True, text=True,
                          env={**_clean_env(), "PYTHONPATH": str(root)}, check=True, cwd=root)
    modules = json.loads(proc.stdout.strip().splitlines()[-1])
    assert (tmp_path / "pipe.ply").stat().st_size > 0  # the mesh was written, by the forked process
    # on one core the PLY is rendered in the job's own process (usable_workers), and needs trimesh there
    forbidden = PIPE_JOB_FORBIDDEN if len(os.sched_getaffinity(0)) >= 2 else ("scipy.integrate", "plotly")
    loaded = [m for m in modules if any(m == f or m.startswith(f + ".") for f in forbidden)]
    assert not loaded, loaded[:5]
    assert len(modules) <= MODULE_BUDGET
