"""One numbering of layers in every message (issue 49, item 1): a message names a layer as the summary, the
report, `patterns` and `design` do, from 1 with its type and angle (`layer 5 (helical 16 deg)`), never by
its list index (`winding.layers[4]`). Every invalid config of tests/config/invalid and a set of planning
refusals (budget, slip, pattern choices, the planner's own) are run; no message holds `layers[`, and the
layer a message names is the config's layer of that number, with that layer's type and angle."""

from __future__ import annotations

import copy
import re
from pathlib import Path

import pytest
import yaml

from winder.app.validate import validate, validate_job
from winder.config.job import parse_config
from winder.config.reader import load_yaml
from winder.errors import ConfigError, WinderError

ROOT = Path(__file__).resolve().parent.parent
INVALID = sorted((ROOT / "tests" / "config" / "invalid").glob("*.yaml"))
PIPE = ROOT / "samples" / "pipe.yaml"  # layer 1 helical 55 deg, layer 2 hoop
NAMED = re.compile(r"\blayer (\d+)\b")


def expected_label(number: int, item: object) -> str:
    """How a message names layer `number` (from 1) given as `item` in the YAML: written out here, not
    taken from winder, with what the item tells (a known type, then its angle)."""
    if not isinstance(item, dict) or item.get("type") not in ("helical", "hoop"):
        return f"layer {number}"
    angle = item.get("angle")
    if isinstance(angle, (int, float)) and not isinstance(angle, bool):
        return f"layer {number} ({item['type']} {angle:g} deg)"
    return f"layer {number} ({item['type']})"


def assert_one_numbering(message: str, items: list) -> int:
    """No `layers[` in message; each layer it names is the config's, by its full label; the count named."""
    assert "layers[" not in message, message
    named = 0
    for m in NAMED.finditer(message):
        number = int(m.group(1))
        assert 1 <= number <= len(items), f"layer {number} of {len(items)}: {message}"
        label = expected_label(number, items[number - 1])
        assert message[m.start():].startswith(label), f"expected {label!r}: {message}"
        if isinstance(items[number - 1], dict) and items[number - 1].get("type") in ("helical", "hoop"):
            assert message[m.start():].startswith(f"layer {number} ("), message
        named += 1
    return named


def _items(data: object) -> list:
    winding = data.get("winding") if isinstance(data, dict) else None
    layers = winding.get("layers") if isinstance(winding, dict) else None
    return layers if isinstance(layers, list) else []


@pytest.mark.parametrize("path", INVALID, ids=[p.stem for p in INVALID])
def test_invalid_config_names_layers_from_one(path: Path) -> None:
    with pytest.raises(ConfigError) as info:
        validate(path)
    try:
        data = load_yaml(path.read_text(encoding="utf-8"))  # as winder reads it
    except (yaml.YAMLError, ConfigError):  # the invalid YAML cases: no layers to name
        data = None
    assert_one_numbering(str(info.value), _items(data))


def test_invalid_configs_about_a_layer_name_it():
    """Not vacuous: the invalid configs about one layer (30 and more) each name it, with its type where known."""
    named = []
    for path in INVALID:
        first = path.read_text(encoding="utf-8").splitlines()[0]
        if NAMED.search(first):
            named.append(path.stem)
            with pytest.raises(ConfigError) as info:
                validate(path)
            assert NAMED.search(str(info.value)), str(info.value)
    assert len(named) >= 30, named
    assert {"hoop_taper_negative", "tension_missing_layer", "winding_unknown_layer_key"} <= set(named)


def _pipe(layers: list[dict], **winding) -> dict:
    data = yaml.safe_load(PIPE.read_text(encoding="utf-8"))
    data["winding"]["layers"] = layers
    data["winding"].update(winding)
    return data


def _vessel(layers: list[dict], **winding) -> dict:
    mandrel = {"profile": {"type": "vessel", "radius": 100, "cylinder_length": 200,
                           "dome": {"type": "hemisphere", "polar_opening": 25},
                           "end_dome": {"type": "hemisphere", "polar_opening": 30}}}
    return {"name": "v", "mandrel": mandrel, "winding": {"band_width": 8, "friction": 0.2, "layers": layers, **winding}}


# config -> the label of the layer refused (the second layer in each: a list index would say 1)
BUDGET = {
    "hoop_passes": (_pipe([{"type": "helical", "angle": 55}, {"type": "hoop", "passes": 2000}]),
                    "layer 2 (hoop).passes"),
    "hoop_angle": (_pipe([{"type": "helical", "angle": 55}, {"type": "hoop", "angle": 89.999, "passes": 2}]),
                   "layer 2 (hoop 89.999 deg).angle"),
    "pattern_factor": (_pipe([{"type": "hoop"}, {"type": "helical", "angle": 55, "pattern": 19}]),
                       "layer 2 (helical 55 deg).pattern"),
    "slip_number_open": (_pipe([{"type": "hoop"}, {"type": "helical", "angle": 55, "slip": 0.1}]),
                         "layer 2 (helical 55 deg).slip"),
    "vessel_angle": (_vessel([{"type": "hoop"}, {"type": "helical", "angle": 15}]),
                     "layer 2 (helical 15 deg).angle"),
}


@pytest.mark.parametrize("name", BUDGET)
def test_budget_refusals_name_the_layer_from_one(name: str) -> None:
    data, label = BUDGET[name]
    job = parse_config(copy.deepcopy(data), "part.yaml")
    with pytest.raises(ConfigError) as info:
        validate_job(job)
    message = str(info.value)
    assert f"part.yaml: {label}: " in message, message
    assert assert_one_numbering(message, data["winding"]["layers"]) >= 1


def test_pattern_choices_of_a_hoop_name_it_from_one():
    from winder.winding.choices import pattern_choices  # noqa: PLC0415

    data = _pipe([{"type": "helical", "angle": 55}, {"type": "hoop", "passes": 2}])
    job = parse_config(copy.deepcopy(data), "part.yaml")
    with pytest.raises(ConfigError) as info:
        pattern_choices(job, 1)
    message = str(info.value)
    assert "part.yaml: layer 2 (hoop): a hoop layer has no pattern to choose" in message
    assert_one_numbering(message, data["winding"]["layers"])


def test_slip_refusal_of_the_planner_names_the_layer_from_one():
    """A friction-held turnaround the friction cannot hold: refused by the planner (PlanContext.key)."""
    from winder.winding.plan import plan  # noqa: PLC0415

    data = _vessel([{"type": "hoop"}, {"type": "helical", "angle": 12, "turnaround_radius": 42}])
    job = parse_config(copy.deepcopy(data), "v.yaml")
    with pytest.raises(WinderError) as info:
        plan(job)
    message = str(info.value)
    assert message.startswith("v.yaml: layer 2 (helical 12 deg): on the first dome: "), message
    assert "what plans it: winding.friction" in message
    assert assert_one_numbering(message, data["winding"]["layers"]) >= 1
