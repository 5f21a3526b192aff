"""Reading a winding program back: the stage after export/ (which only writes).

`program_file` streams a program from disk and tells its dialect; `gcode` and `cells` read G-code
dialects and robot languages to rows of logical axes (`parsed.ParsedProgram`); `exact_paths` gives the
fiber path a program is measured against, and `contacts`, `contact_bands`, `contact_windows` find where
each programmed eye's free fiber touches it. `winder.app.simulate` orchestrates them.
"""
