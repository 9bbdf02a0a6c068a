"""The bore settings of a milling program (``bore_operation``, ``bore_tool_diameter``,
``bore_tool_number``): checked here (:func:`check_bore_settings`, called by
:class:`camgen.export.gcode_spec.MachiningSpec`) and resolved to their defaults; the blocks that
cut the bore are :mod:`camgen.export.gcode_bore`.  A setting given where it would change nothing
is refused.
"""
from __future__ import annotations

from camgen.errors import ParameterError, require_positive
from camgen.export.fanuc_settings import DEFAULT_TOOL_NUMBER, MAX_TOOL_NUMBER

__all__ = ["BORE_OPERATIONS", "MILLING_DIALECTS", "TOOL_CHANGERS", "WIRE_DIALECT", "bore_operation_of", "bore_tool_number_of", "check_bore_settings",
           "outline_tool_number"]

#: Values of ``bore_operation``: milled by a helix, drilled, cut by the wire (wire EDM), left to another operation.
BORE_OPERATIONS = ("helix", "drill", "wire", "none")
#: The wire-EDM dialect (its bore: :mod:`camgen.export.wire_edm_bore`).
WIRE_DIALECT = "wire_edm"
#: Dialects whose programs mill (the bore settings apply).
MILLING_DIALECTS = ("linuxcnc", "grbl", "fanuc")
#: Dialects with a tool changer (``T<n> M6`` and ``G43 H<n>``).
TOOL_CHANGERS = ("linuxcnc", "fanuc")


def outline_tool_number(tool_number: int | None) -> int:
    """The outline's tool number: ``tool_number`` (fanuc), else :data:`DEFAULT_TOOL_NUMBER`."""
    return DEFAULT_TOOL_NUMBER if tool_number is None else tool_number


def check_bore_settings(dialect: str, tool_number: int | None, op: str | None, tool: float | None, number: int | None,
                        wire_compensation: bool = True) -> None:
    """Refuse bore settings out of range or where they would change nothing: ``op`` the
    operation, ``tool`` the bore tool's diameter (mm), ``number`` its tool number;
    ``wire_compensation``: the wire-EDM program uses the control's wire offset (the bore's wire
    cuts need it: their wire-centre path is not built)."""
    if op is not None and op not in BORE_OPERATIONS:
        raise ParameterError("bore_operation", op, f"one of {BORE_OPERATIONS}")
    if op == "wire" and not wire_compensation:
        raise ParameterError("bore_operation", op, '"none" with wire_compensation = false',
                             "the bore is cut with the control's wire offset G41 D<k> only; set wire_compensation = true")
    if op is not None and op != "none" and (op == "wire") != (dialect == WIRE_DIALECT):
        raise ParameterError("bore_operation", op, '"wire" or "none" with dialect = "wire_edm"' if dialect == WIRE_DIALECT else
                             '"helix", "drill" or "none" with a milling dialect', f"the {dialect} program cannot cut the bore that way")
    if op == "drill" and dialect not in TOOL_CHANGERS:
        raise ParameterError("bore_operation", op, f'"drill" only with dialect = {" or ".join(TOOL_CHANGERS)}',
                             "GRBL has no canned drilling cycle (G83)")
    if dialect not in MILLING_DIALECTS:
        for name, value in (("bore_tool_diameter", tool), ("bore_tool_number", number)):
            if value is not None:
                raise ParameterError(name, value, f"only with dialect = {' or '.join(MILLING_DIALECTS)}", f"the {dialect} program mills no bore")
    if tool is not None:
        require_positive("bore_tool_diameter", tool)
        if op in ("none", "drill"):
            raise ParameterError("bore_tool_diameter", tool, f'left out with bore_operation = "{op}"',
                                 "no bore is milled" if op == "none" else "the drill has the bore's diameter")
    if number is not None:
        if isinstance(number, bool) or not isinstance(number, int) or not 1 <= number <= MAX_TOOL_NUMBER:
            raise ParameterError("bore_tool_number", number, f"a whole number, 1 <= n <= {MAX_TOOL_NUMBER}")
        if dialect not in TOOL_CHANGERS:
            raise ParameterError("bore_tool_number", number, f"only with dialect = {' or '.join(TOOL_CHANGERS)}",
                                 "GRBL has no tool changer: the program stops (M0) for the change")
        if tool is None and op != "drill":
            raise ParameterError("bore_tool_number", number, 'only with bore_tool_diameter_mm or bore_operation = "drill"',
                                 "without it the outline's tool cuts the bore, no tool change")
        if number == outline_tool_number(tool_number):
            raise ParameterError("bore_tool_number", number, f"another number than the outline's tool T{number}")


def bore_operation_of(op: str | None, tool: float | None, dialect: str, wire_compensation: bool = True) -> str:
    """The operation ``op`` resolved: a wire program cuts the bore (``"wire"``; ``"none"`` with
    ``wire_compensation`` off: the bore's wire cuts use the wire offset); a milling one mills it
    (``"helix"``) when a bore tool is given, else leaves it (``"none"``)."""
    if op is not None:
        return op
    if dialect == WIRE_DIALECT:
        return "wire" if wire_compensation else "none"
    return "helix" if tool is not None else "none"


def bore_tool_number_of(number: int | None, tool_number: int | None) -> int:
    """The bore tool's number: ``number``, else the outline's tool number + 1 (- 1 for the last)."""
    if number is not None:
        return number
    main = outline_tool_number(tool_number)
    return main + 1 if main < MAX_TOOL_NUMBER else main - 1
