"""`check` under a time limit of its own (issue 45): past it, exit 1 with a message naming what the check
was doing (reading the file, building the surface, the work budget), never "solvers do not converge"."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from click.testing import CliRunner

import winder.app.validate as validate
from tests.configs import tiny_pipe
from winder.cli import main
from winder.errors import WinderError


def test_a_check_past_its_limit_names_the_stage_it_was_in(tmp_path: Path, monkeypatch) -> None:
    config = tmp_path / "tiny.yaml"
    config.write_text(tiny_pipe(), encoding="utf-8")
    real = validate.build_surface

    def slow(*args):
        time.sleep(5.0)
        return real(*args)

    monkeypatch.setattr(validate, "build_surface", slow)
    with pytest.raises(WinderError) as info:
        validate.validate_within(config, 0.3)
    assert info.value.exit_code == 1
    assert str(info.value).startswith(f"{config}: the check did not finish within its time limit of 0.3 s "
                                      f"(check --time-limit): stopped while building the mandrel's surface")
    result = CliRunner().invoke(main, ["check", str(config), "--time-limit", "0.3"])
    assert result.exit_code == 1 and "stopped while building the mandrel's surface" in result.stderr
    assert "converge" not in result.stderr


def test_check_within_its_limit_is_unchanged(tmp_path: Path) -> None:
    config = tmp_path / "tiny.yaml"
    config.write_text(tiny_pipe(), encoding="utf-8")
    result = CliRunner().invoke(main, ["check", str(config)])
    assert result.exit_code == 0 and result.stdout.startswith("ok: ")


def test_run_past_its_limit_while_reading_says_so(tmp_path: Path, monkeypatch) -> None:
    """A `.wind` of 190,000 keys was stopped by `run --time-limit 10` as 'solvers do not converge'."""
    import winder.config.job as job_module  # noqa: PLC0415
    from winder.app.jobs import run_job  # noqa: PLC0415

    config = tmp_path / "tiny.yaml"
    config.write_text(tiny_pipe(), encoding="utf-8")
    real = job_module.load_config

    def slow(path):
        time.sleep(5.0)
        return real(path)

    monkeypatch.setattr(job_module, "load_config", slow)
    report = run_job(config, tmp_path / "out", seconds=0.3)
    assert report.exit_code == 1 and f"stopped while reading {config}" in report.message, report.message
    assert "converge" not in report.message


def test_simulate_past_its_limit_names_its_stage(monkeypatch) -> None:
    import winder.winding.plan as plan_module  # noqa: PLC0415
    from winder.app.simulate import simulate_files  # noqa: PLC0415
    from winder.errors import SolverError  # noqa: PLC0415

    root = Path(__file__).resolve().parents[2]
    real = plan_module.plan

    def slow(job, *rest):
        time.sleep(5.0)
        return real(job, *rest)

    monkeypatch.setattr(plan_module, "plan", slow)
    with pytest.raises(SolverError, match=r"within its time limit of 0.5 s \(--time-limit\): stopped while planning"):
        simulate_files(str(root / "samples" / "pipe.yaml"), str(root / "samples" / "reference" / "pipe" / "pipe.gcode"),
                       seconds=0.5)
