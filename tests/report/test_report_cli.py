"""`winder report` and `winder run --report` (docs/guide/commands.md), and a single job's progress bar.

Same conventions as `run`: one `Error:` line per problem, exit 2 for an invalid config (or the plot
extra missing), 1 for a job that cannot be computed; a failing config does not stop the others; a
failed job leaves no file behind.
"""

from __future__ import annotations

import html
import io
import sys
from pathlib import Path

from click.testing import CliRunner

import winder.cli.jobs as cli  # the single job's progress bar lives with the job commands
from winder.cli import main

ROOT = Path(__file__).resolve().parents[2]
PIPE = ROOT / "samples" / "pipe.yaml"
INVALID = ROOT / "tests" / "config" / "invalid" / "bad_radius.yaml"
ELBOW = ROOT / "samples" / "elbow.yaml"


def _infeasible(folder: Path) -> Path:
    """The elbow sample wound geodesically at 20 deg: the fiber bridges at the inside of the bend
    (below 31.1 deg no friction holds it there), a valid config no winding exists for (exit 1)."""
    text = ELBOW.read_text(encoding="utf-8").replace("{type: helical, angle: 45, slip: auto}", "{type: helical, angle: 20}")
    assert "angle: 20}" in text
    path = folder / "infeasible.yaml"
    path.write_text(text.replace("name: elbow", "name: infeasible"), encoding="utf-8")
    return path


def _run(*args: str):
    return CliRunner().invoke(main, list(args))


def _errors(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith("Error:")]


def test_report_writes_one_page_and_nothing_else(tmp_path):
    res = _run("report", str(PIPE), "-o", str(tmp_path))
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.html"]
    text = (tmp_path / "pipe.html").read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and "pipe: winding report" in text


def test_report_batch_goes_on_past_bad_configs(tmp_path):
    bad = _infeasible(tmp_path)
    out = tmp_path / "out"
    res = _run("report", str(INVALID), str(bad), str(PIPE), "-o", str(out))
    assert res.exit_code == 2, res.output  # an invalid config outranks a failed job
    errors = _errors(res.stderr)
    assert len(errors) == 2 and str(INVALID) in errors[0] and str(bad) in errors[1]
    assert sorted(p.name for p in out.iterdir()) == ["pipe.html"]  # the failed jobs left nothing
    res = _run("report", str(bad), "-o", str(out))
    assert res.exit_code == 1 and len(_errors(res.stderr)) == 1


def test_run_report_writes_the_page_beside_the_other_outputs(tmp_path):
    res = _run("run", str(PIPE), "--report", "--format", "csv", "-o", str(tmp_path))
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.csv", "pipe.html", "pipe.summary.json"]
    res = _run("run", str(PIPE), "-o", str(tmp_path / "plain"))
    assert "pipe.html" not in {p.name for p in (tmp_path / "plain").iterdir()}  # only on request


def test_without_plotly_report_says_how_to_install_it_and_run_is_unaffected(tmp_path, monkeypatch):
    for mod in [m for m in sys.modules if m == "plotly" or m.startswith("plotly.")]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setitem(sys.modules, "plotly", None)  # import plotly -> ImportError
    for args in (["report", str(PIPE)], ["run", str(PIPE), "--report"]):
        res = _run(*args, "-o", str(tmp_path / "r"))
        assert res.exit_code == 2, res.output
        assert _errors(res.stderr) == [line for line in res.stderr.splitlines() if line]
        assert 'pip install "winder[plot]"' in res.stderr
        assert not (tmp_path / "r").exists()  # refused before any work
    res = _run("run", str(PIPE), "-o", str(tmp_path / "plain"))
    assert res.exit_code == 0 and (tmp_path / "plain" / "pipe.gcode").is_file()


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_single_job_bar_draws_only_on_a_terminal_and_only_after_a_second(monkeypatch):
    quiet = io.StringIO()
    bar = cli._JobBar(quiet)
    monkeypatch.setattr(cli, "SHOW_AFTER_S", 0.0)
    bar(0.5, "pipe: layer 1 of 2: circuit 3 of 19")
    bar.close()
    assert quiet.getvalue() == ""  # not a terminal: nothing
    term = _Terminal()
    bar = cli._JobBar(term)
    monkeypatch.setattr(cli, "SHOW_AFTER_S", 3600.0)
    bar(0.2, "early")
    assert term.getvalue() == ""  # a job shorter than the delay shows nothing
    monkeypatch.setattr(cli, "SHOW_AFTER_S", 0.0)
    bar(0.25, "layer 1 of 2: circuit 5 of 19")
    bar(0.75, "layer 2 of 2: hoop traverse 1 of 2")
    bar.close()
    drawn = term.getvalue()
    assert "layer 2 of 2: hoop traverse 1 of 2" in drawn and "75%" in drawn


def test_run_of_one_job_reports_progress_to_its_bar(tmp_path, monkeypatch):
    seen = []

    class Recorder(cli._JobBar):
        def __call__(self, fraction, label):
            seen.append((fraction, label))

    monkeypatch.setattr(cli, "_JobBar", Recorder)
    res = _run("run", str(PIPE), "-o", str(tmp_path))
    assert res.exit_code == 0, res.output
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    assert any("circuit 19 of 19" in label for _, label in seen)  # per circuit
    assert any("hoop traverse 2 of 2" in label for _, label in seen)  # per layer
    assert "%" not in res.stderr  # CliRunner's stderr is no terminal: no bar drawn


