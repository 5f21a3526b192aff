"""Fuzzing the command line with random and mutated job files (hypothesis).

Whatever a user types into a job file, `winder check` and `winder run` either succeed or print
`Error: <file>: ...` and exit 2 (invalid config) or 1 (not computable); never a traceback, never an
"internal error", and a failed `run` leaves no file behind.

The examples are derandomized so CI is repeatable; WINDER_FUZZ_EXAMPLES=500 (say) runs more of them,
with fresh random seeds.

The mutation sweep (issue 15) mutates every sample and documented config FUZZ_CONFIGS times in all
(wrong types, scales 1e-9 .. 1e9, deletions, unknown keys), runs `check` on all of them and `check`
then `run` on FUZZ_RUNS of them, in child processes under a 2 GB memory limit and a time limit
(tests/sandbox.py). The nightly size (README):
WINDER_FUZZ_CONFIGS=20000 WINDER_FUZZ_RUNS=2000 python -m pytest tests/test_fuzz.py -k sweep
"""

from __future__ import annotations

import copy
import math
import os
import random
import signal
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
import yaml
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.sandbox import run_limited
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


# -- the mutation sweep ------------------------------------------------------------------------------
FUZZ_CONFIGS = int(os.environ.get("WINDER_FUZZ_CONFIGS", "2000"))
FUZZ_RUNS = int(os.environ.get("WINDER_FUZZ_RUNS", "24"))
FUZZ_SEED = int(os.environ.get("WINDER_FUZZ_SEED", "15"))
SWEEP_SECONDS = 120  # per command: a hang guard on a busy machine, not a speed assertion
RUN_LIMIT_S = 10  # run --time-limit: a job past it fails cleanly (exit 1), which the sweep counts
SCALES = [1e-9, 1e-6, 1e-3, 0.1, 0.5, 2.0, 10.0, 1e3, 1e6, 1e9]
UNKNOWN_KEYS = ["extra", "Radius", "typo", "x", "1", "band", "layer", "name "]


def _quick(base: dict) -> dict:
    """A base made quick to run: few points per pass, no tolerance."""
    data = copy.deepcopy(base)
    if isinstance(data.get("winding"), dict):
        data["winding"]["points"] = 6
        data["winding"].pop("tolerance", None)
    return data


SWEEP_BASES = [_quick(b) for b in BASES]


def _mutate(rng: random.Random, data: Any) -> Any:
    """One mutation of a random place: a scale (of a number), a wrong type, a deletion or an
    unknown key (in a mapping)."""
    paths = _paths(data)[1:]
    op = rng.choice(["scale", "scale", "scale", "retype", "retype", "delete", "unknown"])
    numbers = [p for p in paths if isinstance(_get(data, p), (int, float)) and not isinstance(_get(data, p), bool)]
    mappings = [p for p in _paths(data) if isinstance(_get(data, p), dict)]
    if op == "scale" and numbers:
        path = rng.choice(numbers)
        parent, key = _get(data, path[:-1]), path[-1]
        value = parent[key]
        factor = rng.choice(SCALES) * rng.choice([1, 1, 1, -1])
        scaled = float(value) * factor if abs(value) < 1e300 else math.inf
        # an int stays an int now and then (a count scaled: passes, pattern, points)
        whole = isinstance(value, int) and math.isfinite(scaled) and abs(scaled) < 1e18 and rng.random() < 0.5
        parent[key] = int(scaled) if whole else scaled
    elif op == "unknown" and mappings:
        _get(data, rng.choice(mappings))[rng.choice(UNKNOWN_KEYS)] = rng.choice(ODD_VALUES + [1, 10.0, "auto"])
    elif paths:
        path = rng.choice(paths)
        parent, key = _get(data, path[:-1]), path[-1]
        if op == "delete":
            del parent[key]
        else:
            parent[key] = rng.choice(ODD_VALUES)
    else:
        return rng.choice(ODD_VALUES)
    return data


def sweep_configs(n: int, seed: int) -> list[tuple[str, Any]]:
    """n mutated job files (base name, data), every base in turn, one to three mutations each."""
    rng = random.Random(seed)
    out = []
    for i in range(n):
        base = SWEEP_BASES[i % len(SWEEP_BASES)]
        data = copy.deepcopy(base)
        for _ in range(rng.choice([1, 1, 1, 2, 3])):
            data = _mutate(rng, data)
            if not isinstance(data, (dict, list)):
                break
        out.append((base["name"], data))
    return out


