"""HV codes: rectangles that tile the image, exact file round trips, one clear error for a damaged file,
the decoder's fixed point against each block's map by hand, and refinement in no more bits."""
import numpy as np
import pytest
import torch

from ifslib.compression.config import CodeOptions, RefineOptions
from ifslib.compression.decode import decode, plan
from ifslib.compression.encode import collage, encode
from ifslib.compression.fileformat import from_bytes, to_bytes
from ifslib.compression.rectangles import rectangle_isometry, rectangle_pool
from ifslib.compression.refine import refine
from ifslib.errors import IFSError
from compression_images import photo

HV = CodeOptions(min_block=4, max_block=16, partition="hv")
FIELDS = ("y", "x", "size", "domain", "iso", "s_idx", "m_idx", "block_height", "block_width")


@pytest.fixture(scope="module")
def code():
    return encode(photo(48)[:, :40], HV, bpp=1.5)


def test_an_hv_code_tiles_the_padded_image_with_rectangles_within_its_budget(code):
    H, W = code.padded
    cover = np.zeros((H, W), dtype=int)
    for y, x, h, w in zip(*(t.tolist() for t in (code.y, code.x, code.heights, code.widths))):
        assert h >= HV.min_block and w >= HV.min_block
        cover[y:y + h, x:x + w] += 1
    assert (cover == 1).all()
    assert (code.heights != code.widths).any()
    assert len(to_bytes(code)) * 8 <= 1.5 * 48 * 40


def test_the_file_names_the_partition_and_round_trips_exactly(code):
    data = to_bytes(code)
    back = from_bytes(data)
    assert back.options == HV and data[9] == 1  # the partition's byte: HV
    for name in FIELDS:
        assert torch.equal(getattr(back, name), getattr(code, name)), name
    assert torch.equal(decode(back).image, decode(code).image)


@pytest.mark.parametrize("damage", ["truncate", "flip", "partition"])
def test_a_damaged_hv_file_gives_the_clear_error(code, damage):
    data = bytearray(to_bytes(code))
    if damage == "truncate":
        data = data[:-3]
    elif damage == "flip":
        data[-2] ^= 0x10
    else:
        data[9] = 0  # said to be a quadtree: the CRC covers the header
    with pytest.raises(IFSError, match="corrupt or truncated"):
        from_bytes(bytes(data))


def test_the_fixed_point_is_each_rectangles_map_of_its_own_domain(code):
    """At the decoded fixed point x*, each block equals s (D - mean D) + m with D its domain cut from x* by hand."""
    x = decode(code, tol=1e-7, max_iter=400).padded
    s, m = code.s(), code.m()
    for i in range(0, len(code), max(1, len(code) // 25)):
        y0, x0, h, w = (int(t[i]) for t in (code.y, code.x, code.heights, code.widths))
        d = rectangle_isometry(rectangle_pool(x, h, w)[int(code.domain[i])], int(code.iso[i]))
        by_hand = s[i] * (d - d.mean()) + m[i]
        torch.testing.assert_close(x[y0:y0 + h, x0:x0 + w], by_hand, atol=1e-4, rtol=0)


def test_the_plan_gathers_four_isometries_on_rectangles(code):
    p = plan(code)
    assert sum(len(g.leaves) for g in p.groups) == len(code)
    rect = (code.heights != code.widths) & ~code.flat
    assert (code.iso[rect] < 4).all()


def test_refinement_of_an_hv_code_decodes_no_worse_in_no_more_bits():
    image = photo(48)[:, :40]
    chosen = collage(image, HV, bpp=1.5)
    better = refine(chosen.code, image, RefineOptions(searches=1, steps=3, repartitions=1))
    err = [float(((decode(c).image - image) ** 2).mean()) for c in (chosen.code, better)]
    assert err[1] <= err[0] and better.bits() <= chosen.code.bits()
    assert better.options.partition == "hv"


def test_hv_options_are_checked_where_they_enter():
    with pytest.raises(IFSError, match="partition must be one of"):
        CodeOptions(partition="triangles")
    with pytest.raises(IFSError, match="adaptive coder"):
        CodeOptions(partition="hv", coder="fixed")
    with pytest.raises(IFSError, match="give bpp"):
        encode(photo(32), HV, quality=30)
