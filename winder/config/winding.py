"""The `winding:` section of a job file: the layers and how accurately each pass is solved.

The parser receives a `winder.config.reader.Reader` (it carries the file name and formats every
message), plus the few facts about the mandrel it checks against; winder.config.job calls it.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

from winder.config.material import MaterialConfig, parse_materials
from winder.config.reader import LENGTH_SLACK
from winder.config.layers import (MAX_LAYER_CIRCUITS, MIN_HOOP_ANGLE, SLIP_AUTO, LayerConfig, LayerType,  # noqa: F401
                                  layer_key, layer_label, parse_layer)
from winder.config.tension import TensionConfig, check_tensions, parse_tension

DEFAULT_POINTS = 200
# A pass is solved in O(points); beyond this the result is no more accurate, only slower.
MAX_POINTS = 100_000
DEFAULT_FRICTION = 0.2
DEFAULT_ANGLE_TOLERANCE = 0.5  # deg: how far closing a pattern may move a layer's angle from the one asked
MIN_COVERAGE = 0.999  # winding.min_coverage's default: the covered fraction every layer proves


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
    layers = tuple(parse_layer(rd, item, layer_key(i, item), friction, vessel) for i, item in enumerate(items))
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
