"""Measures and dimension: the IFS with probabilities, its invariant measure (by the chaos game, or exactly
by cylinders), a fit of maps and probabilities to a gray image through that measure, and the dimensions
(similarity, Moran, box counting). Uses the core, and the automatic path for a start read from a support."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
