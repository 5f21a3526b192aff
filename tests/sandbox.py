"""Running winder commands in a child process under a memory limit and a per-command time limit.

`run_limited(cases)` starts one Python process per worker, limits its address space (RLIMIT_AS, like
`prlimit --as`) before numpy is imported, and runs each case's commands through click's CliRunner,
each under SIGALRM. A case is a list of argument lists (e.g. check, then run, on the same config);
the result of each command: exit code (or "hang" / "crash"), seconds, peak memory of the worker so
far (VmHWM: the high-water mark of its own memory since exec; ru_maxrss would also count the test
process it was spawned from, hundreds of MB late in a suite; or, where larger, the peak of the PSS
summed over it and the machine stage's forked workers, sampled every 50 ms while it has any: their
VmHWM would count the pages they share with it twice; each has the address-space limit of its own),
stdout, stderr, the uncaught exception if any,
and the files left in its -o folder.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

MEMORY_BYTES = 2 * 1024**3
SECONDS = 20

_CHILD = r"""
import json, os, resource, signal, sys, threading, time
limit, seconds = int(sys.argv[1]), int(sys.argv[2])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
from click.testing import CliRunner
from winder.cli import main

TREE_KB = [0]  # the peak PSS summed with the workers' since the command began

def _pss_kb(pid):
    try:
        with open(f"/proc/{pid}/smaps_rollup") as f:
            return next((int(line.split()[1]) for line in f if line.startswith("Pss:")), 0)
    except OSError:
        return 0

def _sample():
    me = os.getpid()
    while True:
        try:
            kids = [int(c) for t in os.listdir(f"/proc/{me}/task")
                    for c in open(f"/proc/{me}/task/{t}/children").read().split()]
        except OSError:
            kids = []
        if kids:
            TREE_KB[0] = max(TREE_KB[0], sum(_pss_kb(pid) for pid in [me, *kids]))
        time.sleep(0.05)

threading.Thread(target=_sample, daemon=True).start()

def peak_mb():
    try:
        with open("/proc/self/status") as status:
            own = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:")) / 1024
    except (OSError, StopIteration):
        own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return max(own, TREE_KB[0] / 1024)

class Hang(BaseException):
    pass

def alarm(signum, frame):
    raise Hang()

signal.signal(signal.SIGALRM, alarm)
for line in sys.stdin:
    out = []
    for args in json.loads(line):
        started = time.perf_counter()
        TREE_KB[0] = 0
        signal.alarm(seconds)
        try:
            res = CliRunner().invoke(main, args)
            code, stdout, stderr = res.exit_code, res.stdout, res.stderr
            exc = res.exception
            uncaught = None if exc is None or isinstance(exc, SystemExit) else f"{type(exc).__name__}: {exc}"
        except Hang:
            code, stdout, stderr, uncaught = "hang", "", "", None
        finally:
            signal.alarm(0)
        folder = args[args.index("-o") + 1] if "-o" in args else None
        left = sorted(os.listdir(folder)) if folder and os.path.isdir(folder) else []
        out.append({"args": args, "code": code, "seconds": time.perf_counter() - started,
                    "peak_mb": peak_mb(),
                    "stdout": stdout, "stderr": stderr, "uncaught": uncaught, "left": left})
    print(json.dumps(out), flush=True)
"""


def run_limited(cases: list[list[list[str]]], workers: int = 1, memory: int = MEMORY_BYTES,
                seconds: int = SECONDS) -> list[list[dict]]:
    """The results of each case's commands, in order (module docstring); cases are split over
    `workers` child processes. A child that dies (out of memory outside Python's reach) gives
    "crash" for the commands it had not answered."""
    chunks = [cases[k::workers] for k in range(workers)]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")  # 2 children on 2 cores
    root = Path(__file__).resolve().parent.parent
    procs = [subprocess.Popen([sys.executable, "-c", _CHILD, str(memory), str(seconds)], cwd=root, env=env,
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for _ in chunks]
    answers = []
    for proc, chunk in zip(procs, chunks):
        # All of a child's input at once; it answers one line per case.
        stdin = "".join(json.dumps(case) + "\n" for case in chunk)
        answers.append((proc, stdin))
    results: list[list[list[dict]]] = []
    for proc, stdin in answers:
        stdout, _ = proc.communicate(stdin)
        results.append([json.loads(line) for line in stdout.splitlines() if line.startswith("[")])
    merged: list[list[dict]] = [None] * len(cases)  # type: ignore[list-item]
    for k, (chunk, got) in enumerate(zip(chunks, results)):
        for j, case in enumerate(chunk):
            merged[k + j * workers] = got[j] if j < len(got) else [
                {"args": args, "code": "crash", "seconds": 0.0, "peak_mb": 0.0, "stdout": "", "stderr": "",
                 "uncaught": None, "left": []} for args in case]
    return merged
