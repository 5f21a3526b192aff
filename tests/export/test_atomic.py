"""Atomic writes: the whole file or the old one, output permissions, no temporary file left."""

from __future__ import annotations

import os
import stat

import pytest

import winder.export.atomic as atomic
from winder.errors import ConfigError, ExportError


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
    taken = tmp_path / f".job.ply.winder-{os.getpid()}-{'00' * 8}.tmp"
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


def _null_device(tmp_path):
    """A character device like /dev/null inside tmp_path (mknod needs root), else skip."""
    device = tmp_path / "null"
    try:
        os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    except (PermissionError, AttributeError, OSError):
        pytest.skip("cannot make a device node here")
    return device


def test_a_device_is_written_into_not_replaced(tmp_path):
    """`-o /dev/null` must not put a regular file where the device was (a rename would, as root)."""
    device = _null_device(tmp_path)
    atomic.write_atomic(device, "x,y\n")
    assert stat.S_ISCHR(device.stat().st_mode)
    link = tmp_path / "job.csv"
    link.symlink_to(device)
    atomic.write_atomic(link, "x,y\n")
    assert link.is_symlink() and stat.S_ISCHR(device.stat().st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["job.csv", "null"]


def test_a_fifo_gets_the_payload_and_one_without_reader_is_refused(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    with pytest.raises(ExportError, match=r"pipe.csv: cannot write here: a FIFO that nobody reads$"):
        atomic.write_atomic(fifo, "x")  # at once, not blocked forever
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        atomic.write_atomic(fifo, "x,y\n")
        assert os.read(reader, 100) == b"x,y\n"
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(fifo.stat().st_mode)


def test_a_link_to_a_file_stays_a_link(tmp_path):
    real = tmp_path / "real.csv"
    real.write_text("old")
    link = tmp_path / "job.csv"
    link.symlink_to(real)
    atomic.write_atomic(link, "new")
    assert link.is_symlink() and real.read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["job.csv", "real.csv"]


def test_an_output_path_that_is_an_input_or_no_file_is_refused(tmp_path):
    """`geodesic job.yaml -o job.yaml` (or a link to it, or simulate's -o on its PROGRAM) wrote the
    CSV over the input; `-o ''` wrote nothing and said nothing; `-o x.csv/` wrote x.csv."""
    config = tmp_path / "job.yaml"
    config.write_text("name: t\n")
    link = tmp_path / "link.yaml"
    link.symlink_to(config)
    for output in (str(config), str(link), str(tmp_path / "." / "job.yaml")):
        with pytest.raises(ConfigError, match=r"^-o: is CONFIG itself, which writing there would destroy") as err:
            atomic.check_output_file(output, {"CONFIG": str(config)})
        assert err.value.exit_code == 2
    for output in ("", "x.csv/"):
        with pytest.raises(ConfigError, match=rf"^-o: must name a file, got '{output}'$"):
            atomic.check_output_file(output, {"CONFIG": str(config)})
    atomic.check_output_file(str(tmp_path / "new.csv"), {"CONFIG": str(config), "PROGRAM": str(tmp_path / "gone")})
    assert config.read_text() == "name: t\n"


# -- links to open descriptors (issue 45): written into, never replaced ------------------------------
def test_a_chain_of_links_to_an_open_descriptor_is_a_descriptor(tmp_path):
    (tmp_path / "fd1").symlink_to("/proc/self/fd/1")
    (tmp_path / "hop").symlink_to(tmp_path / "fd1")
    (tmp_path / "fdlink").symlink_to("/proc/self/fd")
    for path in (tmp_path / "fd1", tmp_path / "hop", tmp_path / "fdlink" / "1", "/proc/self/fd/1", "/dev/fd/1"):
        assert atomic.descriptor(path) == (os.getpid(), 1), path
        assert atomic.is_stream(path), path
    (tmp_path / "plain").write_text("x")
    (tmp_path / "tofile").symlink_to(tmp_path / "plain")
    for path in (tmp_path / "plain", tmp_path / "tofile", tmp_path / "new.csv"):
        assert atomic.descriptor(path) is None and not atomic.is_stream(path), path


def test_this_process_descriptor_is_written_at_its_own_offset(tmp_path):
    """A link to /proc/self/fd/N is written through descriptor N (its offset, its append mode), the
    link left a link: the way `-o /dev/stdout >> log` appends."""
    log = tmp_path / "log.txt"
    log.write_bytes(b"kept\n")
    fd = os.open(log, os.O_WRONLY | os.O_APPEND)
    try:
        link = tmp_path / "out.csv"
        link.symlink_to(f"/proc/self/fd/{fd}")
        atomic.write_atomic(link, "x,y\n")
        atomic.write_atomic(link, "1,2\n")
    finally:
        os.close(fd)
    assert log.read_bytes() == b"kept\nx,y\n1,2\n"
    assert link.is_symlink() and os.readlink(link) == f"/proc/self/fd/{fd}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.txt", "out.csv"]


def test_a_user_link_to_a_file_in_another_folder_is_written_through(tmp_path):
    """As cp, a shell's > and editors do: the file the link names is replaced whole, the link stays."""
    (tmp_path / "share").mkdir()
    (tmp_path / "share" / "job.csv").write_text("old")
    (tmp_path / "out").mkdir()
    link = tmp_path / "out" / "job.csv"
    link.symlink_to(tmp_path / "share" / "job.csv")
    atomic.write_atomic(link, "new")
    assert link.is_symlink() and (tmp_path / "share" / "job.csv").read_text() == "new"
    assert sorted(p.name for p in (tmp_path / "share").iterdir()) == ["job.csv"]
