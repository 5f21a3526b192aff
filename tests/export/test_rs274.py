"""LinuxCNC's own interpreter reads every program winder writes: `rs274 -g` (Debian package
linuxcnc-uspace) on the generic, linuxcnc and marlin programs of every sample and config, its
canonical moves compared with winder's motion program: one STRAIGHT_FEED per programmed move, each
ending where the program's row is, and (G93) each taking the row's planned time, so that the
program's time is the summary's winding_time_s."""

from __future__ import annotations

import re

import numpy as np
import pytest

from every_job import EVERY, IDS, job_of, planned, program_of, text_of
from rs274_run import RS274, run_rs274
from winder.machine.limits import AXIS_DECIMALS

pytestmark = pytest.mark.skipif(RS274 is None, reason="rs274 not installed (Debian package linuxcnc-uspace)")

POSITION_TOL = 0.6 * 10.0**-AXIS_DECIMALS  # mm, deg: a value as written (3 decimals) against the program's
TIME_TOL = 2e-3  # relative: a move's time from rs274's feed (4 decimals) against the planned one
TOTAL_TOL = 1e-4  # relative: the program's time against winding_time_s
CANON = "XYZABC"  # the order of STRAIGHT_FEED's first six numbers
_FEED = re.compile(r"STRAIGHT_FEED\(([^)]*)\)")
_RATE = re.compile(r"SET_FEED_RATE\(([^)]*)\)")


def canonical(path, text: str) -> tuple[np.ndarray, np.ndarray]:
    """rs274 -g of `text`: each STRAIGHT_FEED's end (n, 6) and the feed rate it runs at (n,)."""
    ends, rates, rate = [], [], np.nan
    for line in run_rs274(path, text).splitlines():
        found = _RATE.search(line)
        if found:
            rate = float(found.group(1))
            continue
        found = _FEED.search(line)
        if found:
            ends.append([float(v) for v in found.group(1).split(",")[:6]])
            rates.append(rate)
    return np.array(ends).reshape(-1, 6), np.array(rates)


def written_rows(values: np.ndarray) -> np.ndarray:
    """The program's rows a dialect writes: a row whose rounded values repeat the last is left out."""
    shown = np.round(values, AXIS_DECIMALS)
    return np.flatnonzero(np.concatenate([[True], np.any(shown[1:] != shown[:-1], axis=1)]))


def _rows_among_pieces(ends: np.ndarray, want: np.ndarray) -> np.ndarray:
    """Which of rs274's move ends (n, k) are the program's rows (m, k), in order: the others are the pieces
    a move was cut into at a full turn of A (at 360 k less one written unit, where a row may also fall)."""
    kept = np.zeros(ends.shape[0], dtype=bool)
    j = 0
    for i in range(ends.shape[0]):
        if j < want.shape[0] and np.abs(ends[i] - want[j]).max() < POSITION_TOL:
            kept[i], j = True, j + 1
    return kept


def straight_length(delta: np.ndarray) -> np.ndarray:
    """LinuxCNC's length of a move (what an inverse-time or per-minute feed is over): the linear
    axes' distance when one moves, else the rotary axes'."""
    linear = np.linalg.norm(delta[:, :3], axis=1)
    return np.where(linear > 0.0, linear, np.linalg.norm(delta[:, 3:], axis=1))


