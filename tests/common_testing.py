"""Brute-force references the tests share (independent formulas, not the library's)."""


def point_segment(p, a, b):
    ab, ap = b - a, p - a
    h = ((ap @ ab) / (ab @ ab)).clamp(0, 1)
    return (ap - h * ab).norm()


def polygon_sdf(p, corners):
    """Signed distance to a convex polygon given counter-clockwise, from its edges (independent formula)."""
    edges = [(corners[i], corners[(i + 1) % len(corners)]) for i in range(len(corners))]
    dist = min(point_segment(p, a, b) for a, b in edges)
    inside = all(((b - a)[0] * (p - a)[1] - (b - a)[1] * (p - a)[0]) > 0 for a, b in edges)
    return -dist if inside else dist


def load_module(name, path):
    """The script at ``path`` imported as module ``name`` (once; a script outside the package, such as docs/slides.py)."""
    import importlib.util
    import sys

    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        sys.modules[name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]


def benchmark_module(name):
    """The helper ``benchmarks/<name>.py`` (the literature's samplers and scores: benchmarks' code, not the
    package's) imported once as ``benchmarks_<name>``."""
    from pathlib import Path

    return load_module(f"benchmarks_{name}", Path(__file__).resolve().parents[1] / "benchmarks" / f"{name}.py")


def fractal_target(maps=2, seed=4, size=64):
    """A random fractal (`ifslib.random_fractals.random_ifs`) drawn by the float64 chaos game at 256², as the benchmark
    draws them, then made ``size`` pixels wide as a fit does (`resize_target`)."""
    import ifslib
    from ifslib.core.targets.target import resize_target, target_from_mask

    truth = ifslib.random_fractals.random_ifs(maps, seed)
    mask = ifslib.render(truth, 256, method="chaos", points=1_000_000, seed=seed).numpy() >= 0.5
    return truth, resize_target(target_from_mask(mask, f"random{maps}_{seed}"), size)


def random_affine(seed, reflect=False):
    """A seeded random affine map of the plane, ``(a (2, 2), t (2,))`` in float64; ``reflect``: det a < 0."""
    import torch

    g = torch.Generator().manual_seed(seed)
    a = (torch.rand(2, 2, generator=g, dtype=torch.float64) - 0.5) * 1.2
    if reflect and torch.det(a) > 0:
        a[1] = -a[1]
    t = (torch.rand(2, generator=g, dtype=torch.float64) - 0.5) * 0.4
    return a, t


#: The small Koch fits of tests/core/fitting (run, fit): its size in pixels and its depth.
KOCH_SIZE, KOCH_DEPTH = 48, 2


def koch_start(target, seed=0):
    """The Koch pattern at `KOCH_DEPTH` on ``target``'s best-fit line, jittered by 0.05 (seeded)."""
    import ifslib

    return ifslib.initialize(ifslib.patterns.koch(depth=KOCH_DEPTH), target, jitter=0.05, seed=seed)
