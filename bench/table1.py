"""Table 1 and the accuracy-time frontier, derived from the measured points of each mandrel.

The frontier of a method at an accuracy level is the fastest of its measured configurations whose
relative length error is at or below that level, and stays there for every tighter configuration of
its sweep (so that a setting whose error happens to cross zero is not taken for an accurate one). winder is "ahead" at a level when its fastest
configuration there is faster than every baseline's; the verdicts are written from the numbers.
"""

from __future__ import annotations

from typing import Any

LEVELS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)
NOISE = 0.10  # a ratio within this of 1 is reported as a tie on this noisy machine

LABELS = {
    "newton": "winder newton, smooth length",
    "newton_richardson": "winder newton, Richardson (n and 2n+1)",
    "newton_polyline": "winder newton, polyline",
    "lbfgs": "paper's L-BFGS (polyline)",
    "shooting": "RK shooting (winder.paths.shooting, DOP853)",
    "collocation": "scipy solve_bvp (collocation)",
    "mesh": "mesh + edge-flip geodesic (trimesh, potpourri3d)",
}
OURS = ("newton", "newton_richardson")
BASELINES = ("collocation", "shooting", "mesh", "lbfgs")
FRONTIER_METHODS = ("newton", "newton_richardson", "newton_polyline", "collocation", "shooting", "mesh", "lbfgs")


LOOSE_FIRST = {"collocation": True, "shooting": True}  # knob order: tolerances shrink, n and triangles grow


def method_sweeps(case_result: dict[str, Any], method: str) -> list[list[dict[str, Any]]]:
    """A method's measured (seconds, rel_error) points as sweeps, each ordered from the loosest to
    the tightest setting. L-BFGS: one sweep per run, its recorded iterates in order (as if it had
    been stopped at each)."""
    if method == "lbfgs":
        return [[{"method": "lbfgs", "setting": f"n = {r['n']}, it. {it}", "seconds": sec, "rel_error": err}
                 for it, sec, err in zip(r["trajectory"]["iteration"], r["trajectory"]["seconds"],
                                         r["trajectory"]["rel_error"])]
                for r in case_result.get("lbfgs", [])]
    pts = [p for p in case_result["points"] if p["method"] == method and "rel_error" in p]
    pts.sort(key=lambda p: -p["param"] if LOOSE_FIRST.get(method) else p["param"])
    return [pts] if pts else []


def best_at(sweeps: list[list[dict[str, Any]]], level: float) -> dict[str, Any] | None:
    """The fastest point that meets the level and after which every tighter point of its sweep meets
    it too: a setting that lands on the truth by luck (an error changing sign) does not count."""
    ok = []
    for sweep in sweeps:
        for k, p in enumerate(sweep):
            if all(abs(q["rel_error"]) <= level for q in sweep[k:]):
                ok.append(p)
    return min(ok, key=lambda p: p["seconds"]) if ok else None


def frontier(case_result: dict[str, Any]) -> dict[str, Any]:
    """{"levels": [...], "rows": {method: [cell or None per level]}}, cell = setting, seconds, error."""
    rows = {}
    for m in FRONTIER_METHODS:
        sweeps = method_sweeps(case_result, m)
        if not sweeps:
            continue
        rows[m] = [None if (b := best_at(sweeps, lv)) is None else
                   {"setting": b["setting"], "seconds": b["seconds"], "rel_error": b["rel_error"]} for lv in LEVELS]
    return {"levels": list(LEVELS), "rows": rows}


