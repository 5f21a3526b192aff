"""The bench runs end to end at a tiny size and writes a page that matches its JSON; its closed forms,
baselines and verdicts are right. No timed assertions: times are only checked to be positive."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from bench import run_bench, tiny, write_outputs
from bench.__main__ import main as bench_main
from bench.baselines import bvp_geodesic, grid_for, length_and_gradient, seed_chain
from bench.cases import cases, cone_length, developable_tube_length, ellipse_perimeter
from bench.table1 import frontier, verdict_text, verdicts
from winder.paths.geodesic import geodesic

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    results = run_bench(tiny())
    paths = write_outputs(results, out)
    return results, out, paths


def test_tiny_bench_writes_json_markdown_and_matches(tiny_run):
    _, out, paths = tiny_run
    assert (out / "results.json") in paths and (out / "RESULTS.md") in paths
    data = json.loads((out / "results.json").read_text())
    page = (out / "RESULTS.md").read_text()
    (case,) = data["cases"]
    assert case["key"] == "bend"
    # The page is generated from the JSON: its figures appear verbatim.
    assert f"{case['truth']['length_mm']:.12g} mm" in page
    for heading in ("## Summary", "## Accuracy against time", "## Table 1", "## Figure 7", "## Figure 8",
                    "## Section 6.1", "## Section 6.2"):
        assert heading in page
    # Every figure the JSON lists exists; without matplotlib the page says why there are none.
    for name in data["figures"]:
        assert (out / name).is_file()
    if not data["figures"]:
        assert "matplotlib is not installed" in page
    # Measured points are sane: positive times, and newton at n = 50 is accurate on the bend.
    newton = {p["param"]: p for p in case["points"] if p["method"] == "newton" and "rel_error" in p}
    assert all(p["seconds"] > 0 for p in newton.values())
    assert abs(newton[50]["rel_error"]) < 1e-6
    assert abs(case["truth"]["shoot_rel_diff"]) == 0.0  # the bend's truth is shooting itself
    methods = {p["method"] for p in case["points"]}
    assert {"newton", "newton_richardson", "newton_polyline", "shooting", "collocation"} <= methods
    assert case["lbfgs"][0]["iterations"] <= tiny().lbfgs_cap
    assert data["helix"]["rows"][0]["newton"]["rel_diff_vs_shooting"] is not None
    assert len(data["evolution"]["runs"][0]["frames"]) == tiny().frames


def test_from_json_rewrites_the_page(tiny_run, monkeypatch):
    _, out, _ = tiny_run
    before = (out / "RESULTS.md").read_text()
    (out / "RESULTS.md").unlink()
    # The figures were checked above; skip redrawing them here (matplotlib is the slow part).
    monkeypatch.setattr("bench.figures.make_figures", lambda results, path: ([], []))
    assert bench_main(["-o", str(out), "--from-json"]) == 0
    after = (out / "RESULTS.md").read_text()
    assert after.startswith("# winder benchmarks")
    def table1(page):
        return page.split("## Table 1")[1].split("## Figure 7")[0]

    assert table1(after) == table1(before)
    assert "no figures were drawn" not in after  # make_figures gave no note; only images are left out


def test_closed_forms():
    assert cone_length(60.0, 30.0, 300.0, 0.0) == pytest.approx(np.hypot(300.0, 30.0), rel=1e-14)
    assert ellipse_perimeter(40.0, 40.0) == pytest.approx(2 * np.pi * 40.0, rel=1e-14)
    assert ellipse_perimeter(60.0, 35.0) == pytest.approx(ellipse_perimeter(35.0, 60.0), rel=1e-15)
    assert developable_tube_length(3.0, 4.0) == pytest.approx(5.0)
    with pytest.raises(ValueError):
        cone_length(60.0, 30.0, 300.0, 40.0)  # past pi unrolled: the chord would pass the apex


@pytest.mark.parametrize("key", ["cone", "ellipse"])
def test_closed_forms_agree_with_newton(key):
    case = next(c for c in cases() if c.key == key)
    surface = case.surface()
    res = geodesic(surface, case.start, case.end, rounds=case.rounds, n=500, estimate=False)
    assert res.length == pytest.approx(case.closed_form(), rel=1e-8)


def test_collocation_baseline_on_the_elliptic_tube():
    case = next(c for c in cases() if c.key == "ellipse")
    surface = case.surface()
    a, b = case.ends_s(surface)
    res = bvp_geodesic(surface, a, b, case.rounds, tol=1e-4)
    assert res.status == 0
    assert res.length == pytest.approx(case.closed_form(), rel=1e-6)


def test_length_gradient_matches_finite_differences():
    case = next(c for c in cases() if c.key == "bend")
    surface = case.surface()
    rng = np.random.default_rng(1)
    s = np.linspace(0.0, surface.length, 9)
    th = np.linspace(0.0, 2.5 * np.pi, 9) + 0.05 * rng.standard_normal(9)
    _, grad = length_and_gradient(surface, s, th)
    h = 1e-6
    for i in (1, 4, 7):
        for j, arr in enumerate((s, th)):
            up, dn = arr.copy(), arr.copy()
            up[i] += h
            dn[i] -= h
            args_up = (up, th) if j == 0 else (s, up)
            args_dn = (dn, th) if j == 0 else (s, dn)
            fd = (length_and_gradient(surface, *args_up)[0] - length_and_gradient(surface, *args_dn)[0]) / (2 * h)
            assert grad[i - 1, j] == pytest.approx(fd, rel=1e-5, abs=1e-7)


def test_mesh_grid_and_seed_chain_wind_the_rounds():
    case = next(c for c in cases() if c.key == "ellipse")
    surface = case.surface()
    grid = grid_for(surface, 20_000, (0.0, np.pi / 2))
    assert grid.nt % 4 == 0 and abs(grid.triangles - 20_000) < 0.1 * 20_000
    a, b = case.ends_s(surface)
    chain = seed_chain(surface, grid, a, b, case.rounds)
    j = np.array(chain) % grid.nt
    turned = np.sum(np.mod(np.diff(j), grid.nt)) / grid.nt  # forward angle steps, in turns
    assert turned == pytest.approx(2.25)
    assert chain[0] == 0 and chain[-1] == (grid.ns - 1) * grid.nt + grid.nt // 4


def test_verdicts_say_plainly_where_winder_is_behind():
    def pt(method, seconds, err, setting="x"):
        return {"method": method, "seconds": seconds, "rel_error": err, "setting": setting, "param": 0}

    result = {"points": [pt("newton", 0.010, 1e-6), pt("newton", 0.020, 1e-9),
                         pt("newton_richardson", 0.030, 1e-9),
                         pt("collocation", 0.005, 1e-6), pt("collocation", 0.100, 1e-10),
                         pt("shooting", 0.0105, 1e-5)], "lbfgs": []}
    front = frontier(result)
    v = verdicts(front)
    levels = {item["level"]: item for item in v["newton"]}
    assert set(levels) == {1e-4, 1e-5, 1e-6}  # collocation faster down to 1e-6; behind from 1e-7
    kinds = {b["baseline"]: b["kind"] for b in levels[1e-5]["baselines"]}
    assert kinds == {"collocation": "faster", "shooting": "tie"}
    text = verdict_text("Bend", "newton", levels[1e-6])
    assert "is faster" in text and "2.00x as long" in text
    # Richardson reaches nothing above 1e-9 faster than collocation, and only 1e-9 at all from its sweep.
    rich = {item["level"] for item in v["newton_richardson"]}
    assert rich == {1e-4, 1e-5, 1e-6}


def test_speed_check_runs_and_reports_its_stop():
    from bench.speed import measure  # noqa: PLC0415

    rep = measure(repeats=1, lbfgs_cap=20, sizes=(100,))
    assert rep.lbfgs_iterations <= 20 and rep.lbfgs_stop == "iteration cap"
    assert rep.newton_change < 1e-12  # Newton is converged: one more solve leaves the length alone
    assert [n for n, _ in rep.growth] == [100]


def test_a_refused_example_is_a_row_of_its_own(monkeypatch, tmp_path):
    """One example that a tool refuses is reported as failed; the other examples still get figures."""
    from bench import fiberpath_jobs  # noqa: PLC0415

    def refuse(argv):
        raise RuntimeError(f"{argv[0]} exited 1: Error: the payout eye comes too close")

    monkeypatch.setattr(fiberpath_jobs, "_timed", refuse)
    row = fiberpath_jobs._job("cone_reducer", 1)
    assert row["error"].endswith("the payout eye comes too close")
    page = "\n".join(fiberpath_jobs.markdown({"jobs": [row], "startup_s": {}, "startup_targets_s": {},
                                              "imports": []}))
    assert "| cone_reducer | - | - | failed: `" in page


def test_the_installed_copy_is_this_tree_without_an_editable_finder(tmp_path):
    """Whole jobs are timed on winder as `pip install .` leaves it: this tree's code, byte-compiled, and
    no editable-install path finder loaded at start."""
    import subprocess  # noqa: PLC0415

    from bench.fiberpath_jobs import installed_winder  # noqa: PLC0415

    with installed_winder() as script:
        probe = ("import sys, winder; print(winder.__file__); "
                 "print(any('editable' in m for m in sys.modules))")
        where, editable = subprocess.run([str(script.parent / "python"), "-c", probe], cwd=tmp_path,
                                         capture_output=True, text=True, check=True).stdout.split()
        assert Path(where).is_relative_to(script.parent.parent) and editable == "False"
        assert list(Path(where).parent.glob("__pycache__/*.pyc"))
        check = subprocess.run([str(script), "check", str(ROOT / "samples" / "pipe.yaml")], cwd=tmp_path,
                               capture_output=True, text=True)
        assert check.returncode == 0, check.stderr
