"""The report prints as a traveller (winder.report.traveller): headless Chromium prints the page to PDF
(--print-to-pdf) as one A4 page per job with the whole layer table (each layer's row, its sign-off
column, the materials' totals and costs); a table of 80 layers still keeps to its page. Page count and
size are read from the PDF itself; its text (pdftotext) and a rendering (pdftoppm) where poppler is
installed."""

from __future__ import annotations

import re
import shutil
import subprocess
from types import SimpleNamespace

import numpy as np
import pytest

from winder.config.job import parse_config
from winder.config.material import MaterialConfig
from winder.report.html import STYLE
from winder.report.traveller import PRINT_STYLE, traveller_html

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no chromium found (apt-get install chromium)")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-pdf-header-footer",
         "--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9")
A4_PT = (595.28, 841.89)  # 210 x 297 mm
PAGE_TOL_PT = 1.5  # Chromium's page box, in whole CSS pixels
MASS_PRINTED = 0.0005  # kg: a mass as the traveller prints it (3 decimals)
JOB = {"name": "traveller_job",
       "mandrel": {"profile": {"type": "vessel", "radius": 100, "cylinder_length": 300,
                               "dome": {"type": "hemisphere", "polar_opening": 30}}},
       "winding": {"band_width": 10, "points": 30, "tension": 45,
                   "material": {"name": "carbon_epoxy", "fiber_tex": 800, "tows": 4, "fiber_density": 1.78,
                                "resin_density": 1.15, "fiber_volume_fraction": 0.6, "fiber_price_per_kg": 28.5,
                                "resin_price_per_kg": 7.2},
                   "layers": [{"type": "helical", "angle": 22}, {"type": "hoop", "passes": 2, "tension": 60},
                              {"type": "helical", "angle": 35}]},
       "machine": {"eye": {"radius": 180}, "feed": 2500, "dialect": "linuxcnc"}}


def print_pdf(html_path, tmp_path) -> bytes:
    """Chromium's PDF of a page, printed with a fresh profile and no network."""
    pdf = tmp_path / "printed.pdf"
    subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", f"--print-to-pdf={pdf}",
                    html_path.as_uri()], capture_output=True, timeout=180, check=False)
    assert pdf.exists() and pdf.stat().st_size > 0
    return pdf.read_bytes()


def pages(pdf: bytes) -> list[tuple[float, float]]:
    """The (width, height) in pt of each page of a PDF (its page objects' MediaBox)."""
    boxes = re.findall(rb"/Type\s*/Page\b(?!s).*?/MediaBox\s*\[\s*([-\d.]+)\s+([-\d.]+)\s+([-\d.]+)\s+([-\d.]+)\s*\]",
                       pdf, re.S)
    count = len(re.findall(rb"/Type\s*/Page\b(?!s)", pdf))
    assert len(boxes) == count
    return [(float(x1) - float(x0), float(y1) - float(y0)) for x0, y0, x1, y1 in boxes]


def pdf_text(path) -> str | None:
    tool = shutil.which("pdftotext")
    if tool is None:
        return None
    return subprocess.run([tool, "-layout", str(path), "-"], capture_output=True, text=True, check=True).stdout


def _one_a4_page(pdf: bytes) -> None:
    (size,) = pages(pdf)
    assert abs(size[0] - A4_PT[0]) < PAGE_TOL_PT and abs(size[1] - A4_PT[1]) < PAGE_TOL_PT


def test_the_report_prints_as_one_a4_traveller(tmp_path):
    pytest.importorskip("plotly")
    from winder.report.export import export  # noqa: PLC0415
    from winder.winding.plan import plan as plan_job  # noqa: PLC0415

    job = parse_config(JOB, "traveller_job.yaml")
    plan = plan_job(job)
    page = tmp_path / "traveller_job.html"
    page.write_text(export(plan, job))
    pdf = print_pdf(page, tmp_path)
    _one_a4_page(pdf)
    text = pdf_text(tmp_path / "printed.pdf")
    if text is None:
        pytest.skip("pdftotext (poppler-utils) not installed: the page count and size were checked, not its text")
    assert "Traveller: traveller_job" in text and "sign-off" in text and "Unrolled pattern" not in text
    rows = [re.search(rf"^\s*{k}\s+(helical|hoop)\s+carbon_epoxy\s+4\s+800\s+10\.0\s+(\d+\.\d)", text, re.M)
            for k in (1, 2, 3)]
    assert all(rows) and [float(r[2]) for r in rows] == [45.0, 60.0, 45.0]
    masses = [(float(a), float(b)) for a, b in re.findall(r"(\d\.\d{3})\s+(\d\.\d{3})\s*$", text, re.M)]
    by_hand = sum(f * 28.5 + r * 7.2 for f, r in masses[:3])  # the layer rows' masses at the config's prices
    total = float(re.search(r"total \(fiber [\d.]+, resin [\d.]+\)\s+([\d.]+)", text)[1])
    assert total == pytest.approx(by_hand, abs=3 * MASS_PRINTED * (28.5 + 7.2) + 0.005)
    render = shutil.which("pdftoppm")
    if render is not None:  # the printed page is drawn, not blank
        subprocess.run([render, "-r", "30", "-png", "-singlefile", str(tmp_path / "printed.pdf"),
                        str(tmp_path / "page")], check=True)
        assert (tmp_path / "page.png").stat().st_size > 2000


def test_a_long_layer_table_keeps_to_one_page(tmp_path):
    n = 80
    material = MaterialConfig(fiber_tex=1200, tows=6, fiber_density=2.56, fiber_volume_fraction=0.55)
    job = SimpleNamespace(winding=SimpleNamespace(band_width=12.0, material_of=lambda i: material))
    layers = [{"index": k + 1, "type": "helical" if k % 3 else "hoop", "angle_deg": 30.0 + k % 50,
               "circuits": 40 + k, "passes": 80 + 2 * k, "winding_time_s": 600.0 + k, "fiber_mass_kg": 0.5,
               "resin_mass_kg": 0.2, "tension_n": 50.0 - 0.2 * k, "tension_range_n": [50.0 - 0.2 * k] * 2,
               "material_length_mm": 1.0e5} for k in range(n)]
    summary = {"name": "long", "source": "long.yaml", "layers": layers, "winding_time_s": 6.0e4, "mass_kg": 56.0}
    page = tmp_path / "long.html"
    page.write_text(f"<!DOCTYPE html><html><head><meta charset=utf-8><style>{STYLE}{PRINT_STYLE}</style></head>"
                    f"<body><main>{traveller_html(summary, job, 'long.gcode')}</main></body></html>")
    pdf = print_pdf(page, tmp_path)
    _one_a4_page(pdf)
    text = pdf_text(tmp_path / "printed.pdf")
    if text is not None:
        found = [int(m) for m in re.findall(r"^\s*(\d+)\s+(?:helical|hoop)\s", text, re.M)]
        assert found == list(range(1, n + 1))
        assert np.isclose(float(re.search(r"laminate mass ([\d.]+) kg", text)[1]), 56.0)
