"""Fractal image compression: a partitioned IFS of a gray image, fitted block by block, decoded by iteration.

The pipeline, one module a stage::

    config     CodeOptions (the file's layout and coder), RefineOptions, the tuned numbers
    partitions the partitions by name (`Partition`: how each is chosen and coded), each its module's
    partition  the quadtree of range blocks: grown where a split buys the most error per bit, or pruned
               at a price per bit bisected to fit a budget (rate-distortion)
    domains    the domain pool (blocks twice as large, averaged down) and the 8 isometries
    quantize   contrast s and mean m to the integers the file stores
    collage    least squares for every domain at once: each block's best map
    entropy    adaptive models and constriction's range coder, one face for encoding and decoding
    fields     the fields in the range coder's order and contexts (file version 2)
    fixedformat the fixed-length fields of file version 1
    rates      what each field costs; the partition whose coded file fits a budget
    repartition every block fitted with a domain or flat, the partition chosen by rate-distortion
    hv         the HV partition: rectangles cut at their strongest edge (rectangles, hvfields)
    encode     the collage coder: a code of the image at a rate -> Code
    code       Code: the blocks and their quantized maps
    fileformat the file: a header naming the version, then the fields (range-coded, or fixed in version 1)
    decode     iterate the maps from any start, at any multiple of 0.5 -> the attractor, post-filtered
    deblock    the post-filter: pixels facing across a block seam averaged (the weight in file version 3)
    refine     attractor coding: the code refined through the decoder's fixed point, in no more bits
    method     compress(image, bpp, method="collage" | "attractor"), the post-filter kept where it helps

Typical use::

    from ifslib.compression import compress, decode, write
    code = compress(gray, bpp=0.25)            # gray: (h, w) floats in [0, 1]
    write(code, "photo.ifsc")
    image = decode(code, scale=2).image        # (2h, 2w) tensor
"""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
from .code import Code
from .config import CodeOptions, RefineOptions
from .decode import Decoded, decode
from .encode import encode
from .fileformat import from_bytes, read, to_bytes, write
from .method import METHODS, compress
from .refine import refine

__all__ = ["Code", "CodeOptions", "RefineOptions", "Decoded", "decode", "encode", "from_bytes", "read",
           "to_bytes", "write", "METHODS", "compress", "refine"]
