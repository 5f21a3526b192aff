"""Paths given on the command line, held to what the system can open before any work is done.

A path with a component longer than a file name may be (255 bytes on Linux's file systems), or
longer than a whole path may be, cannot be written: it is refused up front with a one-line error
(ConfigError, exit 2), as is an output path through a loop of links, or one that is a link to
nothing (writing there would create folders and a file outside the folder named). And any path
shown in a message is shown on one line: `shown` escapes its control characters (a newline in a
config's name would split the `Error:` line in two).
"""

from __future__ import annotations

import errno
import os

from winder.errors import ConfigError

__all__ = ["NAME_MAX", "PATH_MAX", "check_path", "shown"]

NAME_MAX = 255  # bytes of one path component (ext4, xfs, btrfs, tmpfs)
PATH_MAX = 4096  # bytes of a whole path, its terminating NUL included (Linux)
SHOWN_BYTES = 40  # of an over-long component, in the message


def shown(text: str) -> str:
    """text with every control character (a newline, a tab, an escape) written as its escape."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text)


def check_path(path: str | os.PathLike, key: str, output: bool = False) -> None:
    """Refuse (ConfigError naming key, exit 2) a path the system cannot open for its length, and an
    output path (output=True) through a loop of links or that is a link to nothing."""
    text = os.fspath(path)
    raw = os.fsencode(text)
    if len(raw) >= PATH_MAX:
        raise ConfigError(f"the path is {len(raw)} bytes long, more than the {PATH_MAX - 1} a path may have, "
                          f"got {shown(text[:SHOWN_BYTES])!r}...", key_path=key)
    for part in raw.split(os.fsencode(os.sep)):
        if len(part) > NAME_MAX:
            name = os.fsdecode(part)
            raise ConfigError(f"a name in the path is {len(part)} bytes long, more than the {NAME_MAX} a file "
                              f"name may have, got {shown(name[:SHOWN_BYTES])!r}...", key_path=key)
    if not output:
        return
    probe = text
    while probe:
        try:
            os.stat(probe)
            break
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                raise ConfigError(f"a loop of links in the path, got {shown(text)!r}", key_path=key) from exc
            if probe == text and os.path.islink(probe):
                raise ConfigError(f"a link to a file that does not exist ({shown(os.readlink(probe))!r}): not "
                                  f"followed, got {shown(text)!r}", key_path=key) from exc
        parent = os.path.dirname(probe.rstrip(os.sep))
        if parent == probe:
            break
        probe = parent
