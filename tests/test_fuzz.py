"""Fuzzing the command line with random and mutated job files (hypothesis).

Whatever a user types into a job file, `winder check` and `winder run` either succeed or print
`Error: <file>: ...` and exit 2 (invalid config) or 1 (not computable); never a traceback, never an
"internal error", and a failed `run` leaves no file behind.

The examples are derandomized so CI is repeatable; WINDER_FUZZ_EXAMPLES=500 (say) runs more of them,
with fresh random seeds.
"""

from __future__ import annotations

import copy
import math
import os
import signal
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import yaml
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from winder.cli import main

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
EXTRA = int(os.environ.get("WINDER_FUZZ_EXAMPLES", "0"))
_FUZZ = settings(deadline=None, derandomize=EXTRA == 0, database=None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def examples(n: int) -> settings:
    return settings(_FUZZ, max_examples=EXTRA or n)
RUN_SECONDS = 30  # a single mutated job taking longer than this is a hang, and a bug


def _load(path: Path) -> dict:
    return yaml.safe_load(path.read_text(encoding="utf-8"))


# The job files every mutation starts from: the samples and the documented examples. For `run`, the
# quick ones only (open mandrels; vessels spend seconds closing their pattern), with few points.
BASES = [_load(p) for p in sorted(SAMPLES.glob("*.yaml")) + sorted((ROOT / "configs").glob("*.yaml"))]
QUICK = [copy.deepcopy(b) for b in BASES if b["name"] in ("pipe", "cone")]
for base in QUICK:
    base["winding"]["points"] = 6
    base["winding"].pop("tolerance", None)

ODD_VALUES = [None, True, False, "", "text", "55", "1e3", [], {}, [1, 2], {"a": 1}, math.nan, math.inf,
              -math.inf, 0, -1, -0.0, -1e-9, 1e-300, 1e308, 10**400, -(10**30), 3.5, 7, "auto", "\x00", "é"]

scalars = st.one_of(st.sampled_from(ODD_VALUES), st.integers(-(10**6), 10**6),
                    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=12))
yamlish = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                        st.dictionaries(st.text(max_size=8), inner, max_size=4)),
                       max_leaves=12)


def _paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    """Every key path into a nested structure of dicts and lists."""
    out = [prefix]
    if isinstance(node, dict):
        for key, value in node.items():
            out += _paths(value, prefix + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            out += _paths(value, prefix + (i,))
    return out


def _get(node: Any, path: tuple) -> Any:
    for key in path:
        node = node[key]
    return node


@st.composite
def mutated(draw: st.DrawFn, bases: list[dict]) -> dict | Any:
    """A valid job file with one to three mutations: a key deleted or added, a value replaced by
    one of the wrong type / NaN / infinite / negative / huge, a number scaled."""
    data = copy.deepcopy(draw(st.sampled_from(bases)))
    for _ in range(draw(st.integers(1, 3))):
        paths = _paths(data)
        path = draw(st.sampled_from(paths))
        op = draw(st.sampled_from(["delete", "replace", "scale", "add_key", "to_list"]))
        if not path:  # the whole document
            if op in ("replace", "to_list"):
                data = draw(yamlish)
            continue
        parent, key = _get(data, path[:-1]), path[-1]
        value = parent[key]
        if op == "delete":
            del parent[key]
        elif op == "replace":
            parent[key] = draw(st.one_of(scalars, yamlish))
        elif op == "scale" and isinstance(value, (int, float)) and not isinstance(value, bool):
            factor = draw(st.sampled_from([-1, 0, 1e-9, 1e-3, 0.5, 1.0001, 2, 10, 1e3, 1e6, 1e12]))
            parent[key] = value * factor
        elif op == "add_key" and isinstance(value, dict):
            value[draw(st.sampled_from(["extra", "Radius", "typo", "x", "1"]))] = draw(scalars)
        elif op == "to_list" and isinstance(value, dict):
            parent[key] = list(value.values())
        if not isinstance(data, (dict, list)):
            break
    return data


def _dump(data: Any) -> str:
    try:
        return yaml.safe_dump(data, allow_unicode=True, sort_keys=False)
    except yaml.YAMLError:
        return repr(data)


class Hang(BaseException):
    """A job running past RUN_SECONDS (a BaseException: nothing in winder may swallow it)."""


@contextmanager
def time_limit(seconds: int):
    def _alarm(signum, frame):
        raise Hang(f"took more than {seconds} s")

    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _invoke(args: list[str]):
    result = CliRunner().invoke(main, args)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise AssertionError(f"uncaught {type(result.exception).__name__}: {result.exception}\n"
                             f"{result.output}") from result.exception
    assert "Traceback" not in result.output, result.output
    assert "internal error" not in result.output, result.output
    return result


def _assert_refused_properly(result, config: Path, codes: set[int]) -> None:
    assert result.exit_code in codes | {0}, (result.exit_code, result.output)
    if result.exit_code:
        errors = [line for line in result.stderr.splitlines() if line.startswith("Error:")]
        assert errors, result.output
        assert all(config.name in line for line in errors), result.output


@examples(80)
@given(st.one_of(mutated(BASES), mutated(BASES), yamlish))
def test_check_never_crashes(data):
    with tempfile.TemporaryDirectory() as tmp:
        config = Path(tmp) / "fuzz.yaml"
        config.write_text(_dump(data), encoding="utf-8")
        result = _invoke(["check", str(config)])
        _assert_refused_properly(result, config, {2})


@examples(40)
@given(st.text(max_size=200))
def test_check_random_text(text):
    with tempfile.TemporaryDirectory() as tmp:
        config = Path(tmp) / "fuzz.yaml"
        config.write_text(text, encoding="utf-8")
        result = _invoke(["check", str(config)])
        _assert_refused_properly(result, config, {2})


@examples(25)
@given(mutated(QUICK))
def test_run_never_crashes(data):
    with tempfile.TemporaryDirectory() as tmp:
        config = Path(tmp) / "fuzz.yaml"
        config.write_text(_dump(data), encoding="utf-8")
        out = Path(tmp) / "out"
        try:
            with time_limit(RUN_SECONDS):
                result = _invoke(["run", str(config), "-o", str(out), "--format", "csv,gcode"])
        except Hang as exc:
            raise AssertionError(f"winder run {exc} on:\n{_dump(data)}") from None
        _assert_refused_properly(result, config, {1, 2})
        written = sorted(p.name for p in out.iterdir()) if out.exists() else []
        if result.exit_code:
            assert written == [], (written, result.output)  # a failed job leaves nothing behind
        else:
            name = data["name"]
            assert written == sorted([f"{name}.csv", f"{name}.gcode", f"{name}.summary.json"])
