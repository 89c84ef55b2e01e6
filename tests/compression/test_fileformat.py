"""The file: exact round trips in every version, old files read as before, and one clear error for a wrong,
truncated, padded or corrupt file."""
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.decode import decode
from ifslib.compression.encode import encode
from ifslib.compression.fileformat import HEADER, HEADER_2, HEADER_3, from_bytes, read, to_bytes, write
from ifslib.errors import IFSError
from compression_images import photo

FIELDS = ("y", "x", "size", "domain", "iso", "s_idx", "m_idx")
DATA = Path(__file__).parent / "data"


@pytest.mark.parametrize("coder", ["fixed", "adaptive"])
@pytest.mark.parametrize("layout", [dict(min_block=4, max_block=16),
                                    dict(min_block=8, max_block=8, s_bits=3, m_bits=9, s_max=0.5)])
def test_round_trip_is_exact(tmp_path, layout, coder):
    options = CodeOptions(**layout, coder=coder)
    code = encode(photo(40)[:, :36], options, bpp=1.5)
    back = read(tmp_path / "a.ifsc") if write(code, tmp_path / "a.ifsc") else None
    assert (back.height, back.width, back.options) == (40, 36, options)
    for name in FIELDS:
        assert torch.equal(getattr(back, name), getattr(code, name)), name


def test_a_version_1_file_of_the_previous_release_decodes_as_it_did():
    """``data/version1.ifsc``: an attractor code of ``photo(40)[:, :36]`` written by commit 8d74e3d, and its decoding."""
    data = (DATA / "version1.ifsc").read_bytes()
    assert data[4] == 1
    code = from_bytes(data)
    assert code.options.coder == "fixed" and (code.height, code.width) == (40, 36)
    assert np.allclose(decode(code).image.numpy(), np.load(DATA / "version1_decoded.npy"), atol=1e-6)
    assert to_bytes(code) == data  # written again, byte for byte


@pytest.mark.parametrize("partition", ["quadtree", "hv"])
def test_a_version_2_file_of_the_previous_release_decodes_as_it_did(partition):
    """``data/version2_*.ifsc``: attractor codes of ``photo(40)[:, :36]`` at 1 bpp written by commit c24b3cc
    (before the deblocking filter), and their decodings: read unfiltered, and written again byte for byte."""
    data = (DATA / f"version2_{partition}.ifsc").read_bytes()
    assert data[4] == 2
    code = from_bytes(data)
    assert code.options.partition == partition and code.options.deblock == 0
    assert np.array_equal(decode(code).image.numpy(), np.load(DATA / f"version2_{partition}_decoded.npy"))
    assert to_bytes(code) == data


@pytest.mark.parametrize("partition", ["quadtree", "hv"])
def test_the_deblocking_weight_round_trips_in_version_3(partition):
    options = CodeOptions(min_block=4, max_block=16, partition=partition, deblock=0.17)
    code = encode(photo(40)[:, :36], options, bpp=1.5)
    data = to_bytes(code)
    assert data[4] == 3 and data[HEADER_3.size - 5] == 17
    back = from_bytes(data)
    assert back.options == options
    for name in FIELDS:
        assert torch.equal(getattr(back, name), getattr(code, name)), name
    assert torch.equal(decode(back).image, decode(code).image)
    assert to_bytes(back) == data


def test_wrong_truncated_and_corrupt_version_3_files():
    data = to_bytes(encode(photo(32), CodeOptions(min_block=4, max_block=16, deblock=0.25), bpp=1.0))
    assert data[4] == 3 and data[HEADER_3.size - 5] == 25
    for cut in (5, HEADER_2.size, HEADER_3.size, len(data) - 1):
        with pytest.raises(IFSError, match="truncated"):
            from_bytes(data[:cut])
    for at in (HEADER_3.size - 5, HEADER_3.size - 1, HEADER_3.size + 2):  # the weight, the CRC, the fields
        bad = bytearray(data)
        bad[at] ^= 1
        with pytest.raises(IFSError, match="corrupt"):
            from_bytes(bytes(bad))
    # a weight out of range with a CRC that matches it: refused by name, not decoded
    for weight in (0, 51):
        head = data[:HEADER_3.size - 5] + bytes([weight])
        payload = data[HEADER_3.size:]
        forged = head + struct.pack(">I", zlib.crc32(payload, zlib.crc32(head))) + payload
        with pytest.raises(IFSError, match="deblocking weight"):
            from_bytes(forged)


def test_the_filter_needs_the_adaptive_coder_and_hundredths():
    with pytest.raises(IFSError, match="adaptive coder"):
        CodeOptions(coder="fixed", deblock=0.1)
    for bad in (-0.1, 0.6, 0.123, "0.1", True):
        with pytest.raises(IFSError, match="deblock"):
            CodeOptions(deblock=bad)


def test_wrong_truncated_padded_and_corrupt_version_1_files():
    data = to_bytes(encode(photo(32), CodeOptions(min_block=4, max_block=16, coder="fixed"), bpp=1.0))
    with pytest.raises(IFSError, match="IFSC"):
        from_bytes(b"\x89PNG" + data[4:])
    with pytest.raises(IFSError, match="truncated"):
        from_bytes(data[:10])
    with pytest.raises(IFSError, match="truncated"):
        from_bytes(data[:-3])
    with pytest.raises(IFSError, match="after its code"):
        from_bytes(data + b"\x00")
    with pytest.raises(IFSError, match="version 4"):
        from_bytes(data[:4] + b"\x04" + data[5:])
    with pytest.raises(IFSError, match="header is corrupt"):
        from_bytes(data[:HEADER.size - 4] + b"\x09" + data[HEADER.size - 3:])  # s_bits = 9


def test_wrong_truncated_padded_and_corrupt_version_2_files():
    data = to_bytes(encode(photo(32), CodeOptions(min_block=4, max_block=16), bpp=1.0))
    assert data[4] == 2
    with pytest.raises(IFSError, match="IFSC"):
        from_bytes(b"GIF8" + data[4:])
    for cut in (3, 5, 10, HEADER_2.size, len(data) - 1):
        with pytest.raises(IFSError, match="truncated"):
            from_bytes(data[:cut])
    with pytest.raises(IFSError, match="corrupt"):
        from_bytes(data + b"\x00")
    rng = np.random.default_rng(0)
    for at in [5, 9, 10, 12, *rng.integers(HEADER_2.size, len(data), 8)]:  # any byte but the magic and version
        for bit in (0, 5):
            bad = bytearray(data)
            bad[at] ^= 1 << bit
            with pytest.raises(IFSError, match="corrupt"):
                from_bytes(bytes(bad))


def test_a_missing_file(tmp_path):
    with pytest.raises(IFSError, match="no compressed file"):
        read(tmp_path / "nothing.ifsc")
