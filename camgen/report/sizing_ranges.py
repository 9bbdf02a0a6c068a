"""The sizing answers of report.html (the ``sizing_ranges`` key, issue 26 item 4): every
interval of a roller radius, arm length or pivot distance at which the cam meets its design
limits, each end with what bounds it (from report.json's ``figures.sizing_ranges``)."""
from __future__ import annotations

import html
from typing import TYPE_CHECKING

from camgen.report.format import number
from camgen.report.model import json_number, json_object, json_objects

if TYPE_CHECKING:
    from camgen.report.model import CamReport

__all__ = ["BOUNDS", "sizing_ranges_section"]

#: What bounds an end, as the table says it (the check names of report.json, and the two ends that are no check).
BOUNDS = {
    "geometry": "no follower beyond (the key's valid range)",
    "range_searched": "end of the range searched",
    "not found": "no failing value found beyond",
}
_WHAT = {"roller_radius": "roller radius (roller_radius_mm)", "arm_length": "arm length (arm_length_mm)",
         "pivot_distance": "pivot distance from the cam axis (pivot_x_mm, pivot_y_mm)"}


def _bound(text: str) -> str:
    return " and ".join(BOUNDS.get(part, part) for part in text.split(" and "))


def sizing_ranges_section(cam: "CamReport") -> str:
    """The table of passing intervals ("" when the scene asks for none)."""
    if "sizing_ranges" not in cam.figures:
        return ""
    rows = []
    for name, value in json_object(cam.figures["sizing_ranges"]).items():
        entry = json_object(value)
        what = html.escape(_WHAT.get(name, name))
        given = number(json_number(entry["scene_mm"]))
        runs = json_objects(entry["intervals"])
        if not runs:
            rows.append(f"<tr><td>{what}</td><td class='num'>{given}</td><td colspan='4'>none passes</td></tr>")
        for run in runs:
            rows.append(f"<tr><td>{what}</td><td class='num'>{given}</td>"
                        f"<td class='num'>{number(json_number(run['low_mm']))}</td><td>{html.escape(_bound(str(run['low_bound'])))}</td>"
                        f"<td class='num'>{number(json_number(run['high_mm']))}</td><td>{html.escape(_bound(str(run['high_bound'])))}</td></tr>")
    return ("<h3>Sizing ranges</h3><p class='note'>Every interval of values (mm) at which the cam meets all its design limits, "
            "the other values as the scene gives them; each end tried and passing, 0.001 mm beyond it tried and failing the check "
            "named (a pivot moves along its own direction from the cam axis).</p>"
            "<table class='figures'><thead><tr><th>quantity</th><th>scene (mm)</th><th>from (mm)</th><th>bounded by</th>"
            f"<th>to (mm)</th><th>bounded by</th></tr></thead><tbody>{''.join(rows)}</tbody></table>")
