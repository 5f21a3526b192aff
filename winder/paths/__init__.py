"""Stage 3, paths: fiber paths on a surface.

geodesic (the variational solver: Newton on the block-tridiagonal Hessian, L-BFGS for comparison),
ode (the geodesic ODE and ray tracing; friction-held paths belong here), shooting (two-point shooting,
the independent check).

May import: winder.errors, winder.config (constants), winder.geometry.
"""
