"""Timing on a noisy machine: interleaved repeats, medians, and a record of the environment.

Every figure of the bench is a median of repeated runs; the runs of the methods being compared are
interleaved (round-robin), so that a burst of load from another process hits all of them alike and
the ratios between them stay meaningful. Nothing here prints.
"""

from __future__ import annotations

import gc
import os
import platform
import statistics
import subprocess
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

SLOW = 0.5  # s: a task whose first run takes longer keeps that run as a sample (no separate warm-up)


@dataclass
class Timed:
    """The outcome of one timed task: its wall-time samples (s), last value, or the error it raised."""

    samples: list[float] = field(default_factory=list)
    value: Any = None
    values: list[Any] = field(default_factory=list)
    error: str | None = None

    @property
    def median(self) -> float:
        return statistics.median(self.samples) if self.samples else float("nan")

    @property
    def ok(self) -> bool:
        return self.error is None and bool(self.samples)


def _once(fn: Callable[[], Any]) -> tuple[float, Any]:
    """One timed call, the garbage collector paused inside it (collected once per round instead)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        t0 = time.perf_counter()
        value = fn()
        return time.perf_counter() - t0, value
    finally:
        if enabled:
            gc.enable()


def interleaved(tasks: list[tuple[Any, Callable[[], Any]]], repeats: int, min_repeats: int,
                budget: float) -> dict[Any, Timed]:
    """Time each task repeatedly, round-robin across the tasks; returns key -> Timed.

    Each task first runs once as a warm-up (kept as a sample when it is slower than SLOW). It then
    gets up to `repeats` samples, fewer for a slow one (about `budget` seconds each, at least
    `min_repeats`). A task that raises is recorded with its error and not run again.
    """
    out: dict[Any, Timed] = {key: Timed() for key, _ in tasks}
    target: dict[Any, int] = {}
    gc.collect()
    for key, fn in tasks:
        try:
            dt, value = _once(fn)
        except Exception as exc:  # noqa: BLE001 - a baseline failing is a result, not a crash
            out[key].error = f"{type(exc).__name__}: {exc}"
            continue
        out[key].value = value
        if dt > SLOW:
            out[key].samples.append(dt)
            out[key].values.append(value)
        target[key] = max(min_repeats, min(repeats, int(budget / max(dt, 1e-9))))
    for _ in range(max(target.values(), default=0)):
        gc.collect()
        for key, fn in tasks:
            t = out[key]
            if key not in target or len(t.samples) >= target[key] or t.error is not None:
                continue
            try:
                dt, value = _once(fn)
            except Exception as exc:  # noqa: BLE001
                t.error = f"{type(exc).__name__}: {exc}"
                continue
            t.samples.append(dt)
            t.value = value
            t.values.append(value)
    return out


@contextmanager
def blas_threads(n: int | None):
    """Limit the BLAS thread pools (threadpoolctl) to n threads inside the block; None: leave them.

    On this 2-core machine shared with other work, OpenBLAS's threads spin against each other inside
    scipy's L-BFGS-B (measured: several times slower per iteration); one thread is fair to every
    method, none of which gains from BLAS threads at these sizes.
    """
    if n is None:
        yield False
        return
    try:
        from threadpoolctl import threadpool_limits  # noqa: PLC0415
    except ImportError:
        yield False
        return
    with threadpool_limits(limits=n):
        yield True


def blas_info() -> list[dict[str, Any]]:
    """The BLAS libraries loaded (threadpoolctl), with the kernel each one runs; [] if unknown."""
    try:
        import numpy  # noqa: F401, PLC0415 - load the libraries before asking
        import scipy.linalg  # noqa: F401, PLC0415
        from threadpoolctl import threadpool_info  # noqa: PLC0415
    except ImportError:
        return []
    keep = ("internal_api", "version", "architecture", "num_threads", "prefix")
    return [{k: d.get(k) for k in keep} for d in threadpool_info()]


def _version(module: str) -> str | None:
    try:
        from importlib.metadata import version  # noqa: PLC0415

        return version(module)
    except Exception:  # noqa: BLE001 - not installed
        return None


def _git_commit() -> str | None:
    root = Path(__file__).resolve().parents[1]
    try:
        out = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, timeout=10, check=False)
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    if out.returncode != 0:
        return None
    return out.stdout.strip() + ("+dirty" if dirty.stdout.strip() else "")


def environment(threads: int | None) -> dict[str, Any]:
    """What the numbers were measured on."""
    try:
        load = os.getloadavg()
    except OSError:
        load = None
    return {
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "cpus": os.cpu_count(),
        "load_average_at_start": [round(x, 2) for x in load] if load else None,
        "packages": {m: _version(m) for m in ("numpy", "scipy", "trimesh", "potpourri3d", "matplotlib",
                                              "threadpoolctl", "fiberpath")},
        "blas": blas_info(),
        "blas_threads_limit": threads,
        "openblas_env": {k: os.environ.get(k) for k in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE",
                                                         "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")},
        "git_commit": _git_commit(),
    }
