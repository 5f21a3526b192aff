"""Realistic parts nobody tuned for: seeded job configs across the classes and ranges shops wind.

Each part is drawn from its seed alone (numpy's PCG64), so a failing part is named by (class, seed)
and comes back the same. The classes and ranges (issue 41, "Build" 2):

- vessel: radius 40 to 400, length / diameter 0.5 to 6, hemisphere, ellipsoid (depth 0.5 to 1 R) or
  isotensoid domes, torispherical heads, ellipsoids given as a drawing's points (contour), end domes
  closed round a shaft, openings 5 to 40 % of the radius (unequal ends half the time), 2 to 30 layers of
  helicals at 8 to 70 deg (geodesic, a number of slip or `auto`) and hoops, bands 3 to 40 mm;
- pipe: radius 10 to 600, 0.3 to 12 m, helicals at 15 to 89 deg, 1 to 12 layers;
- cone: tapers 1:5 to 1:100 up to 12 m (poles and reducers);
- tube: non-circular sections: ellipses of aspect 1.2 to 4, rounded rectangles of aspect 1 to 4 with
  corners 5 to 30 % of the short side, superellipses;
- elbow: 30 to 90 deg, bend radius 1 to 5 D, DN50 to DN600, straight legs;
- duct: a spline axis through a few points, bent gently against its radius;
and hoop layers on every class.

A shop picks what winds: a helical angle a vessel's geodesic can turn at (past the opening by half a
band) and a band that keeps the circuits to what a job of its class winds. The `size` caps the work of
a part: SUITE for the test suite (about 40 parts in a few minutes), NIGHTLY for the nightly run and
the bench (the ranges as shops wind them, within a few seconds of CPU each).

Outcomes (outcome()): `planned` (exit 0, every invariant proved), `physical` (a refusal naming what is
physically in the way and the key to change), `numerical` (no convergence, an integral that did not
settle, an iteration limit, an internal error: a defect of winder), `invariant` (a plan or program that
broke an invariant it proves before it writes: a defect too), `other` (a refusal of none of these
kinds: a defect until its words say what is in the way).
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np

CLASSES = ("vessel", "pipe", "cone", "tube", "elbow", "duct")


@dataclasses.dataclass(frozen=True)
class Size:
    """The work a generated part may take: most layers, most circuits a helical layer winds (the band
    is widened to keep to it), the longest mandrel (mm), points a pass, largest radius (mm)."""

    layers: int
    circuits: int
    length: float
    points: int
    radius: float
    bent: float  # the largest tube radius of a bent axis (elbows, ducts: their programs are robot poses)


SUITE = Size(layers=2, circuits=16, length=1000.0, points=30, radius=150.0, bent=35.0)
NIGHTLY = Size(layers=12, circuits=80, length=12000.0, points=50, radius=600.0, bent=300.0)

ROUND_POINTS = 6  # points a round of the mandrel a pass takes at least (winder asks for 3)
MOST_POINTS = 4000  # a pass's points, at most: past it the layer is refused for its points (physical enough)
# A job refused by the invariants it proves before it writes (winder.machine.invariants): the plan or
# the program of winder did not keep its promise, a defect like a numerical refusal.
INVARIANT = re.compile(r"does not lay the planned path|of the part as wound so far|is written .* outside machine\.limits|"
                       r"of its surface \(the widest gap")
NUMERICAL = re.compile(r"converge|did not settle|iteration|internal error|not finite|nan\b|singular", re.I)
PHYSICAL = re.compile(r"friction|bridg|lift-off|slip|clear|reach|fold|thick|band|angle|cover|limit|opening|"
                      r"bend|radius|turn", re.I)
KEY = re.compile(r"\b(winding|machine|mandrel)\.[a-z_]+|\b(angle|band_width|friction|slip|turnaround_radius|"
                 r"min_coverage|clearance|passes|points|circuits|pattern|polar_opening|step_back|taper)\b")


def part(seed: int, cls: str, size: Size = SUITE) -> dict:
    """The job config (a dict, as YAML reads it) of the part of class `cls` drawn from `seed`."""
    rng = np.random.default_rng([CLASSES.index(cls), seed])
    body = {"vessel": _vessel, "pipe": _pipe, "cone": _cone, "tube": _tube, "elbow": _elbow, "duct": _duct}[cls]
    config = body(rng, size)
    config["name"] = f"{cls}_{seed}"
    return config


def parts(count: int, seed: int = 0, size: Size = SUITE) -> list[tuple[str, int, dict]]:
    """count parts (class, seed, config), the classes in turn, seeds from `seed` on."""
    out = []
    for k in range(count):
        cls = CLASSES[k % len(CLASSES)]
        s = seed + k // len(CLASSES)
        out.append((cls, s, part(s, cls, size)))
    return out


def outcome(ok: bool, message: str) -> str:
    """planned | physical | numerical | invariant | other (module docstring) of a job's result."""
    if ok:
        return "planned"
    if NUMERICAL.search(message):
        return "numerical"
    if INVARIANT.search(message):
        return "invariant"
    return "physical" if PHYSICAL.search(message) and KEY.search(message) else "other"


