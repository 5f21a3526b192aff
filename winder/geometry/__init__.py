"""Stage 2, geometry: the mandrel as a sweep surface with exact derivatives.

frames (rotation-minimizing frames), curves (guide curves), sections (r(theta) shapes), profiles
(r(t)), domes and isotensoid (vessel dome meridians), vessel (dome, cylinder, dome), surface
(Phi(s, theta) and the fold check), build (the one module that reads config types: config ->
surface, refusing with key paths what only geometry knows), measure (lengths, curvature, Richardson).

May import: winder.errors; winder.config only in build.py.
"""
