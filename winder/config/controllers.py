"""Controllers described as data (docs/guide/controllers.md): a post file.

One `Controller` says everything winder needs to write a program for a controller and to read one
back: its engine (which writer, winder.export.dialects.<engine>, and which reader; the motion itself is
the one motion program), number format, block numbers, comment form, the tension command, the lines
before, around and after the moves, its limits (line length, digits of a value) and how it keeps the
rotary axis. The built-in dialects are such files (winder/config/posts/*.post.yaml, one per name,
the registry of winder.config.dialects); a user's post file starts from one (`extends`) and changes
what its controller spells otherwise: a new controller is a file, no code. Templates are Python format
strings: `{text}` (comment), `{newtons}` and `{fraction}` (tension, N and the share of
`tension_full_scale`), `{axis}` and `{value}` (rotary reset), `{name}` (the job's name, letters,
digits and _ only) and `{chord_tolerance}` (header, preamble, footer).
"""

from __future__ import annotations

import dataclasses
import functools
import re
import string
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

POSTS = Path(__file__).with_name("posts")
SUFFIX = ".post.yaml"
ENGINES = ("generic", "marlin", "robot", "krl", "rapid", "urscript")
FEEDS = ("fiber", "inverse_time")  # F the fiber's feed (mm/min), or 60 / the move's planned time (G93)
CELL_ENGINES = ("krl", "rapid", "urscript")  # a robot cell's own language, written as its own files
ROTARY_MODES = ("continuous", "wrap", "reset_per_layer", "reset_per_pass")
COMMENT_STARTS = ";(#!'"  # a comment line starts with one of these, never with a word's letter
_TEMPLATE_FIELDS = {"comment": ("text",), "tension": ("newtons", "fraction"), "reset": ("axis", "value"),
                    "lines": ("name", "chord_tolerance")}
_NUMBER_SPEC = re.compile(r"^(\.\d{1,2}f)?$")  # a number's format: fixed decimals (the reader reads them)
_G_CODE_KEYS = ("decimals", "block_numbers", "comment", "header", "preamble", "footer", "max_line_length",
                "max_digits", "rotary", "uppercase", "feed")
_KEYS = ("name", "extends", "engine", "about", "sources", "tension", "tension_full_scale", *_G_CODE_KEYS)


@dataclasses.dataclass(frozen=True)
class Rotary:
    """How the program writes the rotary axis: continuous (cumulative), wrap (modulo 360, each move
    within half a turn: the controller's modulo axis takes the shortest way), reset_per_layer /
    reset_per_pass (`reset` sets the axis' position to its value modulo 360 there, `cancel` at the end)."""

    mode: str = "continuous"
    reset: str | None = None
    cancel: str | None = None


