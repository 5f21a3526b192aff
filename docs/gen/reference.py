"""The generated reference pages of the docs site: the command reference from winder's click commands,
the config reference from the config's JSON Schema (winder.config.schema, itself held to the readers key
by key by tests/config/test_schema.py).

The docs build calls these through docs/gen/hooks.py; run alone it writes the pages into a folder:
`python docs/gen/reference.py OUT_DIR`.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Any

import click

from winder.cli import main
from winder.config.schema import job_schema

# -- text -----------------------------------------------------------------------------------------------


def escaped(text: str) -> str:
    """text for Markdown: `<name>` outside code spans would be read as an HTML tag, `|` as a table cell."""
    pieces = re.split(r"(`[^`]*`)", text)
    return "".join(p if p.startswith("`") else p.replace("<", "&lt;").replace(">", "&gt;").replace("|", "\\|")
                   for p in pieces)


def _paragraphs(text: str) -> str:
    """click's help text (paragraphs separated by blank lines, lines wrapped) as Markdown paragraphs."""
    text = click.unstyle(text or "").replace("\b\n", "")
    return "\n\n".join(escaped(" ".join(p.split())) for p in re.split(r"\n\s*\n", text) if p.strip())


# -- commands -------------------------------------------------------------------------------------------
def _option_rows(command: click.Command, ctx: click.Context) -> list[str]:
    rows = []
    for param in command.get_params(ctx):
        record = param.get_help_record(ctx)
        if record is None or isinstance(param, click.Argument):
            continue
        names, help_text = record
        rows.append(f"| `{names}` | {escaped(' '.join(help_text.split()))} |")
    return rows


def command_reference() -> str:
    """The command reference: for each command its usage, its help and its options, as `--help` shows them.

    Returns
    -------
    str
        A Markdown page, one section per command, in alphabetical order.
    """
    root = click.Context(main, info_name="winder")
    out = ["# Command reference", "",
           "Generated from the command line itself (`winder COMMAND --help` shows the same). Exit status "
           "everywhere: 0 success, 2 bad usage or an invalid config, 1 a job that could not be computed; every "
           "problem is one line starting with `Error:`. How to use them together: [Commands](../guide/commands.md).",
           ""]
    for name in sorted(main.commands):
        command = main.commands[name]
        ctx = click.Context(command, info_name=name, parent=root)
        out += [f"## winder {name}", "", "```", command.get_usage(ctx).removeprefix("Usage: "), "```", "",
                _paragraphs(command.help or ""), "", "| option | meaning |", "|---|---|", *_option_rows(command, ctx),
                ""]
    return "\n".join(out)


# -- config ---------------------------------------------------------------------------------------------
def _type_text(node: dict[str, Any]) -> str:
    if "const" in node:
        return f"`{node['const']}`"
    if "enum" in node:
        return " \\| ".join(f"`{v}`" for v in node["enum"])
    if "anyOf" in node or ("oneOf" in node and "properties" not in node and "type" not in node):
        return " or ".join(_type_text(b) for b in node.get("anyOf", node.get("oneOf")))
    kind = node.get("type", "")
    kinds = kind if isinstance(kind, list) else [kind]
    words = {"object": "mapping", "array": "list", "number": "number", "integer": "whole number",
             "boolean": "true/false", "string": "text", "null": "empty"}
    return " or ".join(words.get(k, k) for k in kinds if k != "null") or "mapping"


def _children(node: dict[str, Any]) -> list[dict[str, Any]]:
    """The mapping schemas inside node: itself, its branches, its items."""
    if "properties" in node:
        return [node]
    found = []
    for branch in node.get("anyOf", node.get("oneOf", [])):
        found += _children(branch)
    if isinstance(node.get("items"), dict):
        found += _children(node["items"])
    return found


# The frozen dataclass each mapping (or kind) is read into, for a script using winder as a library.
READ_INTO = {"": "job.JobConfig", "mandrel": "mandrel.MandrelConfig", "mandrel.axis@line": "line.LineAxis",
             "mandrel.axis@arc": "axes.ArcAxis", "mandrel.axis@path": "axes.PathAxis",
             "mandrel.axis@spline": "axes.SplineAxis", "mandrel.profile@constant": "mandrel.ConstantProfile",
             "mandrel.profile@cone": "profiles.ConeProfile", "mandrel.profile@table": "profiles.TableProfile",
             "mandrel.profile@vessel": "vessel.VesselProfile", "mandrel.profile.dome": "vessel.Dome",
             "mandrel.section@circle": "mandrel.CircleSection", "mandrel.section@ellipse": "sections.EllipseSection",
             "mandrel.section@rounded_rectangle": "sections.RoundedRectangleSection",
             "mandrel.section@superellipse": "sections.SuperellipseSection", "winding": "winding.WindingConfig",
             "winding.layers[]": "winding.LayerConfig", "winding.material": "material.MaterialConfig",
             "machine": "machine.MachineConfig", "machine.axes": "machine.MachineAxes",
             "machine.limits": "machine.MachineLimits", "machine.dynamics": "machine.MachineDynamics",
             "machine.robot": "robot.RobotCell", "machine.robot.base": "robot.Pose", "analysis": "analysis.AnalysisConfig"}


def _read_into(path: str, kind: str | None) -> str:
    """`Read into winder.config.x.Y.` for the mapping at path (of a kind), or ''."""
    target = READ_INTO.get(f"{path}@{kind}") or READ_INTO.get(path)
    return f" Read into `winder.config.{target}`." if target else ""


