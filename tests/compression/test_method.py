"""compress: the collage method is the coder itself; attractor decodes closer at the same bytes; bad names refused."""
import pytest
import torch

from dataclasses import replace

from ifslib.compression import CodeOptions, RefineOptions, compress, encode, to_bytes
from ifslib.compression.refine import decoded_error
from ifslib.errors import IFSError
from compression_images import photo

O = CodeOptions(min_block=4, max_block=16)


def test_collage_is_the_encoder_and_attractor_its_refinement():
    image = photo(32, seed=5)
    collage = compress(image, bpp=1.0, method="collage", options=O, deblock=0)
    assert to_bytes(collage) == to_bytes(encode(image, O, bpp=1.0))
    attractor = compress(image, bpp=1.0, options=O, refinement=RefineOptions(searches=1, steps=4), deblock=0)
    assert len(to_bytes(attractor)) == len(to_bytes(collage))
    assert decoded_error(attractor, image)[0] <= decoded_error(collage, image)[0]


@pytest.mark.parametrize("method", ["collage", "attractor"])
def test_the_filter_is_kept_only_where_it_decodes_closer(method):
    image = photo(32, seed=5)
    refinement = RefineOptions(searches=1, steps=4)
    code = compress(image, bpp=1.0, method=method, options=O, refinement=refinement, deblock=0.2)
    assert code.options.deblock in (0, 0.2)
    other = replace(code, options=replace(code.options, deblock=0.2 - code.options.deblock))
    assert decoded_error(code, image)[0] <= decoded_error(other, image)[0]
    assert len(to_bytes(code)) <= 1.0 * 32 * 32 / 8
    # a filter named in the options is used as given; version 1 has none to try
    given = compress(image, bpp=1.0, method=method, options=replace(O, deblock=0.3), refinement=refinement)
    assert given.options.deblock == 0.3
    fixed = compress(image, bpp=1.0, method=method, options=replace(O, coder="fixed"), refinement=refinement)
    assert fixed.options.deblock == 0 and to_bytes(fixed)[4] == 1


def test_an_unknown_method_names_the_known_ones():
    with pytest.raises(IFSError, match="collage, attractor"):
        compress(torch.zeros(16, 16), bpp=1.0, method="jpeg")
