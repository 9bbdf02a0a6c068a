"""The cam-form registry: one module per form, one line here.

Adding a form: write ``camgen/forms/<name>.py`` exposing ``FORM`` (a
:class:`~camgen.forms.base.CamForm`) and add its module to :data:`FORM_MODULES`.  A form with a
``read`` and ``build`` realises every displacement-law motion at once.
"""
from __future__ import annotations

import importlib

from camgen.forms.base import CamForm

__all__ = ["FORM_MODULES", "CamForm", "form_names", "get_form", "register", "unregister"]

#: form name (the ``form`` value in scene files) -> module defining ``FORM``
FORM_MODULES: dict[str, str] = {
    "plate": "camgen.forms.plate",
    "constant_breadth": "camgen.forms.constant_breadth",
}

_EXTRA: dict[str, CamForm] = {}


def register(form: CamForm) -> None:
    """Register a form defined outside this package (plug-ins, tests)."""
    _EXTRA[form.name] = form


def unregister(name: str) -> None:
    _EXTRA.pop(name, None)


def form_names() -> list[str]:
    return sorted(set(FORM_MODULES) | set(_EXTRA))


def get_form(name: str) -> CamForm:
    """The registered form ``name`` (KeyError if none)."""
    if name in _EXTRA:
        return _EXTRA[name]
    form: CamForm = importlib.import_module(FORM_MODULES[name]).FORM
    return form
