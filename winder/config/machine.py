"""The `machine:` section of a job file: the winder's axes, payout eye, feed, limits, robot mode.

Every key has a default. The parser receives a `winder.config.reader.Reader` plus the facts about the
mandrel it checks against (bent axis, largest radius); winder.config.job calls it.
"""

from __future__ import annotations

import dataclasses
from dataclasses import field
from typing import TYPE_CHECKING, Any

from winder.config.arms import ARMS
from winder.config.controllers import Controller, builtin
from winder.config.dialects import REGISTRY as DIALECT_REGISTRY
from winder.config.robot import RobotCell, language_problem, parse_robot_cell

if TYPE_CHECKING:
    from winder.config.reader import Reader

DEFAULT_EYE_CLEARANCE = 20.0
DEFAULT_FEED = 3000.0
DEFAULT_CHORD_TOLERANCE = 0.05
# The program writes axes and feeds with 3 decimals (winder.machine.limits.AXIS_DECIMALS, held equal
# by tests/config/test_config.py): the least feed and chord tolerance that mean anything in it.
WRITTEN_RESOLUTION = 0.001
MAX_EYE_CLEARANCE = 2000.0

MACHINE_ROLES = ("carriage", "rotation", "cross_feed", "yaw")
DIALECTS = tuple(DIALECT_REGISTRY)  # the dialect registry's names (winder.config.dialects)
# A shop winder's axes (speed in mm/min or deg/min, acceleration in mm/s^2 or deg/s^2): the example of docs/guide/config.md.
DEFAULT_DYNAMICS = {"carriage": (30000.0, 1500.0), "rotation": (20000.0, 3000.0),
                    "cross_feed": (10000.0, 1000.0), "yaw": (20000.0, 3000.0)}
# Axis words of G-code (ISO 6983 / RS-274); any other letter (F, G, M, N, ...) would change the
# meaning of a program line.
AXIS_LETTERS = "XYZABCUVW"


@dataclasses.dataclass(frozen=True)
class MachineAxes:
    """G-code letters of the machine axes (YAML `machine.axes`); distinct, from X Y Z A B C U V W.

    carriage: carriage travel along the mandrel axis (mm). rotation: mandrel turn (deg, cumulative).
    cross_feed: radial distance of the payout eye from the axis (mm). yaw: payout-eye yaw (deg).
    """

    carriage: str = "X"
    rotation: str = "A"
    cross_feed: str = "Z"
    yaw: str = "B"


@dataclasses.dataclass(frozen=True)
class MachineLimits:
    """Travel limits (YAML `machine.limits`), each (min, max) in the axis' unit, or None: unlimited."""

    carriage: tuple[float, float] | None = None
    rotation: tuple[float, float] | None = None
    cross_feed: tuple[float, float] | None = None
    yaw: tuple[float, float] | None = None

    def get(self, role: str) -> tuple[float, float] | None:
        """The limits of one axis by role name (carriage, rotation, cross_feed, yaw)."""
        if role not in MACHINE_ROLES:
            raise KeyError(role)
        return getattr(self, role)

    def items(self) -> tuple[tuple[str, tuple[float, float]], ...]:
        """The (role, (min, max)) pairs of the limited axes."""
        return tuple((role, lim) for role in MACHINE_ROLES if (lim := getattr(self, role)) is not None)


@dataclasses.dataclass(frozen=True)
class AxisDynamics:
    """One axis' top speed (mm/min or deg/min) and acceleration (mm/s^2 or deg/s^2), both > 0."""

    speed: float
    acceleration: float


def _default_dynamics(role: str) -> AxisDynamics:
    return AxisDynamics(*DEFAULT_DYNAMICS[role])


@dataclasses.dataclass(frozen=True)
class MachineDynamics:
    """Per logical axis top speed and acceleration (YAML `machine.dynamics`); defaults DEFAULT_DYNAMICS."""

    carriage: AxisDynamics = field(default_factory=lambda: _default_dynamics("carriage"))
    rotation: AxisDynamics = field(default_factory=lambda: _default_dynamics("rotation"))
    cross_feed: AxisDynamics = field(default_factory=lambda: _default_dynamics("cross_feed"))
    yaw: AxisDynamics = field(default_factory=lambda: _default_dynamics("yaw"))

    def get(self, role: str) -> AxisDynamics:
        if role not in MACHINE_ROLES:
            raise KeyError(role)
        return getattr(self, role)


