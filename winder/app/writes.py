"""A job's output files put in place as one set: the old set or the new one, never a mix, whatever
else writes into the folder and whenever the writer dies (docs/guide/output-files.md).

The protocol (winder.export.journal): under the output folder's lock, first finish what dead writers
left there; write every file of the set aside (temporary files, and a hard link kept to each old file);
make the commit record (one rename: the switch); rename the files into place; drop the record and the
old files' links. On a failure or an interrupt the set is taken back (the old files put back). A name
that is a link to a regular file is written through (the file it names is replaced, the link stays);
a device, FIFO or descriptor (a link to /dev/null, /dev/stdout) is written into once the set is in
place; a link to nothing, a loop or a folder is refused before anything is written.
"""

from __future__ import annotations

import os
from pathlib import Path

from winder.app.interrupts import held

__all__ = ["write_outputs"]


def _destinations(folder: Path, rendered: dict[str, bytes]) -> tuple[list, list]:
    """(streams, files): (path, bytes) of the names written into, and (output file, bytes) of those put in
    place as the set; ExportError for a name that cannot be written (winder.export.atomic.output_target)."""
    from winder.export.atomic import is_stream, output_target  # noqa: PLC0415

    streams, files = [], []
    for file_name, data in rendered.items():
        path = folder / file_name
        if is_stream(path):
            streams.append((path, data))
        else:
            files.append((output_target(path), data))
    return streams, files


def write_outputs(out_dir: str | os.PathLike, rendered: dict[str, bytes]) -> list[str]:
    """Write the rendered files (file name -> bytes) into out_dir as one set and return their paths.

    All or nothing: on any failure (or an interrupt) the files already put in place are taken back and
    the old ones put back, so the folder holds the old set or the new set; a writer killed on the way
    leaves a commit record that the next winder writing into the folder completes (module docstring).
    """
    from winder.export import journal  # noqa: PLC0415
    from winder.export.atomic import write_stream, write_temporary  # noqa: PLC0415

    folder = Path(out_dir)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:  # a file in the way, a read-only parent: write_temporary says which, for the first file
        pass
    streams, files = _destinations(folder, rendered)
    with journal.folder_lock(folder) as locked:
        journal.recover(folder, locked)
        journal.settle_earlier(folder, [target.name for target, _ in files if target.parent == folder], locked)
        entries: list[journal.Entry] = []
        record = None
        try:
            for target, data in files:
                with held():  # a stop signal waits until the file is noted for the rollback
                    backup, had_old = journal.keep_old(target)
                    try:
                        tmp = write_temporary(target, data)
                    except BaseException:
                        if backup is not None:
                            backup.unlink(missing_ok=True)
                        raise
                    entries.append((tmp, target, backup, had_old))
            with held():  # the switch: the record, then the renames it promises
                record = journal.commit(folder, entries)
                for tmp, target, _, _ in entries:
                    os.replace(tmp, target)
            for path, data in streams:
                write_stream(path, data)
            with held():
                record.unlink()
                record = None
                journal.drop_backups(entries)
        except BaseException:
            with held():  # the rollback is not cut short by an interrupt (after a failure of another kind)
                try:
                    journal.roll_back(folder, entries, record)
                except OSError:  # a folder gone read-only: the record stays for the next writer
                    pass
            raise
    return [str(folder / file_name) for file_name in rendered]
