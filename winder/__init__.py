"""winder: filament-winding CAM on sweep-surface mandrels.

Stages, each a package that imports only from earlier ones: config (YAML -> frozen dataclasses)
-> geometry (the sweep surface) -> paths (geodesics) -> winding (the plan) -> machine (one motion
program) -> export (CSV, G-code, PLY, summary) -> report (the HTML page) -> app (jobs, regress) ->
cli.py (the only module that talks to the user). errors.py and progress.py (the progress callback)
are shared by all.
"""

__version__ = "0.1.0"
