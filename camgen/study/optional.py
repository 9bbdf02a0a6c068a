"""Optional packages of the study commands, imported when used, refused in one line when absent."""
from __future__ import annotations

import importlib
from types import ModuleType

from camgen.errors import CamgenError

__all__ = ["MissingExtra", "require"]


class MissingExtra(CamgenError):
    """An optional package a command needs is not installed (exit 2: install the extra)."""


def require(module: str, what: str, extra: str = "sweep") -> ModuleType:
    """``module`` imported, or :class:`MissingExtra` naming the extra that installs it."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtra(f"{what} needs the Python package '{module.split('.')[0]}': install camgen's '{extra}' extra "
                           f"(python3 -m pip install \"camgen[{extra}]\")") from None
