"""One `winder run` job, start to finish, and batches of them on a process pool.

A job: load the config -> plan every layer -> render every requested output in memory -> only then
write them all, each atomically. If anything fails, the files this call already renamed into place
are removed again (and earlier outputs they replaced are put back), so a failed job leaves no file
of its own behind, not even a partial one (docs/guide/conventions.md). Timings go into the JobReport (the console), never into the files, so a job's outputs
are byte-identical from run to run and whatever the number of worker processes.

No click here: the CLI (winder.cli) and the regression runner (winder.app.regress) both build on this.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
import dataclasses
from typing import TYPE_CHECKING

from winder.app.interrupts import in_worker, raise_if_interrupted, stop_signals_held_back, stop_workers, worker_init
from winder.app.wall_clock import TimeUp, time_limit, time_up_message
from winder.app.writes import write_outputs
from winder.errors import ConfigError, SolverError, WinderError
from winder.export import registry
from winder.export.paths import shown as shown_path
from winder.progress import Progress, doing, part

if TYPE_CHECKING:
    from concurrent.futures import Future

PLANNING_SHARE = 0.85  # of a job's progress bar: the planning; the rest renders the outputs

__all__ = [
    "ALL_FORMATS", "FORMATS", "JobReport", "JobTask", "error_message", "exit_status", "output_names",
    "render_outputs", "run_job", "run_jobs", "write_outputs",
]

# Optional outputs of `run`, in the order they are written; `<name>.summary.json` is always written.
FORMATS = registry.SELECTABLE
ALL_FORMATS = registry.DEFAULT  # what a job writes when no format is named (the report only on request)


@dataclasses.dataclass(frozen=True)
class JobReport:
    """What happened to one config.

    config: the config path as given. name: the job name (None if the config could not be read).
    ok: all outputs written. exit_code: 0, or the SPEC exit status of the failure (2 invalid config,
    1 not computable / not writable). message: the one-line error (starting with the config path),
    "" when ok. outputs: the files written (paths as strings, in writing order; empty on failure).
    fiber_length_mm, layers: of the plan (None / 0 when planning failed). seconds: wall time.
    """

    config: str
    name: str | None
    ok: bool
    exit_code: int
    message: str
    outputs: tuple[str, ...] = ()
    fiber_length_mm: float | None = None
    layers: int = 0
    seconds: float = 0.0

    @property
    def status(self) -> str:
        if self.ok:
            return "ok"
        return "invalid" if self.exit_code == 2 else "failed"


def error_message(exc: BaseException, source: str | None = None) -> str:
    """The one-line message of an error (without the `Error: ` prefix), starting with source.

    WinderError messages name their file already; an unexpected exception is a bug in winder and
    says so, rather than showing a traceback.
    """
    if isinstance(exc, WinderError):
        text = str(exc).strip() or type(exc).__name__
    else:
        text = f"internal error ({type(exc).__name__}: {exc}); please report it"
    if source:  # a path holding a newline stays on the line, escaped (the same file everywhere)
        from winder.export.paths import shown  # noqa: PLC0415

        text = text.replace(source, shown(source)) if source in text else text
        source = shown(source)
    text = " ".join(text.splitlines())  # one line per problem
    if source and not text.startswith(f"{source}:"):
        text = f"{source}: {text}"
    return text


def exit_code_of(exc: BaseException) -> int:
    """SPEC exit status of an error: the WinderError's own (2 invalid input, 1 not computable); 1
    for anything unexpected."""
    return int(exc.exit_code) if isinstance(exc, WinderError) else 1


def exit_status(codes: Iterable[int]) -> int:
    """The exit status of a batch: 2 if any config was invalid, else 1 if any job failed, else 0."""
    codes = set(codes)
    if 2 in codes:
        return 2
    if codes - {0}:
        return 1
    return 0


def output_names(name: str, formats: Iterable[str], summary: bool = True) -> list[str]:
    """File names of a job's outputs, in writing order: the requested formats, then the summary
    (unless summary is False: `winder report` writes the page alone)."""
    return [name + f.suffix for f in registry.chosen(formats, always=summary)]


def render_outputs(job, plan, formats: Iterable[str], summary: bool = True, progress: Progress | None = None,
                   program=None, make_program: Callable[[], object] | None = None) -> dict[str, bytes]:
    """Every requested output of a planned job, in memory: file name -> bytes (writing order).

    program: the job's motion program when the caller has built it already; else make_program()
    builds it (run_job's builds and proves it, raising where an invariant fails), or
    motion_program where an output needs it.
    """
    chosen = registry.chosen(formats, always=summary)
    needed = make_program is not None or any(f.program for f in chosen)
    builds = program is None and needed and getattr(job, "machine", None) is not None
    free = [f for f in chosen if not f.program] if builds else []
    from winder.app.machine_pool import aside  # noqa: PLC0415

    # The outputs that need no program are rendered on a forked process while it is built.
    with aside(lambda: _render_each(job, plan, free, None, None)) as rendered_aside:
        if program is None and needed:
            program = make_program() if make_program is not None else motion_program(job, plan)
        rendered = _render_each(job, plan, [f for f in chosen if f not in free], program, progress)
        rendered.update(rendered_aside())
    first_error = next((rendered[job.name + f.suffix] for f in chosen
                        if isinstance(rendered[job.name + f.suffix], Exception)), None)
    if first_error is not None:  # the error of the first format in writing order, as one by one
        raise first_error
    return {job.name + s: data for f in chosen for s, data in rendered[job.name + f.suffix].items()}


def _render_each(job, plan, chosen: list, program, progress: Progress | None) -> dict[str, bytes | Exception]:
    """file name -> {suffix: bytes} of each format (registry.Format.render_set), or the error that kept
    it from being rendered."""
    rendered: dict[str, bytes | Exception] = {}
    for i, fmt in enumerate(chosen):
        if progress is not None:
            progress(i / len(chosen), f"rendering the {fmt.name}")
        try:
            rendered[job.name + fmt.suffix] = fmt.render_set(plan, job, program)
        except WinderError as exc:  # raised by render_outputs in writing order
            rendered[job.name + fmt.suffix] = exc
    return rendered


def motion_program(job, plan):
    """The job's one motion program, handed to every output that writes or times it (the G-code, the
    summary, the report), or the ExportError that kept it from being built (the G-code raises it, the
    summary says why), or None without a machine."""
    from winder.errors import ExportError  # noqa: PLC0415
    from winder.machine.chunks import build_program_in_groups  # noqa: PLC0415 - a few layers at a time

    if getattr(job, "machine", None) is None:
        return None
    from winder.app.machine_pool import run_groups  # noqa: PLC0415

    from winder.machine.tension import pass_tensions, with_tension  # noqa: PLC0415

    tensions = pass_tensions(job, plan)
    try:
        return with_tension(build_program_in_groups(plan, job.machine, run_groups=run_groups), tensions)
    except ExportError as exc:
        return exc


def proved(job, plan, program):
    """The program (or its build's error, or None) once the job's invariants hold, with their margins
    (winder.machine.invariants); SolverError naming the first one broken: nothing is written then."""
    from winder.machine.invariants import mended_and_proved  # noqa: PLC0415

    program, found = mended_and_proved(plan, job, program)
    return dataclasses.replace(program, invariants=found) if hasattr(program, "invariants") else program


def _plan(job, progress: Progress | None = None):
    from winder.app.validate import validate_job  # noqa: PLC0415
    from winder.winding.plan import plan  # noqa: PLC0415 - a heavy import, and not needed by `check`

    with doing(f"checking {shown_path(job.source)} as `check` does (values, surface, work budget)"):
        validate_job(job)  # the checks of `check`, so that `run` refuses nothing `check` accepted
    try:
        return plan(job, progress)
    except ConfigError as exc:
        # Past validation, a refusal rests on what was computed (a circuit count on the grown
        # mandrel sharing a factor with the pattern): a job that cannot be computed, exit 1.
        raise SolverError(exc.message, file=exc.file, key_path=exc.key_path) from exc


def run_job(config_path: str | os.PathLike, out_dir: str | os.PathLike = ".",
            formats: Sequence[str] = ALL_FORMATS, source: str | None = None, summary: bool = True,
            progress: Progress | None = None, seconds: float | None = None) -> JobReport:
    """Run one job: load, plan, render in memory, then write. Never raises for a failing job (the
    failure is in the report); only KeyboardInterrupt / SystemExit pass through. A top-level
    function with picklable arguments and result, so it runs on a process pool.

    source: the config's name in messages and in the outputs (which may record it) once the file
    is read; default the path as given. `regress` passes the bare file name, so that outputs do not
    depend on the folder the samples were run from. summary: write `<name>.summary.json` as well (the
    default). progress: told the fraction of the job done (planning per layer and circuit, then each
    output); None in worker processes.
    seconds: the job's wall-clock limit (None: none); past it the job fails (exit 1), no file left.
    """
    import dataclasses  # noqa: PLC0415

    from winder.config.job import load_config  # noqa: PLC0415

    config = os.fspath(config_path)
    shown = config
    started = time.perf_counter()
    name: str | None = None
    plan = None
    try:
        with time_limit(seconds):
            formats = tuple(formats)
            output_names("x", formats, summary)  # refuses an unknown format before any work
            with doing(f"reading {shown_path(config)}"):
                job = load_config(config)
            if source is not None:
                job = dataclasses.replace(job, source=source)
                shown = source
            name = job.name
            cell_dialect = job.machine.dialect if job.machine is not None and job.machine.cell is not None else None
            if formats == tuple(ALL_FORMATS) and cell_dialect in FORMATS:  # a robot cell's language by default
                formats += (cell_dialect,)
            from winder.app.validate import refuse_formats  # noqa: PLC0415 - beside the geometry it loads

            refuse_formats(job, formats)  # what the config alone refuses, before any planning
            if progress is not None:
                progress = _named(progress, name)
            plan = _plan(job, part(progress, 0.0, PLANNING_SHARE))

            def checked_program():
                program = motion_program(job, plan)
                if cell_dialect is not None and isinstance(program, Exception):
                    raise program  # the cell's reach check refuses before any file, whatever is written
                return proved(job, plan, program)

            with doing(f"building the motion program and the outputs of {name} (its layers planned)"):
                rendered = render_outputs(job, plan, formats, summary, part(progress, PLANNING_SHARE, 1.0),
                                          make_program=checked_program)
            outputs = write_outputs(out_dir, rendered)
        if progress is not None:
            progress(1.0, "written")
    except TimeUp as up:
        raise_if_interrupted(up)  # a stop signal came first: the job ends as interrupted
        exc = WinderError(time_up_message(seconds, up.activity))
        return JobReport(config, name, False, 1, error_message(exc, shown), (), _fiber_length(plan),
                         _layer_count(plan), time.perf_counter() - started)
    except Exception as exc:  # noqa: BLE001 - every failure becomes a report, never a traceback
        raise_if_interrupted(exc)  # what a stop signal broke (an import it cut short) ends as the interrupt
        return JobReport(config, name, False, exit_code_of(exc), error_message(exc, shown),
                         (), _fiber_length(plan), _layer_count(plan), time.perf_counter() - started)
    return JobReport(config, name, True, 0, "", tuple(outputs), _fiber_length(plan), _layer_count(plan),
                     time.perf_counter() - started)


def _named(progress: Progress, name: str) -> Progress:
    """The callback with the job's name in front of every label."""
    return lambda fraction, label: progress(fraction, f"{name}: {label}")


def _fiber_length(plan) -> float | None:
    try:
        return None if plan is None else float(plan.total_fiber_length_mm)
    except Exception:  # noqa: BLE001
        return None


def _layer_count(plan) -> int:
    try:
        return 0 if plan is None else len(plan.layers)
    except Exception:  # noqa: BLE001
        return 0


# -- batches ---------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class JobTask:
    """One job of a batch: run_job(config, out_dir, formats[, source][, summary][, seconds])."""

    config: str
    out_dir: str
    formats: tuple[str, ...] = ALL_FORMATS
    source: str | None = None  # see run_job
    summary: bool = True
    seconds: float | None = None  # see run_job

    def submit_args(self) -> tuple[tuple, dict]:
        kwargs: dict = {"source": self.source} if self.source else {}
        if not self.summary:
            kwargs["summary"] = False
        if self.seconds:
            kwargs["seconds"] = self.seconds
        return (self.config, self.out_dir, self.formats), kwargs


def default_workers() -> int:
    """One worker per CPU this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on every platform
        return max(1, os.cpu_count() or 1)


def workers_for(jobs: int, tasks: int) -> int:
    """The worker processes for `tasks` jobs with --jobs `jobs` (0: one per CPU), at least one."""
    return max(1, min(jobs or default_workers(), tasks))


def run_jobs(tasks: Sequence[JobTask], workers: int = 1,
             job: Callable[..., JobReport] = run_job) -> Iterator[tuple[int, JobReport]]:
    """Run the tasks, yielding (index, report) as each finishes (completion order).

    workers == 1 (or a single task) runs in this process, in order; otherwise a pool of that many
    worker processes (never more than there are tasks). A worker process that dies (killed, out of
    memory) breaks the pool: the jobs it took down are run again, each alone in a fresh process, so
    only the job that kills its worker fails (exit status 1) and the others still run. job is run_job (replaceable
    for tests; it must be picklable for workers > 1).
    """
    from winder.export.paths import check_path  # noqa: PLC0415

    for out_dir in dict.fromkeys(task.out_dir for task in tasks):  # a name past 255 bytes, a loop: before any job
        check_path(out_dir, "-o", output=True)
    workers = max(1, min(int(workers), len(tasks)))
    if workers == 1:
        for i, task in enumerate(tasks):
            args, kwargs = task.submit_args()
            yield i, job(*args, **kwargs)
        return
    # concurrent.futures.process takes ~17 ms to import: a single job (most runs) never needs it.
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait  # noqa: PLC0415
    from concurrent.futures.process import BrokenProcessPool  # noqa: PLC0415

    pool = ProcessPoolExecutor(max_workers=workers, initializer=worker_init)
    retry: list[int] = []
    try:
        with stop_signals_held_back():  # the pool's threads and workers start here: only this thread takes them
            futures: dict[Future, int] = {
                pool.submit(in_worker, job, *task.submit_args()[0], **task.submit_args()[1]): i
                for i, task in enumerate(tasks)
            }
        pending = set(futures)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in sorted(done, key=futures.__getitem__):
                i = futures[future]
                try:
                    report = future.result()
                except BrokenProcessPool:
                    # A worker died; every job not finished by then fails with the pool, though only
                    # one of them killed it. Each gets a second chance, alone, below.
                    retry.append(i)
                    continue
                except Exception as exc:  # noqa: BLE001 - e.g. an unpicklable result
                    report = _worker_failure(tasks[i].config, exc)
                yield i, report
    except BaseException:
        # An interrupt (or an abandoned generator): stop the workers now, each rolling back its job,
        # rather than letting them finish the batch without a parent.
        stop_workers(pool)
        raise
    pool.shutdown(wait=True)
    for i in sorted(retry):
        raise_if_interrupted()  # the workers died of the terminal's Ctrl-C: no second chance
        task = tasks[i]
        alone = ProcessPoolExecutor(max_workers=1, initializer=worker_init)
        try:
            args, kwargs = task.submit_args()
            with stop_signals_held_back():
                submitted = alone.submit(in_worker, job, *args, **kwargs)
            report = submitted.result()
        except Exception as exc:  # noqa: BLE001 - this job kills its worker: it fails, alone
            report = _worker_failure(task.config, exc)
        except BaseException:
            stop_workers(alone)
            raise
        alone.shutdown(wait=True)
        yield i, report


def _worker_failure(config: str, exc: BaseException) -> JobReport:
    from concurrent.futures.process import BrokenProcessPool  # noqa: PLC0415 - loaded by the pool

    if isinstance(exc, BrokenProcessPool):
        what = "the worker process running this job died (killed, or out of memory?)"
    else:
        what = f"the worker process failed ({type(exc).__name__}: {exc})"
    return JobReport(config, None, False, 1, error_message(WinderError(what), config))
