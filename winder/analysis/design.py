"""`winder design`: netting sizing before anything is planned (docs/math/09-structure.md 9.2, 9.8).

On the reference section of a surface of revolution (a vessel's cylinder, an open mandrel's largest
section, radius R): each layer's thickness as configured (a helical layer 2 t_p N_c B / (2 pi R cos a)
with N_c = ceil(2 pi R cos a / B), a hoop traverse t_p per pass), the burst pressure the fiber families
give under every load (pressure, axial force, torque), the helical and hoop thickness the loads need at
each helical layer's angle, and the optimum angle. On a vessel also both domes: the helical layers at
their geodesic angles on the bare dome (sin a = R sin a_R / r) and their thickness t_R R cos a_R /
(r cos a) (the same fiber crossing every parallel), hoops ending at the equators, from the equator to a
band width outside the largest turnaround (inside it the bosses carry the load: not netting's).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.analysis.gauge import is_vessel
from winder.analysis.job import check_analysis, load_case, netting_allowable
from winder.analysis.loads import resultants
from winder.analysis.materials import allowable_notes
from winder.analysis.netting import Wall, limits, optimum_angle, sizing
from winder.analysis.stations import surface_geometry
from winder.config.winding import layer_label
from winder.errors import ConfigError
from winder.winding.laminate import helical_mean_thickness
from winder.winding.wall import material_of, mean_radius, reference_station

HOOP_DEG = 90.0  # a hoop layer without an angle: its fibers along the parallel, to netting's accuracy
DOME_STATIONS = 64  # stations per dome, equator to the turnaround zone's edge


@dataclasses.dataclass(frozen=True, kw_only=True)
class LayerSizing:
    """One layer as configured: thickness (mm) on the reference section, its fibers' angle (deg) and
    netting allowable on the composite (MPa) and its source; helical layers also the helical and hoop
    thickness the loads need at their angle (mm; None for hoops)."""

    layer: int
    type: str
    angle_deg: float
    thickness_mm: float
    netting_stress_mpa: float
    allowable_source: str
    helical_needed_mm: float | None = None
    hoop_needed_mm: float | None = None


@dataclasses.dataclass(frozen=True, kw_only=True)
class Zone:
    """A netting burst (MPa) over a zone of the part: where (station t, radius r, mm) and which layer
    governs (1-based; None: a load no fiber carries)."""

    name: str
    burst_mpa: float
    t_mm: float
    r_mm: float
    layer: int | None


@dataclasses.dataclass(frozen=True, kw_only=True)
class Design:
    """The netting design of a job: R (mm), the load case, each layer, the zones covered (the cylinder,
    and a vessel's domes), the least burst over them, the optimum angle (deg) with the helical thickness
    it needs alone (mm), what was covered, and the notes on the allowables."""

    name: str
    radius_mm: float
    pressure_mpa: float
    axial_force_n: float
    torque_nmm: float
    ends: str
    layers: tuple[LayerSizing, ...]
    zones: tuple[Zone, ...]
    optimum_angle_deg: float
    optimum_thickness_mm: float
    covered: str
    notes: tuple[str, ...]

    @property
    def burst(self) -> Zone:
        return min(self.zones, key=lambda z: z.burst_mpa)

    def as_json(self) -> dict:
        def num(x, k=4):
            return None if x is None or not math.isfinite(x) else round(float(x), k) + 0.0

        zones = [{"zone": z.name, "burst_pressure_netting_mpa": num(z.burst_mpa), "t_mm": num(z.t_mm, 3),
                  "r_mm": num(z.r_mm, 3), "layer": z.layer} for z in self.zones]
        return {"name": self.name, "radius_mm": num(self.radius_mm), "pressure_mpa": num(self.pressure_mpa),
                "axial_force_n": num(self.axial_force_n), "torque_nmm": num(self.torque_nmm), "ends": self.ends,
                "burst_pressure_netting_mpa": num(self.burst.burst_mpa), "burst_netting_zone": self.burst.name,
                "burst_netting_layer": self.burst.layer, "zones": zones, "covered": self.covered,
                "netting_optimum_angle_deg": num(self.optimum_angle_deg),
                "optimum_helical_thickness_mm": num(self.optimum_thickness_mm), "notes": list(self.notes),
                "layers": [{"layer": s.layer, "type": s.type, "angle_deg": num(s.angle_deg),
                            "thickness_mm": num(s.thickness_mm), "netting_stress_mpa": num(s.netting_stress_mpa),
                            "allowable_source": s.allowable_source,
                            "helical_thickness_needed_mm": num(s.helical_needed_mm),
                            "hoop_thickness_needed_mm": num(s.hoop_needed_mm)} for s in self.layers]}


def _check(job, surface) -> None:
    if job.analysis is None:
        raise ConfigError("required by winder design (the load case: pressure in MPa, and optionally "
                          "axial_force, torque, ends)", file=job.source, key_path="analysis")
    if not job.analysis.pressure > 0.0:
        raise ConfigError("must be > 0 for winder design (the pressure the layers are sized for, MPa)",
                          file=job.source, key_path="analysis.pressure")
    if not surface.is_revolution:
        raise ConfigError("winder design needs a surface of revolution (a straight axis and circular sections); "
                          "the shell model of --format abaqus covers the others", file=job.source, key_path="mandrel")


def _dome_stations(surface, radius: float, inner: float) -> list[tuple[str, np.ndarray]]:
    """Each dome's stations t from its equator to where r = inner (the turnaround zone's edge)."""
    a, b = surface.profile.equator_t
    out = []
    for name, lo, hi in (("start dome", 0.0, a), ("end dome", b, surface.axial_length)):
        t = np.linspace(lo, hi, 4 * DOME_STATIONS + 1)
        r = surface.perimeter(surface.s_of_t(t)) / (2.0 * np.pi)
        keep = t[(r >= inner) & (r < radius * (1.0 - 1e-9))]
        if keep.size:
            out.append((name, np.linspace(keep.min(), keep.max(), DOME_STATIONS)))
    return out


def design(job, surface) -> Design:
    """The netting design of a validated job on its (bare) surface; ConfigError where it does not apply."""
    plies = check_analysis(job)
    _check(job, surface)
    band = job.winding.band_width
    region = job.winding.region or (0.0, surface.axial_length)
    radius = mean_radius(surface, reference_station(surface, region, band))
    case = load_case(job)
    layers, hel, notes = [], [], []
    for i, cfg in enumerate(job.winding.layers):
        ply = material_of(job.winding.material_of(i)).ply(band)
        allow = netting_allowable(job, i, plies[i])
        notes += [n for n in allowable_notes(plies[i], allow) if n not in notes]
        sigma = allow.composite
        if cfg.type.value == "helical":
            a = math.radians(cfg.angle_deg)
            circuits = math.ceil(2.0 * math.pi * radius * math.cos(a) / band)
            t = helical_mean_thickness(ply, circuits, band, radius, a)
            t_h, t_c = sizing(case.pressure, radius, sigma, a, case.closed, case.axial_force, case.torque)
            layers.append(LayerSizing(layer=i + 1, type="helical", angle_deg=cfg.angle_deg, thickness_mm=t,
                                      netting_stress_mpa=sigma, allowable_source=allow.source,
                                      helical_needed_mm=t_h, hoop_needed_mm=t_c))
            hel.append((i, ply, circuits, a))
        else:
            angle = cfg.angle_deg if cfg.angle_deg is not None else HOOP_DEG
            layers.append(LayerSizing(layer=i + 1, type="hoop", angle_deg=angle, thickness_mm=ply * cfg.passes,
                                      netting_stress_mpa=sigma, allowable_source=allow.source))
    allow = [netting_allowable(job, i, plies[i]) for i in range(len(layers))]
    base = dict(helical=np.array([s.type == "helical" for s in layers]), modulus=np.array([p.E1 for p in plies]),
                tension=np.array([a.composite for a in allow]),
                compression=np.array([a.composite_compression for a in allow]))
    ref_t = reference_station(surface, region, band)
    groups = [("cylinder" if is_vessel(surface) else "reference section", np.array([ref_t]))]
    covered = f"the reference section (R = {radius:.3f} mm)"
    if is_vessel(surface) and hel:
        inner = radius * max(math.sin(a) for *_, a in hel) + band
        groups += _dome_stations(surface, radius, inner)
        covered = (f"the cylinder (R = {radius:.3f} mm) and both domes from the equator to r = {inner:.3f} mm "
                   "(a band outside the largest turnaround; the bosses carry the rest)")
    zones = []
    for name, t in groups:
        geo = surface_geometry(surface, t)
        angle = np.zeros((t.size, len(layers)))
        thick = np.zeros_like(angle)
        for k, s in enumerate(layers):
            if s.type == "hoop":
                if name in ("cylinder", "reference section"):
                    angle[:, k], thick[:, k] = math.radians(s.angle_deg), s.thickness_mm
                continue
            _, ply, circuits, a = next(h for h in hel if h[0] == k)
            sin_a = np.clip(radius * math.sin(a) / geo.r, 0.0, 1.0)
            angle[:, k] = np.arcsin(sin_a)
            thick[:, k] = helical_mean_thickness(ply, circuits, band, 1.0, 0.0) / (geo.r * np.cos(angle[:, k]))
        per_p, held = resultants(geo, case)
        net = limits(Wall(angle=angle, thickness=thick, **base), per_p, held)
        i = net.index
        k = int(net.layer[i])
        zones.append(Zone(name=name, burst_mpa=net.pressure, t_mm=float(t[i]), r_mm=float(geo.r[i]),
                          layer=layers[k].layer if k >= 0 else None))
    n_m = (0.5 * radius if case.closed else 0.0) * case.pressure + case.axial_force / (2 * math.pi * radius)
    best = optimum_angle(n_m, radius * case.pressure)
    sigma0 = next((s.netting_stress_mpa for s in layers if s.type == "helical"), layers[0].netting_stress_mpa)
    t_opt, _ = sizing(case.pressure, radius, sigma0, best, case.closed, case.axial_force, case.torque)
    return Design(name=job.name, radius_mm=radius, pressure_mpa=case.pressure, axial_force_n=case.axial_force,
                  torque_nmm=case.torque, ends=job.analysis.ends, layers=tuple(layers), zones=tuple(zones),
                  optimum_angle_deg=math.degrees(best), optimum_thickness_mm=t_opt, covered=covered,
                  notes=tuple(notes))


def design_text(d: Design) -> str:
    """The design as a few lines for a terminal: every load it used, each layer, each zone's burst."""
    lines = [f"{d.name}: netting design at {d.pressure_mpa:g} MPa, axial force {d.axial_force_n:g} N, torque "
             f"{d.torque_nmm:g} N mm, {d.ends} ends",
             f"  covers {d.covered}"]
    for s in d.layers:
        line = (f"  {layer_label(s.layer - 1, s.type, round(s.angle_deg, 2))}: {s.thickness_mm:.4f} mm as configured "
                f"(allowable {s.netting_stress_mpa:.0f} MPa on the composite, from {s.allowable_source})")
        if s.helical_needed_mm is not None:
            line += (f"; the loads need helical {s.helical_needed_mm:.4f} mm and hoop {s.hoop_needed_mm:.4f} mm "
                     "at this angle")
        lines.append(line)
    for z in d.zones:
        own = next((s for s in d.layers if s.layer == z.layer), None)
        who = layer_label(own.layer - 1, own.type, round(own.angle_deg, 2)) if own else "a load no fiber carries"
        lines.append(f"  burst (netting) {z.burst_mpa:.3f} MPa on the {z.name} at r = {z.r_mm:.3f} mm, t = "
                     f"{z.t_mm:.3f} mm ({who} first)")
    lines.append(f"  optimum angle {d.optimum_angle_deg:.4f} deg: helical alone {d.optimum_thickness_mm:.4f} mm")
    lines += [f"  note: {n}" for n in d.notes]
    return "\n".join(lines)
