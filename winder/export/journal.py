"""A set of output files switched in one step, and what a writer killed on the way leaves (docs/guide/output-files.md).

One rename is atomic on POSIX; a set of renames is not. So a set is switched through a commit record
in the output folder, `.winder-<pid>-<16 hex>.journal`, a small JSON list of (temporary file, output
file, hard link kept to the old file or null), itself made by one rename once every temporary file
and old-file link is complete:

- before the record exists, the folder holds the old set (and temporary files): a writer that dies
  leaves only those, and the next writer removes them (roll back);
- once it exists, the new set is decided: the writer renames each temporary file into place and then
  removes the record; a writer that dies in between (a few renames: microseconds) leaves the record,
  and the next winder that writes into the folder completes the renames before anything else
  (roll forward);
- a writer that fails (or is interrupted) after its record first turns the record into
  `.winder-<pid>-<16 hex>.rollback` (one rename), then puts the old files back; a rollback record a
  dead writer leaves is finished the same way by the next one.

Recovery runs under the folder's lock (an advisory flock on the folder itself, which every winder
writer holds while it writes there, and which the system releases when its holder dies): a record
found by the lock's holder is a dead writer's. Temporary files and old-file links carry their
writer's pid (LEFTOVER) and are removed when that process no longer exists.
"""

from __future__ import annotations

import errno
import json
import os
import re
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from winder.progress import doing

__all__ = ["Entry", "commit", "drop_backups", "folder_lock", "forward", "keep_old", "recover", "roll_back", "settle", "settle_earlier"]

# (temporary file, output file, link kept to the old file or None, whether there was an old file: on a
# file system without hard links an old file cannot be kept, and a rollback leaves the new one there)
Entry = tuple[Path, Path, "Path | None", bool]
JOURNAL, ROLLBACK = "journal", "rollback"
_RECORD_MAX_BYTES = 1 << 20  # a record lists a job's few files: anything larger is not winder's
# O_EXCL: the name is ours alone (no file or link of that name is followed or truncated); the
# temporary file is made directly with the permissions an output gets (0666 less the umask).
_FLAGS = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
NAME_TRIES = 100  # a clash needs another writer drawing the same 64 random bits in this folder
TEMP_NAME_BYTES = 64  # of the output's name kept in a temporary file's (the name stays below 255 bytes)
LEFTOVER = re.compile(r"^\..*\.winder-(\d+)-[0-9a-f]{16}\.(?:tmp|old)\Z", re.DOTALL)  # see temporary_name


def temporary_name(name: str, suffix: str = "tmp") -> str:
    """A new hidden name for a file beside `name`, marked with this process's id: the mark
    (LEFTOVER) is how a later writer tells a dead writer's file from a user's."""
    short = os.fsencode(name)[:TEMP_NAME_BYTES].decode("utf-8", "ignore")
    return f".{short}.winder-{os.getpid()}-{os.urandom(8).hex()}.{suffix}"


def open_temporary(path: Path) -> tuple[int, Path]:
    """A new file beside path, open for writing: (descriptor, its path). tempfile.mkstemp does the
    same, but importing tempfile (shutil, random, bz2, lzma) costs more than a small job's writes."""
    for _ in range(NAME_TRIES):
        tmp = path.with_name(temporary_name(path.name))
        try:
            return os.open(tmp, _FLAGS, 0o666), tmp
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name beside {path.name} after {NAME_TRIES} tries")


@contextmanager
def folder_lock(folder: Path, wait: bool = True) -> Iterator[bool]:
    """Hold an exclusive advisory lock on folder while inside; yields whether it is held. wait=False
    takes it only if it is free at once. A file system without flock (or a folder that cannot be
    opened) yields False: the writes go on without it."""
    try:
        import fcntl  # noqa: PLC0415 - POSIX only
    except ImportError:  # pragma: no cover - not POSIX
        yield False
        return
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        yield False
        return
    try:
        yield _lock(fcntl, fd, folder, wait)
    finally:
        os.close(fd)  # releases the lock


