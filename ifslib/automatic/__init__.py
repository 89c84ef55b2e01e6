"""The automatic path: a start read from the image and its fit. The plan (curve, shape, or a fractal's
maps found by the fractal search: `ifslib.discover`), and the
``auto`` strategy, which it registers in the core's table of strategies (`ifslib.core.fitting.strategies`)."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
from . import fit_plan as _fit_plan  # noqa: F401, E402 - registers the ``auto`` strategy in the core's table
from . import auto, fractal  # noqa: E402
from .plan import Plan, discover  # noqa: E402

__all__ = ["Plan", "auto", "discover", "fractal"]
