"""`python -m bench`: the paper's Table 1, Figures 7 and 8 and applications (sections 6.1, 6.2), the
accuracy-time frontier against solve_bvp, shooting, a mesh baseline and the paper's L-BFGS, and a whole
job against fiberpath; written as Markdown, JSON and PNG (bench/results/).

run_bench(settings, progress) measures and returns a JSON-ready dict; write_outputs writes the page.
Optional packages (the `bench` extra: matplotlib, potpourri3d, threadpoolctl; fiberpath, run as a
separate program) are skipped with a note when missing. Library code: nothing here prints.
"""

from bench.run import report_from_json, run_bench, write_outputs
from bench.settings import FULL, QUICK, Settings, tiny

__all__ = ["FULL", "QUICK", "Settings", "report_from_json", "run_bench", "tiny", "write_outputs"]
