"""Atomic file writes: a temporary file beside the target, then a rename (docs/guide/output-files.md).

A job that fails leaves no output file of its own behind, not even a partial one. Where an
output path leads decides how it is written:

- a device, a FIFO or a socket (`-o /dev/null`), or a link to an open descriptor (`/dev/stdout`,
  `/dev/fd/N`, `/proc/self/fd/N`, or a link to one of them): written into, never replaced; a
  descriptor of this process through the descriptor itself (`-o /dev/stdout > out.csv` fills out.csv at
  the shell's offset, `>>` appends), another process's descriptor appended to;
- a symbolic link to a regular file, wherever that file is: written through, as `cp`, a shell's `>` or
  an editor do: the file it names is replaced atomically in its own folder and the link stays;
- a link to nothing, a loop of links or a link to a folder: refused (following it would create files
  elsewhere, or there is no file to write);
- a regular file or a new name: replaced atomically.

Temporary files are named `.<name>.winder-<pid>-<16 hex>.tmp` (winder.export.journal removes those of
dead writers).
"""

from __future__ import annotations

import errno
import os
import re
import stat
import sys
from pathlib import Path

from winder.errors import ConfigError, ExportError
from winder.export.journal import open_temporary

_DESCRIPTORS = re.compile(r"^/proc/(\d+)/(?:task/\d+/)?fd\Z")  # /proc/self/fd, /dev/fd resolved
MAX_HOPS = 40  # links followed before a chain counts as a loop (Linux's own limit)


def descriptor(path: str | Path) -> tuple[int, int] | None:
    """(pid, fd) when path, or a link on its way, names an open descriptor (/proc/<pid>/fd/<fd>, which
    /dev/stdout, /dev/fd/N and /proc/self/fd/N are); else None. Such a link's target is the file the
    descriptor has open, which may lie anywhere: it is the descriptor that is written into."""
    hop = os.path.abspath(os.fspath(path))
    for _ in range(MAX_HOPS):
        where = _DESCRIPTORS.match(os.path.realpath(os.path.dirname(hop)))
        if where is not None and os.path.basename(hop).isdigit():
            return int(where.group(1)), int(os.path.basename(hop))
        try:
            hop = os.path.join(os.path.dirname(hop), os.readlink(hop))
        except OSError:  # not a link (or gone): the end of the chain
            return None
    return None


def is_stream(path: str | Path) -> bool:
    """Whether path is written into, never replaced: a device, a FIFO or a socket (links followed), or
    a link to an open descriptor (descriptor)."""
    if descriptor(path) is not None:
        return True
    try:
        mode = os.stat(path).st_mode
    except OSError:  # missing, or a dangling link
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def output_target(path: str | Path) -> Path:
    """The file a write to path replaces: path itself, or the regular file a link names (wherever it is:
    the link stays). ExportError for a link to nothing, a loop of links, or a folder (by link or not)."""
    path = Path(path)
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    try:
        mode = os.stat(target).st_mode
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise ExportError(f"{path}: a loop of links: not followed; remove the link") from exc
        if target is not path:
            raise ExportError(f"{path}: a link to a file that does not exist: not followed; remove the link, got "
                              f"{os.readlink(path)!r}") from exc
        return path  # a new file
    if stat.S_ISDIR(mode):
        what = "a link to a folder" if target is not path else "a folder"
        raise ExportError(f"{path}: cannot write here: {what}, not a file")
    return target


def check_output_file(output: str, inputs: dict[str, str]) -> None:
    """Refuse (ConfigError, exit 2, naming -o) an output file path that is empty, ends in a slash or is a
    folder, or is one of the inputs (name -> path) by any path or link, which the write would destroy."""
    from winder.export.paths import check_path, shown  # noqa: PLC0415

    if not output or output.endswith(("/", os.sep)) or (os.path.isdir(output) and descriptor(output) is None):
        raise ConfigError(f"must name a file, got {shown(output)!r}", key_path="-o")
    check_path(output, "-o", output=True)
    for name, given in inputs.items():
        try:
            same = os.path.samefile(output, given)
        except OSError:  # one of them missing: not the same file
            continue
        if same:
            raise ConfigError(f"is {name} itself, which writing there would destroy, got {output!r}", key_path="-o")


def write_stream(path: str | Path, payload: bytes) -> None:
    """Write payload into a device, FIFO, socket or descriptor (is_stream); ExportError if it cannot be."""
    held = descriptor(path)
    if held is not None and held[0] == os.getpid():
        _write_descriptor(path, held[1], payload)
        return
    flags = os.O_WRONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    try:  # another process's descriptor: appended to, never truncated
        if held is not None and stat.S_ISREG(os.stat(path).st_mode):
            flags |= os.O_APPEND
        fd = os.open(path, flags)  # O_NONBLOCK: a FIFO nobody reads refuses at once (ENXIO), never blocks
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


def _write_descriptor(path: str | Path, fd: int, payload: bytes) -> None:
    """Write payload to this process's open descriptor fd, after what Python's own streams hold."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):  # closed or replaced streams: nothing held
            pass
    view = memoryview(payload)
    try:
        while view:
            view = view[os.write(fd, view):]
    except BrokenPipeError:
        raise
    except OSError as exc:
        raise ExportError(f"{path}: cannot write: {exc.strerror or exc}") from exc


def write_temporary(target: Path, payload: bytes) -> Path:
    """The whole payload in a new temporary file beside target (target's folder made if missing)."""
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = open_temporary(target)
    except (FileExistsError, NotADirectoryError) as exc:  # a file where a folder of the path should be
        blocker = next((p for p in (target.parent, *target.parent.parents) if p.exists() and not p.is_dir()),
                       None)
        why = f"{blocker} is a file, not a folder" if blocker is not None else exc.strerror or str(exc)
        raise ExportError(f"{target}: cannot write here: {why}") from exc
    except OSError as exc:
        raise ExportError(f"{target}: cannot write here: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(payload)
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        if isinstance(exc, OSError):
            raise ExportError(f"{target}: cannot write: {exc.strerror}") from exc
        raise
    return tmp


def write_atomic(path: str | Path, data: bytes | str) -> None:
    """Write data to path so that readers see either the old file or the whole new one (the module's
    rules for devices, descriptors and links); a dead writer's leftovers in that folder go first."""
    from winder.export.journal import folder_lock, recover  # noqa: PLC0415

    path = Path(path)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    if is_stream(path):
        write_stream(path, payload)
        return
    target = output_target(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError:  # a file in the way: write_temporary names it
        pass
    with folder_lock(target.parent, wait=False) as locked:
        if locked:  # another winder writing there (a paused run): its folder is left to it
            recover(target.parent)
        tmp = write_temporary(target, payload)
        try:
            os.replace(tmp, target)
        except BaseException as exc:
            tmp.unlink(missing_ok=True)
            if isinstance(exc, OSError):
                raise ExportError(f"{path}: cannot write: {exc.strerror}") from exc
            raise
