"""Ply materials: stiffness and strength of a unidirectional ply, and a small table of common systems.

Units MPa. Strengths are magnitudes (Xc, Yc > 0 for compression). fiber_strength is the dry fiber's
tensile strength (netting: the fibers take it on V_f of the wall, docs/math 9.2); nu23 the transverse
Poisson ratio the shell model's 3D constants need. Every number of the table names its source.
"""

from __future__ import annotations

import dataclasses
import math

from winder.errors import ConfigError

# nu23 where a source gives none: WWFE-I lists 0.4 for its carbon and glass/epoxy plies.
DEFAULT_NU23 = 0.4


@dataclasses.dataclass(frozen=True)
class Lamina:
    """A unidirectional ply: E1, E2, G12 (MPa), nu12; strengths Xt, Xc, Yt, Yc, S (MPa); the fiber's
    strength (MPa, None: unknown), the fiber volume fraction the data were measured at, nu23."""

    name: str
    E1: float
    E2: float
    G12: float
    nu12: float
    Xt: float
    Xc: float
    Yt: float
    Yc: float
    S: float
    fiber_strength: float | None = None
    fiber_volume_fraction: float | None = None
    nu23: float = DEFAULT_NU23

    @property
    def nu21(self) -> float:
        return self.nu12 * self.E2 / self.E1

    def netting_stress(self, fiber_volume_fraction: float | None = None) -> float:
        """The netting allowable on the composite thickness (MPa): fiber_strength V_f where both are
        known (V_f: the job's material's, else the data's), else Xt (docs/math 9.2)."""
        vf = fiber_volume_fraction if fiber_volume_fraction is not None else self.fiber_volume_fraction
        if self.fiber_strength is not None and vf is not None:
            return self.fiber_strength * vf
        return self.Xt


# The shipped systems. Sources:
#  [DI] I. M. Daniel, O. Ishai, Engineering Mechanics of Composite Materials, 2nd ed., Oxford University
#       Press 2006, Table A.4 (properties of unidirectional composite materials).
#  [WWFE] P. D. Soden, M. J. Hinton, A. S. Kaddour, "Lamina properties, lay-up configurations and loading
#       conditions for a range of fibre-reinforced composite laminates", Composites Science and Technology
#       58 (1998) 1011-1022, Table 1 and 2 (the World-Wide Failure Exercise data).
#  Fiber strengths: manufacturers' data sheets as named per entry.
MATERIALS: dict[str, Lamina] = {
    # AS4/3501-6 [DI]; AS4 fiber 4,413 MPa (Hexcel HexTow AS4 data sheet).
    "carbon_epoxy": Lamina("carbon_epoxy", E1=147_000.0, E2=10_300.0, G12=7_000.0, nu12=0.27, Xt=2_280.0,
                           Xc=1_725.0, Yt=57.0, Yc=228.0, S=76.0, fiber_strength=4_413.0,
                           fiber_volume_fraction=0.63),
    # E-glass/epoxy [DI]; E-glass fiber 3,450 MPa ([DI] Table A.1).
    "eglass_epoxy": Lamina("eglass_epoxy", E1=41_000.0, E2=10_400.0, G12=4_300.0, nu12=0.28, Xt=1_140.0,
                           Xc=620.0, Yt=39.0, Yc=128.0, S=89.0, fiber_strength=3_450.0,
                           fiber_volume_fraction=0.55),
    # T300/BSL914C [WWFE] (V_f 0.60, nu23 0.4); T300 fiber 3,530 MPa (Toray T300 data sheet).
    "t300_914c": Lamina("t300_914c", E1=138_000.0, E2=11_000.0, G12=5_500.0, nu12=0.28, Xt=1_500.0, Xc=900.0,
                        Yt=27.0, Yc=200.0, S=80.0, fiber_strength=3_530.0, fiber_volume_fraction=0.60),
    # E-glass/LY556/HT907/DY063 [WWFE] (V_f 0.62, nu23 0.4); E-glass 3,450 MPa as above.
    "eglass_ly556": Lamina("eglass_ly556", E1=53_480.0, E2=17_700.0, G12=5_830.0, nu12=0.278, Xt=1_140.0,
                           Xc=570.0, Yt=35.0, Yc=114.0, S=72.0, fiber_strength=3_450.0,
                           fiber_volume_fraction=0.62),
}

STIFFNESS_KEYS = ("E1", "E2", "G12", "nu12")
STRENGTH_KEYS = ("Xt", "Xc", "Yt", "Yc", "S")


def lamina_of(name: str | None, given: dict[str, float], source: str = "",
              key_path: str = "winding.material") -> Lamina:
    """The ply of a job's material: the table's `name` with the given properties replacing its own, or
    the given properties alone (all of E1, E2, G12, nu12 and Xt, Xc, Yt, Yc, S); ConfigError otherwise."""
    if name is not None:
        if name not in MATERIALS:
            raise ConfigError(f"unknown material {name!r}; winder's table has {', '.join(MATERIALS)} (or give "
                              f"E1, E2, G12, nu12, Xt, Xc, Yt, Yc, S)", file=source or None,
                              key_path=f"{key_path}.name")
        ply = dataclasses.replace(MATERIALS[name], **given)
    else:
        missing = [k for k in STIFFNESS_KEYS + STRENGTH_KEYS if k not in given]
        if missing:
            raise ConfigError(f"the structural analysis needs the ply's {', '.join(missing)} (MPa; or a name "
                              f"from winder's table: {', '.join(MATERIALS)})", file=source or None,
                              key_path=f"{key_path}.{missing[0]}")
        ply = Lamina("given", **given)
    if not ply.nu12 ** 2 < ply.E1 / ply.E2:  # else Q is not positive definite: no stable ply
        raise ConfigError(f"must satisfy nu12^2 < E1 / E2 ({ply.E1:g} / {ply.E2:g}) for a stable ply, got "
                          f"{ply.nu12:g}", file=source or None, key_path=f"{key_path}.nu12")
    if not math.isfinite(ply.netting_stress()):
        raise ConfigError("the netting stress is not finite", file=source or None, key_path=key_path)
    return ply
