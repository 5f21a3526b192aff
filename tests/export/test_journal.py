"""winder.export.journal: commit records a later writer completes, and files it must leave alone.

A record is acted on only when every entry is one its writer could have made (its own temporary and
old-file names, beside their output): a record planted in a folder to make the next winder rename or
remove other files, or a record too deeply nested to read, is left as it is and harms nothing."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from winder.export import journal


def _record(folder: Path, kind: str, files: list, pid: int = 999_999_991) -> Path:
    path = folder / f".winder-{pid}-{'ab' * 8}.{kind}"
    path.write_text(json.dumps({"pid": pid, "files": files}), encoding="utf-8")
    return path


@pytest.mark.parametrize("kind", ["journal", "rollback"])
def test_a_planted_record_moves_and_removes_nothing(tmp_path: Path, kind: str) -> None:
    out, victims = tmp_path / "out", tmp_path / "victims"
    out.mkdir()
    victims.mkdir()
    (victims / "thesis.tex").write_text("keep")
    (victims / "other.txt").write_text("keep too")
    plants = [
        _record(out, kind, [[str(victims / "other.txt"), str(victims / "thesis.tex"), None, False]]),
        _record(out, kind, [[str(victims / ".x.winder-999999991-0000000000000000.tmp"), str(victims / "thesis.tex"),
                             None, False]], pid=999_999_992),  # winder's name, but a new file outside the folder
        _record(out, kind, [["a.tmp", "a.csv", None, False]], pid=999_999_993),  # not a winder name
    ]
    deep = out / f".winder-999999994-{'cd' * 8}.{kind}"
    deep.write_text("[" * 200_000 + "]" * 200_000, encoding="utf-8")
    journal.recover(out)
    assert (victims / "thesis.tex").read_text() == "keep" and (victims / "other.txt").read_text() == "keep too"
    assert all(p.exists() for p in (*plants, deep))  # not winder's: left as they are


def test_a_dead_writers_rollback_record_puts_the_old_set_back(tmp_path: Path) -> None:
    """Killed while taking its set back: a.csv was put in place and had an old file (kept as a link), a.ply
    was new and in place, a.gcode's temporary file never moved."""
    pid = 999_999_995
    (tmp_path / "a.csv").write_text("new csv")
    (tmp_path / f".a.csv.winder-{pid}-{'11' * 8}.old").write_text("old csv")
    (tmp_path / "a.ply").write_text("new ply")
    (tmp_path / "a.gcode").write_text("old gcode")
    (tmp_path / f".a.gcode.winder-{pid}-{'22' * 8}.tmp").write_text("new gcode")
    _record(tmp_path, "rollback", [[f".a.csv.winder-{pid}-{'33' * 8}.tmp", "a.csv", f".a.csv.winder-{pid}-{'11' * 8}.old", True],
                                   [f".a.ply.winder-{pid}-{'44' * 8}.tmp", "a.ply", None, False],
                                   [f".a.gcode.winder-{pid}-{'22' * 8}.tmp", "a.gcode", None, True]], pid=pid)
    journal.recover(tmp_path)
    assert {p.name: p.read_text() for p in tmp_path.iterdir()} == {"a.csv": "old csv", "a.gcode": "old gcode"}


def test_leftovers_of_a_live_writer_stay(tmp_path: Path) -> None:
    mine = tmp_path / f".a.csv.winder-{os.getpid()}-{'55' * 8}.tmp"
    mine.write_text("being written")
    dead = tmp_path / f".a.csv.winder-999999996-{'66' * 8}.tmp"
    dead.write_text("left by a dead writer")
    user = tmp_path / ".a.csv.12345.old"  # a user's own name, not winder's mark
    user.write_text("mine")
    journal.recover(tmp_path)
    assert mine.exists() and user.exists() and not dead.exists()


def test_what_earlier_versions_left_beside_a_jobs_outputs_goes(tmp_path: Path) -> None:
    """Issue 45: killed writers of the second round left `.pipe.csv.<pid>.old` and `.pipe.ply.<hex>.tmp`
    that no later run removed; the next run of that job now does (a live pid's stay)."""
    from winder.app.writes import write_outputs  # noqa: PLC0415

    left = [".a.csv.999999997.old", f".a.ply.{'7f' * 8}.tmp", ".a.gcode.999999998.old"]
    kept = [f".a.csv.{os.getpid()}.old", ".notes.999999997.old", f".other.csv.{'7f' * 8}.tmp"]
    for name in left + kept:
        (tmp_path / name).write_text("x")
    write_outputs(tmp_path, {"a.csv": b"1", "a.gcode": b"3", "a.ply": b"2", "a.summary.json": b"{}"})
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(kept + ["a.csv", "a.gcode", "a.ply", "a.summary.json"])
