"""The layer planners: helical layers on open mandrels (dwells), on vessels (Clairaut turnarounds),
and hoops. Each takes a PlanContext and one layer config and returns a LayerPlan.

May import: as winder.winding.
"""
