"""The winder command line. The only module that imports click or talks to the user.

Exit status (SPEC.md): 0 success; 2 bad usage or an invalid config; 1 a job that could not be
computed. Every error is one line starting with `Error:`; the mapping lives in `_guard` alone.
"""

from __future__ import annotations

import functools
import json
import sys
import time
import warnings
from typing import Callable

import click

from winder import __version__
from winder.app.interrupts import interrupts_raise
from winder.errors import ExportError, Interrupted, WinderError

# Each command imports the stages it needs when it runs: numpy, scipy and the pipeline take most of a
# second to import, which `winder --help` and `winder check` should not pay. So the two values the
# options show are written here (tests/test_cli.py keeps them equal to the library's).
METHODS = ("newton", "lbfgs")  # winder.paths.geodesic.Method's values
DEFAULT_POINTS = 200  # winder.config.winding.DEFAULT_POINTS
MAX_POINTS = 100_000  # winder.config.winding.MAX_POINTS: the command line holds the config's limit
DEFAULT_TIME_LIMIT = 600.0  # s per job: the largest job the work budget allows plans in about a minute
MAX_ROUNDS = 1000  # --rounds and the turns of --start / --end: a 1000-round helix needs 48,000 points


def _echo(message: str, err: bool = False) -> None:
    """click.echo; standard output on a full disk is an ExportError (exit 1). A closed pipe goes on to
    click, which ends quietly with exit 1; standard error closed or full leaves the exit status alone."""
    try:
        click.echo(message, err=err)
    except OSError as exc:
        if not err and not isinstance(exc, BrokenPipeError):
            raise ExportError(f"standard output: cannot write: {exc.strerror or exc}") from exc
        if not err:
            raise


def _error(exc: BaseException, source: str | None = None) -> int:
    """Print the one `Error: ...` line of exc (naming source if the message does not) and return
    its SPEC exit status: 2 for an invalid config or bad input, 1 for anything that could not be
    computed or written, 1 (with a please-report note) for an unexpected exception."""
    from winder.app.jobs import error_message, exit_code_of  # noqa: PLC0415

    _echo(f"Error: {error_message(exc, source)}", err=True)
    return exit_code_of(exc)


def _guard(fn: Callable) -> Callable:
    """Turn winder's errors into `Error: ...` and the SPEC exit codes; never a traceback.

    The one place where an exception becomes an exit status (through winder.app.jobs.exit_code_of, which
    the batch commands use for each of their jobs as well)."""

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
    """Every way out is one `Error:` line and a SPEC exit status: usage errors without usage lines; TERM
    and INT raise Interrupted (app.interrupts): the job in hand rolls back, exit 128 + the signal."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        if not standalone_mode:  # a caller handling click's exceptions itself
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
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
            except Interrupted as exc:
                _echo(f"Error: {exc}; the files of the job in hand were not written or were removed", err=True)
                sys.exit(exc.exit_code)
            except (click.Abort, KeyboardInterrupt):  # no prompts here: an interrupt off the main thread
                _echo("Error: interrupted by SIGINT", err=True)
                sys.exit(130)
        except (WinderError, OSError) as exc:  # a closed pipe click ends itself, quietly
            why = exc if isinstance(exc, WinderError) else ExportError(f"standard output: cannot write: {exc.strerror}")
            sys.exit(_error(why))
        sys.exit(rv if isinstance(rv, int) else 0)


class FiniteRange(click.FloatRange):
    """click's FloatRange, refusing nan too: its range checks are comparisons, all false for nan."""

    def convert(self, value, param, ctx):  # type: ignore[no-untyped-def] - click's signature
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


@main.command("geodesic", short_help="The geodesic on the mandrel of CONFIG from START to END.")
@click.argument("config", type=click.Path(dir_okay=False))
@click.option("--start", required=True, metavar="T,DEG", help="Start point: station t (mm), angle (deg).")
@click.option("--end", required=True, metavar="T,DEG", help="End point: station t (mm), angle (deg).")
@click.option("--rounds", type=int, default=0, show_default=True, help="Extra full turns: +360*N on the end angle.")
@click.option("--points", "points", type=click.IntRange(min=1, max=MAX_POINTS), default=None,
              help=f"Intermediate points (default {DEFAULT_POINTS}, and at least 48 per round).")
