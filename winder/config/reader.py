"""Reading a job file's values: a YAML 1.2 loader and the Reader that checks each value.

Every error a Reader raises is a ConfigError reading `<file>: <key.path>: <what is wrong>, got
<value>` (docs/guide/commands.md, "Exit status"); the parsers of winder.config.mandrel and winder.config.winding use nothing else.
"""

from __future__ import annotations

import datetime
import difflib
import math
import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from typing import Any

import yaml

from winder.config.yaml_expansion import ExpansionError, expanded_size
from winder.errors import ConfigError

# Slack (mm) when comparing user-typed lengths with computed ones: an arc's length is irrational,
# so a region end typed as 235.62 for a 150 mm x 90 deg bend must still count as "inside".
LENGTH_SLACK = 1e-3
MAX_SIZE = 1e6  # the largest length (mm), feed (mm/min) or other positive size a config may give


# -- reading YAML ----------------------------------------------------------------------------------
class _Rules:
    """What winder's YAML means, whichever parser reads it: duplicate keys refused."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        seen: set[Any] = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)  # type: ignore[attr-defined]
            try:  # hash() first: `set() in seen` hashes a set key as a frozenset, and add() would not
                hash(key)
                duplicate = key in seen
            except TypeError:  # an unhashable key: the base class reports it
                continue
            if duplicate:
                raise yaml.constructor.ConstructorError(None, None, f"duplicate key {key!r}",
                                                        key_node.start_mark)
            seen.add(key)
        return yaml.constructor.SafeConstructor.construct_mapping(self, node, deep)  # type: ignore[arg-type]


class YamlLoader(_Rules, yaml.SafeLoader):
    """SafeLoader reading plain scalars by the YAML 1.2 core schema, refusing duplicate keys.

    PyYAML follows YAML 1.1, where `1e-3` is a string, `no` and `off` are false, `1:30` is 90 and
    `2024-01-01` is a date: surprises for a process engineer typing a tolerance or a name. A
    duplicate key silently wins in PyYAML; here it is an error, since one of the two is a typo.
    """

    yaml_implicit_resolvers: dict[str, list[tuple[str, re.Pattern[str]]]] = {}


_INT_DIGITS = 400  # digits of the longest integer read as one: 1e400 is beyond a float already


def _construct_int(loader: YamlLoader, node: yaml.ScalarNode) -> int:
    text = loader.construct_scalar(node)
    base = 16 if text.startswith("0x") else 8 if text.startswith("0o") else 10
    if len(text) > _INT_DIGITS:  # past any float, and past what Python converts (4,300 digits)
        return -math.inf if text.startswith("-") else math.inf
    return int(text[2:] if base != 10 else text, base)


def _construct_float(loader: YamlLoader, node: yaml.ScalarNode) -> float:
    text = loader.construct_scalar(node).lower()
    if text.endswith(".inf"):
        return -math.inf if text.startswith("-") else math.inf
    return math.nan if text == ".nan" else float(text)


def _construct_bool(loader: YamlLoader, node: yaml.ScalarNode) -> bool:
    text = loader.construct_scalar(node).lower()
    if text not in ("true", "false"):  # an explicit `!!bool yes`
        raise ValueError(text)
    return text == "true"


YamlLoader.add_implicit_resolver("tag:yaml.org,2002:null", re.compile(r"^(?:~|null|Null|NULL|)$"),
                              ["~", "n", "N", ""])
YamlLoader.add_implicit_resolver("tag:yaml.org,2002:bool", re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"),
                              list("tTfF"))
# int before float: both match "12", and the first match wins.
YamlLoader.add_implicit_resolver("tag:yaml.org,2002:int",
                              re.compile(r"^(?:[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+)$"),
                              list("-+0123456789"))
YamlLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
               r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"),
    list("-+.0123456789"))
def _refusing(kind: str, construct: Callable[[Any, yaml.ScalarNode], Any]) -> Callable[[Any, yaml.ScalarNode], Any]:
    """construct, with a scalar it cannot read (an explicit `!!int abc`, `!!timestamp 2001-13-45`, an
    int of 5,000 digits) refused as invalid YAML at the value's line, not as a Python exception."""

    def checked(loader: Any, node: yaml.ScalarNode) -> Any:
        try:
            return construct(loader, node)
        except (ValueError, TypeError, AttributeError, OverflowError) as exc:
            raise yaml.constructor.ConstructorError(
                None, None, f"{show_value(node.value)} is not {kind}", node.start_mark) from exc

    return checked


for _tag, _kind, _construct in (("int", "a whole number", _construct_int), ("float", "a number", _construct_float),
                                ("bool", "true or false", _construct_bool),
                                ("timestamp", "a date", yaml.SafeLoader.construct_yaml_timestamp),
                                ("binary", "base64 data", yaml.SafeLoader.construct_yaml_binary)):
    YamlLoader.add_constructor(f"tag:yaml.org,2002:{_tag}", _refusing(_kind, _construct))


try:
    from yaml.cyaml import CParser as _CParser  # PyYAML built with libyaml
except ImportError:
    _CParser = None


