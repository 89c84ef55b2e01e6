"""The collage coder: least squares and the domain search against brute force, rates kept, bad input refused."""
import numpy as np
import pytest
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.domains import ISOMETRIES, isometry, pool
from ifslib.compression.encode import encode, ranges, search
from ifslib.compression.fileformat import header_bytes, to_bytes
from ifslib.compression.quantize import dequantize_m, dequantize_s, zero_s
from ifslib.errors import IFSError
from compression_images import photo

O = CodeOptions(min_block=4, max_block=16)


def brute(r: np.ndarray, blocks: np.ndarray, s_max: float):
    """Every (isometry, domain): the clipped least-squares s by numpy's polyfit and its squared error."""
    out = {}
    for k in range(ISOMETRIES):
        for d, block in enumerate(blocks):
            dk = isometry(torch.as_tensor(block), k).numpy().reshape(-1)
            dc = dk - dk.mean()
            s = np.polyfit(dc, r, 1)[0] if dc.any() else 0.0
            s = float(np.clip(s, -s_max, s_max))
            out[k, d] = (s, float((((r - r.mean()) - s * dc) ** 2).sum()))
    return out


def test_the_search_finds_the_brute_force_best_domain():
    image = photo(32, seed=3).double()
    blocks = pool(image, 4).numpy()
    targets = ranges(image, 4)[[0, 5, 17, 40, 63]]
    from ifslib.compression.domains import pool_with_isometries
    fit = search(targets, pool_with_isometries(image, 4), O)
    for i, r in enumerate(targets.numpy()):
        table = brute(r, blocks, O.s_max)
        best = min(e for _, e in table.values())
        s, err = table[int(fit.iso[i]), int(fit.domain[i])]
        assert err == pytest.approx(best, rel=1e-9, abs=1e-12)
        # the stored s is the least-squares s rounded to its level; the error counts the rounding
        q = float(dequantize_s(fit.s_idx[i], O, torch.float64))
        levels = dequantize_s(torch.arange(2**O.s_bits), O, torch.float64)
        assert q == pytest.approx(float(levels[(levels - s).abs().argmin()]))
        dk = isometry(torch.as_tensor(blocks[int(fit.domain[i])]), int(fit.iso[i])).numpy().reshape(-1)
        m = float(dequantize_m(fit.m_idx[i], O, torch.float64))
        exact = ((r - (q * (dk - dk.mean()) + m)) ** 2).sum()
        assert float(fit.err[i]) == pytest.approx(exact, rel=1e-9, abs=1e-12)


def test_a_non_flat_range_never_gets_s_zero():
    flat = torch.full((2, 16), 0.5, dtype=torch.float64)
    domains = torch.rand(8, 5, 16, dtype=torch.float64)
    free = search(flat, domains, O)
    kept = search(flat, domains, O, nonflat=torch.tensor([True, False]))
    assert (free.s_idx == zero_s(O)).all() and (free.domain == 0).all()
    assert kept.s_idx[0] != zero_s(O) and kept.s_idx[1] == zero_s(O)


@pytest.mark.parametrize("bpp", [0.4, 0.8, 1.5])
def test_the_file_keeps_the_rate(bpp):
    image = photo(48)
    code = encode(image, O, bpp=bpp)
    size = len(to_bytes(code))
    assert size * 8 <= bpp * 48 * 48
    assert size * 8 > 0.8 * bpp * 48 * 48 or (code.size == O.min_block).all()


def test_more_bits_buy_a_closer_collage_and_quality_targets_its_psnr():
    image = photo(32)
    low, high = encode(image, O, bpp=0.6), encode(image, O, bpp=2.0)
    assert len(high) > len(low)
    code = encode(image, O, quality=30)
    assert code.height == 32 and code.width == 32


def test_an_odd_sized_image_is_padded_and_remembered():
    code = encode(photo(48)[:37, :45], O, bpp=1.0)
    assert (code.height, code.width) == (37, 45) and code.padded == (48, 48)


@pytest.mark.parametrize("image, kwargs, words", [
    (torch.zeros(4, 4), {"bpp": 1}, "at least 8 x 8"),
    (torch.zeros(3, 16, 16), {"bpp": 1}, "gray image"),
    (torch.zeros(16, 16, dtype=torch.uint8), {"bpp": 1}, "floats"),
    (torch.full((16, 16), 2.0), {"bpp": 1}, r"\[0, 1\]"),
    (torch.full((16, 16), float("nan")), {"bpp": 1}, "finite"),
    (torch.zeros(16, 16), {}, "exactly one"),
    (torch.zeros(16, 16), {"bpp": 1, "quality": 30}, "exactly one"),
    (torch.zeros(16, 16), {"bpp": -1}, "bpp"),
    (torch.zeros(16, 16), {"quality": float("inf")}, "quality"),
    (torch.zeros(32, 32), {"bpp": 0.01}, "too few"),
])
def test_bad_input_says_what_to_do(image, kwargs, words):
    with pytest.raises(IFSError, match=words):
        encode(image, O, **kwargs)


@pytest.mark.parametrize("coder", ["fixed", "adaptive"])
def test_the_header_is_counted(coder):
    options = CodeOptions(min_block=4, max_block=16, coder=coder)
    code = encode(photo(32), options, bpp=1.0)
    assert len(to_bytes(code)) == header_bytes(options) + -(-code.bits() // 8) <= 32 * 32 / 8


def test_a_rate_below_the_coarsest_code_is_refused_with_the_rate_it_needs():
    image = photo(64)
    with pytest.raises(IFSError, match="at least") as refused:
        encode(image, O, bpp=0.05)
    needed = float(str(refused.value).split("takes ")[1].split(" bpp")[0])
    code = encode(image, O, bpp=needed)
    assert len(to_bytes(code)) * 8 <= needed * 64 * 64
