"""Interrupts: TERM and INT stop a job or a batch cleanly (exit 130 / 143, docs/guide/commands.md).

In the main process, `interrupts_raise` turns both signals into Interrupted, which unwinds through a
job's writes (winder.app.jobs.write_outputs takes back what it put in place) and through the batch
loop, which stops its workers with `stop_workers`. A worker runs each job through `in_worker`: a signal
in the middle of a job rolls that job back and ends the worker; between jobs it just ends it. Workers
also get TERM when their parent dies (Linux), so none outlives a killed batch.

The first stop signal decides, whatever becomes of its exception: it is recorded (`interrupted`) before
Interrupted is raised, and later signals change nothing. An exception raised inside an import can come
out as another one (pybind11's modules of scipy wrap it: `ImportError: initialization failed`), or be
swallowed (a `__del__`), or leave a half-imported module that fails later; so whatever leaves
`interrupts_raise` after a stop signal leaves as the interrupt, and whoever turns an error into a report
or an `Error:` line inside it (a batch's job report, a command's) first calls `raise_if_interrupted`.
"""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from winder.errors import Interrupted

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

__all__ = ["STOP_SIGNALS", "block_stop_signals", "first_arrived", "held", "in_worker", "interrupted",
           "interrupts_raise", "raise_if_interrupted", "stop_signals_held_back", "stop_workers",
           "watch_arrival_order", "worker_init"]

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
WORKER_GRACE_S = 1.0  # a worker stopped by TERM rolls back its job's files within this, or is killed


def _ignore(signum: int, frame) -> None:
    """A stop signal after the first: nothing. Not SIG_IGN: a signal already caught but not yet handled
    (a Ctrl-C reaching every process of the group, then the parent's TERM) would find SIG_IGN and
    raise OSError ("ignored due to race condition") in the middle of the rollback."""


_ARRIVALS: int | None = None  # the read end of the signal wake-up pipe (watch_arrival_order)


def watch_arrival_order(read_end: int | None = None) -> None:
    """Keep the order in which signals arrive. Python runs the handlers of signals pending together in
    signal-number order (INT before TERM, whichever came first), so a TERM then an INT 1 ms later,
    both caught during a long C call, would end winder as if by INT. Python's C-level handler writes
    each signal's number to the wake-up file descriptor as it arrives: first_arrived reads it back."""
    global _ARRIVALS  # noqa: PLW0603 - the one pipe of the process
    if read_end is not None:  # set up already (winder.__main__, before any import)
        _ARRIVALS = read_end
        return
    try:
        read, write = os.pipe()
        os.set_blocking(read, False)
        os.set_blocking(write, False)
        signal.set_wakeup_fd(write, warn_on_full_buffer=False)
    except (OSError, ValueError, AttributeError):  # not the main thread, or no pipes here
        return
    _ARRIVALS = read


def first_arrived(signum: int) -> int:
    """The stop signal that arrived first among those not handled yet (signum if none is recorded)."""
    if _ARRIVALS is None:
        return signum
    try:
        arrived = os.read(_ARRIVALS, 4096)
    except OSError:  # nothing recorded
        return signum
    return next((b for b in arrived if b in STOP_SIGNALS), signum)


_FIRST: int | None = None  # the first stop signal this process caught: its status is the exit status
_HELD = 0  # inside `held` (nested): an interrupt is recorded, and raised as the section ends
_PENDING = False  # an interrupt recorded inside `held`, not raised yet


def interrupted() -> int | None:
    """The first stop signal this process caught (None: none)."""
    return _FIRST


def raise_if_interrupted(cause: BaseException | None = None) -> None:
    """Raise Interrupted (from cause) if a stop signal was caught: an error that comes after it (an
    import it broke, a half-imported module) is the interrupt's doing, and ends as the interrupt."""
    if _FIRST is not None:
        raise Interrupted(_FIRST) from cause


def _raise_interrupted(signum: int, frame) -> None:
    # Idempotent: a second signal (this handler nested in the first, or run after it) finds the first
    # recorded and raises that one again, or finds _ignore installed.
    global _FIRST, _PENDING  # noqa: PLW0603 - the state the handler shares with the code it interrupts
    for sig in STOP_SIGNALS:  # one interrupt: the rollback on the way out must not be interrupted
        signal.signal(sig, _ignore)
    if _FIRST is None:
        _FIRST = first_arrived(signum)
    if _HELD:
        _PENDING = True
        return
    raise Interrupted(_FIRST)


@contextmanager
def held() -> Iterator[None]:
    """An interrupt inside is raised as the section ends (or not, if it raises something else: whoever
    reports that calls raise_if_interrupted). For the few statements that must run together, as a file
    renamed into place and noted for the rollback, a temporary file made and noted for removal."""
    global _HELD, _PENDING  # noqa: PLW0603
    _HELD += 1
    try:
        yield
    finally:
        _HELD -= 1
    if _PENDING and not _HELD:
        _PENDING = False
        raise_if_interrupted()


def _unraisable(hook: Callable[[Any], None]) -> Callable[[Any], None]:
    """sys.unraisablehook, quiet for an Interrupted raised where Python cannot raise it (a `__del__`, a
    weakref callback): it would print a traceback; the interrupt is recorded and ends winder all the same."""

    def quiet(unraisable: Any) -> None:
        if not isinstance(unraisable.exc_value, Interrupted):
            hook(unraisable)

    return quiet


