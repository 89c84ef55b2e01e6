"""The ``compress`` and ``decompress`` subcommands of ``python -m ifslib`` (registered by `ifslib.cli`).

The coder (`ifslib.compression`) and torch are imported once the arguments are checked.

Examples::

    python -m ifslib compress photo.png -o photo.ifsc --bpp 0.25
    python -m ifslib decompress photo.ifsc -o photo.png --scale 2
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from .errors import IFSError
from .names import COMPRESSION_METHODS, PARTITIONS
from .progress import draw_bars, note


def read_gray(path: str) -> np.ndarray:
    """An image file as ``(h, w)`` float32 gray levels in [0, 1], at its full size and upright (EXIF): 8-bit divided
    by 255, 16-bit by 65535 (Pillow's 8-bit conversion would clip it at 255)."""
    from PIL import ImageOps

    # the target reader's file handling; imports torch (the thread count): after the arguments are checked
    from .core.targets.image import _WIDE_MODES, _image_file, _luma

    path = Path(path)
    with _image_file(path) as opened:
        im = ImageOps.exif_transpose(opened)  # a phone's photo, as its viewer shows it
        if im.mode in _WIDE_MODES:
            im = im.convert("I")
        if im.mode in ("I", "F"):
            gray, top = np.asarray(im, dtype=np.float64), (65535.0 if im.mode == "I" else 1.0)
        else:
            gray, top = _luma(im), 255.0
    # checked outside the file's context, whose ValueError handler would take an IFSError for a bad file
    if not (np.isfinite(gray).all() and gray.min() >= 0 and gray.max() <= top):
        raise IFSError(f"{str(path)!r} holds {im.mode!r} values from {gray.min():g} to {gray.max():g}, not gray "
                       f"levels from 0 to {top:g}; save it with 8 or 16 bits a pixel")
    return (gray / top).astype(np.float32)


#: The extensions `decompress` writes, each a lossless format of 8-bit gray (Pillow picks it by the extension).
OUTPUT_FORMATS = {".png": "PNG", ".tif": "TIFF", ".tiff": "TIFF", ".bmp": "BMP", ".pgm": "PPM"}


def output_format(path: str) -> str:
    """Pillow's name of the format ``path``'s extension names in `OUTPUT_FORMATS`, else `IFSError` listing them."""
    suffix = Path(path).suffix.lower()
    if suffix not in OUTPUT_FORMATS:
        raise IFSError(f"the output {path!r} must end in one of {', '.join(OUTPUT_FORMATS)} (a lossless image "
                       f"format, picked by the extension), got {suffix or 'no extension'!r}")
    return OUTPUT_FORMATS[suffix]


def cmd_compress(args: argparse.Namespace) -> None:
    from skimage.metrics import peak_signal_noise_ratio

    from .compression import compress, decode, write
    from .compression.config import CodeOptions
    from .compression.partitions import partition_of

    options = CodeOptions(partition=args.partition)
    if args.bpp is None and partition_of(options).at_quality is None:  # before the image is read
        raise IFSError(f"a {args.partition} partition is coded at a rate: give --bpp, not --quality")
    t0 = time.perf_counter()
    image = read_gray(args.image)
    code = compress(image, bpp=args.bpp, quality=args.quality, method=args.method, options=options,
                    progress=not args.quiet and draw_bars(), deblock=args.deblock)
    size = write(code, args.output)
    psnr = peak_signal_noise_ratio(image, decode(code).image.numpy(), data_range=1.0)
    print(f"wrote {args.output}: {size:,} bytes ({8 * size / image.size:.3f} bpp), {len(code)} blocks, "
          f"{args.method} coding, deblocking {code.options.deblock:g}; decoded PSNR {psnr:.2f} dB; "
          f"{time.perf_counter() - t0:.1f} s")


def cmd_decompress(args: argparse.Namespace) -> None:
    from .compression import decode, read
    from .compression.config import DECODE_TOL
    from PIL import Image

    fmt = output_format(args.output)  # before decoding: a wrong name costs nothing
    code = read(args.file)
    result = decode(code, args.scale)
    Path(args.output).parent.mkdir(parents=True, exist_ok=True)
    pixels = (result.image.numpy() * 255).round().astype(np.uint8)
    Image.fromarray(pixels, mode="L").save(args.output, fmt)
    print(f"wrote {args.output}: {pixels.shape[1]} x {pixels.shape[0]} px (scale {args.scale:g}), "
          f"{result.iterations} iterations")
    if result.change > DECODE_TOL:
        note(f"ifslib decompress: the decoder had not settled after {result.iterations} iterations "
             f"(a pixel still moved by {result.change:.2g}); the image is its last iterate")


def _rate(value: str) -> float:
    try:
        number = float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {value!r}") from None
    if not (number > 0 and np.isfinite(number)):
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {value!r}")
    return number


def _weight(value: str) -> float:
    try:
        number = float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {value!r}") from None
    if not (0 <= number <= 0.5 and abs(number * 100 - round(number * 100)) < 1e-9):
        raise argparse.ArgumentTypeError(f"expected a weight from 0 to 0.5 in steps of 0.01, got {value!r}")
    return round(number * 100) / 100


def add_parsers(sub) -> None:
    """Add ``compress`` and ``decompress`` to the subparsers ``sub``."""
    c = sub.add_parser("compress", help="fractal-compress a gray image (colour is converted to gray)",
                       description="Fractal-compress an image: a partitioned IFS fitted block by block by the "
                                   "collage theorem, then (attractor) refined through the decoder.")
    c.add_argument("image", help="image file (PNG, JPEG, ...); colour is converted to gray")
    rate = c.add_mutually_exclusive_group(required=True)
    rate.add_argument("--bpp", type=_rate, help="file size in bits per pixel, header included (e.g. 0.25)")
    rate.add_argument("--quality", type=_rate, metavar="Q",
                      help="split blocks until the collage's PSNR reaches Q dB (e.g. 30)")
    c.add_argument("--method", choices=COMPRESSION_METHODS, default="attractor",
                   help="collage (the classic coder) or attractor (no more bits, refined through the decoder; "
                        "the default)")
    c.add_argument("--partition", choices=PARTITIONS, default=next(iter(PARTITIONS)),
                   help="how the image is cut into range blocks: " + "; ".join(
                       f"{name} ({phrase})" for name, phrase in PARTITIONS.items()) + " (default %(default)s)")
    c.add_argument("--deblock", type=_weight, metavar="W",
                   help="the decoder's post-filter: each pixel beside a block seam takes weight W (0 to 0.5, "
                        "in steps of 0.01) from the pixel across it, recorded in the file and kept only if it "
                        "decodes closer; 0: none (default: the coder's tuned weight)")
    c.add_argument("--quiet", action="store_true", help="no progress bars")
    c.add_argument("-o", "--output", required=True, help="compressed file to write (.ifsc)")
    c.set_defaults(run=cmd_compress)
    d = sub.add_parser("decompress", help="decode a compressed file to an image, at any multiple of 0.5 of its size",
                       description="Decode a file written by `compress` by iterating its maps from a gray image.")
    d.add_argument("file", help="a file written by `ifslib compress`")
    d.add_argument("--scale", type=_rate, default=1.0,
                   help="output pixels per image pixel (default 1; 2 doubles each side): a multiple of 2 / the "
                        "smallest block, 0.5 for the default 4 px blocks")
    d.add_argument("-o", "--output", required=True,
                   help="image file to write, its format picked by the extension: .png, .tif, .tiff, .bmp or .pgm "
                        "(all lossless)")
    d.set_defaults(run=cmd_decompress)
