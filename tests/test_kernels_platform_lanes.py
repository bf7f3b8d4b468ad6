"""The platform of a block's lanes (``_kernels._platform.platform_block``) against scipy's
``Rotation.from_euler`` (an independent reference), for intrinsic and extrinsic orders, with
lanes whose angles lie beyond ``_trig.sin_cos``'s own range (there the C library's sine and
cosine, in a loop run only where a lane needs it) and a NaN lane among finite ones."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from screwkit.engine._kernels._layout import BLOCK, P_P0, P_R0


@pytest.fixture(scope="module")
def platforms():
    from numba import njit

    from screwkit.engine._kernels._platform import platform_block

    @njit(cache=False)
    def run(order, plat, FP, nb):
        platform_block(order, plat, FP, nb)

    return run


@pytest.mark.parametrize("seq, order", [("XYX", (0, 1, 0, 1)), ("ZYX", (2, 1, 0, 1)),
                                        ("zyx", (2, 1, 0, 0)), ("xzy", (0, 2, 1, 0))])
def test_block_platforms_match_scipy_within_and_beyond_the_own_sine_range(platforms, seq,
                                                                          order):
    from screwkit.engine._kernels._trig import SIN_COS_MAX
    rng = np.random.default_rng(len(seq) + sum(order))
    nb = BLOCK - 3                                   # (a partial block)
    angles = rng.uniform(-np.pi, np.pi, (nb, 3))
    # beyond SIN_COS_MAX: the C library's (sin_cos's own reduction is off by 1e-8 at 1e9,
    # by everything at 1e16 and beyond)
    angles[5, 0] = 1.0e9
    angles[6, 1] = -1.0e16
    angles[7, 2] = 1.0e20
    angles[8, 0] = SIN_COS_MAX * 4.0
    angles[9, 1] = np.nan                            # a NaN lane among finite ones
    R0 = Rotation.from_rotvec([0.3, -0.2, 0.9]).as_matrix()   # the base's frame
    plat = np.zeros(40)
    plat[P_R0:P_R0 + 9] = R0.ravel()
    plat[P_P0:P_P0 + 3] = (1.0, -2.0, 0.5)
    FP = np.zeros((27, BLOCK))
    FP[0:3, :nb] = rng.normal(size=(3, nb))
    FP[3:6, :nb] = angles.T
    platforms(np.array(order, np.int64), plat, FP, nb)
    finite = ~np.isnan(angles).any(axis=1)
    want = R0 @ Rotation.from_euler(seq, angles[finite]).as_matrix()
    got = FP[6:15, :nb].T.reshape(nb, 3, 3)[finite]
    assert np.max(np.abs(got - want)) < 1e-13
    assert np.isnan(FP[6:15, 9]).any()               # the NaN lane is NaN, not a value
    # the origin: the pose's position in the base's frame, from its point P0
    o = FP[0:3, :nb].T[finite] @ R0.T + plat[P_P0:P_P0 + 3]
    assert np.max(np.abs(FP[15:18, :nb].T[finite] - o)) < 1e-13
