"""How long `winder report` takes to write the page of the largest sample, and how big it is.

Planning is timed apart (it is the planner's cost, not the report's). Run from the repository root:
    python bench/report_speed.py [samples/*.yaml]
Prints one line per config: planning seconds, report seconds (median of REPEATS), page size in MB.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

REPEATS = 5


def main(paths: list[str]) -> None:
    from winder.config.job import load_config
    from winder.export.summary import summary_dict
    from winder.winding.plan import plan as plan_job

    t0 = time.perf_counter()
    from plotly.io import to_html  # noqa: F401 - the one-off import (plotly.io is lazy), on its own line
    print(f"import plotly: {time.perf_counter() - t0:.2f} s")
    from winder.report.html import report_html

    for path in paths:
        job = load_config(path)
        t0 = time.perf_counter()
        plan = plan_job(job)
        planning = time.perf_counter() - t0
        summary = summary_dict(plan)
        times, size = [], 0
        for _ in range(REPEATS):
            t0 = time.perf_counter()
            text = report_html(plan, summary, job.winding.band_width)
            out = Path("/tmp") / f"{job.name}.bench.html"
            out.write_text(text, encoding="utf-8")
            times.append(time.perf_counter() - t0)
            size = out.stat().st_size
        points = sum(p.t.size for layer in plan.layers for p in layer.passes)
        print(f"{job.name:20s} {points:6d} points  planning {planning:6.2f} s  report {statistics.median(times):5.2f} s "
              f"(max {max(times):.2f})  {size / 1e6:5.2f} MB")


if __name__ == "__main__":
    main(sys.argv[1:] or sorted(str(p) for p in Path("samples").glob("*.yaml")))
