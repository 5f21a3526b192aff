"""Atomic file writes: a temporary file in the target folder, then a rename.

A job that fails leaves no output file of its own behind, not even a partial one (docs/guide/outputs.md). An
output path that names a device, a FIFO or a socket (`-o /dev/null`, `-o /dev/stdout`) is written
straight into it: a rename would put a regular file in the device's place. A symbolic link to a
file in the link's own folder (or below it) stays a link: the file it names is replaced. A link out of
its folder is never written through: the link itself is replaced by the new file, and the file it
named, elsewhere, is left as it was (an output folder's files stay inside it, whatever links it holds).
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from winder.errors import ConfigError, ExportError

# O_EXCL: the name is ours alone (no file or link of that name is followed or truncated); the
# temporary file is made directly with the permissions an output gets (0666 less the umask).
_FLAGS = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
NAME_TRIES = 100  # a clash needs another writer drawing the same 64 random bits in this folder


def _open_temporary(path: Path) -> tuple[int, Path]:
    """A new file beside path, open for writing: (descriptor, its path). tempfile.mkstemp does the
    same, but importing tempfile (shutil, random, bz2, lzma) costs more than a small job's writes."""
    for _ in range(NAME_TRIES):
        tmp = path.with_name(f".{path.name}.{os.urandom(8).hex()}.tmp")
        try:
            return os.open(tmp, _FLAGS, 0o666), tmp
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name beside {path.name} after {NAME_TRIES} tries")


def is_stream(path: Path) -> bool:
    """Whether path (links followed) is a device, a FIFO or a socket: written into, never replaced."""
    try:
        mode = os.stat(path).st_mode
    except OSError:  # missing, or a dangling link
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def output_target(path: str | Path) -> Path:
    """The path a write to path replaces: the file a symbolic link names when that file is in the link's
    own folder or below it (so the link stays), else path itself (a link out of the folder included)."""
    path = Path(path)
    if not path.is_symlink() or is_stream(path):
        return path
    target = path.resolve()
    return target if target.is_relative_to(path.parent.resolve()) else path


def check_output_file(output: str, inputs: dict[str, str]) -> None:
    """Refuse (ConfigError, exit 2, naming -o) an output file path that is empty, ends in a slash (a
    folder), or is one of the inputs (name -> path) by any path or link, which the write would destroy."""
    from winder.export.paths import check_path  # noqa: PLC0415

    if not output or output.endswith(("/", os.sep)):
        raise ConfigError(f"must name a file, got {output!r}", key_path="-o")
    check_path(output, "-o", output=True)
    for name, given in inputs.items():
        try:
            same = os.path.samefile(output, given)
        except OSError:  # one of them missing: not the same file
            continue
        if same:
            raise ConfigError(f"is {name} itself, which writing there would destroy, got {output!r}", key_path="-o")


def _write_stream(path: Path, payload: bytes) -> None:
    # O_NONBLOCK: a FIFO nobody reads refuses at once (ENXIO) instead of blocking forever.
    try:
        fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        why = "a FIFO that nobody reads" if exc.errno == errno.ENXIO else exc.strerror or str(exc)
        raise ExportError(f"{path}: cannot write here: {why}") from exc
    try:
        os.set_blocking(fd, True)
        with os.fdopen(fd, "wb") as fh:
            fh.write(payload)
    except BrokenPipeError:  # `-o /dev/stdout | head`: the reader has what it wanted; the caller ends quietly
        raise
    except OSError as exc:
        raise ExportError(f"{path}: cannot write: {exc.strerror or exc}") from exc


def write_atomic(path: str | Path, data: bytes | str) -> None:
    """Write data to path so that readers see either the old file or the whole new one."""
    path = Path(path)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    if is_stream(path):
        _write_stream(path, payload)
        return
    target = output_target(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = _open_temporary(target)
    except (FileExistsError, NotADirectoryError) as exc:  # a file where a folder of the path should be
        blocker = next((p for p in (target.parent, *target.parent.parents) if p.exists() and not p.is_dir()),
                       None)
        why = f"{blocker} is a file, not a folder" if blocker is not None else exc.strerror or str(exc)
        raise ExportError(f"{path}: cannot write here: {why}") from exc
    except OSError as exc:
        raise ExportError(f"{path}: cannot write here: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(payload)
        os.replace(tmp, target)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise ExportError(f"{path}: cannot write: {exc.strerror}") from exc
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
