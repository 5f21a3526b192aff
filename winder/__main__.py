"""The `winder` executable (and `python -m winder`): the command line of winder.cli.

Importing numpy and scipy takes a second or two; a TERM or Ctrl-C in that time ends winder with one
`Error:` line and exit 143 / 130 rather than a traceback (nothing is written yet). Once winder.cli
runs, it handles both itself (winder.app.interrupts).
"""

from __future__ import annotations

import os
import signal


_ARRIVALS: int | None = None  # the read end of the signal wake-up pipe: the order signals arrived in
_COMMAND_RAN = False  # the command has run: a signal now comes as winder ends, not while it starts


def _first_arrived(signum: int) -> int:
    # Python runs the handlers of signals pending together in number order (INT before TERM), and a
    # handler may run nested at the start of another's: the wake-up pipe says which came first.
    try:
        arrived = os.read(_ARRIVALS, 4096) if _ARRIVALS is not None else b""
    except OSError:
        arrived = b""
    return next((b for b in arrived if b in (signal.SIGINT, signal.SIGTERM)), signum)


def _starting(signum: int, frame) -> None:
    # Idempotent: the other stop signal (TERM then INT, 0-80 ms apart) is blocked before anything is
    # written, so one Error line and the first signal's status, whatever comes next.
    signal.pthread_sigmask(signal.SIG_BLOCK, (signal.SIGINT, signal.SIGTERM))
    signum = _first_arrived(signum)  # TERM then INT: TERM's status
    when = " as it ended" if _COMMAND_RAN else " while starting"
    os.write(2, f"Error: interrupted by {signal.Signals(signum).name}{when}\n".encode())
    os._exit(128 + signum)


# Installed as this module is imported, before anything else is (the `winder` entry script imports
# it, then calls main): the earliest moment winder's own code runs. Before it, the interpreter is
# still starting (its site import, ~20-100 ms on a busy machine): a TERM there ends the process by
# the signal, an INT is the interpreter's own "Fatal Python error: init_import_site", which no code
# of winder can catch.
# (Only when this module is the program: `python -m winder`, or a script named winder; a library or a
# test importing it keeps its own handlers.)
import sys  # noqa: E402 - already loaded by the interpreter: no time

if __name__ == "__main__" or os.path.basename(sys.argv[0] if sys.argv else "").startswith("winder"):
    try:
        _ARRIVALS, _write = os.pipe()
        os.set_blocking(_ARRIVALS, False)
        os.set_blocking(_write, False)
        signal.set_wakeup_fd(_write, warn_on_full_buffer=False)
    except (OSError, ValueError):
        _ARRIVALS = None
    for _sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(_sig, _starting)

import gc  # noqa: E402

if __name__ == "__main__" or os.path.basename(sys.argv[0] if sys.argv else "").startswith("winder"):
    from winder.app.interrupts import watch_arrival_order  # noqa: E402 - after the handlers

    watch_arrival_order(_ARRIVALS)  # the same pipe, read by winder's own handlers from now on

GC_YOUNG_THRESHOLD = 50_000  # allocations between the collector's young passes (Python's default: 700)
# winder's linear algebra is banded solves and small products, which BLAS does not split over threads;
# its idle worker threads only spin (a core each for a while after numpy loads and after every call),
# taking that core from the job, or from the batch's other jobs. A value the user set is kept.
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")


def main() -> None:
    for sig in (signal.SIGINT, signal.SIGTERM):  # again: main() may be called without the import above
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
    if sys.stdout is None:  # started with standard output closed (`>&-`): click would print nothing, exit 0
        os.write(2, b"Error: standard output is closed (>&-): winder reports there; redirect it to a file or "
                    b"/dev/null instead\n")
        sys.exit(2)
    from winder.cli import main as cli  # noqa: PLC0415 - after the handlers: the import takes a while

    global _COMMAND_RAN  # noqa: PLW0603 - read by the handler
    _COMMAND_RAN = True  # winder.cli's handlers from here; _starting again only once they are put back
    try:
        cli()
    finally:
        # The command is done (its status decided, its files in place): a stop signal in the
        # interpreter's last moments, when Python has put the default handlers back, must not end the
        # process by the signal instead.
        signal.pthread_sigmask(signal.SIG_BLOCK, (signal.SIGINT, signal.SIGTERM))
        gc.freeze()


if __name__ == "__main__":
    main()
