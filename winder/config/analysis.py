"""The `analysis:` section of a job file (docs/guide/will-it-hold.md): the
load case, where the headline figures come from, the user's targets, and the ply properties
`winding.material` may carry (a name from winder's table, or the numbers themselves).

    analysis: {pressure: 30, axial_force: 0, torque: 0, ends: closed, gauge: cylinder,
               burst_pressure: 67.5, stress_ratio: 2.25}
    winding.material: {name: carbon_epoxy, ...} or {E1: 135000, E2: 10000, G12: 5000, nu12: 0.3,
                       Xt: 2200, Xc: 1200, Yt: 50, Yc: 200, S: 80, strand_strength: 4900, ...}
The name is checked against the table by the analysis stage (winder.analysis.materials.lamina_of).
Every load has a documented upper limit (docs/guide/will-it-hold.md): past it a value is a typo in
another unit, and its products would overflow the shell model's loads.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from winder.config.reader import Reader

ENDS = ("closed", "open")
GAUGES = ("cylinder", "wound", "all")
# Pressures past this are typos (bar or psi typed as MPa): the strongest wound vessels burst below 300 MPa.
MAX_PRESSURE = 1_000.0
# |axial force| (N) past this is a typo: 1000 MPa on a 2 m diameter closes with 3.1e9 N.
MAX_AXIAL_FORCE = 1.0e10
# |torque| (N mm) past this is a typo: that force on a 1 m radius.
MAX_TORQUE = 1.0e13
# A required stress ratio past this is a typo: the standards ask 2 to 3.6 of their fiber materials.
MAX_STRESS_RATIO = 10.0
# Moduli and strengths (MPa) past this are typed in Pa or psi: carbon fibers reach 600 GPa.
MAX_MODULUS = 1.0e6
LAMINA_KEYS = ("name", "E1", "E2", "G12", "nu12", "Xt", "Xc", "Yt", "Yc", "S", "fiber_strength", "strand_strength")


@dataclasses.dataclass(frozen=True, kw_only=True)
class AnalysisConfig:
    """YAML `analysis:`. pressure: working pressure, MPa, in [0, MAX_PRESSURE]. axial_force: N (tension +),
    |F| <= MAX_AXIAL_FORCE. torque: N mm, |T| <= MAX_TORQUE. ends: `closed` (the pressure's end thrust on the
    wall; vessels always) or `open` (pipes only). gauge: where the headline figures come from (None: the
    cylinder on vessels, the wound region on open mandrels). burst_pressure: the least burst the design must
    reach (MPa, None: not asked). stress_ratio: the fiber stress ratio required (a number for every fiber
    material, or (material name, ratio) pairs; None: not asked)."""

    pressure: float = 0.0
    axial_force: float = 0.0
    torque: float = 0.0
    ends: str = "closed"
    gauge: str | None = None
    burst_pressure: float | None = None
    stress_ratio: float | tuple[tuple[str, float], ...] | None = None

    def required_ratio(self, material: str) -> float | None:
        """The stress ratio required of fiber material `material` (None: not asked of it)."""
        if self.stress_ratio is None or isinstance(self.stress_ratio, float):
            return self.stress_ratio
        return dict(self.stress_ratio).get(material)


@dataclasses.dataclass(frozen=True)
class LaminaConfig:
    """The ply properties a material gives: a table name and/or numbers (MPa), as (key, value) pairs."""

    name: str | None = None
    given: tuple[tuple[str, float], ...] = ()

    @property
    def values(self) -> dict[str, float]:
        return dict(self.given)


def _bounded(rd: Reader, m: dict, path: str, key: str, limit: float, unit: str, why: str) -> float:
    value = rd.number(m[key], rd.at(path, key))
    if not -limit <= value <= limit:
        raise rd.error(rd.at(path, key), f"must be in [-{limit:g}, {limit:g}] {unit} ({why})", m[key])
    return value


def _ratio(rd: Reader, value: Any, path: str) -> float:
    r = rd.number(value, path)
    if not 1.0 <= r <= MAX_STRESS_RATIO:
        raise rd.error(path, f"must be in [1, {MAX_STRESS_RATIO:g}] (fiber stress at the minimum burst over fiber "
                       "stress at the working pressure)", value)
    return r


def parse_analysis(rd: Reader, value: Any, path: str, vessel: bool) -> AnalysisConfig:
    m = rd.mapping(value, path, ("pressure", "axial_force", "torque", "ends", "gauge", "burst_pressure",
                                 "stress_ratio"))
    out: dict[str, Any] = {}
    if "pressure" in m:
        p = rd.number(m["pressure"], rd.at(path, "pressure"))
        if not 0.0 <= p <= MAX_PRESSURE:
            raise rd.error(rd.at(path, "pressure"), f"must be in [0, {MAX_PRESSURE:g}] MPa (internal pressure; "
                           "1 MPa = 10 bar)", m["pressure"])
        out["pressure"] = p
    if "axial_force" in m:
        out["axial_force"] = _bounded(rd, m, path, "axial_force", MAX_AXIAL_FORCE, "N", "tension +; 1 kN = 1000 N")
    if "torque" in m:
        out["torque"] = _bounded(rd, m, path, "torque", MAX_TORQUE, "N mm", "1 N m = 1000 N mm")
    if "ends" in m:
        ends = m["ends"]
        if ends not in ENDS:
            raise rd.error(rd.at(path, "ends"), "must be closed or open", ends)
        if vessel and ends == "open":
            raise rd.error(rd.at(path, "ends"), "a vessel's ends are closed (its domes take the end thrust)",
                           ends)
        out["ends"] = ends
    if "gauge" in m:
        if m["gauge"] not in GAUGES:
            raise rd.error(rd.at(path, "gauge"), f"must be one of {', '.join(GAUGES)}", m["gauge"])
        out["gauge"] = m["gauge"]
    if "burst_pressure" in m:
        b = rd.positive(m["burst_pressure"], rd.at(path, "burst_pressure"))
        if not out.get("pressure", 0.0) < b <= MAX_PRESSURE:
            raise rd.error(rd.at(path, "burst_pressure"), f"must be above the working pressure "
                           f"({out.get('pressure', 0.0):g} MPa) and at most {MAX_PRESSURE:g} MPa", m["burst_pressure"])
        out["burst_pressure"] = b
    if "stress_ratio" in m:
        where = rd.at(path, "stress_ratio")
        if isinstance(m["stress_ratio"], dict):
            given = rd.mapping(m["stress_ratio"], where, tuple(str(k) for k in m["stress_ratio"]))
            out["stress_ratio"] = tuple((str(k), _ratio(rd, v, rd.at(where, str(k)))) for k, v in given.items())
        else:
            out["stress_ratio"] = _ratio(rd, m["stress_ratio"], where)
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
