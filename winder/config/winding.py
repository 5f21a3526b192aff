"""The `winding:` and `machine:` sections of a job file: the winding plan and the winder.

The parsers here receive a `winder.config.reader.Reader` (it carries the file name and formats every
message), plus the few facts about the mandrel they check against; winder.config.mandrel calls them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

DEFAULT_POINTS = 200
# A pass is solved in O(points); beyond this the result is no more accurate, only slower.
MAX_POINTS = 100_000
DEFAULT_FRICTION = 0.2
DEFAULT_EYE_CLEARANCE = 20.0
DEFAULT_FEED = 3000.0
DEFAULT_CHORD_TOLERANCE = 0.05
MAX_EYE_CLEARANCE = 2000.0
# Hoop layers below this angle lay a visibly helical band; such a layer is a helical one.
MIN_HOOP_ANGLE = 70.0
# Slack (mm) when comparing user-typed lengths with computed ones: an arc's length is irrational,
# so a region end typed as 235.62 for a 150 mm x 90 deg bend must still count as "inside".
LENGTH_SLACK = 1e-3

MACHINE_ROLES = ("carriage", "rotation", "cross_feed", "yaw")
# Axis words of G-code (ISO 6983 / RS-274); any other letter (F, G, M, N, ...) would change the
# meaning of a program line.
AXIS_LETTERS = "XYZABCUVW"


class LayerType(Enum):
    """How a layer is wound."""

    HELICAL = "helical"
    HOOP = "hoop"


@dataclass(frozen=True)
class LayerConfig:
    """One layer of the plan (YAML: an entry of `winding.layers`).

    type: `helical` (a full-coverage pattern of circuits, each a forward and a return pass laying
        +angle and -angle bands) or `hoop` (near-circumferential turns on the cylindrical region).
    angle_deg: YAML `angle`, the winding angle from the meridian in degrees (0 = along the axis,
        90 = circumferential). Helical: required, in (0, 90). Hoop: optional, in [70, 90); when
        left out (None) the planner derives it from the band width (one band width of advance per
        mandrel turn).
    pattern: helical only. YAML `pattern: auto` (None: the planner picks the skip k needing the least
        angle or dwell adjustment) or an integer k >= 1 (the circuit advance is 2 pi k / N_c; the
        planner refuses k sharing a factor with N_c).
    passes: hoop only (helical layers always 1): the number of traverses over the region; each
        traverse lays one ply, so 2 is there and back.
    """

    type: LayerType
    angle_deg: float | None = None
    pattern: int | None = None
    passes: int = 1


@dataclass(frozen=True)
class WindingConfig:
    """The winding plan (YAML `winding:`). band_width and layers are required.

    band_width: width of the fiber band as laid, mm, > 0.
    region: YAML `region: {start, end}`: the axial station range (t, mm) wound on an open mandrel,
        0 <= start < end <= T; None (the default) is the whole mandrel. Not for vessels, whose
        turnarounds lie on the domes.
    points: points per pass, the accuracy of each geodesic solve, integer >= 3 (default 200).
    tolerance: instead of points: refine each pass until its estimated length error is below this
        (mm, > 0). Exclusive with points; when tolerance is given, points is None.
    dwell_start_deg, dwell_end_deg: YAML `dwell: {start, end}`: the least mandrel turn (deg) while the
        carriage waits at each end of an open mandrel, >= 0 (default 0). The planner may dwell longer to
        close the pattern. Not for vessels.
    friction: fiber-mandrel friction coefficient for the slip check of non-geodesic paths, in [0, 1]
        (default 0.2; typical wet epoxy rovings 0.1 to 0.3).
    layers: the layers, wound in this order, at least one.
    """

    band_width: float
    region: tuple[float, float] | None = None
    points: int | None = DEFAULT_POINTS
    tolerance: float | None = None
    dwell_start_deg: float = 0.0
    dwell_end_deg: float = 0.0
    friction: float = DEFAULT_FRICTION
    layers: tuple[LayerConfig, ...] = ()


@dataclass(frozen=True)
class MachineAxes:
    """G-code letters of the machine axes (YAML `machine.axes`); distinct, from X Y Z A B C U V W.

    carriage: carriage travel along the mandrel axis (mm). rotation: mandrel turn (deg, cumulative).
    cross_feed: radial distance of the payout eye from the axis (mm). yaw: payout-eye yaw (deg).
    """

    carriage: str = "X"
    rotation: str = "A"
    cross_feed: str = "Z"
    yaw: str = "B"


@dataclass(frozen=True)
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


@dataclass(frozen=True)
class MachineConfig:
    """The winder (YAML `machine:`). Every key has a default, so the section may be left out.

    axes: the axis letters (see MachineAxes).
    eye_radius, eye_clearance: the payout-eye envelope, exactly one is set. YAML `eye: {radius: Z}`:
        the eye moves on a cylinder of radius Z (mm) around the axis (larger than the mandrel).
        YAML `eye: {clearance: c}`: the eye keeps c mm beyond the local mandrel radius
        (default: clearance 20).
    feed: G-code feed rate F, mm/min, > 0 (default 3000).
    chord_tolerance: largest deviation (mm) between the programmed straight moves and the exact
        eye path, > 0 (default 0.05); the exporter drops points within it.
    limits: axis travel limits (see MachineLimits); the exporter refuses a program exceeding them.
    robot: true: write eye poses (position and fiber direction in the mandrel frame) for a robot
        instead of G-code axes. Default: true exactly when the mandrel axis is bent, which a
        straight-axis winder cannot follow (an explicit false is then refused).
    """

    axes: MachineAxes = field(default_factory=MachineAxes)
    eye_radius: float | None = None
    eye_clearance: float | None = DEFAULT_EYE_CLEARANCE
    feed: float = DEFAULT_FEED
    chord_tolerance: float = DEFAULT_CHORD_TOLERANCE
    limits: MachineLimits = field(default_factory=MachineLimits)
    robot: bool = False


# -- winding ---------------------------------------------------------------------------------------
_WINDING_KEYS = ("band_width", "layers", "region", "points", "tolerance", "dwell", "friction")
_LAYER_KINDS = {
    "helical": (("angle",), ("pattern",)),
    "hoop": ((), ("angle", "passes")),
}


def parse_winding(rd: Reader, value: Any, path: str, *, axis_length: float | None,
                  vessel: bool) -> WindingConfig:
    """The winding section; axis_length is T when known without computation (None otherwise)."""
    m = rd.mapping(value, path, _WINDING_KEYS, required=("band_width", "layers"))
    band_width = rd.positive(m["band_width"], rd.at(path, "band_width"))

    region = None
    if "region" in m:
        if vessel:
            raise rd.error(rd.at(path, "region"), "applies to open mandrels only; on a vessel the fiber "
                           "turns around on the domes", m["region"])
        region = _parse_region(rd, m["region"], rd.at(path, "region"), axis_length)

    if "points" in m and "tolerance" in m:
        raise rd.error(rd.at(path, "tolerance"), "give points or tolerance, not both", m["tolerance"])
    points: int | None = DEFAULT_POINTS
    tolerance = None
    if "tolerance" in m:
        points = None
        tolerance = rd.positive(m["tolerance"], rd.at(path, "tolerance"))
    elif "points" in m:
        points = rd.integer(m["points"], rd.at(path, "points"), minimum=3, maximum=MAX_POINTS)

    dwell = (0.0, 0.0)
    if "dwell" in m:
        if vessel:
            raise rd.error(rd.at(path, "dwell"), "applies to open mandrels only; on a vessel the fiber "
                           "turns around on the domes", m["dwell"])
        dwell = _parse_dwell(rd, m["dwell"], rd.at(path, "dwell"))

    friction = DEFAULT_FRICTION
    if "friction" in m:
        friction = rd.number(m["friction"], rd.at(path, "friction"))
        if not 0.0 <= friction <= 1.0:
            raise rd.error(rd.at(path, "friction"), "must be in [0, 1] (a friction coefficient)",
                           m["friction"])

    items = rd.listing(m["layers"], rd.at(path, "layers"), 1, "layer")
    layers = tuple(_parse_layer(rd, item, rd.at(rd.at(path, "layers"), i)) for i, item in enumerate(items))
    return WindingConfig(band_width, region, points, tolerance, dwell[0], dwell[1], friction, layers)


def _parse_region(rd: Reader, value: Any, path: str, axis_length: float | None) -> tuple[float, float]:
    m = rd.mapping(value, path, ("start", "end"), required=("start", "end"))
    start = rd.number(m["start"], rd.at(path, "start"))
    end = rd.number(m["end"], rd.at(path, "end"))
    if start < 0.0:
        raise rd.error(rd.at(path, "start"), "must be >= 0 (t starts at 0 at the start of the axis)",
                       m["start"])
    if end <= start:
        raise rd.error(rd.at(path, "end"), f"must be larger than start ({start:g})", m["end"])
    if axis_length is not None and end > axis_length:
        if end > axis_length + LENGTH_SLACK:
            raise rd.error(rd.at(path, "end"), f"must not exceed the mandrel length ({axis_length:g} mm)",
                           m["end"])
        end = axis_length  # within typing precision of the end: the planner must not step past T
    return (start, end)


def _parse_dwell(rd: Reader, value: Any, path: str) -> tuple[float, float]:
    m = rd.mapping(value, path, ("start", "end"))
    ends = []
    for key in ("start", "end"):
        dwell = rd.number(m.get(key, 0.0), rd.at(path, key))
        if dwell < 0.0:
            raise rd.error(rd.at(path, key), "must be >= 0 (degrees of mandrel turn)", m[key])
        ends.append(dwell)
    return (ends[0], ends[1])


def _parse_layer(rd: Reader, value: Any, path: str) -> LayerConfig:
    kind, m = rd.typed(value, path, "layer", _LAYER_KINDS)
    angle_path = rd.at(path, "angle")
    if kind == "helical":
        angle = rd.number(m["angle"], angle_path)
        if not 0.0 < angle < 90.0:
            raise rd.error(angle_path, "must be in (0, 90) degrees from the meridian (0 is along the "
                           "axis, 90 is a hoop)", m["angle"])
        pattern = None
        if "pattern" in m and m["pattern"] != "auto":
            pattern = rd.integer(m["pattern"], rd.at(path, "pattern"), minimum=1,
                                 what="must be auto or a whole number >= 1")
        return LayerConfig(LayerType.HELICAL, angle, pattern, 1)

    angle_deg = None
    if "angle" in m:
        angle_deg = rd.number(m["angle"], angle_path)
        if not MIN_HOOP_ANGLE <= angle_deg < 90.0:
            raise rd.error(angle_path, f"must be in [{MIN_HOOP_ANGLE:g}, 90) degrees for a hoop layer "
                           "(leave it out to derive it from the band width; lower angles are a helical "
                           "layer)", m["angle"])
    passes = rd.integer(m.get("passes", 1), rd.at(path, "passes"), minimum=1)
    return LayerConfig(LayerType.HOOP, angle_deg, None, passes)


# -- machine ---------------------------------------------------------------------------------------
_MACHINE_KEYS = ("axes", "eye", "feed", "chord_tolerance", "limits", "robot")


def parse_machine(rd: Reader, value: Any, path: str, *, bent: bool,
                  max_radius: float | None) -> MachineConfig:
    """The machine section (None: all defaults). bent: the mandrel axis is not straight;
    max_radius: the mandrel's largest distance from its axis, when known without computation."""
    if value is None:
        return MachineConfig(robot=bent)
    m = rd.mapping(value, path, _MACHINE_KEYS)
    axes = _parse_axes(rd, m["axes"], rd.at(path, "axes")) if "axes" in m else MachineAxes()
    limits = _parse_limits(rd, m["limits"], rd.at(path, "limits")) if "limits" in m else MachineLimits()
    eye_radius, eye_clearance = None, DEFAULT_EYE_CLEARANCE
    if "eye" in m:
        eye_radius, eye_clearance = _parse_eye(rd, m["eye"], rd.at(path, "eye"), max_radius, limits)
    feed = rd.positive(m.get("feed", DEFAULT_FEED), rd.at(path, "feed"))
    chord_tolerance = rd.positive(m.get("chord_tolerance", DEFAULT_CHORD_TOLERANCE),
                                  rd.at(path, "chord_tolerance"))
    robot = bent
    if "robot" in m:
        robot = rd.boolean(m["robot"], rd.at(path, "robot"))
        if bent and not robot:
            raise rd.error(rd.at(path, "robot"), "must be true for a bent mandrel axis: a straight-axis "
                           "winder cannot follow it, so winder writes eye poses for a robot", m["robot"])
    return MachineConfig(axes, eye_radius, eye_clearance, feed, chord_tolerance, limits, robot)


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
    m = rd.mapping(value, path, ("radius", "clearance"))
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
