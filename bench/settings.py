"""How big a bench run is: the full run (committed results page), --quick, and the test's tiny one."""

from __future__ import annotations

from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Settings:
    """Sizes of every experiment. Times are seconds, tolerances relative.

    newton_n : the n swept for Newton (Figure 7 and the accuracy-time frontier); table_n are added.
    large_n : Newton's time at large n on the bent tube (linear growth), smooth length only.
    shoot_tols : rtol (= atol) of the RK shooting baseline. bvp_tols : solve_bvp's tol, swept from
        loose to tight until the error is below bvp_stop_error, the solver stops on its node limit, or
        one solve takes longer than bvp_time_limit.
    mesh_triangles : triangle counts of the mesh baseline.
    lbfgs_n, lbfgs_cap : the paper's L-BFGS at these n, each run at most lbfgs_cap iterations (one
        run each: too slow to repeat).
    fig8_n, fig8_cap : per-iteration histories of Newton, L-BFGS and LO (Figure 8).
    helix_rounds, helix_n : section 6.1. frames, evolution_n, bend_deg : section 6.2.
    truth_tol : shooting tolerance of the ground truth where there is no closed form.
    repeats, min_repeats, budget : timing repeats per task (at most, at least, and about this many
        seconds of samples per task).
    job : compare a whole cylinder job with fiberpath (if installed). blas_check : measure L-BFGS-B
        with the BLAS threads left alone against one thread. blas_threads : the limit while timing.
    """

    name: str
    cases: tuple[str, ...] = ("bend", "cone", "ellipse")
    newton_n: tuple[int, ...] = (10, 15, 20, 30, 50, 70, 100, 150, 200, 300, 500, 700, 1000, 1500, 2000, 4000)
    table_n: tuple[int, ...] = (50, 500, 1000)
    large_n: tuple[int, ...] = (1000, 10_000, 100_000)
    shoot_tols: tuple[float, ...] = (1e-4, 1e-5, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10, 1e-11,
                                     1e-12, 1e-13)
    bvp_tols: tuple[float, ...] = (1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7,
                                   1e-8, 1e-9)
    bvp_stop_error: float = 1e-11
    bvp_time_limit: float = 5.0
    bvp_max_nodes: int = 50_000
    mesh_triangles: tuple[int, ...] = (20_000, 80_000, 320_000)
    lbfgs_n: tuple[int, ...] = (50, 500, 1000)
    lbfgs_cap: int = 10_000
    fig8_n: int = 200
    fig8_cap: int = 3000
    helix_rounds: tuple[int, ...] = (5, 10, 20)
    helix_n: int = 1000
    frames: int = 50
    evolution_n: tuple[int, ...] = (50, 1000)
    bend_deg: tuple[float, float] = (60.0, 120.0)
    truth_tol: float = 1e-13
    repeats: int = 15
    min_repeats: int = 3
    budget: float = 1.5
    job: bool = True
    speed: bool = True  # issue 14's figures: the solver against solve_bvp (analytic Jacobians), start-up
    fiberpath_jobs: bool = True  # every fiberpath example as a whole job, both tools as command lines
    speed_repeats: int = 5
    blas_check: bool = True
    blas_threads: int | None = 1

    @property
    def quick(self) -> bool:
        return self.name != "full"

    @property
    def all_newton_n(self) -> tuple[int, ...]:
        return tuple(sorted(set(self.newton_n) | set(self.table_n)))


FULL = Settings(name="full")

QUICK = Settings(
    name="quick",
    newton_n=(20, 30, 50, 100, 200, 500, 1000),
    large_n=(1000, 10_000),
    shoot_tols=(1e-6, 1e-10),
    bvp_tols=(1e-2, 1e-4, 1e-6),
    bvp_time_limit=2.0,
    mesh_triangles=(5_000, 20_000),
    lbfgs_n=(50,),
    lbfgs_cap=300,
    fig8_n=100,
    fig8_cap=300,
    helix_rounds=(5,),
    helix_n=300,
    frames=10,
    evolution_n=(50,),
    truth_tol=1e-11,
    repeats=3,
    min_repeats=1,
    budget=0.3,
    fiberpath_jobs=False,
    speed_repeats=3,
    blas_check=False,
)


def tiny(**changes) -> Settings:
    """A run of a few seconds for the smoke test."""
    base = Settings(
        name="tiny", cases=("bend",), newton_n=(30, 50), table_n=(50,), large_n=(200,), shoot_tols=(1e-8,),
        bvp_tols=(1e-3,), mesh_triangles=(2_000,), lbfgs_n=(30,), lbfgs_cap=20, fig8_n=30, fig8_cap=20,
        helix_rounds=(2,), helix_n=60, frames=3, evolution_n=(30,), truth_tol=1e-10, repeats=1,
        min_repeats=1, budget=0.05, job=False, speed=False, fiberpath_jobs=False, blas_check=False)
    return replace(base, **changes)
