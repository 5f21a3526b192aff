"""The command line's common ground: the group, the one `Error:` line per problem, shared options.

Exit status (docs/guide/commands.md): 0 success; 2 bad usage or an invalid config; 1 a job that could not be
computed. Every error is one line starting with `Error:`; the mapping lives in `_guard` alone.
"""

from __future__ import annotations

import functools
import sys
import warnings
from typing import Callable

import click

from winder import __version__
from winder.app.interrupts import interrupted, interrupts_raise, raise_if_interrupted
from winder.errors import ExportError, Interrupted, WinderError

# Each command imports the stages it needs when it runs: numpy, scipy and the pipeline take most of a
# second to import, which `winder --help` and `winder check` should not pay. So the two values the
# options show are written here (tests/test_cli.py keeps them equal to the library's).
METHODS = ("newton", "lbfgs")  # winder.paths.geodesic.Method's values
DEFAULT_POINTS = 200  # winder.config.winding.DEFAULT_POINTS
MAX_POINTS = 100_000  # winder.config.winding.MAX_POINTS: the command line holds the config's limit
DEFAULT_TIME_LIMIT = 600.0  # s per job: the largest job the work budget allows plans in about a minute
CHECK_TIME_LIMIT = 60.0  # s per config of `check`: the slowest config within the limits checks in ~10 s
MAX_ROUNDS = 1000  # --rounds and the turns of --start / --end: a 1000-round helix needs 48,000 points


def _echo(message: str, err: bool = False) -> None:
    """click.echo; a full stdout is an ExportError (exit 1), a closed pipe click's (quiet, exit 1), stderr's alone."""
    try:
        click.echo(message, err=err)
    except OSError as exc:
        if not err and not isinstance(exc, BrokenPipeError):
            raise ExportError(f"standard output: cannot write: {exc.strerror or exc}") from exc
        if not err:
            raise


def _error(exc: BaseException, source: str | None = None) -> int:
    """Print exc's one `Error: ...` line (naming source) and return its SPEC exit status (2 invalid, else 1)."""
    raise_if_interrupted(exc)  # an error a stop signal caused (an import it cut short) ends as the interrupt
    from winder.app.jobs import error_message, exit_code_of  # noqa: PLC0415

    _echo(f"Error: {error_message(exc, source)}", err=True)
    return exit_code_of(exc)


def _guard(fn: Callable) -> Callable:
    """Winder's errors as `Error: ...` and SPEC exit codes, never a traceback (via app.jobs.exit_code_of)."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except (KeyboardInterrupt, Interrupted, BrokenPipeError, click.exceptions.Exit, click.ClickException,
                click.Abort):  # BrokenPipeError: click ends quietly
            raise
        except Exception as exc:  # noqa: BLE001 - the promise is: no traceback, ever
            sys.exit(_error(exc))

    return wrapper


class WinderGroup(click.Group):
    """Every way out one `Error:` line and SPEC status; TERM, INT: Interrupted, rolled back, 128 + signal."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        if not standalone_mode:  # a caller handling click's exceptions itself
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        try:  # the outermost: an interrupt anywhere below, even in a handler of another error
            try:  # the outer one: standard output on a full disk past _guard (click's --help, the bare help)
                try:
                    with warnings.catch_warnings(), interrupts_raise():
                        warnings.simplefilter("ignore")  # numbers are checked where they are reported
                        rv = super().main(args, prog_name, complete_var, False, **extra)
                except click.exceptions.NoArgsIsHelpError as exc:  # a bare `winder`: the help, as click shows it
                    _echo(exc.ctx.get_help() if exc.ctx is not None else exc.format_message())
                    sys.exit(exc.exit_code)
                except click.ClickException as exc:
                    _echo(f"Error: {' '.join(exc.format_message().split())}", err=True)
                    sys.exit(exc.exit_code)
                except (click.Abort, KeyboardInterrupt):  # no prompts here: an interrupt off the main thread
                    _echo("Error: interrupted by SIGINT", err=True)
                    sys.exit(130)
            except (WinderError, OSError) as exc:  # a closed pipe click ends itself, quietly
                why = (exc if isinstance(exc, WinderError)
                       else ExportError(f"standard output: cannot write: {exc.strerror}"))
                sys.exit(_error(why))
        except Interrupted as exc:  # interrupts_raise's, also for an error or a return after a stop signal
            _echo(f"Error: {exc}; the files of the job in hand were not written or were removed", err=True)
            sys.exit(exc.exit_code)
        except SystemExit as exc:  # a command's status, decided after a stop signal it never saw raised
            first = interrupted()
            if first is None or exc.code == 128 + first:
                raise
            _echo(f"Error: {Interrupted(first)}", err=True)
            sys.exit(128 + first)
        sys.exit(rv if isinstance(rv, int) else 0)


def _plain_number(kind: click.ParamType, value, param, ctx) -> None:
    """Refuse what Python's int() and float() read but a user does not mean: digit separators (`1_0` is
    10 to Python) and digits of other scripts (`١٠` is 10 too), as YAML and the program readers do."""
    if isinstance(value, str) and ("_" in value or not value.isascii()):
        kind.fail(f"{value!r} is not a plain number (ASCII digits, no _).", param, ctx)


class WholeRange(click.IntRange):
    """click's IntRange on plain numbers only (_plain_number)."""

    def convert(self, value, param, ctx):  # type: ignore[no-untyped-def] - click's signature
        _plain_number(self, value, param, ctx)
        return super().convert(value, param, ctx)


class FiniteRange(click.FloatRange):
    """click's FloatRange on plain numbers only (_plain_number), refusing nan too: its range checks are
    comparisons, all false for nan."""

    def convert(self, value, param, ctx):  # type: ignore[no-untyped-def] - click's signature
        _plain_number(self, value, param, ctx)
        number = super().convert(value, param, ctx)
        if number != number:
            self.fail(f"{value!r} is not a number.", param, ctx)
        return number


_TIME_LIMIT = click.option("--time-limit", "time_limit", type=FiniteRange(min=0, min_open=True, max=1e6),
                           default=DEFAULT_TIME_LIMIT, show_default=True, metavar="SECONDS",
                           help="Wall-clock limit of each job or solve; past it, exit 1 and no file written.")


@click.group(cls=WinderGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="winder")
def main() -> None:
    """winder: filament-winding CAM on sweep-surface mandrels."""
