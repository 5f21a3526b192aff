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
    """Read and validate a job file (YAML, or fiberpath's `.wind` JSON).

    Parameters
    ----------
    path : str or Path
        The job file. Its name starts every message; a `file:` inside it is read relative to its folder.

    Returns
    -------
    JobConfig
        The validated, frozen config: mandrel, winding (None without a `winding:`), machine (defaults
        where left out) and analysis (None without an `analysis:`).

    Raises
    ------
    ConfigError
        For every problem, one line `<file>: <key.path>: <what>, got <value>` (exit status 2).

    Examples
    --------
    >>> load_config("missing.yaml")
    Traceback (most recent call last):
    ...
    winder.errors.ConfigError: missing.yaml: cannot read the file: No such file or directory
    """
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
    """Validate the loaded YAML of a job file.

    Parameters
    ----------
    data : dict
        The file's data as YAML (winder.config.reader.load_yaml) or JSON reads it.
    source : str
        The file name every message starts with.

    Returns
    -------
    JobConfig
        As load_config.

    Examples
    --------
    >>> job = parse_config({"name": "pipe",
    ...                     "mandrel": {"axis": {"type": "line", "length": 500},
    ...                                 "profile": {"type": "constant", "radius": 50}},
    ...                     "winding": {"band_width": 10, "layers": [{"type": "helical", "angle": 55}]}},
    ...                    "pipe.yaml")
    >>> job.winding.layers[0].label(0), job.machine.feed
    ('layer 1 (helical 55 deg)', 3000.0)
    >>> parse_config({"name": "pipe", "mandrel": {"axis": {"type": "line", "length": 500},
    ...                                           "profile": {"type": "constant", "raduis": 50}}}, "pipe.yaml")
    Traceback (most recent call last):
    ...
    winder.errors.ConfigError: pipe.yaml: mandrel.profile.raduis: unknown key for a constant profile; did you mean 'radius'? allowed: type, radius
    """
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
