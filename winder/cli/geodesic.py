"""`winder geodesic`: one two-point geodesic on a mandrel."""

from __future__ import annotations

import json

import click

from winder.cli.base import (DEFAULT_POINTS, MAX_POINTS, MAX_ROUNDS, METHODS, _TIME_LIMIT, FiniteRange, WholeRange,
                              _echo, _guard, main)


@main.command("geodesic", short_help="The geodesic on the mandrel of CONFIG from START to END.")
@click.argument("config", type=click.Path(dir_okay=False))
@click.option("--start", required=True, metavar="T,DEG", help="Start point: station t (mm), angle (deg).")
@click.option("--end", required=True, metavar="T,DEG", help="End point: station t (mm), angle (deg).")
@click.option("--rounds", type=WholeRange(), default=0, show_default=True, help="Extra full turns: +360*N on the end angle.")
@click.option("--points", "points", type=WholeRange(min=1, max=MAX_POINTS), default=None,
              help=f"Intermediate points (default {DEFAULT_POINTS}, and at least 48 per round).")
@click.option("--tolerance", type=FiniteRange(min=0, min_open=True), default=None, metavar="MM",
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
