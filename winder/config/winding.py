"""The `winding:` section of a job file: the layers and how accurately each pass is solved.

The parser receives a `winder.config.reader.Reader` (it carries the file name and formats every
message), plus the few facts about the mandrel it checks against; winder.config.job calls it.
"""

from __future__ import annotations

import dataclasses
import math
from enum import Enum
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

from winder.config.material import MaterialConfig, parse_materials
from winder.config.reader import LENGTH_SLACK
from winder.config.tension import TensionConfig, check_tensions, parse_tension

DEFAULT_POINTS = 200
# A pass is solved in O(points); beyond this the result is no more accurate, only slower.
MAX_POINTS = 100_000
DEFAULT_FRICTION = 0.2
DEFAULT_ANGLE_TOLERANCE = 0.5  # deg: how far closing a pattern may move a layer's angle from the one asked
# Hoop layers below this angle lay a visibly helical band; such a layer is a helical one.
MIN_HOOP_ANGLE = 70.0
MIN_COVERAGE = 0.999  # winding.min_coverage's default: the covered fraction every layer proves
MAX_LAYER_CIRCUITS = 20_000  # YAML `circuits:`; = winder.winding.budget.MAX_CIRCUITS (the work budget)
SLIP_AUTO = "auto"


class LayerType(Enum):
    """How a layer is wound."""

    HELICAL = "helical"
    HOOP = "hoop"


def layer_label(index: int, kind: str | None = None, angle_deg: float | None = None) -> str:
    """How every message and output names layer `index` (0-based): from 1, with its type and angle.

    Examples
    --------
    >>> layer_label(4, "helical", 16.0)
    'layer 5 (helical 16 deg)'
    >>> layer_label(1, "hoop")
    'layer 2 (hoop)'
    """
    words = " ".join(w for w in (kind, f"{angle_deg:g} deg" if angle_deg is not None else None) if w)
    return f"layer {index + 1} ({words})" if words else f"layer {index + 1}"


def layer_key(index: int, item: Any) -> str:
    """The key path of layer `index` (0-based) of `winding.layers` as read, before it is parsed: its
    layer_label with what its mapping tells (a known type, then a numeric angle), so that a message
    names the layer as every other message does (`layer 2 (hoop).passes`).

    Examples
    --------
    >>> layer_key(1, {"type": "hoop", "passes": 0}), layer_key(0, {"type": "helical", "angle": 16})
    ('layer 2 (hoop)', 'layer 1 (helical 16 deg)')
    >>> layer_key(2, {"type": "spiral", "angle": 16}), layer_key(3, "hoop")
    ('layer 3', 'layer 4')
    """
    if not isinstance(item, dict):
        return layer_label(index)
    kind = item.get("type")
    if not isinstance(kind, str) or kind not in _LAYER_KINDS:
        return layer_label(index)
    angle = item.get("angle")
    if isinstance(angle, bool) or not isinstance(angle, (int, float)):
        return layer_label(index, kind)
    try:
        value = float(angle)
    except OverflowError:
        return layer_label(index, kind)
    return layer_label(index, kind, value if math.isfinite(value) else None)


