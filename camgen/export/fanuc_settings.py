"""The settings only a Fanuc/Haas program has: program number, tool number, radius register.

They are checked here (:func:`check_fanuc_settings`, called by
:class:`camgen.export.gcode_spec.MachiningSpec`) and resolved to their defaults
(:func:`fanuc_numbers`); the program's words are :mod:`camgen.export.gcode_fanuc`.  A setting given
with another dialect is refused: it would change nothing.
"""
from __future__ import annotations

from dataclasses import dataclass

from camgen.errors import ParameterError

__all__ = ["DEFAULT_PROGRAM_NUMBER", "DEFAULT_TOOL_NUMBER", "FANUC_DIALECT", "FanucNumbers", "MAX_PROGRAM_NUMBER", "MAX_RADIUS_REGISTER",
           "MAX_TOOL_NUMBER", "check_fanuc_settings", "fanuc_numbers"]

#: The dialect name of Fanuc / Haas / the ISO modes of Okuma and Mazak.
FANUC_DIALECT = "fanuc"
#: ``O`` program numbers: four digits (O0001..O9999).
MAX_PROGRAM_NUMBER = 9999
DEFAULT_PROGRAM_NUMBER = 1
#: ``T`` tool numbers (two digits, what every Fanuc-style changer takes); ``G43 H`` uses the same number.
MAX_TOOL_NUMBER = 99
DEFAULT_TOOL_NUMBER = 1
#: ``D`` offset registers (Fanuc tables hold 400 or 999; Haas 200: the header names the one used).
MAX_RADIUS_REGISTER = 999


@dataclass(frozen=True)
class FanucNumbers:
    """The numbers a Fanuc program uses: ``O`` program, ``T``/``H`` tool and length offset, ``D`` radius register."""

    program: int
    tool: int
    radius_register: int


def _whole(name: str, value: object, high: int) -> None:
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= high:
        raise ParameterError(name, value, f"a whole number, 1 <= n <= {high}")


def check_fanuc_settings(dialect: str, program_number: int | None, tool_number: int | None, radius_register: int | None) -> None:
    """Refuse a Fanuc setting out of range, or given for another dialect (it would change nothing)."""
    given = {"program_number": program_number, "tool_number": tool_number, "radius_register": radius_register}
    if dialect != FANUC_DIALECT:
        for name, value in given.items():
            if value is not None:
                raise ParameterError(name, value, f"only with dialect = '{FANUC_DIALECT}'", f"the {dialect} program has no such word")
    _whole("program_number", program_number, MAX_PROGRAM_NUMBER)
    _whole("tool_number", tool_number, MAX_TOOL_NUMBER)
    _whole("radius_register", radius_register, MAX_RADIUS_REGISTER)


def fanuc_numbers(program_number: int | None, tool_number: int | None, radius_register: int | None) -> FanucNumbers:
    """The numbers with their defaults: program 1, tool 1, the radius register the tool's number."""
    tool = DEFAULT_TOOL_NUMBER if tool_number is None else tool_number
    return FanucNumbers(DEFAULT_PROGRAM_NUMBER if program_number is None else program_number, tool,
                        tool if radius_register is None else radius_register)
