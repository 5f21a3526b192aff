"""`winder schema` (winder.config.schema) against the readers it describes.

Truths: jsonschema's own Draft 2020-12 validator; every shipped config; the readers themselves, watched
while they read every config the tests hold (the keys each mapping allows at each key path, and the
kinds of each `type`), and read from their source (every key a reader names), so that a key added to a
reader and not to the schema, or the other way round, fails here.
"""

from __future__ import annotations

import ast
import json
import os
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from winder.cli import main
from winder.config.job import load_config
from winder.config.reader import Reader, load_yaml
from winder.config.schema import job_schema
from winder.errors import ConfigError

jsonschema = pytest.importorskip("jsonschema")

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = job_schema()
VALIDATOR = jsonschema.Draft202012Validator(SCHEMA)
# The fiberpath examples' hand-written configs, where the environment names their folder (.ci/run does).
_EXAMPLES = os.environ.get("WINDER_FIBERPATH_EXAMPLES")
SHIPPED = sorted([*ROOT.glob("configs/*.yaml"), *ROOT.glob("samples/*.yaml"), *ROOT.glob("parts/*.yaml"),
                  *ROOT.glob("docs/tutorial/*.yaml"),
                  *(Path(_EXAMPLES).glob("*.yaml") if _EXAMPLES else [])])
TEST_YAML = sorted(p for p in (ROOT / "tests").rglob("*.yaml") if "post" not in p.name)
# Keys a reader allows only to refuse them with a reason (an ellipsoid's depth on another dome says why
# instead of "unknown key"): the schema refuses them outright.
REFUSED_WITH_A_REASON = {("hemisphere", "depth"), ("isotensoid", "depth"), ("torispherical", "depth"),
                         ("contour", "depth")}
# Mappings whose keys are the user's own names (a stress ratio per fiber material).
FREE_KEYS = re.compile(r"\.stress_ratio$")


def _errors(data) -> list[str]:
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in VALIDATOR.iter_errors(data)]


def test_the_schema_is_a_draft_2020_12_schema():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    assert SCHEMA["$schema"] == "https://json-schema.org/draft/2020-12/schema"


def test_winder_schema_prints_it():
    result = CliRunner().invoke(main, ["schema"])
    assert result.exit_code == 0
    assert json.loads(result.stdout) == SCHEMA


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(p.parents[1])))
def test_every_shipped_config_validates(path):
    assert _errors(load_yaml(path.read_text(encoding="utf-8"))) == []


def test_every_config_the_readers_accept_validates(reads):
    *_, accepted = reads
    assert len([p for p in accepted if p in TEST_YAML]) >= 20  # the test configs are still where this looks
    for path in accepted:
        assert _errors(load_yaml(path.read_text(encoding="utf-8"))) == [], path


@pytest.mark.parametrize("where, typo", [
    ((), ("name", "nmae")),
    (("winding",), ("band_width", "band_widht")),
    (("mandrel", "profile"), ("radius", "raduis")),
    (("machine", "eye"), ("clearance", "clearence")),
    (("winding", "layers", 0), ("angle", "angel")),
])
def test_a_mistyped_key_is_refused_by_both(tmp_path, where, typo):
    data = load_yaml((ROOT / "samples" / "pipe.yaml").read_text(encoding="utf-8"))
    node = data
    for key in where:
        node = node[key]
    right, wrong = typo
    node[wrong] = node.pop(right)
    assert _errors(data), "the schema accepts a mistyped key"
    path = tmp_path / "typo.yaml"
    path.write_text(json.dumps(data), encoding="utf-8")  # JSON is YAML
    with pytest.raises(ConfigError, match=wrong):
        load_config(path)


# -- the schema against the readers, key path by key path -----------------------------------------------
def _objects_at(node: dict, parts: list) -> list[dict]:
    """The object schemas at a reader's key path (every branch of a oneOf / anyOf)."""
    if "properties" not in node and ("oneOf" in node or "anyOf" in node):
        return [o for branch in node.get("oneOf", node.get("anyOf")) for o in _objects_at(branch, parts)]
    if not parts:
        return [node] if "properties" in node else []
    head, rest = parts[0], parts[1:]
    if head == "[]":
        return _objects_at(node["items"], rest) if "items" in node else []
    child = node.get("properties", {}).get(head)
    return _objects_at(child, rest) if child is not None else []


# A layer's key path names it as messages do (`layer 2 (hoop).passes`: winder.config.winding.layer_key).
LAYER_KEY = re.compile(r"^layer \d+(?: \([^)]*\))?")


def _listed(path: str) -> str:
    """The reader's key path with each list index as `[]` (a layer's label as `winding.layers[]`)."""
    return re.sub(r"\[\d+\]", "[]", LAYER_KEY.sub("winding.layers[]", path))


