"""File version 1's fields: depth first over the quadtree, every field its fixed number of bits.

A split flag for every node larger than the smallest block and, at each leaf, s (s_bits), m (m_bits)
and, unless s = 0, the isometry (3 bits) and the domain (`domains.domain_bits`). The last byte is
padded with zeros. Still written for ``CodeOptions(coder="fixed")``, and read for old files.
"""
from __future__ import annotations

import numpy as np
import torch

from ..errors import IFSError
from .config import CodeOptions
from .domains import ISOMETRY_BITS, domain_bits, domain_count
from .fields import FIELD_NAMES
from .partition import walk
from .quantize import zero_s


class BitWriter:
    """Unsigned integers of given widths, most significant bit first."""

    def __init__(self):
        self.bits: list[int] = []

    def put(self, value: int, width: int) -> None:
        self.bits.extend((value >> (width - 1 - i)) & 1 for i in range(width))

    def bytes(self) -> bytes:
        return np.packbits(np.array(self.bits, dtype=np.uint8)).tobytes()


class BitReader:
    """Reads what `BitWriter` wrote; a read past the end is a truncated file."""

    def __init__(self, data: bytes):
        self.bits = np.unpackbits(np.frombuffer(data, dtype=np.uint8))
        self.at = 0

    def get(self, width: int) -> int:
        if self.at + width > len(self.bits):
            raise IFSError("the compressed file is truncated (it ends inside the code); copy it again")
        value = 0
        for bit in self.bits[self.at:self.at + width]:
            value = (value << 1) | int(bit)
        self.at += width
        return value


def fixed_payload(code) -> bytes:
    """The version 1 fields of ``code`` (a `Code`), bit-packed."""
    o = code.options
    H, W = code.padded
    leaf = {(int(s), int(y), int(x)): i for i, (s, y, x) in enumerate(zip(code.size, code.y, code.x))}
    out, zero = BitWriter(), zero_s(o)
    for node, split in walk(H, W, o, lambda n: n not in leaf):
        if node[0] > o.min_block:
            out.put(int(split), 1)
        if not split:
            i = leaf[node]
            out.put(int(code.s_idx[i]), o.s_bits)
            out.put(int(code.m_idx[i]), o.m_bits)
            if int(code.s_idx[i]) != zero:
                out.put(int(code.iso[i]), ISOMETRY_BITS)
                out.put(int(code.domain[i]), domain_bits(H, W, node[0]))
    return out.bytes()


def read_fixed(payload: bytes, height: int, width: int, o: CodeOptions) -> dict[str, torch.Tensor]:
    """The fields (`fields.FIELD_NAMES`) of a padded ``height x width`` code from its version 1 payload."""
    bits, zero, rows = BitReader(payload), zero_s(o), []
    for node, split in walk(height, width, o, lambda n: bits.get(1) == 1):
        if split:
            continue
        s_idx, m_idx = bits.get(o.s_bits), bits.get(o.m_bits)
        iso = domain = 0
        if s_idx != zero:
            iso, domain = bits.get(ISOMETRY_BITS), bits.get(domain_bits(height, width, node[0]))
            if domain >= domain_count(height, width, node[0]):
                raise IFSError(f"the file is corrupt: domain {domain} of a {node[0]} px block is past the pool's "
                               f"{domain_count(height, width, node[0])}")
        rows.append((node[1], node[2], node[0], domain, iso, s_idx, m_idx))
    if len(payload) != (bits.at + 7) // 8:
        raise IFSError(f"the file has {len(payload) - (bits.at + 7) // 8} bytes after its code; "
                       "it is not one compressed image")
    return {name: torch.tensor(column, dtype=torch.long) for name, column in zip(FIELD_NAMES, zip(*rows))}
