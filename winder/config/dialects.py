"""The dialect registry: every way winder writes a machine program, by the name machine.dialect gives.

Each built-in dialect is one file, winder/config/posts/<name>.post.yaml (winder.config.controllers):
its description names its engine, whose writer is winder.export.dialects.<engine> (make(program,
band_width) -> a Dialect; a robot cell's language: serialize(program) -> {suffix: text}) and whose
reader is winder.readback (gcode.py for G-code, cells.py for the cells' languages). The table is
built from the files' names and engines when it is first read, so that validation knows the names
and the export stage imports a writer only when it writes one. A new dialect is a new file.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator, Mapping

from winder.config.controllers import CELL_ENGINES, builtin, builtin_names


@dataclasses.dataclass(frozen=True)
class DialectEntry:
    """One dialect: name (machine.dialect), module (its writer), robot (writes robot poses), cell (a
    robot cell's own language, written as its own files: winder.export.robot_programs)."""

    name: str
    module: str
    robot: bool = False
    cell: bool = False


class _Registry(Mapping):
    """name -> DialectEntry of every built-in post file, read on first use."""

    def __init__(self) -> None:
        self._rows: dict[str, DialectEntry] | None = None

    def _table(self) -> dict[str, DialectEntry]:
        if self._rows is None:
            rows = {}
            for name in builtin_names():
                engine = builtin(name).engine
                cell = engine in CELL_ENGINES
                rows[name] = DialectEntry(name, f"winder.export.dialects.{engine}", cell or engine == "robot", cell)
            self._rows = rows
        return self._rows

    def __getitem__(self, name: str) -> DialectEntry:
        return self._table()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(builtin_names())

    def __len__(self) -> int:
        return len(builtin_names())

    def __contains__(self, name: object) -> bool:
        return name in builtin_names()


REGISTRY: Mapping[str, DialectEntry] = _Registry()


def entry(name: str) -> DialectEntry:
    """The registry's row of a dialect name (KeyError for a name not registered)."""
    return REGISTRY[name]


def robot_dialects() -> tuple[str, ...]:
    """The dialects that write robot poses (the pose listing first, then the cells' languages)."""
    return tuple(name for name, e in REGISTRY.items() if e.robot)
