"""The paper's method for comparison: scipy's L-BFGS-B on the chain energy with its analytic gradient
(winder.paths.energy), from the given path; winder.paths.geodesic's Method.LBFGS."""

from __future__ import annotations

import numpy as np

from winder.geometry.surface import SweepSurface
from winder.paths.energy import energy_terms
from winder.paths.newton import PathSolve, StopReason

LBFGS_MAX_ITER = 200_000
LBFGS_FTOL = 1e-15  # relative energy decrease per iteration at which L-BFGS-B stops
LBFGS_GTOL = 1e-9  # largest gradient component (mm) at which L-BFGS-B stops


def _lbfgs(surface: SweepSurface, s: np.ndarray, th: np.ndarray, max_iter: int = LBFGS_MAX_ITER,
           callback=None) -> PathSolve:
    n = s.shape[0] - 2
    history: list[tuple[float, float]] = []

    last: dict[str, np.ndarray] = {}

    def fun(x: np.ndarray) -> tuple[float, np.ndarray]:
        ss, tt = s.copy(), th.copy()
        ss[1:-1], tt[1:-1] = x[0::2], x[1::2]
        e, grad, *_ = energy_terms(surface, ss, tt, full_hessian=False)
        last["x"], last["g"] = x.copy(), grad.ravel()
        return e, last["g"]

    def record(intermediate_result) -> None:
        # The accepted iterate is the last one evaluated (L-BFGS-B's line search ends on it).
        g = last["g"] if np.array_equal(last["x"], intermediate_result.x) else fun(intermediate_result.x)[1]
        history.append((float(intermediate_result.fun), float(np.linalg.norm(g))))
        if callback is not None:
            callback(intermediate_result)

    from scipy.optimize import minimize  # noqa: PLC0415 - heavy, and only this baseline needs it

    x0 = np.stack([s[1:-1], th[1:-1]], axis=1).ravel()
    bounds = [(0.0, surface.length), (None, None)] * n
    res = minimize(fun, x0, jac=True, method="L-BFGS-B", bounds=bounds, callback=record,
                   options={"maxiter": max_iter, "maxfun": 2 * max_iter, "ftol": LBFGS_FTOL, "gtol": LBFGS_GTOL,
                            "maxcor": 10})
    s_out, th_out = s.copy(), th.copy()
    s_out[1:-1], th_out[1:-1] = res.x[0::2], res.x[1::2]
    converged = bool(res.success)
    reason = StopReason.LBFGS if converged else StopReason.MAX_ITER
    return PathSolve(s_out, th_out, int(res.nit), converged, reason, np.array(history), int(res.nfev))
