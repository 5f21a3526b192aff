"""Hostile input, second and third rounds (issues 34, 45): outputs that never mix, links written through.

The race is repeated WINDER_TRIALS times (default 4, to keep the suite short; the issue's 200, about 7 minutes on 2 cores):
WINDER_TRIALS=200 python -m pytest tests/app/test_hostile_writes.py -k race
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.configs import tiny_pipe
from winder.app.batch import name_clash
from winder.app.jobs import run_job

ROOT = Path(__file__).resolve().parents[2]
TRIALS = int(os.environ.get("WINDER_TRIALS", "4"))


def _config(folder: Path, stem: str, name: str = "tiny", angle: float = 45.0) -> Path:
    path = folder / f"{stem}.yaml"
    path.write_text(tiny_pipe(name, angle), encoding="utf-8")
    return path


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def test_race_two_runs_into_one_folder_leave_one_whole_set(tmp_path: Path) -> None:
    """Two `winder run` of one job name (configs 0.01 deg apart) into one folder at once: the folder
    holds one run's whole set (before the folder lock, about 1 try in 10 left a mix, both exit 0)."""
    configs = [_config(tmp_path, "a", angle=45.0), _config(tmp_path, "b", angle=45.01)]
    sets = []
    for config in configs:
        out = tmp_path / f"ref_{config.stem}"
        assert run_job(config, out).ok
        sets.append(_files(out))
    assert sets[0] != sets[1]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    mixed = []
    for k in range(TRIALS):
        out = tmp_path / f"out{k}"
        procs = [subprocess.Popen([sys.executable, "-m", "winder", "run", str(c), "-o", str(out)], env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True) for c in configs]
        results = [(p.wait(timeout=120), p.stderr.read()) for p in procs]
        for p in procs:
            p.stderr.close()
        assert [code for code, _ in results] == [0, 0], results
        if _files(out) not in sets:
            mixed.append(k)
    assert mixed == [], f"{len(mixed)} of {TRIALS} trials left a mixed set"


def test_names_whose_files_collide_are_refused_in_a_batch(tmp_path: Path) -> None:
    """`q` and `q.layup` both write q.layup.csv (the layup CSV of q, the job CSV of q.layup)."""
    owner: dict[str, str] = {}
    assert name_clash("q.yaml", "q", owner, "out") is None
    clash = name_clash("ql.yaml", "q.layup", owner, "out")
    assert clash is not None and clash.exit_code == 2
    assert "q.layup.csv" in str(clash) and "q.yaml" in str(clash)
    assert name_clash("r.yaml", "q.lay", owner, "out") is None  # q.lay.csv is nobody's


def test_check_and_run_refuse_q_and_q_layup(tmp_path: Path) -> None:
    q, ql = _config(tmp_path, "q", "q"), _config(tmp_path, "ql", "q.layup")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for args in (["check", str(q), str(ql)],
                 ["run", str(q), str(ql), "--format", "csv", "--format", "layup", "-o", str(tmp_path / "o")]):
        res = subprocess.run([sys.executable, "-m", "winder", *args], env=env, capture_output=True, text=True,
                             timeout=120)
        errors = [line for line in res.stderr.splitlines() if line.startswith("Error:")]
        assert res.returncode == 2, res.stderr
        assert any("would both write q.layup.csv" in e for e in errors), res.stderr
        assert "Traceback" not in res.stderr


@pytest.mark.parametrize("kind", ["dangling", "dangling_deep", "loop"])
def test_links_in_the_folder_are_not_followed_out_of_it(tmp_path: Path, kind: str) -> None:
    config = _config(tmp_path, "tiny")
    out = tmp_path / "out"
    out.mkdir()
    outside = tmp_path / "outside"
    if kind == "dangling":
        (out / "tiny.csv").symlink_to(outside / "tiny.csv")
        outside.mkdir()
    elif kind == "dangling_deep":
        (out / "tiny.csv").symlink_to(outside / "x" / "y" / "tiny.csv")
    else:
        (out / "tiny.gcode").symlink_to(out / "loop")
        (out / "loop").symlink_to(out / "tiny.gcode")
    before = sorted(p.name for p in out.iterdir())
    report = run_job(config, out)
    assert not report.ok and report.exit_code == 1
    assert ("a loop of links" if kind == "loop" else "a link to a file that does not exist") in report.message
    assert sorted(p.name for p in out.iterdir()) == before  # nothing written, the links left alone
    assert not outside.exists() or list(outside.iterdir()) == []


# -- paths: one clear line, exit 2, before any work -------------------------------------------------
LONG = "a" * 300


def _invoke(args: list[str]):
    from click.testing import CliRunner  # noqa: PLC0415

    from winder.cli import main  # noqa: PLC0415

    result = CliRunner().invoke(main, args)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    errors = [line for line in result.stderr.splitlines() if line.startswith("Error:")]
    return result.exit_code, errors


