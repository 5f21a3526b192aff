"""The eye's lead by Newton steps (winder.machine.leads) against the bracket-and-regula-falsi search
it replaced (kept here as the truth): the same 'found' flags and the same crossings within the
search's tolerance, on random lines and on the points of real jobs; and the envelope's slope (the
Newton steps' derivative) against differences of the envelope itself."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from winder.config.job import load_config
from winder.config.machine import MachineConfig
from winder.geometry.build import build_surface
from winder.machine import kinematics, leads
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


def old_first_crossing(f, m, lmax, guess=None, f0=None):
    """The search before Newton steps: the guess's grid interval or a scan brackets the crossing,
    the Illinois variant of regula falsi closes the bracket."""
    grid = lmax * (np.arange(1, leads.LEAD_SCAN + 1) / leads.LEAD_SCAN) ** 2
    lam = np.full(m, lmax)
    lo, hi = np.zeros(m), np.full(m, lmax)
    flo, fhi = np.zeros(m), np.zeros(m)
    found = np.zeros(m, dtype=bool)
    pending = np.arange(m)
    prev_lam, prev_f = 0.0, (f(np.zeros(m), pending) if f0 is None else f0)
    if guess is not None:
        k = np.searchsorted(grid, np.where(np.isfinite(guess), guess, np.inf))
        idx = np.flatnonzero(k < leads.LEAD_SCAN)
        k = k[idx]
        below = np.where(k > 0, grid[np.maximum(k - 1, 0)], 0.0)
        f_hi = f(grid[k], idx)
        f_lo = np.where(k > 0, f(below, idx), prev_f[idx])
        hit = (f_hi >= 0.0) & (f_lo < 0.0)
        sel = idx[hit]
        lo[sel], hi[sel], flo[sel], fhi[sel] = below[hit], grid[k[hit]], f_lo[hit], f_hi[hit]
        found[sel] = True
        pending = np.flatnonzero(~found)
        prev_f = prev_f[pending]
    for grid_lam in grid:
        if pending.size == 0:
            break
        val = f(np.full(pending.size, grid_lam), pending)
        hit = val >= 0.0
        sel = pending[hit]
        lo[sel], hi[sel], flo[sel], fhi[sel] = prev_lam, grid_lam, prev_f[hit], val[hit]
        found[sel] = True
        pending, prev_f, prev_lam = pending[~hit], val[~hit], grid_lam
    active = np.flatnonzero(found)
    a, b, fa, fb = lo[active], hi[active], flo[active], fhi[active]
    side = np.zeros(active.size, dtype=np.int8)
    for _ in range(leads.ROOT_ITER):
        if active.size == 0:
            break
        c = np.clip(b - fb * (b - a) / (fb - fa), a, b)
        fc = f(c, active)
        done = (np.abs(fc) <= leads.ROOT_TOL) | (b - a <= leads.ROOT_TOL)
        lam[active[done]] = c[done]
        up = fc >= 0.0
        fa = np.where(up & (side == 1), 0.5 * fa, np.where(up, fa, fc))
        fb = np.where(~up & (side == -1), 0.5 * fb, np.where(up, fc, fb))
        a, b = np.where(up, a, c), np.where(up, c, b)
        side = np.where(up, 1, -1).astype(np.int8)
        keep = ~done
        active, a, b, fa, fb, side = active[keep], a[keep], b[keep], fa[keep], fb[keep], side[keep]
    lam[active] = b
    return lam, found


def old_lead_straight(p, d, env):
    """The lead of the search before Newton steps (clearance mode), from the same cylinder guess."""
    m = p.shape[0]
    r0 = np.hypot(p[:, 0], p[:, 1])
    at_p = env.at(p[:, 2])

    def f(lam, i):
        return np.hypot(p[i, 0] + lam * d[i, 0], p[i, 1] + lam * d[i, 1]) - env.at(p[i, 2] + lam * d[i, 2])

    with np.errstate(divide="ignore", invalid="ignore"):
        guess = leads._cylinder_lead(p, d, r0, at_p)
        guess = leads._cylinder_lead(p, d, r0, env.at(p[:, 2] + np.where(np.isfinite(guess), guess, 0.0) * d[:, 2]))
    return old_first_crossing(f, m, leads.MAX_LEAD_FACTOR * env.max_radius, guess, r0 - at_p)


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
