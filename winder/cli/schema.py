"""`winder schema`: the job file's JSON Schema on standard output, for YAML editors to complete and check
configs as they are typed (winder.config.schema)."""

from __future__ import annotations

import json

from winder.cli.base import _echo, _guard, main


@main.command("schema", short_help="Print the config file's JSON Schema (draft 2020-12).")
@_guard
def schema_cmd() -> None:
    """Print the JSON Schema (draft 2020-12) of winder's config file on standard output: every key with its
    type, unit, range and default, unknown keys refused. Point a YAML editor at it, e.g. a first line
    `# yaml-language-server: $schema=winder.schema.json` after `winder schema > winder.schema.json`.
    Exit status: 0."""
    from winder.config.schema import job_schema  # noqa: PLC0415

    _echo(json.dumps(job_schema(), indent=2))
