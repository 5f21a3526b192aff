"""The job file's JSON Schema (draft 2020-12), printed by `winder schema` for YAML editors.

Every key the readers of winder.config accept, with its type, unit, range and default in its
`description`, and unknown keys refused (`additionalProperties: false`). The readers stay the
authority (they also check what a schema cannot say: a region inside the mandrel, a polar opening
below the radius); tests/config/test_schema.py holds the two together, key by key, so that a key
added to a reader without its line here fails a test.

Examples
--------
>>> s = job_schema()
>>> s["$schema"]
'https://json-schema.org/draft/2020-12/schema'
>>> sorted(s["properties"])
['analysis', 'machine', 'mandrel', 'name', 'winding']
>>> s["properties"]["winding"]["additionalProperties"]
False
"""

from __future__ import annotations

from winder.config.analysis import (ENDS, GAUGES, MAX_AXIAL_FORCE, MAX_MODULUS, MAX_PRESSURE, MAX_STRESS_RATIO,
                                    MAX_TORQUE)
from winder.config.arms import ARMS
from winder.config.dialects import REGISTRY as DIALECTS
from winder.config.files import MAX_NAME_LENGTH
from winder.config.machine import (AXIS_LETTERS, DEFAULT_CHORD_TOLERANCE, DEFAULT_DYNAMICS, DEFAULT_EYE_CLEARANCE,
                                   DEFAULT_FEED, MACHINE_ROLES, MAX_EYE_CLEARANCE, WRITTEN_RESOLUTION, MachineAxes)
from winder.config.material import MAX_DENSITY, MAX_TOWS
from winder.config.reader import MAX_SIZE
from winder.config.robot import (DEFAULT_AXES, DEFAULT_JOINT_STEP, DEFAULT_SINGULARITY_MARGIN, MAX_CELL_SIZE,
                                 POSE_KEYS)
from winder.config.schema_kit import Schema, choice, closed, nullable, number, pair, positive, tagged
from winder.config.sections import MAX_EXPONENT
from winder.config.winding import (DEFAULT_FRICTION, DEFAULT_POINTS, MAX_LAYER_CIRCUITS, MAX_POINTS, MIN_COVERAGE,
                                   MIN_HOOP_ANGLE)

__all__ = ["SCHEMA_ID", "job_schema"]

SCHEMA_ID = "https://winder.invalid/schema/job.json"  # names the schema; nothing is fetched from it


def _length(what: str, default: float | None = None) -> Schema:
    return positive(what, "mm", MAX_SIZE, default)


def _points(what: str, width: int, names: str) -> Schema:
    return {"type": "array", "description": f"{what}: a list of [{names}] (mm), at least 2.", "minItems": 2,
            "items": {"type": "array", "items": {"type": "number"}, "minItems": width, "maxItems": width}}


def _table_points() -> Schema:
    t = number("Station along the axis, from 0, increasing", "mm", lo=0, hi=MAX_SIZE)
    r = positive("Radius there", "mm", MAX_SIZE)
    return {"type": "array", "description": "The profile's points: a list of [t, r] (mm), at least 2.",
            "minItems": 2, "items": {"type": "array", "prefixItems": [t, r], "minItems": 2, "maxItems": 2}}


# -- mandrel ---------------------------------------------------------------------------------------
def _arc_keys() -> dict[str, Schema]:
    return {"radius": _length("Bend radius of the axis"),
            "angle": number("Bend angle", "deg", lo=0, lo_open=True, hi=360),
            "toward": number("The side the axis bends toward, from e2 toward e3 (theta = toward is the inside of "
                             "the bend)", "deg", default=0)}


def _segment() -> Schema:
    line = closed("A straight piece", {"line": _length("Its length")}, ("line",))
    arc = closed("A circular bend", {"arc": closed("The bend", _arc_keys(), ("radius", "angle"))}, ("arc",))
    return {"type": "object", "description": "One piece of the guide: {line: L} or {arc: {radius, angle, "
            "toward}}.", "oneOf": [line, arc]}


