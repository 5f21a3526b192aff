"""The eye's lead in clearance mode: Newton steps from the envelope's cylinder give the lead of the
full scan (with regula falsi or with Newton steps on its brackets) within the search's tolerance, and
that lead is the ray's first crossing of the envelope."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from winder.config.job import load_config
from winder.config.machine import MachineConfig
from winder.geometry.build import build_surface
from winder.machine import kinematics, leads
from winder.machine.envelope import eye_envelope
from roundoff import assert_roundoff

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = 400  # points along each ray before its lead, all inside the envelope
# mm of envelope distance: each search stops within ROOT_TOL of the envelope, so two crossings differ
# by at most twice that over the slope of the distance along the ray.
LEAD_TOL = 2.0 * leads.ROOT_TOL
# mm: a turned copy takes its representative's lead, its line up to SAME_LINE (and 3e-11 mm of noise)
# away; the lead moves by that times its sensitivity to the line (up to ~100 near grazing).
COPY_LEAD_TOL = 1e-8


@pytest.mark.parametrize("config", ["configs/ellipsoid_vessel.yaml", "samples/cone.yaml", "samples/pipe.yaml"])
def test_guessed_bracket_gives_the_scans_lead(config, monkeypatch):
    job = load_config(ROOT / config)
    surface = build_surface(job.mandrel, job.source, job.name)
    env = eye_envelope(surface, MachineConfig(eye_clearance=20.0, eye_radius=None))
    rng = np.random.default_rng(11)
    m = 3000
    s = rng.uniform(0.0, surface.length, m)
    th = rng.uniform(0.0, 2.0 * np.pi, m)
    ev = surface.evaluate(s, th, order=1)
    mix = rng.normal(size=(m, 2))
    mix[:50, 1] = 1e-7  # nearly along the meridian (toward or away from the axis on a dome)
    d = ev.ps * mix[:, :1] + ev.pt * mix[:, 1:]
    lam, ok = leads.eye_leads(ev.p, d, env)
    guessed, newton_scans = [], []
    plain = leads.first_crossing

    def scan_only(f, n, lmax, guess=None, f0=None, fd=None):  # f(0) found by the scan itself, too
        guessed.append(guess is not None and fd is not None)
        newton_scans.append(plain(f, n, lmax, fd=fd))
        return plain(f, n, lmax)  # the scan and regula falsi alone

    monkeypatch.setattr(leads, "first_crossing", scan_only)
    lam_scan, ok_scan = leads.eye_leads(ev.p, d, env)
    assert guessed == [True]
    u = leads.unit_rows(d)
    e = ev.p + lam[:, None] * u
    r = np.hypot(e[:, 0], e[:, 1])
    slope = (e[:, 0] * u[:, 0] + e[:, 1] * u[:, 1]) / r - env.slope(e[:, 2]) * u[:, 2]
    for other, ok_other in [(lam_scan, ok_scan), newton_scans[0]]:
        assert np.array_equal(ok, ok_other) and np.array_equal(lam[~ok], other[~ok])
        assert np.all(np.abs(lam - other)[ok] * np.abs(slope[ok]) <= LEAD_TOL)
    # The first crossing: on the envelope, and inside it all along the ray before.
    gap = r - env.at(e[:, 2])
    assert np.all(np.abs(gap[ok]) <= leads.ROOT_TOL)
    t = np.linspace(0.0, 1.0, SAMPLES, endpoint=False)[1:]
    for i in np.flatnonzero(ok)[:300]:
        pts = ev.p[i] + (t * lam[i])[:, None] * u[i]
        assert np.all(np.hypot(pts[:, 0], pts[:, 1]) < env.at(pts[:, 2]))


def test_unwrap_each_is_np_unwrap_per_run():
    rng = np.random.default_rng(5)
    for _ in range(200):
        sizes = rng.integers(0, 30, size=rng.integers(1, 8))
        b = np.angle(np.exp(1j * np.cumsum(rng.normal(size=sizes.sum()) * rng.choice([0.1, 2.0]))))
        b[rng.random(b.size) < 0.05] = -0.0
        ends = np.cumsum(sizes)
        want = np.concatenate([np.unwrap(b[e - n:e]) for e, n in zip(ends, sizes)])
        got = kinematics._unwrap_each(b, sizes)
        assert_roundoff(got, want)


def test_level_envelope_leads_are_the_tables_bit_for_bit(monkeypatch):
    """A cylinder's clearance envelope is level: its leads without the table look-ups are the same numbers."""
    job = load_config(ROOT / "samples/pipe.yaml")
    surface = build_surface(job.mandrel, job.source, job.name)
    env = eye_envelope(surface, MachineConfig(eye_clearance=20.0, eye_radius=None))
    assert env.level is not None and env.constant is None
    rng = np.random.default_rng(4)
    m = 5000
    ev = surface.evaluate(rng.uniform(0.0, surface.length, m), rng.uniform(0.0, 2.0 * np.pi, m), order=1)
    mix = rng.normal(size=(m, 2))
    mix[:100, 1] = rng.choice([0.0, 1e-9, -1e-12], 100)  # along the axis: no crossing within the largest lead
    d = ev.ps * mix[:, :1] + ev.pt * mix[:, 1:]
    lam, ok = leads.eye_leads(ev.p, d, env)
    monkeypatch.setattr(type(env), "level", property(lambda self: None))
    lam_table, ok_table = leads.eye_leads(ev.p, d, env)
    assert np.array_equal(ok, ok_table) and not ok.all()
    assert_roundoff(lam, lam_table)


def test_turned_copies_take_their_own_leads():
    """Lines turned about the axis (with round-off noise, as a helical layer's circuits) are solved
    once (leads.SAME_LINE): each copy's lead is its own, solved alone, within LEAD_TOL."""
    job = load_config(ROOT / "configs/ellipsoid_vessel.yaml")
    surface = build_surface(job.mandrel, job.source, job.name)
    env = eye_envelope(surface, MachineConfig(eye_clearance=20.0, eye_radius=None))
    rng = np.random.default_rng(7)
    s, th = rng.uniform(0.0, surface.length, 40), rng.uniform(0.0, 2.0 * np.pi, 40)
    mix = rng.normal(size=(40, 2))
    turns = rng.uniform(0.0, 60.0, 25)
    s, th0 = np.tile(s, turns.size), np.tile(th, turns.size)
    th = th0 + np.repeat(turns, 40)
    ev = surface.evaluate(s, th, order=1)
    d = ev.ps * np.tile(mix[:, :1], (turns.size, 1)) + ev.pt * np.tile(mix[:, 1:], (turns.size, 1))
    p = ev.p + rng.uniform(-3e-11, 3e-11, ev.p.shape)
    lam, ok = leads.eye_leads(p, d, env)
    alone = [leads.eye_leads(p[i:i + 1], d[i:i + 1], env) for i in range(p.shape[0])]
    np.testing.assert_array_equal(ok, [a[1][0] for a in alone])
    np.testing.assert_allclose(lam, [a[0][0] for a in alone], rtol=0.0, atol=COPY_LEAD_TOL)
