"""Post files (winder.config.controllers): every built-in reads, and a post file's bad values are one
ConfigError naming the post file and the key, never another exception (templates that would not format
or not read back, wrong types, unknown keys, a move as the tension command)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from winder.config.controllers import Controller, builtin, builtin_names, read_pattern, read_post
from winder.errors import ConfigError

BAD = [
    {"extends": "nowhere"}, {"extends": 3}, {"extends": "generic", "engine": "generic"},
    {"extends": "generic", "decimals": {"linear": 2}}, {"extends": "generic", "decimals": {"angular": 7.5}},
    {"extends": "generic", "block_numbers": {"start": 0, "step": 10}}, {"extends": "generic", "block_numbers": 5},
    {"extends": "generic", "comment": "N{text}"}, {"extends": "generic", "comment": "({text}) ({text})"},
    {"extends": "generic", "comment": "; text"}, {"extends": "generic", "tension": "M68 E0 Q{newtons:e}"},
    {"extends": "generic", "tension": "M68 E0 Q{force}"}, {"extends": "generic", "tension": "M68 E0 Q40"},
    {"extends": "generic", "tension": "G1 X{newtons:.1f}"}, {"extends": "generic", "tension": "M68 {"},
    {"extends": "generic", "tension": "M68 E0 Q{fraction:.3f}"}, {"extends": "generic", "header": "%"},
    {"extends": "generic", "header": ["{0}"]}, {"extends": "generic", "footer": ["M30\nM2"]},
    {"extends": "generic", "max_line_length": 10}, {"extends": "generic", "max_digits": 2},
    {"extends": "generic", "rotary": {"mode": "spin"}}, {"extends": "generic", "rotary": {"mode": "reset_per_layer"}},
    {"extends": "linuxcnc", "rotary": {"mode": "wrap", "reset": "G92 {axis}{value:.3f}"}},
    {"extends": "generic", "uppercase": "yes"}, {"extends": "generic", "feed": "fast"}, {"extends": "krl", "comment": "; {text}"},
    {"extends": "generic", "colour": "red"}, ["extends", "generic"], None,
]


def test_every_builtin_reads():
    for name in builtin_names():
        post = builtin(name)
        assert isinstance(post, Controller) and post.dialect == name


@pytest.mark.parametrize("data", BAD, ids=[str(i) for i in range(len(BAD))])
def test_a_bad_post_file_is_one_config_error(tmp_path, data):
    import yaml  # noqa: PLC0415

    path = tmp_path / "bad.post.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(ConfigError) as info:
        read_post(path, "bad.post.yaml", None)
    assert str(info.value).startswith("bad.post.yaml: ")


@settings(max_examples=60, deadline=None)
@given(st.text(max_size=30))
def test_any_tension_template_is_refused_or_writes_what_it_reads(template):
    """A template either is refused, or the line it writes reads back the tension it was given."""
    from winder.config.controllers import parse_post  # noqa: PLC0415
    from winder.config.reader import Reader  # noqa: PLC0415

    try:
        post = parse_post(Reader("p.post.yaml"), {"tension": template}, builtin("generic"), "p")
    except ConfigError:
        return
    line = post.tension_line(41.25)
    hit = read_pattern(post.tension).match(line)
    assert hit is not None and abs(post.newtons(hit.groupdict()) - 41.25) <= 0.5
