"""An HV code's fields in the order and contexts the range coder sees them (file version 2, partition "hv").

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

from collections import defaultdict

import numpy as np
import torch

from ..errors import IFSError
from .config import HV_STEP, CodeOptions
from .entropy import Adaptive, Coder, Magnitude
from .fields import MeanGrid, code_leaf
from .quantize import zero_s
from .rectangles import Block, cut_positions, split_block


class HVModels:
    """The adaptive models of one HV code, made the first time a context is met (alike in encoder and decoder)."""

    def __init__(self, options: CodeOptions):
        self.split = defaultdict(lambda: Adaptive.uniform(2))
        self.axis = Adaptive.uniform(2)
        self.position = {}
        self.flat = defaultdict(lambda: Adaptive.uniform(2))
        self.s = Adaptive.uniform(2 * zero_s(options) - 1)
        self.m = {flat: Magnitude(2**options.m_bits) for flat in (False, True)}
        self.iso = {n: Adaptive.uniform(n) for n in (4, 8)}
        self.row, self.col = {}, {}

    def place(self, count: int) -> Adaptive:
        return self.position.setdefault(count, Adaptive.uniform(count))

    def lattice_models(self, shape, rows: int, cols: int) -> tuple[Magnitude, Magnitude]:
        return self.row.setdefault(shape, Magnitude(rows)), self.col.setdefault(shape, Magnitude(cols))


def _cut(owner: np.ndarray | None, block: Block, options: CodeOptions) -> tuple[int, int] | None:
    """The encoder's cut of ``block``: the first axis and position no leaf crosses (None: a leaf)."""
    y, x, h, w = block
    if owner[y, x] == owner[y + h - 1, x + w - 1]:
        return None
    for p in cut_positions(h, options.min_block):
        if (owner[y + p - 1, x:x + w] != owner[y + p, x:x + w]).all():
            return 0, p
    for p in cut_positions(w, options.min_block):
        if (owner[y:y + h, x + p - 1] != owner[y:y + h, x + p]).all():
            return 1, p
    raise IFSError(f"the code's blocks are not an HV partition (no cut of {tuple(block)} leaves them whole)")


def code_hv_fields(coder: Coder, height: int, width: int, options: CodeOptions, code=None) -> tuple[list[tuple], HVModels]:
    """Run every field of a padded ``height x width`` HV code through ``coder``: ``([(y, x, height, width,
    domain, iso, s_idx, m_idx)], the models)``. Encoding, ``code`` is the `Code`; decoding, None."""
    o, models, b, means = options, HVModels(options), options.max_block, MeanGrid(height, width, HV_STEP, options)
    owner, index = None, {}
    if code is not None:
        owner = np.full((height, width), -1, dtype=np.int64)
        for i, (y, x, h, w) in enumerate(zip(*(t.tolist() for t in (code.y, code.x, code.heights, code.widths)))):
            owner[y:y + h, x:x + w] = i
            index[(y, x, h, w)] = i
        if (owner < 0).any():
            raise IFSError("the code's blocks do not cover its image")
    rows, stack = [], [Block(y, x, b, b) for y in range(height - b, -1, -b) for x in range(width - b, -1, -b)]
    while stack:
        block = stack.pop()
        y, x, h, w = block
        cuts = (cut_positions(h, o.min_block), cut_positions(w, o.min_block))
        want = None if code is None else _cut(owner, block, o)
        split = bool(cuts[0] or cuts[1]) and coder.code(
            models.split[min(h, w)], None if code is None else int(want is not None),
            ("split", None if code is None else int(want is not None))) == 1
        if split:
            axis = (0 if not cuts[1] else 1 if not cuts[0] else
                    coder.code(models.axis, None if code is None else want[0], ("axis",)))
            at = coder.code(models.place(len(cuts[axis])), None if code is None else cuts[axis].index(want[1]),
                            ("place",))
            stack += list(reversed(split_block(block, axis, cuts[axis][at])))
            continue
        i = None if code is None else index.get(tuple(block))
        if code is not None and i is None:
            raise IFSError(f"the code's blocks are not an HV partition (no block at {tuple(block)})")
        rows.append((*block, *code_leaf(coder, models, block, means, height, width, o, code, i)))
    return rows, models


def hv_columns(rows: list[tuple]) -> dict[str, torch.Tensor]:
    """The `Code` fields of decoded HV rows: ``y, x, size`` (the longer side), the sides and the maps."""
    if not rows:
        raise IFSError("the file is corrupt (it codes no block)")
    y, x, h, w, domain, iso, s_idx, m_idx = (torch.tensor(c, dtype=torch.long) for c in zip(*rows))
    return dict(y=y, x=x, size=torch.maximum(h, w), domain=domain, iso=iso, s_idx=s_idx, m_idx=m_idx,
                block_height=h, block_width=w)
