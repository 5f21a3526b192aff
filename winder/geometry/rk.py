"""An explicit embedded Runge-Kutta integrator in numpy: Dormand and Prince's 8(5,3) pair.

The tableau is the one of Hairer, Norsett and Wanner, Solving ODEs I (2nd ed., II.5 and II.10): 12
stages for an 8th-order step (the 13th, f at the new point, is the next step's first), an error
estimate mixing the embedded 5th- and 3rd-order ones,

    err = |h| E5^2 / sqrt(n (E5^2 + 0.01 E3^2)),   E_p^2 = sum_i (e_p . k / sc_i)^2,
    sc_i = atol + rtol max(|y_i|, |y_new_i|),

and a 7th-order dense output from 3 more stages per step. It exists because importing
scipy.integrate costs half a second, far more than the few traces a job needs; results agree with
scipy's DOP853 (the same pair) to the tolerance asked (tests/geometry/test_rk.py,
tests/paths/test_friction_rk.py).

solve_rk speaks solve_ivp's vocabulary (t, y, sol, t_events, y_events, status, message, nfev,
success) for the calls winder makes: a scalar time, forward integration, terminal or recorded events
with a direction, located on the dense output between steps.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import field
from typing import Callable, Sequence

import numpy as np

from winder.geometry.roots import bracketed_root

SAFETY = 0.9  # of the step the error estimate asks for
MIN_FACTOR, MAX_FACTOR = 0.2, 10.0  # step change per step
ERROR_EXPONENT = -1.0 / 8.0  # the estimate's leading term is O(h^8)
STEP_FLOOR = 10.0  # steps below this many ulps of t fail
EVENT_XTOL = 4.0 * np.finfo(float).eps  # relative: event times are located to this
MESSAGES = {0: "The solver successfully reached the end of the integration interval.",
            1: "A termination event occurred.",
            -1: "Required step size is less than spacing between numbers."}

# -- the tableau (the published values, to double precision) ---------------------------------------
_C = np.array([0, 0.05260015195876773, 0.0789002279381516, 0.1183503419072274, 0.2816496580927726,
               0.3333333333333333, 0.25, 0.3076923076923077, 0.6512820512820513, 0.6, 0.8571428571428571, 1.0, 1.0,
               0.1, 0.2, 0.7777777777777778])
_A = [  # row i: a_i0 .. a_i,i-1; row 12 holds the weights b, rows 13..15 the dense output's stages
    [0.05260015195876773],
    [0.0197250569845379, 0.0591751709536137],
    [0.02958758547680685, 0, 0.08876275643042054],
    [0.2413651341592667, 0, -0.8845494793282861, 0.924834003261792],
    [0.037037037037037035, 0, 0, 0.17082860872947386, 0.12546768756682242],
    [0.037109375, 0, 0, 0.17025221101954405, 0.06021653898045596, -0.017578125],
    [0.03709200011850479, 0, 0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402, 0.008273789163814023],
    [0.6241109587160757, 0, 0, -3.3608926294469414, -0.868219346841726, 27.59209969944671, 20.154067550477894,
     -43.48988418106996],
    [0.47766253643826434, 0, 0, -2.4881146199716677, -0.590290826836843, 21.230051448181193, 15.279233632882423,
     -33.28821096898486, -0.020331201708508627],
    [-0.9371424300859873, 0, 0, 5.186372428844064, 1.0914373489967295, -8.149787010746927, -18.52006565999696,
     22.739487099350505, 2.4936055526796523, -3.0467644718982196],
    [2.273310147516538, 0, 0, -10.53449546673725, -2.0008720582248625, -17.9589318631188, 27.94888452941996,
     -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636],
    [0.054293734116568765, 0, 0, 0, 0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, 0.3111643669578199,
     -0.1521609496625161, 0.20136540080403034, 0.04471061572777259],
    [0.056167502283047954, 0, 0, 0, 0, 0, 0.25350021021662483, -0.2462390374708025, -0.12419142326381637,
     0.15329179827876568, 0.00820105229563469, 0.007567897660545699, -0.008298],
    [0.03183464816350214, 0, 0, 0, 0, 0.028300909672366776, 0.053541988307438566, -0.05492374857139099, 0, 0,
     -0.00010834732869724932, 0.0003825710908356584, -0.00034046500868740456, 0.1413124436746325],
    [-0.42889630158379194, 0, 0, 0, 0, -4.697621415361164, 7.683421196062599, 4.06898981839711, 0.3567271874552811,
     0, 0, 0, -0.0013990241651590145, 2.9475147891527724, -9.15095847217987],
]
_E5 = [  # b minus the embedded 5th-order weights
    0.01312004499419488, 0, 0, 0, 0, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864,
    -0.35032884874997366, 0.3341791187130175, 0.08192320648511571, -0.022355307863886294]
_B3 = [  # the embedded 3rd-order weights
    0.2440944881889764, 0, 0, 0, 0, 0, 0, 0, 0.7338466882816118, 0, 0, 0.022058823529411766]
_D = [  # the interpolant's 4 highest coefficients
    [-8.428938276109013, 0, 0, 0, 0, 0.5667149535193777, -3.0689499459498917, 2.38466765651207, 2.117034582445028,
     -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331, 18.148505520854727,
     -9.194632392478356, -4.436036387594894],
    [10.427508642579134, 0, 0, 0, 0, 242.28349177525817, 165.20045171727028, -374.5467547226902, -22.113666853125306,
     7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845, -31.139403219565178,
     -9.35292435884448, 35.81684148639408],
    [19.985053242002433, 0, 0, 0, 0, -387.0373087493518, -189.17813819516758, 527.8081592054236, -11.57390253995963,
     6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508, -60.19669523126412,
     84.32040550667716, 11.99229113618279],
    [-25.69393346270375, 0, 0, 0, 0, -154.18974869023643, -231.5293791760455, 357.6391179106141, 93.40532418362432,
     -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114, 96.32455395918828,
     -39.17726167561544, -149.72683625798564],
]


def _tableau():
    a = np.zeros((16, 16))
    for i, row in enumerate(_A, start=1):
        a[i, :i] = row
    return a, np.array(_E5), a[12, :12] - np.array(_B3), np.array(_D)


A, E5, E3, D = _tableau()
B = A[12, :12]
_A_ROWS = [A[i, :i].copy() for i in range(16)]  # contiguous rows: one small matmul per stage


class DenseOutput:
    """The 7th-order interpolant over the steps: call with t () -> (n,) or (m,) -> (n, m).

    Hairer's form per step [t_j, t_j + h_j], x = (t - t_j) / h_j, x1 = 1 - x:
    y = r1 + x (r2 + x1 (r3 + x (r4 + x1 (r5 + x (r6 + x1 (r7 + x r8)))))). Outside the steps the
    nearest step's polynomial extrapolates.
    """

    def __init__(self, t: np.ndarray, h: np.ndarray, coef: np.ndarray):
        self.t, self.h, self.coef = t, h, coef  # (k + 1,) step ends, (k,) steps, (k, 8, n)
        self.t_min, self.t_max = float(t[0]), float(t[-1])

    def __call__(self, t) -> np.ndarray:
        tt = np.asarray(t, dtype=float)
        flat = np.atleast_1d(tt)
        j = np.clip(np.searchsorted(self.t, flat, side="right") - 1, 0, self.h.size - 1)
        out = _horner(self.coef[j], ((flat - self.t[j]) / self.h[j])[:, None]).T
        return out[:, 0] if tt.ndim == 0 else out


def _horner(r: np.ndarray, x):
    """Hairer's nested form of r (..., 8, n) at x (broadcast to (..., n))."""
    x1 = 1.0 - x
    y = r[..., 7, :]
    for i in range(6, -1, -1):
        y = r[..., i, :] + (x if i % 2 == 0 else x1) * y
    return y