@pytest.mark.parametrize("command", ["run", "geodesic", "simulate", "regress"])
def test_a_path_component_past_255_bytes_is_refused_up_front(tmp_path: Path, command: str) -> None:
    pipe = str(ROOT / "samples" / "pipe.yaml")
    target = str(tmp_path / LONG)
    args = {"run": ["run", pipe, "-o", target],
            "geodesic": ["geodesic", pipe, "--start", "10,0", "--end", "400,90", "-o", target + ".csv"],
            "simulate": ["simulate", pipe, str(tmp_path / "p.gcode"), "-o", target + ".csv"],
            "regress": ["regress", target]}[command]
    code, errors = _invoke(args)
    assert code == 2 and len(errors) == 1, errors
    assert "a name in the path is 30" in errors[0] and "more than the 255 a file name may have" in errors[0]


@pytest.mark.parametrize("command", ["run", "geodesic", "geodesic_below"])
def test_a_loop_of_links_where_an_output_goes_is_refused(tmp_path: Path, command: str) -> None:
    (tmp_path / "l1").symlink_to(tmp_path / "l2")
    (tmp_path / "l2").symlink_to(tmp_path / "l1")
    pipe = str(ROOT / "samples" / "pipe.yaml")
    geodesic = ["geodesic", pipe, "--start", "10,0", "--end", "400,90", "-o"]
    args = {"run": ["run", pipe, "-o", str(tmp_path / "l1")], "geodesic": [*geodesic, str(tmp_path / "l1")],
            "geodesic_below": [*geodesic, str(tmp_path / "l1" / "x.csv")]}[command]
    code, errors = _invoke(args)
    assert code == 2 and len(errors) == 1 and "-o: a loop of links in the path" in errors[0], errors


def test_a_dangling_link_as_the_output_file_is_refused(tmp_path: Path) -> None:
    (tmp_path / "g.csv").symlink_to(tmp_path / "elsewhere" / "g.csv")
    code, errors = _invoke(["geodesic", str(ROOT / "samples" / "pipe.yaml"), "--start", "10,0", "--end", "400,90",
                            "-o", str(tmp_path / "g.csv")])
    assert code == 2 and len(errors) == 1 and "a link to a file that does not exist" in errors[0], errors
    assert not (tmp_path / "elsewhere").exists()


@pytest.mark.parametrize("command", ["check", "run"])
def test_a_config_path_holding_a_newline_stays_on_one_error_line(tmp_path: Path, command: str) -> None:
    config = tmp_path / "a\nb.yaml"
    config.write_text(tiny_pipe("nl", 45).replace("band_width: 10", "band_width: -1"))
    args = [command, str(config)] + (["-o", str(tmp_path / "out")] if command == "run" else [])
    code, errors = _invoke(args)
    assert code == 2 and len(errors) == 1, errors
    assert errors[0].startswith(f"Error: {tmp_path}/a\\nb.yaml: winding.band_width: must be > 0"), errors


