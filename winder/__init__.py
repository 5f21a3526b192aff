"""winder: filament-winding CAM on sweep-surface mandrels.

Pipeline: config (YAML -> frozen dataclasses) -> surface (guide curve, rotation-minimizing
frame, radius r(t, theta)) -> geodesic (variational fiber paths) -> pattern/coverage (winding
plan) -> export (CSV, G-code, PLY).
"""

__version__ = "0.1.0"