def _excepthook(hook: Callable[..., None]) -> Callable[..., None]:
    """sys.excepthook, quiet for an Interrupted: a C extension that fails to import numpy's C API prints
    the error it got (PyErr_Print, numpy's import_array) and raises an ImportError instead."""

    def quiet(kind: type[BaseException], value: BaseException, tb: Any) -> None:
        if not isinstance(value, Interrupted):
            hook(kind, value, tb)

    return quiet


def block_stop_signals() -> None:
    """Block TERM and INT for the rest of this process (it is ending on an interrupt): a second signal
    stays pending and dies with the process, even in the interpreter's last moments, when Python puts
    the default handlers back and a handler could no longer run."""
    try:
        signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    except (AttributeError, OSError, ValueError):  # not POSIX
        pass


@contextmanager
def stop_signals_held_back() -> Iterator[None]:
    """TERM and INT wait (pending) while this thread is inside. The threads and worker processes
    started inside inherit it, so a stop signal always reaches the main thread, which handles it: a
    thread that did not hold them back could be handed one in the interpreter's last moments, after
    Python put the default handlers back, and the process would die by it after its Error line.
    A worker lets them through once its own handlers are in (worker_init)."""
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    except (AttributeError, OSError, ValueError):  # not POSIX
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


@contextmanager
def interrupts_raise() -> Iterator[None]:
    """TERM and INT raise Interrupted in this (main) thread while inside, so that a job's writes are
    rolled back and batch workers stopped on the way out; the old handlers come back after. After a
    stop signal, whatever leaves the section leaves as Interrupted: an error (the signal's doing, module
    docstring) or nothing (a library swallowed the exception)."""
    import sys  # noqa: PLC0415

    try:
        old = {sig: signal.signal(sig, _raise_interrupted) for sig in STOP_SIGNALS}
    except ValueError:  # not the main thread: signals stay as they are
        yield
        return
    old_hooks = sys.unraisablehook, sys.excepthook
    sys.unraisablehook, sys.excepthook = _unraisable(old_hooks[0]), _excepthook(old_hooks[1])
    try:
        yield
    except Exception as exc:
        raise_if_interrupted(exc)
        raise
    else:
        raise_if_interrupted()
    finally:
        sys.unraisablehook, sys.excepthook = old_hooks  # after the first signal, no handler raises again
        if _FIRST is not None:  # interrupted: the process ends on the way out
            block_stop_signals()  # and a second signal must not end it first
        else:
            for sig, handler in old.items():
                signal.signal(sig, handler)


_IN_JOB = False  # in a worker process: inside a job (an interrupt must roll its files back)


def _worker_signal(signum: int, frame) -> None:
    if _IN_JOB:
        _raise_interrupted(signum, frame)
    os._exit(128 + signum)  # between jobs: nothing to roll back


def worker_init() -> None:
    """A batch worker: TERM and INT roll back the job in hand and end the process; and it gets TERM
    when its parent dies (Linux), so no worker outlives a killed batch."""
    global _ARRIVALS, _FIRST, _HELD, _PENDING  # noqa: PLW0603 - the parent's, copied by fork: not this process's
    _FIRST, _HELD, _PENDING = None, 0, False
    if _ARRIVALS is not None:
        try:
            signal.set_wakeup_fd(-1)
        except ValueError:
            pass
        _ARRIVALS = None
    for sig in STOP_SIGNALS:
        signal.signal(sig, _worker_signal)
    try:
        import ctypes  # noqa: PLC0415

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGTERM))  # PR_SET_PDEATHSIG
        if os.getppid() == 1:  # the parent died before prctl
            os._exit(128 + signal.SIGTERM)
    except (OSError, AttributeError):  # not Linux: the parent's TERM handler stops the workers
        pass
    try:  # started with them held back (stop_signals_held_back): a signal sent since comes now
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
    except (AttributeError, OSError, ValueError):
        pass


def in_worker(job: Callable[..., Any], *args, **kwargs) -> Any:
    global _IN_JOB  # noqa: PLW0603 - the one flag the signal handler reads
    _IN_JOB = True
    try:
        result = job(*args, **kwargs)
    except Interrupted as exc:  # the job's files are rolled back by now
        os._exit(exc.exit_code)
    finally:
        _IN_JOB = False
    if _FIRST is not None:  # an interrupt some library swallowed: the worker ends all the same
        os._exit(128 + _FIRST)
    return result


def stop_workers(pool: ProcessPoolExecutor) -> None:
    """TERM to every worker (each rolls back its job), then KILL to any still running after the grace;
    then shut the pool down and wait (at most the grace) for its manager thread. Left running, that
    thread closes its wake-up pipe while the interpreter's exit writes to it (Python 3.11's
    concurrent.futures checks, then writes), which prints a traceback after a clean interrupt."""
    manager = getattr(pool, "_executor_manager_thread", None)
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for proc in processes:
        try:
            proc.terminate()
        except (OSError, ValueError):
            pass
    deadline = time.monotonic() + WORKER_GRACE_S
    for proc in processes:
        try:
            proc.join(max(0.0, deadline - time.monotonic()))
            if proc.is_alive():
                proc.kill()
                proc.join(WORKER_GRACE_S)
        except (OSError, ValueError, AssertionError):
            pass
    pool.shutdown(wait=False, cancel_futures=True)
    if manager is not None:
        manager.join(WORKER_GRACE_S)
