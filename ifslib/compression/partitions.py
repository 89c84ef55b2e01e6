"""The partitions of a compressed photograph by name, and what the coder needs of each (`Partition`).

A partition is a module of `ifslib.compression` defining its ``PARTITION`` (the quadtree's `repartition`,
the HV partition's `hv`) and its entry in `ifslib.names.PARTITIONS` (the command line's, before torch
loads; its place there is its number in a file's header). The modules are imported at the first look-up,
not with this one: they import the modules (`code`, `fields`, ...) that look partitions up here.
"""
from __future__ import annotations

import functools
import importlib
import pkgutil
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ..names import PARTITIONS


@dataclass(frozen=True)
class Partition:
    """One partition of the image into range blocks.

    Attributes
    ----------
    name : str
        Its key in `ifslib.names.PARTITIONS` (`CodeOptions.partition`).
    rectangles : bool
        Whether its `Code` gives each block's ``block_height`` and ``block_width`` (else squares of ``size``).
    fields : callable
        ``fields(coder, height, width, options, code=None) -> (rows, models)``: every field of a padded
        code through an `entropy.Coder` in the file's order, encoding ``code`` or (None) decoding.
    columns : callable
        ``columns(rows) -> {name: (L,) tensor}``: the `Code`'s fields of the rows ``fields`` decoded.
    at_rate : callable
        ``at_rate(target, pool_image, height, width, options, budget_bits, progress) -> rates.Choice``: the code
        of the padded ``target``, domains cut from ``pool_image``, in ``budget_bits`` (models: `fields.Models` or None).
    at_quality : callable, optional
        ``at_quality(padded, height, width, options, budget_bits, target_err, progress) -> Code``: the
        collage code grown until its squared error is ``target_err``; None where it is chosen at a rate only.
    """

    name: str
    rectangles: bool
    fields: Callable
    columns: Callable
    at_rate: Callable
    at_quality: Callable | None = None


@functools.cache
def table() -> dict[str, Partition]:
    """Every partition by name, in `ifslib.names.PARTITIONS`'s order (a test checks each has its module)."""
    found = {}
    for module in pkgutil.iter_modules([str(Path(__file__).parent)]):
        if entry := getattr(importlib.import_module(f".{module.name}", __package__), "PARTITION", None):
            found[entry.name] = entry
    return {name: found[name] for name in PARTITIONS}


def partition_of(options) -> Partition:
    """The `Partition` a `CodeOptions` names (one of `ifslib.names.PARTITIONS`, checked there)."""
    return table()[options.partition]
