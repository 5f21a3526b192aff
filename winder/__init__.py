"""winder: filament-winding CAM on sweep-surface mandrels.

Stages, each a package that imports only from earlier ones: config (YAML -> frozen dataclasses, the
JSON Schema) -> geometry (the sweep surface) -> paths (geodesics, friction-held paths) -> winding (the
plan, the laminate) -> analysis (will it hold) -> machine (one motion program) -> export (writers only:
CSV, G-code dialects, robot languages, PLY, summary, FE decks) -> readback (programs read back) -> report
(the HTML page) -> app (jobs, regress, simulate) -> cli (the package that talks to the user). errors.py and
progress.py (the progress callback) are shared by all. docs/architecture.md has the table of modules,
docs/math/ the math, chapter by chapter.
"""

__version__ = "0.1.0"
