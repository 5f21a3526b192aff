"""winder.winding.budget: the work of a job, from the config and the surface, before any path.

Truths: the closed-form circuit count N_c = ceil(P cos(alpha) / B) with P = 2 pi r (docs/math/05-winding.md), the
hoop's turns (region length / pitch, one band width of advance per turn) and the planner's own
result on the same job (the budget holds it from above).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from winder.app.validate import validate
from winder.config.job import load_config
from winder.errors import ConfigError
from winder.geometry.build import build_surface
from winder.winding import budget as bud
from winder.winding.plan import plan
from winder.winding.results import PassKind
from winder.winding.turnaround import turnaround_points

ROOT = Path(__file__).resolve().parents[2]
HOSTILE = ROOT / "tests" / "app" / "hostile"
PIPE = ROOT / "samples" / "pipe.yaml"


def _surface(path: Path):
    job = load_config(path)
    return build_surface(job.mandrel, job.source, job.name)


def _budget(path: Path) -> bud.Budget:
    job = load_config(path)
    return bud.check_budget(job, build_surface(job.mandrel, job.source, job.name))


def test_pipe_budget_matches_the_closed_form_and_holds_the_plan() -> None:
    budget = _budget(PIPE)
    helical, hoop = budget.layers
    assert helical.circuits == math.ceil(2 * math.pi * 50 * math.cos(math.radians(55)) / 10)  # 19
    assert helical.passes == 2 * helical.circuits
    assert helical.pass_points == 30 + 2
    pitch = 10 / math.sqrt(1 - (10 / (2 * math.pi * 50)) ** 2)
    assert hoop.pass_points == math.ceil((480 - 20) / pitch * 360 / 5) + 1
    assert 2 * hoop.pass_points <= hoop.points <= 2 * hoop.pass_points + turnaround_points(
        _surface(PIPE), (20.0, 480.0))  # and the reversal between the two traverses
    planned = plan(load_config(PIPE))
    assert [layer.circuits for layer in planned.layers][0] == helical.circuits
    laid = [sum(p.s.size for p in layer.passes) for layer in planned.layers]
    traverses = [p.s.size for p in planned.layers[1].passes if p.kind is PassKind.HOOP]
    assert laid[0] <= helical.points and traverses == [hoop.pass_points] * 2 and laid[1] <= hoop.points
    assert budget.points == helical.points + hoop.points
    assert budget.memory_bytes < bud.MAX_MEMORY_BYTES


@pytest.mark.parametrize("name, key, limit", [
    ("band_1e-6", "winding.band_width", str(bud.MAX_CIRCUITS)),
    ("hoop_band_1e-4", "winding.band_width", str(bud.MAX_PASS_POINTS)),
    ("hoop_89_999", "layer 1 (hoop 89.999 deg).angle", str(bud.MAX_PASS_POINTS)),
    ("hoop_passes_1e6", "layer 1 (hoop).passes", str(bud.MAX_PASSES)),
    ("pattern_factor", "layer 1 (helical 55 deg).pattern", "19 circuits"),
])
def test_past_a_limit_is_refused_naming_key_and_limit(name: str, key: str, limit: str) -> None:
    with pytest.raises(ConfigError) as info:
        _budget(HOSTILE / f"{name}.yaml")
    assert info.value.exit_code == 2
    assert info.value.key_path == key and limit in info.value.message
    assert f"{name}.yaml: {key}: " in str(info.value)


def test_total_points_and_memory_are_held(tmp_path: Path) -> None:
    text = PIPE.read_text(encoding="utf-8")
    many = tmp_path / "many.yaml"
    # 2000 passes of 3,300 points each: every pass is fine, the job is not.
    many.write_text(text.replace("{type: hoop, passes: 2}", "{type: hoop, passes: 2000}"), encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        _budget(many)
    assert info.value.key_path == "layer 2 (hoop).passes" and str(bud.MAX_TOTAL_POINTS) in info.value.message
    fine = tmp_path / "fine.yaml"
    # One circuit of 100,000 points per pass: few points in all, but the tangent solve of a pass
    # (4 times finer, with its Richardson twin) would need about 2 GB.
    fine.write_text(text.replace("points: 30 ", "points: 100000 ").replace("band_width: 10", "band_width: 300")
                    .replace("    - {type: hoop, passes: 2}\n", ""), encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        _budget(fine)
    assert info.value.key_path == "winding.points" and "GB of memory" in info.value.message
    hoops = tmp_path / "hoops.yaml"
    # One hoop traverse of 0.05 mm pitch over 460 mm, 9,200 turns: 662,000 points and 2.1 GB of it
    # alone; the memory comes from the hoop's turns, not from winding.points.
    hoops.write_text(text.replace("band_width: 10", "band_width: 0.05").replace(
        "    - {type: helical, angle: 55, pattern: auto}\n", "").replace("{type: hoop, passes: 2}", "{type: hoop, passes: 1}"),
        encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        _budget(hoops)
    assert info.value.key_path == "layer 1 (hoop)" and "GB of memory" in info.value.message


def test_validate_refuses_what_run_needs() -> None:
    with pytest.raises(ConfigError) as info:
        validate(HOSTILE / "no_winding.yaml")
    assert info.value.key_path == "winding" and "required key missing" in info.value.message
    job, surface, budget = validate(PIPE)
    assert job.name == "pipe" and budget.points > 0 and surface.axial_length == 500


ESTIMATE_WITHIN = 1.5  # the memory estimate against the measured peak, either way (issue 29)


def test_memory_estimate_holds_a_part_within_1_5x(tmp_path: Path) -> None:
    """The estimate against ru_maxrss of `winder run` in a fresh process, on a quick realistic part (the
    cone reducer, about 2 s); the slow parts and the vessels: tests/app/test_hostile_budget.py, nightly."""
    from tests.sandbox import run_limited

    part = ROOT / "parts" / "cone_reducer.yaml"
    (result,), = run_limited([[["run", str(part), "-o", str(tmp_path / "out")]]], seconds=120)
    assert result["code"] == 0, result["stderr"]
    estimate = _budget(part).memory_bytes / 2**20
    assert 1.0 / ESTIMATE_WITHIN < estimate / result["peak_mb"] < ESTIMATE_WITHIN, (estimate, result["peak_mb"])