def _lock(fcntl, fd: int, folder: Path, wait: bool) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return True
    except BlockingIOError:
        if not wait:
            return False
    except OSError:
        return False
    holder = lock_holder(fd)
    who = f"process {holder}" if holder is not None else "another process"
    with doing(f"waiting for the output folder {folder}, whose lock {who} holds (a winder writing there, or a "
               "reader taking it)"):
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)  # a time limit or an interrupt raises out of here (PEP 475)
        except OSError:
            return False
    return True


def lock_holder(fd: int) -> int | None:
    """The pid holding a flock on fd's file, from /proc/locks (Linux), or None."""
    st = os.fstat(fd)
    inode = f"{os.major(st.st_dev):02x}:{os.minor(st.st_dev):02x}:{st.st_ino}"
    try:
        with open("/proc/locks", encoding="ascii", errors="replace") as fh:
            for line in fh:
                fields = line.split()
                if len(fields) > 5 and fields[1] == "FLOCK" and fields[5] == inode and fields[4].isdigit():
                    return int(fields[4])
    except OSError:
        pass
    return None


def alive(pid: int) -> bool:
    """Whether a process of that id exists (a pid reused by another process counts as alive)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: someone else's process
        return True
    return True


def _path(folder: Path, text: str) -> Path:
    return folder / text  # an absolute path (a link's target in another folder) stays as it is


def _shown(folder: Path, path: Path | None) -> str | None:
    if path is None:
        return None
    return path.name if path.parent == folder else str(path)


def commit(folder: Path, entries: list[Entry]) -> Path:
    """Make the set's commit record in folder (one rename): from here on the new set is decided."""
    files = [[_shown(folder, tmp), _shown(folder, final), _shown(folder, backup), had_old]
             for tmp, final, backup, had_old in entries]
    text = json.dumps({"pid": os.getpid(), "files": files})
    fd, tmp = open_temporary(folder / "set")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        record = folder / f".winder-{os.getpid()}-{os.urandom(8).hex()}.{JOURNAL}"
        os.replace(tmp, record)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return record


def forward(folder: Path, entries: list[Entry], record: Path) -> None:
    """Put each temporary file still there in place, then drop the record and the old files' links."""
    for tmp, final, _, _ in entries:
        try:
            os.replace(tmp, final)
        except FileNotFoundError:  # put in place already
            pass
    record.unlink(missing_ok=True)
    drop_backups(entries)


def drop_backups(entries: list[Entry]) -> None:
    """Remove the links kept to the old files (the old files themselves are replaced or put back)."""
    for _, _, backup, _ in entries:
        if backup is not None:
            backup.unlink(missing_ok=True)


def roll_back(folder: Path, entries: list[Entry], record: Path | None) -> None:
    """Take the set back: a committed record is first turned into a rollback record (one rename); then
    every temporary file goes, and each output put in place gives way to its old file (or to nothing).
    Safe to repeat: an entry whose temporary file and old-file link are both gone is done."""
    if record is not None and record.name.endswith("." + JOURNAL):
        rollback = record.with_name(record.name[: -len(JOURNAL)] + ROLLBACK)
        os.replace(record, rollback)
        record = rollback
    for tmp, final, backup, had_old in entries:
        if tmp.exists() or tmp.is_symlink():
            tmp.unlink(missing_ok=True)  # never put in place
        elif backup is not None:
            try:
                os.replace(backup, final)
            except FileNotFoundError:  # put back already
                pass
        elif record is not None and not had_old:  # a new file of the set, in place: nothing to give way to
            final.unlink(missing_ok=True)
    if record is not None:
        record.unlink(missing_ok=True)
    drop_backups(entries)


