"""The dialect registry: every way winder writes a machine program, by the name machine.dialect gives.

One row per dialect: its name, the module (under winder.export.dialects) whose make(program,
band_width) returns its serializer, and whether it writes robot poses (it needs machine.robot or a
bent axis; a G-code dialect needs a straight axis). The table names modules without importing them,
so that config validation knows the names and the export stage imports a serializer only when it
writes one. A new dialect is a new module defining make() and one register() line below.
"""

from __future__ import annotations

import dataclasses


@dataclasses.dataclass(frozen=True)
class DialectEntry:
    """One dialect: name (machine.dialect), module (defines make(program, band_width) -> Dialect),
    robot (writes robot poses)."""

    name: str
    module: str
    robot: bool = False
    cell: bool = False  # a robot cell's own language: written as its own files (winder.export.robot_programs)


REGISTRY: dict[str, DialectEntry] = {}


def register(name: str, module: str, robot: bool = False, cell: bool = False) -> None:
    """Add a dialect to the registry (module: a dotted module path, imported when it is used; cell: a
    robot cell's language, whose module defines serialize(program) -> {suffix: text})."""
    REGISTRY[name] = DialectEntry(name, module, robot or cell, cell)


def entry(name: str) -> DialectEntry:
    """The registry's row of a dialect name (KeyError for a name not registered)."""
    return REGISTRY[name]


def robot_dialects() -> tuple[str, ...]:
    """The dialects that write robot poses (the pose listing first, then the cells' languages)."""
    return tuple(name for name, e in REGISTRY.items() if e.robot)


register("generic", "winder.export.dialects.generic")
register("marlin", "winder.export.dialects.marlin")
register("linuxcnc", "winder.export.dialects.linuxcnc")
register("robot", "winder.export.dialects.robot", robot=True)
register("krl", "winder.export.dialects.krl", cell=True)
register("rapid", "winder.export.dialects.rapid", cell=True)
register("urscript", "winder.export.dialects.urscript", cell=True)
