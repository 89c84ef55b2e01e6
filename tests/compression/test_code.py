"""The code's bit count matches its file, and its maps are replaced without touching the partition."""
import pytest
import torch

from ifslib.compression.code import split_flag_count
from ifslib.compression.config import CodeOptions
from ifslib.compression.encode import encode
from ifslib.compression.fileformat import header_bytes, to_bytes
from ifslib.compression.partition import walk
from ifslib.errors import IFSError
from compression_images import photo

O = CodeOptions(min_block=4, max_block=16)


def test_split_flags_are_one_per_node_above_the_smallest():
    code = encode(photo(32), CodeOptions(min_block=4, max_block=16, coder="fixed"), bpp=1.2)
    leaves = set(zip(code.size.tolist(), code.y.tolist(), code.x.tolist()))
    nodes = [n for n, _ in walk(32, 32, O, lambda n: n not in leaves) if n[0] > O.min_block]
    assert split_flag_count(code) == len(nodes)


@pytest.mark.parametrize("coder", ["fixed", "adaptive"])
@pytest.mark.parametrize("bpp", [0.5, 1.0, 2.5])
def test_bits_match_the_file(bpp, coder):
    options = CodeOptions(min_block=4, max_block=16, coder=coder)
    code = encode(photo(32), options, bpp=bpp)
    assert len(to_bytes(code)) == header_bytes(options) + -(-code.bits() // 8) <= bpp * 32 * 32 / 8


def test_with_maps_keeps_the_partition():
    code = encode(photo(32), O, bpp=1.0)
    new = code.with_maps(m_idx=torch.zeros_like(code.m_idx))
    assert torch.equal(new.size, code.size) and new.m().eq(0).all()
    with pytest.raises(IFSError, match="partition|only"):
        code.with_maps(size=code.size)
