"""Stage 5, machine: what the winder does to lay a plan.

kinematics (the payout eye on the fiber's tangent line, axis values, robot poses), limits (travel
limits), program (one MotionProgram on logical axes: A and B continuity, limits, point reduction).

May import: winder.errors, winder.config, winder.geometry, winder.paths, winder.winding.
"""
