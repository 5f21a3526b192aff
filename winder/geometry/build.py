"""The validated mandrel config -> the sweep surface: the one geometry module that reads config types.

Every other geometry module takes plain numbers. Here each config part becomes its geometry (guide
curve, profile or vessel meridian, section), and what only the built geometry can tell is refused with
the file and the key path: a bend folding the surface onto itself, dome shapes outside their fits, a
table interpolation dipping to r <= 0, a spline that is not finite. What the config reader checks
(signs, ranges, required keys) is not checked again.
"""

from __future__ import annotations

import numpy as np

from typing import TYPE_CHECKING

from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.config.reader import show_value
from winder.errors import ConfigError
from winder.geometry.curves import GuideCurve, Line
from winder.geometry.domes import (ELLIPSOID_MAX_DEPTH, ELLIPSOID_MIN_DEPTH, ISOTENSOID_MAX_OPENING,
                                   ISOTENSOID_MIN_OPENING, DomeMeridian, Ellipsoid, Hemisphere)
from winder.geometry.profiles import AxialProfile, Profile, linear, table_profile
from winder.geometry.sections import Circle, Section
from winder.geometry.surface import SELF_INTERSECTION_MARGIN, Fold, SweepSurface, find_fold
from winder.geometry.vessel import VesselMeridian

if TYPE_CHECKING:
    from winder.config.axes import ArcAxis, PathAxis, SplineAxis
    from winder.config.vessel import Dome, VesselProfile

__all__ = ["build_surface", "make_curve", "make_dome", "make_profile", "make_section", "make_vessel"]


def make_curve(cfg: LineAxis | ArcAxis | PathAxis | SplineAxis, source: str) -> GuideCurve:
    """The guide curve of an axis config."""
    if isinstance(cfg, LineAxis):
        return Line(cfg.length)
    # The other kinds' config module is loaded already: cfg is one of them.
    from winder.config.axes import ArcAxis, PathAxis, SplineAxis  # noqa: PLC0415
    from winder.geometry.arcs import ArcSpec, chain  # noqa: PLC0415

    if isinstance(cfg, ArcAxis):
        return chain((ArcSpec(cfg.radius, cfg.angle_deg, cfg.toward_deg),))
    if isinstance(cfg, PathAxis):
        return chain(tuple(ArcSpec(s.radius, s.angle_deg, s.toward_deg) if isinstance(s, ArcAxis) else s.length
                           for s in cfg.segments))
    if isinstance(cfg, SplineAxis):
        from winder.geometry.spline_curves import spline_curve  # noqa: PLC0415

        return spline_curve(np.asarray(cfg.points, dtype=float), source, "mandrel.axis.points")
    raise ConfigError(f"{source}: mandrel.axis: unsupported axis {cfg!r}")


def make_profile(cfg: object, axial_length: float | None, source: str) -> AxialProfile | Profile:
    """The profile of a profile config. axial_length : the guide curve's length T, or None when the
    axis is implied by the profile."""
    if isinstance(cfg, ConstantProfile):
        return AxialProfile(linear(axial_length, cfg.radius, cfg.radius), axial_length, cfg.radius)
    from winder.config.profiles import ConeProfile, TableProfile  # noqa: PLC0415
    from winder.config.vessel import VesselProfile  # noqa: PLC0415

    if isinstance(cfg, ConeProfile):
        return AxialProfile(linear(axial_length, cfg.start_radius, cfg.end_radius), axial_length,
                            cfg.start_radius)
    if isinstance(cfg, TableProfile):
        return table_profile(np.asarray(cfg.points, dtype=float), axial_length, source, "mandrel.profile.points")
    if isinstance(cfg, VesselProfile):
        return make_vessel(cfg, source)
    raise ConfigError(f"{source}: mandrel.profile: unsupported profile {cfg!r}")


