"""winder.config.reader.load_yaml: libyaml's parser and PyYAML's own read every job file alike, and
what libyaml refuses is reported as PyYAML reports it."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from winder.config import reader
from winder.config.job import load_config
from winder.errors import ConfigError

ROOT = Path(__file__).resolve().parents[2]
JOB_FILES = sorted([*ROOT.glob("samples/*.yaml"), *ROOT.glob("configs/*.yaml"),
                    *(ROOT / "tests/config/invalid").glob("*.yaml")])
needs_libyaml = pytest.mark.skipif(reader._CParser is None, reason="PyYAML built without libyaml")


def same(a: object, b: object) -> bool:
    """Equal data, with the same types, key order and NaNs."""
    if type(a) is not type(b):
        return False
    if isinstance(a, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    if isinstance(a, dict):
        return list(a) == list(b) and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return a == b


@needs_libyaml
@pytest.mark.parametrize("path", JOB_FILES, ids=lambda p: p.name)
def test_both_parsers_read_the_same_data(path: Path) -> None:
    """Same data from both; where the file is not YAML, the same refusal. A document past the expansion
    limit (or recursive) is refused by winder over both parsers alike (tested below)."""
    text = path.read_text(encoding="utf-8")
    try:
        reader.load_yaml(text)
    except reader.ExpansionError:
        return
    except (yaml.YAMLError, ValueError, RecursionError):
        pass
    try:
        expected = yaml.load(text, Loader=reader.YamlLoader)  # noqa: S506
    except yaml.YAMLError as exc:  # not YAML: load_yaml raises PyYAML's own error
        with pytest.raises(type(exc)) as info:
            reader.load_yaml(text)
        assert str(info.value) == str(exc)
        return
    assert same(yaml.load(text, Loader=reader._FastLoader), expected)  # noqa: S506


@pytest.mark.parametrize("text", [
    "a: 1e-3\nb: no\nc: 1:30\nd: 2024-01-01\ne: 0x1F\nf: .inf\ng: ~\nh: True\n",
    "a: [1, 2.5, -3]\nb: {c: 'x', d: \"y\"}\n",
])
def test_core_schema_scalars(text: str) -> None:
    data = reader.load_yaml(text)
    assert same(data, yaml.load(text, Loader=reader.YamlLoader))  # noqa: S506
    if "1e-3" in text:
        assert data == {"a": 0.001, "b": "no", "c": "1:30", "d": "2024-01-01", "e": 31, "f": math.inf,
                        "g": None, "h": True}


@pytest.mark.parametrize(("text", "message"), [
    ("name: a\nmandrel: {profile: {radius: 40}\n", "line 3, column 1: invalid YAML: expected ',' or '}'"),
    ("name: a\nname: b\n", "line 2, column 1: invalid YAML: duplicate key 'name'"),
    ("name: a\nmandrel:\n" + "".join(" " * i + "x:\n" for i in range(1, 1500)),
     "invalid YAML: nested too deeply"),
])
def test_refusals_are_pyyamls(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "job.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        load_config(path)
    assert message in str(info.value)


@pytest.mark.skipif(reader._CParser is None, reason="PyYAML without libyaml: its own composer raises RecursionError")
def test_nesting_is_counted_before_libyaml_composes_it() -> None:
    """libyaml's composer recurses in C (PyYAML 6.0.3 overflowed the stack on 100,000 '['): the depth is
    read from the event stream first, and past MAX_NESTING the document is refused as too deep."""
    depth = reader.MAX_NESTING
    value = reader.load_yaml("a: " + "[" * (depth - 1) + "1" + "]" * (depth - 1))["a"]
    for _ in range(depth - 1):
        value = value[0]
    assert value == 1
    with pytest.raises(RecursionError):
        reader.load_yaml("a: " + "[" * depth + "1" + "]" * depth)
    with pytest.raises(RecursionError):
        reader.load_yaml("x:\n" + "".join("  " * k + "- \n" for k in range(1, 3 * depth)))
    assert reader._deeper_than("a: {b: [1, {c: 2}]}", 3) and not reader._deeper_than("a: {b: [1, {c: 2}]}", 4)


# -- aliases: counted expanded, in time linear in the file (issue 45) --------------------------------
def test_the_expanded_size_counts_each_alias_as_what_it_stands_for() -> None:
    """[&a [1, 2, 3], *a, *a]: the outer list, three lists of four values each (closed form 1 + 3 x 4)."""
    loader = reader.YamlLoader("[&a [1, 2, 3], *a, *a]")
    try:
        assert reader.expanded_size(loader.get_single_node()) == 13
    finally:
        loader.dispose()


@pytest.mark.parametrize("parser", ["libyaml", "pyyaml"])
def test_a_document_expanding_past_the_limit_is_refused_before_it_is_built(parser, monkeypatch) -> None:
    """Nine levels of ten aliases: 10^9 values; refused at once (before: built as shared lists, then
    walked by every check), with the same message by both parsers."""
    if parser == "pyyaml":
        monkeypatch.setattr(reader, "_CParser", None)
    elif reader._CParser is None:
        pytest.skip("PyYAML built without libyaml")
    levels = ["&l0 [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]"]
    levels += [f"&l{k} [{', '.join([f'*l{k - 1}'] * 10)}]" for k in range(1, 9)]
    with pytest.raises(yaml.YAMLError, match="its aliases expand it to more than 1,000,000 values"):
        reader.load_yaml("x: [" + ", ".join(levels) + "]\n")
    just_under = "x: [&a [" + ", ".join(["0"] * 998) + "], " + ", ".join(["*a"] * 999) + "]\n"  # 999,003 values
    assert len(reader.load_yaml(just_under)["x"]) == 1000


def test_a_recursive_alias_is_refused() -> None:
    with pytest.raises(yaml.YAMLError, match="an alias inside its own anchor"):
        reader.load_yaml("a: &x {b: *x}\n")
