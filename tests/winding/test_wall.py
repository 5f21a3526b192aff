"""The laminate through the planner and the outputs: material config and its errors, build-up layer
on layer (outer radius, Clairaut on the grown vessel), masses, the layup CSV, and no change at all
for jobs without a material."""

import csv
import io
import json
import math

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.errors import ConfigError
from winder.machine.program import build_program
from winder.export.layup import HEADER, layup_csv_text
from winder.export.summary import summary_dict
from winder.winding.buildup import share_around
from winder.winding.laminate import helical_mean_thickness
from winder.winding.plan import plan

RADIUS_RTOL = 1e-3  # outer radius against R plus the closed-form means (issue: 1e-3)
MASS_RTOL = 1e-9
VOLUME_RTOL = 1e-2
CLAIRAUT_RTOL = 1e-6

TEX = {"fiber_tex": 800, "tows": 4, "fiber_density": 1.78, "resin_density": 1.15, "fiber_volume_fraction": 0.6}
PLY = 4 * 800 / (1000 * 1.78) / 0.6 / 10.0  # mm, band width 10
PIPE = {"axis": {"type": "line", "length": 500}, "profile": {"type": "constant", "radius": 50}}
VESSEL = {"profile": {"type": "vessel", "radius": 100, "cylinder_length": 300,
                      "dome": {"type": "hemisphere", "polar_opening": 30}}}


def _job(mandrel, layers, material=TEX, **winding):
    w = {"band_width": 10, "points": 40, "layers": layers, **winding}
    if material is not None:
        w["material"] = material
    return parse_config({"name": "w", "mandrel": mandrel, "winding": w,
                         "machine": {"eye": {"radius": 200}, "feed": 3000}}, "w.yaml")


@pytest.fixture(scope="module")
def pipe_plan():
    return plan(_job(PIPE, [{"type": "helical", "angle": 55}, {"type": "hoop", "passes": 2}],
                     region={"start": 20, "end": 480}, dwell={"start": 10, "end": 10}))


@pytest.fixture(scope="module")
def vessel_plan():
    return plan(_job(VESSEL, [{"type": "helical", "angle": 22}, {"type": "hoop", "passes": 1},
                              {"type": "helical", "angle": 35}]))


# -- config ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("material, message", [
    ({"fiber_tex": 800, "tows": 4, "fiber_density": 1.78}, "winding.material.fiber_volume_fraction: required with fiber_tex"),
    ({**TEX, "fiber_volume_fraction": 1.2}, "winding.material.fiber_volume_fraction: must be in (0, 1)"),
    ({**TEX, "tows": 2.5}, "winding.material.tows:"),
    ({**TEX, "fiber_tex": -3}, "winding.material.fiber_tex: must be"),
    ({**TEX, "ply_thickness": 0.2}, "winding.material.ply_thickness: give fiber_tex (with tows) or ply_thickness, not both"),
    ({"ply_thickness": 12}, "winding.material.ply_thickness: must be smaller than the band width (10 mm), got 12"),
    ({"tows": 4}, "winding.material: needs fiber_tex"),
    ({"ply_thickness": 0.3, "colour": "red"}, "winding.material.colour: unknown key"),
    ({"fiber_tex": 1e5, "tows": 100, "fiber_density": 1.0, "fiber_volume_fraction": 0.5}, "not thinner than its width"),
])
def test_invalid_materials(material, message):
    with pytest.raises(ConfigError) as err:
        _job(PIPE, [{"type": "helical", "angle": 55}], material=material)
    assert str(err.value).startswith("w.yaml: ") and message in str(err.value)


def test_layer_material_override_and_missing():
    job = _job(PIPE, [{"type": "helical", "angle": 55}, {"type": "hoop", "material": {"ply_thickness": 0.5}}])
    assert job.winding.material_of(1).ply_thickness == 0.5 and job.winding.material_of(0).fiber_tex == 800
    with pytest.raises(ConfigError, match=r"layer 1 \(helical 55 deg\): needs a material"):
        _job(PIPE, [{"type": "helical", "angle": 55}, {"type": "hoop", "material": {"ply_thickness": 0.5}}],
             material=None)


