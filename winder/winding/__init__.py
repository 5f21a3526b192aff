"""Stage 4, winding: the plan of a whole job, layer by layer.

pattern (circuit counts and skips), coverage (bands at stations), passes (the planning context and
shared pass builders), slip (friction check), layers/ (helical_open, helical_vessel, hoop), results
(the plan's frozen result types), plan (the dispatcher: plan(job)).

May import: winder.errors, winder.config, winder.geometry, winder.paths.
"""
