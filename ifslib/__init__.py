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
from .threads import configure_threads

configure_threads()  # IFSLIB_THREADS=N fixes torch's thread count for the package; unset: the free cores

from .errors import IFSError  # noqa: E402
from .geometry import crossings, patterns  # noqa: E402
from .geometry.ifs import IFS  # noqa: E402
from .geometry.io import load_ifs, save_ifs  # noqa: E402
from .geometry.leaves import expand  # noqa: E402
from .geometry.primitives import Primitive  # noqa: E402
from .geometry.rules import Rule, rule_maps  # noqa: E402
from .raster.chaos import chaos_game  # noqa: E402
from .raster.measure import chaos_measure, invariant_measure  # noqa: E402
from .raster.distance import distance_field  # noqa: E402
from .raster.nearest import nearest_leaf, pixel_centres  # noqa: E402
from .raster.render import default_sigma, render  # noqa: E402
from . import data  # noqa: E402
from .targets.target import Target, load_target  # noqa: E402
from .scoring import dimension, losses, metrics  # noqa: E402
from .scoring.losses import LOSSES, loss  # noqa: E402
from .scoring.metrics import chamfer, evaluate, f1, iou, point_error  # noqa: E402
from . import compression  # noqa: E402
from .discovery import auto, fractal, initialization  # noqa: E402
from .discovery.initialization import best_fit_line, initialize  # noqa: E402
from .discovery.plan import Plan, discover  # noqa: E402
from .fitting import strategies  # noqa: E402
from .fitting.batch import fit_many  # noqa: E402
from .fitting.fit import fit  # noqa: E402
from .fitting.measure_fit import fit_measure  # noqa: E402
from .fitting.options import Checkpoint, RunOptions, StrategyOptions  # noqa: E402
from .fitting.result import FitResult, History, Stage  # noqa: E402
from .studies import sweep  # noqa: E402

#: The teaching modules load matplotlib; they are imported on first use (``ifslib.figures``), so the
#: command line and a fit without figures start half a second sooner.
_TEACHING = {"exercises": "exercises", "figures": "figures", "landscape": "landscape", "animate": "animate"}


def __getattr__(name: str):
    if name in _TEACHING:
        import importlib

        module = importlib.import_module(f".teaching.{_TEACHING[name]}", __name__)
        value = module.animate if name == "animate" else module
        globals()[name] = value
        return value
    raise AttributeError(f"module 'ifslib' has no attribute {name!r}")

__version__ = "0.1.0"

__all__ = ["Checkpoint", "FitResult", "History", "Plan", "RunOptions", "Stage", "StrategyOptions", "discover", "IFS", "IFSError", "LOSSES", "Primitive", "Rule", "Target", "animate", "auto", "best_fit_line", "fractal",
           "chamfer", "chaos_game", "chaos_measure", "configure_threads", "crossings", "data", "default_sigma", "dimension", "distance_field", "evaluate",
           "exercises", "expand", "f1", "figures", "fit", "fit_many", "fit_measure", "initialization", "initialize", "invariant_measure", "iou",
           "landscape", "load_ifs", "load_target", "loss", "losses", "metrics", "nearest_leaf", "patterns",
           "pixel_centres", "point_error", "render", "rule_maps", "save_ifs", "strategies", "sweep"]
