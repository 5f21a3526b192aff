"""Continuous programs (issue: machine programs a controller runs as written): on every straight-axis
sample the mandrel never stops or turns back while the eye moves, and the eye reverses at the ends
while the mandrel turns. The programs are the shipped references (`winder regress samples` holds them
to what `run` writes), read here by a parser of their own."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
STRAIGHT = ["pipe", "cone", "vessel_hemi", "vessel_isotensoid", "elliptic_tube", "vessel_laminate"]
PRINTED = 1e-3  # the generic dialect's last printed place (mm, deg)
_WORD = re.compile(r"([A-Z])(-?\d+(?:\.\d+)?)")


def moves(name: str) -> np.ndarray:
    """(m, 4) X, A, Z, B of every G1 of the sample's reference program."""
    rows = []
    for line in (SAMPLES / "reference" / name / f"{name}.gcode").read_text().splitlines():
        if line.startswith("G1 "):
            words = dict(_WORD.findall(line.split(";")[0]))
            rows.append([float(words[k]) for k in "XAZB"])
    return np.array(rows)


@pytest.mark.parametrize("name", STRAIGHT)
def test_the_mandrel_never_stops_or_turns_back(name):
    v = moves(name)
    step = np.diff(v, axis=0)
    sense = np.sign(v[-1, 1] - v[0, 1])
    # Every move turns the mandrel on, in one sense (no dwell sample asks for a still mandrel).
    assert np.all(step[:, 1] * sense >= PRINTED / 2), np.flatnonzero(step[:, 1] * sense < PRINTED / 2)[:5]


@pytest.mark.parametrize("name", ["pipe", "cone", "elliptic_tube"])
def test_the_eye_reverses_while_the_mandrel_turns(name):
    """At each end of an open mandrel the carriage turns back: every reversal of X lies inside a
    stretch where A keeps moving, and the yaw passes through the hoop orientation (B = 0) there."""
    v = moves(name)
    dx = np.diff(v[:, 0])
    moving = np.flatnonzero(np.abs(dx) >= PRINTED / 2)
    flips = moving[1:][np.sign(dx[moving[1:]]) != np.sign(dx[moving[:-1]])]
    assert flips.size >= 2
    b = v[:, 3]
    for k in flips:
        window = b[max(k - 12, 0):k + 13]
        assert window.min() <= PRINTED and window.max() >= -PRINTED  # B crosses 0 nearby