class _FastLoader(_Rules, _CParser or object, yaml.constructor.SafeConstructor,  # type: ignore[misc]
                  yaml.resolver.Resolver):
    """YamlLoader's rules on libyaml's parser (several times faster than PyYAML's own)."""

    yaml_implicit_resolvers = YamlLoader.yaml_implicit_resolvers
    yaml_constructors = YamlLoader.yaml_constructors

    def __init__(self, stream: str) -> None:
        _CParser.__init__(self, stream)  # type: ignore[union-attr]
        yaml.constructor.SafeConstructor.__init__(self)
        yaml.resolver.Resolver.__init__(self)


# Collections nested deeper than this are refused (RecursionError, as PyYAML's own composer raises):
# a job file needs a few levels. libyaml's composer recurses in C, and some PyYAML builds (6.0.3's)
# overflow the C stack on a file of 100,000 '[' instead of raising.
MAX_NESTING = 100


def _deeper_than(text: str, limit: int) -> bool:
    """Whether the document nests collections deeper than limit, from libyaml's event stream (its
    parser keeps its own stack, so no recursion), read only until the limit is passed: libyaml's
    scanner costs time in proportion to the depth for every token. A YAMLError where it cannot read."""
    parser = _CParser(text)  # type: ignore[misc]
    depth = 0
    try:
        while (event := parser.get_event()) is not None and not isinstance(event, yaml.StreamEndEvent):
            if isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
                depth += 1
                if depth > limit:
                    return True
            elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
                depth -= 1
    finally:
        parser.dispose()
    return False


def _load(loader: Any) -> Any:
    """The document of a loader, refused past MAX_EXPANDED_VALUES before it is constructed."""
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        expanded_size(node)
        return loader.construct_document(node)
    finally:
        loader.dispose()


def load_yaml(text: str) -> Any:
    """The data of a YAML document read by YamlLoader's rules, in time and memory linear in its size.

    libyaml parses where PyYAML has it. Anything it refuses is read again by PyYAML's own parser,
    which raises the error: messages (line, column, problem) and the nesting and expansion limits are
    the same with or without libyaml.
    """
    if _CParser is not None:
        try:
            deep = _deeper_than(text, MAX_NESTING)
        except yaml.YAMLError:
            deep = False  # PyYAML's parser below names the problem
        if deep:
            raise RecursionError(f"collections nested deeper than {MAX_NESTING} levels")
        try:
            return _load(_FastLoader(text))
        except ExpansionError:
            raise  # read whole already: PyYAML's parser would take 20 s to say the same
        except (yaml.YAMLError, ValueError, RecursionError):
            pass
    return _load(YamlLoader(text))


# -- checking values -------------------------------------------------------------------------------
_NO_VALUE = object()


