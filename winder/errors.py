"""The one error hierarchy of winder. The CLI maps each class to an exit status."""

from __future__ import annotations


class WinderError(Exception):
    """Base class of every error winder reports to a user."""

    exit_code = 1


class ConfigError(WinderError):
    """An invalid config or bad input: names the file, the key path, the value, what is allowed."""

    exit_code = 2


class SolverError(WinderError):
    """A computation that cannot be done: no convergence, a path leaving the mandrel, infeasible winding."""

    exit_code = 1


class ExportError(WinderError):
    """An output that cannot be written: axis limits exceeded, unwritable folder."""

    exit_code = 1