@dataclasses.dataclass(frozen=True, kw_only=True)
class Controller:
    """One controller (module docstring); linear / angular: decimals of mm and deg values;
    block_numbers: (start, step, largest) or None; source: the file it was read from."""

    name: str
    engine: str
    about: str = ""
    sources: tuple[str, ...] = ()
    linear: int = 3
    angular: int = 3
    block_numbers: tuple[int, int, int] | None = None
    comment: str = "; {text}"
    tension: str | None = None
    tension_full_scale: float | None = None
    header: tuple[str, ...] = ()
    preamble: tuple[str, ...] = ()
    footer: tuple[str, ...] = ()
    max_line_length: int = 255
    max_digits: int | None = None
    rotary: Rotary = Rotary()
    uppercase: bool = False
    feed: str = "fiber"  # FEEDS: how F is written (the generic engine's)
    source: str = ""
    dialect: str = ""  # the built-in dialect this is or extends (its name in machine.dialect)

    @property
    def cell(self) -> bool:
        return self.engine in CELL_ENGINES

    @property
    def plain(self) -> bool:
        """Whether the text is written as the generic writer writes it (no pass over its lines needed)."""
        return (self.comment == "; {text}" and self.block_numbers is None and not self.uppercase
                and self.max_line_length >= 255)

    def tension_line(self, newtons: float) -> str:
        """The command that sets the tension to `newtons` (N per band); ExportError past the output's
        full scale where the command writes its share."""
        fraction = newtons / self.tension_full_scale if self.tension_full_scale else float("nan")
        if "{fraction" in self.tension and fraction > 1.0:
            from winder.errors import ExportError  # noqa: PLC0415

            raise ExportError(f"a tension of {newtons:g} N is past the {self.name} controller's analog output, "
                              f"{self.tension_full_scale:g} N at full scale (tension_full_scale): give the "
                              f"tensioner's full scale in a post file, or lower winding.tension")
        return self.tension.format(newtons=newtons, fraction=fraction)

    def newtons(self, read: dict[str, str]) -> float:
        """The tension (N) a tension line's fields (as read_pattern's groups) say."""
        if "newtons" in read:
            return float(read["newtons"])
        return float(read["fraction"]) * float(self.tension_full_scale or float("nan"))

    def tension_reader(self):
        """A reader of this controller's tension lines, for every language's read-back: the tension (N)
        a line sets, else None."""
        pattern = read_pattern(self.tension) if self.tension else None

        def read(line: str) -> float | None:
            hit = pattern.match(line) if pattern is not None else None
            return self.newtons(hit.groupdict()) if hit else None

        return read

    def end_code(self) -> str | None:
        """The footer line that ends the program (its last that is not `%`), if any."""
        return next((line for line in reversed(self.footer) if line.strip() != "%"), None)


def read_pattern(template: str, code=lambda text: text) -> re.Pattern:
    """A regular expression matching the lines `template` writes (case-insensitive), each field a named
    group (numbers by their digits, text by anything); code: what the reader does to a line before it
    matches (the same is done to the template's literal text)."""
    marks = {}
    literal = []
    for k, (text, field, spec, _) in enumerate(string.Formatter().parse(template)):
        literal.append(text)
        if field is not None:
            mark = f"\x00{k}\x00"
            marks[mark] = field
            literal.append(mark)
    shown = code("".join(literal))
    pattern = re.escape(shown)
    named: set[str] = set()
    for mark, field in marks.items():
        number = field in ("newtons", "fraction", "value", "chord_tolerance")
        group = r"[-+]?(?:\d+\.?\d*|\.\d+)" if number else (r"[A-Z]" if field == "axis" else r".*?")
        head = "?:" if field in named else f"?P<{field}>"  # a field written twice is read once
        named.add(field)
        pattern = pattern.replace(re.escape(mark), f"({head}{group})", 1)
    return re.compile(f"^{pattern}$", re.I)


def _template(rd: Reader, value: Any, path: str, kind: str, required: tuple[str, ...] = ()) -> str:
    text = rd.text(value, path)
    allowed = _TEMPLATE_FIELDS[kind]
    try:
        fields = [(f, spec) for _, f, spec, _ in string.Formatter().parse(text) if f is not None]
    except ValueError as exc:
        raise rd.error(path, f"unreadable template ({exc})", value) from exc
    for field, spec in fields:
        if field not in allowed:
            raise rd.error(path, f"unknown field {{{field}}}; allowed: {', '.join('{' + a + '}' for a in allowed)}",
                           value)
        if field in ("value", "text", "name", "axis") and spec:
            raise rd.error(path, f"{{{field}}} takes no format (it is written as winder gives it)", value)
        if field not in ("text", "name", "axis", "value") and not _NUMBER_SPEC.match(spec or ""):
            raise rd.error(path, f"{{{field}}} takes a fixed number of decimals, {{{field}:.1f}} to "
                           f"{{{field}:.99f}}, got {{{field}:{spec}}}", value)
    named = {g for g, _ in fields}
    if kind in ("tension", "reset") and re.match(r"\s*(N\d+\s*)?G0*[01](?!\d)", text, re.I):
        raise rd.error(path, "must not be a move (G0, G1): a program's moves are winder's", value)
    if (required and not named & set(required)) or "\n" in text or "\r" in text:
        raise rd.error(path, f"must be one line with {' or '.join('{' + r + '}' for r in required)}", value)
    return text


