"""The tension of every pass (N per band), carried in the motion program (winder.machine.program's
Segment.tension) so that every program writes it as its controller's command and `simulate` reads it
back: a layer's own (constant, or linear from its first pass to its last), else the job's, or the
job's uniform-prestress schedule (winder.analysis.prestress, docs/math/16-winding-tension.md).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.config.tension import UNIFORM_PRESTRESS, TensionConfig
from winder.config.winding import WindingConfig
from winder.errors import ConfigError, SolverError
from winder.machine.program import MotionProgram, build_program
from winder.winding.results import WindingPlan


def pass_tensions(job, plan: WindingPlan) -> tuple[tuple[float, ...], ...] | None:
    """Per layer, the tension (N) of each of its passes; None when the job programs none."""
    winding: WindingConfig | None = job.winding
    if winding is None or (winding.tension is None and all(layer.tension is None for layer in winding.layers)):
        return None
    schedule = None
    if winding.tension is not None and winding.tension.schedule == UNIFORM_PRESTRESS:
        schedule = prestress_tensions(job, plan, winding.tension)
    out = []
    for i, layer in enumerate(plan.layers):
        n = len(layer.passes)
        own: TensionConfig | None = winding.layers[i].tension
        fractions = np.linspace(0.0, 1.0, n) if n > 1 else np.zeros(n)
        if own is None and schedule is not None:
            out.append((float(schedule[i]),) * n)
        else:
            out.append(tuple(float(v) for v in (own or winding.tension).at(fractions)))
    return tuple(out)


def prestress_tensions(job, plan: WindingPlan, config: TensionConfig) -> np.ndarray:
    """The uniform-prestress schedule's winding tension per layer (N); ConfigError without the ply data
    it needs, SolverError where a layer would need more than the schedule's max (or no tension)."""
    from winder.analysis.job import layer_laminae  # noqa: PLC0415
    from winder.analysis.prestress import RingStack, uniform_prestress  # noqa: PLC0415

    key = "winding.tension"
    walls = [layer.laminate for layer in plan.layers]
    plies = layer_laminae(job) if job.winding.has_laminate else ()
    if not plies or any(w is None for w in walls) or any(p is None for p in plies):
        raise ConfigError(f"{config.schedule} needs every layer's material with its ply stiffness (a name from "
                          "winder's table, or E1 and E2) and its thickness (fiber_tex, tows, ... or ply_thickness)",
                          file=job.source, key_path=key)
    thickness = np.array([w.thickness_mm for w in walls])
    outer = np.array([w.outer_radius_mm for w in walls])
    e2 = np.array([p.E2 for p in plies])
    stack = RingStack(radius=outer - 0.5 * thickness, thickness=thickness,
                      angle_deg=np.array([layer.angle_deg for layer in plan.layers]),
                      e1=np.array([p.E1 for p in plies]), e2=e2,
                      band_area=float(job.winding.band_width) * np.array([w.ply_mm for w in walls]),
                      radial_modulus=np.full_like(e2, config.radial_modulus) if config.radial_modulus else e2,
                      mandrel_stiffness=(config.mandrel_modulus / float(outer[0] - thickness[0])
                                         if config.mandrel_modulus else np.inf))
    wound = uniform_prestress(stack, config.start)
    for i, value in enumerate(wound.tolist()):
        cfg = job.winding.layers[i]
        if not value > 0.0 or (config.limit is not None and value > config.limit):
            limit = f"past its max of {config.limit:g} N" if config.limit is not None else "none"
            raise SolverError(f"{cfg.label(i)}: the uniform prestress of {config.start:g} N needs a winding tension "
                              f"of {value:.1f} N ({limit}): lower the residual, or give this layer its own tension",
                              file=job.source, key_path=key)
    return wound


def with_tension(program: MotionProgram, tensions: tuple[tuple[float, ...], ...] | None) -> MotionProgram:
    """The program with each pass's tension (pass_tensions' per layer, per pass in the plan's order)."""
    if tensions is None or isinstance(program, Exception):
        return program
    segments = tuple(tuple(dataclasses.replace(seg, tension=value) for seg, value in zip(segs, values))
                     for segs, values in zip(program.segments, tensions))
    return dataclasses.replace(program, segments=segments)


def job_program(plan: WindingPlan, job) -> MotionProgram:
    """The job's motion program with its tensions (what an output builds when it is handed none)."""
    return with_tension(build_program(plan, job.machine), pass_tensions(job, plan))
