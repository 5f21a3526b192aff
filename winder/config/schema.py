"""The job file's JSON Schema (draft 2020-12), printed by `winder schema` for YAML editors.

Every key the readers of winder.config accept, with its type, unit, range and default in its
`description`, and unknown keys refused (`additionalProperties: false`). The readers stay the
authority (they also check what a schema cannot say: a region inside the mandrel, a polar opening
below the radius); tests/config/test_schema.py holds the two together, key by key, so that a key
added to a reader without its line here fails a test. The `winding:` section is
winder.config.schema_winding's.

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

from winder.config.analysis import (ENDS, GAUGES, MAX_AXIAL_FORCE, MAX_PRESSURE, MAX_STRESS_RATIO,
                                    MAX_TORQUE)
from winder.config.arms import ARMS
from winder.config.axes import MAX_SEGMENTS, MAX_SPLINE_POINTS
from winder.config.contours import CONTOUR_TOLERANCE, MAX_CONTOUR_TOLERANCE
from winder.config.contours import MAX_POINTS as MAX_CONTOUR_POINTS
from winder.config.contours import MIN_POINTS as MIN_CONTOUR_POINTS
from winder.config.dialects import REGISTRY as DIALECTS
from winder.config.files import MAX_NAME_LENGTH
from winder.config.machine import (AXIS_LETTERS, DEFAULT_CHORD_TOLERANCE, DEFAULT_DYNAMICS, DEFAULT_EYE_CLEARANCE,
                                   DEFAULT_FEED, MACHINE_ROLES, MAX_EYE_CLEARANCE, WRITTEN_RESOLUTION, MachineAxes)
from winder.config.reader import MAX_SIZE
from winder.config.robot import (MIN_PROGRAM_LIMIT, DEFAULT_AXES, DEFAULT_JOINT_STEP, DEFAULT_RING_DEPTH, DEFAULT_RING_WIDTH,
                                 DEFAULT_SINGULARITY_MARGIN, MAX_CELL_SIZE, POSE_KEYS)
from winder.config.schema_kit import Schema, choice, closed, length, nullable, number, pair, positive, tagged
from winder.config.schema_winding import winding_schema
from winder.config.sections import MAX_EXPONENT

__all__ = ["SCHEMA_ID", "job_schema"]

SCHEMA_ID = "https://winder.invalid/schema/job.json"  # names the schema; nothing is fetched from it


def _points(what: str, width: int, names: str, most: int) -> Schema:
    return {"type": "array", "description": f"{what}: a list of [{names}] (mm), 2 to {most}.", "minItems": 2,
            "maxItems": most,
            "items": {"type": "array", "items": {"type": "number"}, "minItems": width, "maxItems": width}}


def _table_points() -> Schema:
    t = number("Station along the axis, from 0, increasing", "mm", lo=0, hi=MAX_SIZE)
    r = positive("Radius there", "mm", MAX_SIZE)
    return {"type": "array", "description": "The profile's points: a list of [t, r] (mm), at least 2.",
            "minItems": 2, "items": {"type": "array", "prefixItems": [t, r], "minItems": 2, "maxItems": 2}}


# -- mandrel ---------------------------------------------------------------------------------------
def _arc_keys() -> dict[str, Schema]:
    return {"radius": length("Bend radius of the axis"),
            "angle": number("Bend angle", "deg", lo=0, lo_open=True, hi=360),
            "toward": number("The side the axis bends toward, from e2 toward e3 (theta = toward is the inside of "
                             "the bend)", "deg", default=0)}


def _segment() -> Schema:
    line = closed("A straight piece", {"line": length("Its length")}, ("line",))
    arc = closed("A circular bend", {"arc": closed("The bend", _arc_keys(), ("radius", "angle"))}, ("arc",))
    return {"type": "object", "description": "One piece of the guide: {line: L} or {arc: {radius, angle, "
            "toward}}.", "oneOf": [line, arc]}


def _axis() -> Schema:
    return tagged("The guide curve x(t); t is arc length along it, from 0", {
        "line": ("straight, along +z", {"length": length("Axis length T")}, ("length",)),
        "arc": ("a circular bend", _arc_keys(), ("radius", "angle")),
        "path": ("a tangent-continuous chain of lines and arcs",
                 {"segments": {"type": "array", "minItems": 1, "maxItems": MAX_SEGMENTS, "items": _segment(),
                               "description": f"The pieces, in order, 1 to {MAX_SEGMENTS}."}}, ("segments",)),
        "spline": ("a C2 interpolating curve through the points (moved so the first is the origin)",
                   {"points": _points("The points the axis passes through", 3, "x, y, z", MAX_SPLINE_POINTS)},
                   ("points",)),
    })


# A closed end (polar_opening 0) turns around the mandrel's shaft: shaft_radius with it, and only with it.
_CLOSED_END = {
    "if": {"properties": {"polar_opening": {"const": 0, "description": "A closed end."}},
           "required": ["polar_opening"]},
    "then": {"required": ["shaft_radius"]},
    "dependentSchemas": {"shaft_radius": {"properties": {"polar_opening": {
        "const": 0, "description": "shaft_radius is a closed end's only."}}, "required": ["polar_opening"]}},
}
_DXF = r"\.[dD][xX][fF]$"


def _contour() -> dict[str, Schema]:
    z = number("z: distance from the junction toward the pole, increasing", "mm")
    r = number("r: radius there, never rising toward the pole", "mm", lo=0)
    return {
        "points": {"type": "array", "minItems": MIN_CONTOUR_POINTS, "maxItems": MAX_CONTOUR_POINTS,
                   "description": f"The meridian's points from the junction with the cylinder (z = 0, r = the "
                   f"vessel radius) toward the pole: a list of [z, r] (mm), {MIN_CONTOUR_POINTS} to "
                   f"{MAX_CONTOUR_POINTS}; or file.",
                   "items": {"type": "array", "prefixItems": [z, r], "minItems": 2, "maxItems": 2}},
        "file": {"type": "string", "pattern": r"\.([cC][sS][vV]|[dD][xX][fF])$",
                 "description": "Instead of points: a .csv of z,r (header z,r) or a .dxf drawing of the meridian "
                 "(LINE, ARC, LWPOLYLINE, SPLINE, ELLIPSE chained end to end, x = z, y = r), relative to the "
                 "config's folder."},
        "layer": {"type": "string", "description": "With a .dxf file: the drawing's layer holding the meridian "
                  "(default: the whole model space)."},
        "tolerance": positive("Largest distance of the smoothed meridian from the points", "mm",
                              MAX_CONTOUR_TOLERANCE, CONTOUR_TOLERANCE),
    }


def _dome() -> Schema:
    what = "Radius (not diameter) of the polar opening, below the vessel radius; 0 a closed end (with shaft_radius)"
    opening = number(what, "mm", lo=0, hi=MAX_SIZE, hi_open=True)
    closed_end = {"shaft_radius": length("Closed ends only (polar_opening 0): radius of the mandrel shaft the "
                                         "fibers turn around, below the vessel radius")}
    out = tagged("One end dome of a vessel", {
        "hemisphere": ("a half sphere of the vessel radius", {"polar_opening": opening, **closed_end},
                       ("polar_opening",)),
        "ellipsoid": ("a half ellipsoid", {"polar_opening": opening,
                                           "depth": length("Semi-axis along the vessel axis (the depth to the "
                                                           "closed pole)"), **closed_end},
                      ("polar_opening", "depth")),
        "isotensoid": ("the netting isotensoid of the radius and the opening", {"polar_opening": opening,
                                                                                **closed_end}, ("polar_opening",)),
        "torispherical": ("a torispherical (ASME-style) head: a crown sphere meeting the cylinder through a knuckle "
                          "torus", {"crown_radius": length("Crown radius, at least the vessel radius (ASME heads: "
                                                           "about the diameter)"),
                                    "knuckle_radius": length("Knuckle radius, below the vessel radius"),
                                    "polar_opening": opening, **closed_end},
                          ("crown_radius", "knuckle_radius", "polar_opening")),
        "contour": ("a liner's meridian from a drawing (points, or a CSV or DXF file), smoothed to C2 within the "
                    "tolerance", {**_contour(), "polar_opening": number(
                        "Radius of the polar opening the contour must reach (default: its last point's); 0 a closed "
                        "end (with shaft_radius)", "mm", lo=0, hi=MAX_SIZE, hi_open=True), **closed_end}, ()),
    })
    for variant in out["oneOf"]:
        variant.update(_CLOSED_END)
        if variant["properties"]["type"]["const"] == "contour":
            variant["oneOf"] = [{"required": ["points"]}, {"required": ["file"]}]
            variant["dependentSchemas"] = {**_CLOSED_END["dependentSchemas"], "layer": {
                "required": ["file"], "properties": {"file": {"pattern": _DXF, "description": "A .dxf drawing."}}}}
    return out


def _profile() -> Schema:
    return tagged("The radius along the axis, r(t)", {
        "constant": ("r = radius", {"radius": length("Tube radius")}, ("radius",)),
        "cone": ("linear from t = 0 to t = T", {"start_radius": length("Radius at t = 0"),
                                                "end_radius": length("Radius at t = T")},
                 ("start_radius", "end_radius")),
        "table": ("smooth interpolation through [t, r] points, t from 0 increasing",
                  {"points": _table_points()}, ("points",)),
        "vessel": ("a cylinder between two domes; t = 0 at the first dome's polar opening",
                   {"radius": length("Cylinder radius R"),
                    "cylinder_length": number("Length of the cylinder between the domes", "mm", lo=0, hi=MAX_SIZE),
                    "dome": _dome(), "end_dome": _dome() | {"description": "The dome at t = T (default: as dome)."}},
                   ("radius", "cylinder_length", "dome")),
    })


def _section() -> Schema:
    return tagged("The cross-section r(theta), scaled by profile(t) / profile(0) when a profile is given", {
        "circle": ("a circle of the profile's radius (default)", {}, ()),
        "ellipse": ("semi-axis a along e2, b along e3", {"a": length("Semi-axis along e2"),
                                                         "b": length("Semi-axis along e3")}, ("a", "b")),
        "rounded_rectangle": ("width along e2, height along e3, round corners",
                              {"width": length("Width along e2"), "height": length("Height along e3"),
                               "corner_radius": length("Corner radius, <= min(width, height) / 2")},
                              ("width", "height", "corner_radius")),
        "superellipse": ("|x/a|^p + |y/b|^p = 1", {"a": length("Semi-axis along e2"),
                                                   "b": length("Semi-axis along e3"),
                                                   "exponent": number("The exponent p", lo=2, hi=MAX_EXPONENT)},
                         ("a", "b", "exponent")),
    })


def _mandrel() -> Schema:
    return closed("The mandrel: guide curve, radius along it, cross-section.",
                  {"axis": _axis(), "profile": _profile(), "section": _section()})


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
            "origin": _pose("The ring's centre and axis (its z) in the cell"),
            "width": positive("The ring's body along its axis, which no link may touch", "mm", MAX_CELL_SIZE,
                              DEFAULT_RING_WIDTH),
            "depth": positive("The ring's body outward from its inner face", "mm", MAX_CELL_SIZE,
                              DEFAULT_RING_DEPTH)}),
        "max_joint_step": number("Largest joint turn between consecutive poses", "deg", lo=0, lo_open=True, hi=180,
                                 default=DEFAULT_JOINT_STEP),
        "singularity_margin": number("Least distance of the wrist from its singularity", "deg", lo=0, hi=90,
                                     hi_open=True, default=DEFAULT_SINGULARITY_MARGIN),
        "program_limit": number("The most the controller holds of one program; past it the program is written "
                                "as a main program calling one subprogram per layer (default: the arm's "
                                "language's limit, docs/math/10-robot-cell.md 10.10)", "bytes", integer=True,
                                lo=MIN_PROGRAM_LIMIT)}, ("arm",))
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
        "radius": length("The eye moves on a cylinder of this radius around the axis"),
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
                      "post": {"type": "string", "pattern": r"\S", "description": "A post file describing the "
                               "controller (docs/guide/controllers.md), relative to the config's folder; it extends "
                               "a built-in dialect, which machine.dialect, if given too, must be."},
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
            "properties": {"name": name, "mandrel": _mandrel(), "winding": nullable(winding_schema()),
                           "machine": nullable(_machine()), "analysis": nullable(_analysis())}}
