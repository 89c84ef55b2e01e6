"""Fractal image compression: a partitioned IFS of a gray image, fitted block by block, decoded by iteration
(one module a stage: docs/guide/design.md)::

    from ifslib.compression import compress, decode, write
    code = compress(gray, bpp=0.25)            # gray: (h, w) floats in [0, 1]
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
