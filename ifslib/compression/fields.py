"""The fields of a code in the order and the contexts the range coder sees them (file version 2).

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import torch

from ..errors import IFSError
from .config import CodeOptions
from .domains import ISOMETRIES, lattice
from .entropy import Adaptive, Coder, Decoder, Encoder, Magnitude, unzigzag, zigzag
from .partition import walk
from .partitions import partition_of
from .quantize import zero_s
from .rectangles import isometry_count, rectangle_lattice, rectangle_step

FIELD_NAMES = ("y", "x", "size", "domain", "iso", "s_idx", "m_idx")


class Models:
    """Every adaptive model of one code, fresh (the encoder and the decoder start alike)."""

    def __init__(self, height: int, width: int, options: CodeOptions):
        levels = 2**options.m_bits
        self.split = {size: Adaptive.uniform(2) for size in options.sizes}
        self.flat = {size: Adaptive.uniform(2) for size in options.sizes}
        self.s = Adaptive.uniform(2 * zero_s(options) - 1)
        self.m = {flat: Magnitude(levels) for flat in (False, True)}
        self.iso = {ISOMETRIES: Adaptive.uniform(ISOMETRIES)}
        self.row, self.col = {}, {}
        for size in options.sizes:
            rows, cols = lattice(height, width, size)
            self.row[size], self.col[size] = Magnitude(rows), Magnitude(cols)

    def lattice_models(self, shape: tuple[int, int], rows: int, cols: int) -> tuple[Magnitude, Magnitude]:
        return self.row[shape[0]], self.col[shape[0]]


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


def code_fields(coder: Coder, height: int, width: int, options: CodeOptions, code=None) -> tuple[list[tuple], Models]:
    """Run every field of a padded ``height x width`` code through ``coder``: ``([(y, x, size, domain, iso, s_idx,
    m_idx)], the models as they ended)``.

    Encoding, ``code`` is the `Code` whose fields are coded; decoding, ``code`` is None and the rows
    are what the coder decodes.
    """
    o, models, means = options, Models(height, width, options), MeanGrid(height, width, options.min_block, options)
    leaf = None if code is None else {(int(s), int(y), int(x)): i
                                      for i, (s, y, x) in enumerate(zip(code.size, code.y, code.x))}

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
        rows.append((y, x, size, *code_leaf(coder, models, (y, x, size, size), means, height, width, o, code, i,
                                            (size,))))
    return rows, models


def code_leaf(coder: Coder, models, block, means: MeanGrid, height: int, width: int, options: CodeOptions, code, i,
              key: tuple = ()) -> tuple[int, int, int, int]:
    """Run the fields of leaf ``block`` ``(y, x, height, width)`` through ``coder`` (``code``'s block ``i``
    encoding, None decoding): ``(domain, iso, s_idx, m_idx)``. The ledger's keys carry ``key`` (the
    quadtree's block size: its rates price each size apart); ``models`` is either partition's."""
    y, x, h, w = block
    zero, levels = zero_s(options), 2**options.m_bits

    def value(name):
        return None if code is None else int(getattr(code, name)[i])

    s_idx = value("s_idx")
    want = None if s_idx is None else int(s_idx == zero)
    flat = coder.code(models.flat[min(h, w)], want, ("flat", *key, want)) == 1
    if not flat:
        s_sym = coder.code(models.s, None if s_idx is None else s_idx - (s_idx > zero), ("s",))
        s_idx = s_sym + (s_sym >= zero)
    else:
        s_idx = zero
    guess, m_idx = means.predict(*block), value("m_idx")
    want = None if m_idx is None else zigzag(m_idx - guess, levels)
    m_idx = (guess + unzigzag(coder.code_magnitude(models.m[flat], want, ("m", flat)), levels)) % levels
    means.fill(*block, m_idx)
    iso = domain = 0
    if not flat:
        iso = coder.code(models.iso[isometry_count(h, w)], value("iso"), ("iso",))
        domain = _code_domain(coder, models, block, height, width, value("domain"), key)
    return domain, iso, s_idx, m_idx


def _code_domain(coder: Coder, models, block, height: int, width: int, domain: int | None, key: tuple) -> int:
    """The domain as its offset on its shape's lattice from the one centred on the range, modulo rows and columns."""
    y, x, h, w = block
    n_rows, n_cols = rectangle_lattice(height, width, h, w)
    sy, sx = rectangle_step(height, width, h, w)
    r0 = min(max(round((y - h / 2) / sy), 0), n_rows - 1)
    c0 = min(max(round((x - w / 2) / sx), 0), n_cols - 1)
    row_model, col_model = models.lattice_models((h, w), n_rows, n_cols)
    want_r = None if domain is None else zigzag(domain // n_cols - r0, n_rows)
    want_c = None if domain is None else zigzag(domain % n_cols - c0, n_cols)
    r = (unzigzag(coder.code_magnitude(row_model, want_r, ("row", *key)), n_rows) + r0) % n_rows
    c = (unzigzag(coder.code_magnitude(col_model, want_c, ("col", *key)), n_cols) + c0) % n_cols
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