@dataclasses.dataclass(frozen=True)
class MachineConfig:
    """The winder (YAML `machine:`). Every key has a default, so the section may be left out.

    axes: the axis letters (see MachineAxes).
    eye_radius, eye_clearance: the payout-eye envelope, exactly one is set. YAML `eye: {radius: Z}`:
        the eye moves on a cylinder of radius Z (mm) around the axis (larger than the mandrel).
        YAML `eye: {clearance: c}`: the eye keeps c mm beyond the local mandrel radius
        (default: clearance 20).
    eye_size: the payout eye's diameter (mm, >= 0, YAML `eye: {..., size: d}`; default 0, a point):
        with a clearance the eye's body keeps the clearance (its centre c + d / 2 from the mandrel);
        with a radius the body must clear the mandrel.
    feed: G-code feed rate F, mm/min, > 0 (default 3000).
    chord_tolerance: largest deviation (mm) between the programmed straight moves and the exact
        eye path, >= 0.001 and below the eye clearance (default 0.05); the exporter drops points within it.
    limits: axis travel limits (see MachineLimits); the exporter refuses a program exceeding them.
    robot: true: write eye poses (position and fiber direction in the mandrel frame) for a robot (a
        mapping: a robot cell, `cell`, winder.config.robot)
        instead of G-code axes. Default: true exactly when the mandrel axis is bent, which a
        straight-axis winder cannot follow (an explicit false is then refused).
    dialect: how the program is written (DIALECTS): generic G-code, marlin (fiberpath's X A B
        machines), linuxcnc (inverse-time feed), robot (eye poses). Default: robot for a robot,
        else generic; `robot` and the robot mode imply each other.
    dynamics: per-axis top speed and acceleration (see MachineDynamics).
    """

    axes: MachineAxes = field(default_factory=MachineAxes)
    eye_radius: float | None = None
    eye_clearance: float | None = DEFAULT_EYE_CLEARANCE
    feed: float = DEFAULT_FEED
    chord_tolerance: float = DEFAULT_CHORD_TOLERANCE
    limits: MachineLimits = field(default_factory=MachineLimits)
    robot: bool = False
    dialect: str = "generic"
    eye_size: float = 0.0
    dynamics: MachineDynamics = field(default_factory=MachineDynamics)
    cell: RobotCell | None = None  # machine.robot as a mapping: the robot cell (winder.config.robot)
    post: Controller | None = None  # machine.post: a controller described by a post file (None: the dialect's)

    @property
    def controller(self) -> Controller:
        """The description of the controller the program is written for (winder.config.controllers)."""
        return self.post if self.post is not None else builtin(self.dialect)


# -- machine ---------------------------------------------------------------------------------------
_MACHINE_KEYS = ("axes", "eye", "feed", "chord_tolerance", "limits", "robot", "dialect", "dynamics", "post")


