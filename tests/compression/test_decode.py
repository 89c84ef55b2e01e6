"""The decoder: one iteration against a loop over blocks by hand, a fixed point from any start, any scale."""
import numpy as np
import pytest
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.decode import decode, domain_means, iterate, iterate_offset, plan
from ifslib.compression.domains import domain_step, isometry, lattice
from ifslib.compression.encode import encode
from ifslib.errors import IFSError
from compression_images import photo

O = CodeOptions(min_block=4, max_block=16)


def by_hand(code, image: np.ndarray) -> np.ndarray:
    """One application of the operator, block by block with numpy."""
    out = np.zeros_like(image)
    s, m = code.s(torch.float64).numpy(), code.m(torch.float64).numpy()
    for i in range(len(code)):
        size, y, x, d, k = (int(v[i]) for v in (code.size, code.y, code.x, code.domain, code.iso))
        step, (_, cols) = domain_step(*code.padded, size), lattice(*code.padded, size)
        dy, dx = (d // cols) * step, (d % cols) * step
        block = image[dy:dy + 2 * size, dx:dx + 2 * size].reshape(size, 2, size, 2).mean((1, 3))
        block = isometry(torch.as_tensor(block), k).numpy()
        out[y:y + size, x:x + size] = s[i] * (block - block.mean()) + m[i]
    return out


def test_one_iteration_matches_the_blocks_by_hand():
    code = encode(photo(48, seed=1), O, bpp=1.5)
    image = np.random.default_rng(0).random((48, 48))
    got = iterate(plan(code), torch.as_tensor(image), code.s(torch.float64), code.m(torch.float64))
    np.testing.assert_allclose(got.numpy(), by_hand(code, image), atol=1e-12)


def test_any_start_reaches_the_same_fixed_point():
    code = encode(photo(32), O, bpp=1.5)
    results = [decode(code, start=start, tol=1e-7, dtype=torch.float64)
               for start in (None, torch.zeros(32, 32), torch.rand(20, 20, generator=torch.Generator().manual_seed(0)))]
    for r in results[1:]:
        torch.testing.assert_close(r.image, results[0].image, atol=1e-5, rtol=0)
    x = results[0].padded
    again = iterate(plan(code), x, code.s(torch.float64), code.m(torch.float64))
    assert (again - x).abs().max() < 1e-6
    assert results[0].iterations < 100


def test_the_decoded_image_resembles_the_original():
    image = photo(32)
    code = encode(image, O, bpp=2.0)
    mse = float(((decode(code).image - image) ** 2).mean())
    assert 10 * np.log10(1 / mse) > 22


@pytest.mark.parametrize("scale", [0.5, 2.0, 1.5])
def test_decoding_at_a_scale_keeps_the_picture(scale):
    code = encode(photo(48)[:40, :44], O, bpp=1.5)
    one = decode(code).image
    big = decode(code, scale).image
    assert big.shape == (round(40 * scale), round(44 * scale))
    # averaged back to the 1x grid (or compared on it), the picture is the same within a few gray levels
    back = torch.nn.functional.interpolate(big[None, None].double(), size=(40, 44), mode="area")[0, 0]
    assert float((back - one.double()).abs().mean()) < 0.03


@pytest.mark.parametrize("kwargs, words", [({"scale": 0.3}, "multiple of 0.5"), ({"scale": "2"}, "scale"),
                                           ({"tol": 0}, "tol"), ({"start": torch.zeros(2, 3, 3)}, "start image")])
def test_bad_decoding_requests(kwargs, words):
    code = encode(photo(32), O, bpp=1.0)
    with pytest.raises(IFSError, match=words):
        decode(code, **kwargs)


def test_the_classic_form_agrees_with_the_centred_one_at_its_offsets():
    code = encode(photo(32), O, bpp=1.5)
    p, x = plan(code), torch.rand(32, 32, dtype=torch.float64, generator=torch.Generator().manual_seed(2))
    s, m = code.s(torch.float64), code.m(torch.float64)
    o = m - s * domain_means(p, x)
    torch.testing.assert_close(iterate_offset(p, x, s, o), iterate(p, x, s, m))
    y = torch.rand(32, 32, dtype=torch.float64, generator=torch.Generator().manual_seed(3))
    moved = (iterate_offset(p, x, s, o) - iterate_offset(p, y, s, o)).abs().max()
    assert moved <= s.abs().max() * (x - y).abs().max() + 1e-12  # a contraction by max |s|
