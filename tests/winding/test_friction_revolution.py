"""slip: auto on open surfaces of revolution (docs/math/09): a cone whose geodesic turns around before
the narrow end is held at its angle by friction. Truths: the cone's closed form lambda = r' / sin(alpha),
against the slip measured from the laid passes' points (winder.winding.slip); the pass's angle from its
points; Clairaut for where the geodesic would turn."""

from __future__ import annotations

import math

import numpy as np
import pytest

from winder.app.validate import validate_job
from winder.config.job import parse_config
from winder.errors import ConfigError

SLOPE = -50.0 / 400.0  # the reducer: cone 100 -> 50 over 400 mm
SLIP_TOL = 1e-3  # measured |k_g / k_n| from the polyline (winder.winding.slip.SLIP_MARGIN) vs closed form
ANGLE_TOL = 0.05  # deg: the winding angle measured from the laid points (chords of 200-point passes)


def reducer(friction: float, angle: float = 45.0):
    mandrel = {"axis": {"type": "line", "length": 400}, "profile": {"type": "cone", "start_radius": 100,
                                                                    "end_radius": 50}}
    return parse_config({"name": "reducer", "mandrel": mandrel,
                         "winding": {"band_width": 10, "friction": friction,
                                     "layers": [{"type": "helical", "angle": angle, "slip": "auto"}]}}, "r.yaml")


def test_reducer_held_at_its_angle_with_the_closed_form_slip():
    from winder.winding.plan import plan  # noqa: PLC0415

    job = reducer(0.2)
    assert 100.0 * math.sin(math.radians(45.0)) > 50.0  # Clairaut: the geodesic cannot reach the narrow end
    validate_job(job)
    layer = plan(job).layers[0]
    assert layer.max_slip == pytest.approx(abs(SLOPE) / math.sin(math.radians(45.0)), abs=SLIP_TOL)
    assert layer.min_normal_curvature > 0.0
    assert layer.coverage.covered_fraction >= 0.999
    wound = [p for p in layer.passes if p.kind.name in ("FORWARD", "RETURN")]
    angles = np.concatenate([np.abs(p.alpha_deg[1:-1]) for p in wound])
    assert np.all(np.abs(angles - 45.0) < ANGLE_TOL)


def test_reducer_refused_by_check_naming_the_friction_it_needs():
    with pytest.raises(ConfigError, match=r"only with friction 0\.177 .*above winding\.friction 0\.1") as info:
        validate_job(reducer(0.1))
    assert info.value.key_path == "winding.friction"


def test_a_geodesic_that_reaches_stays_geodesic():
    from winder.winding.plan import plan  # noqa: PLC0415

    layer = plan(reducer(0.2, angle=25.0)).layers[0]  # 100 sin 25 = 42 < 50: Clairaut reaches
    assert layer.max_slip < SLIP_TOL
