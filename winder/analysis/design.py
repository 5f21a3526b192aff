"""`winder design`: netting sizing before anything is planned (docs/math/09-structure.md 9.2).

On the reference section of a surface of revolution (a vessel's cylinder, an open mandrel's largest
section, radius R): each layer's thickness as configured (MATH.md 8's closed forms: a helical layer
2 t_p N_c B / (2 pi R cos a) with N_c = ceil(2 pi R cos a / B), a hoop traverse t_p), the burst pressure
they give, the helical and hoop thickness the pressure needs at each helical layer's angle, and the
optimum angle.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.analysis.job import check_analysis, load_case, netting_stress
from winder.analysis.netting import cylinder_limits, optimum_angle, sizing
from winder.errors import ConfigError
from winder.winding.laminate import helical_mean_thickness
from winder.winding.wall import material_of, mean_radius, reference_station

HOOP_DEG = 90.0  # a hoop layer without an angle: its fibers along the parallel, to netting's accuracy


@dataclasses.dataclass(frozen=True)
class LayerSizing:
    """One layer as configured: thickness (mm) on the reference section, its fibers' angle (deg) and
    netting allowable (MPa); helical layers also the helical and hoop thickness the pressure needs
    at their angle (mm; None for hoops)."""

    layer: int
    type: str
    angle_deg: float
    thickness_mm: float
    netting_stress_mpa: float
    helical_needed_mm: float | None = None
    hoop_needed_mm: float | None = None


@dataclasses.dataclass(frozen=True)
class Design:
    """The netting design of a job: R (mm), the load case, each layer, the burst of the layers as
    configured (MPa; axial and hoop limits) and the optimum angle (deg) with the helical thickness it
    needs alone (mm)."""

    name: str
    radius_mm: float
    pressure_mpa: float
    axial_force_n: float
    ends: str
    layers: tuple[LayerSizing, ...]
    axial_limit_mpa: float
    hoop_limit_mpa: float
    burst_pressure_netting_mpa: float
    optimum_angle_deg: float
    optimum_thickness_mm: float

    def as_json(self) -> dict:
        def num(x, k=4):
            return None if x is None or not math.isfinite(x) else round(float(x), k) + 0.0

        return {"name": self.name, "radius_mm": num(self.radius_mm), "pressure_mpa": num(self.pressure_mpa),
                "axial_force_n": num(self.axial_force_n), "ends": self.ends,
                "axial_limit_mpa": num(self.axial_limit_mpa), "hoop_limit_mpa": num(self.hoop_limit_mpa),
                "burst_pressure_netting_mpa": num(self.burst_pressure_netting_mpa),
                "netting_optimum_angle_deg": num(self.optimum_angle_deg),
                "optimum_helical_thickness_mm": num(self.optimum_thickness_mm),
                "layers": [{"layer": s.layer, "type": s.type, "angle_deg": num(s.angle_deg),
                            "thickness_mm": num(s.thickness_mm), "netting_stress_mpa": num(s.netting_stress_mpa),
                            "helical_thickness_needed_mm": num(s.helical_needed_mm),
                            "hoop_thickness_needed_mm": num(s.hoop_needed_mm)} for s in self.layers]}


def design(job, surface) -> Design:
    """The netting design of a validated job on its (bare) surface; ConfigError where it does not apply."""
    plies = check_analysis(job)
    if job.analysis is None:
        raise ConfigError("required by winder design (the load case: pressure in MPa, and optionally "
                          "axial_force, torque, ends)", file=job.source, key_path="analysis")
    if not job.analysis.pressure > 0.0:
        raise ConfigError("must be > 0 for winder design (the pressure the layers are sized for, MPa)",
                          file=job.source, key_path="analysis.pressure")
    if not surface.is_revolution:
        raise ConfigError("winder design needs a surface of revolution (a straight axis and circular sections); "
                          "the shell model of --format abaqus covers the others", file=job.source, key_path="mandrel")
    band = job.winding.band_width
    region = job.winding.region or (0.0, surface.axial_length)
    radius = mean_radius(surface, reference_station(surface, region, band))
    case = load_case(job)
    layers, hel_t, hel_a, sig_h = [], [], [], []
    hoop_cap = 0.0
    for i, cfg in enumerate(job.winding.layers):
        ply = material_of(job.winding.material_of(i)).ply(band)
        sigma = netting_stress(job, i, plies[i])
        if cfg.type.value == "helical":
            a = math.radians(cfg.angle_deg)
            circuits = math.ceil(2.0 * math.pi * radius * math.cos(a) / band)
            t = helical_mean_thickness(ply, circuits, band, radius, a)
            t_h, t_c = sizing(case.pressure, radius, sigma, a, case.closed, case.axial_force)
            layers.append(LayerSizing(i + 1, "helical", cfg.angle_deg, t, sigma, t_h, t_c))
            hel_t.append(t * sigma)  # thickness weighted by its allowable: one sigma below
            hel_a.append(a)
            sig_h.append(sigma)
        else:
            angle = cfg.angle_deg if cfg.angle_deg is not None else HOOP_DEG
            t = ply * cfg.passes
            layers.append(LayerSizing(i + 1, "hoop", angle, t, sigma))
            hoop_cap += sigma * t * math.sin(math.radians(angle)) ** 2
    # limits with each layer at its own allowable: capacities in N/mm over a unit sigma
    lim = cylinder_limits(radius, 1.0, np.array(hel_t) if hel_t else 0.0, np.array(hel_a) if hel_a else 0.0,
                          hoop_cap, case.closed, case.axial_force)
    n_m = (0.5 * radius if case.closed else 0.0) * case.pressure + case.axial_force / (2 * math.pi * radius)
    best = optimum_angle(n_m, radius * case.pressure)
    sigma0 = sig_h[0] if sig_h else layers[0].netting_stress_mpa
    t_opt, _ = sizing(case.pressure, radius, sigma0, best, case.closed, case.axial_force)
    return Design(job.name, radius, case.pressure, case.axial_force, job.analysis.ends, tuple(layers),
                  float(lim.axial[0]), float(lim.hoop[0]), float(lim.burst[0]), math.degrees(best), t_opt)


def design_text(d: Design) -> str:
    """The design as a few lines for a terminal."""
    lines = [f"{d.name}: netting design on R = {d.radius_mm:.3f} mm at {d.pressure_mpa:g} MPa ({d.ends} ends"
             + (f", axial force {d.axial_force_n:g} N" if d.axial_force_n else "") + ")"]
    for s in d.layers:
        line = (f"  layer {s.layer} {s.type} {s.angle_deg:.2f} deg: {s.thickness_mm:.4f} mm as configured "
                f"(sigma {s.netting_stress_mpa:.0f} MPa)")
        if s.helical_needed_mm is not None:
            line += (f"; the pressure needs helical {s.helical_needed_mm:.4f} mm and hoop {s.hoop_needed_mm:.4f} mm "
                     "at this angle")
        lines.append(line)
    lines.append(f"  burst (netting) {d.burst_pressure_netting_mpa:.3f} MPa: axial limit {d.axial_limit_mpa:.3f}, "
                 f"hoop limit {d.hoop_limit_mpa:.3f} MPa")
    lines.append(f"  optimum angle {d.optimum_angle_deg:.4f} deg: helical alone {d.optimum_thickness_mm:.4f} mm")
    return "\n".join(lines)
