"""A batch's bookkeeping beside its jobs: names that would clash in one folder, and the summary the
command line prints (as text lines: the library never prints)."""

from __future__ import annotations

import os
from collections.abc import Sequence

from winder.app.jobs import ALL_FORMATS, FORMATS, JobReport, JobTask, error_message, exit_code_of
from winder.errors import ConfigError
from winder.export.paths import shown

__all__ = ["name_clash", "refuse_format_among_configs", "shown", "summary_lines"]


def name_clash(path: str, name: str, owner: dict[str, str], where: str) -> ConfigError | None:
    """The error of a batch's job whose files would clash with an earlier job's (owner: every file
    name the jobs so far may write, casefolded, each to its config and job name; this job's are added).

    Every format's file counts, whichever are asked for: `check` does not know the formats, and what
    it accepts `run` must not refuse. So `q` and `q.layup` clash (both may write q.layup.csv), and
    so do Pipe and pipe (one file on some disks)."""
    from winder.export import registry  # noqa: PLC0415

    files = {(name + suffix).casefold(): name + suffix for suffix in registry.suffixes()}
    for key, file_name in files.items():
        if key in owner:
            other, other_name = owner[key].rsplit("\0", 1)
            if other_name.casefold() == name.casefold():
                return ConfigError(f"{path}: name: {name!r} is also the name of {other} in this batch; "
                                   f"both would write {name}.* into {where}")
            return ConfigError(f"{path}: name: {name!r} and the name {other_name!r} of {other} in this batch "
                               f"would both write {file_name} into {where}; rename one, got {name!r}")
    owner.update((key, f"{path}\0{name}") for key in files)
    return None


def refuse_format_among_configs(configs: Sequence[str]) -> None:
    """A format name given where a config goes is bad usage (exit 2): `--format csv gcode` leaves gcode
    to the configs, and the batch would run with csv alone."""
    for path in configs:
        if path.lower() in FORMATS and not os.path.lexists(path):
            raise ConfigError(f"{path}: not a config file but a format: give one format per --format "
                              f"(--format csv --format gcode) or comma-separate them (--format csv,gcode)")


def summary_lines(reports: Sequence[JobReport], out_dir: str) -> list[str]:
    """The batch's table (a row per job: config, name, status, layers, fiber, seconds) and its tally."""
    rows = [("config", "name", "status", "layers", "fiber (mm)", "seconds")]
    rows += [(shown(r.config), shown(r.name or "-"), r.status, str(r.layers) if r.layers else "-",
              "-" if r.fiber_length_mm is None else f"{r.fiber_length_mm:.3f}", f"{r.seconds:.2f}")
             for r in reports]
    widths = [max(len(row[j]) for row in rows) for j in range(len(rows[0]))]
    lines = ["  ".join(cell.rjust(w) if j in (3, 4, 5) else cell.ljust(w)
                       for j, (cell, w) in enumerate(zip(row, widths))).rstrip() for row in rows]
    ok = sum(r.ok for r in reports)
    written = sum(len(r.outputs) for r in reports)
    tally = f"{ok} of {len(reports)} jobs ok" if len(reports) > 1 else ("ok" if ok else "failed")
    return lines + [f"{tally}; {written} file{'s' if written != 1 else ''} written to {out_dir}"]


def batch_tasks(configs: Sequence[str], out_dir: str, formats: tuple[str, ...], summary: bool,
                seconds: float | None) -> tuple[list[JobReport | None], list[JobTask], list[int]]:
    """The batch's reports so far (a name clash refused before any job runs), its tasks, and each
    task's place among the configs."""
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
    return reports, tasks, index


def parse_formats(values: Sequence[str]) -> tuple[str, ...]:
    """`run --format`'s values (repeated or comma-separated) in FORMATS order; none given: ALL_FORMATS.
    ValueError names a value that is no format."""
    if not values:
        return ALL_FORMATS
    chosen = set()
    for value in values:
        for part in value.split(","):
            part = part.strip().lower()
            if part not in FORMATS:
                raise ValueError(f"{part!r} is not one of {', '.join(FORMATS)} (the summary JSON is always written)")
            chosen.add(part)
    return tuple(f for f in FORMATS if f in chosen)