@pytest.mark.parametrize("dialect", ["generic", "linuxcnc", "marlin"])
@pytest.mark.parametrize("path", EVERY, ids=IDS)
def test_rs274_reads_the_program(path, dialect, tmp_path):
    text = text_of(path, dialect)
    if text is None:
        pytest.skip(f"{path.name}: no {dialect} program (robot poses, or marlin without a fixed eye)")
    program = program_of(path)
    if dialect == "marlin":  # Marlin needs no program end (fiberpath writes none); rs274 refuses a file without
        text += "M2\n"
    ends, rates = canonical(tmp_path / f"{path.stem}.ngc", text)
    ax = program.machine.axes
    if dialect == "marlin":  # X A B: A and B negated (fiberpath's conventions), no cross-feed
        columns, signs = [CANON.index(c) for c in "XAB"], np.array([1.0, -1.0, -1.0])
        values = program.values[:, [0, 1, 3]] * signs
    else:
        columns = [CANON.index(c) for c in (ax.carriage, ax.rotation, ax.cross_feed, ax.yaw)]
        values = program.values
    rows = written_rows(values)
    kept = np.ones(ends.shape[0], dtype=bool)
    if dialect == "marlin":  # a move cut at each full turn of A (one written unit short): its pieces are one move
        kept = _rows_among_pieces(ends[:, columns], values[rows])
    first = 1 if dialect == "linuxcnc" else 0  # linuxcnc: a rapid G0 to the start, then the feeds
    assert np.count_nonzero(kept) == rows.size - first
    assert np.abs(ends[kept][:, columns] - values[rows[first:]]).max() < POSITION_TOL
    assert np.abs(ends[-1, columns] - values[-1]).max() < POSITION_TOL
    if dialect == "generic":  # F the fiber feed, as the program has it
        assert np.abs(rates - program.feed[rows]).max() < 1e-3
        return
    # The time rs274 gives each move (its length over its feed) against the planned time.
    starts = np.vstack([np.zeros((1, 6)), ends[:-1]]) if dialect == "marlin" else None
    if dialect == "linuxcnc":
        start = np.zeros(6)
        start[columns] = np.round(values[rows[0]], AXIS_DECIMALS)
        starts = np.vstack([start, ends[:-1]])
    seconds = 60.0 * straight_length(ends - starts) / rates
    seconds = np.diff(np.concatenate([[0.0], np.cumsum(seconds)[kept]]))  # a cut move's pieces together
    clock = np.cumsum(program.times.time_s)
    planned = np.diff(clock[rows])
    planned = planned if dialect == "linuxcnc" else np.concatenate([[np.nan], planned])
    check = slice(1, None) if dialect == "marlin" else slice(None)  # marlin's first move: at machine.feed
    close = np.abs(seconds[check] - planned[check]) <= TIME_TOL * planned[check] + 1e-4
    assert close.all(), (np.flatnonzero(~close)[:5], seconds[check][~close][:5], planned[check][~close][:5])
    assert np.sum(seconds[check]) == pytest.approx(program.times.total_s, rel=TOTAL_TOL, abs=1e-3)


@pytest.mark.parametrize("path", EVERY, ids=IDS)
def test_rs274_reads_every_gcode_file_run_writes(path, tmp_path):
    """The program file `run` writes by default (its gcode format, rendered as run renders it) is read
    by rs274, a robot's eye poses too (five-axis G-code: X Y Z the eye, B C the fiber's direction)."""
    from winder.app.jobs import ALL_FORMATS, render_outputs  # noqa: PLC0415

    assert "gcode" in ALL_FORMATS
    job, program = job_of(path), program_of(path)
    names = render_outputs(job, planned(path), ("gcode",), summary=False, program=program)
    programs = {name: data for name, data in names.items() if name.endswith(".gcode")}
    assert set(programs) == {job.name + ".gcode"}
    for name, data in programs.items():
        text = data.decode("utf-8")
        if program.robot:
            _check_poses(canonical(tmp_path / f"{path.stem}.ngc", text)[0], program.values)
            continue
        ends, _ = canonical(tmp_path / f"{path.stem}.ngc", text)
        assert ends.shape[0] > 0



DIRECTION_TOL = 5e-6  # a unit vector from B and C as rs274 prints them (4 decimals of a degree: 1.7e-6 rad)


def _check_poses(ends: np.ndarray, poses: np.ndarray) -> None:
    """rs274's moves of a robot program against the program's poses (m, 6): one move per written row,
    the eye where the row is, and B C (B from +Z, C about +Z from +X, as README.md's robot dialect
    states) the row's unit fiber direction."""
    b_deg = np.degrees(np.arccos(np.clip(poses[:, 5], -1.0, 1.0)))
    c_deg = np.degrees(np.unwrap(np.arctan2(poses[:, 4], poses[:, 3])))
    shown = np.column_stack([np.round(poses[:, :3], AXIS_DECIMALS), np.round(b_deg, 6), np.round(c_deg, 6)])
    rows = np.flatnonzero(np.concatenate([[True], np.any(shown[1:] != shown[:-1], axis=1)]))
    assert ends.shape[0] == rows.size
    assert np.abs(ends[:, :3] - poses[rows, :3]).max() < POSITION_TOL
    b, c = np.radians(ends[:, CANON.index("B")]), np.radians(ends[:, CANON.index("C")])
    read = np.column_stack([np.sin(b) * np.cos(c), np.sin(b) * np.sin(c), np.cos(b)])
    assert np.abs(read - poses[rows, 3:]).max() < DIRECTION_TOL
