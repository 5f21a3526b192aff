"""fiberpath's `.wind` job files (JSON, schemaVersion 1.x) read as winder jobs.

What maps to what (docs/guide/fiberpath.md): mandrelParameters (diameter, windLength, and
endDiameter for a cone, schema 1.1) is a straight mandrel of circular section; towParameters.width is
winding.band_width (thickness is written down, and needs a material to become a laminate); hoop layers
are hoop layers of 2 passes, 1 when `terminal`; helical layers are helical layers at windAngle, the
pattern left to winder (fiberpath's patternNumber, skipIndex, leadInMM and leadOutDegrees are kept as
comments: winder closes its own pattern); lockDegrees is the least dwell at each end; skip layers turn
the mandrel only (winder starts the next layer where the last one ends); defaultFeedRate is
machine.feed, on a marlin X A B machine of fiberpath's axes. Every value is checked with the Reader, so
a bad one is one line naming the file and the JSON path (exit 2).
"""

from __future__ import annotations

import dataclasses
import json
import re
from pathlib import Path
from typing import Any

from winder.config.files import MAX_NAME_LENGTH, read_text
from winder.config.reader import Reader
from winder.errors import ConfigError

WIND_SUFFIX = ".wind"
# fiberpath reads any 1.x (additive) and refuses other majors; x in ASCII digits (\d would take any
# script's), a few of them (fiberpath's are 1.0 to 1.2; 100,000 nines are no version)
SCHEMA = re.compile(r"1\.[0-9]{1,4}")
EYE_CLEARANCE = 20.0  # mm beyond the mandrel's largest radius: marlin's eye stays at one radius
CARRIAGE_MARGIN = 500.0  # mm of carriage travel beyond each end of the wind length
CROSS_FEED_LIMIT = 400.0  # mm, at least the eye radius plus this margin's tenth
CHORD_TOLERANCE = 0.05

_TOP = ("schemaVersion", "mandrelParameters", "towParameters", "defaultFeedRate", "layers")
_MANDREL = ("diameter", "windLength", "endDiameter", "profile")
_TOW = ("width", "thickness")
_KINDS = {"hoop": ((), ("terminal",)),
          "helical": (("windAngle", "patternNumber", "skipIndex", "lockDegrees", "leadInMM", "leadOutDegrees"),
                      ("skipInitialNearLock", "frictionLambda")),
          "skip": (("mandrelRotation",), ())}


def _no_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """The object of JSON's pairs, refusing a key given twice (in time linear in the pairs: the JSON
    reader calls this once per object, and a 2 MB file may hold 200,000 keys in one)."""
    out = dict(pairs)
    if len(out) < len(pairs):
        seen: set[str] = set()
        key = next(k for k, _ in pairs if k in seen or seen.add(k))
        raise ValueError(f"duplicate key {key!r}")
    return out


def _load(path: str | Path, source: str) -> Any:
    text = read_text(path, source, kind="fiberpath .wind file")
    try:
        return json.loads(text, object_pairs_hook=_no_duplicates)
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{source}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from exc
    except (ValueError, RecursionError) as exc:
        raise ConfigError(f"{source}: invalid JSON: {exc}") from exc


def _layer(rd: Reader, value: Any, path: str) -> tuple[str, dict[str, Any]]:
    """(windType, the layer's checked values) of one .wind layer."""
    kind, m = rd.typed(value, path, "layer", _KINDS, tag="windType")
    out: dict[str, Any] = {}
    if kind == "hoop":
        out["terminal"] = rd.boolean(m.get("terminal", False), rd.at(path, "terminal"))
    elif kind == "skip":
        out["mandrelRotation"] = rd.number(m["mandrelRotation"], rd.at(path, "mandrelRotation"))
    else:
        angle = rd.positive(m["windAngle"], rd.at(path, "windAngle"))
        if angle >= 90.0:
            raise rd.error(rd.at(path, "windAngle"), "must be below 90 degrees from the mandrel axis (90 is a "
                           "hoop layer)", m["windAngle"])
        out["windAngle"] = angle
        for key in ("patternNumber", "skipIndex"):
            out[key] = rd.integer(m[key], rd.at(path, key), minimum=1)
        for key in ("lockDegrees", "leadInMM", "leadOutDegrees"):
            out[key] = rd.positive(m[key], rd.at(path, key))
        out["skipInitialNearLock"] = rd.boolean(m.get("skipInitialNearLock", False), rd.at(path, "skipInitialNearLock"))
        lam = rd.number(m.get("frictionLambda", 0.0), rd.at(path, "frictionLambda"))
        if lam != 0.0:
            raise rd.error(rd.at(path, "frictionLambda"), "must be 0 on a cylinder or a cone (fiberpath winds a "
                           "friction ratio only on a profile mandrel, which winder does not read)", m["frictionLambda"])
    return kind, out


