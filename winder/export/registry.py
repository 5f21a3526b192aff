"""Output formats: name -> file suffix and the module whose export(plan, job) renders it.

The table is static, so that the formats are known (for `--format`, output names, regress) without
importing an exporter; each exporter module defines export(plan, job) -> str | bytes (or the function a
row names: the mesh formats share one module) and is imported only when its format is rendered. A new
format is one row here and one module. The report
(`winder.report.export`) is a row too: its module lives in the later report stage and is found by
name only when a report is asked for, so `run` without `--report` never needs plotly.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterable
import dataclasses

from winder.errors import ConfigError


@dataclasses.dataclass(frozen=True)
class Format:
    """One output: its name (as in `--format`), its file suffix, the module rendering it, whether
    every job writes it (the summary), and whether `run` writes it when no format is named (not the
    report: it needs the plot extra)."""

    name: str
    suffix: str
    module: str
    always: bool = False
    default: bool = True
    function: str = "export"
    part_of: str | None = None  # written with that format, never asked for alone (KRL's .dat)
    program: bool = False  # its export takes the job's motion program (program=, built once per job)
    extras: str | None = None  # the module's function giving the files it writes beside (KRL's layer modules)

    def render(self, plan, job, program=None) -> bytes:
        """This format's file: its exporter's text or bytes for a planned job.

        Parameters
        ----------
        plan : WindingPlan
            The planned job (winder.winding.plan.plan).
        job : JobConfig
            Its config.
        program : MotionProgram, optional
            The job's motion program (winder.machine.program.build_program), built once per job, for the
            formats that take it (`program`).

        Returns
        -------
        bytes
            The file's content, UTF-8 for text formats.
        """
        export = getattr(importlib.import_module(self.module), self.function)
        data = export(plan, job, program=program) if self.program else export(plan, job)
        return data.encode("utf-8") if isinstance(data, str) else bytes(data)

    def render_set(self, plan, job, program=None) -> dict[str, bytes]:
        """{suffix: bytes} of this format's file, then of those it writes beside it in the same set."""
        return {self.suffix: self.render(plan, job, program)} | self.render_extras(plan, job, program)

    def render_extras(self, plan, job, program=None) -> dict[str, bytes]:
        """{suffix: bytes} of the files this format writes beside its own in the same set, in writing
        order: a KRL program split per layer's modules (`_L<N>.src`, `_L<N>.dat`); none for the others."""
        if self.extras is None:
            return {}
        export = getattr(importlib.import_module(self.module), self.extras)
        texts = export(plan, job, program=program) if self.program else export(plan, job)
        return {suffix: text.encode("utf-8") for suffix, text in texts.items()}


FORMATS: tuple[Format, ...] = (  # in writing order
    Format("csv", ".csv", "winder.export.job_csv"),
    Format("gcode", ".gcode", "winder.export.gcode", program=True),
    Format("ply", ".ply", "winder.export.ply"),
    Format("stl", ".stl", "winder.export.ply", default=False, function="export_stl"),
    Format("obj", ".obj", "winder.export.ply", default=False, function="export_obj"),
    Format("glb", ".glb", "winder.export.ply", default=False, function="export_glb"),
    Format("layup", ".layup.csv", "winder.export.layup", default=False),  # needs a material
    Format("abaqus", ".inp", "winder.export.abaqus", default=False),  # needs ply data and analysis:
    Format("report", ".html", "winder.report.export", default=False, program=True),
    Format("krl", ".src", "winder.export.robot_programs", default=False, function="krl_src", program=True,
           extras="krl_layers"),
    Format("krl_dat", ".dat", "winder.export.robot_programs", default=False, function="krl_dat", part_of="krl",
           program=True),
    Format("rapid", ".mod", "winder.export.robot_programs", default=False, function="rapid", program=True),
    Format("urscript", ".script", "winder.export.robot_programs", default=False, function="urscript", program=True),
    Format("summary", ".summary.json", "winder.export.summary", always=True, program=True),
)
SELECTABLE = tuple(f.name for f in FORMATS if not f.always and f.part_of is None)  # the formats a job may leave out
DEFAULT = tuple(f.name for f in FORMATS if not f.always and f.default and f.part_of is None)  # written when none is named


def suffixes() -> tuple[str, ...]:
    """Every output file suffix."""
    return tuple(f.suffix for f in FORMATS)


def suffix_of(name: str) -> str:
    """The file suffix of one format."""
    return next(f.suffix for f in FORMATS if f.name == name)


def format_of(file_name: str) -> Format | None:
    """The format of an output file by its suffix (the longest that matches), or None.

    Examples
    --------
    >>> format_of("tank.layup.csv").name, format_of("tank.csv").name, format_of("tank.txt")
    ('layup', 'csv', None)
    """
    hits = [f for f in FORMATS if file_name.endswith(f.suffix)]
    return max(hits, key=lambda f: len(f.suffix)) if hits else None


def chosen(names: Iterable[str], always: bool = True) -> tuple[Format, ...]:
    """The formats a job writes for the names given, in writing order.

    Parameters
    ----------
    names : iterable of str
        Selectable format names (SELECTABLE: `--format` of `winder run`).
    always : bool
        Add the formats every job writes (the summary).

    Returns
    -------
    tuple of Format
        In writing order, with the files a named format writes beside its own (KRL's .dat).

    Raises
    ------
    ConfigError
        An unknown name, listing the allowed ones.

    Examples
    --------
    >>> [f.name for f in chosen(["gcode", "csv"])]
    ['csv', 'gcode', 'summary']
    >>> [f.suffix for f in chosen(["krl"], always=False)]
    ['.src', '.dat']
    >>> chosen(["pdf"])
    Traceback (most recent call last):
    ...
    winder.errors.ConfigError: unknown output format 'pdf'; allowed: csv, gcode, ply, stl, obj, glb, layup, abaqus, report, krl, rapid, urscript
    """
    wanted = set(names)
    unknown = wanted - set(SELECTABLE)
    if unknown:
        raise ConfigError(f"unknown output format {sorted(unknown)[0]!r}; allowed: {', '.join(SELECTABLE)}")
    return tuple(f for f in FORMATS if (f.always and always) or f.name in wanted or f.part_of in wanted)
