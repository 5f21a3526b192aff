"""`--format abaqus`: `<name>.inp`, an Abaqus / CalculiX input deck of the wound part (docs/guide/will-it-hold.md;
docs/math/09-structure.md 9.5): the shell model of winder.analysis.shell_model written out.

S8R shells on the mandrel surface (OFFSET = -0.5: the nodes on the laminate's inner face, the plies
outward along the element normal); per element a *SHELL SECTION, COMPOSITE with each ply's thickness,
material and *ORIENTATION (SYSTEM = RECTANGULAR, local x the fiber, y in the shell's plane); the ply
materials as ELASTIC, TYPE = ENGINEERING CONSTANTS; *DLOAD P (the internal pressure) on every element,
the ends' thrust, axial force and torque as *CLOAD; the start ring held along the axis and two of its
nodes tangentially; one *STATIC step writing U, S, E (.frd) and the mid-length rings' U (.dat).
"""

from __future__ import annotations

import io

import numpy as np

from winder.analysis.gauge import is_vessel
from winder.analysis.job import check_analysis
from winder.analysis.layup import layer_rows
from winder.analysis.materials import Lamina
from winder.analysis.shell_model import NTHETA, ShellModel, build_model
from winder.errors import ConfigError, ExportError
from winder.escape import abaqus_text

NUM = "%.9g"  # node coordinates and loads: single-precision solvers read 9 digits without loss


def require_analysis(job) -> None:
    """Refuse `--format abaqus` of a job without a laminate, ply data or load case, before planning."""
    if job.analysis is None:
        raise ConfigError("required for --format abaqus (the load case of the shell model: pressure, axial_force, "
                          "torque, ends)", file=job.source, key_path="analysis")
    check_analysis(job)


def _material(name: str, ply: Lamina) -> str:
    g23 = ply.E2 / (2.0 * (1.0 + ply.nu23))  # the transversely isotropic ply's transverse shear modulus
    return (f"*MATERIAL, NAME={name}\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n"
            f"{ply.E1:.9g}, {ply.E2:.9g}, {ply.E2:.9g}, {ply.nu12:.9g}, {ply.nu12:.9g}, {ply.nu23:.9g}, "
            f"{ply.G12:.9g}, {ply.G12:.9g}\n{g23:.9g}, 0.\n")


def _rows(buf: io.StringIO, first: np.ndarray, table: np.ndarray, fmt: str) -> None:
    np.savetxt(buf, np.column_stack([first, table]), fmt=fmt, delimiter=", ")


