"""The eye's lead by Newton steps (winder.machine.leads) against the search it replaced: a scan
brackets each crossing and regula falsi closes it (still first_crossing's way without a slope). The
same 'found' flags and the same crossings within the search's tolerance, on random lines and on the
points of real jobs; and the envelope's slope (the Newton steps' derivative) against differences of
the envelope itself."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from winder.config.job import load_config
from winder.config.machine import MachineConfig
from winder.geometry.build import build_surface
from winder.machine import kinematics, leads, straight
from winder.machine.envelope import eye_envelope
from winder.machine.program import build_program
from winder.winding.plan import plan as plan_job

ROOT = Path(__file__).resolve().parents[2]
# mm of envelope distance: both searches stop within ROOT_TOL of the envelope, so their crossings
# differ by at most twice that over the slope of the distance along the line.
LEAD_TOL = 2.0 * leads.ROOT_TOL
SLOPE_TOL = 1e-6  # relative: central differences of the piecewise linear envelope inside a segment
DIFF_STEP = 1e-5  # mm
CONFIGS = ["configs/ellipsoid_vessel.yaml", "configs/vessel_friction.yaml", "samples/cone.yaml",
           "samples/pipe.yaml"]


def old_lead_straight(p, d, env):
    """The lead of the search before Newton steps (clearance mode): the full scan brackets each
    crossing and the Illinois variant of regula falsi closes it (first_crossing without a slope; the
    old guess only skipped the scan up to the same bracket)."""
    m = p.shape[0]
    r0 = np.hypot(p[:, 0], p[:, 1])
    at_p = env.at(p[:, 2])

    def f(lam, i):
        return np.hypot(p[i, 0] + lam * d[i, 0], p[i, 1] + lam * d[i, 1]) - env.at(p[i, 2] + lam * d[i, 2])

    return leads.first_crossing(f, m, leads.MAX_LEAD_FACTOR * env.max_radius, f0=r0 - at_p)


def assert_same_leads(p, d, env):
    """New and old leads of the lines p + lambda d (d unit): same flags, same crossings within
    LEAD_TOL of envelope distance, the new one on the envelope within ROOT_TOL."""
    lam, ok = leads.lead_straight(p, d, env, "test")
    lam_old, ok_old = old_lead_straight(p, d, env)
    assert np.array_equal(ok, ok_old)
    assert np.array_equal(lam[~ok], lam_old[~ok])  # lmax where the line never reaches the envelope
    e = p + lam[:, None] * d
    r = np.hypot(e[:, 0], e[:, 1])
    gap = r - env.at(e[:, 2])
    assert np.all(np.abs(gap[ok]) <= leads.ROOT_TOL)
    slope = (e[:, 0] * d[:, 0] + e[:, 1] * d[:, 1]) / r - env.slope(e[:, 2]) * d[:, 2]
    assert np.all(np.abs(lam - lam_old)[ok] * np.abs(slope[ok]) <= LEAD_TOL)
    return ok


def clearance_envelope(config):
    job = load_config(ROOT / config)
    surface = build_surface(job.mandrel, job.source, job.name)
    return surface, eye_envelope(surface, MachineConfig(eye_clearance=20.0, eye_radius=None))


@pytest.mark.parametrize("config", CONFIGS)
def test_random_lines_match_the_old_search(config):
    surface, env = clearance_envelope(config)
    rng = np.random.default_rng(23)
    m = 4000
    # Points anywhere inside the envelope (also past the mandrel's ends), directions on the sphere.
    t = rng.uniform(-10.0, surface.axial_length + 10.0, m)
    rad = env.at(t) * np.sqrt(rng.uniform(0.0, 0.999, m))
    ang = rng.uniform(0.0, 2.0 * np.pi, m)
    p = np.column_stack([rad * np.cos(ang), rad * np.sin(ang), t])
    d = leads.unit_rows(rng.normal(size=(m, 3)))
    d[:40] = [0.0, 0.0, 1.0]  # along the axis: no cylinder guess, the scan alone
    d[40:80, :2] = 1e-9 * rng.normal(size=(40, 2))
    d = leads.unit_rows(d)
    ok = assert_same_leads(p, d, env)
    assert ok.mean() > 0.5
    # Tangent rays of the mandrel, as the eye's leads are.
    s = rng.uniform(0.0, surface.length, m)
    th = rng.uniform(0.0, 2.0 * np.pi, m)
    ev = surface.evaluate(s, th, order=1)
    mix = rng.normal(size=(m, 2))
    mix[:50, 1] = 1e-7  # nearly along the meridian
    assert_same_leads(ev.p, leads.unit_rows(ev.ps * mix[:, :1] + ev.pt * mix[:, 1:]), env)


@pytest.mark.parametrize("config", ["samples/cone.yaml", "samples/vessel_isotensoid.yaml"])
def test_real_jobs_leads_match_the_old_search(config, monkeypatch):
    job = load_config(ROOT / config)
    calls = []
    plain = leads.lead_straight

    def record(p, d, env, where):
        calls.append((p.copy(), d.copy(), env))
        return plain(p, d, env, where)

    monkeypatch.setattr(leads, "lead_straight", record)
    monkeypatch.setattr(kinematics, "lead_straight", record)
    monkeypatch.setattr(straight, "lead_straight", record)
    build_program(plan_job(job), job.machine)
    monkeypatch.undo()  # the comparisons below call the search itself, unrecorded
    assert calls and sum(p.shape[0] for p, _, _ in calls) > 1000
    for p, d, env in calls:
        assert env.constant is None  # clearance mode: the search, not the cylinder's closed form
        assert assert_same_leads(p, d, env).all()


@pytest.mark.parametrize("config", CONFIGS)
def test_slope_is_the_envelopes_derivative(config):
    surface, env = clearance_envelope(config)
    x = env.stations if env.radius_stations is None else env.radius_stations
    rng = np.random.default_rng(3)
    t = rng.uniform(x[0] - 200.0, x[-1] + 200.0, 20000)
    # Away from the table's stations (its kinks) and from where it reaches the axis.
    j = np.searchsorted(x, t)
    near = np.minimum(np.abs(t - x[np.clip(j, 0, x.size - 1)]), np.abs(t - x[np.clip(j - 1, 0, x.size - 1)]))
    t = t[(near > 2.0 * DIFF_STEP) & (env.at(t - DIFF_STEP) > 0.0) & (env.at(t + DIFF_STEP) > 0.0)]
    diff = (env.at(t + DIFF_STEP) - env.at(t - DIFF_STEP)) / (2.0 * DIFF_STEP)
    slope = env.slope(t)
    assert np.all(np.abs(slope - diff) <= SLOPE_TOL * (1.0 + np.abs(slope)))
    assert np.array_equal(env.slope(t[t < x[0]]), np.full(np.sum(t < x[0]), env.end_slopes[0]))
    assert np.all(env.slope(np.array([-1e6, 1e6])) == 0.0)  # clipped at the axis, or flat ends
