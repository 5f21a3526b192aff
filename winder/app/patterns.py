"""The `patterns` command: the feasible patterns of a job's helical layers (winder.winding.choices), as a
table or JSON, each with the layer's YAML that selects it (`run` winds exactly that choice)."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import time
from typing import Any

from winder.config.wind_yaml import yaml_number as _num
from winder.config.winding import SLIP_AUTO, LayerConfig
from winder.errors import ConfigError

__all__ = ["choice_yaml", "convert_file", "patterns_json", "patterns_output", "patterns_tables", "patterns_text"]


def patterns_output(config: str, layer: int | None, angle: float | None, within: float, as_json: bool) -> str:
    """What `winder patterns` prints: the tables, or the JSON list of docs/guide/commands.md."""
    tables = patterns_tables(config, layer, angle, within)
    return json.dumps(patterns_json(tables), allow_nan=False) if as_json else patterns_text(tables)


def convert_file(wind: str, output: str) -> str:
    """Write the winder config of fiberpath's job WIND to output (`winder convert`); the text to print:
    a line saying so, or with output `-` (standard output, as the shell's tools read it) the config."""
    from winder.config.wind_yaml import convert_wind  # noqa: PLC0415
    from winder.export.atomic import check_output_file, write_atomic  # noqa: PLC0415
    from winder.export.paths import shown  # noqa: PLC0415

    if output == "-":  # a file of that name is ./-
        return convert_wind(wind).rstrip("\n")
    check_output_file(output, {"WIND": wind})
    text = convert_wind(wind)
    write_atomic(output, text)
    return f"ok: {shown(wind)} -> {shown(output)}"


def choice_yaml(cfg: LayerConfig, angle: float, circuits: int, pattern: int) -> str:
    """The layer entry (a YAML flow mapping) that selects the choice: the angle asked, the circuits and
    the skip, and the layer's slip or turnaround radius where it has one."""
    keys = [f"type: helical, angle: {_num(angle)}, circuits: {circuits}, pattern: {pattern}"]
    if cfg.slip == SLIP_AUTO:
        keys.append("slip: auto")
    elif cfg.slip:
        keys.append(f"slip: {_num(cfg.slip)}")
    if cfg.turnaround_radius is not None:
        start, end = cfg.turnaround_radius
        ends = ", ".join(f"{k}: {_num(v)}" for k, v in (("start", start), ("end", end)) if v is not None)
        keys.append(f"turnaround_radius: {_num(start)}" if start == end else f"turnaround_radius: {{{ends}}}")
    return "{" + ", ".join(keys) + "}"


def patterns_tables(config: str, layer: int | None, angle: float | None, within: float) -> list[tuple[Any, float]]:
    """(PatternTable, seconds) of the helical layer `layer` (1-based) of config, or of each one."""
    from winder.app.validate import validate  # noqa: PLC0415
    from winder.winding.choices import all_helical, pattern_choices  # noqa: PLC0415

    job, _, _ = validate(config)  # every check `run` makes before it computes (exit 2)
    helical = all_helical(job)
    n = len(job.winding.layers)
    if layer is not None and not 1 <= layer <= n:
        raise ConfigError(f"--layer: {config} has layers 1 to {n}, got {layer}")
    if layer is not None and layer - 1 not in helical:
        raise ConfigError(f"--layer: layer {layer} of {config} is a hoop layer; its helical layers: "
                          f"{', '.join(str(i + 1) for i in helical) or 'none'}")
    if not helical:
        raise ConfigError(f"{config}: no helical layer (patterns lists the choices of helical layers)")
    if angle is not None and not 0.0 < angle < 90.0:
        raise ConfigError(f"--angle: must be in (0, 90) degrees from the meridian, got {angle:g}")
    if not (math.isfinite(within) and within >= 0.0):
        raise ConfigError(f"--within: must be >= 0 degrees, got {within:g}")
    from winder.winding.plan import layer_contexts  # noqa: PLC0415

    wanted = [layer - 1] if layer is not None else helical
    start = time.perf_counter()
    contexts, done = layer_contexts(job, max(wanted) + 1)  # one plan of the layers up to the last one asked
    tables = []
    for index in wanted:
        table = pattern_choices(job, index, angle, within, contexts[index], done.layers[index])
        tables.append((table, time.perf_counter() - start, job.winding.layers[index]))
        start = time.perf_counter()
    return tables


def patterns_json(tables: list) -> list[dict[str, Any]]:
    """The objects docs/guide/commands.md names: every field of each choice and its `yaml`."""
    rows = []
    for table, _, cfg in tables:
        for c in table.choices:
            row = dataclasses.asdict(c)
            row["yaml"] = choice_yaml(cfg, table.requested_angle_deg, c.circuits, c.pattern)
            rows.append(row)
    return rows


_HEAD = ("", "circuits", "pattern", "p", "angle", "dwell+", "c mm", "covered", "gap mm", "overlap", "layers",
         "fiber m", "time s", "slip", "yaml to paste in winding.layers")


def patterns_text(tables: list) -> str:
    """A table per layer: its header (the rule, the cost), then one row per choice, `*` the planner's own."""
    from winder.winding.choices import SORT_RULE  # noqa: PLC0415

    lines = []
    for table, seconds, cfg in tables:
        lines.append(f"layer {table.layer}: helical at {table.requested_angle_deg:g} deg, {len(table.choices)} "
                     f"choices in {seconds:.2f} s ({table.plans} layer plans; {table.method})")
        lines.append(f"sorted by: {SORT_RULE}; * the layer as configured (the planner's own choice where it has none); p: circuits before a band lands beside the "
                     f"first (+ leading, - lagging); dwell+: turn added to the least dwells to close")
        rows = [_HEAD]
        for c in table.choices:
            rows.append(("*" if c.chosen else "", str(c.circuits), str(c.pattern), f"{c.crossovers}{'+' if c.lead == 'leading' else '-'}", f"{c.angle_deg:.3f}", f"{c.dwell_added_deg:.2f}",
                         "-" if c.turnaround_radius_mm is None else f"{c.turnaround_radius_mm:.3f}",
                         f"{c.covered_fraction:.4f}", f"{c.max_gap_mm:.3f}", f"{c.max_overlap_mm:.3f}",
                         f"{c.min_layers}-{c.max_layers}", f"{c.fiber_length_mm / 1000.0:.3f}", f"{c.time_s:.1f}",
                         f"{c.max_slip:.3f}", choice_yaml(cfg, table.requested_angle_deg, c.circuits, c.pattern)))
        widths = [max(len(r[j]) for r in rows) for j in range(len(_HEAD))]
        lines += ["  ".join(cell.ljust(w) if j in (0, len(_HEAD) - 1) else cell.rjust(w)
                            for j, (cell, w) in enumerate(zip(r, widths))).rstrip() for r in rows]
        lines.append("")
    return "\n".join(lines).rstrip()
