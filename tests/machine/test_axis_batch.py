"""The program's axes of all passes in one batch (winder.machine.axis_batch) against eye_path pass by
pass with the turn counts carried from pass to pass: the same program, to round-off."""

from __future__ import annotations

from dataclasses import fields, replace
from pathlib import Path

import numpy as np
import pytest

from conftest import surface_of
from plans import cylinder_plan
from winder.config.job import load_config
from winder.config.machine import MachineConfig
from winder.config.mandrel import ConstantProfile, LineAxis
from winder.machine import program
from winder.machine.axis_batch import TURN_BACK_DEG, _Turns
from winder.machine.kinematics import EyePath, eye_path
from winder.winding.plan import plan as plan_job
from roundoff import assert_roundoff

ROOT = Path(__file__).resolve().parents[2]


def _pass_by_pass(surface, calls):
    """straight_axes the slow way: one eye_path per pass (twice where the eye would turn back)."""

    def axes(passes, wheres, leads, dense, env, machine, sense):
        turns, a_end, b_end, paths, jumped = _Turns(), None, None, [], []
        for fp, where, lead, dn in zip(passes, wheres, leads, dense):
            planned = np.asarray(fp.theta, dtype=float)
            theta, jump = turns.place(planned, np.asarray(fp.points[0], dtype=float))
            kw = dict(envelope=env, sense=sense, where=where)
            path = eye_path(fp.points, fp.direction, surface, machine, theta=theta, lead=lead, **kw)
            if jump and a_end is not None and (path.a_deg[0] - a_end) * turns.sense > TURN_BACK_DEG:
                theta = turns.turn_on(planned)
                path = eye_path(fp.points, fp.direction, surface, machine, theta=theta, lead=lead, **kw)
            if dn is not None:
                p, d, th, _, dense_lead = dn
                path = eye_path(p, d, surface, machine, theta=th + float(theta[0] - planned[0]), lead=dense_lead,
                                **kw)
            a_end = float(path.a_deg[-1])
            if b_end is not None:
                path = replace(path, b_deg=path.b_deg + 360.0 * np.round((b_end - path.b_deg[0]) / 360.0))
            b_end = float(path.b_deg[-1])
            turns.done(theta, fp.points[-1])
            paths.append(path)
            jumped.append(jump)
        calls.append((sum(jumped), sum(dn is not None for dn in dense)))
        whole = EyePath(*(np.concatenate([getattr(p, f.name) for p in paths]) for f in fields(EyePath)))
        return whole, np.array([len(p.x) for p in paths]), jumped

    return axes


def _vessel():
    job = load_config(ROOT / "samples/vessel_hemi.yaml")
    return plan_job(job), job.machine


def _pipe():
    plan = cylinder_plan(surface_of(LineAxis(300.0), ConstantProfile(40.0)))  # helical, then hoop layer
    return plan, MachineConfig(eye_radius=None, eye_clearance=20.0, chord_tolerance=0.05)


@pytest.mark.parametrize("make", [_vessel, _pipe])
def test_batched_axes_are_pass_by_pass(make, monkeypatch):
    plan, machine = make()
    batched = program.build_program(plan, machine)
    calls = []
    monkeypatch.setattr(program, "straight_passes", lambda *args: None)  # the steps, not the one gather
    monkeypatch.setattr(program, "straight_axes", _pass_by_pass(plan.outer_surface, calls))
    plain = program.build_program(plan, machine)
    assert len(calls) == 1 and calls[0][0] > 0  # some passes start away from the last one's end
    if make is _vessel:
        assert calls[0][1] > 0  # and some were densified
    for name in ("values", "index", "fiber", "feed"):
        assert_roundoff(getattr(batched, name), getattr(plain, name), err_msg=name)
    assert batched.segments == plain.segments
