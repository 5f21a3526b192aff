"""The `analysis:` section of a job file (SPEC.md "Structural analysis"): the load case, and the ply
properties `winding.material` may carry (a name from winder's table, or the numbers themselves).

    analysis: {pressure: 30, axial_force: 0, torque: 0, ends: closed}
    winding.material: {name: carbon_epoxy, ...} or {E1: 135000, E2: 10000, G12: 5000, nu12: 0.3,
                       Xt: 2200, Xc: 1200, Yt: 50, Yc: 200, S: 80, fiber_strength: 4900, ...}
The name is checked against the table by the analysis stage (winder.analysis.materials.lamina_of).
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

ENDS = ("closed", "open")
# Pressures past this are typos (MPa typed as kPa): the strongest wound vessels burst below 300 MPa.
MAX_PRESSURE = 10_000.0
# Moduli and strengths (MPa) past this are typed in Pa or psi: carbon fibers reach 600 GPa.
MAX_MODULUS = 1.0e6
LAMINA_KEYS = ("name", "E1", "E2", "G12", "nu12", "Xt", "Xc", "Yt", "Yc", "S", "fiber_strength")


@dataclasses.dataclass(frozen=True)
class AnalysisConfig:
    """YAML `analysis:`. pressure: internal pressure, MPa, >= 0. axial_force: N (tension +). torque: N mm.
    ends: `closed` (the pressure's end thrust on the wall; vessels always) or `open` (pipes only)."""

    pressure: float = 0.0
    axial_force: float = 0.0
    torque: float = 0.0
    ends: str = "closed"


@dataclasses.dataclass(frozen=True)
class LaminaConfig:
    """The ply properties a material gives: a table name and/or numbers (MPa), as (key, value) pairs."""

    name: str | None = None
    given: tuple[tuple[str, float], ...] = ()

    @property
    def values(self) -> dict[str, float]:
        return dict(self.given)


def parse_analysis(rd: Reader, value: Any, path: str, vessel: bool) -> AnalysisConfig:
    m = rd.mapping(value, path, ("pressure", "axial_force", "torque", "ends"))
    out: dict[str, Any] = {}
    if "pressure" in m:
        p = rd.number(m["pressure"], rd.at(path, "pressure"))
        if not 0.0 <= p <= MAX_PRESSURE:
            raise rd.error(rd.at(path, "pressure"), f"must be in [0, {MAX_PRESSURE:g}] MPa (internal pressure; "
                           "1 MPa = 10 bar)", m["pressure"])
        out["pressure"] = p
    for key in ("axial_force", "torque"):
        if key in m:
            out[key] = rd.number(m[key], rd.at(path, key))
    if "ends" in m:
        ends = m["ends"]
        if ends not in ENDS:
            raise rd.error(rd.at(path, "ends"), "must be closed or open", ends)
        if vessel and ends == "open":
            raise rd.error(rd.at(path, "ends"), "a vessel's ends are closed (its domes take the end thrust)",
                           ends)
        out["ends"] = ends
    return AnalysisConfig(**out)


def parse_lamina(rd: Reader, m: dict, path: str) -> LaminaConfig | None:
    """The ply keys of a material mapping m (None when it has none)."""
    if not any(k in m for k in LAMINA_KEYS):
        return None
    name = rd.text(m["name"], rd.at(path, "name")) if "name" in m else None
    given = []
    for key in LAMINA_KEYS[1:]:
        if key not in m:
            continue
        where = rd.at(path, key)
        if key == "nu12":
            v = rd.number(m[key], where)
            if not 0.0 <= v < 1.0:
                raise rd.error(where, "must be in [0, 1) (the ply's major Poisson ratio, typically 0.25 to 0.35)",
                               m[key])
        else:
            v = rd.number(m[key], where)
            if not 0.0 < v <= MAX_MODULUS:
                raise rd.error(where, f"must be in (0, {MAX_MODULUS:g}] MPa (compressive strengths as "
                               "magnitudes)", m[key])
        given.append((key, v))
    return LaminaConfig(name, tuple(given))