def _lines(rd: Reader, value: Any, path: str) -> tuple[str, ...]:
    if not isinstance(value, list):
        raise rd.error(path, "must be a list of lines", value)
    return tuple(_template(rd, v, rd.at(path, i), "lines") for i, v in enumerate(value))


def _decimals(rd: Reader, value: Any, path: str) -> dict[str, int]:
    m = rd.mapping(value, path, ("linear", "angular"))
    return {key: rd.integer(m[key], rd.at(path, key), minimum=3, maximum=6,
                            what="must be a whole number from 3 (the resolution the clearance and limits are "
                                 "checked at) to 6") for key in m}


def _block_numbers(rd: Reader, value: Any, path: str) -> tuple[int, int, int] | None:
    if value is None or value is False:
        return None
    m = rd.mapping(value, path, ("start", "step", "max"), required=("start", "step"))
    start = rd.integer(m["start"], rd.at(path, "start"), minimum=1, maximum=10**8)
    step = rd.integer(m["step"], rd.at(path, "step"), minimum=1, maximum=10**6)
    largest = rd.integer(m.get("max", 10**9 - 1), rd.at(path, "max"), minimum=start + step, maximum=10**9 - 1)
    return start, step, largest


def _comment(rd: Reader, value: Any, path: str) -> str:
    text = _template(rd, value, path, "comment", ("text",))
    if not text or text[0] not in COMMENT_STARTS or text.count("{text}") != 1:
        raise rd.error(path, f"must start with one of {' '.join(COMMENT_STARTS)} and hold {{text}} once", value)
    return text


def _rotary(rd: Reader, value: Any, path: str, base: Rotary) -> Rotary:
    m = rd.mapping(value, path, ("mode", "reset", "cancel"))
    mode = m.get("mode", base.mode)
    if mode not in ROTARY_MODES:
        raise rd.error(rd.at(path, "mode"), f"must be one of {', '.join(ROTARY_MODES)}", mode)
    reset = _template(rd, m["reset"], rd.at(path, "reset"), "reset", ("value",)) if "reset" in m else base.reset
    cancel = base.cancel if "reset" not in m else None
    if "cancel" in m:
        cancel = None if m["cancel"] is None else rd.text(m["cancel"], rd.at(path, "cancel"))
    if mode.startswith("reset") and reset is None:
        raise rd.error(rd.at(path, "reset"), f"required with mode {mode}: the line that sets the axis' position, "
                       "e.g. \"G92 {axis}{value}\"")
    return Rotary(mode, reset, cancel)