@dataclasses.dataclass(frozen=True)
class WindJob:
    """A .wind file read: data, the winder config (what parse_config reads); layers, each .wind layer as
    (windType, its checked values); thickness, the tow's (mm); version, the schemaVersion."""

    data: dict[str, Any]
    layers: tuple[tuple[str, dict[str, Any]], ...]
    thickness: float
    version: str


def read_wind(path: str | Path) -> WindJob:
    """The winder job of a .wind file, every value checked (ConfigError naming the JSON path)."""
    source = str(path)
    rd = Reader(source)
    top = rd.mapping(_load(path, source), "", _TOP, required=("mandrelParameters", "towParameters",
                                                               "defaultFeedRate", "layers"))
    version = top.get("schemaVersion", "1.0")
    if not isinstance(version, str) or not SCHEMA.fullmatch(version.strip()):
        raise rd.error("schemaVersion", "must be a 1.x version string, x of 1 to 4 ASCII digits (fiberpath's "
                       "format 1.x)", version)
    mp = rd.mapping(top["mandrelParameters"], "mandrelParameters", _MANDREL, required=("diameter", "windLength"))
    if "profile" in mp:
        raise rd.error("mandrelParameters.profile", "a profile mandrel (schema 1.2, Von Karman) is not read by winder; "
                       "give a cylinder, or a cone by endDiameter", mp["profile"])
    diameter = rd.positive(mp["diameter"], "mandrelParameters.diameter")
    length = rd.positive(mp["windLength"], "mandrelParameters.windLength")
    end = rd.positive(mp["endDiameter"], "mandrelParameters.endDiameter") if "endDiameter" in mp else diameter
    tp = rd.mapping(top["towParameters"], "towParameters", _TOW, required=_TOW)
    width = rd.positive(tp["width"], "towParameters.width")
    thickness = rd.positive(tp["thickness"], "towParameters.thickness")
    feed = rd.positive(top["defaultFeedRate"], "defaultFeedRate")
    items = rd.listing(top["layers"], "layers", 1, "layer")
    layers = [_layer(rd, item, rd.at("layers", i)) for i, item in enumerate(items)]
    if all(kind == "skip" for kind, _ in layers):
        raise rd.error("layers", "has no hoop or helical layer: nothing to wind")

    stem = re.sub(r"[^A-Za-z0-9_.-]", "_", Path(source).stem).lstrip(".")[:MAX_NAME_LENGTH] or "wind"
    profile = ({"type": "constant", "radius": diameter / 2.0} if end == diameter
               else {"type": "cone", "start_radius": diameter / 2.0, "end_radius": end / 2.0})
    wound = []
    for kind, layer in layers:
        if kind == "hoop":
            wound.append({"type": "hoop", "passes": 1 if layer["terminal"] else 2})
        elif kind == "helical":
            wound.append({"type": "helical", "angle": layer["windAngle"], "pattern": "auto"})
    winding: dict[str, Any] = {"band_width": width, "layers": wound}
    locks = [layer["lockDegrees"] for kind, layer in layers if kind == "helical"]
    if locks:
        winding["dwell"] = {"start": max(locks), "end": max(locks)}
    eye = max(diameter, end) / 2.0 + EYE_CLEARANCE
    machine = {"axes": {"carriage": "X", "rotation": "A", "cross_feed": "Z", "yaw": "B"}, "dialect": "marlin",
               "eye": {"radius": eye}, "feed": feed, "chord_tolerance": CHORD_TOLERANCE,
               "limits": {"carriage": [-CARRIAGE_MARGIN, length + CARRIAGE_MARGIN],
                          "cross_feed": [0.0, max(CROSS_FEED_LIMIT, eye + 0.1 * CROSS_FEED_LIMIT)], "yaw": [-90.0, 90.0]}}
    data = {"name": stem, "mandrel": {"axis": {"type": "line", "length": length}, "profile": profile,
                                      "section": {"type": "circle"}},
            "winding": winding, "machine": machine}
    return WindJob(data, tuple(layers), thickness, version.strip())
