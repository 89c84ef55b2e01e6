"""Measures and dimension: the IFS with probabilities, its invariant measure (by the chaos game, or exactly
by cylinders), a fit of maps and probabilities to a gray image through that measure, and the dimensions
(similarity, Moran, box counting). Uses the core, and the automatic path for a start read from a support."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
from . import dimension  # noqa: E402
from .collage_search import fit_measure_from_collage  # noqa: E402
from .measure import chaos_measure, cylinder_measure, invariant_measure  # noqa: E402
from .measure_fit import fit_measure, fit_measure_from_support  # noqa: E402

__all__ = ["chaos_measure", "cylinder_measure", "dimension", "fit_measure", "fit_measure_from_collage",
           "fit_measure_from_support", "invariant_measure"]
