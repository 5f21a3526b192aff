"""The report stage: pictures that are right, not just present, in a page that opens offline.

Truths from outside the report code: the planner's own coverage (winder.coverage) for the bare
fraction, the plan's circuit counts for the bands, brute-force sampling for the interval unions, and a
real headless browser (Chromium over the DevTools protocol, report_browser.py) for the page.
"""

from __future__ import annotations

import dataclasses
import html.parser
import os
import re
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from every_job import job_of, planned as planned_once  # each sample planned once per session
from winder.errors import ConfigError
from winder.export.summary import summary_dict
from winder.report.bands import Crossings, band_counts, covered_fraction
from winder.report.coverage_map import layer_coverage_map
from winder.report.vessel import is_wound_vessel
from winder.report.html import report_html
from winder.report.profiles import angle_profile, profiles_figure
from winder.report.tables import layer_table
from winder.report.unrolled import unrolled_bands, unrolled_figure, wrapped
from winder.geometry.sections import arc_map

SAMPLES = sorted((Path(__file__).resolve().parents[2] / "samples").glob("*.yaml"))
BARE_TOL = 1e-3  # the agreement between the map and the summary
MAX_REPORT_BYTES = 10_000_000
UNION_TOL = 1e-12  # exact unions: rounding only
ANGLE_TOL_DEG = 1e-6


@pytest.fixture(scope="module")
def planned():
    """name -> (plan, summary dict, band width) of every sample."""
    out = {}
    for path in SAMPLES:
        job, plan = job_of(path), planned_once(path)
        out[job.name] = (plan, summary_dict(plan), job.winding.band_width)
    return out


# -- the numbers in the pictures ----------------------------------------------------------------------
def test_bare_fraction_equals_one_minus_covered_on_every_sample(planned):
    seen = 0
    for name, (plan, summary, band_width) in planned.items():
        arcs = arc_map(plan.surface.section)
        for layer, row in zip(plan.layers, summary["layers"]):
            m = layer_coverage_map(plan, layer, arcs, band_width)
            expected = 1.0 - row["coverage"]["covered_fraction"]
            assert abs(m.bare_fraction - expected) <= BARE_TOL, (name, layer.index, m.bare_fraction, expected)
            seen += 1
    assert seen >= len(SAMPLES)


def test_gaps_show_where_the_summary_says_coverage_is_incomplete(planned):
    for name, (plan, summary, band_width) in planned.items():
        arcs = arc_map(plan.surface.section)
        for layer, row in zip(plan.layers, summary["layers"]):
            m = layer_coverage_map(plan, layer, arcs, band_width)
            incomplete = row["coverage"]["covered_fraction"] < 0.99
            assert bool(m.gap.any()) == incomplete, (name, layer.index)
            # A +-alpha layer is two band layers where it is even: where it has no gap it has at least
            # one band of each direction.
            laid = m.count > 0
            assert np.all(m.count[laid & ~m.gap] >= (2 if layer.type.value == "helical" else 1)), name


def test_unrolled_band_count_is_twice_the_circuits_of_each_helical_layer(planned):
    for name, (plan, _, _) in planned.items():
        arcs = arc_map(plan.surface.section)
        titles = [f"layer {layer.index}" for layer in plan.layers]
        fig = unrolled_figure(plan, arcs, titles)
        for layer in plan.layers:
            if layer.type.value != "helical":
                continue
            drawn = [tr for tr in fig["data"] if tr["meta"]["layer"] == layer.index
                     and tr["meta"]["kind"] in ("forward", "return")]
            assert sum(tr["meta"]["bands"] for tr in drawn) == 2 * layer.circuits, name
            # Each direction carries one band per circuit, every circuit once.
            for tr in drawn:
                circuits = {c for c, y in zip(tr["customdata"], tr["y"]) if y is not None}
                assert circuits == set(range(1, layer.circuits + 1)), (name, tr["name"])
            assert len(unrolled_bands(arcs, layer)) == 2 * layer.circuits


def test_unrolled_lines_stay_on_the_plane_and_follow_the_pass(planned):
    plan, _, _ = planned["elliptic_tube"]
    arcs = arc_map(plan.surface.section)
    for band in unrolled_bands(arcs, plan.layers[0])[:6]:
        ok = np.isfinite(band.u_deg)
        assert np.all((band.u_deg[ok] >= 0.0) & (band.u_deg[ok] <= 360.0))
        assert band.t[ok].min() >= 0.0 and band.t[ok].max() <= plan.surface.axial_length + 1e-9