def deck_text(model: ShellModel, plies: dict[int, Lamina], pressure: float, title: str) -> str:
    """The deck of a shell model; plies: each layer's (1-based) Lamina."""
    buf = io.StringIO()
    buf.write(f"*HEADING\n{abaqus_text(title)}\n** winder: shell model of the wound laminate (docs/math/09-structure.md 9.5)\n")
    n, e = model.nodes.shape[0], model.elements.shape[0]
    buf.write("*NODE, NSET=NALL\n")
    _rows(buf, np.arange(1, n + 1), model.nodes, "%d, " + ", ".join([NUM] * 3))
    buf.write("*ELEMENT, TYPE=S8R, ELSET=EALL\n")
    np.savetxt(buf, np.column_stack([np.arange(1, e + 1), model.elements + 1]), fmt="%d", delimiter=", ")
    for name, ids in (("START", model.fixed_axial), ("MIDA", model.rings[0]), ("MIDB", model.rings[1])):
        buf.write(f"*NSET, NSET={name}\n")
        np.savetxt(buf, (np.sort(ids) + 1).reshape(-1, 1), fmt="%d")
    buf.write("*ELSET, ELSET=MERIDIAN\n")  # the elements read back along the mandrel (winder analyze)
    np.savetxt(buf, (model.meridian + 1).reshape(-1, 1), fmt="%d")
    buf.write("*ELSET, ELSET=PRESSED\n")  # the pressure's elements: all but a boss's flange zones
    np.savetxt(buf, (np.nonzero(model.pressed)[0] + 1).reshape(-1, 1), fmt="%d")
    for k, (ids, ref, rot) in enumerate(model.rigid):  # a polar boss: rigid, the laminate on its flange bonded
        buf.write(f"*NSET, NSET=BOSS{k + 1}\n")
        np.savetxt(buf, (ids + 1).reshape(-1, 1), fmt="%d")
        buf.write(f"*RIGID BODY, NSET=BOSS{k + 1}, REF NODE={ref + 1}, ROT NODE={rot + 1}\n")
    for layer in sorted(set(model.ply_layer.tolist())):
        buf.write(_material(f"PLY{layer}", plies[layer]))
    present = model.ply_thickness > 0.0
    number = np.arange(1, e + 1)
    for c in range(present.shape[1]):  # orientations first: the sections name them
        k = np.nonzero(present[:, c])[0]
        np.savetxt(buf, np.column_stack([number[k], np.full(k.size, c + 1), model.fiber[k, c], model.across[k, c]]),
                   fmt="*ORIENTATION, NAME=O%d_%d, SYSTEM=RECTANGULAR\n" + ", ".join(["%.9f"] * 6))
    # one section per element, written a group of elements with the same plies at a time
    masks, group = np.unique(present, axis=0, return_inverse=True)
    for g, mask in enumerate(masks):
        k = np.nonzero(group.ravel() == g)[0]
        cols = np.nonzero(mask)[0]
        fmt = "*ELSET, ELSET=E%d\n%d\n*SHELL SECTION, ELSET=E%d, COMPOSITE, OFFSET=-0.5" + "".join(
            f"\n%.6f, , PLY{model.ply_layer[c]}, O%d_{c + 1}" for c in cols)
        table = [number[k]] * 3
        for c in cols:
            table += [model.ply_thickness[k, c], number[k]]
        np.savetxt(buf, np.column_stack(table), fmt=fmt)
    buf.write("*BOUNDARY\nSTART, 3, 3, 0.\n" + "".join(f"{n + 1}, 1, 1, 0.\n" for n in model.fixed_x)
              + "".join(f"{n + 1}, 2, 2, 0.\n" for n in model.fixed_y))
    buf.write("*STEP\n*STATIC\n")
    if pressure:
        buf.write(f"*DLOAD\nPRESSED, P, {pressure:.9g}\n")
    loaded = np.nonzero(np.any(model.loads != 0.0, axis=1))[0]
    if loaded.size:
        buf.write("*CLOAD\n")
        ids = np.repeat(loaded + 1, 3)
        dof = np.tile([1, 2, 3], loaded.size)
        val = model.loads[loaded].ravel()
        keep = val != 0.0
        np.savetxt(buf, np.column_stack([ids[keep], dof[keep], val[keep]]), fmt=["%d", "%d", NUM], delimiter=", ")
    buf.write("*NODE FILE\nU\n*EL FILE\nS, E\n*NODE PRINT, NSET=MIDA\nU\n*NODE PRINT, NSET=MIDB\nU\n"
              "*EL PRINT, ELSET=MERIDIAN\nS, E\n*END STEP\n")
    return buf.getvalue()


def export(plan, job) -> str:
    """The registry's entry (winder.export.registry)."""
    require_analysis(job)
    laminae = check_analysis(job)
    model = job_model(plan, job)
    return deck_text(model, {int(k): laminae[int(k) - 1] for k in set(model.ply_layer.tolist())}, job.analysis.pressure,
                     job.name)


def job_model(plan, job, refine: float = 1.0, ntheta: int = NTHETA) -> ShellModel:
    """The shell model of a planned job with an `analysis:` section (ExportError without a laminate)."""
    rows = layer_rows(plan, every_cell=True)
    if not rows:
        raise ExportError("no layer lays a laminate: no shell model", file=job.source)
    case = job.analysis
    return build_model(plan.surface, rows, plan.band_width, case.pressure, case.ends == "closed", case.axial_force,
                       case.torque, refine, ntheta, bosses=is_vessel(plan.surface))
