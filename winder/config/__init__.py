"""Stage 1, config: a job file (YAML) -> validated, frozen dataclasses.

reader (the YAML loader and the value Reader that words every message), mandrel, winding, machine
(one module per section: dataclasses and parser), extent (what the mandrel tells without computation),
job (the whole file: load_config, parse_config, JobConfig).

May import: winder.errors only.
"""