def parse_machine(rd: Reader, value: Any, path: str, *, bent: bool,
                  max_radius: float | None) -> MachineConfig:
    """The machine section (None: all defaults). bent: the mandrel axis is not straight;
    max_radius: the mandrel's largest distance from its axis, when known without computation."""
    if value is None:
        return MachineConfig(robot=bent, dialect="robot" if bent else "generic")
    m = rd.mapping(value, path, _MACHINE_KEYS)
    axes = _parse_axes(rd, m["axes"], rd.at(path, "axes")) if "axes" in m else MachineAxes()
    limits = _parse_limits(rd, m["limits"], rd.at(path, "limits")) if "limits" in m else MachineLimits()
    eye_radius, eye_clearance, eye_size = None, DEFAULT_EYE_CLEARANCE, 0.0
    if "eye" in m:
        eye = m["eye"]
        if isinstance(eye, dict) and "size" in eye:
            eye_size = rd.number(eye["size"], rd.at(rd.at(path, "eye"), "size"))
            if eye_size < 0.0:
                raise rd.error(rd.at(rd.at(path, "eye"), "size"), "must be >= 0 (the eye's diameter, mm)", eye["size"])
            if eye_size > MAX_EYE_CLEARANCE:  # far larger, the search for the eye's lead never ends
                raise rd.error(rd.at(rd.at(path, "eye"), "size"), f"must be <= {MAX_EYE_CLEARANCE:g} mm (the eye's "
                               f"diameter; an eye that large cannot guide the band)", eye["size"])
            eye = {k: v for k, v in eye.items() if k != "size"}
        eye_radius, eye_clearance = _parse_eye(rd, eye, rd.at(path, "eye"), max_radius, limits)
        if eye_radius is not None and max_radius is not None and eye_radius - eye_size / 2 <= max_radius:
            raise rd.error(rd.at(rd.at(path, "eye"), "size"), f"an eye this large on radius {eye_radius:g} would "
                           f"touch the mandrel (largest radius {max_radius:g} mm)", m["eye"]["size"])
    feed = rd.positive(m.get("feed", DEFAULT_FEED), rd.at(path, "feed"))
    if feed < WRITTEN_RESOLUTION:
        raise rd.error(rd.at(path, "feed"), f"must be >= {WRITTEN_RESOLUTION:g} mm/min (the program writes F with 3 "
                       f"decimals: a slower feed reads F0.000, at which no controller moves)", m["feed"])
    chord_tolerance = rd.positive(m.get("chord_tolerance", DEFAULT_CHORD_TOLERANCE),
                                  rd.at(path, "chord_tolerance"))
    if chord_tolerance < WRITTEN_RESOLUTION:
        raise rd.error(rd.at(path, "chord_tolerance"), f"must be >= {WRITTEN_RESOLUTION:g} mm (the program writes "
                       f"the axes to {WRITTEN_RESOLUTION:g}: a finer tolerance cannot be held, only multiply the "
                       f"points)", m["chord_tolerance"])
    if eye_clearance is not None and not chord_tolerance < eye_clearance:
        # The collision check lets the moves' chords cut up to the tolerance into the clearance
        # (winder.machine.collision); at or beyond it the eye could pass through the mandrel unrefused.
        if "chord_tolerance" in m:
            raise rd.error(rd.at(path, "chord_tolerance"), f"must be smaller than the eye's clearance "
                           f"({eye_clearance:g} mm): the programmed moves may cut that far inside the eye's "
                           f"path, into the mandrel", m["chord_tolerance"])
        raise rd.error(rd.at(rd.at(path, "eye"), "clearance"), f"must be larger than the chord tolerance "
                       f"({chord_tolerance:g} mm, machine.chord_tolerance): the programmed moves may cut that far "
                       f"inside the eye's path, into the mandrel", m["eye"]["clearance"])
    robot, cell = bent, None
    if isinstance(m.get("robot"), dict):
        cell, robot = parse_robot_cell(rd, m["robot"], rd.at(path, "robot")), True
    elif "robot" in m:
        if not isinstance(m["robot"], bool):
            raise rd.error(rd.at(path, "robot"), "must be true, false or a robot cell (a mapping with an arm: "
                           f"{', '.join(ARMS)})", m["robot"])
        robot = m["robot"]
        if bent and not robot:
            raise rd.error(rd.at(path, "robot"), "must be true for a bent mandrel axis: a straight-axis "
                           "winder cannot follow it, so winder writes eye poses for a robot", m["robot"])
    post = _parse_post(rd, m, path) if "post" in m else None
    robot, dialect = _parse_dialect(rd, m if post is None else {**m, "dialect": post.dialect}, path, robot, bent, cell)
    dynamics = _parse_dynamics(rd, m["dynamics"], rd.at(path, "dynamics")) if "dynamics" in m else MachineDynamics()
    return MachineConfig(axes, eye_radius, eye_clearance, feed, chord_tolerance, limits, robot, dialect,
                         eye_size, dynamics, cell, post)


def _parse_post(rd: Reader, m: dict, path: str) -> Controller:
    """machine.post: a post file, read relative to the config's folder; machine.dialect, when given too,
    must be the built-in dialect the post extends."""
    from pathlib import Path  # noqa: PLC0415

    from winder.config.controllers import read_post  # noqa: PLC0415
    from winder.errors import ConfigError  # noqa: PLC0415

    where = rd.at(path, "post")
    name = rd.text(m["post"], where)
    if not name.strip():
        raise rd.error(where, "must name a post file (a controller described as data)", m["post"])
    file = Path(name) if Path(name).is_absolute() else Path(rd.source).parent / name
    try:
        post = read_post(file, name, None)
    except ConfigError as exc:  # named as the post file's: the config's key path first
        raise rd.error(where, exc.format_message()) from exc
    if "dialect" in m and m["dialect"] != post.dialect:
        raise rd.error(rd.at(path, "dialect"), f"must be left out or be {post.dialect}, the dialect the post file "
                       f"{name} extends", m["dialect"])
    return post


