"""The Fanuc / Haas dialect (``dialect = "fanuc"``; also the ISO modes of Okuma and Mazak).

The moves are those of :func:`camgen.export.gcode.gcode_program` (the same tool path, leads,
passes and pockets); this module writes the words a Fanuc-style control needs around them:

* ``%`` framing, ``O<program_number>`` (four digits) with the cam's name, ``M30`` and ``%``;
* ``G21`` (``G20`` in an inch program: :mod:`camgen.export.gcode_units`) alone in the first block (units before anything else), then the safe start line
  ``G17 G40 G49 G80 G90 G94 G54``, the tool call ``T<n> M06``, spindle ``S.. M03`` and the length
  offset ``G0 G43 H<n> Z<safe>`` (``H`` = the tool number);
* cutter compensation ``G41/G42 D<radius_register>`` switched on in a ``G1`` block of the
  lead-in and off (``G40``) in a ``G1`` block of the lead-out: never on an arc.  The register
  holds a **radius**, and the header says which value it expects:

  - ``cutter_compensation = true``: the program is the profile itself; ``D`` holds the tool
    radius (plus its wear);
  - ``cutter_compensation = false``: the program is the tool-centre path (the profile offset by
    the tool radius, as for LinuxCNC); compensation is still switched on along the same leads
    so that the wear offset works, and ``D`` holds **0** (plus the wear only);

* arcs by ``I``/``J`` (incremental centre, never ``R``: no full-circle ambiguity), as every dialect;
* comments upper-case, of letters, digits and ``. , = _ - + *`` only (older Fanuc controls take
  no lower-case letters or other signs in a comment).

The leads are those of :mod:`camgen.export.gcode_leads` (a straight move and a tangent quarter
arc, ``lead_style = "arc"``, or a straight tangent line): the compensation is switched on in
the straight move before the arc and off in the straight move after the lead-out arc.  The
compensated entry move ends, on a Fanuc (start-up type A or B) as on LinuxCNC, on the offset
line of the following straight block, which the tool runs along into the lead arc; the ``G40``
block starts at the offset point of the previous line's end, on the same line.  So the tool
runs tangentially in and out, with no corner.  A wear value in ``D`` must stay below what the
leads take (:func:`camgen.export.gcode_leads.wear_limit`: the entry move longer than the radius
offset by, the tool inside the lead arcs); the header states that limit.
"""
from __future__ import annotations

import math
import re
from typing import Sequence

from camgen.export.fanuc_settings import FanucNumbers, fanuc_numbers
from camgen.export.gcode_leads import wear_limit
from camgen.export.gcode_moves import comment
from camgen.export.gcode_spec import MachiningSpec

__all__ = ["COMMENT_CHARACTERS", "SAFE_START", "UNITS_BLOCK", "fanuc_comment", "fanuc_end", "fanuc_leads", "fanuc_numbers_of",
           "fanuc_start"]

#: The first block: the units alone, before any coordinate is read.
UNITS_BLOCK = "G21"
#: The safe start line: XY plane, no compensation, no length offset, no canned cycle, absolute, feed per minute, G54.
SAFE_START = "G17 G40 G49 G80 G90 G94 G54"
#: The characters a comment keeps (upper case); any other becomes a space.
COMMENT_CHARACTERS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 .,=_-+*")
#: Signs a comment spells out before the others are dropped.
_SIGN_WORDS = (("<=", " UP TO "), (">=", " AT LEAST "), ("'", ""))
_COMMENT = re.compile(r"\(([^()\n]*)\)")


def fanuc_numbers_of(spec: MachiningSpec) -> FanucNumbers:
    """Program, tool and radius-register numbers of ``spec`` with their defaults."""
    return fanuc_numbers(spec.program_number, spec.tool_number, spec.radius_register)


def fanuc_comment(text: str) -> str:
    """``text`` as a Fanuc comment body: upper case, unknown signs as spaces."""
    for sign, words in _SIGN_WORDS:
        text = text.replace(sign, words)
    return "".join(c if c in COMMENT_CHARACTERS else " " for c in text.upper())


