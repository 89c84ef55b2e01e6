"""`ifslib.automatic.moments`: the symmetric square root of a covariance."""
import numpy as np

from ifslib.automatic.moments import sqrtm_psd


def test_the_root_is_symmetric_and_squares_to_the_covariance_and_a_flat_one_stays_invertible():
    rng = np.random.default_rng(0)
    for _ in range(5):
        a = rng.normal(size=(2, 2))
        c = a @ a.T
        root = sqrtm_psd(c)
        np.testing.assert_allclose(root, root.T, atol=1e-12)
        np.testing.assert_allclose(root @ root, c, atol=1e-10)
        assert np.linalg.eigvalsh(root).min() > 0
    flat = sqrtm_psd(np.diag([1.0, 0.0]))  # a line's covariance: floored, not singular
    assert np.isfinite(np.linalg.inv(flat)).all()
