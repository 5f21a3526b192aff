"""Atomic writes: the whole file or the old one, output permissions, no temporary file left."""

from __future__ import annotations

import os
import stat

import pytest

import winder.export.atomic as atomic
from winder.errors import ExportError


def test_writes_the_payload_with_output_permissions(tmp_path):
    umask = os.umask(0o022)
    try:
        atomic.write_atomic(tmp_path / "a" / "job.csv", "x,y\n")
    finally:
        os.umask(umask)
    out = tmp_path / "a" / "job.csv"
    assert out.read_bytes() == b"x,y\n"
    assert stat.S_IMODE(out.stat().st_mode) == 0o644
    assert sorted(p.name for p in out.parent.iterdir()) == ["job.csv"]


def test_replaces_the_old_file_whole(tmp_path):
    out = tmp_path / "job.gcode"
    out.write_bytes(b"old" * 1000)
    atomic.write_atomic(out, b"new")
    assert out.read_bytes() == b"new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["job.gcode"]


def test_a_taken_temporary_name_is_drawn_again(tmp_path, monkeypatch):
    draws = iter([b"\0" * 8, b"\0" * 8, b"\1" * 8])
    monkeypatch.setattr(atomic.os, "urandom", lambda n: next(draws))
    taken = tmp_path / f".job.ply.{'00' * 8}.tmp"
    taken.write_bytes(b"someone else's")
    atomic.write_atomic(tmp_path / "job.ply", b"ply")
    assert (tmp_path / "job.ply").read_bytes() == b"ply"
    assert taken.read_bytes() == b"someone else's"  # never followed, truncated or removed
    assert sorted(p.name for p in tmp_path.iterdir()) == [taken.name, "job.ply"]


def test_a_folder_that_is_a_file_is_one_clear_error(tmp_path):
    (tmp_path / "out").write_text("a file")
    for target in (tmp_path / "out" / "job.csv", tmp_path / "out" / "deeper" / "job.csv"):
        with pytest.raises(ExportError, match=r"job.csv: cannot write here: .*/out is a file, not a folder$"):
            atomic.write_atomic(target, "x")


def test_a_failed_write_leaves_nothing(tmp_path, monkeypatch):
    def full(*_args):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "replace", full)
    with pytest.raises(ExportError, match="No space left on device"):
        atomic.write_atomic(tmp_path / "job.csv", "x")
    assert list(tmp_path.iterdir()) == []