@click.option("--tolerance", type=click.FloatRange(min=0, min_open=True), default=None, metavar="MM",
              help="Choose the points so that the length's error bound is below MM.")
@click.option("--method", type=click.Choice(METHODS), default="newton", show_default=True, help="lbfgs: the paper's.")
@click.option("-o", "--output", type=click.Path(dir_okay=False), default=None, help="Write the path CSV here.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with the results.")
@_TIME_LIMIT
@_guard
def geodesic_cmd(config: str, start: str, end: str, rounds: int, points: int | None,
                 tolerance: float | None, method: str, output: str | None, as_json: bool,
                 time_limit: float) -> None:
    """The geodesic on the mandrel of CONFIG from START to END (END's angle + 360 N for --rounds N). Exit
    status: 0 solved, 2 a bad option or an invalid config, 1 no convergence or past --time-limit."""
    from winder.app.requests import geodesic_json, geodesic_text, solve_geodesic  # noqa: PLC0415
    from winder.export.path_csv import write_path_csv  # noqa: PLC0415

    job, res = solve_geodesic(config, start, end, rounds, points, tolerance, method, time_limit, MAX_ROUNDS, MAX_POINTS,
                              output)
    if output is not None:
        write_path_csv(output, res)
    if as_json:
        _echo(json.dumps(geodesic_json(job.name, res, rounds), allow_nan=False))
    else:
        _echo(geodesic_text(job.name, res, rounds, output))


@main.command("check", short_help="Validate configs as `run` would, without computing paths.")
@click.argument("configs", nargs=-1, required=True, type=click.Path(dir_okay=False))
def check_cmd(configs: tuple[str, ...]) -> None:
    """Validate configs as `run` would, before computing: values, geometry, the winding plan, the
    work budget (no path computation). Exit status: 0 every config valid, 2 if any is invalid."""
    from winder.app.batch import name_clash, shown  # noqa: PLC0415
    from winder.app.jobs import exit_status  # noqa: PLC0415
    from winder.app.validate import validate  # noqa: PLC0415

    codes = []
    owner: dict[str, str] = {}
    for path in configs:
        try:
            job, _, _ = validate(path)  # every check `run` makes before it computes
            clash = name_clash(path, job.name, owner, "one output folder") if len(configs) > 1 else None
            if clash is not None:  # as run refuses it in a batch of these configs
                raise clash
        except Exception as exc:  # noqa: BLE001 - one line per bad config, then the next one
            codes.append(_error(exc, path))
        else:
            _echo(f"ok: {shown(path)} ({job.name})")
    status = exit_status(codes)  # as `run` would exit: 2 if any is invalid, 1 if one cannot be wound
    if status:
        sys.exit(status)


# -- run -------------------------------------------------------------------------------------------
def _parse_formats(ctx: click.Context, param: click.Parameter, values: tuple[str, ...]) -> tuple[str, ...]:
    """--format csv --format gcode, or --format csv,gcode; none given: csv, gcode, ply."""
    from winder.app.jobs import ALL_FORMATS, FORMATS  # noqa: PLC0415

    if not values:
        return ALL_FORMATS
    chosen = set()
    for value in values:
        for part in value.split(","):
            part = part.strip().lower()
            if part not in FORMATS:
                raise click.BadParameter(f"{part!r} is not one of {', '.join(FORMATS)} (the summary "
                                         "JSON is always written)", ctx=ctx, param=param)
            chosen.add(part)
    return tuple(f for f in FORMATS if f in chosen)


def _progress(length: int, label: str):
    """A batch's progress bar on stderr, on a terminal only (a log keeps only the Error lines)."""
    return click.progressbar(length=length, label=label, file=sys.stderr, show_pos=True, show_eta=False,
                             hidden=length <= 1 or not sys.stderr.isatty())


SHOW_AFTER_S = 1.0  # a single job's own bar appears once it has run this long
BAR_STEPS = 1000


