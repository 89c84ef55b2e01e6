"""compress: the collage method is the coder itself; attractor decodes closer at the same bytes; bad names refused."""
import pytest
import torch

from ifslib.compression import CodeOptions, RefineOptions, compress, encode, to_bytes
from ifslib.compression.refine import decoded_error
from ifslib.errors import IFSError
from compression_images import photo

O = CodeOptions(min_block=4, max_block=16)


def test_collage_is_the_encoder_and_attractor_its_refinement():
    image = photo(32, seed=5)
    collage = compress(image, bpp=1.0, method="collage", options=O)
    assert to_bytes(collage) == to_bytes(encode(image, O, bpp=1.0))
    attractor = compress(image, bpp=1.0, options=O, refinement=RefineOptions(searches=1, steps=4))
    assert len(to_bytes(attractor)) == len(to_bytes(collage))
    assert decoded_error(attractor, image)[0] <= decoded_error(collage, image)[0]


def test_an_unknown_method_names_the_known_ones():
    with pytest.raises(IFSError, match="collage, attractor"):
        compress(torch.zeros(16, 16), bpp=1.0, method="jpeg")