def parse_post(rd: Reader, value: Any, base: Controller | None, name: str) -> Controller:
    """A post file's mapping over `base` (the description it extends; None: a built-in root, which
    names its engine)."""
    m = rd.mapping(value, "", _KEYS)
    if base is None:
        engine = m.get("engine")
        if engine not in ENGINES:
            raise rd.error("engine", f"must be one of {', '.join(ENGINES)}", engine)
        base = Controller(name=name, engine=engine, dialect=name)
    elif "engine" in m:
        raise rd.error("engine", f"comes from the dialect it extends ({base.name}: {base.engine})", m["engine"])
    if base.cell and (extra := next((k for k in _G_CODE_KEYS if k in m), None)):
        raise rd.error(extra, f"does not apply to a {base.engine} program (a robot cell's language): only "
                       "tension and tension_full_scale do")
    out: dict[str, Any] = {"name": rd.text(m.get("name", name), "name"), "source": rd.source}
    if "about" in m:
        out["about"] = rd.text(m["about"], "about")
    if "sources" in m:
        out["sources"] = tuple(rd.text(v, rd.at("sources", i)) for i, v in enumerate(rd.listing(m["sources"],
                                                                                                 "sources", 0, "line")))
    if "decimals" in m:
        out.update(_decimals(rd, m["decimals"], "decimals"))
    if "block_numbers" in m:
        out["block_numbers"] = _block_numbers(rd, m["block_numbers"], "block_numbers")
    if "comment" in m:
        out["comment"] = _comment(rd, m["comment"], "comment")
    for key in ("header", "preamble", "footer"):
        if key in m:
            out[key] = _lines(rd, m[key], key)
    if "tension" in m:
        out["tension"] = _template(rd, m["tension"], "tension", "tension", ("newtons", "fraction"))
    if "tension_full_scale" in m:
        out["tension_full_scale"] = rd.positive(m["tension_full_scale"], "tension_full_scale")
    if "max_line_length" in m:
        out["max_line_length"] = rd.integer(m["max_line_length"], "max_line_length", minimum=60, maximum=100_000)
    if "max_digits" in m:
        out["max_digits"] = None if m["max_digits"] is None else rd.integer(m["max_digits"], "max_digits", 5, 15)
    if "rotary" in m:
        out["rotary"] = _rotary(rd, m["rotary"], "rotary", base.rotary)
        if out["rotary"].mode != "continuous" and base.engine in ("marlin", "robot"):
            raise rd.error("rotary.mode", f"a {base.engine} program keeps its rotation continuous (fiberpath's "
                           "machines and robot poses have no modulo axis to keep)", out["rotary"].mode)
    if "uppercase" in m:
        out["uppercase"] = rd.boolean(m["uppercase"], "uppercase")
    if "feed" in m:
        if base.engine != "generic" or m["feed"] not in FEEDS:
            allowed = f"one of {', '.join(FEEDS)}" if base.engine == "generic" else "its engine's own (leave it out)"
            raise rd.error("feed", f"must be {allowed} for a {base.engine} program", m["feed"])
        out["feed"] = m["feed"]
    post = dataclasses.replace(base, **out)
    if post.tension is not None and "{fraction" in post.tension and not post.tension_full_scale:
        raise rd.error("tension_full_scale", "required with {fraction} in tension: the tension (N) at the "
                       "output's full scale")
    return post


FIRST = ("generic", "marlin", "linuxcnc", "robot", "krl", "rapid", "urscript")  # the order messages list them in


@functools.cache
def builtin_names() -> tuple[str, ...]:
    """The built-in dialects, by their files' names (no file read: the registry knows them at once)."""
    names = {p.name[:-len(SUFFIX)] for p in POSTS.glob("*" + SUFFIX)}
    return tuple(n for n in FIRST if n in names) + tuple(sorted(names - set(FIRST)))


@functools.cache
def builtin(name: str) -> Controller:
    """A built-in dialect's description (its file read once per process)."""
    path = POSTS / f"{name}{SUFFIX}"
    if name not in builtin_names():
        raise KeyError(name)
    return read_post(path, str(path), None)


def read_post(path: Path, source: str, base: Controller | None) -> Controller:
    """A post file read and checked; `extends` resolved among the built-ins (base: given, for a
    built-in root, None)."""
    from winder.config.files import read_text  # noqa: PLC0415
    from winder.config.reader import Reader, load_yaml  # noqa: PLC0415

    import yaml  # noqa: PLC0415

    rd = Reader(source)
    try:
        data = load_yaml(read_text(path, source, kind="post file"))
    except (yaml.YAMLError, ValueError, RecursionError) as exc:
        from winder.errors import ConfigError  # noqa: PLC0415

        raise ConfigError(f"{source}: invalid YAML: {str(exc).splitlines()[0] if str(exc) else 'unreadable'}") from exc
    name = Path(source).name.removesuffix(SUFFIX).removesuffix(".yaml")
    shipped = Path(path).parent == POSTS
    if isinstance(data, dict) and "extends" in data:
        parent = data["extends"]
        if not isinstance(parent, str) or parent not in builtin_names() or (shipped and parent == name):
            raise rd.error("extends", f"must be one of the built-in dialects: {', '.join(builtin_names())}", parent)
        base = builtin(parent)
    elif base is None and not (isinstance(data, dict) and "engine" in data and shipped):
        raise rd.error("extends", f"required: the built-in dialect this controller starts from "
                       f"({', '.join(builtin_names())})")
    post = parse_post(rd, data, base, name)
    return dataclasses.replace(post, dialect=name if shipped else base.name)