def _register_words(spec: MachiningSpec, climb: bool) -> str:
    # G41: tool left of the travel = outside of a clockwise (climb) path
    return f"{'G41' if climb else 'G42'} D{fanuc_numbers_of(spec).radius_register:02d}"


def fanuc_leads(spec: MachiningSpec, climb: bool, entry: Sequence[tuple[str, str]], exit_blocks: Sequence[tuple[str, str]]) -> tuple[str, str, str]:
    """Lead-in, lead-out and the header's mode text of a Fanuc program.

    ``entry`` and ``exit_blocks``: the leads' blocks as (motion word, words)
    (:func:`camgen.export.gcode_leads.lead_blocks`); the first of ``entry`` and the last of
    ``exit_blocks`` are straight moves, which switch the compensation on and off.  With cutter
    compensation the profile is programmed; without it the tool-centre path, the compensation
    switched on and off along the same leads for the wear offset only.
    """
    words = _register_words(spec, climb)
    register = f"D{fanuc_numbers_of(spec).radius_register:02d}"
    (word, first), *rest = entry
    *before, (last_word, last) = exit_blocks
    lead_in = f"{word} {words} {first} F{spec.feed:.{spec.feed_decimals}f}\n" + "".join(f"{w} {rest_words}\n" for w, rest_words in rest)
    lead_out = "".join(f"{w} {rest_words}\n" for w, rest_words in before) + f"G40 {last_word} {last}\n"
    if spec.cutter_compensation:
        mode = f"cutter compensation {words} on the profile, {register} = tool radius"
    else:
        mode = f"tool-centre path = profile offset by the tool radius, {words} for the wear only, {register} = 0"
    return lead_in, lead_out, mode


def fanuc_start(spec: MachiningSpec, pocketed: bool) -> list[str]:
    """The header's register line and the blocks before the first move: units, safe start, tool
    call, spindle, length offset at safe Z.  ``pocketed``: the program mills pockets (tool-centre
    passes without compensation) before the outline."""
    numbers = fanuc_numbers_of(spec)
    d = spec.decimals
    value = spec.tool_radius if spec.cutter_compensation else 0.0
    what = "the tool radius" if spec.cutter_compensation else "0, the path is the tool centre"
    # the leads take a wear below wear_limit (the entry move, the lead arcs), printed rounded down
    limit = math.floor(wear_limit(spec) * 10**d) / 10**d
    unit = "in" if spec.units == "inch" else "mm"
    wear = f"plus the wear, below {limit:.{d}f} {unit} for the leads"
    return [
        comment(f"radius register D{numbers.radius_register:02d} = {value:.{d}f} {unit}: {what}; {wear}; "
                f"D read as a radius; length offset H{numbers.tool:02d} of tool T{numbers.tool}"
                + ("; pockets without compensation" if pocketed else "")),
        spec.units_word,  # UNITS_BLOCK, or G20 in an inch program (camgen.export.gcode_units)
        SAFE_START,
        f"T{numbers.tool} M06",
        f"S{spec.spindle_rpm:.0f} M03",
        f"G0 G43 H{numbers.tool:02d} Z{spec.safe_z:.{d}f}",
    ]


def fanuc_end(spec: MachiningSpec, cam: str, body: Sequence[str]) -> str:
    """The whole program: ``%``, ``O`` number with the cam's name, ``body`` (header comments and
    moves, as the other dialects write them), spindle stop, ``M30``, ``%``; every comment made
    Fanuc-safe (:func:`fanuc_comment`)."""
    number = fanuc_numbers_of(spec).program
    text = f"%\nO{number:04d} ({fanuc_comment(cam)})\n" + "".join(body) + "M05\nM30\n%\n"
    return _COMMENT.sub(lambda m: f"({fanuc_comment(m.group(1))})", text)