@dataclasses.dataclass(frozen=True)
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
    slip: helical only. 0 (geodesic, the default), a number lambda = k_g / k_n in [0, friction] (its
        sign follows the pass direction; on vessels the domes' lambda, on bent tubes the largest
        |lambda| the passes through the bends may use), or SLIP_AUTO (friction-held where geodesics
        cannot cover or turn: bent tubes, vessels whose Clairaut turnaround is inside an opening).
    turnaround_radius: helical on vessels only: (first dome, end dome) radii (mm) to turn around at,
        lambda solved for on each (|lambda| <= friction); YAML a number (both) or {start, end} (either may
        be left out: that dome turns at its own opening plus half a band). None: where the slip leads
        (Clairaut for slip 0; slip auto: each dome at its own opening plus half a band where the
        geodesic would turn inside it, docs/math/17 17.6).
    circuits: helical only. YAML `circuits: N` (whole, >= 1): wind exactly N circuits instead of the
        planner's count (the fewest that cover, raised where passes bunch); `winder patterns` lists
        the choices. None: the planner's count.
    """

    type: LayerType
    angle_deg: float | None = None
    pattern: int | None = None
    passes: int = 1
    slip: float | str = 0.0
    turnaround_radius: tuple[float | None, float | None] | None = None
    material: MaterialConfig | None = None  # this layer's own (config.material), else the job's
    circuits: int | None = None
    taper: float = 0.0  # hoop: mm over which the layer's reversals step in at each end (math 8.9)
    step_back: float = 0.0  # helical on vessels: mm its turnarounds move toward the equator (math 8.8)
    min_coverage: float | None = None  # the covered fraction it proves (None: winding.min_coverage)
    tension: TensionConfig | None = None  # N per band, this layer's own (winder.config.tension)

    def label(self, index: int) -> str:
        """`layer 5 (helical 16 deg)`: layer_label of this layer at 0-based position `index`."""
        return layer_label(index, self.type.value, self.angle_deg)


@dataclasses.dataclass(frozen=True)
class WindingConfig:
    """The winding plan (YAML `winding:`). band_width and layers are required.

    band_width: width of the fiber band as laid, mm, > 0.
    region: YAML `region: {start, end}`: the axial station range (t, mm) wound on an open mandrel,
        0 <= start < end <= T; None (the default) is the whole mandrel. Not for vessels, whose
        turnarounds lie on the domes.
    points: points per pass, the accuracy of each geodesic solve, integer >= 3 (default 200, and more for a
        pass of many rounds: winder.winding.passes.pass_points).
    tolerance: instead of points: refine each pass until its estimated length error is below this
        (mm, > 0). Exclusive with points; when tolerance is given, points is None.
    dwell_start_deg, dwell_end_deg: YAML `dwell: {start, end}`: the least mandrel turn (deg) while the
        carriage waits at each end of an open mandrel, >= 0 (default 0). The planner may dwell longer to
        close the pattern. Not for vessels.
    friction: fiber-mandrel friction coefficient for the slip check of non-geodesic paths, in [0, 1]
        (default 0.2; typical wet epoxy rovings 0.1 to 0.3).
    layers: the layers, wound in this order, at least one.
    angle_tolerance: how far (deg, >= 0) closing a vessel layer's pattern may move its angle from the one
        asked (default 0.5); beyond it another circuit count, a friction-held closure at the angle, or a
        refusal listing the choices (docs/math/17 17.7).
    """

    band_width: float
    region: tuple[float, float] | None = None
    points: int | None = DEFAULT_POINTS
    tolerance: float | None = None
    dwell_start_deg: float = 0.0
    dwell_end_deg: float = 0.0
    friction: float = DEFAULT_FRICTION
    layers: tuple[LayerConfig, ...] = ()
    material: MaterialConfig | None = None  # config.material; None: no laminate, no build-up
    bridging_tolerance: float | None = None  # mm of lift-off (math 8.10); None: one ply (0 without a material)
    min_coverage: float = MIN_COVERAGE  # the covered fraction every layer proves unless it asks another
    tension: TensionConfig | None = None  # N per band (winder.config.tension); None: none programmed
    angle_tolerance: float = DEFAULT_ANGLE_TOLERANCE  # deg a pattern's closing may move an angle (docs/math/17 17.7)
    # Whether `points` was written: the default grows with a pass's rounds (winder.winding.passes.pass_points)
    points_given: bool = False

    def min_coverage_of(self, index: int) -> float:
        """The covered fraction layer `index` (0-based) must prove: its own, else the job's."""
        own = self.layers[index].min_coverage
        return self.min_coverage if own is None else own

    def tension_of(self, index: int) -> TensionConfig | None:
        """The tension of layer `index` (0-based): its own, else the job's."""
        return self.layers[index].tension or self.tension

    @property
    def has_laminate(self) -> bool:
        """Whether the layers build a laminate (a material is given): build-up, thickness, masses."""
        return self.material is not None or any(layer.material is not None for layer in self.layers)

    def material_of(self, index: int) -> MaterialConfig | None:
        """The material of layer `index` (0-based): its own, else the job's."""
        return self.layers[index].material or self.material


# -- winding ---------------------------------------------------------------------------------------
_WINDING_KEYS = ("band_width", "layers", "region", "points", "tolerance", "dwell", "friction", "material",
                 "bridging_tolerance", "min_coverage", "tension", "angle_tolerance")
