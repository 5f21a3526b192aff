"""The shipped samples as a user's CI sees them: their references hold exact columns, and
`winder regress` separates noise from change both ways (issue: regress that holds on every machine).

- Exact columns, read from the stored references (which test_cli's regression keeps current):
  Clairaut along every vessel pass, one sign along every dwell.
- Noise passes: the computation perturbed below the printed precision (a Newton stopping tolerance
  100 times tighter, one BLAS thread instead of the default, the samples run in another order).
- Change fails, with a readable difference: band width +0.1 mm, angle +0.01 deg, one circuit more.
"""

from __future__ import annotations

import csv
import os
import shutil
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest

from winder.paths import geodesic as geodesic_module
from winder.app.regress import format_result, regress

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples"
VESSEL_SAMPLES = ("vessel_hemi", "vessel_isotensoid")
FAST_SAMPLES = ("cone", "pipe", "vessel_hemi")  # the quick ones, for the perturbed runs
CLAIRAUT_RTOL = 1e-5  # r sin(alpha) along a pass, from the 6-decimal CSV


def reference_rows(name: str) -> list[dict[str, str]]:
    with open(SAMPLES / "reference" / name / f"{name}.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def passes_of(rows: list[dict[str, str]]) -> dict[tuple[str, str], list[dict[str, str]]]:
    out: dict[tuple[str, str], list[dict[str, str]]] = defaultdict(list)
    for row in rows:
        out[(row["layer"], row["pass"])].append(row)
    return out


# -- exact columns ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", VESSEL_SAMPLES)
def test_clairaut_from_the_job_csv(name):
    """r sin(alpha_deg) is constant along each helical pass (turnaround points excepted), at the
    sample's own number of points: alpha_deg is the smooth path's tangent, not a chord's."""
    checked = 0
    for rows in passes_of(reference_rows(name)).values():
        if rows[0]["kind"] not in ("forward", "return"):
            continue
        xyz = np.array([[float(r["x"]), float(r["y"])] for r in rows])
        alpha = np.radians(np.array([float(r["alpha_deg"]) for r in rows]))
        c = np.hypot(xyz[:, 0], xyz[:, 1]) * np.sin(np.abs(alpha))
        inner = c[1:-1]
        assert np.ptp(inner) / inner.mean() < CLAIRAUT_RTOL, (name, rows[0]["pass"], np.ptp(inner) / inner.mean())
        checked += 1
    assert checked >= 10


@pytest.mark.parametrize("name", sorted(p.stem for p in SAMPLES.glob("*.yaml")))
def test_dwell_angle_has_one_sign(name):
    """A dwell or hoop's alpha_deg never flips sign with round-off (only a swing through the hoop
    changes it, once); every winding angle is in (-90, 90]."""
    rows = reference_rows(name)
    alpha = np.array([float(r["alpha_deg"]) for r in rows])
    assert (alpha > -90.0).all() and (alpha <= 90.0).all()
    for rows_of_pass in passes_of(rows).values():
        kind = rows_of_pass[0]["kind"]
        if kind not in ("dwell", "hoop"):
            continue
        a = np.array([float(r["alpha_deg"]) for r in rows_of_pass])
        flips = np.flatnonzero(np.sign(a[1:]) != np.sign(a[:-1]))
        if kind == "hoop" or np.ptp(np.abs(a)) < 1e-9:  # along a helix or a parallel: one sign
            assert flips.size == 0, (name, rows_of_pass[0]["pass"], a[flips])
        else:
            # A swing round an end that holds the fiber: |alpha| rises to the hoop and falls again,
            # and the sign changes once, there (from the pass it came from to the pass it goes to).
            top = int(np.argmax(np.abs(a)))
            step = np.max(np.abs(np.diff(np.abs(a))))
            assert flips.size == 1 and abs(a[flips[0]]) >= 90.0 - step - 1e-9, (name, rows_of_pass[0]["pass"])
            assert np.all(np.diff(np.abs(a[:top + 1])) >= -1e-9) and np.all(np.diff(np.abs(a[top:])) <= 1e-9)


# -- noise passes ----------------------------------------------------------------------------------
def copy_samples(tmp_path: Path, names: tuple[str, ...], rename=lambda n: n) -> Path:
    folder = tmp_path / "samples"
    (folder / "reference").mkdir(parents=True)
    for name in names:
        shutil.copy(SAMPLES / f"{name}.yaml", folder / f"{rename(name)}.yaml")
        shutil.copytree(SAMPLES / "reference" / name, folder / "reference" / rename(name))
    return folder


def assert_all_pass(results) -> None:
    text = "\n".join(line for r in results for line in format_result(r))
    assert results and all(r.ok for r in results), text


def test_tighter_newton_stop_is_noise(tmp_path, monkeypatch):
    monkeypatch.setattr(geodesic_module, "STEP_TOL", geodesic_module.STEP_TOL * 1e-2)
    assert_all_pass(regress(copy_samples(tmp_path, FAST_SAMPLES)))


# Runs regress in a fresh process with the samples in reverse order.
REVERSED_REGRESS = """
import sys
import winder.app.regress as r
found = r.find_samples
r.find_samples = lambda folder: found(folder)[::-1]
results = r.regress(sys.argv[1])
for result in results:
    print("\\n".join(r.format_result(result)))
sys.exit(r.regress_exit_status(results))
"""


def test_one_blas_thread_and_another_order_is_noise(tmp_path):
    """One BLAS thread (the default is one per core) and the samples in reverse order, in a fresh
    process, as a user's CI on another machine would run them."""
    folder = copy_samples(tmp_path, FAST_SAMPLES)
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    proc = subprocess.run([sys.executable, "-c", REVERSED_REGRESS, str(folder)], env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert [line.split()[1] for line in proc.stdout.splitlines() if line.startswith("ok ")] == \
        list(FAST_SAMPLES[::-1])


# -- change fails ----------------------------------------------------------------------------------
def edit_pipe(tmp_path: Path, old: str, new: str) -> Path:
    folder = copy_samples(tmp_path, ("pipe",))
    config = folder / "pipe.yaml"
    text = config.read_text()
    assert old in text
    config.write_text(text.replace(old, new))
    return folder


@pytest.mark.parametrize("old, new, expect", [
    ("band_width: 10", "band_width: 10.1", "pipe.summary.json"),         # band width +0.1 mm
    ("angle: 55,", "angle: 55.01,", "column alpha_deg"),                 # angle +0.01 deg
    ("band_width: 10", "band_width: 9.3", "layers[0].circuits: expected 19, got 20"),  # one circuit more
])
def test_a_real_change_fails_readably(tmp_path, old, new, expect):
    results = regress(edit_pipe(tmp_path, old, new))
    assert len(results) == 1 and not results[0].ok
    text = "\n".join(format_result(results[0]))
    assert text.startswith("FAIL pipe") and expect in text, text
