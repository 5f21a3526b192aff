"""The `winder` executable (and `python -m winder`): the command line of winder.cli.

Importing numpy and scipy takes a second or two; a TERM or Ctrl-C in that time ends winder with one
`Error:` line and exit 143 / 130 rather than a traceback (nothing is written yet). Once winder.cli
runs, it handles both itself (winder.app.interrupts).
"""

from __future__ import annotations

import gc
import os
import signal
import sys

GC_YOUNG_THRESHOLD = 50_000  # allocations between the collector's young passes (Python's default: 700)
# winder's linear algebra is banded solves and small products, which BLAS does not split over threads;
# its idle worker threads only spin (a core each for a while after numpy loads and after every call),
# taking that core from the job, or from the batch's other jobs. A value the user set is kept.
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")


def _starting(signum: int, frame) -> None:
    os.write(2, f"Error: interrupted by {signal.Signals(signum).name} while starting\n".encode())
    os._exit(128 + signum)


def main() -> None:
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, _starting)
    for name in BLAS_THREAD_VARIABLES:  # before numpy loads (the commands import it), and for the workers
        os.environ.setdefault(name, "1")
    # One run, one short-lived process. The cyclic collector's young passes (every 700 allocations by
    # default) mostly walk what the imports build, tens of thousands of objects that live to the end,
    # while a job leaves a few dozen objects of cyclic garbage: they run less often. At the end
    # whatever is alive is frozen, so that the interpreter's exit does not walk it all once more just
    # before the process frees it. Measured on a small job: 5 % of its instructions, and 30-40 ms of
    # wall time at its exit.
    gc.set_threshold(GC_YOUNG_THRESHOLD)
    from winder.cli import main as cli  # noqa: PLC0415 - after the handlers: the import takes a while

    try:
        cli()
    finally:
        gc.freeze()


if __name__ == "__main__":
    main()
