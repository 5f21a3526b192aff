"""The one error hierarchy of winder. Every error carries its exit status (docs/guide/commands.md), and where known
the file and the key path it is about; the CLI prints format_message() and exits with exit_code."""

from __future__ import annotations


def _rebuild(cls: type, message: str, file: str | None, key_path: str | None) -> WinderError:
    return cls(message, file=file, key_path=key_path)


class WinderError(Exception):
    """Base class of every error winder reports to a user.

    message : what is wrong (", got <value>" included where there is one). file : the job file or
    folder it concerns; key_path : e.g. "mandrel.axis.radius" (a config key, or an input's name).
    """

    exit_code = 1

    def __init__(self, message: str, *, file: str | None = None, key_path: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.file = file
        self.key_path = key_path

    def format_message(self) -> str:
        """`file: key.path: message`, leaving out what is not known."""
        return ": ".join(part for part in (self.file, self.key_path, self.message) if part)

    def __str__(self) -> str:
        return self.format_message()

    def __reduce__(self):  # keep file and key_path across process boundaries (batch jobs)
        return (_rebuild, (type(self), self.message, self.file, self.key_path))


class ConfigError(WinderError):
    """An invalid config or bad input: names the file, the key path, the value, what is allowed."""

    exit_code = 2


class InfeasibleConfigError(ConfigError):
    """A valid config whose winding no fiber can hold, refused from the config alone, before any
    computation (docs/guide/config.md: exit 1)."""

    exit_code = 1


class SolverError(WinderError):
    """A computation that cannot be done: no convergence, a path leaving the mandrel, infeasible winding."""

    exit_code = 1


class ExportError(WinderError):
    """An output that cannot be written: axis limits exceeded, unwritable folder."""

    exit_code = 1


class Interrupted(BaseException):
    """A TERM or INT signal stopping the work: not an error of the input, so not a WinderError, and a
    BaseException so that no `except Exception` of a job swallows it; what is half-written is rolled
    back on the way out. exit_code is 128 + the signal number (130 for INT, 143 for TERM)."""

    def __init__(self, signum: int) -> None:
        import signal  # noqa: PLC0415

        name = signal.Signals(signum).name
        super().__init__(f"interrupted by {name}")
        self.signum = signum
        self.signal_name = name
        self.exit_code = 128 + signum

    def __reduce__(self):
        return (type(self), (self.signum,))
