"""Each pass's tension from the config (winder.machine.tension): the uniform-prestress schedule on a
laminate leaves every layer the residual once the wall is wound (docs/math/16), falls from the inner
layers to the outer, and is refused where a layer would need more than its max, or where the plies'
stiffness is not known."""

from __future__ import annotations

import numpy as np
import pytest

from winder.analysis.prestress import RingStack, residual_tensions
from winder.config.job import parse_config
from winder.errors import ConfigError, SolverError
from winder.machine.tension import pass_tensions
from winder.winding.plan import plan as plan_job

RESIDUAL = 30.0
MATERIAL = {"name": "carbon_epoxy", "fiber_tex": 800, "tows": 4, "fiber_density": 1.78, "resin_density": 1.15,
            "fiber_volume_fraction": 0.6}
JOB = {"name": "prestress", "mandrel": {"axis": {"type": "line", "length": 300},
                                        "profile": {"type": "constant", "radius": 40}},
       "winding": {"band_width": 10, "region": {"start": 30, "end": 270}, "points": 30, "material": MATERIAL,
                   "tension": {"schedule": "uniform_prestress", "residual": RESIDUAL, "radial_modulus": 60},
                   "layers": [{"type": "hoop", "passes": 2}, {"type": "helical", "angle": 60},
                              {"type": "hoop", "passes": 2}, {"type": "hoop", "passes": 2}]},
       "machine": {"eye": {"radius": 80}}}


def _job(tension):
    return parse_config({**JOB, "winding": {**JOB["winding"], "tension": tension}}, "prestress.yaml")


@pytest.fixture(scope="module")
def planned():
    return plan_job(_job(JOB["winding"]["tension"]))


def test_the_schedule_leaves_every_layer_the_residual(planned):
    job = _job(JOB["winding"]["tension"])
    per_pass = pass_tensions(job, planned)
    wound = np.array([values[0] for values in per_pass])
    assert all(len(set(values)) == 1 for values in per_pass)  # one tension per layer
    walls = [layer.laminate for layer in planned.layers]
    thickness = np.array([w.thickness_mm for w in walls])
    stack = RingStack(radius=np.array([w.outer_radius_mm for w in walls]) - thickness / 2, thickness=thickness,
                      angle_deg=np.array([layer.angle_deg for layer in planned.layers]),
                      e1=np.full(4, 147_000.0), e2=np.full(4, 10_300.0),  # carbon_epoxy's table values
                      band_area=10.0 * np.array([w.ply_mm for w in walls]), radial_modulus=np.full(4, 60.0))
    assert residual_tensions(stack, wound) == pytest.approx(np.full(4, RESIDUAL), rel=1e-9)
    assert wound[0] > wound[-1] > RESIDUAL  # the inner layers wound tighter; the outermost by its own loss


def test_a_layer_needing_more_than_max_is_refused(planned):
    job = _job({**JOB["winding"]["tension"], "max": RESIDUAL + 0.5})
    with pytest.raises(SolverError, match=r"layer 1 \(hoop\): the uniform prestress of 30 N needs a winding tension"):
        pass_tensions(job, planned)


def test_the_schedule_needs_the_plies_stiffness(planned):
    material = {k: v for k, v in MATERIAL.items() if k != "name"}
    job = parse_config({**JOB, "winding": {**JOB["winding"], "material": material}}, "prestress.yaml")
    with pytest.raises(ConfigError, match="needs every layer's material with its ply stiffness"):
        pass_tensions(job, planned)
