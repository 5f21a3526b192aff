"""Reading a job's text files: a regular UTF-8 file of bounded size, and the output name's limit."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from winder.errors import ConfigError

# A job file is a page of YAML; a table or spline of 10,000 points is about 300 kB. Beyond this it is
# not a job file (or a device such as /dev/zero), and reading it would not end in reasonable time.
MAX_FILE_BYTES = 2_000_000
# Output files are <name>.<suffix>, written through hidden temporary files with ~30 more characters;
# file systems allow 255 bytes per name.
MAX_NAME_LENGTH = 200


def checked_size(path: str | Path, source: str, kind: str = "job file", limit: int = MAX_FILE_BYTES) -> int:
    """The size of the file at path, a regular file of at most limit bytes, checked before it is opened
    (opening a FIFO would block, /dev/zero never ends): else ConfigError naming source."""
    try:
        info = os.stat(path)
    except OSError as exc:
        raise ConfigError(f"{source}: cannot read the file: {exc.strerror or exc}") from exc
    if not stat.S_ISREG(info.st_mode):
        raise ConfigError(f"{source}: not a regular file (a {kind} is a text file)")
    if info.st_size > limit:
        raise ConfigError(f"{source}: the file has {info.st_size} bytes, more than a {kind}'s limit of {limit}")
    return info.st_size


def read_text(path: str | Path, source: str, kind: str = "job file", limit: int = MAX_FILE_BYTES,
              errors: str = "strict") -> str:
    """The text of a job file (or another kind of text file): a regular file of at most limit bytes,
    UTF-8 (errors: as bytes.decode's; "replace" reads other bytes as U+FFFD instead of refusing)."""
    checked_size(path, source, kind, limit)
    try:
        with open(path, "rb") as fh:
            raw = fh.read(limit + 1)
    except OSError as exc:
        raise ConfigError(f"{source}: cannot read the file: {exc.strerror or exc}") from exc
    if len(raw) > limit:  # it grew while being read
        raise ConfigError(f"{source}: the file has more than a {kind}'s limit of {limit} bytes")
    try:
        return raw.decode("utf-8", errors=errors)
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{source}: not a UTF-8 text file ({exc.reason} at byte {exc.start})") from exc
