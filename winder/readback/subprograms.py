"""A cell program's layers as subprograms (docs/math/10-robot-cell.md 10.10), read in the order the
controller runs them: each subprogram's lines in place of its call (KRL `<name>_L<N>( )` and `DEF
<name>_L<N>( ) ... END`, each layer's module's .src read after the main .src by
winder.readback.program_file; RAPID `layer_N;` and `PROC layer_N() ... ENDPROC`; URScript `layer_N()`
and `def layer_N(): ... end` within the main function). Every subprogram is defined once
and called once, from the main program only; anything else is refused naming its line."""

from __future__ import annotations

import dataclasses
import re

from winder.errors import ConfigError


@dataclasses.dataclass(frozen=True)
class Grammar:
    """How a language spells a layer's subprogram: its definition's first line (the name its group 1),
    its last line, a call (the name its group 1)."""

    start: re.Pattern
    end: str
    call: re.Pattern
    comment: str = ""  # what starts a comment after a statement (KRL's ;)
    preamble: tuple[str, ...] = ()  # the lines a module's file starts with, dropped before a definition


_KRL_MODULE = r"([A-Za-z][A-Za-z0-9_]{0,22}_L[0-9]{1,9})"  # <name>_L<N> (the writer keeps it to 24 characters)
KRL = Grammar(re.compile(rf"^DEF {_KRL_MODULE}\( \)$", re.I), "END", re.compile(rf"^{_KRL_MODULE}\( \)$", re.I),
              ";", ("&ACCESS RVP", "&REL 1"))
RAPID = Grammar(re.compile(r"^PROC (layer_[0-9]{1,9})\(\)$"), "ENDPROC", re.compile(r"^(layer_[0-9]{1,9});$"))
URSCRIPT = Grammar(re.compile(r"^def (layer_[0-9]{1,9})\(\):$"), "end", re.compile(r"^(layer_[0-9]{1,9})\(\)$"))


def _code(line: str, grammar: Grammar) -> str:
    """A line's statement without a trailing comment, stripped."""
    return (line.split(grammar.comment)[0] if grammar.comment else line).strip()


def in_order(lines: list[tuple[int, str]], grammar: Grammar, source: str) -> list[tuple[int, str]]:
    """The (line number, text) lines in the order they run: each subprogram's body where it is called,
    its definition taken out."""
    bodies: dict[str, list[tuple[int, str]]] = {}
    defined_at: dict[str, int] = {}
    rest: list[tuple[int, str]] = []
    current: str | None = None
    for number, raw in lines:
        code = _code(raw, grammar)
        if current is not None:
            if code.upper() == grammar.end.upper():
                current = None
            else:
                bodies[current].append((number, raw))
            continue
        hit = grammar.start.match(code)
        if hit:
            while rest and _code(rest[-1][1], grammar) in grammar.preamble:  # the module file's first lines
                rest.pop()
            name = hit[1].lower()
            if name in bodies:
                raise ConfigError(f"{source}: line {number}: {hit[1]} is defined twice (line {defined_at[name]})")
            bodies[name], defined_at[name], current = [], number, name
            continue
        rest.append((number, raw))
    if current is not None:
        raise ConfigError(f"{source}: line {defined_at[current]}: {current} has no {grammar.end}: cut short?")
    out, called = [], set()
    for number, raw in rest:
        hit = grammar.call.match(_code(raw, grammar))
        if not hit:
            out.append((number, raw))
            continue
        name = hit[1].lower()
        if name not in bodies or name in called:
            what = "is not defined" if name not in bodies else "is called twice"
            raise ConfigError(f"{source}: line {number}: {hit[1]} {what}: each layer's subprogram runs once")
        for inner, text in bodies[name]:
            if grammar.call.match(_code(text, grammar)) or grammar.start.match(_code(text, grammar)):
                raise ConfigError(f"{source}: line {inner}: a layer's subprogram calls or defines no other")
        called.add(name)
        out += bodies[name]
    missing = sorted(set(bodies) - called, key=lambda k: defined_at[k])
    if missing:
        raise ConfigError(f"{source}: line {defined_at[missing[0]]}: {missing[0]} is never called: its layer would "
                          f"not be wound")
    return out


def defined(lines: list[tuple[int, str]], grammar: Grammar) -> list[str]:
    """The names of the subprograms the lines define, in order."""
    return [hit[1] for _, raw in lines if (hit := grammar.start.match(_code(raw, grammar)))]
