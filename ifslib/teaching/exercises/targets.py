"""The fit exercises' targets: pictures shipped with the package, drawn by ``course/targets.py`` from maps
that only the instructor's source holds."""
from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from ...errors import IFSError
from ...core.targets.target import Target, load_target

FOLDER = Path(__file__).resolve().parent / "targets"
#: The sizes drawn: the notebooks' quick (64) and teaching (128, 256) values.
SIZES = (64, 128, 256)


def _target(name: str, size: int) -> Target:
    if size not in SIZES:
        raise IFSError(f"the exercise's {name} target is drawn at {', '.join(map(str, SIZES))} px, not {size!r}: "
                       "set the notebook's size to one of them")
    path = FOLDER / f"{name}_{size}.png"
    if not path.is_file():
        raise IFSError(f"{path} is missing: reinstall ifslib, or run `python course/targets.py` in a checkout")
    with Image.open(path) as image:
        return load_target(np.asarray(image.convert("1"), dtype=bool), size)


def koch_target(size: int = 64) -> Target:
    """A Koch-like curve the library does not ship (its five points drawn at random, turned), ``size`` 64, 128 or
    256 px: the plain `ifslib.patterns.koch` lies more than a pixel from it."""
    return _target("koch", size)


def carpet_target(size: int = 64) -> Target:
    """A Sierpinski carpet of other proportions, ``size`` px: the library's square rules cannot take its rectangles."""
    return _target("carpet", size)


def two_map_target(size: int = 64) -> Target:
    """The attractor of two similarities drawn at random (not a pattern the library ships), ``size`` px."""
    return _target("two_maps", size)
