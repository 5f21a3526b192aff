"""winder.winding.choices: every listed pattern is what `run` winds when its YAML is pasted as the layer.

Over every sample's helical layers: the planner's own choice is listed and marked; the choices planned
through their pasted YAML (a new config read by the config reader, then `plan`, the whole job) give the
listed circuits, skip, angle (ANGLE_TOL) and coverage (COVERAGE_TOL), and the fiber length within
LENGTH_RTOL. The samples whose choices cost seconds each (SLOW: the isotensoid and laminate vessels) run
with WINDER_SLOW=1 (`WINDER_SLOW=1 pytest tests/winding/test_choices.py`, about 2 min).
"""

from __future__ import annotations

import math
import os
from dataclasses import replace
from pathlib import Path

import pytest

from winder.config.job import load_config, parse_config
from winder.config.reader import load_yaml
from winder.winding.choices import all_helical, crossovers, pattern_choices
from winder.winding.plan import plan

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = sorted((ROOT / "samples").glob("*.yaml"))
SLOW = {"vessel_isotensoid", "vessel_laminate"}  # 15-35 s each on a loaded machine
ANGLE_TOL = 0.01  # deg
COVERAGE_TOL = 1e-3
LENGTH_RTOL = 1e-3

CASES = [(p, i) for p in SAMPLES for i in all_helical(load_config(p))]


def _planned(path: Path, index: int, yaml_text: str):
    """Layer index of the job at path with the layer replaced by the pasted YAML, planned whole."""
    data = load_yaml(path.read_text(encoding="utf-8"))
    data["winding"]["layers"][index] = {**load_yaml(yaml_text),
                                        **{k: v for k, v in data["winding"]["layers"][index].items()
                                           if k == "material"}}
    return plan(parse_config(data, str(path))).layers[index]


@pytest.mark.parametrize("path,index", CASES, ids=[f"{p.stem}-{i + 1}" for p, i in CASES])
def test_listed_choices_are_what_run_winds(path: Path, index: int) -> None:
    if path.stem in SLOW and not os.environ.get("WINDER_SLOW"):
        pytest.skip("seconds per choice: WINDER_SLOW=1 runs it")
    from winder.app.patterns import choice_yaml

    job = load_config(path)
    table = pattern_choices(job, index)
    own = plan(job).layers[index]
    chosen = [c for c in table.choices if c.chosen]
    assert len(chosen) == 1 and (chosen[0].circuits, chosen[0].pattern) == (own.circuits, own.pattern)
    cfg = job.winding.layers[index]
    # the planner's own, the first other, the last, and one of another circuit count
    picks = {0, len(table.choices) - 1, *(i for i, c in enumerate(table.choices) if not c.chosen)}
    others = [i for i, c in enumerate(table.choices) if c.circuits != own.circuits]
    sample = sorted(picks)[:2] + [len(table.choices) - 1] + others[:1] + [table.choices.index(chosen[0])]
    for i in sorted(set(sample)):
        c = table.choices[i]
        got = _planned(path, index, choice_yaml(cfg, table.requested_angle_deg, c.circuits, c.pattern))
        assert (got.circuits, got.pattern) == (c.circuits, c.pattern)
        assert abs(got.angle_deg - c.angle_deg) <= ANGLE_TOL
        assert abs(got.coverage.covered_fraction - c.covered_fraction) <= COVERAGE_TOL
        assert got.coverage.max_layers == c.max_layers
        assert math.isclose(got.fiber_length_mm, c.fiber_length_mm, rel_tol=LENGTH_RTOL)


def test_the_sort_puts_complete_coverage_and_the_asked_angle_first() -> None:
    job = load_config(ROOT / "samples" / "pipe.yaml")
    table = pattern_choices(job, 0)
    keys = [(c.covered_fraction < 0.999, round(abs(c.angle_deg - table.requested_angle_deg), 2), c.circuits)
            for c in table.choices]
    assert keys == sorted(keys)
    assert table.choices[0].chosen  # the planner's least-dwell skip of its own count leads
    assert {c.circuits for c in table.choices} == {19, 20, 21}


def test_crossovers_are_the_circuits_before_a_band_lands_beside_the_first() -> None:
    for n in (7, 18, 60):
        for k in range(1, n):
            if math.gcd(k, n) != 1:
                continue
            p, lead = crossovers(n, k)
            slots = [(j * k) % n for j in range(p + 1)]
            assert slots[p] == (1 if lead == "leading" else n - 1)
            assert all(s not in (1, n - 1) for s in slots[1:p])


def test_circuits_key_is_wound_as_given_and_gaps_are_noted() -> None:
    job = load_config(ROOT / "samples" / "pipe.yaml")
    layers = list(job.winding.layers)
    layers[0] = replace(layers[0], circuits=17, pattern=None)
    few = plan(replace(job, winding=replace(job.winding, layers=tuple(layers)))).layers[0]
    assert few.circuits == 17 and few.coverage.covered_fraction < 0.999
    assert any("leaves gaps" in note for note in few.notes)
