"""What the planner produces: fiber passes grouped in layers (the exporters' input).

Every array is plain numpy; shapes in the docstrings. Angles are radians inside arrays named
theta, degrees in fields named *_deg (the user-facing convention).
"""

from __future__ import annotations

import dataclasses
from enum import Enum
from typing import TYPE_CHECKING

import numpy as np

from winder.config.winding import LayerType
from winder.geometry.surface import SurfaceEval, SweepSurface
from winder.geometry.measure import row_norms

if TYPE_CHECKING:  # the laminate record builds on this module
    from winder.winding.wall import LayerLaminate


class PassKind(Enum):
    FORWARD = "forward"  # t increasing (+alpha band)
    RETURN = "return"  # t decreasing (-alpha band)
    DWELL = "dwell"  # at an end of an open mandrel: the mandrel turns, the fiber on a parallel
    TURNAROUND = "turnaround"  # past the winding region: the fiber turns toward the parallel and back
    HOOP = "hoop"  # a hoop traverse


@dataclasses.dataclass(frozen=True, eq=False)
class FiberPass:
    """One stretch of fiber, laid in winding order.

    t, s, theta : (m,) float: axial station (mm), internal station, unwrapped angle (rad), continuous
        from the previous pass of the same layer.
    points : (m, 3) float, mandrel-frame xyz (mm).
    direction : (m, 3) float, unit fiber direction in the laying order (toward the part not yet laid).
    alpha_deg : (m,) float, signed winding angle from the meridian, (-90, 90]: +alpha on forward
        passes, -alpha on return passes (see winding_angle_deg).
    """

    layer: int  # 1-based
    circuit: int  # 1-based; hoop traverses count as circuits
    number: int  # 1-based index of the pass within its layer, in winding order
    kind: PassKind
    t: np.ndarray
    s: np.ndarray
    theta: np.ndarray
    points: np.ndarray
    direction: np.ndarray
    alpha_deg: np.ndarray
    length: float  # mm


@dataclasses.dataclass(frozen=True, eq=False)
class Coverage:
    """Coverage of a layer at stations along its winding region (docs/math/05-winding.md).

    stations : (k,) float, the t where it was measured.
    covered_fraction : covered perimeter / perimeter, the least over the stations.
    max_gap_mm : the widest uncovered stretch along the perimeter. max_overlap_mm : the widest stretch
        of one band that others of the same direction also cover (at most a band's width along the
        perimeter; winder.winding.bands).
    min_layers, max_layers : band layers over any perimeter point (a +-alpha layer is 2 where even).
    """

    stations: np.ndarray
    covered_fraction: float
    max_gap_mm: float
    max_overlap_mm: float
    min_layers: int
    max_layers: int


@dataclasses.dataclass(frozen=True)
class LayerPlan:
    """A planned layer.

    angle_deg : the winding angle laid at the reference section (after any pattern adjustment);
        requested_angle_deg the config's. circuits N_c, pattern k (circuit advance 2 pi k / N_c).
    dwell_start_deg, dwell_end_deg : mandrel turn at each end of an open mandrel per circuit.
    turnaround_radius : vessels: the Clairaut constant c where the fiber turns on the domes (mm); where
        friction turns each dome at its own radius, their mean, and turnaround_radii each (first, end).
    alpha_min_deg, alpha_max_deg : range of the winding angle (folded to [0, 90]) over the wound
        passes, their ends included (turnarounds and dwells left out).
    time_s : estimated winding time at the machine feed.
    max_slip : largest |k_g / k_n| the layer's fibers need; min_normal_curvature : least k_n (1/mm, > 0:
        every fiber presses), both measured from the passes' points (winder.winding.slip).
    """

    index: int
    type: LayerType
    angle_deg: float
    requested_angle_deg: float
    circuits: int
    pattern: int
    dwell_start_deg: float
    dwell_end_deg: float
    turnaround_radius: float | None
    fiber_length_mm: float
    alpha_min_deg: float
    alpha_max_deg: float
    time_s: float
    passes: tuple[FiberPass, ...]
    coverage: Coverage
    notes: tuple[str, ...] = ()
    max_slip: float = 0.0
    min_normal_curvature: float = float("nan")
    surface: SweepSurface | None = None  # the (grown) mandrel it was wound on; None: the plan's
    laminate: LayerLaminate | None = None  # what it adds to the wall (a job with a material)
    max_lift_off_mm: float = 0.0  # largest lift-off of its fiber over a concave stretch (docs/math 8.10)
    lift_off_t: float = 0.0  # where: station t (mm) and pass number
    lift_off_pass: int = 0
    turnaround_radii: tuple[float, float] | None = None  # vessels: (first dome, end dome) radii (mm)

    @property
    def angle_change_deg(self) -> float:
        return self.angle_deg - self.requested_angle_deg