def _axis() -> Schema:
    return tagged("The guide curve x(t); t is arc length along it, from 0", {
        "line": ("straight, along +z", {"length": _length("Axis length T")}, ("length",)),
        "arc": ("a circular bend", _arc_keys(), ("radius", "angle")),
        "path": ("a tangent-continuous chain of lines and arcs",
                 {"segments": {"type": "array", "minItems": 1, "items": _segment(),
                               "description": "The pieces, in order, at least one."}}, ("segments",)),
        "spline": ("a C2 interpolating curve through the points (moved so the first is the origin)",
                   {"points": _points("The points the axis passes through", 3, "x, y, z")}, ("points",)),
    })


def _dome() -> Schema:
    opening = _length("Radius (not diameter) of the polar opening, below the vessel radius")
    return tagged("One end dome of a vessel", {
        "hemisphere": ("a half sphere of the vessel radius", {"polar_opening": opening}, ("polar_opening",)),
        "ellipsoid": ("a half ellipsoid", {"polar_opening": opening,
                                           "depth": _length("Semi-axis along the vessel axis (the depth to the "
                                                            "closed pole)")}, ("polar_opening", "depth")),
        "isotensoid": ("the netting isotensoid of the radius and the opening", {"polar_opening": opening},
                       ("polar_opening",)),
    })


def _profile() -> Schema:
    return tagged("The radius along the axis, r(t)", {
        "constant": ("r = radius", {"radius": _length("Tube radius")}, ("radius",)),
        "cone": ("linear from t = 0 to t = T", {"start_radius": _length("Radius at t = 0"),
                                                "end_radius": _length("Radius at t = T")},
                 ("start_radius", "end_radius")),
        "table": ("smooth interpolation through [t, r] points, t from 0 increasing",
                  {"points": _table_points()}, ("points",)),
        "vessel": ("a cylinder between two domes; t = 0 at the first dome's polar opening",
                   {"radius": _length("Cylinder radius R"),
                    "cylinder_length": number("Length of the cylinder between the domes", "mm", lo=0, hi=MAX_SIZE),
                    "dome": _dome(), "end_dome": _dome() | {"description": "The dome at t = T (default: as dome)."}},
                   ("radius", "cylinder_length", "dome")),
    })


def _section() -> Schema:
    return tagged("The cross-section r(theta), scaled by profile(t) / profile(0) when a profile is given", {
        "circle": ("a circle of the profile's radius (default)", {}, ()),
        "ellipse": ("semi-axis a along e2, b along e3", {"a": _length("Semi-axis along e2"),
                                                         "b": _length("Semi-axis along e3")}, ("a", "b")),
        "rounded_rectangle": ("width along e2, height along e3, round corners",
                              {"width": _length("Width along e2"), "height": _length("Height along e3"),
                               "corner_radius": _length("Corner radius, <= min(width, height) / 2")},
                              ("width", "height", "corner_radius")),
        "superellipse": ("|x/a|^p + |y/b|^p = 1", {"a": _length("Semi-axis along e2"),
                                                   "b": _length("Semi-axis along e3"),
                                                   "exponent": number("The exponent p", lo=2, hi=MAX_EXPONENT)},
                         ("a", "b", "exponent")),
    })


def _mandrel() -> Schema:
    return closed("The mandrel: guide curve, radius along it, cross-section.",
                  {"axis": _axis(), "profile": _profile(), "section": _section()})


