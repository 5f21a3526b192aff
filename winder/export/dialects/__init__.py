"""Controller dialects: each serializes a winder.machine.program.MotionProgram to text and computes
nothing. text.py holds what they share (comments, number format, one line per move) and post_text.py
what a controller's description changes in it (winder.config.controllers); generic.py is a
straight-axis winder's G-code (its feed the fiber's or inverse time), marlin.py fiberpath's X A B
machines, robot.py the eye poses for a robot, krl.py, rapid.py and urscript.py the robot cells'
languages. A new dialect is a post file (winder/config/posts/, or a user's machine.post); a new
engine (a way of writing moves no description spells) is a module here defining make(program,
band_width), named by its descriptions' `engine`.

May import: errors, config, geometry, paths, winding, machine (never winder.app or the CLI).
"""
