"""The `design` request: a config validated as `run` would, then its netting design (winder.analysis.design)."""

from __future__ import annotations

import json


def design_output(config: str, as_json: bool) -> str:
    """What `winder design CONFIG [--json]` prints: one JSON object, or a few lines."""
    from winder.analysis.design import design, design_text  # noqa: PLC0415
    from winder.app.validate import validate  # noqa: PLC0415

    job, surface, _ = validate(config)
    result = design(job, surface)
    return json.dumps(result.as_json(), allow_nan=False) if as_json else design_text(result)