_LAYER_KINDS = {
    "helical": (("angle",), ("pattern", "slip", "turnaround_radius", "material", "circuits", "step_back",
                             "min_coverage", "tension")),
    "hoop": ((), ("angle", "passes", "material", "taper", "min_coverage", "tension")),
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
        region = _parse_region(rd, m["region"], rd.at(path, "region"), axis_length, band_width)

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
    layers = tuple(_parse_layer(rd, item, layer_key(i, item), friction, vessel) for i, item in enumerate(items))
    material, layers = parse_materials(rd, m.get("material"), items, layers, path, band_width)
    bridging = None
    if "bridging_tolerance" in m:
        bridging = rd.number(m["bridging_tolerance"], rd.at(path, "bridging_tolerance"))
        if bridging < 0.0:
            raise rd.error(rd.at(path, "bridging_tolerance"), "must be >= 0 (mm of lift-off a fiber may stand "
                           "off the mandrel over a concave stretch)", m["bridging_tolerance"])
    _check_tapers(rd, items, layers, region)
    least = _parse_fraction(rd, m, path, "min_coverage", MIN_COVERAGE)
    layers = tuple(dataclasses.replace(layer, min_coverage=_parse_fraction(rd, item, layer.label(i), "min_coverage",
                                                                             None))
                   if isinstance(item, dict) and "min_coverage" in item else layer
                   for i, (layer, item) in enumerate(zip(layers, items)))
    tension = parse_tension(rd, m["tension"], rd.at(path, "tension"), job=True) if "tension" in m else None
    check_tensions(rd, layers, tension)
    angle_tolerance = DEFAULT_ANGLE_TOLERANCE
    if "angle_tolerance" in m:
        key = rd.at(path, "angle_tolerance")
        angle_tolerance = rd.number(m["angle_tolerance"], key)
        if not 0.0 <= angle_tolerance <= 90.0:
            raise rd.error(key, "must be in [0, 90] degrees (how far closing a pattern may move a layer's angle)",
                           m["angle_tolerance"])
    return WindingConfig(band_width=band_width, region=region, points=points, tolerance=tolerance,
                         dwell_start_deg=dwell[0], dwell_end_deg=dwell[1], friction=friction, layers=layers,
                         material=material, bridging_tolerance=bridging, min_coverage=least, tension=tension,
                         angle_tolerance=angle_tolerance, points_given="points" in m)


def _parse_fraction(rd: Reader, m: dict, path: str, key: str, default: float | None) -> float | None:
    """A covered fraction (min_coverage) in (0, 1], or the default where the key is left out."""
    if key not in m:
        return default
    value = rd.number(m[key], rd.at(path, key))
    if not 0.0 < value <= 1.0:
        raise rd.error(rd.at(path, key), "must be a covered fraction in (0, 1]", m[key])
    return value


def _check_tapers(rd: Reader, items: list, layers: tuple[LayerConfig, ...],
                  region: tuple[float, float] | None) -> None:
    """A hoop taper must leave its traverses a length: 2 taper (P - 1) / P below the region's length
    (checked here where the region is given; on vessels and whole mandrels by the planner)."""
    if region is None:
        return
    for i, layer in enumerate(layers):
        inward = 2.0 * layer.taper * (layer.passes - 1) / layer.passes
        if layer.type is LayerType.HOOP and inward >= region[1] - region[0]:
            key = rd.at(layer.label(i), "taper")
            raise rd.error(key, f"steps the hoop's reversals in by {inward:g} mm in all, more than the region "
                           f"({region[1] - region[0]:g} mm)", items[i]["taper"])


def _parse_region(rd: Reader, value: Any, path: str, axis_length: float | None,
                  band_width: float) -> tuple[float, float]:
    m = rd.mapping(value, path, ("start", "end"), required=("start", "end"))
    start = rd.number(m["start"], rd.at(path, "start"))
    end = rd.number(m["end"], rd.at(path, "end"))
    if start < 0.0:
        raise rd.error(rd.at(path, "start"), "must be >= 0 (t starts at 0 at the start of the axis)",
                       m["start"])
    if end <= start:
        raise rd.error(rd.at(path, "end"), f"must be larger than start ({start:g})", m["end"])
    if end - start < band_width:  # no band fits: the passes would have no length to be solved on
        raise rd.error(rd.at(path, "end"), f"must be at least one band width ({band_width:g} mm) past start "
                       f"({start:g})", m["end"])
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


def _parse_slip(rd: Reader, m: dict, path: str, friction: float,
                vessel: bool) -> tuple[float | str, tuple[float | None, float | None] | None]:
    """The helical layer's slip and turnaround_radius (docs/guide/config.md)."""
    slip: float | str = 0.0
    if "slip" in m and m["slip"] != SLIP_AUTO:
        slip = rd.number(m["slip"], rd.at(path, "slip"))
        if not 0.0 <= slip <= friction:
            raise rd.error(rd.at(path, "slip"), f"must be auto or a number in [0, {friction:g}] (|k_g / k_n| "
                           f"within winding.friction; its sign follows the pass direction)", m["slip"])
    elif "slip" in m:
        slip = SLIP_AUTO
    radius = None
    if "turnaround_radius" in m:
        key = rd.at(path, "turnaround_radius")
        if not vessel:
            raise rd.error(key, "applies to vessels only (the fiber turns around on the domes)",
                           m["turnaround_radius"])
        if isinstance(slip, float) and slip > 0.0:
            raise rd.error(key, "give slip or turnaround_radius, not both (the slip is solved for the radius)",
                           m["turnaround_radius"])
        value = m["turnaround_radius"]
        if isinstance(value, dict):
            ends = rd.mapping(value, key, ("start", "end"))
            if not ends:
                raise rd.error(key, "give start, end or both (mm: the radius each dome turns at)", value)
            radius = tuple(rd.positive(ends[e], rd.at(key, e)) if e in ends else None for e in ("start", "end"))
        else:
            both = rd.positive(value, key)
            radius = (both, both)
    return slip, radius


def _parse_circuits(rd: Reader, m: dict, path: str, pattern: int | None) -> int | None:
    """A helical layer's `circuits: N`, the pattern (when given) coprime with it."""
    if "circuits" not in m:
        return None
    circuits = rd.integer(m["circuits"], rd.at(path, "circuits"), minimum=1, maximum=MAX_LAYER_CIRCUITS)
    if pattern is not None and circuits > 1 and math.gcd(pattern, circuits) != 1:
        raise rd.error(rd.at(path, "pattern"), f"shares a factor with circuits: {circuits}, so some slots would be "
                       f"wound twice and others never (winder patterns lists the skips that close)", pattern)
    return circuits


def _parse_layer(rd: Reader, value: Any, path: str, friction: float, vessel: bool) -> LayerConfig:
    layer = _parse_layer_kind(rd, value, path, friction, vessel)
    if isinstance(value, dict) and "tension" in value:
        own = parse_tension(rd, value["tension"], rd.at(path, "tension"), job=False)
        layer = dataclasses.replace(layer, tension=own)
    return layer


def _parse_layer_kind(rd: Reader, value: Any, path: str, friction: float, vessel: bool) -> LayerConfig:
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
        slip, radius = _parse_slip(rd, m, path, friction, vessel)
        step_back = 0.0
        if "step_back" in m:
            key = rd.at(path, "step_back")
            step_back = rd.number(m["step_back"], key)
            if step_back < 0.0:
                raise rd.error(key, "must be >= 0 (mm toward the equator from the previous helical layer's "
                               "turnaround)", m["step_back"])
            if not vessel:
                raise rd.error(key, "applies to vessels only (the fiber turns around on the domes)", m["step_back"])
            if slip != SLIP_AUTO or radius is not None:
                raise rd.error(key, "needs slip: auto (friction moves the turnaround; a geodesic turns where "
                               "its angle leads) and no turnaround_radius", m["step_back"])
        circuits = _parse_circuits(rd, m, path, pattern)
        return LayerConfig(LayerType.HELICAL, angle, pattern, 1, slip, radius, circuits=circuits,
                           step_back=step_back)

    angle_deg = None
    if "angle" in m:
        angle_deg = rd.number(m["angle"], angle_path)
        if not MIN_HOOP_ANGLE <= angle_deg < 90.0:
            raise rd.error(angle_path, f"must be in [{MIN_HOOP_ANGLE:g}, 90) degrees for a hoop layer "
                           "(leave it out to derive it from the band width; lower angles are a helical "
                           "layer)", m["angle"])
    passes = rd.integer(m.get("passes", 1), rd.at(path, "passes"), minimum=1)
    taper = 0.0
    if "taper" in m:
        taper = rd.number(m["taper"], rd.at(path, "taper"))
        if taper < 0.0:
            raise rd.error(rd.at(path, "taper"), "must be >= 0 (mm over which the hoop layer's thickness runs "
                           "out at each end)", m["taper"])
    return LayerConfig(LayerType.HOOP, angle_deg, None, passes, taper=taper)
