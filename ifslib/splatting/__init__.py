"""Splatting: a differentiable chaos game (chains' points splatted onto the pixel grid) and a fit of many maps and
their probabilities on it, the literature's way (Djeacoumar et al., CGF 2025), and the ``splat`` strategy that runs that
fit from ``ifslib.fit`` and the command line (`strategy`, registered in the core's table when this folder is imported). Uses the
core only."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
from .fit import SplatFit, SplatFitOptions, fit_splat
from .parameters import ContractiveMaps
from .render import SplatOptions, coverage, splat_measure
from . import strategy as _strategy  # noqa: F401, E402 - registers the ``splat`` strategy in the core's table

__all__ = ["ContractiveMaps", "SplatFit", "SplatFitOptions", "SplatOptions", "coverage", "fit_splat",
           "splat_measure"]
