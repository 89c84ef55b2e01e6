"""The compact binary file of a code: a 15-byte header, then the quadtree and the maps bit by bit.

Header (big-endian): ``b"IFSC"``, version (1 byte), height and width (2 bytes each), log2 of the
smallest and largest blocks, s_bits and m_bits (1 byte each), s_max x 10000 (2 bytes). Then, depth
first over the quadtree: a split flag for every node larger than the smallest block and, at each leaf,
s (s_bits), m (m_bits) and, unless s = 0, the isometry (3 bits) and the domain (`domains.domain_bits`).
The last byte is padded with zeros.
"""
from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import torch

from ..errors import IFSError
from .code import Code
from .config import CodeOptions
from .domains import ISOMETRY_BITS, domain_bits, domain_count
from .partition import walk
from .quantize import zero_s

MAGIC = b"IFSC"
VERSION = 1
HEADER = struct.Struct(">4sBHHBBBBH")


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


def to_bytes(code: Code) -> bytes:
    """The file's bytes for ``code``."""
    o = code.options
    H, W = code.padded
    header = HEADER.pack(MAGIC, VERSION, code.height, code.width, o.min_block.bit_length() - 1,
                         o.max_block.bit_length() - 1, o.s_bits, o.m_bits, round(o.s_max * 10000))
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
    return header + out.bytes()


def _header(data: bytes) -> tuple[int, int, CodeOptions]:
    if len(data) < len(MAGIC) or data[:4] != MAGIC:
        raise IFSError("not a fractal-compressed file (it does not start with IFSC); "
                       "give a file written by `ifslib compress`")
    if len(data) < HEADER.size:
        raise IFSError("the compressed file is truncated (it ends inside its header); copy it again")
    _, version, height, width, lo, hi, s_bits, m_bits, s_max = HEADER.unpack_from(data)
    if version != VERSION:
        raise IFSError(f"this file is format version {version}; this ifslib reads version {VERSION} only")
    if height < 8 or width < 8:
        raise IFSError(f"the file's header is corrupt (an image of {height} x {width} pixels)")
    try:
        return height, width, CodeOptions(1 << lo, 1 << hi, s_bits, m_bits, s_max / 10000)
    except IFSError as exc:
        raise IFSError(f"the file's header is corrupt ({exc})") from None


def from_bytes(data: bytes) -> Code:
    """The code in a file's bytes, or `IFSError` for a wrong, truncated or corrupt file."""
    height, width, o = _header(data)
    code = Code(o, height, width, *(torch.empty(0, dtype=torch.long) for _ in range(7)))
    H, W = code.padded
    bits, zero, rows = BitReader(data[HEADER.size:]), zero_s(o), []
    for node, split in walk(H, W, o, lambda n: bits.get(1) == 1):
        if split:
            continue
        s_idx, m_idx = bits.get(o.s_bits), bits.get(o.m_bits)
        iso = domain = 0
        if s_idx != zero:
            iso, domain = bits.get(ISOMETRY_BITS), bits.get(domain_bits(H, W, node[0]))
            if domain >= domain_count(H, W, node[0]):
                raise IFSError(f"the file is corrupt: domain {domain} of a {node[0]} px block is past the pool's "
                               f"{domain_count(H, W, node[0])}")
        rows.append((node[2], node[1], node[0], domain, iso, s_idx, m_idx))
    if len(data) - HEADER.size != (bits.at + 7) // 8:
        raise IFSError(f"the file has {len(data) - HEADER.size - (bits.at + 7) // 8} bytes after its code; "
                       "it is not one compressed image")
    x, y, size, domain, iso, s_idx, m_idx = (torch.tensor(c, dtype=torch.long) for c in zip(*rows))
    return Code(o, height, width, y, x, size, domain, iso, s_idx, m_idx)


def write(code: Code, path) -> int:
    """Write ``code`` to ``path``; returns the bytes written."""
    data = to_bytes(code)
    Path(path).write_bytes(data)
    return len(data)


def read(path) -> Code:
    """The code in the file at ``path`` (`IFSError` for a missing, wrong or truncated file)."""
    path = Path(path)
    if not path.is_file():
        raise IFSError(f"no compressed file at {str(path)!r}")
    return from_bytes(path.read_bytes())
