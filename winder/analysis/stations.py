"""The laminate at every station of the layup (docs/math/09-structure.md 9.2-9.4): membrane loads, ABD,
ply strains and stresses, first-ply failure (Tsai-Wu, maximum stress) and netting, vectorized over
stations and plies. Surfaces of revolution (a straight axis, circular sections); others have no
membrane closed form here (the shell model of `--format abaqus` covers them).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from winder.analysis.clt import abd, membrane_strains, ply_response, reduced_stiffness, rotated_stiffness
from winder.analysis.failure import max_stress_index, max_stress_pressure, tsai_wu_index, tsai_wu_pressure
from winder.analysis.layup import LayerRows
from winder.analysis.loads import LoadCase, StationGeometry, resultants, revolution_geometry
from winder.analysis.materials import Lamina, NettingAllowable
from winder.analysis.netting import NettingLimits, Wall, limits


@dataclasses.dataclass(frozen=True)
class StationAnalysis:
    """Per station (n) and layer (L, the layup's layers in order).

    geometry : the inner face there. layers : the layers' 1-based indices (L,). thickness, angle_deg :
    (n, L) each layer's (0 where absent). a, b, d : (n, 3, 3) ABD. strain_per_mpa : (n, 3) membrane strains
    [m, h, mh] per MPa of pressure; strain_held : (n, 3) from the axial force and torque. ply_stress : (n, P, 3)
    ply-axis stresses at the design pressure; ply_layer : (P,) each ply's layer position (0..L-1).
    tsai_wu, max_stress : (n, L) the least failure pressure (MPa) over each layer's plies (inf: none);
    tsai_wu_index, max_stress_index : (n, L) at the design pressure (nan where the layer is absent).
    netting : limits per station; netting_applies : (n,) bool (9.2: not inside a vessel's boss zone).
    """

    geometry: StationGeometry
    layers: np.ndarray
    thickness: np.ndarray
    angle_deg: np.ndarray
    a: np.ndarray
    b: np.ndarray
    d: np.ndarray
    strain_per_mpa: np.ndarray
    strain_held: np.ndarray
    ply_stress: np.ndarray
    ply_layer: np.ndarray
    tsai_wu: np.ndarray
    max_stress: np.ndarray
    tsai_wu_index: np.ndarray
    max_stress_index: np.ndarray
    netting: NettingLimits
    netting_applies: np.ndarray


def surface_geometry(surface, t: np.ndarray) -> StationGeometry:
    """The inner face's StationGeometry at stations t (n,) of a surface of revolution."""
    s = surface.s_of_t(t)
    ev = surface.evaluate(s, np.zeros_like(s), order=2)
    p, ps, pss = ev.p, ev.ps, ev.pss
    r = np.hypot(p[:, 0], p[:, 1])
    u = p[:, :2] / r[:, None]  # the radial unit vector
    return revolution_geometry(t, r, np.einsum("ij,ij->i", ps[:, :2], u), ps[:, 2],
                               np.einsum("ij,ij->i", pss[:, :2], u), pss[:, 2])


def analysis_stations(rows: tuple[LayerRows, ...]) -> np.ndarray:
    """Every layer's row stations, merged (sorted, unique to the CSV's 6 decimals)."""
    return np.unique(np.round(np.concatenate([r.t for r in rows]), 6))


def analyze_stations(surface, rows: tuple[LayerRows, ...], plies: tuple[Lamina, ...],
                     allowables: tuple[NettingAllowable, ...], case: LoadCase, boss_radius: float = 0.0) -> StationAnalysis:
    """The analysis at every layup station. plies : each layer's Lamina (same order as rows); allowables :
    their netting allowables; boss_radius : on a vessel, netting applies at r >= it (0: everywhere)."""
    t = analysis_stations(rows)
    geo = surface_geometry(surface, t)
    at = [r.at(t) for r in rows]
    angle = np.column_stack([a for a, _ in at])
    thick = np.column_stack([h for _, h in at])
    # plies from the inner face out: a helical layer +a then -a (t/2 each), a hoop one ply
    ply_layer = np.concatenate([[k, k] if r.helical else [k] for k, r in enumerate(rows)]).astype(int)
    sign = np.concatenate([[1.0, -1.0] if r.helical else [1.0] for r in rows])
    share = np.concatenate([[0.5, 0.5] if r.helical else [1.0] for r in rows])
    ply_angle = np.radians(angle[:, ply_layer]) * sign
    ply_t = thick[:, ply_layer] * share
    q = np.stack([reduced_stiffness(plies[k]) for k in ply_layer])  # (P, 3, 3)
    a, b, d = abd(rotated_stiffness(q[None], ply_angle), ply_t)
    per_p, held = resultants(geo, case)
    laid = ply_t.sum(axis=1) > 0.0
    eps_p, eps_0 = np.zeros_like(per_p), np.zeros_like(held)
    safe_a = np.where(laid[:, None, None], a, np.eye(3))
    eps_p[laid] = membrane_strains(safe_a, per_p)[laid]
    eps_0[laid] = membrane_strains(safe_a, held)[laid]
    _, s_p = ply_response(eps_p, ply_angle, q[None])
    _, s_0 = ply_response(eps_0, ply_angle, q[None])
    strengths = tuple(np.array([getattr(plies[k], key) for k in ply_layer]) for key in ("Xt", "Xc", "Yt", "Yc", "S"))
    present = ply_t > 0.0
    tw = np.where(present, tsai_wu_pressure(s_p, s_0, strengths), np.inf)
    ms = np.where(present, max_stress_pressure(s_p, s_0, strengths), np.inf)
    stress = case.pressure * s_p + s_0
    tw_i = np.where(present, tsai_wu_index(stress, strengths), np.nan)
    ms_i = np.where(present, max_stress_index(stress, strengths), np.nan)
    n_layers = len(rows)
    by_layer = [np.full((t.size, n_layers), np.inf), np.full((t.size, n_layers), np.inf),
                np.full((t.size, n_layers), np.nan), np.full((t.size, n_layers), np.nan)]
    for k in range(n_layers):
        mine = ply_layer == k
        by_layer[0][:, k] = tw[:, mine].min(axis=1)
        by_layer[1][:, k] = ms[:, mine].min(axis=1)
        with np.errstate(all="ignore"):
            by_layer[2][:, k] = np.nanmax(np.where(present[:, mine], tw_i[:, mine], -np.inf), axis=1)
            by_layer[3][:, k] = np.nanmax(np.where(present[:, mine], ms_i[:, mine], -np.inf), axis=1)
    for arr in by_layer[2:]:
        arr[~np.isfinite(arr)] = np.nan
    wall = Wall(angle=np.radians(angle), thickness=thick, helical=np.array([r.helical for r in rows]),
                modulus=np.array([p.E1 for p in plies]), tension=np.array([a.composite for a in allowables]),
                compression=np.array([a.composite_compression for a in allowables]))
    net = limits(wall, per_p, held)
    applies = laid & (geo.r >= boss_radius)
    return StationAnalysis(geo, np.array([r.index for r in rows]), thick, angle, a, b, d, eps_p, eps_0, stress,
                           ply_layer, by_layer[0], by_layer[1], by_layer[2], by_layer[3], net, applies)
