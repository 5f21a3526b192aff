"""One layer of the `winding:` section (an entry of `winding.layers`): its record, its label in every
message ("layer 5 (helical 16 deg)", numbered from 1) and its parser; winder.config.winding reads the
list and the job-wide keys around it.
"""

from __future__ import annotations

import dataclasses
import math
from enum import Enum
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

from winder.config.material import MaterialConfig
from winder.config.tension import TensionConfig, parse_tension

# Hoop layers below this angle lay a visibly helical band; such a layer is a helical one.
MIN_HOOP_ANGLE = 70.0
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


_LAYER_KINDS = {
    "helical": (("angle",), ("pattern", "slip", "turnaround_radius", "material", "circuits", "step_back",
                             "min_coverage", "tension")),
    "hoop": ((), ("angle", "passes", "material", "taper", "min_coverage", "tension")),
}


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


def parse_layer(rd: Reader, value: Any, path: str, friction: float, vessel: bool) -> LayerConfig:
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
