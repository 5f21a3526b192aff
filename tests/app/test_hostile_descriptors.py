"""Hostile input, third round (issue 45): an output that is a link to an open descriptor is written into.

`winder geodesic ... -o /dev/stdout > out.csv` replaced the link by its CSV (as root, the machine's
/dev/stdout became a regular file) and out.csv stayed empty. The tests make their own link to
/proc/self/fd/1 in a temporary folder (never touching /dev), redirect standard output to a file, and
check that the output lands in that file and that the link is still a link.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PIPE = ROOT / "samples" / "pipe.yaml"
PROGRAM = ROOT / "samples" / "reference" / "pipe" / "pipe.gcode"


def _shell(command: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(["sh", "-c", command], cwd=cwd, capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)))


@pytest.mark.parametrize("command", ["geodesic", "simulate", "run"])
def test_a_link_to_this_process_stdout_is_written_into(tmp_path: Path, command: str) -> None:
    out = tmp_path / "out"
    out.mkdir()
    name = {"geodesic": "g.csv", "simulate": "s.csv", "run": "pipe.csv"}[command]
    link = out / name
    link.symlink_to("/proc/self/fd/1")
    winder = f'"{sys.executable}" -m winder'
    args = {"geodesic": f"geodesic {PIPE} --start 10,0 --end 400,90 -o {link}",
            "simulate": f"simulate {PIPE} {PROGRAM} -o {link}",
            "run": f"run {PIPE} -o {out} --format csv"}[command]
    res = _shell(f"{winder} {args} > captured.txt", tmp_path)
    assert res.returncode == 0, res.stderr
    assert link.is_symlink() and os.readlink(link) == "/proc/self/fd/1"
    text = (tmp_path / "captured.txt").read_text()
    header = {"geodesic": "i,t,theta_deg,x,y,z\n", "simulate": "layer,", "run": "layer,circuit,pass,"}[command]
    assert text.startswith(header), text[:200]
    rows = [line for line in text.splitlines() if line[:1].isdigit()]
    assert len(rows) > 10
    assert sorted(p.name for p in out.iterdir()) == sorted({name, *(["pipe.summary.json"] if command == "run" else [])})


def test_appending_to_stdout_keeps_what_the_file_held(tmp_path: Path) -> None:
    """`>> log`: the descriptor is opened for appending, and the CSV goes after what was there."""
    link = tmp_path / "g.csv"
    link.symlink_to("/proc/self/fd/1")
    (tmp_path / "log.txt").write_text("earlier line\n")
    res = _shell(f'"{sys.executable}" -m winder geodesic {PIPE} --start 10,0 --end 400,90 -o {link} >> log.txt',
                 tmp_path)
    assert res.returncode == 0, res.stderr
    text = (tmp_path / "log.txt").read_text()
    assert text.startswith("earlier line\ni,t,theta_deg,x,y,z\n")
    assert link.is_symlink()
