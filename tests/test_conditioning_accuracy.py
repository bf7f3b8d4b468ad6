"""The printed condition number near a singularity, against numpy's SVD of the same matrix.

The engine takes the singular values from the eigenvalues of the Gram matrix where the
condition is moderate (fast) and from an SVD beyond ``REFINE``; either way the number it
prints must agree with an SVD of the length-normalised, row-equilibrated ``J`` built here.
"""

import numpy as np

import screwkit


def _normalised(J, c, L):
    f, m = J[..., :3], J[..., 3:]
    Jn = np.concatenate([f, (m - np.cross(c[:, None, :], f)) / L[:, None, None]], axis=-1)
    return Jn / np.linalg.norm(Jn, axis=-1, keepdims=True)


def test_condition_number_agrees_with_an_svd_up_to_the_singular_surface():
    pm = screwkit.load_pm("2SPS+2SPR")
    # alpha + gamma -> 16.589 deg at beta = 0, Zo = 75 (the singular surface of docs/maps.md):
    # conditions from ~10 to beyond 1e4 along the approach
    alpha = 16.589 - np.geomspace(8.0, 1e-3, 60)
    zero = np.zeros(60)
    res = screwkit.analyze(pm, {"alpha": alpha, "beta": zero, "gamma": zero,
                                "Zo": np.full(60, 75.0)}, degrees=True, raise_on_singular=False)
    jac = res.jacobian
    c = jac.conditioning
    s = np.linalg.svd(_normalised(jac.matrix, c.centre, c.length), compute_uv=False)
    ref = s[:, 0] / s[:, -1]
    assert ref.max() > 1e4 and ref.min() < 1e2          # the range the two methods share
    rel = np.abs(jac.condition_number - ref) / ref
    # the smallest singular value is known to ~eps * cond relative from the SVD
    assert np.all(rel <= 1e-13 * ref + 1e-12), (ref[rel.argmax()], rel.max())
