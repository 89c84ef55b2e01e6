"""A learned first guess of an IFS's maps from its picture (`guess`), trained on the project's own random fractals
by ``python -m ifslib.learned.train``; the fits refine it."""
from .estimator import guess

__all__ = ["guess"]