def make_section(cfg: object) -> Section:
    """The section shape of a section config."""
    if isinstance(cfg, CircleSection):
        return Circle()
    # The other outlines load only for the jobs that have them.
    from winder.config.sections import EllipseSection, RoundedRectangleSection, SuperellipseSection  # noqa: PLC0415
    from winder.geometry.outlines import Ellipse, RoundedRectangle, Superellipse  # noqa: PLC0415

    if isinstance(cfg, EllipseSection):
        return Ellipse(cfg.a, cfg.b)
    if isinstance(cfg, SuperellipseSection):
        return Superellipse(cfg.a, cfg.b, cfg.exponent)
    if isinstance(cfg, RoundedRectangleSection):
        return RoundedRectangle(cfg.width, cfg.height, cfg.corner_radius)
    raise TypeError(f"unsupported section {cfg!r}")


def make_dome(dome: Dome, radius: float, source: str, key: str) -> DomeMeridian:
    """One dome's meridian (key: its key path, e.g. "mandrel.profile.dome"). Refuses what only the
    geometry knows: an ellipsoid too flat or too deep to be a dome, an isotensoid opening outside what
    netting theory can shape, a contour whose smooth meridian folds or cannot follow its points. A closed
    end's wound surface ends at its shaft (docs/math/17-vessels-as-built.md 17.5)."""
    from winder.config.vessel import DomeType  # noqa: PLC0415

    R, r0 = float(radius), float(dome.wound_opening) if dome.wound_opening is not None else None
    opening_key = f"{key}.shaft_radius" if dome.closed else f"{key}.polar_opening"
    if dome.type is DomeType.HEMISPHERE:
        return Hemisphere(R, r0)
    if dome.type is DomeType.ELLIPSOID:
        d = float(dome.depth)
        if not ELLIPSOID_MIN_DEPTH * R <= d <= ELLIPSOID_MAX_DEPTH * R:
            raise ConfigError(f"{source}: {key}.depth: must be between {ELLIPSOID_MIN_DEPTH:g} and "
                              f"{ELLIPSOID_MAX_DEPTH:g} times mandrel.profile.radius "
                              f"({ELLIPSOID_MIN_DEPTH * R:g} to {ELLIPSOID_MAX_DEPTH * R:g}), got {d:g}")
        return Ellipsoid(R, r0, d)
    if dome.type is DomeType.TORISPHERICAL:
        from winder.geometry.domes_torispherical import Torispherical  # noqa: PLC0415

        return Torispherical(R, dome.crown_radius, dome.knuckle_radius, r0)
    if dome.type is DomeType.CONTOUR:
        return _contour(dome, R, r0, source, key)
    lo, hi = ISOTENSOID_MIN_OPENING * R, ISOTENSOID_MAX_OPENING * R
    if not lo <= r0 <= hi:
        raise ConfigError(f"{source}: {opening_key}: an isotensoid dome needs its opening "
                          f"between {ISOTENSOID_MIN_OPENING:g} and {ISOTENSOID_MAX_OPENING:g} times "
                          f"mandrel.profile.radius ({lo:g} to {hi:g}; netting theory has no dome at "
                          f"or beyond sqrt(2/3) times the radius), got {r0:g}")
    from winder.geometry.isotensoid import Isotensoid  # noqa: PLC0415 - its integrator loads with it

    return Isotensoid(R, r0)


def _contour(dome: Dome, R: float, r0: float | None, source: str, key: str) -> DomeMeridian:
    """A contour dome; the smoothing's refusals name the point (docs/math/17 17.1)."""
    from winder.geometry.domes_contour import ContourDome, ContourError  # noqa: PLC0415 - contour domes only

    pts = np.asarray(dome.points, dtype=float)
    try:
        return ContourDome(R, pts, dome.tolerance, r0)
    except ContourError as exc:
        label = dome.labels[exc.index]
        z, r = pts[exc.index]
        if label.startswith("mandrel."):
            raise ConfigError(f"{source}: {label}: {exc}, got [{z:g}, {r:g}]") from exc
        raise ConfigError(f"{source}: {key}.file: {label} (z = {z:.6g}, r = {r:.6g}): {exc}") from exc


