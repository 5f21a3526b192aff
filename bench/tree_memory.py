"""A job's memory as a whole: the machine stage may run on forked workers (winder.app.machine_pool),
whose memory a process's own high-water mark (VmHWM) does not count, while their resident sizes
count again the pages they share with the parent. The peak of the proportional set sizes (PSS: each
shared page split among the processes sharing it) summed over the process and its children, sampled
every SAMPLE_S while it has children, counts each page once. Reading a process's smaps walks its page
tables (milliseconds for a few hundred MB), so the sampling is sparse and only while the workers run:
at 50 ms, always, it took a tenth of a core from the job it measures."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

SAMPLE_S = 0.2  # s: a group's dense arrays live for seconds


def _children(pid: int) -> list[int]:
    out: list[int] = []
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            out += [int(c) for c in Path(f"/proc/{pid}/task/{task}/children").read_text().split()]
    except OSError:
        pass
    return out


def _pss_kb(pid: int) -> int:
    try:
        with open(f"/proc/{pid}/smaps_rollup", encoding="ascii") as f:
            return next((int(line.split()[1]) for line in f if line.startswith("Pss:")), 0)
    except OSError:  # gone meanwhile, or not Linux
        return 0


def run_sampled(cmd: list[str], **popen) -> tuple[subprocess.CompletedProcess, int]:
    """Run cmd (its output captured as text) and return (the completed process, the peak summed PSS
    of it and its children in bytes; 0 where /proc has none). Raises CalledProcessError as
    subprocess.run(check=True) does."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **popen)
    peak = 0
    while True:
        workers = _children(proc.pid)
        if workers:  # without them the process's own VmHWM is its peak
            peak = max(peak, sum(_pss_kb(pid) for pid in [proc.pid, *workers]))
        try:  # reading its output meanwhile: a full pipe would stop it
            out, err = proc.communicate(timeout=SAMPLE_S)
            break
        except subprocess.TimeoutExpired:
            continue
    done = subprocess.CompletedProcess(cmd, proc.returncode, out, err)
    done.check_returncode()
    return done, peak * 1024