# -- winding ---------------------------------------------------------------------------------------
def _material() -> Schema:
    modulus = {key: positive(f"Ply {what}", "MPa", MAX_MODULUS) for key, what in (
        ("E1", "modulus along the fiber"), ("E2", "modulus across the fiber"), ("G12", "in-plane shear modulus"),
        ("Xt", "tensile strength along the fiber"), ("Xc", "compressive strength along the fiber (magnitude)"),
        ("Yt", "tensile strength across the fiber"), ("Yc", "compressive strength across the fiber (magnitude)"),
        ("S", "in-plane shear strength"))}
    keys = {
        "fiber_tex": positive("Linear density of one tow", "g/km (tex)", MAX_SIZE),
        "tows": number("Tows per band (with fiber_tex)", integer=True, lo=1, hi=MAX_TOWS),
        "fiber_density": positive("Fiber density", "g/cm^3", MAX_DENSITY),
        "resin_density": positive("Resin density (for the resin mass)", "g/cm^3", MAX_DENSITY),
        "fiber_volume_fraction": number("Fiber volume fraction V_f", lo=0, hi=1, lo_open=True, hi_open=True),
        "ply_thickness": positive("Instead of fiber_tex and tows: one band's thickness as laid, below the band "
                                  "width", "mm", MAX_SIZE),
        "name": {"type": "string", "description": "A material system of winder's table (its ply stiffness and "
                 "strengths; the numbers below override it)."},
        **modulus,
        "nu12": number("Ply major Poisson ratio", lo=0, hi=1, hi_open=True),
        "fiber_strength": positive("Fiber tensile strength, for netting analysis", "MPa", MAX_MODULUS),
        "strand_strength": positive("Impregnated strand strength (ASTM D4018), for netting analysis", "MPa",
                                    MAX_MODULUS),
    }
    return closed("The band's material: fiber_tex with tows, fiber_density and fiber_volume_fraction, or "
                  "ply_thickness; ply properties for the structural analysis.", keys,
                  oneOf=[{"required": ["fiber_tex"]}, {"required": ["ply_thickness"]}],
                  dependentRequired={"fiber_tex": ["tows", "fiber_density", "fiber_volume_fraction"],
                                     "tows": ["fiber_tex"]})


def _coverage(default: str) -> Schema:
    return number(f"The covered fraction the layer proves before anything is written ({default})",
                  lo=0, lo_open=True, hi=1)


def _layer() -> Schema:
    common = {"material": _material() | {"description": "This layer's own material (default: winding.material)."},
              "min_coverage": _coverage("default: winding.min_coverage")}
    helical = {
        "angle": number("Winding angle from the meridian (0 along the axis, 90 a hoop)", "deg", lo=0, hi=90,
                        lo_open=True, hi_open=True),
        "pattern": {"anyOf": [{"const": "auto"}, {"type": "integer", "minimum": 1}], "default": "auto",
                    "description": "The skip k (circuit advance 2 pi k / circuits, k coprime with circuits), or "
                    "auto: the planner's choice. Default auto."},
        "slip": {"anyOf": [{"const": "auto"}, {"type": "number", "minimum": 0, "maximum": 1}], "default": 0,
                 "description": "lambda = k_g / k_n the passes may use, in [0, winding.friction]: 0 geodesic "
                 "(default), or auto: friction-held where geodesics cannot cover or turn."},
        "turnaround_radius": _length("Vessels: turn around on the domes at this radius (lambda solved for)"),
        "circuits": number("Wind exactly this many circuits (winder patterns lists the choices)", integer=True,
                           lo=1, hi=MAX_LAYER_CIRCUITS),
        "step_back": number("Vessels, slip auto: move the turnaround this far toward the equator from the "
                            "previous helical layer's", "mm", lo=0, default=0),
    }
    hoop = {
        "angle": number("Hoop angle from the meridian (default: one band width of advance per turn)", "deg",
                        lo=MIN_HOOP_ANGLE, hi=90, hi_open=True),
        "passes": number("Traverses over the region, each one ply (2: there and back)", integer=True, lo=1,
                         default=1),
        "taper": number("Length over which the layer's thickness runs out at each end", "mm", lo=0, default=0),
    }
    return tagged("One layer, wound in list order", {
        "helical": ("circuits of a forward and a return pass laying +angle and -angle bands",
                    {**helical, **common}, ("angle",)),
        "hoop": ("near-circumferential turns over the cylindrical region", {**hoop, **common}, ()),
    })


def _start_end(what: str, unit: str, required: tuple[str, ...], lo: float = 0.0) -> Schema:
    return closed(what, {"start": number("At t = 0's end", unit, lo=lo), "end": number("At t = T's end", unit,
                                                                                       lo=lo)}, required)


