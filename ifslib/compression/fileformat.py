"""The compact binary file of a code: a header naming the version and the layout, then the fields.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import struct
import zlib
from pathlib import Path

from ..errors import IFSError
from .code import Code
from .config import PARTITIONS, CodeOptions
from .fields import decode_fields, encode_fields
from .fixedformat import fixed_payload, read_fixed

MAGIC = b"IFSC"
HEADER = struct.Struct(">4sBHHBBBBH")  # version 1
HEADER_2 = struct.Struct(">4sBHHBBBHI")
HEADER_3 = struct.Struct(">4sBHHBBBHBI")


def header_bytes(options: CodeOptions) -> int:
    """Bytes of the header a code with ``options`` is written with."""
    return HEADER.size if options.coder == "fixed" else HEADER_3.size if options.deblock else HEADER_2.size


def to_bytes(code: Code) -> bytes:
    """The file's bytes for ``code``: version 1 for ``coder="fixed"``, else version 2."""
    o = code.options
    lo, hi = o.min_block.bit_length() - 1, o.max_block.bit_length() - 1
    if o.coder == "fixed":
        return HEADER.pack(MAGIC, 1, code.height, code.width, lo, hi, o.s_bits, o.m_bits,
                           round(o.s_max * 10000)) + fixed_payload(code)
    payload = encode_fields(code).payload
    layout = (code.height, code.width, list(PARTITIONS).index(o.partition), lo << 4 | hi, o.s_bits << 4 | o.m_bits,
              round(o.s_max * 10000))
    if o.deblock:
        head = HEADER_3.pack(MAGIC, 3, *layout, round(o.deblock * 100), 0)[:-4]
    else:
        head = HEADER_2.pack(MAGIC, 2, *layout, 0)[:-4]
    return head + struct.pack(">I", zlib.crc32(payload, zlib.crc32(head))) + payload


def _options(height: int, width: int, make) -> tuple[int, int, CodeOptions]:
    if height < 8 or width < 8:
        raise IFSError(f"the file's header is corrupt (an image of {height} x {width} pixels)")
    try:
        return height, width, make()
    except IFSError as exc:
        raise IFSError(f"the file's header is corrupt ({exc})") from None


def _version(data: bytes) -> int:
    if data[:4] != MAGIC and not (len(data) < len(MAGIC) and MAGIC.startswith(data)):
        raise IFSError("not a fractal-compressed file (it does not start with IFSC); "
                       "give a file written by `ifslib compress`")
    if len(data) < len(MAGIC) + 1:
        raise IFSError("the compressed file is truncated (it ends inside its header); copy it again")
    version = data[4]
    if version not in (1, 2, 3):
        raise IFSError(f"this file is format version {version}; this ifslib reads versions 1 to 3")
    size = (HEADER, HEADER_2, HEADER_3)[version - 1].size
    if len(data) < size:
        raise IFSError("the compressed file is truncated (it ends inside its header); copy it again")
    return version


def _read_1(data: bytes) -> Code:
    _, _, height, width, lo, hi, s_bits, m_bits, s_max = HEADER.unpack_from(data)
    height, width, o = _options(height, width, lambda: CodeOptions(1 << lo, 1 << hi, s_bits, m_bits, s_max / 10000,
                                                                   coder="fixed"))
    H, W = -(-height // o.max_block) * o.max_block, -(-width // o.max_block) * o.max_block
    return Code(o, height, width, **read_fixed(data[HEADER.size:], H, W, o))


def _read_2(data: bytes, version: int) -> Code:
    if version == 2:
        _, _, height, width, partition, blocks, bits, s_max, crc = HEADER_2.unpack_from(data)
        deblock, size = 0, HEADER_2.size
    else:
        _, _, height, width, partition, blocks, bits, s_max, deblock, crc = HEADER_3.unpack_from(data)
        size = HEADER_3.size
    payload = data[size:]
    if zlib.crc32(payload, zlib.crc32(data[:size - 4])) != crc:
        raise IFSError("the compressed file is corrupt or truncated (its CRC-32 does not match); copy it again")
    if version == 3 and not 0 < deblock <= 50:
        raise IFSError(f"the file's header is corrupt (a deblocking weight of {deblock} hundredths; 1 to 50 are valid)")
    if partition >= len(PARTITIONS):
        raise IFSError(f"the file's header is corrupt (partition {partition}; this ifslib knows "
                       f"{', '.join(PARTITIONS)})")
    height, width, o = _options(height, width, lambda: CodeOptions(1 << (blocks >> 4), 1 << (blocks & 15), bits >> 4,
                                                                   bits & 15, s_max / 10000,
                                                                   partition=list(PARTITIONS)[partition],
                                                                   deblock=deblock / 100))
    H, W = -(-height // o.max_block) * o.max_block, -(-width // o.max_block) * o.max_block
    return Code(o, height, width, **decode_fields(payload, H, W, o))


def from_bytes(data: bytes) -> Code:
    """The code in a file's bytes (version 1, 2 or 3), or `IFSError` for a wrong, truncated or corrupt file."""
    version = _version(data)
    return _read_1(data) if version == 1 else _read_2(data, version)


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
