"""geometry.self_contact: a bent axis that brings far parts of the mandrel into each other is found;
clear mandrels, tight-but-clear U-turns and a full ring are not refused."""

from __future__ import annotations

import pytest

from winder.config.axes import ArcAxis, PathAxis, SplineAxis
from winder.config.mandrel import CircleSection, ConstantProfile, LineAxis, MandrelConfig
from winder.errors import ConfigError
from winder.geometry.build import build_surface
from winder.geometry.self_contact import find_self_contact

RADIUS = 40.0


def _surface(axis, radius: float = RADIUS):
    return build_surface(MandrelConfig(axis, ConstantProfile(radius), CircleSection()), "t.yaml", "m")


def _u_turn(bend: float) -> PathAxis:
    """Two 200 mm legs joined by a half turn of this bend radius: the legs' axes 2 bend apart."""
    return PathAxis((LineAxis(200.0), ArcAxis(bend, 180.0, 0.0), LineAxis(200.0)))


@pytest.mark.parametrize("axis", [
    _u_turn(41.0),  # legs 82 mm apart, the tube 80 mm thick: clear by 2 mm
    _u_turn(150.0),
    PathAxis((LineAxis(100.0), ArcAxis(150.0, 90.0, 0.0), LineAxis(100.0))),  # the elbow
    ArcAxis(45.0, 360.0, 0.0),  # a full ring: its ends meet, nothing else does
    ArcAxis(150.0, 345.0, 0.0),  # an open ring: its end faces 29 mm apart on the inside
    # a J-hook whose end face stops 5 mm short of the long leg: the ends are not inside anything
    PathAxis((LineAxis(300.0), ArcAxis(100.0, 180.0, 0.0), LineAxis(100.0), ArcAxis(50.0, 90.0, 0.0),
              LineAxis(105.0))),
    PathAxis((ArcAxis(60.0, 180.0, 0.0), ArcAxis(60.0, 180.0, 0.0))),  # the same ring in two halves
    SplineAxis(((0.0, 0.0, 0.0), (0.0, 0.0, 200.0), (100.0, 0.0, 400.0))),
])
def test_clear_mandrels_have_no_contact(axis) -> None:
    assert find_self_contact(_surface(axis)) is None


def test_a_second_half_turn_bringing_the_axis_back_along_the_first_leg() -> None:
    # Up 200, a half turn (R 41) down 200, another half turn the same way: the third leg runs up the
    # first one's axis. No bend folds (41 > 40); only far parts meet.
    assert find_self_contact(_surface(_u_turn(41.0), 30.0)) is None
    with pytest.raises(ConfigError, match=r"t\.yaml: mandrel\.axis: the mandrel runs into itself"):
        _surface(PathAxis((LineAxis(200.0), ArcAxis(41.0, 90.0, 0.0), ArcAxis(41.0, 90.0, 0.0),
                           LineAxis(200.0), ArcAxis(41.0, 180.0, 0.0), LineAxis(150.0))))


def test_two_rounds_of_a_loop_and_a_spline_doubling_back_are_refused() -> None:
    for axis in (PathAxis((ArcAxis(60.0, 300.0, 0.0), ArcAxis(60.0, 300.0, 0.0))),  # round 2 overlaps round 1
                 SplineAxis(((0.0, 0.0, 0.0), (0.0, 0.0, 100.0), (10.0, 0.0, 100.0), (10.0, 0.0, 0.0))),
                 SplineAxis(((0.0, 0.0, 0.0), (0.0, 0.0, 100.0), (0.0, 0.0, 0.1)))):  # a cusp
        with pytest.raises(ConfigError, match="runs into itself") as err:
            _surface(axis, 25.0)
        assert err.value.exit_code == 2


def test_the_contact_names_two_far_stations_and_a_point_inside(monkeypatch) -> None:
    from winder.geometry import build  # noqa: PLC0415

    monkeypatch.setattr(build, "_refuse_self_contact", lambda surface, source: None)
    surface = _surface(SplineAxis(((0.0, 0.0, 0.0), (0.0, 0.0, 100.0), (10.0, 0.0, 100.0), (10.0, 0.0, 0.0))),
                       25.0)
    contact = find_self_contact(surface)
    assert contact is not None and contact.radius == pytest.approx(25.0)
    assert abs(contact.t2 - contact.t1) > 2.0 * 25.0 and contact.distance < contact.radius


def test_a_section_wider_than_round_is_tested_by_its_outline() -> None:
    # An omega (legs 99.4 mm apart) of an ellipse 120 x 40 whose long axes face each other: the legs
    # overlap by about 20 mm although their axes are farther apart than any smallest radius reaches.
    from winder.config.sections import EllipseSection  # noqa: PLC0415

    omega = PathAxis((LineAxis(200.0), ArcAxis(120.0, 45.0, 180.0), ArcAxis(120.0, 270.0, 0.0),
                      ArcAxis(120.0, 45.0, 180.0), LineAxis(200.0)))
    with pytest.raises(ConfigError, match="runs into itself"):
        build_surface(MandrelConfig(omega, ConstantProfile(RADIUS), EllipseSection(60.0, 20.0)), "t.yaml", "m")
    assert find_self_contact(_surface(omega)) is None  # round, 80 mm thick: clear
