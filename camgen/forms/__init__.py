"""The cam-form registry: one module per form, one line here.

Adding a form: write ``camgen/forms/<name>.py`` exposing ``FORM`` (a
:class:`~camgen.forms.base.CamForm`) and add its module to :data:`FORM_MODULES`.  A form with a
``read`` and ``build`` realises every displacement-law motion at once.
"""
from __future__ import annotations

from camgen.forms.base import CamForm
from camgen.registry import Registry

__all__ = ["FORM_MODULES", "CamForm", "form_names", "get_form", "register", "unregister"]

#: form name (the ``form`` value in scene files) -> module defining ``FORM``
FORM_MODULES: dict[str, str] = {
    "plate": "camgen.forms.plate",
    "constant_breadth": "camgen.forms.constant_breadth",
    "groove": "camgen.forms.groove",
    "conjugate": "camgen.forms.conjugate",
    "linear": "camgen.forms.linear",
    "barrel": "camgen.forms.barrel",
}

_REGISTRY: Registry[CamForm] = Registry(FORM_MODULES, "FORM")

#: Register (or remove) an entry defined outside this package (plug-ins, tests).
register = _REGISTRY.register
unregister = _REGISTRY.unregister


def form_names() -> list[str]:
    return sorted(_REGISTRY.names())


def get_form(name: str) -> CamForm:
    """The registered form ``name`` (KeyError if none)."""
    return _REGISTRY.get(name)