def make_vessel(cfg: VesselProfile, source: str) -> VesselMeridian:
    """The vessel meridian of a `vessel` profile config."""
    R = float(cfg.radius)
    d1 = make_dome(cfg.dome, R, source, "mandrel.profile.dome")
    d2 = make_dome(cfg.end_dome, R, source, "mandrel.profile.end_dome")
    return VesselMeridian(R, float(cfg.cylinder_length), d1, d2)


def _fold_key(axis: ArcAxis | PathAxis | SplineAxis, curve: GuideCurve, fold: Fold) -> tuple[str, float] | None:
    """(key path, bend radius as configured) of the arc where the surface folds; None off arcs."""
    from winder.config.axes import ArcAxis, PathAxis  # noqa: PLC0415
    from winder.geometry.arcs import Path  # noqa: PLC0415

    if isinstance(axis, ArcAxis):
        return "mandrel.axis.radius", axis.radius
    if isinstance(axis, PathAxis) and isinstance(curve, Path):
        k = int(np.clip(np.searchsorted(curve.starts, fold.t, side="right") - 1, 0, len(curve.pieces) - 1))
        seg = axis.segments[k]
        if isinstance(seg, ArcAxis):
            return f"mandrel.axis.segments[{k}].arc.radius", seg.radius
    return None


def _refuse_fold(surface: SweepSurface, axis: object, source: str) -> None:
    """SPEC: a section reaching the centre of a bend (the surface folds onto itself) is refused."""
    fold = find_fold(surface)
    if fold is None:
        return
    where = _fold_key(axis, surface.curve, fold)
    if where is not None:
        key, radius = where
        raise ConfigError(f"{source}: {key}: must be larger than the mandrel's reach toward the inside of the "
                          f"bend ({fold.reach:.6g} mm), or the surface folds onto itself, got {show_value(radius)}")
    raise ConfigError(
        f"{source}: mandrel: the section (radius {fold.radius:.4g} at t = {fold.t:.4g}, theta = "
        f"{fold.theta_deg:.4g} deg) reaches the bend's centre of curvature (bend radius "
        f"{fold.bend_radius:.4g}): the mandrel would self-intersect; the section radius on the inside of a "
        f"bend must be smaller than the bend radius")


def _refuse_self_contact(surface: SweepSurface, source: str) -> None:
    """SPEC: a mandrel that intersects itself is refused; here the far parts of a bent axis that come
    back within the mandrel's thickness (a tight U-turn, a spline doubling back, a loop)."""
    if surface.curve.max_curvature() == 0.0:
        return
    from winder.geometry.self_contact import find_self_contact  # noqa: PLC0415 - bent axes only

    contact = find_self_contact(surface)
    if contact is not None:
        raise ConfigError(
            f"{source}: mandrel.axis: the mandrel runs into itself: at t = {contact.t1:.6g} mm it passes "
            f"{contact.distance:.4g} mm from the axis at t = {contact.t2:.6g} mm, inside the section there "
            f"(radius {contact.radius:.4g} mm); its far parts must stay a mandrel's thickness apart")


def _refuse_cusp(curve: GuideCurve, source: str) -> None:
    """SPEC: a curve with a kink is refused; here a spline that stops and turns where its points are
    far closer together than their neighbours (a near-duplicate point) and does not reach back far
    enough to run into itself."""
    stall = getattr(curve, "stall_t", None)
    if stall is not None:
        raise ConfigError(f"{source}: mandrel.axis.points: the smooth curve through the points stops and turns "
                          f"back near t = {stall:.6g} mm (a cusp): a point much closer to its neighbour than the "
                          f"others are to theirs (a near-duplicate) makes the spline swing to and fro; remove it")