def _read_record(folder: Path, record: Path, writer: str) -> list[Entry] | None:
    """The entries of a record, or None for a file that is not a record winder wrote (left alone)."""
    try:
        if record.stat().st_size > _RECORD_MAX_BYTES:
            return None
        files = json.loads(record.read_text(encoding="utf-8"))["files"]
        entries = [(_path(folder, t), _path(folder, f), None if b is None else _path(folder, b), bool(old))
                   for t, f, b, old in files]
    except (OSError, ValueError, KeyError, TypeError, RecursionError):  # RecursionError: JSON nested deep
        return None
    return entries if all(_written_by(entry, folder, writer) for entry in entries) else None


def _written_by(entry: Entry, folder: Path, writer: str) -> bool:
    """Whether an entry is one the record's writer could have made: its temporary file and old-file link
    named by that writer (temporary_name) beside the output, and an output outside the folder (a link's
    target) one that existed. A record planted to rename or remove other files names none of them."""
    tmp, final, backup, had_old = entry
    for path, kind in ((tmp, "tmp"), (backup, "old")):
        if path is None:
            continue
        match = LEFTOVER.match(path.name)
        if match is None or match.group(1) != writer or not path.name.endswith(kind) or path.parent != final.parent:
            return False
    return final.parent == folder or had_old


def recover(folder: Path, locked: bool = True) -> None:
    """Finish what dead writers left in folder: their commit records rolled forward, their rollback
    records rolled back, their temporary files and old-file links removed. locked: the caller holds the
    folder's lock (folder_lock), so every record found is a dead writer's; else only the records of
    processes that no longer exist are finished."""
    try:
        names = os.listdir(folder)
    except OSError:
        return
    for name in sorted(names):
        kind = name.rsplit(".", 1)[-1]
        if not (name.startswith(".winder-") and kind in (JOURNAL, ROLLBACK)):
            continue
        record = folder / name
        writer = name[len(".winder-"):].split("-", 1)[0]
        if not locked and (not writer.isdigit() or alive(int(writer))):
            continue
        entries = _read_record(folder, record, writer)
        if entries is None:
            continue
        try:
            if kind == JOURNAL:
                forward(folder, entries, record)
            else:
                roll_back(folder, entries, record)
        except OSError:  # a read-only folder now: left for a later writer
            continue
    settle(folder, names)


def settle(folder: Path, names: list[str] | None = None) -> None:
    """Remove the temporary files and old-file links of writers that no longer run (LEFTOVER's pid)."""
    for name in names if names is not None else os.listdir(folder):
        match = LEFTOVER.match(name)
        if match is None or alive(int(match.group(1))):
            continue
        try:
            (folder / name).unlink()
        except OSError as exc:
            if exc.errno not in (errno.ENOENT, errno.EISDIR, errno.EPERM, errno.EACCES, errno.EROFS):
                raise


def keep_old(final: Path) -> tuple[Path | None, bool]:
    """(a hard link kept to the regular file at final, or None; whether there is one there): what a
    rollback puts back. None with True where the folder has no hard links (some network or FAT ones)."""
    try:
        if not stat.S_ISREG(os.lstat(final).st_mode):
            return None, False
    except OSError:
        return None, False
    backup = final.with_name(temporary_name(final.name, "old"))
    try:
        os.link(final, backup, follow_symlinks=False)
    except OSError:
        return None, True
    return backup, True


def settle_earlier(folder: Path, names, locked: bool) -> None:
    """Remove what writers of winder's earlier versions left beside these outputs: `.<name>.<pid>.old`
    of a dead pid, and, under the folder's lock (those writers held it too), `.<name>.<16 hex>.tmp`."""
    wanted = set(names)
    for entry in os.listdir(folder):
        match = _EARLIER.match(entry)
        if match is None or match.group(1) not in wanted:
            continue
        pid = match.group(2)
        if (pid is not None and alive(int(pid))) or (pid is None and not locked):
            continue
        try:
            (folder / entry).unlink()
        except OSError:
            pass


_EARLIER = re.compile(r"^\.(.+?)\.(?:(\d+)\.old|[0-9a-f]{16}\.tmp)\Z", re.DOTALL)