# -- the classes -----------------------------------------------------------------------------------
def _log_uniform(rng, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _round(x: float, step: float = 0.5) -> float:
    return round(float(round(x / step) * step), 6)


def _band(rng, perimeter: float, angle: float, size: Size, lo: float = 3.0, hi: float = 40.0) -> float:
    """A band of lo to hi mm, widened so that a helical at `angle` winds at most size.circuits circuits."""
    least = perimeter * math.cos(math.radians(angle)) / size.circuits
    return _round(max(_log_uniform(rng, lo, hi), least), 0.5)


def _machine(rng, robot: bool = False) -> dict:
    machine: dict = {"eye": {"clearance": _round(rng.uniform(10.0, 40.0), 1.0)}}
    if robot:
        machine["robot"] = True
    return machine


def _hoop(rng) -> dict:
    return {"type": "hoop", "passes": int(rng.integers(1, 3))}


def _helical(rng, lo: float, hi: float, friction: float, vessel: bool = False) -> dict:
    layer: dict = {"type": "helical", "angle": _round(rng.uniform(lo, hi), 0.5)}
    kind = rng.uniform()
    if kind < 0.4:
        layer["slip"] = "auto"
    elif kind < 0.55 and vessel:
        layer["slip"] = _round(rng.uniform(0.02, 0.6 * friction), 0.01)
    return layer


def _layers(rng, size: Size, lo: float, hi: float, friction: float, least: int = 1, hoops: float = 0.35,
            vessel: bool = False) -> list[dict]:
    count = int(rng.integers(least, max(least, size.layers) + 1))
    out = [_hoop(rng) if rng.uniform() < hoops else _helical(rng, lo, hi, friction, vessel) for _ in range(count)]
    if all(layer["type"] == "hoop" for layer in out):  # a part winds at least one helical
        out[0] = _helical(rng, lo, hi, friction, vessel)
    return out


def _open_winding(rng, size: Size, length: float, perimeter: float, lo: float, hi: float) -> dict:
    friction = _round(rng.uniform(0.15, 0.3), 0.01)
    layers = _layers(rng, size, lo, hi, friction)
    least_angle = min((layer["angle"] for layer in layers if layer["type"] == "helical"), default=45.0)
    band = min(_band(rng, perimeter, least_angle, size), 0.2 * length)
    trim = _round(min(rng.uniform(0.0, 0.05) * length, 200.0), 1.0)
    # A pass needs a few points a round of the mandrel: the steepest helical's rounds over the length.
    steep = max((layer["angle"] for layer in layers if layer["type"] == "helical"), default=45.0)
    rounds = length * math.tan(math.radians(steep)) / perimeter
    points = int(min(max(size.points, math.ceil(ROUND_POINTS * rounds) + 10), MOST_POINTS))
    winding = {"band_width": band, "friction": friction, "points": points, "layers": layers}
    if trim >= 1.0:
        winding["region"] = {"start": trim, "end": _round(length - trim, 1.0)}
    if rng.uniform() < 0.5:
        winding["material"] = {"ply_thickness": _round(rng.uniform(0.15, 0.6), 0.05)}
    return winding


def _vessel(rng, size: Size) -> dict:
    radius = _round(_log_uniform(rng, 40.0, min(400.0, size.radius)), 1.0)
    kind = rng.choice(["hemisphere", "ellipsoid", "isotensoid"])
    opening = _round(rng.uniform(0.05, 0.4) * radius, 0.5)
    dome: dict = {"type": str(kind), "polar_opening": opening}
    if kind == "ellipsoid":
        dome["depth"] = _round(rng.uniform(0.5, 1.0) * radius, 0.5)
    end = dict(dome)
    if rng.uniform() < 0.5:
        end["polar_opening"] = _round(min(rng.uniform(0.05, 0.4) * radius, 1.6 * opening), 0.5)
    depth = dome.get("depth", radius)
    total = rng.uniform(0.5, 6.0) * 2.0 * radius
    cylinder = _round(max(total - 2.0 * depth, 0.25 * radius), 1.0)
    cylinder = min(cylinder, size.length)
    friction = _round(rng.uniform(0.15, 0.3), 0.01)
    big = max(opening, end["polar_opening"])
    band = _band(rng, 2.0 * math.pi * radius, 10.0, size)
    band = min(band, 0.5 * big + 5.0)  # a band turns round a boss: not much wider than its opening
    # The geodesic turns where r sin(alpha) = R sin(alpha_eq): past the larger opening by half a band.
    lo = max(8.0, math.degrees(math.asin(min(0.95, (big + 0.5 * band) / radius))) + 1.0)
    layers = _layers(rng, dataclasses.replace(size, layers=min(30, 2 * size.layers)), lo, max(lo + 2.0, 70.0),
                     friction, least=2, vessel=True)
    winding = {"band_width": band, "friction": friction, "points": size.points, "layers": layers}
    if rng.uniform() < 0.7:
        winding["material"] = {"ply_thickness": _round(rng.uniform(0.1, 0.5), 0.05)}
    machine = _machine(rng)
    dome, end = _as_built(rng, radius, dome), _as_built(rng, radius, end, closable=True)
    profile = {"type": "vessel", "radius": radius, "cylinder_length": cylinder, "dome": dome, "end_dome": end}
    return {"mandrel": {"profile": profile}, "winding": winding, "machine": machine}


def _as_built(rng, radius: float, dome: dict, closable: bool = False) -> dict:
    """A dome as liners come (drawn after the part's other draws, which they leave as they were): a
    hemisphere a torispherical head a third of the time (crown 0.8 to 1 D, knuckle 6 to 15 % of D: its
    depth less, its openings the same), an ellipsoid a drawing's points a third of the time (the
    meridian sampled, z from the cylinder to the opening), and an end dome closed round a shaft of the
    opening's radius a quarter of the time (the helicals turn where they did)."""
    out = dict(dome)
    draw = rng.uniform(size=3)
    if out["type"] == "hemisphere" and draw[0] < 1.0 / 3.0:
        out = {"type": "torispherical", "crown_radius": _round((0.8 + 0.2 * draw[1]) * 2.0 * radius, 0.5),
               "knuckle_radius": _round((0.06 + 0.09 * draw[2]) * 2.0 * radius, 0.5),
               "polar_opening": out["polar_opening"]}
    elif out["type"] == "ellipsoid" and draw[0] < 1.0 / 3.0:
        depth, opening = out["depth"], out["polar_opening"]
        top = math.acos(opening / radius)  # the meridian's angle where it reaches the opening
        angle = np.linspace(0.0, top, 49)
        out = {"type": "contour",
               "points": [[round(depth * math.sin(a), 4), round(radius * math.cos(a), 4)] for a in angle]}
        out["points"][-1][1] = opening
    if closable and draw[1] < 0.25 and out["type"] != "contour":
        out = {**out, "shaft_radius": out["polar_opening"], "polar_opening": 0.0}
    return out


def _pipe(rng, size: Size) -> dict:
    radius = _round(_log_uniform(rng, 10.0, size.radius), 0.5)
    length = _round(min(_log_uniform(rng, 300.0, 12000.0), size.length), 10.0)
    mandrel = {"axis": {"type": "line", "length": length}, "profile": {"type": "constant", "radius": radius}}
    winding = _open_winding(rng, size, length, 2.0 * math.pi * radius, 15.0, 89.0)
    return {"mandrel": mandrel, "winding": winding, "machine": _machine(rng)}


def _cone(rng, size: Size) -> dict:
    length = _round(min(_log_uniform(rng, 500.0, 12000.0), size.length), 10.0)
    taper = 1.0 / _log_uniform(rng, 5.0, 100.0)  # radius lost per unit length (1:5 .. 1:100)
    small = _round(_log_uniform(rng, 15.0, min(150.0, size.radius)), 0.5)
    large = _round(min(small + taper * length, size.radius * 1.5), 0.5)
    profile = {"type": "cone", "start_radius": large, "end_radius": small}
    mandrel = {"axis": {"type": "line", "length": length}, "profile": profile}
    winding = _open_winding(rng, size, length, 2.0 * math.pi * large, 15.0, 75.0)
    return {"mandrel": mandrel, "winding": winding, "machine": _machine(rng)}


def _tube(rng, size: Size) -> dict:
    kind = rng.choice(["ellipse", "rounded_rectangle", "superellipse"])
    big = _round(_log_uniform(rng, 20.0, min(200.0, size.radius)), 0.5)
    if kind == "ellipse":
        section = {"type": "ellipse", "a": big, "b": _round(big / rng.uniform(1.2, 4.0), 0.5)}
        perimeter = math.pi * (big + section["b"]) * 1.1
    elif kind == "rounded_rectangle":
        width, height = 2.0 * big, _round(2.0 * big / rng.uniform(1.0, 4.0), 0.5)
        corner = _round(rng.uniform(0.05, 0.3) * min(width, height), 0.5)
        section = {"type": "rounded_rectangle", "width": width, "height": height, "corner_radius": corner}
        perimeter = 2.0 * (width + height)
    else:
        section = {"type": "superellipse", "a": big, "b": _round(big / rng.uniform(1.0, 3.0), 0.5),
                   "exponent": _round(rng.uniform(2.5, 6.0), 0.5)}
        perimeter = 4.0 * (big + section["b"])
    length = _round(min(_log_uniform(rng, 300.0, 4000.0), size.length), 10.0)
    mandrel = {"axis": {"type": "line", "length": length}, "section": section}
    winding = _open_winding(rng, size, length, perimeter, 20.0, 80.0)
    return {"mandrel": mandrel, "winding": winding, "machine": _machine(rng)}


def _elbow(rng, size: Size) -> dict:
    diameter = _round(_log_uniform(rng, 50.0, min(600.0, 2.0 * size.bent)), 5.0)
    bend = _round(rng.uniform(1.0, 5.0) * diameter, 5.0)
    angle = _round(rng.uniform(30.0, 90.0), 5.0)
    legs = [_round(rng.uniform(0.3, 1.5) * diameter, 5.0) for _ in range(2)]
    axis = {"type": "path", "segments": [{"line": legs[0]}, {"arc": {"radius": bend, "angle": angle, "toward": 0}},
                                         {"line": legs[1]}]}
    radius = 0.5 * diameter
    mandrel = {"axis": axis, "profile": {"type": "constant", "radius": radius}}
    length = legs[0] + legs[1] + math.radians(angle) * bend
    winding = _open_winding(rng, size, length, math.pi * diameter, 40.0, 75.0)
    for layer in winding["layers"]:
        if layer["type"] == "helical":
            layer["slip"] = "auto"  # a bend holds a helical by friction
    return {"mandrel": mandrel, "winding": winding, "machine": _machine(rng, robot=True)}


def _duct(rng, size: Size) -> dict:
    radius = _round(_log_uniform(rng, 20.0, min(150.0, size.bent)), 0.5)
    count = int(rng.integers(4, 7 if size.bent > 100.0 else 5))
    step = _round(rng.uniform(3.0, 6.0) * radius, 5.0)
    drift = np.cumsum(rng.uniform(-0.25, 0.25, size=(count, 2)) * step, axis=0)
    drift[0] = 0.0
    drift[1] = 0.0  # the duct starts straight along +z
    points = [[_round(float(x), 1.0), _round(float(y), 1.0), float(i * step)] for i, (x, y) in enumerate(drift)]
    mandrel = {"axis": {"type": "spline", "points": points}, "profile": {"type": "constant", "radius": radius}}
    winding = _open_winding(rng, size, step * (count - 1), 2.0 * math.pi * radius, 40.0, 75.0)
    for layer in winding["layers"]:
        if layer["type"] == "helical":
            layer["slip"] = "auto"
    return {"mandrel": mandrel, "winding": winding, "machine": _machine(rng, robot=True)}
