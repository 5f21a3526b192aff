"""`winder convert`: a fiberpath `.wind` job written as the equivalent winder config, with comments
saying where each value came from and what winder does differently (winder.config.wind_file reads it)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from winder.config.wind_file import WindJob, read_wind
from winder.escape import yaml_comment


def yaml_number(value: float) -> str:
    """A number as YAML reads it back to the same float."""
    return str(int(value)) if float(value).is_integer() and abs(value) < 1e15 else repr(float(value))


def _flow(m: dict[str, Any]) -> str:
    parts = []
    for key, value in m.items():
        if isinstance(value, dict):
            text = _flow(value)
        elif isinstance(value, list):
            text = "[" + ", ".join(yaml_number(v) for v in value) + "]"
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            text = yaml_number(value)
        else:
            text = str(value)
        parts.append(f"{key}: {text}")
    return "{" + ", ".join(parts) + "}"


def _layer_comment(kind: str, layer: dict[str, Any]) -> str:
    if kind == "hoop":
        return f"fiberpath: hoop, terminal: {'true' if layer['terminal'] else 'false'} (there and back unless terminal)"
    return (f"fiberpath: patternNumber {layer['patternNumber']}, skipIndex {layer['skipIndex']}, lockDegrees "
            f"{yaml_number(layer['lockDegrees'])}, leadInMM {yaml_number(layer['leadInMM'])}, leadOutDegrees "
            f"{yaml_number(layer['leadOutDegrees'])}; winder closes its own pattern (winder patterns lists them)")


def wind_yaml(job: WindJob, source: str) -> str:
    """The commented YAML text of a .wind job read."""
    d = job.data
    m, w, mc = d["mandrel"], d["winding"], d["machine"]
    lines = [f"# Converted by `winder convert` from fiberpath's {yaml_comment(Path(source).name)} (schemaVersion "
             f"{yaml_comment(job.version)}).",
             f"# Tow thickness {yaml_number(job.thickness)} mm: not used for the plan (give winding.material for a "
             f"laminate that grows as wound).",
             f"name: {d['name']}", "", "mandrel:",
             f"  axis: {_flow(m['axis'])}            # = fiberpath windLength (mm)",
             f"  profile: {_flow(m['profile'])}   # = fiberpath diameter / 2 (and endDiameter / 2: a cone)",
             f"  section: {_flow(m['section'])}", "", "winding:",
             f"  band_width: {yaml_number(w['band_width'])}              # = fiberpath towParameters.width"]
    if "dwell" in w:
        lines.append(f"  dwell: {_flow(w['dwell'])}   # = fiberpath lockDegrees (the least turn at each end; "
                     f"the largest of the layers')")
    lines.append("  layers:")
    wound = iter(w["layers"])
    for kind, layer in job.layers:
        if kind == "skip":
            lines.append(f"    # fiberpath skip: the mandrel turns {yaml_number(layer['mandrelRotation'])} deg without "
                         f"fiber; winder starts each layer where the last one ended")
            continue
        lines.append(f"    - {_flow(next(wound))}   # {_layer_comment(kind, layer)}")
    lines += ["", "machine:  # a marlin X A B winder (fiberpath's machines): X carriage, A mandrel, B delivery head",
              f"  axes: {_flow(mc['axes'])}",
              f"  dialect: {mc['dialect']}",
              f"  eye: {_flow(mc['eye'])}      # the eye at a fixed radius: the largest mandrel radius + 20 mm",
              f"  feed: {yaml_number(mc['feed'])}                  # = fiberpath defaultFeedRate (mm/min)",
              f"  chord_tolerance: {yaml_number(mc['chord_tolerance'])}", "  limits:"]
    lines += [f"    {axis}: [{', '.join(yaml_number(v) for v in span)}]" for axis, span in mc["limits"].items()]
    return "\n".join(lines) + "\n"


def convert_wind(path: str | Path) -> str:
    """The winder config (YAML text) of the .wind file at path."""
    return wind_yaml(read_wind(path), str(path))
