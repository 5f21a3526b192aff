"""A YAML document's size with its aliases expanded, counted before it is constructed.

An alias is one node shared, not a copy; but every reader of the data (the checks, the geometry, a
message showing a value) walks it expanded. So a document is refused when its expansion holds more
values than a file of the size limit could hold without aliases: then nothing downstream sees more
than a plain file of that size could give it.
"""

from __future__ import annotations

import yaml

__all__ = ["MAX_EXPANDED_VALUES", "ExpansionError", "expanded_size"]

# What 2 MB of YAML without aliases can hold ("0," per value). 497,000 aliases of one path segment
# took `check` 72 s and 1.2 GB; nine levels of nine ("billion laughs") would never end.
MAX_EXPANDED_VALUES = 1_000_000


class ExpansionError(yaml.composer.ComposerError):
    """A document past MAX_EXPANDED_VALUES, or recursive: refused as it is, by either parser."""


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    return list(node.value) if isinstance(node, yaml.SequenceNode) else []


def expanded_size(root: yaml.Node, limit: int = MAX_EXPANDED_VALUES) -> int:
    """The values (nodes) of a composed document with every alias expanded, counted in time linear in
    its nodes (a node shared through aliases is counted once and its count reused); a ComposerError
    at the node past limit, or at an alias inside its own anchor (a recursive document)."""
    sizes: dict[int, int] = {}
    entered: set[int] = set()  # the nodes on the way down to the current one
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    while stack:
        node, done = stack.pop()
        key = id(node)
        if done:
            entered.discard(key)
            sizes[key] = 1 + sum(sizes[id(child)] for child in _children(node))
            if sizes[key] > limit:
                raise ExpansionError(
                    None, None, f"its aliases expand it to more than {limit:,} values (what 2 MB of YAML "
                    "without aliases holds at most)", node.start_mark)
            continue
        if key in sizes:
            continue
        entered.add(key)
        stack.append((node, True))
        for child in _children(node):
            if id(child) in entered:
                raise ExpansionError(None, None, "an alias inside its own anchor (a recursive document)",
                                     child.start_mark)
            if id(child) not in sizes:
                stack.append((child, False))
    return sizes[id(root)]
