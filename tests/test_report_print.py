"""report.html printed by headless Chromium on Letter and A4 paper: no plot split across two
pages, and a compact page count (issue 21, item 14: it printed on seven loosely laid out pages).

Each plot of the page (an inline SVG in a ``div.fig``) gets two marker words in a copy of the
report made here: one at its top edge, one at its bottom edge.  The PDF's text is read back per
page with pypdf (an independent reader): a plot lies on one page exactly when both its markers
are on the same page.
"""
from __future__ import annotations

import re
import subprocess

import pytest

from helpers import require_tool

#: Paper the copy is printed on: Chromium's default (Letter, the report's ``size: auto``) or A4.
PAPER = {"letter": "", "a4": "<style>@page{size:A4}</style>"}
#: Page size in PDF points (1/72 in): Letter 8.5 x 11 in, A4 210 x 297 mm.
PAGE_POINTS = {"letter": (612.0, 792.0), "a4": (595.28, 841.89)}
#: The plate_cam template's report (one cam: design, profile, curves, motion, dynamics, checks,
#: figures) printed on 6 pages before the print style; the style fits it on 4.
MOST_PAGES = {"plate_cam": 4, "default": 9}
_FIGURE = re.compile(r"<div class='fig'><svg ([^>]*)>")


def _marked(page: str) -> tuple[str, int]:
    """The page with the markers QQTOP<i> and QQBOT<i> at the top and bottom edge of plot i."""
    count = 0

    def mark(m: re.Match) -> str:
        nonlocal count
        height = float(re.search(r'\bheight="([0-9.]+)"', m.group(1)).group(1))
        i, count = count, count + 1
        return (f"{m.group(0)}<text x='4' y='7' font-size='6'>QQTOP{i}</text>"
                f"<text x='4' y='{height - 1:.2f}' font-size='6'>QQBOT{i}</text>")

    return _FIGURE.sub(mark, page), count


def _print(html_path, pdf_path, browser: str, tmp_path) -> None:
    proc = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", f"--user-data-dir={tmp_path / 'profile'}", f"--print-to-pdf={pdf_path}",
         "--no-pdf-header-footer", html_path.as_uri()],
        capture_output=True, text=True, timeout=300,
    )
    assert pdf_path.is_file(), proc.stderr[-2000:]


@pytest.mark.parametrize("template, paper", [("plate_cam", "letter"), ("plate_cam", "a4"), ("default", "a4")])
def test_printed_report_keeps_every_plot_on_one_page(template, paper, tmp_path):
    browser = require_tool("chromium")
    from pypdf import PdfReader

    from camgen.cli import main
    from camgen.scene import template_path

    assert main(["run", str(template_path(template)), "-o", str(tmp_path), "--only", "html", "--quiet"]) == 0
    page = (tmp_path / template / "report.html").read_text(encoding="utf-8")
    marked, plots = _marked(page.replace("</head>", PAPER[paper] + "</head>", 1))
    assert plots >= 4  # the profile, the curves, the motion, the dynamics (and more for the default scene)
    copy = tmp_path / "marked.html"
    copy.write_text(marked, encoding="utf-8")
    pdf = tmp_path / "report.pdf"
    _print(copy, pdf, browser, tmp_path)
    reader = PdfReader(pdf)
    width, height = PAGE_POINTS[paper]
    for sheet in reader.pages:
        assert (float(sheet.mediabox.width), float(sheet.mediabox.height)) == pytest.approx((width, height), abs=1.0)
    where: dict[str, list[int]] = {}
    for number, sheet in enumerate(reader.pages):
        for marker in re.findall(r"QQ(?:TOP|BOT)\d+", sheet.extract_text()):
            where.setdefault(marker, []).append(number)
    for i in range(plots):
        top, bottom = where.get(f"QQTOP{i}"), where.get(f"QQBOT{i}")
        assert top is not None and bottom is not None and len(top) == len(bottom) == 1, (i, top, bottom)
        assert top == bottom, f"plot {i} is split: its top is on page {top[0] + 1}, its bottom on page {bottom[0] + 1}"
    assert len(reader.pages) <= MOST_PAGES[template]
