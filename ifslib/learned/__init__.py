"""A learned first guess of an IFS's maps from its picture (`guess`), trained on the project's own random fractals
by ``python -m ifslib.learned.train``; the fits refine it."""
from .. import threads as _threads  # noqa: F401 - torch's thread settings before this folder loads torch
from .estimator import guess

__all__ = ["guess"]