def test_wrapped_cuts_at_whole_turns_by_linear_interpolation():
    t = np.array([0.0, 10.0, 20.0])
    turns = np.array([0.5, 1.5, 0.75])  # up through 1, back down through 1
    tt, uu = wrapped(t, turns)
    np.testing.assert_allclose(tt[[0, 1, 3, 4, 5, 7, 8]], [0.0, 5.0, 5.0, 10.0, 10 + 20 / 3, 10 + 20 / 3, 20.0])
    np.testing.assert_allclose(uu[[0, 1, 3, 4, 5, 7, 8]], [180.0, 360.0, 0.0, 180.0, 0.0, 360.0, 270.0])
    assert np.isnan(uu[[2, 6]]).all()


def test_winding_angle_profile_on_the_pipe(planned):
    plan, summary, _ = planned["pipe"]
    t = np.linspace(30.0, 470.0, 50)
    for layer in plan.layers:
        lo, mean, hi = angle_profile(layer, t)
        np.testing.assert_allclose(mean, layer.angle_deg, atol=1e-3)  # a helix on a cylinder
        assert np.all(lo <= mean + ANGLE_TOL_DEG) and np.all(mean <= hi + ANGLE_TOL_DEG)
    lo, _, _ = angle_profile(plan.layers[0], np.array([1.0, 499.0]))
    assert np.isnan(lo).all()  # outside the winding region nothing lies


THICKNESS_WRITTEN_TOL = 0.0005 + 1e-9  # mm: y is written with 3 decimals


def test_a_laminate_gets_a_thickness_panel(planned):
    """The sample with a material: each layer's thickness per station, stacked, as the build-up
    computed it; a plan without a material has no thickness panel."""
    plan, _, band_width = planned["vessel_laminate"]
    arcs = arc_map(plan.surface.section)
    maps = tuple(layer_coverage_map(plan, layer, arcs, band_width) for layer in plan.layers)
    fig = profiles_figure(plan, maps, [str(layer.index) for layer in plan.layers])
    panels = [tr for tr in fig["data"] if tr.get("stackgroup") == "mm"]
    assert len(panels) == len(plan.layers) and "yaxis3" in fig["layout"]
    # The stations themselves (x is written to 0.01 mm, which on the band-spread edge of a turnaround,
    # rising from zero over a few mm, moves the thickness by more than its own 3 decimals).
    from winder.report.profiles import PROFILE_STATIONS  # noqa: PLC0415

    t = np.linspace(0.0, plan.surface.axial_length, PROFILE_STATIONS)
    for tr, layer in zip(panels, plan.layers):
        np.testing.assert_allclose(tr["x"], t, atol=0.005)
        lam = layer.laminate
        want = np.interp(t, lam.t, lam.thickness, left=0.0, right=0.0)
        np.testing.assert_allclose(tr["y"], want, rtol=0.0, atol=THICKNESS_WRITTEN_TOL)
    pipe, _, _ = planned["pipe"]
    pipe_maps = tuple(layer_coverage_map(pipe, layer, arc_map(pipe.surface.section), band_width)
                      for layer in pipe.layers)
    assert "yaxis3" not in profiles_figure(pipe, pipe_maps, ["a", "b"])["layout"]


def test_the_table_grows_with_what_the_summary_carries(planned):
    _, summary, _ = planned["vessel_hemi"]
    extra = ("max_slip", "thickness_mm", "fiber_mass_kg", "resin_mass_kg")
    bare = dict(summary, layers=[{k: v for k, v in row.items() if k not in extra} for row in summary["layers"]])
    plain = layer_table(bare)
    assert "friction used" not in plain and "thickness" not in plain
    richer = dict(bare, layers=[dict(row, max_slip=0.05, thickness_mm=0.61, fiber_mass_kg=0.25,
                                     resin_mass_kg=0.1) for row in bare["layers"]])
    text = layer_table(richer)
    for header in ("friction used", "thickness", "fiber mass", "resin mass"):
        assert header in text
    assert "0.0500" in text and "0.610" in text


# -- exact unions ---------------------------------------------------------------------------------------
def _brute(rows: int, centre: np.ndarray, half: np.ndarray, row: np.ndarray, n: int = 200_000) -> np.ndarray:
    u = (np.arange(n) + 0.5) / n
    out = np.zeros(rows)
    for r in range(rows):
        on = np.zeros(n, bool)
        for c, h in zip(centre[row == r], half[row == r]):
            d = np.abs((u - c + 0.5) % 1.0 - 0.5)
            on |= d < h
        out[r] = on.mean()
    return out


