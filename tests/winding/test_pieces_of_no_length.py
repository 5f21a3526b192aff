"""A vessel without a cylinder (cylinder_length 0): its friction-held passes join the two domes' legs at
the equator without a piece of their own (issue 45: a helical at 89.99 deg turning just under the radius
gave 15 copies of one point, and every spline of the pass, in t, refused the duplicate abscissae).

Truths: a pass of distinct points strictly monotone in t (every spline of coverage and the program reads
it so); and continuity in the cylinder's length: the job with no cylinder is the limit of jobs with a
cylinder of 1e-9 mm (same circuits, fiber length within the fiber a 1e-9 mm cylinder adds).
"""

from __future__ import annotations

import numpy as np
import pytest

from winder.config.job import load_config
from winder.winding.plan import plan

FIBER_RTOL = 1e-6  # a 1e-9 mm cylinder at 89.99 deg adds 5.7e-6 mm of fiber a pass, on ~600 mm passes

VESSEL = """\
name: cyl{cyl}
mandrel:
  profile: {{type: vessel, radius: 100, cylinder_length: {cyl}, dome: {{type: {dome}, polar_opening: 30}}}}
winding:
  band_width: 10
  points: 30
  friction: 0.5
  layers:
    - {{type: helical, angle: {angle}, turnaround_radius: {radius}}}
"""


def _plan(tmp_path, dome: str, angle: float, radius: float, cyl: float):
    path = tmp_path / f"{dome}_{cyl}.yaml"
    path.write_text(VESSEL.format(cyl=cyl, dome=dome, angle=angle, radius=radius), encoding="utf-8")
    return plan(load_config(path))


@pytest.mark.parametrize(("dome", "angle", "radius"), [("isotensoid", 89.99, 99.99), ("hemisphere", 89.99, 99.9),
                                                       ("hemisphere", 89.99, 90.0)])
def test_a_vessel_without_a_cylinder_is_the_limit_of_short_cylinders(tmp_path, dome, angle, radius) -> None:
    bare = _plan(tmp_path, dome, angle, radius, 0)
    short = _plan(tmp_path, dome, angle, radius, 1e-9)
    for layer in bare.layers:
        for p in layer.passes:
            chords = np.linalg.norm(np.diff(p.points, axis=0), axis=1)
            assert chords.min() > 0.0, f"pass {p.number} repeats a point"
            steps = np.diff(p.t) * np.sign(p.t[-1] - p.t[0])
            assert steps.min() > 0.0, f"pass {p.number} is not strictly monotone in t"
    assert [len(x.passes) for x in bare.layers] == [len(x.passes) for x in short.layers]
    assert bare.total_fiber_length_mm == pytest.approx(short.total_fiber_length_mm, rel=FIBER_RTOL)


@pytest.mark.parametrize("cyl", [0, 1e-3])
def test_a_slip_with_no_leg_to_act_on_is_a_refusal_not_an_internal_error(tmp_path, cyl) -> None:
    """slip 0.2 at 89.99 deg: the fiber turns at the equator, its dome legs of no length; closing the
    pattern by their slip had a singular Jacobian (internal LinAlgError): now the solver's refusal."""
    from winder.errors import SolverError  # noqa: PLC0415

    path = tmp_path / "slip.yaml"
    path.write_text(VESSEL.format(cyl=cyl, dome="hemisphere", angle=89.99, radius=50).replace(
        "turnaround_radius: 50", "slip: 0.2"), encoding="utf-8")
    with pytest.raises(SolverError, match="on the first dome: .* lower the angle, or give turnaround_radius"):
        plan(load_config(path))
