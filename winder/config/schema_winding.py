"""The `winding:` section of the job file's JSON Schema (winder.config.schema): the band, its material,
the layers, the fiber tension and the accuracy, each key as winder.config.winding, .material and .tension
read it.

Examples
--------
>>> w = winding_schema()
>>> w["required"]
['band_width', 'layers']
>>> w["properties"]["angle_tolerance"]["description"]
"How far closing a vessel layer's pattern may move its angle from the one asked (beyond it: another circuit \
count, a friction-held closure at the angle, or a refusal listing the choices). deg, in [0, 90]. Default 0.5."
"""

from __future__ import annotations

from winder.config.analysis import MAX_MODULUS
from winder.config.material import MAX_DENSITY, MAX_PRICE, MAX_TOWS
from winder.config.reader import MAX_SIZE
from winder.config.schema_kit import Schema, closed, length, number, positive, tagged
from winder.config.tension import MAX_MODULUS as MAX_WALL_MODULUS
from winder.config.tension import MAX_TENSION, UNIFORM_PRESTRESS
from winder.config.winding import (DEFAULT_ANGLE_TOLERANCE, DEFAULT_FRICTION, DEFAULT_POINTS, MAX_LAYER_CIRCUITS,
                                   MAX_POINTS, MIN_COVERAGE, MIN_HOOP_ANGLE)

__all__ = ["winding_schema"]


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
        "fiber_price_per_kg": number("The fiber's price per kg, for the traveller's and the summary's material "
                                     "costs", "your currency per kg", lo=0, hi=MAX_PRICE),
        "resin_price_per_kg": number("The resin's price per kg, for the material costs", "your currency per kg",
                                     lo=0, hi=MAX_PRICE),
    }
    return closed("The band's material: fiber_tex with tows, fiber_density and fiber_volume_fraction, or "
                  "ply_thickness; ply properties for the structural analysis; prices for the costs.", keys,
                  oneOf=[{"required": ["fiber_tex"]}, {"required": ["ply_thickness"]}],
                  dependentRequired={"fiber_tex": ["tows", "fiber_density", "fiber_volume_fraction"],
                                     "tows": ["fiber_tex"]})


def _newtons(what: str) -> Schema:
    return number(what, "N per band", lo=0, lo_open=True, hi=MAX_TENSION)


def _tension(job: bool) -> Schema:
    """`tension:` of the winding (job: the uniform-prestress schedule) or of a layer (its own: a ramp over its
    passes; the job's: a ramp over each layer's passes too), as winder.config.tension reads them."""
    every = _newtons("The tension of every pass")
    ramp = closed("Linear over the layer's passes.", {"start": _newtons("At the layer's first pass"),
                                                      "end": _newtons("At its last pass")}, ("start", "end"))
    if not job:
        return {"description": "This layer's own fiber tension, replacing winding.tension: a number (N per band), "
                "or {start, end} linear over its passes. Every layer has a tension or none has.",
                "anyOf": [every, ramp]}
    schedule = closed("The uniform-prestress schedule of a thick wall (docs/math/16-winding-tension.md): each "
                      "layer's tension computed so that, once the whole wall is wound, every layer keeps the "
                      "residual.", {
                          "schedule": {"const": UNIFORM_PRESTRESS, "description": "The schedule's name."},
                          "residual": _newtons("The tension every layer keeps once the wall is wound"),
                          "max": _newtons("The most the tensioner (or the fiber) takes, at least the residual; a "
                                          "layer that would need more is refused"),
                          "radial_modulus": positive("The wet wall's through-thickness stiffness (default: the "
                                                     "ply's E2)", "MPa", MAX_WALL_MODULUS),
                          "mandrel_modulus": positive("The mandrel's radial stiffness (default: rigid)", "MPa",
                                                      MAX_WALL_MODULUS)}, ("schedule", "residual"))
    return {"description": "The fiber tension the program sets, N per band (docs/guide/tension.md): a number for "
            "every pass, {start, end} linear over each layer's passes, or the uniform-prestress schedule; a layer may "
            "give its own. Default: none programmed.",
            "anyOf": [every, ramp, schedule]}


def _coverage(default: str) -> Schema:
    return number(f"The covered fraction the layer proves before anything is written ({default})",
                  lo=0, lo_open=True, hi=1)


def _turnaround() -> Schema:
    ends = closed("Each dome's own; one left out turns at its own opening plus half a band.", {
        "start": length("The first dome's (at t = 0) turnaround radius"),
        "end": length("The end dome's (at t = T) turnaround radius")}, minProperties=1)
    return {"description": "Vessels: turn around on the domes at this radius (mm; lambda solved for on each): a "
            "number for both domes, or {start, end}.",
            "anyOf": [length("Both domes' turnaround radius"), ends]}


def _layer() -> Schema:
    common = {"material": _material() | {"description": "This layer's own material (default: winding.material)."},
              "min_coverage": _coverage("default: winding.min_coverage"), "tension": _tension(job=False)}
    helical = {
        "angle": number("Winding angle from the meridian (0 along the axis, 90 a hoop)", "deg", lo=0, hi=90,
                        lo_open=True, hi_open=True),
        "pattern": {"anyOf": [{"const": "auto"}, {"type": "integer", "minimum": 1}], "default": "auto",
                    "description": "The skip k (circuit advance 2 pi k / circuits, k coprime with circuits), or "
                    "auto: the planner's choice. Default auto."},
        "slip": {"anyOf": [{"const": "auto"}, {"type": "number", "minimum": 0, "maximum": 1}], "default": 0,
                 "description": "lambda = k_g / k_n the passes may use, in [0, winding.friction]: 0 geodesic "
                 "(default), or auto: friction-held where geodesics cannot cover or turn."},
        "turnaround_radius": _turnaround(),
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


def winding_schema() -> Schema:
    """The schema of `winding:` (the job schema makes it nullable)."""
    keys = {
        "band_width": length("Width of the fiber band as laid"),
        "layers": {"type": "array", "minItems": 1, "items": _layer(), "description": "The layers, at least one."},
        "region": _start_end("Open mandrels: the axial stretch wound, 0 <= start < end <= T (mm); default the "
                             "whole mandrel.", "mm", ("start", "end")),
        "points": number("Points per pass (the accuracy of each solve)", integer=True, lo=3, hi=MAX_POINTS,
                         default=DEFAULT_POINTS),
        "tolerance": length("Instead of points: refine each pass until its estimated length error is below this"),
        "dwell": _start_end("Open mandrels: the least mandrel turn (deg) while the carriage waits at each end; "
                            "the planner may dwell longer to close the pattern.", "deg", ()),
        "friction": number("Fiber-mandrel friction coefficient mu, the slip limit |k_g / k_n| <= mu", lo=0, hi=1,
                           default=DEFAULT_FRICTION),
        "material": _material(),
        "bridging_tolerance": number("Largest lift-off of a fiber over a concave stretch (default: one ply)", "mm",
                                     lo=0),
        "min_coverage": _coverage(f"default {MIN_COVERAGE:g}; a layer may ask its own"),
        "tension": _tension(job=True),
        "angle_tolerance": number("How far closing a vessel layer's pattern may move its angle from the one asked "
                                  "(beyond it: another circuit count, a friction-held closure at the angle, or a "
                                  "refusal listing the choices)", "deg", lo=0, hi=90,
                                  default=DEFAULT_ANGLE_TOLERANCE),
    }
    return closed("The winding plan: band, layers, accuracy, friction, material, tension.", keys,
                  ("band_width", "layers"), **{"not": {"required": ["points", "tolerance"]}})
