"""The decoder's post-filter: against pixel-by-pixel averaging across seams, on squares and rectangles, in the
decoder, differentiable, and the same at one and two threads."""
from dataclasses import replace

import numpy as np
import pytest
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.deblock import boundaries, deblock
from ifslib.compression.decode import block_labels, decode, plan
from ifslib.compression.encode import encode
from compression_images import photo


def brute(image: np.ndarray, label: np.ndarray, a: float) -> np.ndarray:
    """Fisher's filter written out: each pair facing across a seam, columns first, then rows."""
    out = image.astype(np.float64).copy()
    H, W = out.shape
    for passes in ("columns", "rows"):
        src = out.copy()
        for r in range(H):
            for c in range(W):
                if passes == "columns" and c + 1 < W and label[r, c] != label[r, c + 1]:
                    p, q = src[r, c], src[r, c + 1]
                    out[r, c], out[r, c + 1] = (1 - a) * p + a * q, a * p + (1 - a) * q
                if passes == "rows" and r + 1 < H and label[r, c] != label[r + 1, c]:
                    p, q = src[r, c], src[r + 1, c]
                    out[r, c], out[r + 1, c] = (1 - a) * p + a * q, a * p + (1 - a) * q
    return out


def labels(code, scale=1.0) -> np.ndarray:
    p = plan(code, scale)
    label = np.empty(p.height * p.width, dtype=int)
    blocks = zip(code.y.tolist(), code.x.tolist(), code.heights.tolist(), code.widths.tolist())
    for i, (y, x, h, w) in enumerate(blocks):
        grid = np.zeros((p.height, p.width), dtype=bool)
        grid[round(y * scale):round((y + h) * scale), round(x * scale):round((x + w) * scale)] = True
        label[grid.reshape(-1)] = i
    return label.reshape(p.height, p.width)


@pytest.mark.parametrize("partition", ["quadtree", "hv"])
@pytest.mark.parametrize("scale", [1.0, 2.0])
def test_the_filter_is_the_brute_force_average_across_block_seams(partition, scale):
    code = encode(photo(32, seed=3), CodeOptions(min_block=4, max_block=16, partition=partition), bpp=1.5)
    p = plan(code, scale)
    image = torch.rand(p.height, p.width, generator=torch.Generator().manual_seed(1), dtype=torch.float64)
    label = labels(code, scale)
    cols, rows = boundaries(block_labels(p))
    assert np.array_equal(cols.numpy(), label[:, 1:] != label[:, :-1])
    assert np.array_equal(rows.numpy(), label[1:] != label[:-1])
    for a in (0.0, 0.13, 0.5):
        assert np.allclose(deblock(block_labels(p), image, a).numpy(), brute(image.numpy(), label, a), atol=1e-12)


def test_the_decoder_filters_its_fixed_point_and_a_flat_image_stays_flat():
    image = photo(32, seed=4)
    code = encode(image, CodeOptions(min_block=4, max_block=16), bpp=1.0)
    on = replace(code, options=replace(code.options, deblock=0.2))
    plain, filtered = decode(code), decode(on)
    assert torch.equal(plain.padded, filtered.padded)
    p = plan(code)
    assert torch.allclose(filtered.image, deblock(block_labels(p), plain.padded, 0.2)[:32, :32].clamp(0, 1))
    assert not torch.equal(filtered.image, plain.image)
    flat = torch.full((p.height, p.width), 0.3)
    assert torch.allclose(deblock(block_labels(p), flat, 0.5), flat)


def test_the_filter_is_differentiable_and_linear():
    code = encode(photo(32, seed=2), CodeOptions(min_block=4, max_block=16), bpp=1.0)
    p = plan(code)
    x = torch.rand(p.height, p.width, dtype=torch.float64, requires_grad=True)
    y = torch.rand(p.height, p.width, dtype=torch.float64)
    assert torch.autograd.gradcheck(lambda t: deblock(block_labels(p), t, 0.3), (x,))
    assert torch.allclose(deblock(block_labels(p), 2 * x + y, 0.3), 2 * deblock(block_labels(p), x, 0.3) + deblock(block_labels(p), y, 0.3))


def test_the_same_at_one_and_two_threads():
    code = encode(photo(64, seed=6), CodeOptions(min_block=4, max_block=16), bpp=1.0)
    p = plan(code)
    image = torch.rand(p.height, p.width, generator=torch.Generator().manual_seed(0))
    before = torch.get_num_threads()
    try:
        torch.set_num_threads(1)
        one = deblock(block_labels(p), image, 0.25)
        torch.set_num_threads(2)
        two = deblock(block_labels(p), image, 0.25)
    finally:
        torch.set_num_threads(before)
    assert torch.equal(one, two)
