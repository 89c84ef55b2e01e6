"""The file: exact round trips, and one clear error for a wrong, truncated, padded or corrupt file."""
import pytest
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.encode import encode
from ifslib.compression.fileformat import HEADER, from_bytes, read, to_bytes, write
from ifslib.errors import IFSError
from compression_images import photo

FIELDS = ("y", "x", "size", "domain", "iso", "s_idx", "m_idx")


@pytest.mark.parametrize("options", [CodeOptions(min_block=4, max_block=16),
                                     CodeOptions(min_block=8, max_block=8, s_bits=3, m_bits=9, s_max=0.5)])
def test_round_trip_is_exact(tmp_path, options):
    code = encode(photo(40)[:, :36], options, bpp=1.5)
    back = read(tmp_path / "a.ifsc") if write(code, tmp_path / "a.ifsc") else None
    assert (back.height, back.width, back.options) == (40, 36, options)
    for name in FIELDS:
        assert torch.equal(getattr(back, name), getattr(code, name)), name


def test_wrong_truncated_padded_and_corrupt_files():
    data = to_bytes(encode(photo(32), CodeOptions(min_block=4, max_block=16), bpp=1.0))
    with pytest.raises(IFSError, match="IFSC"):
        from_bytes(b"\x89PNG" + data[4:])
    with pytest.raises(IFSError, match="truncated"):
        from_bytes(data[:10])
    with pytest.raises(IFSError, match="truncated"):
        from_bytes(data[:-3])
    with pytest.raises(IFSError, match="after its code"):
        from_bytes(data + b"\x00")
    with pytest.raises(IFSError, match="version 2"):
        from_bytes(data[:4] + b"\x02" + data[5:])
    with pytest.raises(IFSError, match="header is corrupt"):
        from_bytes(data[:HEADER.size - 4] + b"\x09" + data[HEADER.size - 3:])  # s_bits = 9


def test_a_missing_file(tmp_path):
    with pytest.raises(IFSError, match="no compressed file"):
        read(tmp_path / "nothing.ifsc")
