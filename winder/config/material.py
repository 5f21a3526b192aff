"""The `material:` of a winding plan (docs/math/08-laminate-edges.md): per job, and per layer as an override.

    material: {fiber_tex: 800, tows: 4, fiber_density: 1.78, resin_density: 1.15,
               fiber_volume_fraction: 0.6}
    material: {ply_thickness: 0.25}      # mm per band; densities and fraction only for masses
    fiber_price_per_kg, resin_price_per_kg   # optional: the traveller's and the summary's material costs
"""

from __future__ import annotations

import dataclasses
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from winder.config.analysis import LAMINA_KEYS, LaminaConfig, parse_lamina

if TYPE_CHECKING:
    from winder.config.reader import Reader

MAX_TOWS = 1000
# Densities are read in g/cm^3; the densest element (osmium) is 22.6, so a larger value is one typed
# in kg/m^3 (2560 for glass), which would make bands and resin masses a thousand times too small.
MAX_DENSITY = 25.0


@dataclasses.dataclass(frozen=True)
class MaterialConfig:
    """A band's material (YAML `winding.material`, or a layer's `material`).

    fiber_tex: linear density of one tow, g/km (tex), > 0. tows: tows per band, whole number >= 1.
    fiber_density, resin_density: g/cm^3, > 0 and <= MAX_DENSITY. fiber_volume_fraction: V_f, in (0, 1).
    ply_thickness: instead of fiber_tex and tows: the thickness of one band as laid, mm, > 0 and
        below the band width.
    With fiber_tex, tows, fiber_density and fiber_volume_fraction are required and resin_density is
    needed for the resin mass; with ply_thickness the densities and V_f are optional (no masses
    without fiber_density and fiber_volume_fraction).
    """

    fiber_tex: float | None = None
    tows: int | None = None
    fiber_density: float | None = None
    resin_density: float | None = None
    fiber_volume_fraction: float | None = None
    ply_thickness: float | None = None
    lamina: LaminaConfig | None = None  # ply stiffness and strength (docs/guide/will-it-hold.md)
    fiber_price_per_kg: float | None = None  # the fiber's price per kg, in the shop's currency (the traveller's costs)
    resin_price_per_kg: float | None = None  # the resin's


PRICE_KEYS = ("fiber_price_per_kg", "resin_price_per_kg")
MAX_PRICE = 1.0e6  # per kg: past this a price was typed per tonne, or in the wrong unit
_KEYS = ("fiber_tex", "tows", "fiber_density", "resin_density", "fiber_volume_fraction", "ply_thickness",
         *LAMINA_KEYS, *PRICE_KEYS)


def parse_material(rd: Reader, value: Any, path: str, band_width: float) -> MaterialConfig:
    """A material mapping; every problem is one ConfigError naming its key."""
    m = rd.mapping(value, path, _KEYS)
    if "fiber_tex" in m and "ply_thickness" in m:
        raise rd.error(rd.at(path, "ply_thickness"), "give fiber_tex (with tows) or ply_thickness, not both",
                       m["ply_thickness"])
    if "fiber_tex" not in m and "ply_thickness" not in m:
        raise rd.error(path, "needs fiber_tex (g/km, with tows, fiber_density and fiber_volume_fraction) "
                       "or ply_thickness (mm per band)", value)
    out: dict[str, Any] = {}
    if "fiber_tex" in m:
        out["fiber_tex"] = rd.positive(m["fiber_tex"], rd.at(path, "fiber_tex"))
    for key in ("fiber_density", "resin_density"):
        if key in m:
            out[key] = rd.positive(m[key], rd.at(path, key))
            if out[key] > MAX_DENSITY:
                raise rd.error(rd.at(path, key), f"must be at most {MAX_DENSITY:g} g/cm^3 (densities are in "
                               "g/cm^3, not kg/m^3: carbon 1.78, glass 2.56, epoxy 1.15)", m[key])
    if "tows" in m:
        out["tows"] = rd.integer(m["tows"], rd.at(path, "tows"), minimum=1, maximum=MAX_TOWS)
    if "fiber_volume_fraction" in m:
        vf = rd.number(m["fiber_volume_fraction"], rd.at(path, "fiber_volume_fraction"))
        if not 0.0 < vf < 1.0:
            raise rd.error(rd.at(path, "fiber_volume_fraction"), "must be in (0, 1) (the fiber's share "
                           "of the composite volume, typically 0.5 to 0.65)", m["fiber_volume_fraction"])
        out["fiber_volume_fraction"] = vf
    if "fiber_tex" in m:
        for key, what in (("tows", "tows per band"), ("fiber_density", "g/cm^3"),
                          ("fiber_volume_fraction", "in (0, 1)")):
            if key not in m:
                raise rd.error(rd.at(path, key), f"required with fiber_tex ({what})")
    if "ply_thickness" in m:
        if "tows" in m:
            raise rd.error(rd.at(path, "tows"), "only with fiber_tex (ply_thickness already gives the "
                           "band's thickness)", m["tows"])
        ply = rd.positive(m["ply_thickness"], rd.at(path, "ply_thickness"))
        if not ply < band_width:
            raise rd.error(rd.at(path, "ply_thickness"), f"must be smaller than the band width "
                           f"({band_width:g} mm)", m["ply_thickness"])
        out["ply_thickness"] = ply
    else:
        area = out["tows"] * out["fiber_tex"] / (1000.0 * out["fiber_density"]) / out["fiber_volume_fraction"]
        if not area / band_width < band_width:
            raise rd.error(rd.at(path, "fiber_tex"), f"gives a band {area / band_width:.4g} mm thick, "
                           f"not thinner than its width ({band_width:g} mm)", m["fiber_tex"])
    lamina = parse_lamina(rd, m, path)
    if lamina is not None:
        out["lamina"] = lamina
    for key in PRICE_KEYS:
        if key in m:
            price = rd.number(m[key], rd.at(path, key))
            if not 0.0 <= price <= MAX_PRICE:
                raise rd.error(rd.at(path, key), f"must be in [0, {MAX_PRICE:g}] (a price per kg, in your currency)",
                               m[key])
            out[key] = price
    return MaterialConfig(**out)


def parse_materials(rd: Reader, value: Any, items: list[Any], layers: tuple, path: str,
                    band_width: float) -> tuple[MaterialConfig | None, tuple]:
    """The job's material (`value`, None if not given) and the layers with their own materials.

    items : the layers as read (mappings); layers : their parsed LayerConfigs. A layer's material
    overrides the job's; when some layers have one and the job has none, every layer needs one.
    """
    material = None if value is None else parse_material(rd, value, rd.at(path, "material"), band_width)
    out = []
    for i, (item, layer) in enumerate(zip(items, layers)):
        if isinstance(item, dict) and "material" in item:
            where = rd.at(layer.label(i), "material")
            layer = replace(layer, material=parse_material(rd, item["material"], where, band_width))
        out.append(layer)
    if material is None and any(x.material is not None for x in out):
        missing = next((i for i, x in enumerate(out) if x.material is None), None)
        if missing is not None:
            raise rd.error(out[missing].label(missing), "needs a material: other layers have one "
                           "and winding.material (the default for all layers) is not given")
    return material, tuple(out)
