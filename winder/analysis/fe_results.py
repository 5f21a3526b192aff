"""CalculiX's results read back (docs/math/09-structure.md 9.9): the `.dat` file's stresses and strains at
the integration points of the elements along one meridian (the deck's *EL PRINT, ELSET=MERIDIAN), each
ply's mean in its own axes (1 the fiber, 2 across it in the shell, 12 the in-plane shear; the shear's
sign turned to the CLT's frame, winder.analysis.shell_model), and its failure index.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np

from winder.analysis.failure import max_stress_index, tsai_wu_index
from winder.errors import SolverError

_BLOCK = re.compile(r"^ (stresses|strains) \(elem, integ\.pnt\.,[^\n]*\n", re.MULTILINE)


@dataclasses.dataclass(frozen=True, kw_only=True)
class MeridianResults:
    """The FE answer along the meridian: t (m,) each element's station; ply_layer (P,) each slot's layer
    (1-based); present (m, P); stress, strain (m, P, 3) each ply's mean [1, 2, 12] (MPa; engineering
    strain) in the CLT's frame; tsai_wu, max_stress (m, P) failure indices (nan where absent)."""

    t: np.ndarray
    ply_layer: np.ndarray
    present: np.ndarray
    stress: np.ndarray
    strain: np.ndarray
    tsai_wu: np.ndarray
    max_stress: np.ndarray

    def by_layer(self, values: np.ndarray, layer: int) -> np.ndarray:
        """(m,) a layer's largest value over its plies (nan where it is absent)."""
        mine = self.ply_layer == layer
        laid = self.present[:, mine]
        out = np.where(laid, values[:, mine], -np.inf).max(axis=1, initial=-np.inf)
        return np.where(laid.any(axis=1), out, np.nan)


def integration_points(dat: str, kind: str) -> tuple[np.ndarray, np.ndarray]:
    """(element numbers (N,), values (N, 6)) of the .dat's `stresses` or `strains` block (the last step's);
    SolverError where the block is missing (the solve did not finish)."""
    heads = [m for m in _BLOCK.finditer(dat) if m.group(1) == kind]
    if not heads:
        raise SolverError(f"the CalculiX results have no {kind} of the meridian (did the solve finish?)")
    body = dat[heads[-1].end():]
    end = re.search(r"\n\s*\n\s*\S", body[2:])
    lines = body[: end.start() + 2 if end else len(body)].split("\n")
    rows = [ln.split()[:8] for ln in lines if ln.strip() and ln.split()[0].isdigit()]
    table = np.array(rows, dtype=float) if rows else np.zeros((0, 8))
    return table[:, 0].astype(int), table[:, 2:8]


def _ply_means(model, numbers: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(m, P, 6) each meridian element's ply means (the element's integration points split evenly over its
    present plies, inner first, as the composite section lists them)."""
    out = np.full((model.meridian.size, model.ply_layer.size, 6), np.nan)
    order = np.argsort(numbers, kind="stable")
    numbers, values = numbers[order], values[order]
    for row, element in enumerate(model.meridian):
        lo, hi = np.searchsorted(numbers, [element + 1, element + 2])
        slots = np.nonzero(model.ply_thickness[element] > 0.0)[0]
        if hi <= lo or (hi - lo) % slots.size:
            raise SolverError(f"the CalculiX results of element {element + 1} do not split over its {slots.size} "
                              "plies")
        out[row, slots] = values[lo:hi].reshape(slots.size, -1, 6).mean(axis=1)
    return out


def read_meridian(model, dat: str, strengths: dict[int, tuple]) -> MeridianResults:
    """The meridian's ply stresses, strains and failure indices from the .dat text of the model's solve;
    strengths : each layer's (Xt, Xc, Yt, Yc, S)."""
    s = _ply_means(model, *integration_points(dat, "stresses"))
    e = _ply_means(model, *integration_points(dat, "strains"))
    flip = np.array([1.0, 1.0, -1.0])  # CalculiX's local y is -across: the shear's sign turns over
    stress = s[..., [0, 1, 3]] * flip
    strain = e[..., [0, 1, 3]] * np.array([1.0, 1.0, 2.0]) * flip  # tensor to engineering shear
    present = model.ply_thickness[model.meridian] > 0.0
    cols = [np.array([strengths[int(k)][i] for k in model.ply_layer]) for i in range(5)]
    tw = np.where(present, tsai_wu_index(np.nan_to_num(stress), tuple(cols)), np.nan)
    ms = np.where(present, max_stress_index(np.nan_to_num(stress), tuple(cols)), np.nan)
    return MeridianResults(t=model.t[model.meridian], ply_layer=model.ply_layer, present=present, stress=stress,
                           strain=strain, tsai_wu=tw, max_stress=ms)
