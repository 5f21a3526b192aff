"""A stop signal's exception cut short and turned into another one (issue 34): pybind11's modules of
scipy wrap an exception raised while they initialize as `ImportError: initialization failed`, which a
job reported as an internal error (exit 1). The first signal decides, whatever becomes of its
exception, and a second one changes nothing. In this process, with its own signals: each test puts
the handlers, the signal mask and the module's record back.
"""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from winder.app import interrupts, jobs
from winder.app.interrupts import held, interrupted, interrupts_raise
from winder.app.writes import write_outputs
from winder.errors import Interrupted

ROOT = Path(__file__).resolve().parents[2]
PIPE = ROOT / "samples" / "pipe.yaml"
DELIVERY_S = 0.05  # a signal sent to this process is handled within this (the next bytecode, in fact)

pytestmark = pytest.mark.skipif(not hasattr(signal, "pthread_sigmask"), reason="POSIX signals")


@pytest.fixture(autouse=True)
def _own_signals(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    handlers = {sig: signal.getsignal(sig) for sig in interrupts.STOP_SIGNALS}
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, ())
    monkeypatch.setattr(interrupts, "_FIRST", None)
    monkeypatch.setattr(interrupts, "_PENDING", False)
    monkeypatch.setattr(interrupts, "_HELD", 0)
    monkeypatch.setattr(interrupts, "_ARRIVALS", None)  # the order is the calls' here
    try:
        yield
    finally:
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)


def _signal_self(sig: int) -> None:
    os.kill(os.getpid(), sig)
    time.sleep(DELIVERY_S)  # the handler runs here


def test_an_import_error_after_a_signal_ends_the_job_as_the_interrupt(monkeypatch, tmp_path: Path) -> None:
    def plan_cut_short(job, progress=None):
        try:
            _signal_self(signal.SIGTERM)
        except Interrupted as exc:  # as pybind11 does in a module's initialization
            raise ImportError("initialization failed") from exc
        raise AssertionError("the signal was not handled")

    monkeypatch.setattr(jobs, "_plan", plan_cut_short)
    with pytest.raises(Interrupted) as caught, interrupts_raise():
        jobs.run_job(PIPE, tmp_path / "out")
    assert caught.value.exit_code == 128 + signal.SIGTERM
    assert not (tmp_path / "out").exists()


def test_the_first_signal_decides_and_a_second_changes_nothing() -> None:
    with pytest.raises(Interrupted) as caught, interrupts_raise():
        with held():  # both arrive inside: recorded, not raised
            _signal_self(signal.SIGINT)
            _signal_self(signal.SIGTERM)
            assert interrupted() == signal.SIGINT
    assert caught.value.exit_code == 128 + signal.SIGINT  # INT then TERM: 130, as a shell expects
    assert signal.SIGTERM in signal.pthread_sigmask(signal.SIG_BLOCK, ())  # a third one waits for the exit


def test_a_signal_while_a_set_is_written_leaves_the_set_or_nothing(monkeypatch, tmp_path: Path) -> None:
    from winder.export import atomic

    write = atomic.write_temporary
    calls = []

    def write_then_signal(path, data):
        tmp = write(path, data)
        calls.append(path)
        if len(calls) == 2:  # between the second file's temporary and its note for the rollback
            _signal_self(signal.SIGTERM)
        return tmp

    monkeypatch.setattr(atomic, "write_temporary", write_then_signal)
    with pytest.raises(Interrupted), interrupts_raise():
        write_outputs(tmp_path, {"a.csv": b"1", "a.gcode": b"2", "a.ply": b"3"})
    assert len(calls) == 2  # held until the second file was noted, then raised before the third
    assert os.listdir(tmp_path) == []  # no file, no temporary or backup file


def test_a_signal_in_a_finalizer_is_quiet_and_still_ends_the_work(monkeypatch) -> None:
    import sys

    printed = []
    monkeypatch.setattr(sys, "unraisablehook", printed.append)  # where Python would print its traceback

    class Finalized:
        def __del__(self) -> None:
            _signal_self(signal.SIGINT)  # raised in a __del__: Python cannot raise it, only report it

    with pytest.raises(Interrupted) as caught, interrupts_raise():
        Finalized()
        assert interrupted() == signal.SIGINT
        interrupts.raise_if_interrupted()  # where the job's next error or the command's end asks
    assert caught.value.exit_code == 128 + signal.SIGINT
    assert printed == []
    assert sys.unraisablehook == printed.append  # put back


def test_a_signal_printed_by_a_c_extension_is_quiet(monkeypatch) -> None:
    # numpy's import_array (in scipy's modules) prints the error it got through sys.excepthook
    # (PyErr_Print) and raises ImportError: the ImportError ends as the interrupt, the print is silent.
    import sys

    printed = []
    monkeypatch.setattr(sys, "excepthook", lambda *args: printed.append(args))
    with interrupts_raise():
        sys.excepthook(Interrupted, Interrupted(signal.SIGINT), None)
        sys.excepthook(ValueError, ValueError("other"), None)
    assert [args[0] for args in printed] == [ValueError]
