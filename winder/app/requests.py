"""The `geodesic` command: its request checked as a config's values are (exit 2, naming the option),
the solve under a wall-clock limit, and its result as JSON without NaN or Infinity (which JSON does
not have)."""

from __future__ import annotations

import math
from typing import Any

from winder.app.wall_clock import TimeUp, time_limit
from winder.config.reader import station_option
from winder.errors import ConfigError, SolverError, WinderError

__all__ = ["geodesic_json", "geodesic_request", "solve_geodesic", "station"]


def station(text: str, option: str, max_rounds: int) -> tuple[float, float]:
    """Parse `T,DEG` into (t mm, theta rad) (winder.config.reader.station_option); the angle within
    max_rounds turns."""
    t, theta = station_option(text, option)
    if abs(theta) > 2.0 * math.pi * max_rounds:
        raise ConfigError(f"{option}: the angle must be within +-{360 * max_rounds} deg ({max_rounds} turns), "
                          f"got {text!r}")
    return t, theta


def geodesic_request(start: str, end: str, rounds: int, points: int | None, tolerance: float | None,
                     max_rounds: int) -> tuple[tuple[float, float], tuple[float, float]]:
    """The end points (t mm, theta rad) of a geodesic request, or ConfigError naming the option."""
    if points is not None and tolerance is not None:
        raise ConfigError("--points and --tolerance: give one or the other, not both")
    if tolerance is not None and not math.isfinite(tolerance):
        raise ConfigError(f"--tolerance: must be a finite number of mm > 0, got {tolerance}")
    a, b = station(start, "--start", max_rounds), station(end, "--end", max_rounds)
    if abs(b[1] - a[1]) / (2.0 * math.pi) + abs(rounds) > max_rounds:
        raise ConfigError(f"--end: the path would make more than {max_rounds} turns, got {end!r} with "
                          f"--rounds {rounds}")
    if a[0] == b[0] and a[1] == b[1] + 2.0 * math.pi * rounds:
        raise ConfigError(f"--end: must differ from --start (a path of zero length), got {end!r}")
    return a, b


def _finite(value: Any) -> Any:
    return None if isinstance(value, float) and not math.isfinite(value) else value


def geodesic_json(name: str, res, rounds: int) -> dict[str, Any]:
    """The JSON object of `geodesic --json` (docs/guide/conventions.md); a number that is not finite is null."""
    return {key: _finite(value) for key, value in {
        "name": name,
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
    }.items()}


def geodesic_text(name: str, res, rounds: int, output: str | None) -> str:
    """The lines `geodesic` prints without --json."""
    lines = [f"{name}: geodesic length {res.length:.9f} mm ({res.n} points, {rounds} rounds)",
             f"  polyline {res.polyline_length:.9f} mm, Richardson {res.length_extrapolated:.9f} mm "
             f"+- {res.error_estimate:.2e}",
             f"  {res.method.value}: {res.iterations} iterations, {res.reason.value}, {res.seconds * 1e3:.1f} ms"]
    return "\n".join(lines + ([f"  wrote {output}"] if output else []))


def _check_tolerance(surface, a: tuple[float, float], b: tuple[float, float], tolerance: float) -> None:
    """Refuse a --tolerance that the solver would find below double precision after solving (as the
    config's winding.tolerance is refused): against the straight distance between the ends, which no
    path is shorter than."""
    import numpy as np  # noqa: PLC0415
    from winder.paths.geodesic import ROUNDOFF_FLOOR  # noqa: PLC0415

    ends = surface.points(surface.s_of_t(np.array([a[0], b[0]])), np.array([a[1], b[1]]))
    floor = ROUNDOFF_FLOOR * float(np.linalg.norm(ends[1] - ends[0]))
    if tolerance <= floor:
        raise ConfigError(f"--tolerance: must be above what double precision resolves on this path ({floor:.2g} mm "
                          f"for its ends {floor / ROUNDOFF_FLOOR:.6g} mm apart), got {tolerance:g}")


def solve_geodesic(config: str, start: str, end: str, rounds: int, points: int | None, tolerance: float | None,
                   method: str, seconds: float | None, max_rounds: int, max_points: int, output: str | None = None):
    """(job, GeodesicResult) of a request on the mandrel of config; the config's limit on points
    holds for --tolerance's refinement too. ConfigError (exit 2) for a bad request (an output path
    that is no file or is the config itself included: before the solve), SolverError (exit 1, naming
    the file) for no convergence, no finite length or the time limit."""
    from winder.config.job import load_config  # noqa: PLC0415
    from winder.export.atomic import check_output_file  # noqa: PLC0415
    from winder.geometry.build import build_surface  # noqa: PLC0415
    from winder.paths.geodesic import Method, geodesic  # noqa: PLC0415

    if output is not None:
        check_output_file(output, {"CONFIG": config})
    a, b = geodesic_request(start, end, rounds, points, tolerance, max_rounds)
    job = load_config(config)
    surface = build_surface(job.mandrel, job.source, job.name)
    if tolerance is not None:
        _check_tolerance(surface, a, b, tolerance)
    try:
        with time_limit(seconds):
            res = geodesic(surface, a, b, rounds=rounds, n=points, tolerance=tolerance, method=Method(method),
                           max_points=max_points)
    except TimeUp:
        raise SolverError(f"the {method} solver did not finish within the time limit of {seconds:g} s "
                          "(--time-limit)", file=config) from None
    except WinderError as exc:
        if exc.key_path in ("start", "end", "points", "tolerance"):  # the library's names of the options
            exc.key_path = f"--{exc.key_path}"
        if isinstance(exc, SolverError) and exc.file is None:
            exc.file = config  # names the file, once
        raise
    if not res.success:
        raise SolverError(f"the {method} solver did not converge in {res.nit} iterations ({res.message})",
                          file=config)
    if not (math.isfinite(res.length) and math.isfinite(res.polyline_length)):
        raise SolverError(f"the {method} solver gave no finite length for this path", file=config)
    return job, res
