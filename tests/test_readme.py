"""README.md is the page a newcomer reads first: short, and its example config is one winder accepts."""

from __future__ import annotations

import re
from pathlib import Path

from winder.app.validate import validate

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
MAX_README_BYTES = 15_000  # a page, not a manual: the manual lives in docs/


def test_readme_is_a_page():
    assert README.stat().st_size < MAX_README_BYTES


def test_readme_config_is_valid(tmp_path):
    text = README.read_text(encoding="utf-8")
    block = re.search(r"```yaml\n(name: .*?)```", text, re.S)
    assert block is not None
    config = tmp_path / "tour.yaml"
    config.write_text(block.group(1), encoding="utf-8")
    validate(config)  # raises ConfigError on an invalid config


def test_readme_links_exist():
    text = README.read_text(encoding="utf-8")
    for target in re.findall(r"\]\(([^)#]+)\)", text):
        assert (ROOT / target).exists(), target