def test_union_of_bands_on_a_circle_closed_forms():
    # One band across the seam: [0.85, 1.05) covers 0.2. Two overlapping: [0.1, 0.3) u [0.2, 0.5) = 0.4.
    # One wider than the perimeter covers it once.
    c = Crossings(np.array([0, 1, 1, 2]), np.array([0.95, 0.2, 0.35, 0.5]), np.array([0.1, 0.1, 0.15, 0.7]))
    np.testing.assert_allclose(covered_fraction(c, 4), [0.2, 0.4, 1.0, 0.0], atol=UNION_TOL)
    counts = band_counts(c, 4, 20)
    assert counts[0].tolist() == [1] + [0] * 16 + [1, 1, 1]
    assert counts[2].tolist() == [1] * 20 and counts[3].sum() == 0


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 2), st.floats(0.0, 0.999), st.floats(0.001, 0.3)), min_size=1,
                max_size=12))
def test_union_matches_brute_force_sampling(bands):
    row = np.array([b[0] for b in bands])
    centre = np.array([b[1] for b in bands])
    half = np.array([b[2] for b in bands])
    exact = covered_fraction(Crossings(row, centre, half), 3)
    np.testing.assert_allclose(exact, _brute(3, centre, half, row), atol=2e-5 * (len(bands) + 1))
    cells = band_counts(Crossings(row, centre, half), 3, 4000)
    np.testing.assert_allclose((cells > 0).mean(axis=1), exact, atol=2.0 * len(bands) / 4000)


# -- the page -----------------------------------------------------------------------------------------
class _Page(html.parser.HTMLParser):
    VOID = {"meta", "br", "img", "input", "link", "hr", "col", "area", "base", "embed", "source", "wbr"}

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack, self.errors, self.scripts, self.external, self.inline_js = [], [], 0, [], 0
        self.doctype = False

    def handle_decl(self, decl):
        self.doctype = self.doctype or decl.lower() == "doctype html"

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        for key in ("src", "href"):
            value = (attrs.get(key) or "").strip()
            if value and not value.startswith(("#", "data:", "blob:")):
                self.external.append(f"<{tag} {key}={value}>")
        if tag == "script":
            self.scripts += 1
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else None}>")
        else:
            self.stack.pop()


def _largest(planned) -> str:
    return max(planned, key=lambda n: sum(p.t.size for layer in planned[n][0].layers for p in layer.passes))


def test_the_page_is_valid_self_contained_html_under_the_size_limit(planned):
    name = _largest(planned)
    plan, summary, band_width = planned[name]
    text = report_html(plan, summary, band_width)
    page = _Page()
    page.feed(text)
    page.close()
    assert page.doctype and not page.errors and not page.stack, (page.errors, page.stack)
    assert page.external == []  # no script, stylesheet or image from anywhere else
    assert not re.search(r"<script[^>]+src=", text)
    assert text.count("plotly.js v") == 1 or text.count("* plotly.js") == 1  # the bundle, once
    # four figures, and the domes as wound on a vessel with a laminate (winder.report.vessel)
    assert text.count("Plotly.newPlot(") == 4 + is_wound_vessel(plan)
    assert len(text.encode("utf-8")) < MAX_REPORT_BYTES
    assert plan.band_width == band_width  # the plan carries the band it was laid with
    assert report_html(plan, summary) == text  # same plan, same bytes


def test_progress_is_reported_through_the_callback_only(planned, capsys):
    plan, summary, band_width = planned["pipe"]
    calls = []
    report_html(plan, summary, band_width, progress=lambda fraction, label: calls.append((fraction, label)))
    fractions = [c[0] for c in calls]
    assert len(calls) >= len(plan.layers) + 4 and fractions == sorted(fractions) and fractions[-1] == 1.0
    assert capsys.readouterr() == ("", "")  # the library never prints


def test_without_plotly_the_report_says_how_to_install_it(planned, monkeypatch):
    plan, summary, band_width = planned["pipe"]
    for mod in [m for m in sys.modules if m == "plotly" or m.startswith("plotly.")]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setitem(sys.modules, "plotly", None)  # import plotly -> ImportError
    with pytest.raises(ConfigError) as err:
        report_html(plan, summary, band_width)
    assert err.value.exit_code == 2 and 'pip install "winder[plot]"' in str(err.value)


