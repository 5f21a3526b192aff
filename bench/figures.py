"""The bench's plots (PNG), drawn from the results dict only. matplotlib is optional (the bench extra):
without it no PNG is written and the page says so."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from bench.table1 import LABELS, LEVELS

STYLE = {
    "newton": dict(color="tab:blue", marker="o"),
    "newton_richardson": dict(color="tab:cyan", marker="s"),
    "newton_polyline": dict(color="tab:gray", marker=".", linestyle=":"),
    "collocation": dict(color="tab:orange", marker="^"),
    "shooting": dict(color="tab:green", marker="v"),
    "mesh": dict(color="tab:red", marker="D"),
    "lbfgs": dict(color="tab:purple", marker="x"),
    "lo": dict(color="tab:brown", marker="+"),
}
CASE_LINES = ("-", "--", "-.")


def _points(case: dict[str, Any], method: str) -> list[dict[str, Any]]:
    pts = [p for p in case["points"] if p["method"] == method and p.get("rel_error") is not None]
    return sorted(pts, key=lambda p: p["param"] if method not in ("shooting", "collocation") else -p["param"])


def _frontier(plt, results: dict[str, Any], path: Path) -> None:
    cases = results["cases"]
    fig, axes = plt.subplots(1, len(cases), figsize=(5.2 * len(cases), 4.6), squeeze=False)
    for ax, case in zip(axes[0], cases):
        for m in ("newton", "newton_richardson", "newton_polyline", "collocation", "shooting", "mesh"):
            pts = _points(case, m)
            if not pts:
                continue
            st = dict(STYLE[m])
            ax.plot([p["seconds"] for p in pts], [max(abs(p["rel_error"]), 1e-16) for p in pts],
                    label=LABELS[m], markersize=4, linewidth=1, **st)
        for k, run in enumerate(case.get("lbfgs", [])):
            tr = run["trajectory"]
            ax.plot(tr["seconds"], [max(abs(e), 1e-16) for e in tr["rel_error"]], color="tab:purple",
                    linewidth=0.6, alpha=0.6, label=f"paper's L-BFGS, per iteration (n = {run['n']})" if k == 0 else None)
            ax.plot([run["seconds"]], [abs(run["rel_error"])], "x", color="tab:purple")
        ax.axhspan(LEVELS[-1], LEVELS[0], color="0.92", zorder=0)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time (s, median)")
        ax.set_ylabel("relative length error")
        ax.set_title(case["title"])
        ax.grid(True, which="major", alpha=0.3)
    axes[0][0].legend(fontsize=7, loc="lower left")
    fig.suptitle("Accuracy against time (shaded: 1e-4 to 1e-9)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _figure7(plt, results: dict[str, Any], path: Path) -> None:
    cases = results["cases"]
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    ax = axes[0]
    for k, case in enumerate(cases):
        cv = case["convergence"]
        ls = CASE_LINES[k % 3]
        for key, m, name in (("polyline_rel_error", "newton_polyline", "polyline"),
                             ("smooth_rel_error", "newton", "smooth"),
                             ("richardson_rel_error", "newton_richardson", "Richardson")):
            order = cv["order"].get({"polyline_rel_error": "polyline", "smooth_rel_error": "smooth",
                                     "richardson_rel_error": "richardson"}[key])
            lab = f"{case['key']}: {name}" + (f" (slope {order:.2f})" if order is not None else "")
            ax.plot([n + 1 for n in cv["n"]], [max(abs(e), 1e-16) for e in cv[key]], linestyle=ls,
                    color=STYLE[m]["color"], marker=STYLE[m]["marker"], markersize=3, linewidth=1, label=lab)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("n + 1 (segments)")
    ax.set_ylabel("|relative length error|")
    ax.set_title("Error against n (Newton)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6)

    ax = axes[1]
    for k, case in enumerate(cases):
        cv = case["convergence"]
        ls = CASE_LINES[k % 3]
        ax.plot(cv["n"], cv["seconds"], linestyle=ls, color="tab:blue", marker="o", markersize=3,
                label=f"{case['key']}: smooth length")
        ax.plot(cv["n"], cv["seconds_with_estimate"], linestyle=ls, color="tab:cyan", marker="s", markersize=3,
                label=f"{case['key']}: with the 2n+1 solve (Richardson)")
        if case.get("large_n"):
            big = [r for r in case["large_n"] if "seconds" in r]
            ax.plot([r["n"] for r in big], [r["seconds"] for r in big], linestyle=ls, color="black", marker="*",
                    label=f"{case['key']}: large n")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("n (interior points)")
    ax.set_ylabel("wall time (s, median)")
    ax.set_title("Time against n (Newton)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6)

    ax = axes[2]
    lo, hi = 1e-16, 1e-1
    for k, case in enumerate(cases):
        cv = case["convergence"]
        mk = ("o", "s", "^")[k % 3]
        ax.loglog([abs(e) for e in cv["polyline_2n_rel_error"]], cv["error_estimate_rel"], mk, color="tab:gray",
                  markersize=4, label=f"{case['key']}: |L_2n - L_n|/3 vs error of L_2n (polyline)")
        ax.loglog([abs(e) for e in cv["smooth_rel_error"]], cv["smooth_error_estimate_rel"], mk, color="tab:blue",
                  markersize=4, mfc="none", label=f"{case['key']}: smooth-length estimate vs its error")
    ax.plot([lo, hi], [lo, hi], "k-", linewidth=0.8, label="estimate = true error")
    ax.set_xlim(1e-15, 1e-1)
    ax.set_ylim(1e-15, 1e-1)
    ax.set_xlabel("true relative error")
    ax.set_ylabel("estimated relative error")
    ax.set_title("Error estimates against the true error")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _figure8(plt, results: dict[str, Any], path: Path) -> None:
    cases = [c for c in results["cases"] if c.get("figure8")]
    fig, axes = plt.subplots(2, len(cases), figsize=(5.2 * len(cases), 8), squeeze=False)
    for j, case in enumerate(cases):
        f8 = case["figure8"]
        for name, label in (("newton", "Newton (single level)"), ("lbfgs", "L-BFGS on E (paper)"),
                            ("lo", "LO: L-BFGS on the length")):
            h = f8[name]
            st = {"color": STYLE[name]["color"]}
            x = [i + 1 for i in h["iteration"]]
            axes[0][j].plot(x, [max(abs(e), 1e-16) for e in h["rel_error"]], label=label, linewidth=1, **st)
            gx = [i + 1 for i in h["iteration"]]
            own = h["grad_length"] if name == "lo" else h["grad_energy"]
            axes[1][j].plot(gx, own, label=f"{label}: |grad {'L' if name == 'lo' else 'E'}|", linewidth=1, **st)
            axes[1][j].plot(gx, h["grad_length"], linestyle=":", linewidth=1, **st,
                            label=f"{label}: |grad L|" if name != "lo" else None)
        for ax in axes[:, j]:
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, alpha=0.3)
            ax.set_xlabel("iteration + 1")
        axes[0][j].set_ylabel("|relative error| of the polyline length")
        axes[1][j].set_ylabel("gradient norm")
        axes[0][j].set_title(f"{case['title']}, n = {f8['n']}")
        axes[0][j].legend(fontsize=7)
        axes[1][j].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _evolution(plt, results: dict[str, Any], path: Path) -> None:
    ev = results["evolution"]
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for k, run in enumerate(ev["runs"]):
        fr = run["frames"]
        ls = CASE_LINES[k % 3]
        ax.plot([f["bend_deg"] for f in fr], [f["cold_seconds"] for f in fr], ls, color="tab:red",
                label=f"n = {run['n']}: cold solve")
        w = [f for f in fr if f.get("warm_seconds") is not None]
        ax.plot([f["bend_deg"] for f in w], [f["warm_seconds"] for f in w], ls, color="tab:blue",
                label=f"n = {run['n']}: warm start from the previous frame")
    ax.set_yscale("log")
    ax.set_xlabel("bend angle (deg) of the frame")
    ax.set_ylabel("solve time (s, median)")
    ax.set_title(f"Deforming mandrel, {ev['frames']} frames")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def make_figures(results: dict[str, Any], out: Path) -> tuple[list[Path], list[str]]:
    """Write the PNGs; returns their paths and notes (e.g. matplotlib missing)."""
    try:
        import matplotlib  # noqa: PLC0415

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt  # noqa: PLC0415
    except ImportError:
        return [], ["matplotlib is not installed (pip install .[bench]): no figures were drawn"]
    written = []
    plots = [("frontier.png", _frontier, bool(results.get("cases"))),
             ("figure7_convergence.png", _figure7, bool(results.get("cases"))),
             ("figure8_iterations.png", _figure8, any(c.get("figure8") for c in results.get("cases", []))),
             ("evolution.png", _evolution, bool((results.get("evolution") or {}).get("runs")))]
    for name, draw, wanted in plots:
        if wanted:
            draw(plt, results, out / name)
            written.append(out / name)
    return written, []