def _shape(node: dict[str, Any]) -> str:
    """node without its descriptions: two keys of one shape (dome, end_dome) are described once."""
    import json  # noqa: PLC0415

    def bare(value: Any) -> Any:
        if isinstance(value, dict):
            return {k: bare(v) for k, v in value.items() if k != "description"}
        return [bare(v) for v in value] if isinstance(value, list) else value

    return json.dumps(bare(node), sort_keys=True)


def _section(path: str, node: dict[str, Any], out: list[str], seen: dict[str, str]) -> None:
    """One table for the mapping at path (one per kind of a type-tagged mapping), then its sub-mappings."""
    variants = _children(node)
    tagged = len(variants) > 1 and all("const" in v["properties"].get("type", {}) for v in variants)
    if path and _shape(node) in seen:
        out += [f"## `{path}`", "", escaped(node.get("description", "")),
                f"Its keys are those of [`{seen[_shape(node)]}`](#{_anchor(seen[_shape(node)], variants, tagged)}).", ""]
        return
    if path:
        seen[_shape(node)] = path
    below: list[tuple[str, dict]] = []
    for i, variant in enumerate(variants):
        title = f"`{path}`" if path else "The top level"
        if tagged:
            title += f" (type: {variant['properties']['type']['const']})"
        elif i:
            title += " (or)"
        intro = variant.get("description", "") if tagged or "properties" in node else node.get("description", "")
        intro += _read_into(path, variant["properties"]["type"]["const"] if tagged else None)
        required = set(variant.get("required", ()))
        out += [f"## {title}", "", escaped(intro), "", "| key | type | what |", "|---|---|---|"]
        for key, prop in variant["properties"].items():
            mark = " (required)" if key in required and key != "type" else ""
            out.append(f"| `{key}`{mark} | {_type_text(prop)} | {escaped(prop.get('description', ''))} |")
            sub = f"{path}.{key}" if path else key
            if prop.get("type") == "array" and _children(prop.get("items", {})):
                sub += "[]"
            if _children(prop) and all(sub != s for s, _ in below):
                below.append((sub, prop))
        out.append("")
    for sub, prop in below:
        _section(sub, prop.get("items", prop) if prop.get("type") == "array" else prop, out, seen)


def _anchor(path: str, variants: list[dict], tagged: bool) -> str:
    """The anchor MkDocs gives the heading of path's first table."""
    title = path + (f" (type: {variants[0]['properties']['type']['const']})" if tagged else "")
    return re.sub(r"[^\w\- ]", "", title).strip().lower().replace(" ", "-")


def config_reference() -> str:
    """The config reference: every key of the job file by key path, from the JSON Schema `winder schema` prints.

    Returns
    -------
    str
        A Markdown page: one table per mapping (per kind where a `type` names it).
    """
    schema = job_schema()
    out = ["# Config reference", "",
           "Every key of the job file, generated from the JSON Schema that `winder schema` prints (the schema is "
           "checked against the readers key by key). Lengths in mm, angles in degrees. Key paths: `a.b` a key of "
           "a mapping, `a[]` an entry of a list. The readers check more than a schema can say (a region inside "
           "the mandrel, a polar opening below the radius, a slip within the friction): `winder check` says it. "
           "Commented examples: [The config file](../guide/config.md).", ""]
    _section("", schema, out, {})
    return "\n".join(out)


# The public API of the main stages, in pipeline order: what a script calling winder as a library uses.
API = (("winder.config.job", "load_config"), ("winder.config.job", "parse_config"),
       ("winder.config.schema", "job_schema"), ("winder.geometry.build", "build_surface"),
       ("winder.paths.geodesic", "geodesic"), ("winder.winding.plan", "plan"),
       ("winder.machine.program", "build_program"), ("winder.export.registry", "chosen"),
       ("winder.export.registry", "Format.render"))


def api_reference() -> str:
    """The library's entry points, stage by stage: each signature and its numpydoc docstring.

    Returns
    -------
    str
        A Markdown page; the docstrings' examples are the doctests tests/test_doctests.py runs.
    """
    import importlib  # noqa: PLC0415
    import inspect  # noqa: PLC0415

    out = ["# Library reference", "",
           "winder's stages called from Python, in pipeline order: config, geometry, paths, winding, machine, "
           "export. Generated from the docstrings; their examples run as tests. How the stages fit: "
           "[Architecture](../architecture.md).", ""]
    for module_name, qualname in API:
        obj = importlib.import_module(module_name)
        for part in qualname.split("."):
            obj = getattr(obj, part)
        signature = str(inspect.signature(obj)).replace("'", "")
        out += [f"## `{module_name}.{qualname}`", "", "```python", f"{qualname.split('.')[-1]}{signature}", "```", "",
                "```text", inspect.cleandoc(obj.__doc__ or ""), "```", ""]
    return "\n".join(out)


PAGES = {"reference/commands.md": command_reference, "reference/config.md": config_reference,
         "reference/api.md": api_reference}


if __name__ == "__main__":
    target = Path(sys.argv[1] if len(sys.argv) > 1 else "site-reference")
    for uri, make in PAGES.items():
        (target / uri).parent.mkdir(parents=True, exist_ok=True)
        (target / uri).write_text(make(), encoding="utf-8")
        print(target / uri)
