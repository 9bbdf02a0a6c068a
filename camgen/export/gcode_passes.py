"""The depth passes of one milling operation of a G-code program (:mod:`camgen.export.gcode`).

An :class:`Operation` is one programmed closed path with its leads, cut at its depths: per pass
a rapid to the entry point ``P0`` (the tool centre where the lead-in starts, outside the part),
the descent to the pass depth, the lead-in, the closed path, the lead-out and a rapid up to the
safe height.  The leads are given as text, one block each, so their geometry lives elsewhere.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camgen.export.gcode_spec import MachiningSpec

__all__ = ["Operation", "outline_passes"]


@dataclass(frozen=True)
class Operation:
    """One outline operation (mm).

    ``plunge``: the entry point ``P0`` (2,), the tool centre where the lead-in starts;
    ``lead_in``, ``moves``, ``lead_out``: the program text of the lead-in (from ``P0``), of the
    closed path and of the lead-out (ending with the tool outside the part); ``depths``: the Z of
    its passes, falling, < 0; ``name``: how the pass comments call it.
    """

    plunge: np.ndarray
    lead_in: str
    moves: str
    lead_out: str
    depths: tuple[float, ...]
    name: str = "pass"


def outline_passes(op: Operation, spec: MachiningSpec) -> str:
    """The program text of every pass of ``op``: rapid to ``P0`` at the safe height, the plunge
    to the pass depth at the plunge feed, the leads and the closed path, a rapid up."""
    d = spec.decimals
    plunge = f"G0 X{op.plunge[0]:.{d}f} Y{op.plunge[1]:.{d}f}\n"
    out = []
    n = len(op.depths)
    for k, z in enumerate(op.depths, 1):
        out.append(
            f"({op.name} {k} of {n}: Z{z:.{d}f})\n"
            f"{plunge}"
            f"G1 Z{z:.{d}f} F{spec.plunge_feed:.0f}\n"
            f"{op.lead_in}"
            f"{op.moves}"
            f"{op.lead_out}"
            f"G0 Z{spec.safe_z:.{d}f}\n"
        )
    return "".join(out)