class _JobBar:
    """The progress bar of a single job (per layer, per circuit, then each output) on stderr: drawn
    only on a terminal and only once the job has run SHOW_AFTER_S, so quick jobs and pipes stay quiet.
    The library reports through this callback (winder.progress); only this draws."""

    def __init__(self, stream=None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.started = time.monotonic()
        self.bar = None
        self.at = 0

    def __call__(self, fraction: float, label: str) -> None:
        if self.bar is None:
            tty = getattr(self.stream, "isatty", None)
            if not (tty and tty()) or time.monotonic() - self.started < SHOW_AFTER_S:
                return
            self.bar = click.progressbar(length=BAR_STEPS, label=label, file=self.stream, show_eta=False)
            self.bar.__enter__()
        self.bar.label = label
        step = int(min(max(fraction, 0.0), 1.0) * BAR_STEPS) - self.at
        self.at += max(step, 0)
        self.bar.update(max(step, 0))

    def close(self) -> None:
        if self.bar is not None:
            self.bar.__exit__(None, None, None)
            self.bar = None


def _batch(configs: tuple[str, ...], out_dir: str, formats: tuple[str, ...], jobs: int,
           summary: bool = True, seconds: float | None = None) -> None:
    """Run each config as a job (see run_cmd) and report: one Error line per failure, a table, a
    tally; exit with the batch's SPEC status."""
    from winder.app.batch import name_clash, summary_lines  # noqa: PLC0415
    from winder.app.jobs import (JobReport, JobTask, error_message, exit_code_of, exit_status,  # noqa: PLC0415
                                 run_job, run_jobs, workers_for)
    from winder.config.job import load_config  # noqa: PLC0415
    reports: list[JobReport | None] = [None] * len(configs)
    tasks: list[JobTask] = []
    index: list[int] = []
    owner: dict[str, str] = {}
    for i, path in enumerate(configs):
        # Jobs in one folder must not share a name: they would overwrite each other's files. The
        # names are known only from the configs, so read them first (cheap: no computation); a
        # config that cannot be read goes to the job anyway, which reports it in order.
        try:  # a single job clashes with nothing: it reads its config once, in run_job
            name = load_config(path).name if len(configs) > 1 else None
        except Exception:  # noqa: BLE001 - reported by run_job, in its turn
            name = None
        exc = name_clash(path, name, owner, out_dir) if name is not None else None
        if exc is not None:
            reports[i] = JobReport(path, name, False, exit_code_of(exc), error_message(exc, path))
            continue
        tasks.append(JobTask(path, out_dir, formats, summary=summary, seconds=seconds))
        index.append(i)

    single = _JobBar() if len(tasks) == 1 else None
    job = functools.partial(run_job, progress=single) if single is not None else run_job
    try:
        with _progress(len(configs), f"winding {len(configs)} jobs") as bar:
            bar.update(len(configs) - len(tasks))
            for k, report in run_jobs(tasks, workers_for(jobs, len(tasks)), job=job):
                reports[index[k]] = report
                bar.update(1)
    finally:
        if single is not None:
            single.close()

    done = [r for r in reports if r is not None]
    for report in done:
        if not report.ok:
            _echo(f"Error: {report.message}", err=True)
    for line in summary_lines(done, out_dir):
        _echo(line)
    status = exit_status(r.exit_code for r in done)
    if status:
        sys.exit(status)


def _needs_plot_extra() -> None:
    """Refuse a report before any job runs when plotly (the plot extra) is missing: exit 2."""
    from winder.report.plotting import require_plotly  # noqa: PLC0415

    require_plotly()


_OUT_DIR = click.option("-o", "--output-dir", "out_dir", type=click.Path(file_okay=False), default=".",
                        show_default=True, help="Folder for the output files (created if missing).")
_JOBS = click.option("-j", "--jobs", type=click.IntRange(min=0), default=1, show_default=True,
                     help="Worker processes for a batch; 0: one per CPU. The outputs do not depend on it.")


@main.command("run", short_help="Plan and export whole jobs (CSV, G-code, PLY, summary, report).")
@click.argument("configs", nargs=-1, required=True, type=click.Path(dir_okay=False))
@_OUT_DIR
@click.option("--format", "formats", multiple=True, callback=_parse_formats, metavar="csv|gcode|ply|layup|report",
              help="Outputs to write besides <name>.summary.json; repeat or comma-separate "
                   "(default: csv, gcode, ply; layup needs winding.material).")
@click.option("--report", "with_report", is_flag=True,
              help="Also write <name>.html, the report page (needs the plot extra).")
@_JOBS
@_TIME_LIMIT
@_guard
def run_cmd(configs: tuple[str, ...], out_dir: str, formats: tuple[str, ...], with_report: bool,
            jobs: int, time_limit: float) -> None:
    """Plan and export the whole job of each CONFIG: <name>.csv, .gcode, .ply and .summary.json
    (and <name>.html with --report).

    A batch runs on --jobs worker processes; a config that fails is reported and the others still
    run. Exit status: 0 all ok, 2 if any config was invalid, else 1 if any job could not be
    computed or written.
    """
    from winder.app.batch import refuse_format_among_configs  # noqa: PLC0415
    from winder.app.jobs import FORMATS  # noqa: PLC0415

    refuse_format_among_configs(configs)
    if with_report and "report" not in formats:
        formats = tuple(f for f in FORMATS if f in formats or f == "report")
    if "report" in formats:
        _needs_plot_extra()
    _batch(configs, out_dir, formats, jobs, seconds=time_limit)


@main.command("report", short_help="Plan jobs and write one self-contained HTML report each.")
@click.argument("configs", nargs=-1, required=True, type=click.Path(dir_okay=False))
@_OUT_DIR
@_JOBS
@_TIME_LIMIT
@_guard
def report_cmd(configs: tuple[str, ...], out_dir: str, jobs: int, time_limit: float) -> None:
    """Plan each CONFIG and write <name>.html: the summary and layer tables, the unrolled pattern,
    the coverage map, winding angle and band layers along the mandrel, and a 3D view, in one page
    that opens offline in any browser. Needs the plot extra: pip install "winder[plot]".

    Exit status as for run: 0 all ok, 2 if any config was invalid (or plotly is missing), else 1.
    """
    _needs_plot_extra()
    _batch(configs, out_dir, ("report",), jobs, summary=False, seconds=time_limit)


# -- regress ---------------------------------------------------------------------------------------
@main.command("simulate", short_help="Read a program back: what it lays, and its time.")
@click.argument("config", type=click.Path(dir_okay=False))
@click.argument("program", type=click.Path(dir_okay=False))
@click.option("-o", "--output", type=click.Path(dir_okay=False), help="Write the laid path CSV here.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with the results.")
@_guard
def simulate_cmd(config: str, program: str, output: str | None, as_json: bool) -> None:
    """Read PROGRAM (any dialect `run` writes for CONFIG) back through the machine's kinematics: what it lays,
    its machine time and how far it lies from the plan. Exit status: 0 read, 2 an invalid config or a refused
    program (cut short, past machine.limits, the eye inside the mandrel, another job's), 1 a job not planned."""
    from winder.app.simulate import simulate_files  # noqa: PLC0415

    _echo(simulate_files(config, program, output, as_json, DEFAULT_TIME_LIMIT))  # run's limit


@main.command("regress", short_help="Recompute the samples of DIR and compare with their references.")
@click.argument("directory", type=click.Path(file_okay=False))
@click.option("--update", is_flag=True, help="Rewrite the references with the current outputs.")
@click.option("-j", "--jobs", type=click.IntRange(min=0), default=1, show_default=True,
              help="Worker processes; 0: one per CPU.")
@_guard
def regress_cmd(directory: str, update: bool, jobs: int) -> None:
    """Recompute each sample DIRECTORY/<sample>.yaml and compare it with its reference outputs in
    DIRECTORY/reference/<sample>/ (numbers within tolerance); --update rewrites the references.

    Exit status: 0 all match (or were updated), 1 a difference or a failed job, 2 an invalid sample.
    """
    from winder.app import regress as regress_mod  # noqa: PLC0415
    from winder.app.jobs import workers_for  # noqa: PLC0415

    samples = regress_mod.find_samples(directory)
    label = f"{'updating' if update else 'comparing'} {len(samples)} samples"
    with _progress(len(samples), label) as bar:
        results = regress_mod.regress(directory, update=update, workers=workers_for(jobs, len(samples)),
                                      on_result=lambda _: bar.update(1))
    for result in results:
        for line in regress_mod.format_result(result):
            _echo(line)
    bad = [r for r in results if not r.ok]
    for result in bad:
        _echo(f"Error: {regress_mod.failure_line(result)}", err=True)
    _echo(regress_mod.tally_line(results, update))
    status = regress_mod.regress_exit_status(results)
    if status:
        sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    main()