@dataclasses.dataclass(frozen=True, eq=False)
class RKResult:
    """solve_ivp's result fields. t : (m,) steps (the last a terminal event's time); y : (n, m);
    sol : DenseOutput or None; t_events, y_events : per event, (j,) and (j, n); status 0 (the end
    reached), 1 (a terminal event), -1 (failed); nfev : evaluations of fun; nreject : rejected steps."""

    t: np.ndarray
    y: np.ndarray
    sol: DenseOutput | None = field(repr=False)
    t_events: list[np.ndarray] | None
    y_events: list[np.ndarray] | None
    status: int
    message: str
    nfev: int
    nreject: int

    @property
    def success(self) -> bool:
        return self.status >= 0


def _first_step(fun, t0, y0, f0, span, rtol, atol) -> tuple[float, int]:
    """Hairer-Norsett-Wanner's starting step (II.4): one Euler probe bounds the second derivative."""
    sc = atol + rtol * np.abs(y0)
    d0, d1 = (float(np.sqrt(np.mean((v / sc) ** 2))) for v in (y0, f0))
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, span)
    f1 = np.asarray(fun(t0 + h0, y0 + h0 * f0), dtype=float)
    d2 = float(np.sqrt(np.mean(((f1 - f0) / sc) ** 2))) / h0
    big = max(d1, d2)
    h1 = max(1e-6, 1e-3 * h0) if big <= 1e-15 else (0.01 / big) ** (1.0 / 8.0)
    return min(100.0 * h0, h1, span), 1


