"""`winder design`, `patterns`, `convert`, `simulate` and `regress`: the engineer's tools around a job."""

from __future__ import annotations

import sys

import click

from winder.cli.base import DEFAULT_TIME_LIMIT, FiniteRange, WholeRange, _echo, _guard, main
from winder.cli.jobs import _progress


@main.command("design", short_help="Netting sizing of CONFIG's layers for its pressure, before planning.")
@click.argument("config", type=click.Path(dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with the results.")
@_guard
def design_cmd(config: str, as_json: bool) -> None:
    """Netting sizing of CONFIG for its `analysis:` pressure, no path planned. Exit status: 0, 2 invalid."""
    from winder.app.design import design_output  # noqa: PLC0415
    _echo(design_output(config, as_json))


@main.command("analyze", short_help="Solve CONFIG's shell model with CalculiX and set it beside the laminate analysis.")
@click.argument("config", type=click.Path(dir_okay=False))
@click.option("-o", "--output-dir", "out_dir", type=click.Path(file_okay=False), default=".", show_default=True,
              help="Folder for the output files (created if missing).")
@click.option("--json", "as_json", is_flag=True, help="Print the summary's `fe` block as one JSON object.")
@click.option("--refine", type=FiniteRange(0.25, 8.0), default=1.0, show_default=True, metavar="FACTOR",
              help="Element rows along the mandrel, times the default grading (2: the mesh doubled).")
@click.option("--around", type=click.IntRange(12, 192), default=48, show_default=True, metavar="N",
              help="Elements around the mandrel (a multiple of 4).")
@_guard
def analyze_cmd(config: str, out_dir: str, as_json: bool, refine: float, around: int) -> None:
    """Plan CONFIG, write its shell model (<name>.inp), solve it with CalculiX `ccx`, read the fiber stress and
    failure index along the meridian back, and write them beside the laminate analysis into <name>.summary.json
    (`fe`) and <name>.html (with the plot extra). Exit status: 0, 2 an invalid config or no ccx installed,
    1 a job or a solve that failed."""
    from winder.app.analyze import analyze_files  # noqa: PLC0415
    if around % 4:
        raise click.BadParameter(f"must be a multiple of 4 (the supports lie 90 deg apart), got {around}",
                                 param_hint="--around")
    _echo(analyze_files(config, out_dir, as_json, refine, around))


# -- patterns and fiberpath files (issue 33) -------------------------------------------------------
@main.command("patterns", short_help="The feasible patterns of helical layers, side by side.")
@click.argument("config", type=click.Path(dir_okay=False))
@click.option("--layer", type=WholeRange(min=1), help="The layer (1-based); default: every helical one.")
@click.option("--angle", type=FiniteRange(0, 90, True, True), metavar="DEG", help="Ask this angle instead.")
@click.option("--within", type=FiniteRange(0, 45), default=2.0, show_default=True, metavar="DEG",
              help="Vessels: the choices whose closed angle lies this near the angle asked.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON list, one object per choice.")
@_guard
def patterns_cmd(config: str, layer: int | None, angle: float | None, within: float, as_json: bool) -> None:
    """Each feasible pattern of CONFIG's helical layers as the planner computes it, `*` the planner's own, with
    the layer's YAML that makes `run` wind it. Exit status: 0, 2 an invalid config or option, 1 not planned."""
    from winder.app.patterns import patterns_output  # noqa: PLC0415
    _echo(patterns_output(config, layer, angle, within, as_json))


@main.command("convert", short_help="Write a fiberpath .wind job as a winder config (YAML).")
@click.argument("wind", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False, allow_dash=True),
              help="The YAML config to write; - for standard output (./- for a file of that name).")
@_guard
def convert_cmd(wind: str, output: str) -> None:
    """WIND's job as the winder config `run WIND` winds, commented. Exit status: 0, 2 invalid, 1 not written."""
    from winder.app.patterns import convert_file  # noqa: PLC0415
    _echo(convert_file(wind, output))


# -- programs read back, and the regression samples ---------------------------------------------------------------------------------------
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
@click.option("-j", "--jobs", type=WholeRange(min=0), default=1, show_default=True,
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
