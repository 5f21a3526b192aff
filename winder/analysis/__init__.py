"""Structure (docs/math/09-structure.md): will the wound part hold? Ply materials, membrane loads,
netting analysis and sizing, classical lamination theory, first-ply failure, per station of the layup."""