def _winding() -> Schema:
    keys = {
        "band_width": _length("Width of the fiber band as laid"),
        "layers": {"type": "array", "minItems": 1, "items": _layer(), "description": "The layers, at least one."},
        "region": _start_end("Open mandrels: the axial stretch wound, 0 <= start < end <= T (mm); default the "
                             "whole mandrel.", "mm", ("start", "end")),
        "points": number("Points per pass (the accuracy of each solve)", integer=True, lo=3, hi=MAX_POINTS,
                         default=DEFAULT_POINTS),
        "tolerance": _length("Instead of points: refine each pass until its estimated length error is below this"),
        "dwell": _start_end("Open mandrels: the least mandrel turn (deg) while the carriage waits at each end; "
                            "the planner may dwell longer to close the pattern.", "deg", ()),
        "friction": number("Fiber-mandrel friction coefficient mu, the slip limit |k_g / k_n| <= mu", lo=0, hi=1,
                           default=DEFAULT_FRICTION),
        "material": _material(),
        "bridging_tolerance": number("Largest lift-off of a fiber over a concave stretch (default: one ply)", "mm",
                                     lo=0),
        "min_coverage": _coverage(f"default {MIN_COVERAGE:g}; a layer may ask its own"),
    }
    return closed("The winding plan: band, layers, accuracy, friction, material.", keys, ("band_width", "layers"),
                  **{"not": {"required": ["points", "tolerance"]}})


# -- machine ---------------------------------------------------------------------------------------
_ROLE_UNITS = {"carriage": ("mm", "mm/min", "mm/s^2"), "rotation": ("deg", "deg/min", "deg/s^2"),
               "cross_feed": ("mm", "mm/min", "mm/s^2"), "yaw": ("deg", "deg/min", "deg/s^2")}
_ROLE_MEANING = {"carriage": "carriage travel along the mandrel axis", "rotation": "mandrel turn (cumulative)",
                 "cross_feed": "radial distance of the payout eye from the axis", "yaw": "payout-eye yaw"}


def _pose(what: str) -> Schema:
    keys = {k: number(f"{'Position' if k in 'xyz' else 'Rotation'} {k}", "mm" if k in "xyz" else "deg",
                      lo=-(MAX_CELL_SIZE if k in "xyz" else 360.0), hi=MAX_CELL_SIZE if k in "xyz" else 360.0)
            for k in POSE_KEYS}
    return closed(f"{what} (R = Rz(rz) Ry(ry) Rx(rx); left-out values 0).", keys)


def _robot() -> Schema:
    cell = closed("A robot cell: the arm holds the mandrel and passes it through a fixed winding ring.", {
        "arm": choice("The arm (kinematics and joint limits with sources in winder's table)", list(ARMS)),
        "base": _pose("The arm's base in the cell"),
        "tool": _pose("The mandrel frame on the flange (default z 250)"),
        "positioner": closed("The winding ring.", {
            "axes": number("External axes: 1 the ring's turn, 2 and the eye's yaw, 3 and its radial slide",
                           integer=True, lo=1, hi=3, default=DEFAULT_AXES),
            "origin": _pose("The ring's centre and axis (its z) in the cell")}),
        "max_joint_step": number("Largest joint turn between consecutive poses", "deg", lo=0, lo_open=True, hi=180,
                                 default=DEFAULT_JOINT_STEP),
        "singularity_margin": number("Least distance of the wrist from its singularity", "deg", lo=0, hi=90,
                                     hi_open=True, default=DEFAULT_SINGULARITY_MARGIN)}, ("arm",))
    flag = {"type": "boolean", "description": "true: write eye poses for a robot instead of G-code axes "
            "(default: true exactly when the axis is bent)."}
    return {"description": "Robot mode: true / false, or a robot cell.", "anyOf": [flag, cell]}


