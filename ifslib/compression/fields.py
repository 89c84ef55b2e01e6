"""The fields of a code in the order and the contexts the range coder sees them (file version 2).

Depth first over the quadtree, as version 1: each node above the smallest size says whether it is
split (a model per size); each leaf says whether it is flat (a model per size), then, for a block
with a domain, its contrast level (one model), its mean, and, unless flat, its isometry (one model)
and its domain as an offset from the range (a row and a column model per size). The mean is stored
as its difference (modulo the levels) from a prediction, the mean of the blocks already decoded
just above and to the left, one model for flat blocks and one for the rest. The domain's offset is
counted from the lattice point whose domain is centred on the range, modulo the lattice's rows and
columns, so that near domains cost least once the models have learnt that they are likely.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import torch

from ..errors import IFSError
from .config import CodeOptions
from .domains import ISOMETRIES, domain_step, lattice
from .entropy import Adaptive, Coder, Decoder, Encoder, Magnitude, unzigzag, zigzag
from .partition import walk
from .partitions import partition_of
from .quantize import zero_s

FIELD_NAMES = ("y", "x", "size", "domain", "iso", "s_idx", "m_idx")


class Models:
    """Every adaptive model of one code, fresh (the encoder and the decoder start alike)."""

    def __init__(self, height: int, width: int, options: CodeOptions):
        levels = 2**options.m_bits
        self.split = {size: Adaptive.uniform(2) for size in options.sizes}
        self.flat = {size: Adaptive.uniform(2) for size in options.sizes}
        self.s = Adaptive.uniform(2 * zero_s(options) - 1)
        self.m = {flat: Magnitude(levels) for flat in (False, True)}
        self.iso = Adaptive.uniform(ISOMETRIES)
        self.row, self.col = {}, {}
        for size in options.sizes:
            rows, cols = lattice(height, width, size)
            self.row[size], self.col[size] = Magnitude(rows), Magnitude(cols)


class MeanGrid:
    """The means decoded so far, one cell per ``unit`` pixels (blocks' sides are multiples of it), and the
    prediction of the next block's mean: that of the cells just above and to its left, decoded."""

    def __init__(self, height: int, width: int, unit: int, options: CodeOptions):
        self.unit = unit
        self.cells = np.full((height // unit, width // unit), -1, dtype=np.int64)
        self.middle = 2 ** (options.m_bits - 1)

    def predict(self, y: int, x: int, h: int, w: int) -> int:
        r, c, h, w = y // self.unit, x // self.unit, h // self.unit, w // self.unit
        near = np.concatenate([self.cells[r - 1, c:c + w] if r else self.cells[:0, 0],
                               self.cells[r:r + h, c - 1] if c else self.cells[:0, 0]])
        near = near[near >= 0]
        return int(round(float(near.mean()))) if len(near) else self.middle

    def fill(self, y: int, x: int, h: int, w: int, m: int) -> None:
        u = self.unit
        self.cells[y // u:(y + h) // u, x // u:(x + w) // u] = m


def _centred(y: int, size: int, step: int, count: int) -> int:
    """The lattice index whose domain (2 size wide) is centred on the range starting at ``y``."""
    return min(max(round((y - size / 2) / step), 0), count - 1)


def code_fields(coder: Coder, height: int, width: int, options: CodeOptions, code=None) -> tuple[list[tuple], Models]:
    """Run every field of a padded ``height x width`` code through ``coder``: ``([(y, x, size, domain, iso, s_idx,
    m_idx)], the models as they ended)``.

    Encoding, ``code`` is the `Code` whose fields are coded; decoding, ``code`` is None and the rows
    are what the coder decodes.
    """
    o, models, zero = options, Models(height, width, options), zero_s(options)
    means = MeanGrid(height, width, o.min_block, o)
    levels = 2**o.m_bits
    leaf = None if code is None else {(int(s), int(y), int(x)): i
                                      for i, (s, y, x) in enumerate(zip(code.size, code.y, code.x))}

    def value(name, i):
        return None if leaf is None else int(getattr(code, name)[i])

    def is_split(node) -> bool:
        want = None if leaf is None else int(node not in leaf)
        return coder.code(models.split[node[0]], want, ("split", node[0], want)) == 1

    rows = []
    for node, split in walk(height, width, o, is_split):
        if split:
            continue
        size, y, x = node
        i = None if leaf is None else leaf.get(node)
        if leaf is not None and i is None:
            raise IFSError(f"the code's blocks do not tile its quadtree (no block at {node})")
        s_idx = value("s_idx", i)
        want = None if s_idx is None else int(s_idx == zero)
        flat = coder.code(models.flat[size], want, ("flat", size, want)) == 1
        if not flat:
            s_sym = coder.code(models.s, None if s_idx is None else s_idx - (s_idx > zero), ("s",))
            s_idx = s_sym + (s_sym >= zero)
        else:
            s_idx = zero
        guess, m_idx = means.predict(y, x, size, size), value("m_idx", i)
        residual = coder.code_magnitude(models.m[flat], None if m_idx is None else zigzag(m_idx - guess, levels),
                                        ("m", flat))
        m_idx = (guess + unzigzag(residual, levels)) % levels
        means.fill(y, x, size, size, m_idx)
        iso = domain = 0
        if not flat:
            iso = coder.code(models.iso, value("iso", i), ("iso",))
            domain = _code_domain(coder, models, node, height, width, value("domain", i))
        rows.append((y, x, size, domain, iso, s_idx, m_idx))
    return rows, models


def _code_domain(coder: Coder, models: Models, node, height: int, width: int, domain: int | None) -> int:
    size, y, x = node
    n_rows, n_cols = lattice(height, width, size)
    step = domain_step(height, width, size)
    r0, c0 = _centred(y, size, step, n_rows), _centred(x, size, step, n_cols)
    want_r = None if domain is None else zigzag(domain // n_cols - r0, n_rows)
    want_c = None if domain is None else zigzag(domain % n_cols - c0, n_cols)
    r = (unzigzag(coder.code_magnitude(models.row[size], want_r, ("row", size)), n_rows) + r0) % n_rows
    c = (unzigzag(coder.code_magnitude(models.col[size], want_c, ("col", size)), n_cols) + c0) % n_cols
    return r * n_cols + c


class Coded(NamedTuple):
    """A code's range-coded fields: the ``payload``, the ideal bits spent under each key (``ledger``,
    `entropy.Coder`) and the ``models`` as they ended (what each value would cost now)."""

    payload: bytes
    ledger: dict
    models: Models


def columns(rows: list[tuple]) -> dict[str, torch.Tensor]:
    """The `Code` fields (`FIELD_NAMES`, ``(L,)`` int64 each) of the rows `code_fields` decoded."""
    if not rows:
        raise IFSError("the file is corrupt (it codes no block)")
    return {name: torch.tensor(column, dtype=torch.long) for name, column in zip(FIELD_NAMES, zip(*rows))}


def encode_fields(code) -> Coded:
    """The range-coded fields of ``code`` (a `Code`, of any partition)."""
    H, W = code.padded
    coder = Encoder()
    _, models = partition_of(code.options).fields(coder, H, W, code.options, code)
    return Coded(coder.payload(), dict(coder.ledger), models)


def decode_fields(payload: bytes, height: int, width: int, options: CodeOptions) -> dict[str, torch.Tensor]:
    """The `Code` fields of a padded ``height x width`` code from its payload."""
    kind = partition_of(options)
    return kind.columns(kind.fields(Decoder(payload), height, width, options)[0])
