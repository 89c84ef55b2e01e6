"""Attractor coding: the fixed point's implicit gradient against finite differences; refinement keeps the bits."""
import importlib

import pytest
import torch

from ifslib.compression.config import CodeOptions, RefineOptions
from ifslib.compression.decode import fixed_point, plan
from ifslib.compression.encode import encode
from ifslib.compression.fileformat import to_bytes
from ifslib.compression.refine import decoded_error, implicit_fixed_point, refine
from ifslib.errors import IFSError
from compression_images import photo

O = CodeOptions(min_block=4, max_block=16)


def test_the_implicit_gradient_matches_finite_differences():
    code = encode(photo(32, seed=2), O, bpp=1.5)
    p = plan(code)
    weights = torch.rand(32, 32, dtype=torch.float64, generator=torch.Generator().manual_seed(1))
    start = torch.full((32, 32), 0.5, dtype=torch.float64)

    def loss(s, m):
        x, _, _ = fixed_point(p, s, m, start, tol=1e-14, max_iter=2000)
        return float((weights * x).sum())

    s = code.s(torch.float64).requires_grad_()
    m = code.m(torch.float64).requires_grad_()
    (weights * implicit_fixed_point(p, s, m, start, tol=1e-13, max_iter=2000)).sum().backward()
    eps = 1e-6
    for i in (0, len(code) // 2, len(code) - 1):
        for value, grad in ((s, s.grad), (m, m.grad)):
            up, down = value.detach().clone(), value.detach().clone()
            up[i] += eps
            down[i] -= eps
            args = (up, m.detach()) if value is s else (s.detach(), up)
            args_down = (down, m.detach()) if value is s else (s.detach(), down)
            numeric = (loss(*args) - loss(*args_down)) / (2 * eps)
            assert float(grad[i]) == pytest.approx(numeric, rel=1e-5, abs=1e-7)


def test_refinement_decodes_closer_at_the_same_bytes():
    image = photo(48, seed=4)
    code = encode(image, O, bpp=1.0)
    better = refine(code, image, RefineOptions(searches=2, steps=8, repartitions=0))
    assert len(to_bytes(better)) == len(to_bytes(code))
    assert torch.equal(better.size, code.size) and torch.equal(better.flat, code.flat)
    before, _ = decoded_error(code, image)
    after, _ = decoded_error(better, image)
    assert after < before


def test_a_new_partition_is_kept_only_in_no_more_bits_and_closer():
    image = photo(64, seed=5)
    code = encode(image, O, bpp=0.8)
    held = refine(code, image, RefineOptions(searches=1, steps=4, repartitions=0))
    moved = refine(code, image, RefineOptions(searches=1, steps=4, repartitions=1))
    assert moved.bits() <= code.bits() and len(to_bytes(moved)) <= len(to_bytes(code))
    assert decoded_error(moved, image)[0] <= decoded_error(held, image)[0]


def test_refine_refuses_another_image():
    code = encode(photo(32), O, bpp=1.0)
    with pytest.raises(IFSError, match="code is of a 32 x 32"):
        refine(code, photo(48), RefineOptions(steps=1))



def test_a_step_whose_gradient_is_not_finite_is_undone(monkeypatch):
    """The descent rolls such a step back (`StepPolicy.rollback`): it stops with a warning, no level NaN."""
    module = importlib.import_module("ifslib.compression.refine")  # the package's `refine` is the function
    image = photo(32, seed=3)
    code = encode(image, O, bpp=1.0)
    real = module.implicit_fixed_point

    def broken(*args, **kwargs):
        out = real(*args, **kwargs)
        out.register_hook(lambda g: torch.full_like(g, float("nan")))
        return out

    monkeypatch.setattr(module, "implicit_fixed_point", broken)
    with pytest.warns(UserWarning, match="attractor descent stopped"):
        result = module.descend(code, image, steps=12, lr=0.3)
    assert torch.equal(result.size, code.size)
    assert decoded_error(result, image)[0] <= decoded_error(code, image)[0] + 1e-6
