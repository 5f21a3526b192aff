"""Many layers (issue 34): the work budget counts layers and stops summing once past its limit, so that
`check` refuses a config of 20,000 aliased layers (80 kB) at once (it took 85 s); the 40-layer vessel
within 1 GB (WINDER_NIGHTLY=1: it runs about four minutes on a busy machine; 386 MB peak, 1.04 GB before the
machine stage took a few layers at a time, winder.machine.chunks):
WINDER_NIGHTLY=1 python -m pytest tests/app/test_hostile_budget.py
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.sandbox import run_limited

ROOT = Path(__file__).resolve().parents[2]
VESSEL = ROOT / "samples" / "vessel_hemi.yaml"
HANG_GUARD_S = 120
BUSY_MACHINE_S = 20.0
ONE_GB_MB = 1024


def _vessel(tmp_path: Path, name: str, layers: str) -> Path:
    text = VESSEL.read_text(encoding="utf-8")
    head = text[:text.index("winding:")].replace("name: vessel_hemi", f"name: {name}")
    path = tmp_path / f"{name}.yaml"
    path.write_text(head + "winding:\n  band_width: 10\n  points: 30\n  layers:\n" + layers +
                    "machine:\n  eye: {radius: 180}\n  feed: 2500\n", encoding="utf-8")
    return path


@pytest.mark.parametrize("count, key", [(20_000, "winding.layers: 20000 layers, more than the limit of 1000"),
                                        (900, "winding.points: the job would plan")])
def test_many_aliased_layers_are_refused_fast(tmp_path: Path, count: int, key: str) -> None:
    layers = "    - &h {type: helical, angle: 22}\n" + "    - *h\n" * (count - 1)
    config = _vessel(tmp_path, "aliased", layers)
    (result,), = run_limited([[["check", str(config)]]], seconds=HANG_GUARD_S)
    assert result["code"] == 2 and "internal error" not in result["stderr"], result
    errors = [line for line in result["stderr"].splitlines() if line.startswith("Error:")]
    assert len(errors) == 1 and key in errors[0], errors
    assert result["seconds"] < BUSY_MACHINE_S, result["seconds"]


ESTIMATE_WITHIN = 1.5  # the work budget's memory estimate against the measured peak, either way


def _estimate_mb(config: Path) -> float:
    from winder.config.job import load_config
    from winder.geometry.build import build_surface
    from winder.winding.budget import job_budget

    job = load_config(str(config))
    return job_budget(job, build_surface(job.mandrel, job.source, job.name)).memory_bytes / 2**20


@pytest.mark.skipif(not os.environ.get("WINDER_NIGHTLY"), reason="about four minutes each: WINDER_NIGHTLY=1")
@pytest.mark.parametrize("part", ["v40", "large_vessel"])
def test_a_40_layer_vessel_runs_within_1_gb(tmp_path: Path, part: str) -> None:
    if part == "v40":
        layers = "    - {type: helical, angle: 22}\n    - {type: hoop, passes: 1}\n" * 20
        config = _vessel(tmp_path, "v40", layers)
    else:  # issue 29's large isotensoid vessel: 3 GB before
        config = ROOT / "parts" / "large_vessel.yaml"
    (result,), = run_limited([[["run", str(config), "-o", str(tmp_path / "out")]]], seconds=600)
    assert result["code"] == 0, result["stderr"]
    assert result["peak_mb"] < ONE_GB_MB, result["peak_mb"]
    estimate = _estimate_mb(config)
    assert 1.0 / ESTIMATE_WITHIN < estimate / result["peak_mb"] < ESTIMATE_WITHIN, (estimate, result["peak_mb"])


SPLINE_ROUNDS = ROOT / "tests" / "app" / "hostile" / "spline_rounds_31.yaml"
ROUNDS_AGREE = 0.05  # the straightened tube's rounds against the traced geodesic's, relative


def test_spline_helix_with_too_few_points_is_refused_by_check(tmp_path: Path) -> None:
    (result,), = run_limited([[["check", str(SPLINE_ROUNDS)]]], seconds=HANG_GUARD_S)
    assert result["code"] == 2 and "internal error" not in result["stderr"], result
    errors = [line for line in result["stderr"].splitlines() if line.startswith("Error:")]
    assert len(errors) == 1 and "spline_rounds_31.yaml: winding.points: must be at least" in errors[0], errors
    assert result["seconds"] < BUSY_MACHINE_S, result["seconds"]


def test_check_rounds_estimate_agrees_with_the_traced_geodesic() -> None:
    """The rounds `check` estimates (no geodesic) against those the planner finds by tracing the
    geodesic on the bent tube (winder.winding.plan without validation: its own refusal names them)."""
    import re

    from winder.config.job import load_config
    from winder.errors import ConfigError
    from winder.geometry.build import build_surface
    from winder.winding.budget import check_budget
    from winder.winding.plan import plan

    job = load_config(str(SPLINE_ROUNDS))
    with pytest.raises(ConfigError) as estimated:
        check_budget(job, build_surface(job.mandrel, job.source, job.name))
    with pytest.raises(ConfigError) as traced:
        plan(job)
    guess = float(re.search(r"about ([0-9.]+) rounds", estimated.value.message).group(1))
    found = float(re.search(r"path of ([0-9.]+) rounds", traced.value.message).group(1))
    assert abs(guess - found) <= ROUNDS_AGREE * found, (guess, found)
