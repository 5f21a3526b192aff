"""Ply materials: stiffness and strength of a unidirectional ply, and a small table of common systems.

Units MPa. Strengths are magnitudes (Xc, Yc > 0 for compression). strand_strength is the impregnated
strand's tensile strength on the fiber area (ASTM D4018 for carbon tows, D2343 / ISO 9163 for glass rovings):
the netting allowable of the fibers (docs/math/09-structure.md 9.2); fiber_strength the dry filament's,
which a laminate never reaches (information only). nu23 the transverse Poisson ratio the shell model's 3D
constants need. Every number of the table names its source.
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
    strand_strength: float | None = None

    @property
    def nu21(self) -> float:
        return self.nu12 * self.E2 / self.E1

    def netting_stress(self, fiber_volume_fraction: float | None = None) -> float:
        """The netting allowable on the composite thickness (MPa): the fibers' allowable times the job's V_f
        (else the data's; docs/math/09-structure.md 9.2)."""
        return self.netting_allowable(fiber_volume_fraction).composite

    def netting_allowable(self, fiber_volume_fraction: float | None = None) -> NettingAllowable:
        """The fibers' netting allowable and where it comes from: the impregnated strand's strength where
        given, else the ply's Xt over the V_f it was measured at (the fiber stress at the ply's failure);
        compression Xc likewise. V_f: the job's material's (fiber_volume_fraction), else the data's."""
        vf_data = self.fiber_volume_fraction if self.fiber_volume_fraction is not None else fiber_volume_fraction
        vf = fiber_volume_fraction if fiber_volume_fraction is not None else vf_data
        if vf is None or vf_data is None:  # no fraction anywhere: the ply's own strengths, on its thickness
            return NettingAllowable(fiber=self.Xt, fiber_compression=self.Xc, ply_fiber=self.Xt, fraction=1.0,
                                    source="Xt", xt=self.Xt)
        ply = self.Xt / vf_data
        strand = self.strand_strength is not None
        return NettingAllowable(fiber=self.strand_strength if strand else ply, fiber_compression=self.Xc / vf_data,
                                ply_fiber=ply, fraction=vf, source="strand_strength" if strand else "Xt / V_f",
                                xt=self.Xt)


@dataclasses.dataclass(frozen=True, kw_only=True)
class NettingAllowable:
    """A ply's netting allowables: tension and compression on the fibers' area (MPa), the ply's Xt / V_f
    (the fiber stress at its tensile failure), the V_f they act on, where the tension figure comes from
    (`strand_strength`, `Xt / V_f`, or `Xt` when no fraction is known) and the ply's Xt."""

    fiber: float
    fiber_compression: float
    ply_fiber: float
    fraction: float
    source: str
    xt: float

    @property
    def composite(self) -> float:
        """The tension allowable on the composite thickness (MPa): fiber V_f."""
        return self.fiber * self.fraction

    @property
    def composite_compression(self) -> float:
        return self.fiber_compression * self.fraction

    @property
    def above_ply(self) -> bool:
        """The strand figure exceeds what the ply's own test reaches (Xt / V_f): said wherever it is used."""
        return self.fiber > self.ply_fiber * (1.0 + 1e-9)


# The shipped systems. Sources:
#  [DI] I. M. Daniel, O. Ishai, Engineering Mechanics of Composite Materials, 2nd ed., Oxford University
#       Press 2006, Table A.4 (properties of unidirectional composite materials).
#  [WWFE] P. D. Soden, M. J. Hinton, A. S. Kaddour, "Lamina properties, lay-up configurations and loading
#       conditions for a range of fibre-reinforced composite laminates", Composites Science and Technology
#       58 (1998) 1011-1022, Table 1 and 2 (the World-Wide Failure Exercise data).
#  Strand strengths: the fiber makers' data sheets, whose tensile figures are impregnated-strand tests (Hexcel:
#       "tow tensile test, ASTM D4018"; Toray: its method TY-030B-01, a resin-impregnated strand), on the
#       fiber's area. Glass: the filament strength of [DI] Table A.1 is a dry (pristine) figure, no strand
#       test; those entries carry no strand strength and net on Xt / V_f.
MATERIALS: dict[str, Lamina] = {
    # AS4/3501-6 [DI]; AS4 strand 4,413 MPa (Hexcel HexTow AS4 data sheet, ASTM D4018).
    "carbon_epoxy": Lamina("carbon_epoxy", E1=147_000.0, E2=10_300.0, G12=7_000.0, nu12=0.27, Xt=2_280.0,
                           Xc=1_725.0, Yt=57.0, Yc=228.0, S=76.0, strand_strength=4_413.0,
                           fiber_volume_fraction=0.63),
    # E-glass/epoxy [DI]; E-glass filament 3,450 MPa dry ([DI] Table A.1): information, not an allowable.
    "eglass_epoxy": Lamina("eglass_epoxy", E1=41_000.0, E2=10_400.0, G12=4_300.0, nu12=0.28, Xt=1_140.0,
                           Xc=620.0, Yt=39.0, Yc=128.0, S=89.0, fiber_strength=3_450.0,
                           fiber_volume_fraction=0.55),
    # T300/BSL914C [WWFE] (V_f 0.60, nu23 0.4); T300 strand 3,530 MPa (Toray T300 data sheet, TY-030B-01).
    "t300_914c": Lamina("t300_914c", E1=138_000.0, E2=11_000.0, G12=5_500.0, nu12=0.28, Xt=1_500.0, Xc=900.0,
                        Yt=27.0, Yc=200.0, S=80.0, strand_strength=3_530.0, fiber_volume_fraction=0.60),
    # E-glass/LY556/HT907/DY063 [WWFE] (V_f 0.62, nu23 0.4); E-glass filament 3,450 MPa dry as above.
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


def allowable_notes(ply: Lamina, allowable: NettingAllowable) -> list[str]:
    """What the netting allowable of a ply rests on, said wherever it is used: a strand figure above the
    ply's own Xt / V_f, and a dry fiber_strength that is no allowable."""
    notes = []
    if allowable.source == "strand_strength" and allowable.above_ply:
        notes.append(f"{ply.name}: strand_strength {allowable.fiber:g} MPa is above the ply's Xt / V_f = "
                     f"{allowable.ply_fiber:.1f} MPa: netting on the strand figure, first-ply failure on Xt")
    if allowable.source == "strand_strength" and ply.fiber_strength is not None:
        notes.append(f"{ply.name}: fiber_strength {ply.fiber_strength:g} MPa (a dry filament's) is not used: netting "
                     f"on strand_strength {allowable.fiber:g} MPa")
    if allowable.source != "strand_strength" and ply.fiber_strength is not None:
        notes.append(f"{ply.name}: fiber_strength {ply.fiber_strength:g} MPa is the dry filament's, never reached "
                     f"in a laminate: netting on Xt / V_f = {allowable.ply_fiber:.1f} MPa (give strand_strength, the "
                     "impregnated strand's, ASTM D4018 / D2343)")
    return notes