# -- standard output ------------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["check", "run"])
def test_closed_standard_output_is_an_error_not_a_silent_success(tmp_path: Path, command: str) -> None:
    config = _config(tmp_path, "tiny")
    args = f"{command} {config}" + (f" -o {tmp_path / 'out'}" if command == "run" else "")
    res = subprocess.run(["sh", "-c", f'"{sys.executable}" -m winder {args} >&-'], capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=120)
    assert res.returncode == 2, res
    assert res.stderr.startswith("Error: standard output is closed (>&-)") and res.stderr.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_geodesic_into_a_closed_pipe_ends_quietly(tmp_path: Path) -> None:
    pipe = ROOT / "samples" / "pipe.yaml"
    cmd = (f'"{sys.executable}" -m winder geodesic {pipe} --start 10,0 --end 400,900 --points 20000 '
           f"-o /dev/stdout | head -c 10")
    res = subprocess.run(["sh", "-c", cmd], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert res.stdout == "i,t,theta_" and res.stderr == "", res.stderr


# -- links to existing files outside the output folder: written through, as cp or a shell's > do ----
def _links_out(folder: Path, outside: Path, names: tuple[str, ...]) -> bytes:
    """Make each of names a link to its own file outside folder ("victim", "victim2"); their bytes."""
    outside.mkdir(exist_ok=True)
    folder.mkdir(parents=True, exist_ok=True)
    for k, name in enumerate(filter(None, names)):
        (outside / f"victim{k or ''}").write_bytes(b"keep me\n")
        (folder / name).symlink_to(outside / f"victim{k or ''}")
    return b"keep me\n"


@pytest.mark.parametrize("command", ["run", "run_jobs_2", "geodesic", "simulate", "regress_update"])
def test_links_out_of_the_folder_are_written_through(tmp_path: Path, command: str) -> None:
    """A link in DIR (or an `-o` file) to an existing file outside its folder: the file it names gets the
    output (replaced whole in its own folder), the link stays a link, nothing else appears outside."""
    outside = tmp_path / "outside"
    pipe = str(ROOT / "samples" / "pipe.yaml")
    out = tmp_path / "out"
    if command.startswith("run"):
        configs = [_config(tmp_path, "tiny"), _config(tmp_path, "tiny2", "tiny2", 50.0)]
        names = ("tiny.csv", "tiny2.gcode")
        jobs = ["--jobs", "2"] if command == "run_jobs_2" else []
        args = ["run", *map(str, configs if jobs else configs[:1]), "-o", str(out), *jobs]
        if not jobs:
            names = ("tiny.csv", "tiny.gcode")
    elif command == "geodesic":
        names = ("g.csv",)
        args = ["geodesic", pipe, "--start", "10,0", "--end", "400,90", "-o", str(out / "g.csv")]
    elif command == "simulate":
        names = ("s.csv",)
        program = str(ROOT / "samples" / "reference" / "pipe" / "pipe.gcode")
        args = ["simulate", pipe, program, "-o", str(out / "s.csv")]
    else:
        out.mkdir()
        _config(out, "tiny")
        names = ("tiny.csv", "tiny.gcode")
        out = out / "reference" / "tiny"
        args = ["regress", str(tmp_path / "out"), "--update"]
    before = _links_out(out, outside, names)
    res = subprocess.run([sys.executable, "-m", "winder", *args], env=dict(os.environ, PYTHONPATH=str(ROOT)),
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert "Traceback" not in res.stderr and "Error" not in res.stderr, res.stderr
    for k, name in enumerate(names):
        victim = outside / f"victim{k or ''}"
        assert (out / name).is_symlink() and os.readlink(out / name) == str(victim), name
        assert victim.read_bytes() != before and victim.stat().st_size > 0, name
    assert sorted(p.name for p in outside.iterdir()) == sorted(f"victim{k or ''}" for k in range(len(names)))


@pytest.mark.parametrize("command", ["run", "geodesic"])
def test_a_link_to_a_folder_where_a_file_goes_is_refused_and_nothing_written(tmp_path: Path, command: str) -> None:
    outside = tmp_path / "outside"
    (outside / "sub").mkdir(parents=True)
    out = tmp_path / "out"
    out.mkdir()
    name = "tiny.gcode" if command == "run" else "g.csv"
    (out / name).symlink_to(outside / "sub")
    if command == "run":
        report = run_job(_config(tmp_path, "tiny"), out)
        code, message = report.exit_code, report.message
    else:
        code, errors = _invoke(["geodesic", str(ROOT / "samples" / "pipe.yaml"), "--start", "10,0", "--end", "400,90",
                                "-o", str(out / name)])
        message = errors[0]
    assert code == (1 if command == "run" else 2), message
    assert ("a link to a folder, not a file" if command == "run" else "is a directory") in message
    assert sorted(p.name for p in out.iterdir()) == [name] and list((outside / "sub").iterdir()) == []


def test_a_file_written_through_a_link_is_put_back_when_the_job_fails(tmp_path: Path, monkeypatch) -> None:
    """The roll-back puts back the old file the link names, and the link stays a link."""
    from winder.errors import ExportError  # noqa: PLC0415
    from winder.export import atomic  # noqa: PLC0415

    config = _config(tmp_path, "tiny")
    out, outside = tmp_path / "out", tmp_path / "outside"
    before = _links_out(out, outside, ("tiny.csv", "tiny.gcode"))
    real, calls = atomic.write_temporary, []

    def third_fails(target, data):
        calls.append(target)
        if len(calls) == 3:
            raise ExportError(f"{target}: cannot write: No space left on device")
        return real(target, data)

    monkeypatch.setattr(atomic, "write_temporary", third_fails)
    assert not run_job(config, out).ok
    assert (out / "tiny.csv").is_symlink() and os.readlink(out / "tiny.csv") == str(outside / "victim")
    assert (outside / "victim").read_bytes() == before and (outside / "victim1").read_bytes() == before
    assert sorted(p.name for p in out.iterdir()) == ["tiny.csv", "tiny.gcode"]
    assert sorted(p.name for p in outside.iterdir()) == ["victim", "victim1"]


def test_a_run_waiting_for_a_locked_folder_names_the_lock_and_its_holder(tmp_path: Path) -> None:
    """A job whose folder another writer holds (a paused run) times out saying so, not "solvers do not
    converge" (issue 45); it writes nothing. The child only writes (no planning, whose time varies)."""
    from winder.export.journal import folder_lock  # noqa: PLC0415

    out = tmp_path / "out"
    out.mkdir()
    child = ("import sys\nfrom winder.app.wall_clock import TimeUp, time_limit, time_up_message\n"
             "from winder.app.writes import write_outputs\ntry:\n    with time_limit(1.0):\n"
             "        write_outputs(sys.argv[1], {'a.csv': b'x'})\nexcept TimeUp as up:\n"
             "    print(time_up_message(1.0, up.activity))\n")
    with folder_lock(out) as locked:
        assert locked
        res = subprocess.run([sys.executable, "-c", child, str(out)], env=dict(os.environ, PYTHONPATH=str(ROOT)),
                             capture_output=True, text=True, timeout=120)
    assert res.stdout.strip() == (f"the job did not finish within its time limit of 1 s (--time-limit): stopped while "
                                  f"waiting for the output folder {out}, whose lock process {os.getpid()} holds (a "
                                  "winder writing there, or a reader taking it)"), res.stdout + res.stderr
    assert list(out.iterdir()) == []