def verdicts(front: dict[str, Any]) -> dict[str, list[dict[str, Any]]]:
    """Per winder variant, the levels where it is not ahead: one item per level, listing the baselines
    that are faster ("faster"), within timing noise ("tie"), or that reached a level winder's sweep did
    not ("unreached"). An empty list means ahead of every baseline at every level."""
    rows = front["rows"]
    out: dict[str, list[dict[str, Any]]] = {}
    for ours in OURS:
        if ours not in rows:
            continue
        items = []
        for k, level in enumerate(front["levels"]):
            mine = rows[ours][k]
            others = []
            for base in BASELINES:
                theirs = rows.get(base, [None] * len(LEVELS))[k]
                if theirs is None:
                    continue
                if mine is None:
                    others.append({"baseline": base, "kind": "unreached", "theirs": theirs})
                    continue
                ratio = theirs["seconds"] / mine["seconds"]
                if ratio < 1.0 + NOISE:
                    others.append({"baseline": base, "kind": "faster" if ratio < 1.0 - NOISE else "tie",
                                   "theirs": theirs, "ratio": ratio})
            if others:
                items.append({"level": level, "ours": mine, "baselines": others})
        out[ours] = items
    return out


def verdict_text(title: str, ours: str, item: dict[str, Any]) -> str:
    """One plain sentence for a verdicts() item."""
    level, mine = item["level"], item["ours"]
    parts = []
    for b in item["baselines"]:
        th = b["theirs"]
        if b["kind"] == "unreached":
            parts.append(f"{LABELS[b['baseline']]} does ({th['setting']}, {_ms(th['seconds'])})")
        elif b["kind"] == "faster":
            parts.append(f"{LABELS[b['baseline']]} is faster: {_ms(th['seconds'])} ({th['setting']}), winder takes "
                         f"{1.0 / b['ratio']:.2f}x as long")
        else:
            parts.append(f"{LABELS[b['baseline']]} ties within timing noise: {_ms(th['seconds'])} ({th['setting']}, "
                         f"winder {1.0 / b['ratio']:.2f}x)")
    if mine is None:
        return f"{title}, <= {level:.0e}: {LABELS[ours]} did not reach this accuracy in its sweep; " + "; ".join(parts) + "."
    return (f"{title}, <= {level:.0e}: {LABELS[ours]} needs {_ms(mine['seconds'])} ({mine['setting']}); "
            + "; ".join(parts) + ".")


def speedups(front: dict[str, Any], ours: str = "newton") -> dict[str, list[float | None]]:
    """Baseline time / winder time at each level (None where either did not reach it)."""
    rows = front["rows"]
    out = {}
    for base in BASELINES:
        if base not in rows or ours not in rows:
            continue
        out[base] = [None if (m is None or b is None) else b["seconds"] / m["seconds"]
                     for m, b in zip(rows[ours], rows[base])]
    return out


def table1(case_result: dict[str, Any], table_n: tuple[int, ...]) -> dict[str, Any]:
    """The paper's Table 1 rows for one mandrel: newton at table_n (smooth, Richardson, polyline), the
    paper's L-BFGS at its n, and one representative configuration of each baseline."""
    pts = case_result["points"]

    def find(method: str, param) -> dict[str, Any] | None:
        return next((p for p in pts if p["method"] == method and p.get("param") == param and "rel_error" in p), None)

    rows = []
    for n in table_n:
        for m in ("newton", "newton_richardson", "newton_polyline"):
            p = find(m, n)
            if p is not None:
                rows.append({"method": m, "n": n, "setting": p["setting"], "seconds": p["seconds"],
                             "rel_error": p["rel_error"], "samples": p["samples"]})
    for r in case_result.get("lbfgs", []):
        rows.append({"method": "lbfgs", "n": r["n"], "setting": f"n = {r['n']}, cap {r['cap']}",
                     "seconds": r["seconds"], "rel_error": r["rel_error"], "samples": 1,
                     "iterations": r["iterations"], "smooth_rel_error": r["smooth_rel_error"],
                     "paper_stop": r["paper_stop"]})
    for method in ("shooting", "collocation", "mesh"):
        for p in pts:
            if p["method"] == method and "rel_error" in p:
                row = {"method": method, "setting": p["setting"], "seconds": p["seconds"],
                       "rel_error": p["rel_error"], "samples": p["samples"]}
                if method == "mesh":
                    row.update({k: p[k] for k in ("mesh_seconds", "precompute_seconds", "query_seconds")})
                rows.append(row)
    return {"rows": rows}


def _ms(seconds: float) -> str:
    return f"{seconds * 1e3:.3g} ms" if seconds < 10 else f"{seconds:.3g} s"
