"""Controller dialects: each serializes a winder.machine.program.MotionProgram to text and computes
nothing. text.py holds what they share (comments, number format, one line per move); generic.py is a
straight-axis winder's G-code, robot.py the eye poses for a robot. A new dialect is a new module here
defining make(program, band_width) and one register() line in winder.config.dialects.

May import: errors, config, geometry, paths, winding, machine (never winder.app or the CLI).
"""
