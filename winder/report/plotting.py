"""What the report's figures share: the lazy plotly import, colors, axis styles, figure -> HTML.

Figures are built as plain dicts (plotly's JSON schema) and rendered by plotly.io.to_html without
validation: the graph_objects layer would only add a second or more of start-up per report.
Coordinates are rounded (COORD_DECIMALS) before they go into the page: a hundredth of a millimetre or
degree is far below what a screen shows, and halves the file.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from winder.errors import ConfigError

COORD_DECIMALS = 2
GAP_COLOR = "#d62728"  # red: where a band direction leaves the mandrel bare
MANDREL_COLOR = "#c8c8c8"
DWELL_COLOR = "#9a9a9a"
# (+alpha, -alpha) per layer, cycling; no red (gaps) and no gray (mandrel, dwells) among them.
DIRECTION_COLORS = (
    ("#1f77b4", "#ff7f0e"),  # blue / orange
    ("#2ca02c", "#8c564b"),  # green / brown
    ("#17becf", "#9467bd"),  # cyan / purple
    ("#bcbd22", "#e377c2"),  # olive / pink
)
FONT = {"family": "Segoe UI, Helvetica, Arial, sans-serif", "size": 13}
PLOT_CONFIG = {"displaylogo": False, "responsive": True, "scrollZoom": False,
               "toImageButtonOptions": {"format": "png", "scale": 2}}
INSTALL_HINT = 'pip install "winder[plot]"'


def require_plotly():
    """plotly.io, or a usage error (exit 2) saying how to install the `plot` extra."""
    try:
        import plotly.io as pio  # noqa: PLC0415 - optional, and heavy: only when a report is made
    except ImportError as exc:
        raise ConfigError(f"the report draws with plotly, which is not installed: {INSTALL_HINT}") from exc
    return pio


def colors(layer: int) -> tuple[str, str]:
    """(+alpha, -alpha) colors of a layer (1-based)."""
    return DIRECTION_COLORS[(layer - 1) % len(DIRECTION_COLORS)]


PASS_LABELS = {  # (kind, t increasing) -> legend label, in legend order
    ("forward", True): "+α band (forward, t increasing)",
    ("return", False): "−α band (return, t decreasing)",
    ("hoop", True): "hoop traverse, t increasing",
    ("hoop", False): "hoop traverse, t decreasing",
    ("dwell", True): "dwell (mandrel turns, fiber on a parallel)",
    ("turnaround", True): "turnaround (past the winding region)",
}


def pass_style(layer: int, kind: str, rising: bool) -> tuple[str, str]:
    """(legend label, color) of a pass: +alpha / -alpha colors by the direction along t (hoop
    traverses too), dwells gray."""
    if kind in ("dwell", "turnaround"):
        return PASS_LABELS[(kind, True)], DWELL_COLOR
    key = (kind, rising) if kind == "hoop" else (kind, kind == "forward")
    return PASS_LABELS[key], colors(layer)[0 if key[1] else 1]


def style_groups(passes) -> dict[str, list]:
    """The passes of a layer grouped by legend label (see pass_style), in legend order."""
    groups: dict[tuple[str, bool], list] = {key: [] for key in PASS_LABELS}
    for p in passes:
        kind = p.kind.value
        rising = bool(p.t[-1] >= p.t[0]) if kind == "hoop" else (kind != "return")
        rising = rising or kind == "turnaround"  # one legend entry for both ways
        groups[(kind, rising)].append(p)
    return {key: g for key, g in groups.items() if g}


def rounded(values: np.ndarray, decimals: int = COORD_DECIMALS) -> list:
    """A JSON-ready list; NaN (a break between lines) becomes null."""
    arr = np.round(np.asarray(values, dtype=float), decimals)
    out = arr.tolist()
    if np.isnan(arr).any():
        out = _nulls(out)
    return out


def _nulls(items: list) -> list:
    return [_nulls(v) if isinstance(v, list) else (None if v != v else v) for v in items]


def axis(title: str, **extra: Any) -> dict[str, Any]:
    """An axis with a title, light grid and a visible zero line."""
    base = {"title": {"text": title}, "showgrid": True, "gridcolor": "#e6e6e6", "zeroline": False,
            "showline": True, "linecolor": "#888", "mirror": True, "ticks": "outside"}
    base.update(extra)
    return base


def base_layout(title: str, height: int, **extra: Any) -> dict[str, Any]:
    layout = {"title": {"text": title, "x": 0.01, "xanchor": "left", "font": {"size": 17}},
              "height": height, "font": FONT, "paper_bgcolor": "white", "plot_bgcolor": "white",
              "margin": {"l": 80, "r": 30, "t": 70, "b": 60}, "hovermode": "closest",
              "legend": {"groupclick": "toggleitem"}}
    layout.update(extra)
    return layout


def figure_html(figure: dict[str, Any], div_id: str, include_plotlyjs: bool) -> str:
    """One figure as an HTML fragment; include_plotlyjs on the first figure of the page only (the
    plotly.js bundle from the plotly wheel, inline: the page needs no network)."""
    pio = require_plotly()
    height = figure.get("layout", {}).get("height", 500)
    return pio.to_html(figure, config=PLOT_CONFIG, include_plotlyjs=include_plotlyjs, include_mathjax=False,
                       full_html=False, validate=False, div_id=div_id, default_width="100%",
                       default_height=f"{height}px")


def subplot_domains(n: int, gap: float) -> list[tuple[float, float]]:
    """Vertical domains (bottom, top) of n stacked subplots, the first on top."""
    h = (1.0 - gap * (n - 1)) / n
    return [(1.0 - (i + 1) * h - i * gap, 1.0 - i * h - i * gap) for i in range(n)]


def axis_key(kind: str, i: int) -> tuple[str, str]:
    """('xaxis2', 'x2') for the i-th (0-based) subplot's axis of kind 'x' or 'y'."""
    suffix = "" if i == 0 else str(i + 1)
    return f"{kind}axis{suffix}", f"{kind}{suffix}"


def ramp(stops: tuple[str, ...], n: int) -> list[str]:
    """n colors evenly along the piecewise-linear ramp through the hex colors stops."""
    rgb = np.array([[int(c[i:i + 2], 16) for i in (1, 3, 5)] for c in stops], dtype=float)
    where = np.linspace(0.0, len(stops) - 1.0, max(n, 1)) if n > 1 else np.zeros(1)
    lo = np.minimum(np.floor(where).astype(int), len(stops) - 2)
    f = (where - lo)[:, None]
    mixed = np.rint(rgb[lo] * (1.0 - f) + rgb[lo + 1] * f).astype(int)
    return ["#%02x%02x%02x" % tuple(c) for c in mixed]
