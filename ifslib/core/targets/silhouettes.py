"""Silhouettes the library draws itself: letters, polygons, smooth blobs and limbed creatures, as binary masks.

They are targets that need no file: a reader's first image to fit, and the benchmark set of shapes
(`benchmarks/silhouettes.py`). Every drawing is a boolean ``(size, size)`` array in the pixel grid
of docs/guide/conventions.md (row 0 at the top), the figure centred and filling about 80% of the
frame; `ifslib.load_target` takes it as it is.
"""
from __future__ import annotations

import numpy as np
from matplotlib.font_manager import FontProperties
from matplotlib.path import Path
from matplotlib.textpath import TextPath

from ...errors import IFSError, check_int
from ..raster.distance import check_size
from ..raster.nearest import pixel_centres

#: How much of the frame the figure's larger side fills.
FILL = 0.8


def _inside(path: Path, size: int) -> np.ndarray:
    """Pixels whose centres lie inside ``path`` (plane units), as a ``(size, size)`` bool array."""
    x, y = pixel_centres(size)
    return path.contains_points(np.stack([x.numpy(), y.numpy()], 1)).reshape(size, size)


def _fitted(vertices: np.ndarray) -> np.ndarray:
    """Vertices scaled and moved so that their bounding box is centred and its larger side is `FILL`."""
    lo, hi = vertices.min(0), vertices.max(0)
    return (vertices - (lo + hi) / 2) * (FILL / max(hi - lo))


def letter(char: str, size: int = 128, font: str = "DejaVu Sans", weight: str = "bold") -> np.ndarray:
    """A letter (or any text) in a font that matplotlib ships, filled, holes kept.

    Parameters
    ----------
    char : str
        The text to draw, e.g. ``"A"``.
    size : int
        Pixels per side.
    font, weight
        Passed to `matplotlib.font_manager.FontProperties`.
    """
    size = check_size(size)
    if not isinstance(char, str) or not char.strip():
        raise IFSError(f"letter needs a non-blank string, got {char!r}")
    text = TextPath((0, 0), char, size=1, prop=FontProperties(family=font, weight=weight))
    # one polygon per contour: a point is inside when it lies in an odd number of them (holes stay holes)
    contours = text.to_polygons(closed_only=True)
    every = np.concatenate(contours)
    lo, hi = every.min(0), every.max(0)
    # one polygon per contour: a pixel is inside when it lies in an odd number of them (holes stay holes)
    inside = np.zeros((size, size), dtype=bool)
    for contour in contours:
        inside ^= _inside(Path((contour - (lo + hi) / 2) * (FILL / max(hi - lo))), size)
    return inside


def polygon(corners: int, size: int = 128, seed: int = 0, spikiness: float = 0.5) -> np.ndarray:
    """A star-shaped polygon: ``corners`` vertices at random radii and near-regular angles around the centre.

    Parameters
    ----------
    corners : int
        At least 3.
    size : int
    seed : int
    spikiness : float
        Each radius is ``1 - U(0, spikiness)`` (0: a regular polygon).
    """
    size = check_size(size)
    if isinstance(corners, bool) or not isinstance(corners, int) or corners < 3:
        raise IFSError(f"a polygon needs an integer >= 3 corners, got {corners!r}")
    rng = np.random.default_rng(seed)
    step = 2 * np.pi / corners  # corners near the regular polygon's, each moved by up to a third of a step
    angle = np.arange(corners) * step + rng.uniform(-step / 3, step / 3, corners) * (spikiness > 0)
    radius = 1 - rng.uniform(0, spikiness, corners)
    vertices = np.stack([radius * np.cos(angle), radius * np.sin(angle)], 1)
    return _inside(Path(_fitted(vertices), closed=False), size)


