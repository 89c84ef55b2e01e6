"""Teaching: what the notebooks show and ask. Figures, the explorer widget, animations, the
exercises' harness and targets (no answer key: those live in the instructor's notebooks), and loss
landscapes. Imports from everything below it."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
