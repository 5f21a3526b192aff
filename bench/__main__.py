"""`python -m bench` (from the repository root): regenerate the benchmark page bench/results/.

A developer tool beside the product, not a winder command: it measures winder against the paper and
baselines and writes RESULTS.md, results.json and the figures. Optional baselines (pip install
".[bench]"; fiberpath separately) are skipped with a note when missing.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m bench", description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="a smaller run (about a minute) instead of the full one")
    p.add_argument("-o", "--output-dir", default=str(RESULTS),
                   help="folder for RESULTS.md, results.json and the figures (default: bench/results)")
    p.add_argument("--from-json", action="store_true",
                   help="only rewrite RESULTS.md and the figures from OUTPUT_DIR/results.json")
    p.add_argument("--speed", dest="speed_cap", type=int, default=None, metavar="LBFGS_CAP",
                   help="only the solver speed check: Newton vs L-BFGS (capped at LBFGS_CAP iterations), "
                        "growth with n")
    p.add_argument("--parts", type=int, default=None, metavar="N",
                   help="only the generated parts: N of them (tests/part_generator.py), tabled per class "
                        "(bench/generated.py)")
    p.add_argument("--seed", type=int, default=0, help="the first seed of --parts (default 0)")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    from bench import FULL, QUICK, report_from_json, run_bench, write_outputs  # noqa: PLC0415

    if args.speed_cap is not None:
        from bench.speed import measure  # noqa: PLC0415

        rep = measure(lbfgs_cap=args.speed_cap)
        print(f"quarter bend, 1 round, n = 1000: newton {rep.newton_ms:.2f} ms (median, {rep.newton_steps} "
              f"Newton steps over all levels; one more step changes the length by {rep.newton_change:.1e})")
        print(f"  lbfgs {rep.lbfgs_s:.2f} s, {rep.lbfgs_iterations} iterations, stopped at: {rep.lbfgs_stop} "
              f"(length gap {rep.lbfgs_gap:.1e}); lbfgs / newton = {rep.ratio:.0f}x")
        for n, secs in rep.growth:
            print(f"  newton n = {n:>7d}: {secs * 1e3:8.1f} ms ({secs / n * 1e6:.2f} us per point)")
        return 0
    if args.parts is not None:
        from bench.generated import main as generated  # noqa: PLC0415

        return generated(args.parts, args.seed, Path(args.output_dir))
    if args.from_json:
        print(f"wrote {report_from_json(args.output_dir)}")
        return 0
    t0 = time.perf_counter()

    def say(msg: str) -> None:
        print(f"[{time.perf_counter() - t0:6.1f} s] {msg}", file=sys.stderr)

    results = run_bench(QUICK if args.quick else FULL, progress=say)
    for path in write_outputs(results, args.output_dir, progress=say):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