def _crossed(g_old: float, g_new: float, direction: float) -> bool:
    up, down = g_old <= 0.0 <= g_new, g_old >= 0.0 >= g_new
    return (up and direction >= 0.0) or (down and direction <= 0.0)


def _attempt(fun, t: float, h: float, y: np.ndarray, k: np.ndarray, rtol: float, atol: float):
    """Stages 2..12 of a step of h from (t, y) (k[0] = f(t, y) set): the new y (n,) and the scaled error."""
    for i in range(1, 12):
        k[i] = fun(t + _C[i] * h, y + h * (_A_ROWS[i] @ k[:i]))
    y_new = y + h * (B @ k[:12])
    sc = atol + rtol * np.maximum(np.abs(y), np.abs(y_new))
    e5, e3 = (E5 @ k[:12]) / sc, (E3 @ k[:12]) / sc
    s5, s3 = float(e5 @ e5), float(e3 @ e3)
    den = s5 + 0.01 * s3
    err = abs(h) * s5 / math.sqrt(y.size * den) if den > 0.0 else 0.0
    return y_new, (err if math.isfinite(err) else math.inf)


def _roots(events: list, g_old: list[float], g_new: list[float], t: float, t_new: float,
           interpolant: Callable[[], Callable[[float], np.ndarray]]) -> list[tuple[float, int, np.ndarray]]:
    """(time, event index, y) of every event that changed sign over [t, t_new] the way it watches,
    located on the step's interpolant (built only when one did)."""
    hits = []
    for i, g in enumerate(events):
        if _crossed(g_old[i], g_new[i], float(getattr(g, "direction", 0.0))):
            at = interpolant()
            t_root = bracketed_root(lambda s, g=g: float(g(s, at(s))), t, t_new, rtol=0.0,
                                    xtol=EVENT_XTOL * max(abs(t), abs(t_new), 1.0), fa=g_old[i], fb=g_new[i])
            hits.append((t_root, i, at(t_root)))
    return sorted(hits, key=lambda hit: (hit[0], hit[1]))


