"""report.html's VDI 2143 part of a cam (issue 26 items 2 and 5): per segment its law, the
standard's name, the motion task and the characteristic values (report.json's
``figures.vdi2143``), and the law's acceleration harmonics (``figures.acceleration_harmonics``)
as a small stem plot.  It draws only those figures."""
from __future__ import annotations

import html
from typing import TYPE_CHECKING

import numpy as np

from camgen.report.format import FigureMaker, number
from camgen.report.model import json_number, json_numbers, json_object, json_objects

if TYPE_CHECKING:
    from camgen.report.model import CamReport

__all__ = ["vdi_section"]


def _tasks_table(cam: "CamReport") -> str:
    vdi = json_object(cam.figures.get("vdi2143"))
    segments = json_objects(vdi.get("segments"))
    if not segments:
        return ""
    rows = []
    for i, seg in enumerate(segments):
        name = seg.get("vdi_name")
        shown = "-" if name is None else html.escape(f"{name} ({seg.get('vdi_name_en')})") + (
            "" if seg.get("vdi_name_confirmed") else " *")
        values = "".join(f"<td class='num'>{number(json_number(seg[k]))}</td>" for k in ("Cv", "Ca", "Cj", "C_Mdyn"))
        rows.append(f"<tr><td class='num'>{i}</td><td>{html.escape(str(seg['law']))}</td><td>{shown}</td>"
                    f"<td>{html.escape(str(seg['task']))}</td>{values}</tr>")
    return ("<table class='vdi'><caption>VDI 2143: motion task (R rest, G constant velocity, U reversal, B general motion) "
            "and characteristic values (Cv = max|V|, Ca = max|A|, Cj = max|J|, C_Mdyn = max|V A|; * unconfirmed name)</caption>"
            "<thead><tr><th>segment</th><th>law</th><th>VDI 2143 name</th><th>task</th><th>Cv</th><th>Ca</th><th>Cj</th>"
            f"<th>C_Mdyn</th></tr></thead><tbody>{''.join(rows)}</tbody></table>")


def _harmonics_figure(Figure: FigureMaker, cam: "CamReport") -> str:
    block = json_object(cam.figures.get("acceleration_harmonics"))
    if not block:
        return ""
    speed = next((k for k in block if k.startswith("amplitude_") and k.endswith("_per_s2")), None)
    key = speed or next(k for k in block if k.startswith("amplitude_") and k.endswith("_per_rad2"))
    amplitudes = np.asarray(json_numbers(block[key]))
    unit = key[len("amplitude_"):].replace("_per_", "/").replace("s2", "s²").replace("rad2", "rad²")
    fig = Figure(figsize=(5.2, 2.0))
    ax = fig.add_subplot()
    for n, amplitude in enumerate(amplitudes, start=1):
        ax.plot([n, n], [0.0, float(amplitude)], color="tab:blue", width=1.5)
    ax.xlabel("harmonic of the turn", font_size=8)
    ax.ylabel(f"amplitude ({unit})", font_size=8)
    what = f"at {number(cam.rpm)} rpm" if speed and cam.rpm else "per unit cam speed"
    ax.title(f"{cam.name}: acceleration harmonics {what}", font_size=8)
    return f"<div class='fig'>{fig.to_svg()}</div>"


def vdi_section(Figure: FigureMaker, cam: "CamReport") -> str:
    """The VDI 2143 table and the harmonics plot of ``cam`` ("" when it has neither)."""
    table, figure = _tasks_table(cam), _harmonics_figure(Figure, cam)
    if table and figure:  # side by side, as the profile beside the design table (the printed page stays short)
        return f"<div class='tables'>{table}{figure}</div>"
    return table + figure