def _parts(path: str) -> list:
    return [p for p in re.split(r"\.|(\[\])", _listed(path)) if p]


def _watched_reads(monkeypatch) -> tuple[dict, dict, list]:
    """Every (key path -> allowed keys) and (key path -> kinds) the readers check while reading every
    config the tests and the repository hold, valid or not (a reader names its keys before it refuses),
    and the configs they accept."""
    mappings: dict[str, list[frozenset]] = {}
    kinds: dict[str, dict] = {}
    plain, typed = Reader.mapping, Reader.typed

    def mapping(self, value, path, allowed, required=(), kind=""):
        if not kind and not FREE_KEYS.search(path) and self.source == reading[0]:  # not a file the job names
            seen = mappings.setdefault(_listed(path), [])
            if frozenset(allowed) not in seen:
                seen.append(frozenset(allowed))
        return plain(self, value, path, allowed, required, kind)

    def typed_(self, value, path, noun, kinds_, tag="type"):
        if self.source != reading[0]:
            return typed(self, value, path, noun, kinds_, tag)
        kinds.setdefault(_listed(path), {}).update(
            {k: ({tag, *req}, {tag, *req, *opt}) for k, (req, opt) in kinds_.items()})
        return typed(self, value, path, noun, kinds_, tag)

    monkeypatch.setattr(Reader, "mapping", mapping)
    monkeypatch.setattr(Reader, "typed", typed_)
    reading = [""]
    accepted = []
    for path in [*SHIPPED, *TEST_YAML]:
        reading[0] = str(path)
        try:
            load_config(path)
        except ConfigError:
            continue
        accepted.append(path)
    monkeypatch.undo()
    return mappings, kinds, accepted


@pytest.fixture(scope="module")
def reads():
    with pytest.MonkeyPatch.context() as mp:
        yield _watched_reads(mp)


def test_every_mapping_a_reader_reads_has_the_schemas_keys(reads):
    mappings, *_ = reads
    assert {"", "mandrel", "winding", "machine"} <= set(mappings)
    for path, sets in mappings.items():
        where = path or "the top"
        nodes = _objects_at(SCHEMA, _parts(path))
        assert nodes, f"{where}: no such mapping in the schema"
        # One mapping of the reader is one object of the schema, or all of them together (a mapping holding
        # exactly one of its keys: a path's {line: L} or {arc: ...}); a value of several shapes (a tension
        # as {start, end} or as a schedule) is read by one mapping per shape.
        branches = [set(n["properties"]) for n in nodes]
        shapes = [*branches, set().union(*branches)]
        for allowed in sets:
            closest = min(shapes, key=lambda b: len(b ^ allowed))
            assert allowed in shapes, (f"{where}: only the readers allow {sorted(allowed - closest)}, only the "
                                       f"schema {sorted(closest - allowed)}")
        read = set().union(*sets)
        for branch in branches:
            assert branch <= read, f"{where}: the schema allows {sorted(branch - read)}, which no reader does"


def test_every_kind_a_reader_reads_has_the_schemas_keys(reads):
    _, kinds, _ = reads
    assert {"mandrel.axis", "mandrel.profile", "mandrel.section", "winding.layers[]"} <= set(kinds)
    for path, by_kind in kinds.items():
        variants = {n["properties"]["type"]["const"]: n for n in _objects_at(SCHEMA, _parts(path))
                    if "const" in n["properties"].get("type", {})}
        assert set(variants) == set(by_kind), f"{path}: kinds {sorted(by_kind)} read, {sorted(variants)} described"
        for kind, (required, allowed) in by_kind.items():
            allowed = {k for k in allowed if (kind, k) not in REFUSED_WITH_A_REASON}
            node = variants[kind]
            assert set(node["properties"]) == allowed, f"{path} ({kind}): {sorted(allowed ^ set(node['properties']))}"
            assert set(node["required"]) == required, f"{path} ({kind}): required {sorted(required)}"


def _named_keys(tree: ast.Module, constants: dict[str, ast.AST]) -> tuple[set[str], set[str]]:
    """(keys, kinds) a module's readers name: the strings of every allowed-keys argument of a mapping()
    call and of the kinds' keys in a typed() call (the kinds: that dict's own keys), the names they use
    resolved through the config modules' constants."""
    keys: set[str] = set()
    kinds: set[str] = set()

    def resolved(node: ast.AST) -> ast.AST:
        return resolved(constants[node.id]) if isinstance(node, ast.Name) and node.id in constants else node

    def strings(node: ast.AST) -> None:
        for sub in ast.walk(node):
            if isinstance(sub, ast.Constant) and isinstance(sub.value, str):
                keys.add(sub.value)
            elif isinstance(sub, ast.Name) and sub.id in constants:
                strings(constants[sub.id])

    for node in ast.walk(tree):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
            continue
        if node.func.attr == "mapping" and len(node.args) > 2 and not isinstance(node.args[2], (ast.Call, ast.GeneratorExp)):
            strings(node.args[2])
        elif node.func.attr == "typed" and len(node.args) > 3 and isinstance(table := resolved(node.args[3]), ast.Dict):
            kinds.update(k.value for k in table.keys if isinstance(k, ast.Constant))
            for value in table.values:
                strings(value)
    return keys, kinds



