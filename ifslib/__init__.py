"""ifslib: differentiable iterated function systems.

The paper's pipeline, one module a step::

    JSON / pattern -> IFS -> maps -> leaves -> nearest leaf -> distance -> render / loss -> fit -> IFS

Typical use::

    import ifslib
    ifs = ifslib.patterns.koch(depth=4)
    image = ifslib.render(ifs, 256)            # (256, 256) tensor in [0, 1], differentiable
"""
from . import patterns
from .distance import distance_field
from .errors import IFSError
from .ifs import IFS
from .io import load_ifs, save_ifs
from .leaves import expand
from .nearest import nearest_leaf, pixel_centres
from .primitives import Primitive
from .render import default_sigma, render
from .rules import Rule, rule_maps
from .threads import configure_threads

configure_threads()  # IFSLIB_THREADS, when set, fixes torch's thread count once for the package

__version__ = "0.1.0"

__all__ = ["IFS", "IFSError", "Primitive", "Rule", "default_sigma", "distance_field", "expand", "load_ifs",
           "nearest_leaf", "patterns", "pixel_centres", "render", "rule_maps", "save_ifs",
           "configure_threads"]

from . import data, exercises, figures, initialization, landscape, metrics, strategies, sweep  # noqa: E402
from .animate import animate  # noqa: E402
from .batch import fit_many  # noqa: E402
from .fit import FitResult, fit  # noqa: E402
from .initialization import best_fit_line, initialize  # noqa: E402
from .losses import LOSSES, loss  # noqa: E402
from .metrics import chamfer, evaluate, f1, iou, point_error  # noqa: E402
from .targets import Target, load_target  # noqa: E402

__all__ += ["FitResult", "LOSSES", "animate", "Target", "best_fit_line", "chamfer", "data", "evaluate", "f1", "fit", "fit_many",
            "exercises", "figures", "initialization", "initialize", "landscape", "iou", "load_target", "loss",
            "metrics", "point_error", "strategies", "sweep"]
