"""A whole job file (YAML) -> one validated, frozen JobConfig.

Reads the file, refuses bad YAML, and hands each section to its parser (winder.config.mandrel,
.winding, .machine); every problem is a ConfigError naming the file and the key path (docs/guide/commands.md).
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import field
from pathlib import Path

import yaml

from winder.config.analysis import AnalysisConfig, parse_analysis
from winder.config.extent import is_bent, mandrel_reach
from winder.config.files import MAX_FILE_BYTES, MAX_NAME_LENGTH, read_text
from winder.config.machine import MachineConfig, parse_machine
from winder.config.mandrel import MandrelConfig, axis_length, is_vessel, parse_mandrel
from winder.config.reader import Reader, load_yaml
from winder.config.bends import check_bend_angles
from winder.config.winding import WindingConfig, parse_winding
from winder.errors import ConfigError

__all__ = ["MAX_FILE_BYTES", "MAX_NAME_LENGTH", "JobConfig", "load_config", "parse_config", "read_text"]


@dataclasses.dataclass(frozen=True)
class JobConfig:
    """A whole job file. source is the file name used in messages. winding is None when the file has
    none (enough for `geodesic` and `check`); machine is the default MachineConfig when left out."""

    name: str
    source: str
    mandrel: MandrelConfig
    winding: WindingConfig | None = None
    machine: MachineConfig | None = field(default_factory=MachineConfig)
    analysis: AnalysisConfig | None = None  # the load case (docs/guide/will-it-hold.md)


def load_config(path: str | Path) -> JobConfig:
    """Read and validate a job file; every problem is a ConfigError starting with the path."""
    source = str(path)
    if source.lower().endswith(".wind"):  # fiberpath's job format (JSON), read as the same job
        from winder.config.wind_file import read_wind  # noqa: PLC0415

        return parse_config(read_wind(path).data, source)
    text = read_text(path, source)
    try:
        data = load_yaml(text)
    except RecursionError as exc:  # PyYAML composes nested collections recursively
        raise ConfigError(f"{source}: invalid YAML: nested too deeply (a job file needs a few levels)") from exc
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = f"line {mark.line + 1}, column {mark.column + 1}: " if mark is not None else ""
        problem = exc.problem or exc.context or "unreadable"
        raise ConfigError(f"{source}: {where}invalid YAML: {problem}") from exc
    except (yaml.YAMLError, ValueError) as exc:  # ValueError: an explicitly tagged !!int "x"
        raise ConfigError(f"{source}: invalid YAML: {exc}") from exc
    try:
        return parse_config(data, source)
    except RecursionError as exc:  # a value nested too deeply to show in a message
        raise ConfigError(f"{source}: invalid YAML: nested too deeply (a job file needs a few levels)") from exc


# -- the job file ----------------------------------------------------------------------------------
_NAME = re.compile(r"[A-Za-z0-9_.-]+")


def parse_config(data: dict, source: str) -> JobConfig:
    """Validate the loaded YAML of a job file; source is the file name used in messages."""
    rd = Reader(source)
    top = rd.mapping(data, "", ("name", "mandrel", "winding", "machine", "analysis"), required=("name", "mandrel"))
    name = rd.text(top["name"], "name")
    if not _NAME.fullmatch(name):
        raise rd.error("name", "must use only letters, digits, '_', '.' and '-' (it names the output "
                       "files)", name)
    if name.startswith("."):
        raise rd.error("name", "must not start with '.' (it names the output files, which would be hidden, "
                       "or '.' and '..' the folders themselves)", name)
    if len(name) > MAX_NAME_LENGTH:
        raise rd.error("name", f"must have at most {MAX_NAME_LENGTH} characters (it names the output files), "
                       f"got {len(name)} characters")
    mandrel = parse_mandrel(rd, top["mandrel"], "mandrel")
    vessel = is_vessel(mandrel)
    winding = None
    if top.get("winding") is not None:  # an empty `winding:` counts as none
        winding = parse_winding(rd, top["winding"], "winding", axis_length=axis_length(mandrel.axis),
                                vessel=vessel)
    check_bend_angles(mandrel, winding, source)
    machine = parse_machine(rd, top.get("machine"), "machine", bent=is_bent(mandrel.axis),
                            max_radius=mandrel_reach(mandrel, 0.0, math.inf, None))
    analysis = None
    if top.get("analysis") is not None:
        analysis = parse_analysis(rd, top["analysis"], "analysis", vessel)
    return JobConfig(name, source, mandrel, winding, machine, analysis)