# -- build-up ---------------------------------------------------------------------------------------
def test_pipe_outer_radius_is_r_plus_the_means(pipe_plan):
    helical, hoop = pipe_plan.layers
    mean = helical_mean_thickness(PLY, helical.circuits, 10.0, 50.0, math.radians(helical.angle_deg))
    assert helical.laminate.thickness_mm == pytest.approx(mean, rel=RADIUS_RTOL)
    assert hoop.laminate.thickness_mm == pytest.approx(2 * PLY, rel=RADIUS_RTOL)
    assert helical.laminate.outer_radius_mm == pytest.approx(50.0 + mean, rel=RADIUS_RTOL)
    assert hoop.laminate.outer_radius_mm == pytest.approx(50.0 + mean + 2 * PLY, rel=RADIUS_RTOL)
    # the hoops wind on the grown pipe
    r = np.hypot(hoop.passes[0].points[:, 0], hoop.passes[0].points[:, 1])
    np.testing.assert_allclose(r[len(r) // 2], 50.0 + mean, rtol=RADIUS_RTOL)
    s = summary_dict(pipe_plan)
    assert s["outer_radius_mm"] == pytest.approx(50.0 + mean + 2 * PLY, rel=RADIUS_RTOL)
    for layer in pipe_plan.layers:
        assert layer.laminate.volume_mm3 == pytest.approx(layer.fiber_length_mm * PLY * 10.0, rel=VOLUME_RTOL)


def test_masses_by_hand(pipe_plan, vessel_plan):
    for pl in (pipe_plan, vessel_plan):
        for layer in pl.layers:
            lam = layer.laminate
            fiber_kg = layer.fiber_length_mm * 4 * 800 * 1e-6 / 1000
            assert lam.fiber_mass_kg == pytest.approx(fiber_kg, rel=MASS_RTOL)
            assert lam.resin_mass_kg == pytest.approx(fiber_kg * 0.4 / 0.6 * 1.15 / 1.78, rel=MASS_RTOL)
            assert lam.material_length_mm == pytest.approx(4 * layer.fiber_length_mm, rel=MASS_RTOL)
        s = summary_dict(pl)
        total = sum(x.laminate.fiber_mass_kg + x.laminate.resin_mass_kg for x in pl.layers)
        assert s["mass_kg"] == pytest.approx(total, abs=1e-6)


def test_vessel_layers_wind_on_the_grown_vessel(vessel_plan):
    first, hoop, third = vessel_plan.layers
    grown = vessel_plan.surface_of(3)
    big_r = grown.profile.radius
    assert big_r == pytest.approx(hoop.laminate.outer_radius_mm, rel=1e-12)
    assert big_r == pytest.approx(100.0 + first.laminate.thickness_mm + hoop.laminate.thickness_mm, rel=RADIUS_RTOL)
    # Clairaut on the grown vessel: c = R' sin(alpha) on its cylinder, and the solved passes turn there
    c = third.turnaround_radius
    assert c == pytest.approx(big_r * math.sin(math.radians(third.angle_deg)), rel=1e-9)
    p = third.passes[0]
    r = np.hypot(p.points[:, 0], p.points[:, 1])
    assert r.min() == pytest.approx(c, rel=CLAIRAUT_RTOL)
    # the turnaround point is outside the bare dome by about the wall there, inside the opening plane
    assert 0.0 <= p.t.min() and p.t.max() <= vessel_plan.surface.axial_length
    for layer in vessel_plan.layers:
        lam = layer.laminate
        assert np.all(np.isfinite(lam.thickness)) and lam.max_thickness_mm < 20 * lam.thickness_mm
        assert lam.volume_mm3 == pytest.approx(layer.fiber_length_mm * PLY * 10.0, rel=VOLUME_RTOL)


def test_layup_csv(vessel_plan):
    text = layup_csv_text(vessel_plan, 10.0)
    rows = list(csv.DictReader(io.StringIO(text)))
    assert text.splitlines()[0] == HEADER
    assert {int(r["layer"]) for r in rows} == {1, 2, 3}
    third = [r for r in rows if r["layer"] == "3"]
    surf = vessel_plan.surface_of(3)
    mid = min(third, key=lambda r: abs(float(r["t"]) - 0.5 * surf.axial_length))
    assert float(mid["thickness_mm"]) == pytest.approx(vessel_plan.layers[2].laminate.thickness_mm, rel=1e-3)
    assert float(mid["angle_deg"]) == pytest.approx(vessel_plan.layers[2].angle_deg, abs=1e-3)
    assert math.hypot(float(mid["x"]), float(mid["y"])) == pytest.approx(surf.profile.radius, abs=2e-6)
    assert all(float(r["thickness_mm"]) > 0 for r in rows)


def test_no_material_no_laminate():
    pl = plan(_job(PIPE, [{"type": "helical", "angle": 55}], material=None, region={"start": 20, "end": 480}))
    assert all(layer.laminate is None and layer.surface is None for layer in pl.layers)
    s = json.loads(json.dumps(summary_dict(pl)))
    assert "mass_kg" not in s and "thickness_mm" not in s["layers"][0]
    with pytest.raises(ConfigError, match="winding.material: required for --format layup"):
        layup_csv_text(pl, 10.0)


def test_share_around_keeps_the_section_mean(pipe_plan):
    layer = pipe_plan.layers[0]
    s = np.linspace(60.0, 440.0, 7)
    theta = np.arange(48) * 2 * np.pi / 48
    share = share_around(pipe_plan.surface, layer.passes, 10.0, s, theta)
    # a cylinder: |Phi_theta| is the same all around, so the plain mean is 1; circuits tile the
    # perimeter once per direction, so two bands (one each way) cover almost every angle
    np.testing.assert_allclose(share.mean(axis=1), 1.0, rtol=1e-12)
    counts = share * (2 * layer.circuits * 10.0 / (2 * np.pi * 50.0 * math.cos(math.radians(layer.angle_deg))))
    assert np.median(np.round(counts)) == 2


def test_the_eye_clears_the_finished_part():
    job = parse_config({"name": "w", "mandrel": PIPE, "machine": {"eye": {"clearance": 20}, "feed": 3000},
                        "winding": {"band_width": 10, "points": 40, "material": TEX, "region": {"start": 20, "end": 480},
                                    "layers": [{"type": "helical", "angle": 55}, {"type": "hoop", "passes": 3}]}},
                       "w.yaml")
    pl = plan(job)
    outer = pl.layers[-1].laminate.outer_radius_mm
    assert pl.outer_surface.radius(np.array([250.0]), np.zeros(1))[0] == pytest.approx(outer, rel=1e-9)
    program = build_program(pl, job.machine)
    # The clearance holds over the laminate (past the region's ends the part, and the eye, are lower).
    over = (program.values[:, 0] >= 20.0 + 20.0) & (program.values[:, 0] <= 480.0 - 20.0)
    assert over.sum() > 10 and program.values[over, 2].min() >= outer + 20.0 - 1e-6


@pytest.mark.parametrize("mandrel, angle", [
    (VESSEL, 22),
    ({"profile": {"type": "vessel", "radius": 80, "cylinder_length": 250,
                  "dome": {"type": "isotensoid", "polar_opening": 20},
                  "end_dome": {"type": "isotensoid", "polar_opening": 30}}}, 28),
])
def test_a_second_layer_at_the_same_angle_turns_on_the_first_ones_pile_up(mandrel, angle):
    # next to a small opening the first layer's pile-up cannot be followed along the normal (its edge
    # would turn the meridian back); the grown shape fills it, lowered near the opening so that the
    # same angle still turns around there, on top of the pile-up
    pl = plan(_job(mandrel, [{"type": "helical", "angle": angle}, {"type": "helical", "angle": angle}],
                   material={"ply_thickness": 0.3}, points=30))
    first, second = pl.layers
    # on the pile-up: within its band (each layer's pattern moves its own c a little)
    assert abs(second.turnaround_radius - first.turnaround_radius) < 0.5 * 10.0
    grown = pl.surface_of(2)
    ends = (grown.profile.dome.end_radius, grown.profile.end_dome.end_radius)
    assert max(ends) + 5.0 < second.turnaround_radius  # the band still clears the grown opening
    p = second.passes[0]
    assert np.hypot(p.points[:, 0], p.points[:, 1]).min() == pytest.approx(second.turnaround_radius, rel=CLAIRAUT_RTOL)
