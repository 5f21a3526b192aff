"""A job's output files put in place as one set, whatever else writes into the same folder.

Each file is written atomically (winder.export.atomic); the set is made whole by two things:

- an advisory lock on the output folder itself (flock on the folder's descriptor, so no lock file is
  left behind) held while the set is put in place, so that two `winder run` writing one folder at
  once (two shells, two CI jobs, a batch's workers) put their sets in one after the other: the folder
  ends with one set or the other, never a mix of both;
- a roll-back: on any failure (or an interrupt) the files already put in place are taken back and the
  files they replaced put back (kept as hard links until the end).

An output name that is a link is followed only to an existing file inside the output folder (the
file it names is replaced and the link stays); a link to an existing file or folder outside it is
replaced itself, atomically, by the job's file (winder.export.atomic.output_target), the file it
named left untouched, and put back if the job fails; a link to nothing (dangling, or to a folder
that does not exist) or a loop of links is refused before anything is written: following it would
create folders and files outside the output folder.
"""

from __future__ import annotations

import errno
import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from winder.app.interrupts import held
from winder.errors import ExportError

__all__ = ["folder_lock", "write_outputs"]


@contextmanager
def folder_lock(folder: Path) -> Iterator[None]:
    """Hold an exclusive advisory lock on folder (created if missing) while inside. Where the
    folder cannot be locked (a file system without flock, a folder not readable), the writes go
    on without it, as before: the lock only orders winder's own writers."""
    try:
        import fcntl  # noqa: PLC0415 - POSIX only
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        yield
        return
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)  # an interrupt while waiting raises out of here (PEP 475)
        except OSError:
            pass
        yield
    finally:
        os.close(fd)  # releases the lock


def _refuse_links_out(folder: Path, names) -> None:
    """ExportError for an output name that is a link to nothing or a loop (module docstring)."""
    for file_name in names:
        path = folder / file_name
        if not path.is_symlink():
            continue
        try:
            os.stat(path)
        except OSError as exc:
            why = "a loop of links" if exc.errno == errno.ELOOP else "a link to a file that does not exist"
            raise ExportError(f"{path}: {why}: not followed out of the output folder; remove the link, got "
                              f"{os.readlink(path)!r}") from exc


def write_outputs(out_dir: str | Path, rendered: dict[str, bytes]) -> list[str]:
    """Write the rendered files (file name -> bytes) into out_dir as one set and return their paths.

    All or nothing: on any failure (or an interrupt) the files this call already put in place are
    taken back again; where one replaced the output of an earlier run, that earlier file is put
    back, so the folder holds the old set or the new set, never a mix.
    """
    from winder.export.atomic import is_stream, output_target, write_atomic  # noqa: PLC0415

    folder = Path(out_dir)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:  # a file in the way, a read-only parent: write_atomic says which, for the first file
        pass
    _refuse_links_out(folder, rendered)
    written: list[Path] = []  # the files to take back: a link's target, not a device it names
    backups: dict[Path, Path] = {}
    with folder_lock(folder):
        try:
            for file_name, data in rendered.items():
                path = folder / file_name
                if is_stream(path):  # a device or FIFO in the folder (a link to /dev/null): nothing to take back
                    write_atomic(path, data)
                    continue
                target = output_target(path)
                with held():  # a stop signal waits until the file is in place and noted for the rollback
                    backup = _keep_old(target)
                    if backup is not None:
                        backups[target] = backup
                    write_atomic(target, data)
                    written.append(target)
        except BaseException:
            with held():  # the rollback is not cut short by an interrupt (after a failure of another kind)
                for path in reversed(written):
                    try:
                        if path in backups:
                            os.replace(backups.pop(path), path)
                        else:
                            path.unlink(missing_ok=True)
                    except OSError:
                        pass
            raise
        finally:
            with held():  # nor is the removal of the old files kept for it
                for backup in backups.values():
                    try:
                        backup.unlink(missing_ok=True)
                    except OSError:
                        pass
    return [str(folder / file_name) for file_name in rendered]


def _keep_old(path: Path) -> Path | None:
    """A hard link to an existing file or symbolic link at path (the link itself, not what it names: to
    put it back if the job fails), or None."""
    try:
        mode = os.lstat(path).st_mode
    except OSError:
        return None
    if not (stat.S_ISREG(mode) or stat.S_ISLNK(mode)):
        return None
    backup = path.with_name(f".{path.name}.{os.getpid()}.old")
    try:
        backup.unlink(missing_ok=True)
        os.link(path, backup, follow_symlinks=False)
    except OSError:  # no hard links here (some network or FAT folders): no way back, as without
        return None
    return backup
