"""winder.config.machine: machine.dialect and machine.dynamics parse to their dataclasses."""

from __future__ import annotations

import textwrap

from winder.config.job import load_config
from winder.config.machine import DEFAULT_DYNAMICS, AxisDynamics


def write(tmp_path, machine: str):
    path = tmp_path / "m.yaml"
    path.write_text(textwrap.dedent("""\
        name: m
        mandrel:
          axis: {type: line, length: 500}
          profile: {type: constant, radius: 50}
        """) + machine)
    return load_config(path).machine


def test_defaults(tmp_path):
    machine = write(tmp_path, "")
    assert machine.dialect == "generic"
    for role, (speed, acc) in DEFAULT_DYNAMICS.items():
        assert machine.dynamics.get(role) == AxisDynamics(speed, acc)


def test_dialect_and_partial_dynamics(tmp_path):
    machine = write(tmp_path, "machine:\n  dialect: marlin\n  dynamics: {carriage: {speed: 12000}}\n")
    assert machine.dialect == "marlin" and not machine.robot
    assert machine.dynamics.carriage == AxisDynamics(12000.0, DEFAULT_DYNAMICS["carriage"][1])
    assert machine.dynamics.rotation == AxisDynamics(*DEFAULT_DYNAMICS["rotation"])


def test_robot_dialect_means_robot(tmp_path):
    machine = write(tmp_path, "machine:\n  dialect: robot\n")
    assert machine.robot and machine.dialect == "robot"