def _stderr_is_one_error(result: dict, config: str) -> None:
    lines = result["stderr"].splitlines()
    if result["code"] == 0:
        assert lines == [], result["stderr"]
        return
    assert len(lines) == 1 and lines[0].startswith("Error: ") and config in lines[0], result["stderr"]


def _assert_clean(result: dict, config: str, data: Any) -> None:
    where = f"{result['args'][0]} on:\n{_dump(data)}"
    assert result["code"] in (0, 1, 2), f"exit {result['code']}: {where}\n{result['stderr']}"
    assert result["uncaught"] is None, f"{result['uncaught']}: {where}"
    text = result["stdout"] + result["stderr"]
    assert "Traceback" not in text and "internal error" not in text, f"{text}\n{where}"
    _stderr_is_one_error(result, config)


@pytest.fixture(scope="module")
def sweep(tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("sweep")
    configs = sweep_configs(FUZZ_CONFIGS, FUZZ_SEED)
    paths = []
    for k, (_, data) in enumerate(configs):
        path = folder / f"m{k:05d}.yaml"
        path.write_text(_dump(data), encoding="utf-8")
        paths.append(str(path))
    started = time.perf_counter()
    checks = [r[0] for r in run_limited([[["check", p]] for p in paths], workers=2, seconds=SWEEP_SECONDS)]
    # run on configs check accepted (does run agree?) and, a quarter, on ones it refused
    valid = [k for k, r in enumerate(checks) if r["code"] == 0]
    invalid = [k for k, r in enumerate(checks) if r["code"] != 0]
    pick = random.Random(FUZZ_SEED)
    chosen = sorted(pick.sample(valid, min(len(valid), FUZZ_RUNS - FUZZ_RUNS // 4))
                    + pick.sample(invalid, min(len(invalid), FUZZ_RUNS // 4)))
    runs = run_limited([[["check", paths[k]], ["run", paths[k], "-o", str(folder / f"out{k}"),
                                                "--format", "csv,gcode", "--time-limit", str(RUN_LIMIT_S)]]
                        for k in chosen],
                       workers=2, seconds=SWEEP_SECONDS)
    return {"configs": configs, "paths": paths, "checks": checks, "chosen": chosen, "runs": runs,
            "seconds": time.perf_counter() - started}


def test_sweep_size(sweep) -> None:
    assert len(sweep["checks"]) == FUZZ_CONFIGS >= 2000 or "WINDER_FUZZ_CONFIGS" in os.environ
    valid = sum(r["code"] == 0 for r in sweep["checks"])
    # The mutations must reach both sides: valid files that plan, and every kind of refusal.
    assert 0.05 * FUZZ_CONFIGS < valid < 0.95 * FUZZ_CONFIGS, valid
    assert any(r[1]["code"] == 0 for r in sweep["runs"]), "no mutated job ran"


def test_sweep_check_is_clean(sweep) -> None:
    for (_, data), path, result in zip(sweep["configs"], sweep["paths"], sweep["checks"]):
        _assert_clean(result, Path(path).name, data)
        assert result["code"] in (0, 1, 2), result  # 1: refused from the config as not windable


def test_sweep_run_is_clean_and_agrees_with_check(sweep) -> None:
    for k, (check, run) in zip(sweep["chosen"], sweep["runs"]):
        data, path = sweep["configs"][k][1], sweep["paths"][k]
        _assert_clean(check, Path(path).name, data)
        _assert_clean(run, Path(path).name, data)
        assert check["code"] == sweep["checks"][k]["code"]
        if check["code"] == 0:
            assert run["code"] != 2, f"check accepted what run refused: {run['stderr']}\n{_dump(data)}"
        else:  # refused before computing: by both, with the same status and line
            assert run["code"] == check["code"] and run["stderr"] == check["stderr"], (check, run)
        if run["code"]:
            assert run["left"] == [], run["left"]
        else:
            name = data["name"]
            assert run["left"] == sorted([f"{name}.csv", f"{name}.gcode", f"{name}.summary.json"]), run["left"]
