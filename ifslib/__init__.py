"""ifslib: differentiable iterated function systems. The paper's core is `ifslib.core`; each extension is a
folder that uses it and registers what it adds (docs/guide/design.md)."""
import importlib

#: Every public name, and where it lives: (module, attribute), or (module, None) for a module, imported on
#: first use, so the command line refuses a misspelt name before torch loads (`ifslib.threads`).
_PUBLIC = {
    "IFSError": ("errors", "IFSError"),
    "configure_threads": ("threads", "configure_threads"),
    "data": ("data", None),
    # the paper's core: geometry -> raster -> targets -> scoring -> fitting
    "crossings": ("core.geometry.crossings", None), "patterns": ("core.geometry.patterns", None),
    "IFS": ("core.geometry.ifs", "IFS"), "load_ifs": ("core.geometry.io", "load_ifs"), "save_ifs": ("core.geometry.io", "save_ifs"),
    "expand": ("core.geometry.leaves", "expand"), "Primitive": ("core.geometry.primitives", "Primitive"),
    "Rule": ("core.geometry.rules", "Rule"), "rule_maps": ("core.geometry.rules", "rule_maps"),
    "chaos_game": ("core.raster.chaos", "chaos_game"), "distance_field": ("core.raster.distance", "distance_field"),
    "nearest_leaf": ("core.raster.nearest", "nearest_leaf"), "pixel_centres": ("core.raster.nearest", "pixel_centres"),
    "default_sigma": ("core.raster.render", "default_sigma"), "render": ("core.raster.render", "render"),
    "Target": ("core.targets.target", "Target"), "load_target": ("core.targets.target", "load_target"),
    "losses": ("core.scoring.losses", None), "metrics": ("core.scoring.metrics", None),
    "LOSSES": ("names", "LOSSES"), "loss": ("core.scoring.losses", "loss"),
    "chamfer": ("core.scoring.metrics", "chamfer"), "evaluate": ("core.scoring.metrics", "evaluate"),
    "f1": ("core.scoring.metrics", "f1"), "iou": ("core.scoring.metrics", "iou"), "point_error": ("core.scoring.metrics", "point_error"),
    "strategies": ("core.fitting.strategies", None), "fit": ("core.fitting.fit", "fit"),
    "Checkpoint": ("core.fitting.options", "Checkpoint"), "RunOptions": ("core.fitting.options", "RunOptions"),
    "FitResult": ("core.fitting.result", "FitResult"),
    "History": ("core.fitting.result", "History"), "Stage": ("core.fitting.result", "Stage"),
    "initialization": ("core.targets.placement", None), "best_fit_line": ("core.targets.placement", "best_fit_line"),
    "initialize": ("core.targets.placement", "initialize"),
    # beyond the paper: the automatic path, measures, compression, studies
    # (each extension is a subpackage: ifslib.automatic, ifslib.measures, ifslib.splatting, ifslib.studies)
    "discover": ("automatic.plan", "discover"), "dimension": ("measures.dimension", None),
    "compression": ("compression", None), "sweep": ("studies.sweep", None),
    "random_fractals": ("core.geometry.random_fractals", None),
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