def test_every_key_a_reader_names_is_in_the_schema():
    """From the readers' source: a key no config of the tests reaches is still checked."""
    # A module making a Reader of its own reads another kind of file (fiberpath's .wind, a controller's post
    # file): its keys are not the job file's. job.py makes the job file's.
    sources = {p: ast.parse(text) for p in (ROOT / "winder" / "config").glob("*.py")
               if p.name == "job.py" or "Reader(" not in (text := p.read_text(encoding="utf-8"))}
    constants = {t.id: node.value for tree in sources.values() for node in tree.body
                 if isinstance(node, ast.Assign) for t in node.targets if isinstance(t, ast.Name)}
    described, consts = set(), set()
    for node in _walk_schema(SCHEMA):
        described.update(node.get("properties", {}))
        consts.update([node["const"]] if "const" in node else [])
    assert len(sources) > 10
    for path, tree in sources.items():
        keys, kinds = _named_keys(tree, constants)
        assert not keys - described, f"{path.name} reads keys the schema does not describe: {sorted(keys - described)}"
        assert not kinds - consts, f"{path.name} reads kinds the schema does not describe: {sorted(kinds - consts)}"

def _walk_schema(node):
    if isinstance(node, dict):
        yield node
        for value in node.values():
            yield from _walk_schema(value)
    elif isinstance(node, list):
        for value in node:
            yield from _walk_schema(value)


def test_every_key_says_what_it_is():
    """Every key's description ends in a full stop and names a unit or a range where it is a number."""
    for node in _walk_schema(SCHEMA):
        for key, prop in node.get("properties", {}).items():
            assert prop.get("description"), key
            if prop.get("type") in ("number", "integer"):
                assert re.search(r"(>|<|in [\[(]|any finite)", prop["description"]), (key, prop["description"])


def _at(path: str) -> dict:
    """The schema of the key at a dotted path (kind variants by `path@kind`)."""
    node = SCHEMA
    for part in path.split("."):
        name, _, kind = part.partition("@")
        node = node["properties"][name]
        node = node.get("items", node) if node.get("type") == "array" else node
        if kind:
            node = next(v for v in node["oneOf"] if v["properties"]["type"]["const"] == kind)
    return node


def test_the_defaults_the_schema_shows_are_the_configs():
    """Each default an editor shows is the one the config's dataclasses take when the key is left out."""
    from winder.config.analysis import AnalysisConfig  # noqa: PLC0415
    from winder.config.machine import MachineConfig, MachineDynamics  # noqa: PLC0415
    from winder.config.robot import RobotCell  # noqa: PLC0415
    from winder.config.winding import LayerConfig, WindingConfig  # noqa: PLC0415

    machine, dynamics, cell = MachineConfig(), MachineDynamics(), RobotCell("kuka_kr16")
    expected = {
        "winding.points": WindingConfig(1.0).points, "winding.friction": WindingConfig(1.0).friction,
        "winding.layers@hoop.passes": LayerConfig(None).passes, "winding.layers@hoop.taper": LayerConfig(None).taper,
        "winding.layers@helical.step_back": LayerConfig(None).step_back,
        "machine.feed": machine.feed, "machine.chord_tolerance": machine.chord_tolerance,
        "machine.eye.clearance": machine.eye_clearance, "machine.eye.size": machine.eye_size,
        **{f"machine.axes.{role}": getattr(machine.axes, role) for role in ("carriage", "rotation", "cross_feed", "yaw")},
        **{f"machine.dynamics.{role}.speed": dynamics.get(role).speed for role in ("carriage", "rotation", "yaw")},
        **{f"machine.dynamics.{role}.acceleration": dynamics.get(role).acceleration
           for role in ("carriage", "rotation", "yaw")},
        "machine.robot.positioner.axes": cell.axes, "machine.robot.max_joint_step": cell.max_joint_step,
        "machine.robot.singularity_margin": cell.singularity_margin,
        "analysis.pressure": AnalysisConfig().pressure, "analysis.ends": AnalysisConfig().ends,
    }
    for path, value in expected.items():
        node = _robot_at(path) if path.startswith("machine.robot.") else _at(path)
        assert node.get("default") == value, f"{path}: the schema shows {node.get('default')!r}, the config takes {value!r}"


def _robot_at(path: str) -> dict:
    node = next(b for b in _at("machine.robot")["anyOf"] if b.get("type") == "object")
    for part in path.split(".")[2:]:
        node = node["properties"][part]
    return node
