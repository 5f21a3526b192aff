"""`--format layup` through a job run: written where the job has a material (and compared), refused
with exit status 2 and nothing written where it has none; never written by default."""

import csv
from pathlib import Path

from winder.app.jobs import ALL_FORMATS, run_job
from winder.export.layup import HEADER

SAMPLES = Path(__file__).resolve().parents[2] / "samples"


def test_layup_needs_a_material(tmp_path):
    report = run_job(SAMPLES / "pipe.yaml", tmp_path, formats=("layup",))
    assert report.exit_code == 2 and "winding.material: required for --format layup" in report.message
    assert list(tmp_path.iterdir()) == []
    assert "layup" not in ALL_FORMATS


def test_layup_without_a_material_is_refused_before_any_planning(tmp_path, monkeypatch):
    # An invalid request (exit 2) is refused up front, as `check` refuses a config: planning a whole
    # job first only to refuse it wastes the job's time and shows its fiber length in the status table.
    import winder.winding.plan  # noqa: PLC0415

    def no_planning(*args, **kwargs):
        raise AssertionError("planned a job whose layup was going to be refused")

    monkeypatch.setattr(winder.winding.plan, "plan", no_planning)
    report = run_job(SAMPLES / "pipe.yaml", tmp_path, formats=("csv", "layup"))
    assert report.exit_code == 2 and "winding.material: required for --format layup" in report.message
    assert report.layers == 0 and report.fiber_length_mm is None
    assert list(tmp_path.iterdir()) == []


def test_layup_of_the_laminate_sample(tmp_path):
    report = run_job(SAMPLES / "vessel_laminate.yaml", tmp_path, formats=("layup",))
    assert report.ok, report.message
    text = (tmp_path / "vessel_laminate.layup.csv").read_text()
    rows = list(csv.DictReader(text.splitlines()))
    assert text.splitlines()[0] == HEADER and {r["layer"] for r in rows} == {"1", "2", "3"}
    assert all(0.0 <= float(r["angle_deg"]) <= 90.0 and float(r["thickness_mm"]) > 0.0 for r in rows)
