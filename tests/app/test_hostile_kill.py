"""Hostile input, third round (issue 45): output sets under `kill -9` at any instant.

Before, killed 0 to 30 ms after its first temporary file appeared, 16 of 20 `winder run` left new files
beside old ones, and 17 of 20 left litter no later run removed. The guarantee (docs/guide/output-files.md):
after a kill the folder holds the old set or the new one, or (killed inside the switch's few renames)
a commit record that the next winder writing into the folder completes before anything else; that
writer also removes every temporary file of dead writers.

Two experiments: a writer killed right after each step of the protocol in turn (every instant that
matters, by construction), and `winder run` killed at a random instant of its writing, WINDER_KILL_TRIALS
times (3 in the suite; the issue's 20 or more nightly: WINDER_NIGHTLY=1, or set the count).
"""

from __future__ import annotations

import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.configs import tiny_pipe
from winder.export import journal
from winder.export.journal import LEFTOVER

ROOT = Path(__file__).resolve().parents[2]
NIGHTLY = os.environ.get("WINDER_NIGHTLY") == "1"
TRIALS = int(os.environ.get("WINDER_KILL_TRIALS", "24" if NIGHTLY else "3"))
KILL_WINDOW_S = 0.030  # the issue's: killed 0 to 30 ms after the first temporary file appears
ENV = dict(os.environ, PYTHONPATH=str(ROOT))
NAMES = ("a.csv", "a.gcode", "a.ply", "a.summary.json")


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def _litter(folder: Path) -> list[str]:
    return sorted(n for n in os.listdir(folder) if LEFTOVER.match(n) or n.startswith(".winder-"))


# A child writing the new set, killed (SIGKILL, by itself) right after its `step`-th file operation
# of the protocol: each temporary file made, the commit record's rename, each file's rename.
CHILD = """
import os, signal, sys
from pathlib import Path
import winder.export.atomic as atomic
from winder.app.writes import write_outputs
step, count = int(sys.argv[2]), [0]
def tick():
    count[0] += 1
    if count[0] == step:
        os.kill(os.getpid(), signal.SIGKILL)
real_temporary, real_replace = atomic.write_temporary, os.replace
def temporary(target, data):
    tmp = real_temporary(target, data)
    tick()
    return tmp
def replace(a, b):
    real_replace(a, b)
    tick()
atomic.write_temporary, os.replace = temporary, replace
write_outputs(sys.argv[1], {n: b"new " + n.encode() * 1000 for n in %r})
""" % (NAMES,)


@pytest.mark.parametrize("step", range(1, 2 * len(NAMES) + 2))
def test_a_writer_killed_after_any_step_leaves_a_set_the_next_writer_makes_whole(tmp_path: Path, step: int) -> None:
    folder = tmp_path / "out"
    folder.mkdir()
    old = {n: b"old " + n.encode() for n in NAMES}
    new = {n: b"new " + n.encode() * 1000 for n in NAMES}
    for name, data in old.items():
        (folder / name).write_bytes(data)
    res = subprocess.run([sys.executable, "-c", CHILD, str(folder), str(step)], env=ENV, capture_output=True,
                         timeout=120)
    assert res.returncode == -signal.SIGKILL, res.stderr
    left = {n: d for n, d in _files(folder).items() if not n.startswith(".")}
    records = [n for n in os.listdir(folder) if n.startswith(".winder-") and n.endswith(".journal")]
    committed = step > len(NAMES)  # the record's rename is the step after the last temporary file
    assert bool(records) == committed, (step, os.listdir(folder))
    if not committed:
        assert left == old  # never a mix: the switch had not begun
    with journal.folder_lock(folder) as locked:  # what the next winder writing here does first
        assert locked
        journal.recover(folder)
    assert _files(folder) == (new if committed else old)
    assert _litter(folder) == []


def _config(folder: Path, name: str, angle: float) -> Path:
    path = folder / f"{name}_{angle:g}.yaml"
    path.write_text(tiny_pipe(name, angle).replace("points: 8", "points: 400"), encoding="utf-8")
    return path


def _run(config: Path, out: Path) -> None:
    res = subprocess.run([sys.executable, "-m", "winder", "run", str(config), "-o", str(out)], env=ENV,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr


def _kill_while_writing(config: Path, out: Path, rng: random.Random) -> bool:
    """Start `winder run`, kill -9 it 0 to 30 ms after its first temporary file appears; whether killed."""
    proc = subprocess.Popen([sys.executable, "-m", "winder", "run", str(config), "-o", str(out)], env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        while proc.poll() is None and not any(LEFTOVER.match(n) for n in os.listdir(out)):
            time.sleep(0.0005)
        time.sleep(rng.uniform(0.0, KILL_WINDOW_S))
        killed = proc.poll() is None
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait(timeout=300)
    return killed


def test_run_killed_at_random_instants_never_leaves_a_mix_or_litter(tmp_path: Path) -> None:
    """The issue's experiment: an old set in the folder, a new run killed while it writes; then another
    job's run into the folder. Before it: the old set, the new one, or a commit record; after it: the
    old set or the new one, whole, and no file of a dead writer."""
    old_config, new_config = _config(tmp_path, "a", 45.0), _config(tmp_path, "a", 40.0)
    other = _config(tmp_path, "other", 45.0)
    sets = []
    for config in (old_config, new_config):
        _run(config, tmp_path / f"ref_{config.stem}")
        sets.append(_files(tmp_path / f"ref_{config.stem}"))
    assert all(sets[0][n] != sets[1][n] for n in sets[0])
    rng = random.Random(45)
    outcomes = {"old": 0, "new": 0, "record": 0, "killed": 0}
    for trial in range(TRIALS):
        out = tmp_path / f"trial{trial}"
        shutil.copytree(tmp_path / f"ref_{old_config.stem}", out)
        outcomes["killed"] += _kill_while_writing(new_config, out, rng)
        mine = {n: d for n, d in _files(out).items() if not n.startswith(".")}
        if any(n.startswith(".winder-") and n.endswith(".journal") for n in os.listdir(out)):
            outcomes["record"] += 1
        else:
            assert mine in sets, f"trial {trial}: a mixed set before any recovery: {sorted(mine)}"
        _run(other, out)  # the next run into the folder
        mine = {n: d for n, d in _files(out).items() if n.startswith("a.")}
        assert mine in sets, f"trial {trial}: a mixed set after the next run"
        outcomes["old" if mine == sets[0] else "new"] += 1
        assert _litter(out) == [], f"trial {trial}: litter left: {_litter(out)}"
    print(f"kill -9 experiment, {TRIALS} trials: {outcomes}")  # shown with pytest -rP
    assert outcomes["killed"] >= 1, outcomes
