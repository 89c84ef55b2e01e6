"""The kinds of primitive, one module each defining a ``SHAPE``: a new kind is a module here, its test and its
entry in the ``ifslib/1`` JSON Schema (a test says the two agree)."""
from __future__ import annotations

import importlib
import pkgutil

from .shape import PARAM_WIDTH, Shape

#: kind -> Shape, in the modules' alphabetical order.
SHAPES: dict[str, Shape] = {}
for _module in pkgutil.iter_modules(__path__):
    _shape = getattr(importlib.import_module(f".{_module.name}", __name__), "SHAPE", None)
    if _shape is not None:
        SHAPES[_shape.kind] = _shape

__all__ = ["PARAM_WIDTH", "SHAPES", "Shape"]
