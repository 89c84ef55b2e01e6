"""A figure's second moments: the symmetric square root of a covariance, which both the shape starts
(`ifslib.automatic.auto.shape_maps`) and the fractal search's region copies (`ifslib.automatic.fractal.regions`)
use to take one figure's mean and covariance onto another's."""
from __future__ import annotations

import numpy as np


def sqrtm_psd(c: np.ndarray) -> np.ndarray:
    """``(2, 2)`` symmetric square root of a ``(2, 2)`` covariance matrix ``c`` (eigenvalues floored at 1e-12, so
    a flat figure's root is invertible)."""
    w, v = np.linalg.eigh(c)
    return v @ np.diag(np.sqrt(np.maximum(w, 1e-12))) @ v.T
