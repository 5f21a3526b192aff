"""What a job's analysis needs from its config: each layer's ply material, the load case, and the checks
`check` and `run` make before any computation (an unknown material name, missing ply data: exit 2)."""

from __future__ import annotations

from winder.analysis.loads import LoadCase
from winder.analysis.materials import Lamina, NettingAllowable, lamina_of
from winder.errors import ConfigError


def layer_laminae(job) -> tuple[Lamina | None, ...]:
    """Each layer's ply (None where its material gives no ply data); ConfigError for an unknown name or
    incomplete properties. The job's material key path is winding.material, a layer's own
    `layer 5 (helical 16 deg).material` (winder.config.winding.layer_label)."""
    out = []
    for i, layer in enumerate(job.winding.layers):
        cfg = job.winding.material_of(i)
        if cfg is None or cfg.lamina is None:
            out.append(None)
            continue
        own = layer.material is not None
        path = f"{layer.label(i)}.material" if own else "winding.material"
        out.append(lamina_of(cfg.lamina.name, cfg.lamina.values, job.source, path))
    return tuple(out)


def check_analysis(job) -> tuple[Lamina | None, ...]:
    """The layers' plies; with an `analysis:` section every layer needs one (and a thickness: a material)."""
    if job.winding is None:
        return ()
    plies = layer_laminae(job)
    schedule = job.winding.tension is not None and job.winding.tension.schedule is not None
    if schedule and (not job.winding.has_laminate or any(p is None for p in plies)):  # docs/math/16
        raise ConfigError(f"{job.winding.tension.schedule} needs every layer's material with its ply stiffness (a "
                          "name from winder's table, or E1 and E2) and its thickness (fiber_tex, tows, ... or "
                          "ply_thickness)", file=job.source, key_path="winding.tension")
    if job.analysis is None:
        return plies
    if not job.winding.has_laminate:
        raise ConfigError("needs winding.material (the ply thickness and its stiffness and strength: a name from "
                          "winder's table or E1, E2, G12, nu12, Xt, Xc, Yt, Yc, S)", file=job.source,
                          key_path="analysis")
    _check_ratios(job, plies)
    for i, ply in enumerate(plies):
        if ply is None:
            raise ConfigError("the structural analysis needs the ply's stiffness and strength: a name from "
                              "winder's table or E1, E2, G12, nu12, Xt, Xc, Yt, Yc, S", file=job.source,
                              key_path="winding.material" if job.winding.layers[i].material is None
                              else f"{job.winding.layers[i].label(i)}.material")
    return plies


def _check_ratios(job, plies: tuple[Lamina | None, ...]) -> None:
    """A stress_ratio given per material names materials the job's layers use (a typo is never ignored)."""
    ratios = job.analysis.stress_ratio
    if not isinstance(ratios, tuple):
        return
    names = sorted({p.name for p in plies if p is not None})
    for name, _ in ratios:
        if name not in names:
            raise ConfigError(f"no layer's material is named {name!r} (the job's: {', '.join(names) or 'none'})",
                              file=job.source, key_path=f"analysis.stress_ratio.{name}")


def load_case(job) -> LoadCase:
    a = job.analysis
    return LoadCase(a.pressure, a.axial_force, a.torque, a.ends == "closed")


def netting_allowable(job, index: int, ply: Lamina) -> NettingAllowable:
    """The netting allowables of layer `index` (0-based) at its material's V_f (docs/math/09 9.2)."""
    cfg = job.winding.material_of(index)
    return ply.netting_allowable(None if cfg is None else cfg.fiber_volume_fraction)


def netting_stress(job, index: int, ply: Lamina) -> float:
    """The netting allowable of layer `index` (0-based) on the composite thickness (MPa)."""
    return netting_allowable(job, index, ply).composite