def _refuse_spline_fold(mandrel: MandrelConfig, section: Section, source: str) -> None:
    """SPEC: a spline axis bent tighter than the section's largest radius there folds the mandrel onto
    itself; refused from the points alone (numpy), before the spline curve loads scipy."""
    from winder.config.axes import SplineAxis  # noqa: PLC0415

    if not isinstance(mandrel.axis, SplineAxis) or len(mandrel.axis.points) < 3:
        return
    from winder.geometry.spline_fold import spline_bends  # noqa: PLC0415

    bend = spline_bends(np.asarray(mandrel.axis.points, dtype=float))
    rho = float(section.polar(np.linspace(0.0, 2.0 * np.pi, 721))[0].max())
    if mandrel.profile is None:
        widest = np.full_like(bend.z, rho)
    else:
        profile = make_profile(mandrel.profile, bend.length, source)
        t = np.clip(bend.z, 0.0, profile.axial_length)
        scale = 1.0 if isinstance(section, Circle) else profile.reference_radius
        widest = profile.evaluate(profile.s_of_t(t)).r * rho / scale
    reach = widest * bend.kappa
    worst = int(np.argmax(reach))
    if reach[worst] < 1.0 - SELF_INTERSECTION_MARGIN:
        return
    i = int(bend.piece[worst])
    near = i + 1 if bend.z[worst] - bend.z[bend.piece == i][0] > 0.5 * np.ptp(bend.z[bend.piece == i]) else i
    raise ConfigError(
        f"{source}: mandrel.axis.points[{near}]: the axis bends with radius {1.0 / bend.kappa[worst]:.4g} mm at "
        f"t = {bend.z[worst]:.6g} mm (between points[{i}] and points[{i + 1}]), below the mandrel's largest "
        f"section radius there ({widest[worst]:.4g} mm): the mandrel would fold onto itself; spread the points "
        f"or make the section smaller, got {show_value(list(mandrel.axis.points[near]))}")


def build_surface(mandrel: MandrelConfig, source: str = "", name: str = "") -> SweepSurface:
    """The sweep surface of a validated mandrel config (docs/math/01-surface.md).

    Parameters
    ----------
    mandrel : MandrelConfig
        The config's mandrel (winder.config.job.JobConfig.mandrel).
    source : str
        The config file's name, for messages.
    name : str
        The job's name, kept on the surface.

    Returns
    -------
    SweepSurface
        Phi(s, theta) with exact first and second derivatives; `length` the internal station range,
        `axial_length` the axis length T (mm).

    Raises
    ------
    ConfigError
        What only the geometry shows, with its key path: a fold (a section reaching the centre of a
        bend), parts of the mandrel inside each other, a table profile dipping to r <= 0, dome fits.

    Examples
    --------
    >>> from winder.config.job import parse_config
    >>> job = parse_config({"name": "pipe", "mandrel": {"axis": {"type": "line", "length": 500},
    ...                                                 "profile": {"type": "constant", "radius": 50}}}, "pipe.yaml")
    >>> surface = build_surface(job.mandrel, job.source)
    >>> surface.axial_length
    500.0
    >>> surface.points([100.0], [0.0])  # (t, theta) -> xyz: (r cos theta, r sin theta, t) on a straight axis
    array([[ 50.,   0., 100.]])
    """
    section = make_section(mandrel.section)
    axis_cfg = mandrel.axis
    _refuse_spline_fold(mandrel, section, source)
    if mandrel.profile is None:
        curve = make_curve(axis_cfg, source)
        surface = SweepSurface(curve, None, section, 1.0, curve.length, name)
    else:
        if axis_cfg is None:
            profile = make_profile(mandrel.profile, None, source)
            curve = make_curve(LineAxis(profile.axial_length), source)
        else:
            curve = make_curve(axis_cfg, source)
            profile = make_profile(mandrel.profile, curve.length, source)
            if profile.axial_length > curve.length * (1.0 + 1e-9):
                raise ConfigError(f"{source}: mandrel.axis: length {curve.length:.6g} is shorter than the "
                                  f"profile ({profile.axial_length:.6g})")
        scale = 1.0 if isinstance(section, Circle) else profile.reference_radius
        surface = SweepSurface(curve, profile, section, scale, profile.length, name)
    _refuse_fold(surface, axis_cfg, source)
    _refuse_self_contact(surface, source)
    _refuse_cusp(surface.curve, source)
    return surface
