"""winder.app.jobs: a job's outputs are all-or-nothing (a failed job leaves no file of its own, not even
a partial one) and reproducible: byte-identical from run to run and whatever the number of worker
processes."""

from __future__ import annotations

import os
import pickle
import stat
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.configs import tiny_pipe
import winder.export.atomic
import winder.export.gcode
import winder.export.ply
from winder.cli import main
from winder.config.job import load_config
from winder.errors import ExportError
from winder.app.jobs import ALL_FORMATS, JobReport, JobTask, exit_status, output_names, run_job, run_jobs

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples"
CONFIGS = sorted(SAMPLES.glob("*.yaml"))
ALL_FILES = {"pipe.csv", "pipe.gcode", "pipe.ply", "pipe.summary.json"}

TINY = tiny_pipe()


@pytest.fixture
def tiny(tmp_path) -> Path:
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY)
    return path


def names(folder: Path) -> set[str]:
    return {p.name for p in folder.iterdir()} if folder.exists() else set()


def contents(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


# -- the report ------------------------------------------------------------------------------------
def test_report_of_a_good_job(tiny, tmp_path):
    out = tmp_path / "out"
    report = run_job(tiny, out)
    assert report.ok and report.exit_code == 0 and report.message == ""
    assert report.name == "tiny" and report.config == str(tiny)
    assert [Path(p).name for p in report.outputs] == output_names("tiny", ALL_FORMATS)
    assert report.fiber_length_mm > 0 and report.layers == 1 and report.seconds > 0
    assert pickle.loads(pickle.dumps(report)) == report  # crosses process boundaries
    assert pickle.loads(pickle.dumps(run_job)) is run_job


def test_report_of_an_invalid_config(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: bad\nmandrel: {axis: {type: line, length: -1}}\n")
    report = run_job(bad, tmp_path / "out")
    assert not report.ok and report.exit_code == 2 and report.status == "invalid"
    assert report.message.startswith(f"{bad}: mandrel.axis.length")
    assert report.outputs == () and names(tmp_path / "out") == set()


def test_timings_never_go_into_files(tiny, tmp_path):
    report = run_job(tiny, tmp_path / "out")
    for path in report.outputs:
        data = Path(path).read_bytes()
        assert b"seconds" not in data and b"elapsed" not in data


def test_exit_status_of_a_batch():
    assert exit_status([]) == 0
    assert exit_status([0, 0]) == 0
    assert exit_status([0, 1]) == 1
    assert exit_status([1, 2, 0]) == 2


# -- all or nothing --------------------------------------------------------------------------------
def test_failing_exporter_leaves_nothing(tiny, tmp_path, monkeypatch):
    def broken(plan, band_width):
        raise ExportError(f"{plan.source}: the disk is on fire")

    monkeypatch.setattr(winder.export.ply, "ply_bytes", broken)
    out = tmp_path / "out"
    out.mkdir()
    (out / "unrelated.txt").write_text("keep me")
    report = run_job(tiny, out)
    assert not report.ok and report.exit_code == 1
    assert report.message == f"{tiny}: the disk is on fire"
    assert names(out) == {"unrelated.txt"}  # csv and gcode were rendered, never written


def test_failure_while_writing_removes_what_was_renamed(tiny, tmp_path, monkeypatch):
    real = winder.export.atomic.write_temporary
    calls = []

    def flaky(path, data):
        calls.append(Path(path))
        if len(calls) == 3:  # csv and gcode are in place when the PLY cannot be written
            raise ExportError(f"{path}: cannot write: No space left on device")
        return real(path, data)

    monkeypatch.setattr(winder.export.atomic, "write_temporary", flaky)
    out = tmp_path / "out"
    report = run_job(tiny, out)
    assert [p.name for p in calls] == ["tiny.csv", "tiny.gcode", "tiny.ply"]
    assert not report.ok and report.exit_code == 1 and "No space left" in report.message
    assert names(out) == set()  # nothing of this job, no temporary file either


def _third_write_fails(monkeypatch):
    """Make the third file a job writes fail, as a full disk would; returns the real writer."""
    real = winder.export.atomic.write_temporary
    calls = []

    def flaky(path, data):
        calls.append(path)
        if len(calls) == 3:
            raise ExportError(f"{path}: cannot write: No space left on device")
        return real(path, data)

    monkeypatch.setattr(winder.export.atomic, "write_temporary", flaky)
    return real


def test_failure_while_writing_puts_back_the_previous_outputs(tiny, tmp_path, monkeypatch):
    out = tmp_path / "out"
    assert run_job(tiny, out).ok
    before = contents(out)
    tiny.write_text(TINY.replace("angle: 45", "angle: 40"))  # a new plan: different bytes
    real = _third_write_fails(monkeypatch)
    assert not run_job(tiny, out).ok
    assert contents(out) == before  # the earlier run's files, whole, and nothing else
    monkeypatch.setattr(winder.export.atomic, "write_temporary", real)
    assert run_job(tiny, out).ok
    after = contents(out)
    assert after.keys() == before.keys() and after["tiny.csv"] != before["tiny.csv"]


def test_failure_while_writing_keeps_links_and_fifos_of_the_folder(tiny, tmp_path, monkeypatch):
    """An output name that is a link (to a file kept elsewhere) or a FIFO: the failed job puts the
    link's file back and leaves link and FIFO in place, never a regular file instead of them; the FIFO
    is written only once the set is in place (here never)."""
    out = tmp_path / "out"
    assert run_job(tiny, out).ok
    kept = tmp_path / "kept.csv"
    (out / "tiny.csv").rename(kept)
    (out / "tiny.csv").symlink_to(kept)
    fifo = out / "tiny.gcode"
    (out / "tiny.gcode").unlink()
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    before = kept.read_bytes()
    tiny.write_text(TINY.replace("angle: 45", "angle: 40"))
    _third_write_fails(monkeypatch)
    try:
        assert not run_job(tiny, out).ok
        assert os.read(reader, 1 << 20) == b""  # a stream is written once the set is in place: never here
    finally:
        os.close(reader)
    assert (out / "tiny.csv").is_symlink() and kept.read_bytes() == before
    assert stat.S_ISFIFO(fifo.lstat().st_mode)


def test_interrupt_while_writing_removes_what_was_renamed(tiny, tmp_path, monkeypatch):
    real = winder.export.atomic.write_temporary
    calls = []

    def interrupted(path, data):
        calls.append(path)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(path, data)

    monkeypatch.setattr(winder.export.atomic, "write_temporary", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run_job(tiny, tmp_path / "out")
    assert names(tmp_path / "out") == set()


def test_unexpected_exception_is_an_internal_error(tiny, tmp_path, monkeypatch):
    def buggy(plan, machine, *rest):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(winder.export.gcode, "gcode_text", buggy)
    report = run_job(tiny, tmp_path / "out")
    assert not report.ok and report.exit_code == 1
    assert "internal error (ZeroDivisionError: float division by zero)" in report.message
    assert report.message.startswith(str(tiny))
    assert names(tmp_path / "out") == set()


def test_cli_failing_exporter_leaves_nothing(tiny, tmp_path, monkeypatch):
    def broken(plan, machine, *rest):
        raise ExportError(f"{plan.source}: machine.limits.carriage: exceeded")

    monkeypatch.setattr(winder.export.gcode, "gcode_text", broken)
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["run", str(tiny), "-o", str(out)])
    assert result.exit_code == 1
    assert f"Error: {tiny}: machine.limits.carriage: exceeded" in result.stderr
    assert "Traceback" not in result.output
    assert names(out) == set()


# -- reproducible ----------------------------------------------------------------------------------
def test_byte_identical_across_runs(tmp_path):
    first, second = tmp_path / "a", tmp_path / "b"
    assert run_job(SAMPLES / "pipe.yaml", first).ok
    assert run_job(SAMPLES / "pipe.yaml", second).ok
    assert names(first) == ALL_FILES
    assert contents(first) == contents(second)


def test_parallel_equals_sequential_on_all_samples(tmp_path):
    """`winder run --jobs 2` writes exactly the bytes of a sequential run, for every sample."""
    sequential, parallel = tmp_path / "seq", tmp_path / "par"
    runner = CliRunner()
    result = runner.invoke(main, ["run", *map(str, CONFIGS), "-o", str(sequential)])
    assert result.exit_code == 0, result.output
    result = runner.invoke(main, ["run", *map(str, CONFIGS), "-o", str(parallel), "--jobs", "2"])
    assert result.exit_code == 0, result.output
    # csv, gcode, ply and summary per job, and a robot cell's own language beside them (the elbow's
    # KUKA cell: .src and .dat)
    krl = sum(1 for c in CONFIGS if load_config(c).machine.dialect == "krl")
    assert len(names(sequential)) == 4 * len(CONFIGS) + 2 * krl
    seq, par = contents(sequential), contents(parallel)
    assert seq.keys() == par.keys()
    differing = [name for name in seq if seq[name] != par[name]]
    assert differing == []
    # the console shows the jobs in the order given, whatever order they finished in
    rows = [line.split()[0] for line in result.stdout.splitlines()[1:len(CONFIGS) + 1]]
    assert rows == [str(c) for c in CONFIGS]


def _dies(config, out_dir, formats):
    """A job whose worker process dies (os._exit), as if killed."""
    import os  # noqa: PLC0415

    if "die" in str(config):
        os._exit(3)
    return JobReport(str(config), Path(config).stem, True, 0, "")


def test_a_dead_worker_fails_its_job_only(tmp_path):
    tasks = [JobTask(str(tmp_path / "die.yaml"), str(tmp_path))] + [
        JobTask(str(tmp_path / f"ok{i}.yaml"), str(tmp_path)) for i in range(3)]
    reports = dict(run_jobs(tasks, workers=2, job=_dies))
    assert not reports[0].ok and reports[0].exit_code == 1
    assert "worker process" in reports[0].message and reports[0].message.startswith(str(tmp_path / "die.yaml"))
    assert all(reports[i].ok for i in (1, 2, 3))  # taken down with the pool, then run again on its own
