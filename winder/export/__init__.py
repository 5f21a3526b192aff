"""Stage 6, export: outputs that only serialize.

registry (format -> suffix and module), atomic (all-or-nothing writes), job_csv, path_csv, summary,
ply, gcode (the program file: a motion program through its dialect), dialects/ (generic G-code, robot
poses; a new controller is a new dialect).

May import: every earlier stage (errors, config, geometry, paths, winding, machine).
"""
