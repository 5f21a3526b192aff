"""Laminate math (docs/math/08-laminate-edges.md): a band's material, ply thickness, masses, and the thickness a layer
builds along the mandrel.

Units: lengths in mm, tex in g/km (= 1e-6 g/mm), densities in g/cm^3 (= 1e-3 g/mm^3), masses in kg.

Thickness along the mandrel is carried as a fiber volume density: V'(s), the composite volume laid
per unit of meridian arc length s (mm^3/mm), and the per-station mean thickness is V'(s) / A'(s),
A'(s) the surface area per unit s (2 pi r on a unit-speed meridian). Working with V' keeps every
step volume-conserving by construction:
- a band of composite area a crossing the station with ds/dl = cos(alpha) adds a / cos(alpha);
- on a surface of revolution every geodesic pass keeps r sin(alpha) = c, so n crossings give
  V' = n a r / sqrt(r^2 - c^2) and t(r) = n a / (2 pi sqrt(r^2 - c^2)), i.e. the fiber-count law
  t(r) = t(R) R cos(alpha_R) / (r cos(alpha_r));
- at a turnaround (r -> c) that diverges; the band there lies along the parallel and spans one band
  width B of meridian, so the volume within B/2 of the turnaround is spread evenly over
  [s_c - B/2, s_c + B/2] (turnaround_zone). For V' ~ 1/sqrt(s - s_c) this mean equals the law's
  value at the zone's outer edge, so the spread meets the law there to leading order.
The grown mandrel winds on a smooth (C2) version of the thickness: smooth_density convolves V' with a
compact C2 kernel one band wide, which also keeps the total volume.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from winder.config.material import MaterialConfig

TEX_G_PER_MM = 1e-6  # 1 tex = 1 g/km
DENSITY_G_PER_MM3 = 1e-3  # 1 g/cm^3
KG_PER_G = 1e-3


@dataclasses.dataclass(frozen=True)
class Material(MaterialConfig):
    """A band's material (the fields of MaterialConfig) and what follows from it: areas, ply
    thickness, masses. Either fiber_tex, tows, fiber_density and fiber_volume_fraction
    (resin_density for the resin mass), or ply_thickness (mm per band; with the densities and the
    volume fraction for masses).
    """

    @property
    def has_masses(self) -> bool:
        """Whether fiber and resin masses follow from the material (densities and V_f given)."""
        return self.fiber_density is not None and self.fiber_volume_fraction is not None

    def fiber_area(self, band_width: float) -> float:
        """Fiber cross-section of one band (mm^2): tows tex / (1000 rho_f), or V_f t_p B."""
        if self.fiber_tex is not None:
            return self.tows * self.fiber_tex / (1000.0 * self.fiber_density)
        if self.fiber_volume_fraction is None:
            raise ValueError("a ply_thickness material needs fiber_volume_fraction for the fiber area")
        return self.fiber_volume_fraction * self.ply_thickness * band_width

    def composite_area(self, band_width: float) -> float:
        """Composite (fiber and resin) cross-section of one band (mm^2): fiber area / V_f, or t_p B."""
        if self.ply_thickness is not None:
            return self.ply_thickness * band_width
        return self.fiber_area(band_width) / self.fiber_volume_fraction

    def ply(self, band_width: float) -> float:
        """Ply thickness t_p (mm): the composite area spread over the band width."""
        return self.composite_area(band_width) / band_width

    def fiber_mass_kg(self, fiber_length_mm: float, band_width: float) -> float:
        """Fiber mass of a band length (kg): length tows tex 1e-6 g/mm, or length area rho_f."""
        if self.fiber_tex is not None:
            grams = fiber_length_mm * self.tows * self.fiber_tex * TEX_G_PER_MM
        else:
            if not self.has_masses:
                return float("nan")
            grams = fiber_length_mm * self.fiber_area(band_width) * self.fiber_density * DENSITY_G_PER_MM3
        return grams * KG_PER_G

    def resin_mass_kg(self, fiber_length_mm: float, band_width: float) -> float:
        """Resin mass (kg): fiber mass (1 - V_f) / V_f rho_r / rho_f."""
        if not self.has_masses or self.resin_density is None:
            return float("nan")
        vf = self.fiber_volume_fraction
        return (self.fiber_mass_kg(fiber_length_mm, band_width) * (1.0 - vf) / vf
                * self.resin_density / self.fiber_density)

    def material_length_mm(self, fiber_length_mm: float) -> float:
        """Length of tow drawn from the creel (mm): band length times tows (one tow if unknown)."""
        return fiber_length_mm * (self.tows or 1)


# -- closed forms (cylinders) -----------------------------------------------------------------------
def helical_mean_thickness(ply: float, circuits: int, band_width: float, radius: float,
                           alpha: float) -> float:
    """Mean thickness (mm) of a +-alpha helical layer of N_c circuits on a cylinder of radius R.

    2 t_p N_c B / (2 pi R cos(alpha)): two plies where the circuits tile the perimeter once, with the
    overlap counted. alpha in radians.
    """
    return 2.0 * ply * circuits * band_width / (2.0 * math.pi * radius * math.cos(alpha))


def hoop_mean_thickness(ply: float, band_width: float, perimeter: float, pitch: float) -> float:
    """Mean thickness (mm) of one hoop traverse advancing `pitch` per turn around `perimeter`.

    The band is laid along a helix of length sqrt(P^2 + p^2) per turn and p of axis: t_p B sqrt(P^2 +
    p^2) / (p P). At the tiling pitch p = P B / sqrt(P^2 - B^2) that is exactly t_p.
    """
    return ply * band_width * math.hypot(perimeter, pitch) / (pitch * perimeter)


def clairaut_density(r: np.ndarray, c: float, crossings: int, area: float) -> np.ndarray:
    """V'(s) (mm^3/mm) of `crossings` geodesic passes of Clairaut constant c on a surface of
    revolution with unit-speed meridian: n a r / sqrt(r^2 - c^2) where r > c, 0 inside the
    turnaround. r : (m,) float. Infinite at r = c: see turnaround_zone."""
    r = np.asarray(r, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = crossings * area * r / np.sqrt((r - c) * (r + c))
    return np.where(r > c, v, 0.0)


def clairaut_zone_volume(r_of_s, s_c: float, s_edge: float, c: float, crossings: int, area: float,
                         nodes: int = 64) -> float:
    """Exact volume (mm^3) the passes lay between the turnaround station s_c (r(s_c) = c) and s_edge.

    integral of n a r / sqrt(r^2 - c^2) ds; the substitution s = s_c + (s_edge - s_c)(1 - cos tau)
    removes the inverse square root at s_c (Gauss-Legendre in tau). r_of_s : vectorized r(s).
    """
    x, w = np.polynomial.legendre.leggauss(nodes)
    tau = 0.25 * np.pi * (x + 1.0)
    span = s_edge - s_c
    s = s_c + span * (1.0 - np.cos(tau))
    r = np.asarray(r_of_s(s), dtype=float)
    f = crossings * area * r / np.sqrt(np.maximum((r - c) * (r + c), 1e-300)) * abs(span) * np.sin(tau)
    return 0.25 * np.pi * float(f @ w)


def turnaround_zone(s: np.ndarray, density: np.ndarray, s_c: float, band_width: float,
                    zone_volume: float) -> np.ndarray:
    """Spread the volume laid within B/2 of a turnaround evenly over the band it makes there.

    s : (m,) float, uniform stations; density : (m,) float, V'(s) of the passes (infinite or
    unresolved next to s_c). s_c : the turnaround station. zone_volume : the exact volume the passes
    lay within B/2 of s_c on the fibered side (clairaut_zone_volume, or from the laid lengths).
    Returns V' with the zone [s_c - B/2, s_c + B/2] replaced by zone_volume / B (clipped to the
    station range, the volume still conserved). Cell fractions are exact, so the zone holds
    zone_volume whatever the grid (summing V' ds over the cells).
    """
    s = np.asarray(s, dtype=float)
    out = np.asarray(density, dtype=float).copy()
    ds = s[1] - s[0]
    lo, hi = s_c - 0.5 * band_width, s_c + 0.5 * band_width
    lo, hi = max(lo, s[0] - 0.5 * ds), min(hi, s[-1] + 0.5 * ds)
    # cell k covers [s_k - ds/2, s_k + ds/2]; its overlap with the zone and with the half on the fiber
    left, right = s - 0.5 * ds, s + 0.5 * ds
    in_zone = np.clip(np.minimum(right, hi) - np.maximum(left, lo), 0.0, ds) / ds
    # inside the zone the law's (divergent) values give way to the spread; cells cut by the zone's
    # edge keep their law volume on the outer part
    out *= 1.0 - in_zone
    out += in_zone * (zone_volume / ((hi - lo) if hi > lo else ds))
    return out


# -- smoothing for the grown mandrel --------------------------------------------------------------
def _kernel(half_width: float, ds: float) -> np.ndarray:
    """Discrete triweight kernel (1 - x^2)^3 on [-1, 1] (C2 with compact support), summing to 1."""
    k = max(1, int(math.ceil(half_width / ds)))
    x = np.arange(-k, k + 1) * ds / half_width
    w = np.clip(1.0 - x * x, 0.0, None) ** 3
    return w / w.sum()


def smooth_density(s: np.ndarray, density: np.ndarray, half_width: float,
                   mirror: tuple[bool, bool] = (False, False)) -> np.ndarray:
    """V' convolved with a C2 kernel of the given half-width (uniform stations s, (m,) float).

    A band cannot follow a shape narrower than itself, and the next layer's geodesics need a smooth
    mandrel. mirror[i]: reflect the density evenly at that end (an equator, where the thickness
    continues into the cylinder with zero slope) rather than pad it with zeros (a polar opening or an
    open end: no fiber beyond). The total volume is kept except what a zero-padded end sheds.
    """
    s = np.asarray(s, dtype=float)
    v = np.asarray(density, dtype=float)
    if s.size < 3:
        return v.copy()
    w = _kernel(half_width, s[1] - s[0])
    k = w.size // 2
    pad_lo = v[1:k + 1][::-1] if mirror[0] else np.zeros(k)
    pad_hi = v[-k - 1:-1][::-1] if mirror[1] else np.zeros(k)
    if pad_lo.size < k:  # a range shorter than the kernel
        pad_lo = np.concatenate([np.zeros(k - pad_lo.size), pad_lo])
    if pad_hi.size < k:
        pad_hi = np.concatenate([pad_hi, np.zeros(k - pad_hi.size)])
    return np.convolve(np.concatenate([pad_lo, v, pad_hi]), w, mode="valid")


# -- the band-spread cubic at a turnaround (docs/math/08-laminate-edges.md 8.6) -----------------------
SPREAD_INNER = 0.5  # band widths from the turnaround to the band's inner edge (no fiber beyond)
SPREAD_OUTER = 2.0  # band widths from the turnaround to where the fiber-count law holds again
SPREAD_NODES = 8  # Gauss-Legendre nodes per cell for the cubic's cell means


def spread_coefficients(d1: float, e: float, m: float) -> tuple[float, float, float]:
    """(a1, a2, a3) of p(x) = a1 x + a2 x^2 + a3 x^3 with p(1) = d1, p'(1) = e and mean m over [0, 1]
    (p(0) = 0): the closed form of docs/math 8.6."""
    return 12.0 * m - 6.0 * d1 + e, 15.0 * d1 - 24.0 * m - 3.0 * e, 12.0 * m - 8.0 * d1 + 2.0 * e


def band_spread(s: np.ndarray, widths: np.ndarray, density: np.ndarray, s_c: float, band_width: float,
                toward: float, r_of_s) -> np.ndarray:
    """V' with the zone [-B/2, 2B] (in u = toward (s - s_c)) of a turnaround replaced by the cubic of
    docs/math 8.6: zero at the band's inner edge, the law's value and slope at u = 2B, the zone's volume
    kept.

    s, widths, density : (k,) float, the cells (centres, widths) of one smooth piece and V' there.
    toward : +1 where the fiber lies at s > s_c (the equator that way), -1 otherwise.
    r_of_s : vectorized r(s) of the meridian. Returns (k,) float; the volume over the cells is kept.
    """
    s, w, d = (np.asarray(a, dtype=float) for a in (s, widths, density))
    lo_edge, hi_edge = s[0] - 0.5 * w[0], s[-1] + 0.5 * w[-1]
    u_end = SPREAD_OUTER * band_width
    # the zone in s, clipped to the piece (a short dome: the law's end at its equator)
    z0, z1 = sorted((s_c - toward * SPREAD_INNER * band_width, s_c + toward * u_end))
    z0, z1 = max(z0, lo_edge), min(z1, hi_edge)
    if z1 - z0 <= 0.0:
        return d.copy()
    left, right = s - 0.5 * w, s + 0.5 * w
    overlap = np.clip(np.minimum(right, z1) - np.maximum(left, z0), 0.0, None)
    v_zone = float(np.sum(d / w * w * overlap))  # V' is constant within a cell
    s_end = z1 if toward > 0 else z0  # u = 2B (or the piece's end)
    s_start = z0 if toward > 0 else z1  # the band's inner edge (or the piece's end)
    length = abs(s_end - s_start)
    d1 = float(np.interp(s_end, s, d))
    r_end, c = (float(v) for v in r_of_s(np.array([s_end, s_c])))
    h = 1e-3 * band_width
    r_u = toward * float(np.diff(r_of_s(np.array([s_end - h, s_end + h])))[0]) / (2.0 * h)
    q = r_end * r_end - c * c
    if q > 0.0 and d1 > 0.0:
        k = d1 * np.sqrt(q) / r_end  # the law K r / sqrt(r^2 - c^2) through the cell's value
        slope = -k * c * c * r_u / q ** 1.5
    else:
        slope = 0.0
    a1, a2, a3 = spread_coefficients(d1, length * slope, v_zone / length)
    # each cell's mean of p over its overlap with the zone (Gauss-Legendre), p clipped at 0
    xg, wg = np.polynomial.legendre.leggauss(SPREAD_NODES)
    a, b = np.maximum(left, z0), np.minimum(right, z1)
    pts = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * xg[None, :]
    x = np.clip(toward * (pts - s_start) / length, 0.0, 1.0)
    p = np.clip(((a3 * x + a2) * x + a1) * x, 0.0, None)
    vol = 0.5 * overlap * (p @ wg)
    if vol.sum() > 0.0:
        vol *= v_zone / vol.sum()
    return d * (1.0 - overlap / w) + vol / w