def _parse_dialect(rd: Reader, m: dict, path: str, robot: bool, bent: bool,
                   cell: RobotCell | None = None) -> tuple[bool, str]:
    """(robot, dialect): `dialect: robot` turns robot mode on; a G-code dialect needs a straight axis;
    krl, rapid and urscript need a robot cell (the maker's language is the default there)."""
    if "dialect" not in m:
        if cell is not None:
            return True, ARMS[cell.arm].language
        return robot, "robot" if robot else "generic"
    where = rd.at(path, "dialect")
    dialect = m["dialect"]
    if not isinstance(dialect, str) or dialect not in DIALECT_REGISTRY:
        raise rd.error(where, f"must be one of {', '.join(DIALECT_REGISTRY)}", dialect)
    if DIALECT_REGISTRY[dialect].cell:
        if cell is None:
            raise rd.error(where, f"{dialect} needs a robot cell: machine.robot as a mapping with at least an arm "
                           f"({', '.join(ARMS)})", dialect)
        problem = language_problem(cell, dialect)
        if problem is not None:
            raise rd.error(where, problem, dialect)
        return True, dialect
    if DIALECT_REGISTRY[dialect].robot:
        if "robot" in m and not robot:
            raise rd.error(where, "robot needs robot poses, but machine.robot is false", dialect)
        return True, dialect
    if robot:
        why = "the mandrel axis is bent" if bent else "machine.robot is true"
        raise rd.error(where, f"must be robot: {why}, so winder writes eye poses, not {dialect} G-code",
                       dialect)
    return robot, dialect


def _parse_dynamics(rd: Reader, value: Any, path: str) -> MachineDynamics:
    m = rd.mapping(value, path, MACHINE_ROLES)
    axes = {}
    for role, spec in m.items():
        where = rd.at(path, role)
        d = rd.mapping(spec, where, ("speed", "acceleration"))
        default = _default_dynamics(role)
        speed = rd.positive(d.get("speed", default.speed), rd.at(where, "speed"))
        if speed < WRITTEN_RESOLUTION:
            raise rd.error(rd.at(where, "speed"), f"must be >= {WRITTEN_RESOLUTION:g} (the program writes F with 3 "
                           f"decimals: a move this slow reads F0.000, at which no controller moves)", d["speed"])
        axes[role] = AxisDynamics(speed, rd.positive(d.get("acceleration", default.acceleration),
                                                     rd.at(where, "acceleration")))
    return MachineDynamics(**axes)


def _parse_axes(rd: Reader, value: Any, path: str) -> MachineAxes:
    m = rd.mapping(value, path, MACHINE_ROLES)
    letters = {}
    owner: dict[str, str] = {}
    for role in MACHINE_ROLES:
        letter = m.get(role, getattr(MachineAxes, role))
        where = rd.at(path, role)
        if not isinstance(letter, str) or len(letter) != 1 or letter not in AXIS_LETTERS:
            raise rd.error(where, f"must be one G-code axis letter ({', '.join(AXIS_LETTERS)})", letter)
        if letter in owner:
            # Defaults count too: moving yaw to Z needs cross_feed moved off Z as well.
            raise rd.error(where, f"must differ from the other axes ({owner[letter]} is already "
                           f"{letter})", letter)
        owner[letter] = role
        letters[role] = letter
    return MachineAxes(**letters)


def _parse_limits(rd: Reader, value: Any, path: str) -> MachineLimits:
    m = rd.mapping(value, path, MACHINE_ROLES)
    limits = {}
    for role, pair in m.items():
        where = rd.at(path, role)
        if not isinstance(pair, list) or len(pair) != 2:
            raise rd.error(where, "must be a pair [min, max]", pair)
        lo = rd.number(pair[0], where, "min")
        hi = rd.number(pair[1], where, "max")
        if not lo < hi:
            raise rd.error(where, "min must be smaller than max", pair)
        limits[role] = (lo, hi)
    return MachineLimits(**limits)


def _parse_eye(rd: Reader, value: Any, path: str, max_radius: float | None,
               limits: MachineLimits) -> tuple[float | None, float | None]:
    m = rd.mapping(value, path, ("radius", "clearance", "size"))
    if len(m) != 1:
        raise rd.error(path, "give exactly one of radius (a cylinder around the axis) or clearance "
                       "(a distance beyond the mandrel surface)", m)
    if "clearance" in m:
        clearance = rd.positive(m["clearance"], rd.at(path, "clearance"))
        if clearance > MAX_EYE_CLEARANCE:
            raise rd.error(rd.at(path, "clearance"), f"must be <= {MAX_EYE_CLEARANCE:g} mm (a payout eye "
                           f"that far from the mandrel cannot guide the band)", m["clearance"])
        return None, clearance
    where = rd.at(path, "radius")
    radius = rd.positive(m["radius"], where)
    if max_radius is not None and radius <= max_radius:
        raise rd.error(where, f"must be larger than the mandrel's largest radius ({max_radius:g} mm), "
                       "or the eye would hit the mandrel", m["radius"])
    cross = limits.cross_feed
    if cross is not None and not cross[0] <= radius <= cross[1]:
        limits_path = rd.at(rd.at(path.rpartition(".")[0], "limits"), "cross_feed")
        raise rd.error(where, f"must lie within {limits_path} [{cross[0]:g}, {cross[1]:g}]",
                       m["radius"])
    return radius, None
