"""One motion program per job (winder.app.jobs.motion_program), handed to every output that writes or
times it: built once, the same as a fresh build; its build's error reaches the G-code (raised) and the
summary (program_error). The dialect registry (winder.config.dialects) names every dialect once."""

from __future__ import annotations

import importlib

import json
from dataclasses import replace

import pytest

from conftest import surface_of
from plans import cylinder_plan
from winder.app.jobs import render_outputs
from winder.config import controllers
from winder.config.dialects import REGISTRY
from winder.config.machine import DIALECTS, MachineConfig
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.errors import ExportError
from winder.export.gcode import dialect_for, gcode_text
from winder.export.gcode import export as gcode_export
from winder.export.summary import summary_dict
from winder.machine.program import build_program

MACHINE = MachineConfig(eye_radius=60.0, eye_clearance=None, chord_tolerance=0.05)


class _Job:
    name, machine, winding, material = "tube", MACHINE, None, None


def _plan():
    return cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(40.0)))


def test_one_program_for_the_gcode_and_the_summary(monkeypatch):
    plan = _plan()
    calls = []
    import winder.machine.chunks as chunks_module

    real = chunks_module.build_program_in_groups

    def counting(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(chunks_module, "build_program_in_groups", counting)
    out = render_outputs(_Job(), plan, ["gcode"])
    assert len(calls) == 1
    fresh = build_program(plan, MACHINE)
    assert out["tube.gcode"].decode() == gcode_text(plan, MACHINE, program=fresh)
    summary = json.loads(out["tube.summary.json"])
    assert summary["winding_time_s"] == pytest.approx(fresh.times.total_s, abs=0.006)  # 2 decimals written


def test_a_program_that_cannot_be_built_reaches_both():
    plan = _plan()
    error = ExportError("tests/tube.yaml: the eye cannot clear the mandrel")
    assert "program_error" in summary_dict(plan, MACHINE, error)
    with pytest.raises(ExportError, match="cannot clear"):
        gcode_export(plan, _Job(), error)


def test_every_dialect_from_the_registry():
    assert DIALECTS == tuple(REGISTRY)
    program = build_program(_plan(), MACHINE)
    for name, row in REGISTRY.items():
        dialect = dialect_for(replace(program, machine=replace(MACHINE, dialect=name)))
        # A robot cell's language is written as its own files; its .gcode is the robot pose listing.
        assert type(dialect).__module__ == (REGISTRY["robot"].module if row.cell else row.module)
        if row.cell:
            assert callable(importlib.import_module(row.module).serialize)


def test_a_new_dialect_is_one_file(tmp_path, monkeypatch):
    """A built-in dialect is a post file in the package's posts folder: a file more, and the registry,
    the config's machine.dialect and the writer know it (no code)."""
    import shutil  # noqa: PLC0415

    posts = tmp_path / "posts"
    shutil.copytree(controllers.POSTS, posts)
    (posts / "plain.post.yaml").write_text("extends: generic\nabout: the generic G-code under another name\n")
    monkeypatch.setattr(controllers, "POSTS", posts)
    monkeypatch.setattr(REGISTRY, "_rows", None)
    for cached in (controllers.builtin_names, controllers.builtin):
        cached.cache_clear()
    try:
        assert "plain" in REGISTRY and REGISTRY["plain"].module == REGISTRY["generic"].module
        program = build_program(_plan(), MACHINE)
        text = gcode_text(None, MACHINE, program=replace(program, machine=replace(MACHINE, dialect="plain")))
        named = "; controller: plain (the generic G-code under another name)\n"  # the header names it
        assert named in text and text.replace(named, "") == gcode_text(None, MACHINE, program=program)
    finally:
        for cached in (controllers.builtin_names, controllers.builtin):
            cached.cache_clear()
        REGISTRY._rows = None
