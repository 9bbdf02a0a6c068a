"""The mechanisms of the papers camgen reproduces (the tricycle's steering cam, the horse leg),
one module each.  The package namespace imports none of them: import the module you need."""
from __future__ import annotations

__all__: list[str] = []