def blob(size: int = 128, seed: int = 0, harmonics: int = 4, roughness: float = 0.25) -> np.ndarray:
    """A smooth random blob: a closed curve ``r(theta) = 1 + sum_k a_k cos(k theta + phi_k)``.

    Parameters
    ----------
    size, seed : int
    harmonics : int
        Number of Fourier terms (2 .. ``harmonics + 1``).
    roughness : float
        Amplitude scale of the terms (each ``U(0, roughness / k)``).
    """
    size = check_size(size)
    rng = np.random.default_rng(seed)
    theta = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    r = np.ones_like(theta)
    for k in range(2, harmonics + 2):
        r += rng.uniform(0, roughness / (k - 1)) * np.cos(k * theta + rng.uniform(0, 2 * np.pi))
    vertices = np.stack([r * np.cos(theta), r * np.sin(theta)], 1)
    return _inside(Path(_fitted(vertices)), size)


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each of ``points`` ``(n, 2)`` to the segment ``a b``."""
    ab = b - a
    t = np.clip((points - a) @ ab / (ab @ ab), 0, 1)
    return np.linalg.norm(points - (a + t[:, None] * ab), axis=1)


def limbed(size: int = 128, seed: int = 0, limbs: int = 4, width: float = 0.04, tail: bool = True,
           holes: int = 1) -> np.ndarray:
    """A creature: an oval blob with thin bent limbs, a wavy tail and round holes.

    A solid figure whose thin parts make it look porous (its interior share falls towards a
    fractal's, `ifslib.automatic.auto.interior_share`): the benchmark's test of deciding fractal or shape.

    Parameters
    ----------
    size, seed : int
    limbs : int
        Bent limbs (two strokes each) spread around the body, at least 0.
    width : float
        Each limb's width in plane units (the frame is 1 wide; the tail is 0.7 as wide).
    tail : bool
        A wavy stroke on the body's left.
    holes : int
        Round holes of diameter 0.1 punched near the body's centre.
    """
    size = check_size(size)
    check_int(limbs, "limbs", 0)
    check_int(holes, "holes", 0)
    if isinstance(width, bool) or not isinstance(width, (int, float)) or not 0 < width < 0.5:
        raise IFSError(f"width must be a number between 0 and 0.5 (plane units), got {width!r}")
    rng = np.random.default_rng(seed)
    x, y = pixel_centres(size)
    points = np.stack([x.numpy(), y.numpy()], 1)
    theta = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    radius = 0.22 * (1 + sum(rng.uniform(0, 0.15 / (k - 1)) * np.cos(k * theta + rng.uniform(0, 2 * np.pi))
                             for k in range(2, 5)))
    inside = Path(np.stack([1.3 * radius * np.cos(theta), radius * np.sin(theta)], 1)).contains_points(points)
    for i in range(limbs):  # a hip on the body, a knee farther out, a foot turned by about 35 degrees
        angle = (i + 0.5) * 2 * np.pi / limbs + rng.uniform(-0.3, 0.3)
        out = np.array([np.cos(angle), np.sin(angle)])
        hip = 0.15 * out * (1.3, 1)
        knee = hip + 0.18 * out
        foot = knee + 0.14 * np.array([np.cos(angle + 0.6), np.sin(angle + 0.6)])
        for a, b in ((hip, knee), (knee, foot)):
            inside |= _segment_distance(points, a, b) < width / 2
    if tail:
        t = np.linspace(0, 1, 40)
        wave = np.stack([-0.28 - 0.15 * t, 0.05 + 0.08 * np.sin(3 * np.pi * t)], 1)
        near = np.min([_segment_distance(points, a, b) for a, b in zip(wave[:-1], wave[1:])], 0)
        inside |= near < 0.35 * width
    for _ in range(holes):
        centre = np.array([rng.uniform(-0.08, 0.08), rng.uniform(-0.05, 0.05)])
        inside &= np.linalg.norm(points - centre, axis=1) > 0.05
    return inside.reshape(size, size)


def gallery(size: int = 128) -> dict[str, np.ndarray]:
    """The benchmark's silhouettes: three letters, three polygons and three blobs, by name."""
    shapes = {f"letter {c}": letter(c, size) for c in "AGR"}
    shapes.update({f"polygon {n}": polygon(n, size, seed=n) for n in (5, 7, 9)})
    shapes.update({f"blob {s}": blob(size, seed=s) for s in (1, 2, 3)})
    return shapes


def thin_gallery(size: int = 128) -> dict[str, np.ndarray]:
    """Silhouettes with thin limbs, tails and holes, by name: three creatures (`limbed`) and three
    letters of normal weight (a thin Y, a K, a B with two holes)."""
    shapes = {f"creature {s}": limbed(size, seed=s, limbs=3 + s % 3, width=0.03 + 0.01 * (s % 2)) for s in (1, 2, 3)}
    shapes.update({f"thin letter {c}": letter(c, size, weight="normal") for c in "YKB"})
    return shapes