# -- in a real browser --------------------------------------------------------------------------------
READY = ("document.querySelectorAll('.js-plotly-plot').length === {figures} && "
         "document.querySelector('#winder-view3d canvas') !== null")
MIN_3D_COLORS = 200  # a WebGL view that did not draw shows the page background and a few text pixels
MIN_BAND_PIXELS = 200  # pixels of the first layer's +alpha color in the 3D view
COLOR_NEAR = 60  # RGB distance counted as the band's color (antialiasing, depth shading)
SETTLE_S = 0.3
DRAW_ATTEMPTS = 20


def _drawn(rb, png: bytes) -> tuple[int, int]:
    """Distinct colors in the 3D view's screenshot, and pixels of the first layer's +alpha color."""
    pixels = rb.png_pixels(png)[..., :3].astype(int)
    plus = np.array([int("1f77b4"[i:i + 2], 16) for i in (0, 2, 4)])
    return rb.distinct_colors(pixels), int((np.linalg.norm(pixels - plus, axis=2) < COLOR_NEAR).sum())


LAPTOP_WIDTH_PX = 1280  # a shop laptop's browser window
FIT = ("(() => { const t = document.querySelector('table.layers'), s = t.closest('section');"
       " return [t.getBoundingClientRect().right, s.getBoundingClientRect().right,"
       " document.documentElement.scrollWidth, innerWidth]; })()")


@dataclasses.dataclass(frozen=True)
class BrowserSeen:
    """What one sample's report showed in the browser: the load, the 3D view's screenshot (distinct
    colors, band pixels, the PNG), everything seen up to the last screenshot, and the layer table's
    fit (table right, section right, page width, window width)."""

    load: object
    colors: int
    band: int
    png: bytes
    late: object
    fit: list


@pytest.fixture(scope="module")
def in_browser(planned, tmp_path_factory) -> dict[str, BrowserSeen]:
    """Every sample's report loaded once in a laptop-wide window, for the browser tests below: a page
    takes about 7 s to load and draw in software WebGL, so the two tests share each load (the 3D
    view is checked at the laptop width, not the browser's default 1400 px)."""
    import report_browser as rb  # noqa: PLC0415 - beside this file (pytest puts the folder on the path)

    exe = rb.find_browser()
    if exe is None:
        pytest.skip("no chromium found (apt-get install chromium); the browser check of the report did not run")
    folder = tmp_path_factory.mktemp("pages")
    out = {}
    with rb.Browser(exe, width=LAPTOP_WIDTH_PX) as browser:
        for name, (plan, summary, band_width) in planned.items():
            page = folder / f"{name}.html"
            page.write_text(report_html(plan, summary, band_width), encoding="utf-8")
            load = browser.load(page, READY.format(figures=4 + is_wound_vessel(plan)), settle=SETTLE_S)
            fit = browser.evaluate(FIT)
            for _ in range(DRAW_ATTEMPTS):  # software WebGL may still be drawing: look again
                png = browser.screenshot(browser.rect("#winder-view3d"))
                colors, band = _drawn(rb, png)
                if colors >= MIN_3D_COLORS and band >= MIN_BAND_PIXELS:
                    break
                time.sleep(SETTLE_S)
            late = browser.seen()  # everything since the page was opened, the drawing included
            out[name] = BrowserSeen(load, colors, band, png, late, fit)
    return out


def test_every_sample_report_loads_in_a_headless_browser_and_the_3d_view_draws(in_browser):
    keep = os.environ.get("WINDER_REPORT_SCREENSHOTS")
    for name, seen in in_browser.items():
        assert seen.load.errors == [], (name, seen.load.errors)
        assert seen.load.requests == [], (name, seen.load.requests)
        if keep:
            Path(keep).mkdir(parents=True, exist_ok=True)
            (Path(keep) / f"{name}.view3d.png").write_bytes(seen.png)
        assert seen.colors >= MIN_3D_COLORS, (name, seen.colors)
        assert seen.band >= MIN_BAND_PIXELS, (name, seen.band)
        assert seen.late.errors == [] and seen.late.requests == [], (name, seen.late)


def test_the_layer_table_fits_its_section_in_a_laptop_window(in_browser):
    # Columns past the section's edge are cut off the card and need a sideways scroll of the whole page
    # to be found: the time and fiber columns of a laminate went missing that way.
    for name, seen in in_browser.items():
        table_right, section_right, page_width, window = seen.fit
        assert table_right <= section_right and page_width <= window, (name, table_right, section_right,
                                                                       page_width, window)