def show_value(value: object) -> str:
    """A value as the user wrote it in YAML, short enough for a one-line message."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        return str(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)
    text = ""  # strings keep their quotes, so 40 and '40' stay distinguishable
    for piece in _pieces(value, 0):
        text += piece
        if len(text) > SHOWN_CHARS:
            break  # a list of aliases to aliases (a "billion laughs") is never rendered whole
    return text if len(text) <= SHOWN_CHARS else text[:SHOWN_CHARS - 3] + "..."


SHOWN_CHARS = 80  # a value in a message: enough to recognize it on one line
_SHOWN_DEPTH = 20  # levels of nesting rendered; the message is cut long before a job file's nesting


def _pieces(value: object, depth: int) -> Iterator[str]:
    """value as Python writes it (repr), piece by piece, so that the caller can stop early."""
    if depth > _SHOWN_DEPTH:
        yield "..."
    elif isinstance(value, (list, tuple, dict, set, frozenset)):
        if isinstance(value, dict):
            items: Iterable[Any] = value.items()
        elif isinstance(value, (set, frozenset)):  # repr's order follows string hashing, which varies per run
            items = sorted(value, key=repr)
        else:
            items = value
        if not value and isinstance(value, (set, frozenset)):
            yield "set()"
            return
        opening, closing = {list: "[]", tuple: "()", dict: "{}"}.get(type(value), "{}")
        if isinstance(value, tuple) and len(value) == 1:
            closing = ",)"
        yield opening
        for i, item in enumerate(items):
            if i:
                yield ", "
            if isinstance(value, dict):
                yield from _pieces(item[0], depth + 1)
                yield ": "
                item = item[1]
            yield from _pieces(item, depth + 1)
        yield closing
    elif isinstance(value, (datetime.date, datetime.time)):  # an explicit !!timestamp
        yield value.isoformat()
    elif isinstance(value, (str, bytes)):
        yield repr(value[:SHOWN_CHARS])  # a long one is cut anyway
    else:
        yield repr(value)


class Reader:
    """Reads the values of one job file; every error names the file and the key path."""

    def __init__(self, source: str) -> None:
        self.source = source

    @staticmethod
    def at(path: str, key: str | int) -> str:
        """The key path of a mapping key (`a.b`) or a list index (`a[2]`) below path."""
        if isinstance(key, int):
            return f"{path}[{key}]"
        return f"{path}.{key}" if path else key

    def error(self, path: str, what: str, value: object = _NO_VALUE) -> ConfigError:
        got = "" if value is _NO_VALUE else f", got {show_value(value)}"
        return ConfigError(f"{what}{got}", file=self.source, key_path=path or None)

    def mapping(self, value: Any, path: str, allowed: Sequence[str], required: Sequence[str] = (),
                kind: str = "") -> dict[str, Any]:
        """value as a mapping, refusing unknown keys (with a suggestion) and missing required ones."""
        if not isinstance(value, dict):
            raise self.error(path, f"must be a mapping with keys {', '.join(allowed)}", value)
        for key in value:
            if key in allowed:
                continue
            name = key if isinstance(key, str) else show_value(key)
            close = difflib.get_close_matches(name, allowed, n=1)
            what = "unknown key" + (f" for {kind}" if kind else "")
            hint = f"; did you mean '{close[0]}'? allowed: " if close else "; allowed: "
            raise self.error(self.at(path, name), what + hint + ", ".join(allowed))
        for key in required:
            if key not in value:
                raise self.error(self.at(path, key), "required key missing")
        return value

    def typed(self, value: Any, path: str, noun: str, kinds: Mapping[str, tuple[Sequence[str], Sequence[str]]],
              tag: str = "type") -> tuple[str, dict[str, Any]]:
        """A mapping with a `type` key (or tag: fiberpath's `windType`) naming one of kinds: type ->
        (required keys, optional keys)."""
        names = ", ".join(kinds)
        if not isinstance(value, dict):
            raise self.error(path, f"must be a mapping with a {tag} ({names})", value)
        where = self.at(path, tag)
        if tag not in value:
            raise self.error(where, f"required key missing; one of {names}")
        kind = value[tag]
        if not isinstance(kind, str) or kind not in kinds:
            close = difflib.get_close_matches(kind, list(kinds), n=1) if isinstance(kind, str) else []
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise self.error(where, f"must be one of {names}{hint}", kind)
        required, optional = kinds[kind]
        article = "an" if kind[0] in "aeiou" else "a"
        return kind, self.mapping(value, path, (tag, *required, *optional), required,
                                  kind=f"{article} {kind} {noun}")

    def listing(self, value: Any, path: str, minimum: int, noun: str) -> list[Any]:
        if not isinstance(value, list):
            raise self.error(path, f"must be a list of {noun}s", value)
        if len(value) < minimum:
            raise self.error(path, f"must have at least {minimum} {noun}{'s' if minimum > 1 else ''}",
                             value)
        return value

    def number(self, value: Any, path: str, name: str = "") -> float:
        """A finite int or float; YAML booleans are not numbers. name prefixes the message."""
        prefix = f"{name} " if name else ""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(path, f"{prefix}must be a number", value)
        try:
            number = float(value)
        except OverflowError:  # an int beyond float range
            number = math.inf
        if not math.isfinite(number):
            raise self.error(path, f"{prefix}must be a finite number", value)
        return number

    def positive(self, value: Any, path: str, name: str = "") -> float:
        number = self.number(value, path, name)
        if number <= 0.0:
            raise self.error(path, f"{name + ' ' if name else ''}must be > 0", value)
        if number > MAX_SIZE:
            # Sizes, feeds and tolerances beyond this are typos (a kilometre-long mandrel), and they
            # would send the geometry into ranges where nothing finishes in reasonable time.
            raise self.error(path, f"{name + ' ' if name else ''}must be <= {MAX_SIZE:g}", value)
        return number

    def integer(self, value: Any, path: str, minimum: int, maximum: int | None = None,
                what: str = "") -> int:
        """A whole number in [minimum, maximum]; 200.0 counts as whole, 200.5 and true do not."""
        what = what or (f"must be a whole number >= {minimum}"
                        + (f" and <= {maximum}" if maximum is not None else ""))
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(path, what, value)
        if isinstance(value, float) and not (math.isfinite(value) and value.is_integer()):
            raise self.error(path, what, value)
        whole = int(value)
        if whole < minimum or (maximum is not None and whole > maximum):
            raise self.error(path, what, value)
        return whole

    def text(self, value: Any, path: str) -> str:
        if not isinstance(value, str):
            raise self.error(path, "must be text", value)
        return value

    def boolean(self, value: Any, path: str) -> bool:
        if not isinstance(value, bool):
            raise self.error(path, "must be true or false", value)
        return value


def station_option(text: str, option: str) -> tuple[float, float]:
    """A command-line point `T,DEG` as (t mm, theta rad); ConfigError naming the option otherwise."""
    parts = text.split(",")
    try:
        if len(parts) != 2 or "_" in text or not text.isascii():  # float() reads 1_0 and ١٠ as 10; a user does not
            raise ValueError
        t, deg = float(parts[0]), float(parts[1])
    except ValueError as exc:
        raise ConfigError(f"{option}: expected T,DEG (station in mm, angle in degrees), got {text!r}") from exc
    if not (math.isfinite(t) and math.isfinite(deg)):
        raise ConfigError(f"{option}: must be finite numbers, got {text!r}")
    return t, math.radians(deg)
