"""The winder command line: the only package that imports click or talks to the user.

Exit status (docs/guide/commands.md): 0 success; 2 bad usage or an invalid config; 1 a job that could not be
computed. Every error is one line starting with `Error:`; the mapping lives in `base._guard` alone.
A command has its own module by what it is for (`geodesic`, `jobs`, `tools`), registering itself on
`base.main` when imported here; a new command goes beside its kin.
"""

from __future__ import annotations

from winder.cli import geodesic, jobs, schema, tools  # noqa: F401 - each registers its commands on main
from winder.cli.base import DEFAULT_POINTS, MAX_POINTS, METHODS, main

__all__ = ["DEFAULT_POINTS", "MAX_POINTS", "METHODS", "main"]
