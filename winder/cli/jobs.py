"""`winder check`, `run` and `report`: whole jobs, one config or a batch, with their progress bars."""

from __future__ import annotations

import functools
import sys
import time

import click

from winder.cli.base import _TIME_LIMIT, CHECK_TIME_LIMIT, FiniteRange, WholeRange, _echo, _error, _guard, main


@main.command("check", short_help="Validate configs as `run` would, without computing paths.")
@click.argument("configs", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option("--time-limit", "time_limit", type=FiniteRange(min=0, min_open=True, max=1e6),
              default=CHECK_TIME_LIMIT, show_default=True, metavar="SECONDS",
              help="Wall-clock limit of each config's check; past it, exit 1 naming what it was checking.")
def check_cmd(configs: tuple[str, ...], time_limit: float) -> None:
    """Validate configs as `run` would, before computing: values, geometry, the winding plan, the
    work budget (no path computation). Exit status: 0 every config valid, 2 if any is invalid, 1 if a
    check did not finish within --time-limit (neither valid nor invalid)."""
    from winder.app.batch import name_clash, shown  # noqa: PLC0415
    from winder.app.jobs import exit_status  # noqa: PLC0415
    from winder.app.validate import validate_within  # noqa: PLC0415

    codes = []
    owner: dict[str, str] = {}
    for path in configs:
        try:
            job, _, _ = validate_within(path, time_limit)  # every check `run` makes before it computes
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
    from winder.app.batch import parse_formats  # noqa: PLC0415

    try:
        return parse_formats(values)
    except ValueError as exc:
        raise click.BadParameter(str(exc), ctx=ctx, param=param) from exc


def _progress(length: int, label: str):
    """A batch's progress bar on stderr, on a terminal only (a log keeps only the Error lines)."""
    return click.progressbar(length=length, label=label, file=sys.stderr, show_pos=True, show_eta=False,
                             hidden=length <= 1 or not sys.stderr.isatty())


SHOW_AFTER_S = 1.0  # a single job's own bar appears once it has run this long
BAR_STEPS = 1000


class _JobBar:
    """A single job's progress bar on stderr (winder.progress's callback): on a terminal, after SHOW_AFTER_S."""

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
    """Run each config as a job (see run_cmd) and report: a table, a tally, then one Error line per
    failure; exit with the batch's SPEC status."""
    from winder.app.batch import batch_tasks, summary_lines  # noqa: PLC0415
    from winder.app.jobs import exit_status, run_job, run_jobs, workers_for  # noqa: PLC0415

    reports, tasks, index = batch_tasks(configs, out_dir, formats, summary, seconds)
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
    for line in summary_lines(done, out_dir):
        _echo(line)
    # The Error lines last: what a `| tail` or the end of a log shows is why a job failed (issue 49.6).
    for report in done:
        if not report.ok:
            _echo(f"Error: {report.message}", err=True)
    status = exit_status(r.exit_code for r in done)
    if status:
        sys.exit(status)


def _needs_plot_extra() -> None:
    """Refuse a report before any job runs when plotly (the plot extra) is missing: exit 2."""
    from winder.report.plotting import require_plotly  # noqa: PLC0415

    require_plotly()


_OUT_DIR = click.option("-o", "--output-dir", "out_dir", type=click.Path(file_okay=False), default=".",
                        show_default=True, help="Folder for the output files (created if missing).")
_JOBS = click.option("-j", "--jobs", type=WholeRange(min=0), default=1, show_default=True,
                     help="Worker processes for a batch; 0: one per CPU. The outputs do not depend on it.")


@main.command("run", short_help="Plan and export whole jobs (CSV, G-code, PLY, summary, report).")
@click.argument("configs", nargs=-1, required=True, type=click.Path(dir_okay=False))
@_OUT_DIR
@click.option("--format", "formats", multiple=True, callback=_parse_formats,
              metavar="csv|gcode|ply|stl|obj|glb|layup|abaqus|report|krl|rapid|urscript",
              help="Outputs besides <name>.summary.json; repeat or comma-separate (default: csv, gcode, ply, a robot "
                   "cell's language; layup and abaqus need winding.material; krl: .src and .dat, a robot cell's).")
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
