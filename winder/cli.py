"""The winder command line. The only module that imports click or talks to the user.

Exit status (SPEC.md): 0 success; 2 bad usage or an invalid config; 1 a job that could not be
computed. Every error is one line starting with `Error:`; the mapping lives in `_guard` alone.
"""

from __future__ import annotations

import functools
import json
import sys
from pathlib import Path
from typing import Callable

import click
import numpy as np

from winder import __version__
from winder.config import load_config
from winder.errors import ConfigError, SolverError, WinderError
from winder.geodesic import DEFAULT_POINTS, Method, geodesic
from winder.surface import build_surface


def _guard(fn: Callable) -> Callable:
    """Turn winder's errors into `Error: ...` and the SPEC exit codes; never a traceback."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except WinderError as exc:
            click.echo(f"Error: {exc}", err=True)
            sys.exit(exc.exit_code)
        except (KeyboardInterrupt, click.exceptions.Exit, click.ClickException):
            raise
        except Exception as exc:  # noqa: BLE001 - the promise is: no traceback, ever
            click.echo(f"Error: internal error ({type(exc).__name__}: {exc}); please report it", err=True)
            sys.exit(1)

    return wrapper


def _station(text: str, option: str) -> tuple[float, float]:
    """Parse `T,DEG` into (t mm, theta rad)."""
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise ValueError
        t, deg = float(parts[0]), float(parts[1])
    except ValueError as exc:
        raise ConfigError(f"{option}: expected T,DEG (station in mm, angle in degrees), got {text!r}") from exc
    if not (np.isfinite(t) and np.isfinite(deg)):
        raise ConfigError(f"{option}: must be finite numbers, got {text!r}")
    return t, float(np.radians(deg))


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="winder")
def main() -> None:
    """winder: filament-winding CAM on sweep-surface mandrels."""


@main.command("geodesic")
@click.argument("config", type=click.Path(dir_okay=False))
@click.option("--start", required=True, metavar="T,DEG", help="Start point: station t (mm), angle (deg).")
@click.option("--end", required=True, metavar="T,DEG", help="End point: station t (mm), angle (deg).")
@click.option("--rounds", type=int, default=0, show_default=True, help="Extra full turns: +360*N on the end angle.")
@click.option("--points", "points", type=click.IntRange(min=1), default=None,
              help=f"Intermediate points (default {DEFAULT_POINTS}).")
@click.option("--tolerance", type=click.FloatRange(min=0, min_open=True), default=None, metavar="MM",
              help="Refine until the estimated length error is below MM.")
@click.option("--method", type=click.Choice([m.value for m in Method]), default="newton", show_default=True)
@click.option("-o", "--output", type=click.Path(dir_okay=False), default=None, help="Write the path CSV here.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object with the results.")
@_guard
def geodesic_cmd(config: str, start: str, end: str, rounds: int, points: int | None,
                 tolerance: float | None, method: str, output: str | None, as_json: bool) -> None:
    """The geodesic on the mandrel of CONFIG from START to END."""
    from winder.export.path_csv import write_path_csv  # noqa: PLC0415

    if points is not None and tolerance is not None:
        raise ConfigError("--points and --tolerance: give one or the other, not both")
    a, b = _station(start, "--start"), _station(end, "--end")
    job = load_config(config)
    surface = build_surface(job.mandrel, job.source, job.name)
    res = geodesic(surface, a, b, rounds=rounds, n=points or DEFAULT_POINTS, tolerance=tolerance,
                   method=Method(method))
    if not res.converged:
        raise SolverError(f"{config}: the {method} solver did not converge in {res.iterations} "
                          f"iterations ({res.reason.value})")
    if output:
        write_path_csv(output, res)
    if as_json:
        click.echo(json.dumps({
            "name": job.name,
            "length_mm": res.length,
            "polyline_length_mm": res.polyline_length,
            "length_extrapolated_mm": res.length_extrapolated,
            "error_estimate_mm": res.error_estimate,
            "smooth_error_estimate_mm": res.smooth_error_estimate,
            "points": res.n,
            "iterations": res.iterations,
            "converged": res.converged,
            "stop_reason": res.reason.value,
            "method": res.method.value,
            "rounds": rounds,
            "spacing_deviation": res.spacing_deviation,
            "max_geodesic_curvature_per_mm": res.max_geodesic_curvature,
            "seconds": res.seconds,
        }))
    else:
        click.echo(f"{job.name}: geodesic length {res.length:.9f} mm ({res.n} points, {rounds} rounds)")
        click.echo(f"  polyline {res.polyline_length:.9f} mm, Richardson {res.length_extrapolated:.9f} mm "
                   f"+- {res.error_estimate:.2e}")
        click.echo(f"  {res.method.value}: {res.iterations} iterations, {res.reason.value}, "
                   f"{res.seconds * 1e3:.1f} ms")
        if output:
            click.echo(f"  wrote {output}")


@main.command("check")
@click.argument("configs", nargs=-1, required=True, type=click.Path(dir_okay=False))
def check_cmd(configs: tuple[str, ...]) -> None:
    """Validate configs only (no path computation)."""
    bad = 0
    for path in configs:
        try:
            job = load_config(path)
            build_surface(job.mandrel, job.source, job.name)
        except WinderError as exc:
            click.echo(f"Error: {exc}", err=True)
            bad += 1
        except Exception as exc:  # noqa: BLE001
            click.echo(f"Error: {path}: internal error ({type(exc).__name__}: {exc}); please report it", err=True)
            bad += 1
        else:
            click.echo(f"ok: {path} ({job.name})")
    if bad:
        sys.exit(2)


if __name__ == "__main__":  # pragma: no cover
    main()