def solve_rk(fun: Callable[[float, np.ndarray], Sequence[float]], t_span: tuple[float, float], y0, *,
             rtol: float = 1e-3, atol: float = 1e-6, dense_output: bool = False,
             events: Sequence[Callable[[float, np.ndarray], float]] | None = None,
             first_step: float | None = None, max_step: float = math.inf) -> RKResult:
    """Integrate y' = fun(t, y) (y (n,)) from t_span[0] to t_span[1] > t_span[0].

    Parameters
    ----------
    fun : (t, y (n,)) -> (n,) array-like.
    rtol, atol : the error each step keeps below, per component atol + rtol |y|.
    dense_output : build sol over every step (else only the steps an event was located in use it).
    events : g(t, y) -> float; attributes terminal (stop at the first root) and direction (+1: only
        g rising through zero, -1: falling, 0: both) as solve_ivp reads them.
    first_step, max_step : the first step (else chosen), the largest step.

    Returns
    -------
    RKResult; t (m,), y (n, m), t_events[i] (j_i,), y_events[i] (j_i, n).
    """
    t0, t_end = float(t_span[0]), float(t_span[1])
    if not t_end > t0:
        raise ValueError(f"solve_rk integrates forward only, got t_span {t_span}")
    y = np.array(y0, dtype=float)
    k = np.empty((16, y.size))  # the stages, reused by every step
    f = np.asarray(fun(t0, y), dtype=float)
    nfev = 1
    if first_step is None:
        h, extra = _first_step(fun, t0, y, f, min(t_end - t0, max_step), rtol, atol)
        nfev += extra
    else:
        h = min(float(first_step), t_end - t0, max_step)
    events = list(events or ())
    g_old = [float(g(t0, y)) for g in events]
    found: list[list[tuple[float, np.ndarray]]] = [[] for _ in events]
    ts, ys, coefs, hs = [t0], [y], [], []
    t, status, nreject, rejected = t0, 0, 0, False
    while status == 0 and t < t_end:
        if h < STEP_FLOOR * np.spacing(abs(t)):
            status = -1
            break
        last = t + h >= t_end or t_end - (t + h) < STEP_FLOOR * np.spacing(abs(t_end))
        if last:
            h = t_end - t
        k[0] = f
        y_new, err = _attempt(fun, t, h, y, k, rtol, atol)
        nfev += 11
        if err > 1.0:
            h *= max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT)
            rejected, nreject = True, nreject + 1
            continue
        t_new = t_end if last else t + h
        k[12] = f_new = np.asarray(fun(t_new, y_new), dtype=float)
        nfev += 1
        coef = []  # this step's interpolant, built once if dense output or an event asks for it

        def interpolant(t=t, h=h, y=y, y_new=y_new):
            nonlocal nfev
            if not coef:
                coef.append(_step_coefficients(fun, t, h, y, y_new, k))
                nfev += 3
            return lambda s: _horner(coef[0], (s - t) / h)

        if dense_output:
            interpolant()
            coefs.append(coef[0])
            hs.append(h)
        g_new = [float(g(t_new, y_new)) for g in events]
        hits = _roots(events, g_old, g_new, t, t_new, interpolant)
        stop = next((hit for hit in hits if getattr(events[hit[1]], "terminal", False)), None)
        for t_root, i, y_root in hits:
            if stop is None or t_root <= stop[0]:
                found[i].append((t_root, y_root))
        g_old = g_new
        ts.append(t_new if stop is None else stop[0])
        ys.append(y_new if stop is None else stop[2])
        status = 0 if stop is None else 1
        t, y, f = t_new, y_new, f_new
        factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** ERROR_EXPONENT)
        h = min(h * (min(factor, 1.0) if rejected else factor), max_step)
        rejected = False
    sol = None
    if dense_output and coefs:
        nodes = np.array(ts)
        nodes[-1] = t  # after a terminal event the last polynomial runs on to its step's end
        sol = DenseOutput(nodes, np.array(hs), np.stack(coefs))
    t_events = [np.array([v[0] for v in hit]) for hit in found] if events else None
    y_events = [np.array([v[1] for v in hit]).reshape(-1, y.size) for hit in found] if events else None
    return RKResult(np.array(ts), np.array(ys).T, sol, t_events, y_events, status, MESSAGES[status], nfev, nreject)


def _step_coefficients(fun, t: float, h: float, y: np.ndarray, y_new: np.ndarray, k: np.ndarray) -> np.ndarray:
    """The interpolant's (8, n) coefficients of the step [t, t + h] (k's stages 1..13 filled; 14..16 added)."""
    for i in range(13, 16):
        k[i] = fun(t + _C[i] * h, y + h * (_A_ROWS[i] @ k[:i]))
    r = np.empty((8, y.size))
    r[0] = y
    r[1] = y_new - y
    r[2] = h * k[0] - r[1]
    r[3] = r[1] - h * k[12] - r[2]
    r[4:] = h * (D @ k)
    return r