def test_the_page_shows_the_winding_times_of_the_summary_file(tmp_path):
    # The page claims the numbers of <name>.summary.json: its winding time is the machine's time
    # over the program (winding_time_s, acceleration included), not the fiber length at the feed.
    import json  # noqa: PLC0415

    from winder.report.tables import duration  # noqa: PLC0415

    res = _run("run", str(PIPE), "--report", "--format", "csv", "-o", str(tmp_path))
    assert res.exit_code == 0, res.output
    summary = json.loads((tmp_path / "pipe.summary.json").read_text(encoding="utf-8"))
    page = (tmp_path / "pipe.html").read_text(encoding="utf-8")
    assert duration(summary["winding_time_s"]) != duration(summary["estimated_time_s"])  # the case tells them apart
    assert f"({summary['winding_time_s']:,.1f} s)".replace(",", "\u2009") in page  # thin-space thousands
    for layer in summary["layers"]:
        assert f"<td>{duration(layer['winding_time_s'])}</td></tr>" in page


def test_a_job_past_the_axis_limits_says_so_and_keeps_the_feed_estimate(tmp_path):
    # `report` writes no program; where none fits machine.limits the summary has winding_time_s null.
    # The page must say why there is no machine time, and still give the time at the feed.
    from winder.report.tables import duration  # noqa: PLC0415

    text = PIPE.read_text(encoding="utf-8").replace("carriage: [-100, 700]", "carriage: [0, 500]")
    assert "carriage: [0, 500]" in text  # the eye leads the fiber to X 514.3 at the far end
    config = tmp_path / "pipe.yaml"
    config.write_text(text, encoding="utf-8")
    res = _run("run", str(config), "--format", "csv", "-o", str(tmp_path / "run"))
    assert res.exit_code == 0, res.output
    import json  # noqa: PLC0415

    summary = json.loads((tmp_path / "run" / "pipe.summary.json").read_text(encoding="utf-8"))
    assert summary["winding_time_s"] is None
    assert "machine.limits.carriage: axis X (carriage) would reach 514.303 mm" in summary["program_error"]
    res = _run("report", str(config), "-o", str(tmp_path / "page"))
    assert res.exit_code == 0, res.output
    page = (tmp_path / "page" / "pipe.html").read_text(encoding="utf-8")
    assert "no machine program fits this machine" in page
    assert html.escape(summary["program_error"]) in page  # where, as `run` says it
    assert duration(summary["estimated_time_s"]) in page
    for layer in summary["layers"]:
        assert f"<td>{duration(layer['time_s'])}" in page


def test_the_passes_column_counts_the_passes_that_lay_fiber(tmp_path):
    # A shop reads "passes" as traverses of the eye: the pipe's hoop layer is `passes: 2` in its config
    # and its helical layer 19 circuits of one forward and one return pass; the summary's `passes`
    # (152 and 4) counts the CSV's pass pieces, turnarounds and dwells included.
    from winder.report.tables import layer_table  # noqa: PLC0415
    import json  # noqa: PLC0415

    res = _run("run", str(PIPE), "--format", "csv", "-o", str(tmp_path))
    assert res.exit_code == 0, res.output
    summary = json.loads((tmp_path / "pipe.summary.json").read_text(encoding="utf-8"))
    assert [layer["passes"] for layer in summary["layers"]] == [152, 4]
    table = layer_table(summary)
    heads = [h.split("<", 1)[0] for h in table.split("<th>")[1:]]
    rows = [[c.split("</td>", 1)[0] for c in row.split("<td>")[1:]] for row in table.split("<tr>")[2:]]
    column = heads.index("passes")
    assert "passes<br><span class=unit>laid</span>" in table
    assert [row[column] for row in rows] == ["38", "2"]


def test_the_page_shows_the_travel_of_each_axis_from_the_summary(tmp_path):
    # Before winding a shop sets the program's axis travel against its machine's: the pipe's eye runs
    # from X -27.699 to 527.699 (past both mandrel ends at the turnarounds), as the summary says.
    import json  # noqa: PLC0415

    res = _run("run", str(PIPE), "--report", "--format", "csv", "-o", str(tmp_path))
    assert res.exit_code == 0, res.output
    summary = json.loads((tmp_path / "pipe.summary.json").read_text(encoding="utf-8"))
    page = (tmp_path / "pipe.html").read_text(encoding="utf-8")
    assert summary["axis_travel"]["carriage"] == [-27.699, 527.699]
    assert "<tr><th>carriage travel</th><td>-27.699 to 527.699 mm</td></tr>" in page
    low, high = summary["axis_travel"]["rotation"]
    assert f"<tr><th>rotation travel</th><td>{low:,.3f} to {high:,.3f} deg</td></tr>".replace(",", "\u2009") in page
    assert "<tr><th>cross-feed travel</th>" in page and "<tr><th>yaw travel</th>" in page