def _machine() -> Schema:
    axes = closed("G-code letters of the axes, distinct.", {
        role: choice(f"Letter of the {_ROLE_MEANING[role]} ({_ROLE_UNITS[role][0]})", list(AXIS_LETTERS),
                     getattr(MachineAxes, role)) for role in MACHINE_ROLES})
    limits = closed("Travel limits, each [min, max] in the axis' unit; left out: unlimited.", {
        role: pair(f"Limits of the {_ROLE_MEANING[role]}", "min", "max", _ROLE_UNITS[role][0])
        for role in MACHINE_ROLES})
    dynamics = closed("Per axis top speed and acceleration.", {role: closed(f"The {_ROLE_MEANING[role]}.", {
        "speed": number("Top speed", _ROLE_UNITS[role][1], lo=WRITTEN_RESOLUTION, hi=MAX_SIZE,
                        default=DEFAULT_DYNAMICS[role][0]),
        "acceleration": positive("Acceleration", _ROLE_UNITS[role][2], MAX_SIZE, DEFAULT_DYNAMICS[role][1])})
        for role in MACHINE_ROLES})
    eye = closed("The payout-eye envelope: exactly one of radius or clearance; size its diameter.", {
        "radius": _length("The eye moves on a cylinder of this radius around the axis"),
        "clearance": positive("The eye keeps this far beyond the surface as wound", "mm", MAX_EYE_CLEARANCE,
                              DEFAULT_EYE_CLEARANCE),
        "size": number("The eye's diameter; its body keeps the clearance", "mm", lo=0, hi=MAX_EYE_CLEARANCE,
                       default=0)}, oneOf=[{"required": ["radius"]}, {"required": ["clearance"]}])
    return closed("The winder: axis letters, payout eye, feed, limits, dynamics, program dialect; every key has a "
                  "default.", {
                      "axes": axes, "eye": eye,
                      "feed": number("Feed rate F", "mm/min", lo=WRITTEN_RESOLUTION, hi=MAX_SIZE, default=DEFAULT_FEED),
                      "chord_tolerance": number("Largest deviation of the programmed moves from the exact eye path, "
                                                "below the eye clearance", "mm", lo=WRITTEN_RESOLUTION, hi=MAX_SIZE,
                                                default=DEFAULT_CHORD_TOLERANCE),
                      "limits": limits, "robot": _robot(),
                      "dialect": choice("How the program is written", list(DIALECTS)),
                      "dynamics": dynamics})


# -- analysis --------------------------------------------------------------------------------------
def _analysis() -> Schema:
    ratio = number("Required fiber stress ratio (fiber stress at the minimum burst over that at the working "
                   "pressure)", lo=1, hi=MAX_STRESS_RATIO)
    return closed("The load case and the targets of the structural analysis.", {
        "pressure": number("Internal (working) pressure", "MPa", lo=0, hi=MAX_PRESSURE, default=0),
        "axial_force": number("Axial force, tension +", "N", lo=-MAX_AXIAL_FORCE, hi=MAX_AXIAL_FORCE, default=0),
        "torque": number("Torque about the axis", "N mm", lo=-MAX_TORQUE, hi=MAX_TORQUE, default=0),
        "ends": choice("Whether the pressure's end thrust acts on the wall (vessels: always closed)", ENDS,
                       "closed"),
        "gauge": choice("Where the headline figures come from (default: cylinder on vessels, wound on open "
                        "mandrels)", GAUGES),
        "burst_pressure": positive("The least burst pressure the design must reach, above the working pressure",
                                   "MPa", MAX_PRESSURE),
        "stress_ratio": {"description": ratio["description"] + " One number, or one per fiber material name.",
                         "anyOf": [ratio, {"type": "object", "additionalProperties": ratio}]},
    })


def job_schema() -> Schema:
    """The JSON Schema of a job file, as `winder schema` prints it.

    Returns
    -------
    dict
        A draft 2020-12 schema: a mapping with `$schema`, `$id`, `title`, `type`, `properties`,
        `required` and `additionalProperties: false`, every key's unit and range in its description.

    Examples
    --------
    >>> schema = job_schema()
    >>> schema["required"]
    ['name', 'mandrel']
    >>> schema["properties"]["winding"]["properties"]["band_width"]["description"]
    'Width of the fiber band as laid. mm, in (0, 1e+06].'
    """
    name = {"type": "string", "pattern": r"^[A-Za-z0-9_-][A-Za-z0-9_.-]*$", "maxLength": MAX_NAME_LENGTH,
            "description": f"Names the output files: letters, digits, '_', '.', '-', not starting with '.', at most "
                           f"{MAX_NAME_LENGTH} characters."}
    return {"$schema": "https://json-schema.org/draft/2020-12/schema", "$id": SCHEMA_ID,
            "title": "winder job file",
            "description": "A filament-winding job: mandrel, winding plan, machine, load case. Lengths in mm, "
                           "angles in degrees.",
            "type": "object", "required": ["name", "mandrel"], "additionalProperties": False,
            "properties": {"name": name, "mandrel": _mandrel(), "winding": nullable(_winding()),
                           "machine": nullable(_machine()), "analysis": nullable(_analysis())}}
