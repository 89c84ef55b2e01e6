"""The automatic path: a start read from the image and its fit. The plan (curve, shape, or a fractal's
maps found by the fractal search), `initialize` (a pattern placed on the target, or a plan), and the
``auto`` strategy, which it registers in the core's table of strategies (`ifslib.core.fitting.strategies`)."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
