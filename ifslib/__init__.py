"""ifslib: differentiable iterated function systems.

The paper's pipeline, one folder a stage::

    geometry/   JSON / pattern -> IFS -> maps -> leaves
    raster/     leaves -> nearest leaf -> distance -> render
    targets/    image -> Target (mask, distance transform, sizes)
    scoring/    how close a drawing is: losses, metrics, the collage distance
    compression/ fractal image compression of gray photographs: collage and attractor coding
    discovery/  a start read from the image: curve, shape, or a fractal's maps
    fitting/    one Adam run -> strategies -> fit -> FitResult
    studies/    sweeps of many fits
    teaching/   what the notebooks show and ask

Data flows one way: a folder imports only from those above it in this list (and from the
top-level helpers ``errors``, ``data``, ``paths``, ``threads``).

Typical use::

    import ifslib
    ifs = ifslib.patterns.koch(depth=4)
    image = ifslib.render(ifs, 256)            # (256, 256) tensor in [0, 1], differentiable
    limit = ifslib.render(ifs, 256, "attractor")  # the attractor itself, within half a pixel
"""
import importlib
import os

# MKL's strict reproducible mode: a matrix product gives the same bits at any thread count (by
# default a long product is split between the threads, and its last bits follow their number).
# MKL reads it at its first call, so it holds when torch was imported first; a value set by the
# user is kept.
os.environ.setdefault("MKL_CBWR", "AUTO,STRICT")
# OpenMP's idle threads sleep rather than spin between torch's parallel regions. A spinning thread
# holds its core for a while after each small operation; beside another busy process (a test worker,
# a notebook, a sweep's fits) that doubles a 2-thread fit's CPU time and more (a fractal search: 41 s
# of CPU spinning against 10 s passive, the same maps; docs/results/threads.md). libgomp reads it
# when torch loads: set before torch is imported it holds here, and always in the processes started
# from here (notebook kernels, the CLI's runs). A value set by the user is kept.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")


#: Every public name, and where it lives: (module, attribute), or (module, None) for a module. A name is
#: imported on first use, so ``python -m ifslib fit IMAGE --loss typo`` refuses the name before torch
#: loads; torch's thread count is set when the first folder that computes is imported (`ifslib.threads`).
_PUBLIC = {
    "IFSError": ("errors", "IFSError"),
    "configure_threads": ("threads", "configure_threads"),
    "data": ("data", None),
    # the paper's core: geometry -> raster -> targets -> scoring -> fitting
    "crossings": ("geometry.crossings", None), "patterns": ("geometry.patterns", None),
    "IFS": ("geometry.ifs", "IFS"), "load_ifs": ("geometry.io", "load_ifs"), "save_ifs": ("geometry.io", "save_ifs"),
    "expand": ("geometry.leaves", "expand"), "Primitive": ("geometry.primitives", "Primitive"),
    "Rule": ("geometry.rules", "Rule"), "rule_maps": ("geometry.rules", "rule_maps"),
    "chaos_game": ("raster.chaos", "chaos_game"), "distance_field": ("raster.distance", "distance_field"),
    "nearest_leaf": ("raster.nearest", "nearest_leaf"), "pixel_centres": ("raster.nearest", "pixel_centres"),
    "default_sigma": ("raster.render", "default_sigma"), "render": ("raster.render", "render"),
    "Target": ("targets.target", "Target"), "load_target": ("targets.target", "load_target"),
    "losses": ("scoring.losses", None), "metrics": ("scoring.metrics", None),
    "LOSSES": ("names", "LOSSES"), "loss": ("scoring.losses", "loss"),
    "chamfer": ("scoring.metrics", "chamfer"), "evaluate": ("scoring.metrics", "evaluate"),
    "f1": ("scoring.metrics", "f1"), "iou": ("scoring.metrics", "iou"), "point_error": ("scoring.metrics", "point_error"),
    "strategies": ("fitting.strategies", None), "fit_many": ("fitting.batch", "fit_many"), "fit": ("fitting.fit", "fit"),
    "Checkpoint": ("fitting.options", "Checkpoint"), "RunOptions": ("fitting.options", "RunOptions"),
    "StrategyOptions": ("fitting.options", "StrategyOptions"), "FitResult": ("fitting.result", "FitResult"),
    "History": ("fitting.result", "History"), "Stage": ("fitting.result", "Stage"),
    "initialization": ("discovery.initialization", None), "best_fit_line": ("discovery.initialization", "best_fit_line"),
    "initialize": ("discovery.initialization", "initialize"),
    # beyond the paper: the automatic path, measures, compression, studies
    "auto": ("discovery.auto", None), "fractal": ("discovery.fractal", None),
    "Plan": ("discovery.plan", "Plan"), "discover": ("discovery.plan", "discover"),
    "chaos_measure": ("raster.measure", "chaos_measure"), "invariant_measure": ("raster.measure", "invariant_measure"),
    "cylinder_measure": ("raster.measure", "cylinder_measure"),
    "dimension": ("scoring.dimension", None), "fit_measure": ("fitting.measure_fit", "fit_measure"),
    "fit_measure_from_support": ("fitting.measure_fit", "fit_measure_from_support"),
    "compression": ("compression", None), "sweep": ("studies.sweep", None),
    # the teaching modules load matplotlib
    "exercises": ("teaching.exercises", None), "figures": ("teaching.figures", None),
    "landscape": ("teaching.landscape", None), "animate": ("teaching.animate", "animate"),
}


def __getattr__(name: str):
    if name not in _PUBLIC:
        raise AttributeError(f"module 'ifslib' has no attribute {name!r}")
    where, attribute = _PUBLIC[name]
    module = importlib.import_module(f".{where}", __name__)
    value = module if attribute is None else getattr(module, attribute)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))


__version__ = "0.1.0"

__all__ = sorted(_PUBLIC)