@dataclasses.dataclass(frozen=True)
class WindingPlan:
    """A whole job's plan: the mandrel surface and its layers in winding order, and the band width
    (mm) they were laid with (None for a plan built by hand without one)."""

    name: str
    source: str
    surface: SweepSurface
    layers: tuple[LayerPlan, ...]
    band_width: float | None = None
    outer: SweepSurface | None = None  # the mandrel grown by every layer (a laminate); None: surface

    @property
    def total_fiber_length_mm(self) -> float:
        return float(sum(layer.fiber_length_mm for layer in self.layers))

    @property
    def total_time_s(self) -> float:
        return float(sum(layer.time_s for layer in self.layers))

    @property
    def outer_surface(self) -> SweepSurface:
        """The finished part's surface: what the payout eye must clear."""
        return self.outer if self.outer is not None else self.surface

    def surface_of(self, layer: int) -> SweepSurface:
        """The surface layer `layer` (1-based) was wound on: the mandrel grown by the layers below, the
        part as wound so far, which the payout eye must clear while this layer is wound (on a vessel's
        domes the pile-ups stand as laid, past the bosses' planes: docs/math/17 17.8; its t runs over
        [t_start, axial_length])."""
        own = self.layers[layer - 1].surface
        return own if own is not None else self.surface


HOOP_SLOPE = 1e-12  # |meridian component| / |circumferential| below this: the fiber runs on a parallel


def winding_angle_deg(surface: SweepSurface, s: np.ndarray, theta: np.ndarray,
                      direction: np.ndarray) -> np.ndarray:
    """Signed winding angle (deg, (-90, 90]) of fiber directions (m, 3) from the meridian.

    Magnitude: the angle between the fiber line and the meridian (direction of increasing t). Sign:
    + where theta increases with t (a forward pass with the mandrel turning +), - where it decreases
    (the return pass of the same circuit): the +alpha / -alpha of a winding engineer. A fiber along
    a parallel (a dwell, the turn of a hoop, within HOOP_SLOPE) has no t direction to follow: its
    sign is that of the mandrel's turn, and every plan turns the mandrel toward +theta, so it reads
    +90 whatever the round-off in its meridian component.
    """
    return winding_angle_of(surface.evaluate(s, theta, order=1), direction)


def winding_angle_of(ev: SurfaceEval, direction: np.ndarray) -> np.ndarray:
    """winding_angle_deg from the surface's first derivatives at the points (an evaluation of order >= 1)."""
    e_s = ev.ps / row_norms(ev.ps)[:, None]
    e_t = ev.pt - np.einsum("ij,ij->i", ev.pt, e_s)[:, None] * e_s
    e_t /= row_norms(e_t)[:, None]
    v_s = np.einsum("ij,ij->i", direction, e_s)
    v_t = np.einsum("ij,ij->i", direction, e_t)
    magnitude = np.degrees(np.arctan2(np.abs(v_t), np.abs(v_s)))
    alpha = np.where(v_s * v_t < 0.0, -magnitude, magnitude)
    return np.where(np.abs(v_s) <= HOOP_SLOPE * np.abs(v_t), 90.0, alpha)
