"""The platform of a block of lanes (poses), compiled (private): the pose parameters' rotation
(Euler angles), the platform's frame and the angular Jacobian of the angles, into a lane of
``FP`` (``_kin``'s module docstring), written once as lane loops (:func:`platform_lanes`,
the lane axis last) and compiled twice, once per lane stride: :func:`._kin.platform` (one
pose, a block of one lane, :func:`~._jit.one_lane`) and :func:`platform_block` (a block of
:data:`._layout.BLOCK`).  Each is a function of its own, compiled once and called by every
forward pass (not typed again inside each caller: numba's IR inlining of the lane loops
into every kernel of the forward pass doubled the first run's compile); within each the
stride is a constant, so that LLVM folds the one-pose loops and vectorises the block's.
"""

from ._jit import borrowing, borrowing_inlined, choose, inlined, lanes
from ._layout import BLOCK, P_P0, P_R0
from ._trig import beyond_sin_cos, sin_cos, sin_cos_fix


@borrowing_inlined
def axis_entries(ax, c, s):
    """The rotation by the angle of cosine ``c`` and sine ``s`` about the base axis ``ax``
    (0, 1, 2), row-major: a select per entry (:func:`~._jit.choose`), so that a lane loop
    over it vectorises (``ax`` is the model's; returned from branches, the tuple kept the
    platform's lane loop scalar)."""
    x, y, z = ax == 0, ax == 1, ax == 2
    return (choose(x, 1.0, c), choose(z, -s, 0.0), choose(y, s, 0.0),
            choose(z, s, 0.0), choose(y, 1.0, c), choose(x, -s, 0.0),
            choose(y, -s, 0.0), choose(x, s, 0.0), choose(z, 1.0, c))


@borrowing_inlined
def mul3(A, B):
    """``A @ B`` of two row-major 3x3 tuples (each entry's three products summed in order)."""
    return (A[0] * B[0] + A[1] * B[3] + A[2] * B[6], A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
            A[0] * B[2] + A[1] * B[5] + A[2] * B[8], A[3] * B[0] + A[4] * B[3] + A[5] * B[6],
            A[3] * B[1] + A[4] * B[4] + A[5] * B[7], A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
            A[6] * B[0] + A[7] * B[3] + A[8] * B[6], A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
            A[6] * B[2] + A[7] * B[5] + A[8] * B[8])


@borrowing_inlined
def column(A, a):
    """Column ``a`` of the row-major 3x3 tuple ``A`` (selects, as :func:`axis_entries`)."""
    x, y = a == 0, a == 1
    return (choose(x, A[0], choose(y, A[1], A[2])), choose(x, A[3], choose(y, A[4], A[5])),
            choose(x, A[6], choose(y, A[7], A[8])))


@borrowing_inlined
def unit(a):
    """The base vector ``e_a``."""
    return choose(a == 0, 1.0, 0.0), choose(a == 1, 1.0, 0.0), choose(a == 2, 1.0, 0.0)


@borrowing_inlined
def platform_row(plat, FPb, k, ls, r, Rb, E0, E1, E2):
    """Row ``r`` of lane ``k``'s ``Rp = R0 Rb``, ``o`` and ``E = R0 [E0 E1 E2]`` into ``FPb``
    (:func:`platform_lanes`'s; the array, not its pointer, so that the argument types have
    a text ``first_compile.txt`` can hold)."""
    fp = lanes(FPb)
    x0, x1, x2 = plat[P_R0 + 3 * r], plat[P_R0 + 3 * r + 1], plat[P_R0 + 3 * r + 2]
    fp[(6 + 3 * r) * ls + k] = x0 * Rb[0] + x1 * Rb[3] + x2 * Rb[6]
    fp[(7 + 3 * r) * ls + k] = x0 * Rb[1] + x1 * Rb[4] + x2 * Rb[7]
    fp[(8 + 3 * r) * ls + k] = x0 * Rb[2] + x1 * Rb[5] + x2 * Rb[8]
    fp[(18 + 3 * r) * ls + k] = x0 * E0[0] + x1 * E0[1] + x2 * E0[2]
    fp[(19 + 3 * r) * ls + k] = x0 * E1[0] + x1 * E1[1] + x2 * E1[2]
    fp[(20 + 3 * r) * ls + k] = x0 * E2[0] + x1 * E2[1] + x2 * E2[2]
    fp[(15 + r) * ls + k] = (x0 * fp[k] + x1 * fp[ls + k] + x2 * fp[2 * ls + k]
                             + plat[P_P0 + r])


@borrowing
def platform_block(order, plat, FPb, nb):
    """The platforms of the ``nb`` lanes of a block ``FPb (27, BLOCK)`` (:func:`platform_lanes`)."""
    platform_lanes(order, plat, FPb, nb, BLOCK)


@inlined
def platform_lanes(order, plat, FPb, nb, ls):
    """The platforms of ``nb`` lanes at the pose parameters (Xo Yo Zo alpha beta gamma)
    already in rows 0-5 of ``FPb (27, ls)`` into its other rows (module docstring); Euler
    angles as scipy's ``Rotation.from_euler`` defines them.  The sines and cosines are
    :func:`._trig.sin_cos`'s (a lane loop, vectorised, as the joints'; libm's beyond its
    range), parked in rows 18-23 (``E``'s, written last); the rest runs across the lanes
    too (the Euler order is the model's, a select per entry of :func:`axis_entries`).
    Inlined into :func:`._kin.platform` and :func:`platform_block` only, where ``ls`` is a
    constant."""
    a0, a1, a2 = order[0], order[1], order[2]
    fp = lanes(FPb)
    for q in range(3):
        for k in range(nb):
            fp[(19 + 2 * q) * ls + k], fp[(18 + 2 * q) * ls + k] = sin_cos(fp[(3 + q) * ls + k])
        far = 0
        for k in range(nb):
            far += beyond_sin_cos(fp[(3 + q) * ls + k])
        if far:
            for k in range(nb):
                x = fp[(3 + q) * ls + k]
                fp[(19 + 2 * q) * ls + k], fp[(18 + 2 * q) * ls + k] = sin_cos_fix(
                    x, fp[(19 + 2 * q) * ls + k], fp[(18 + 2 * q) * ls + k])
    if order[3] == 1:              # intrinsic: R = R1(alpha) R2(beta) R3(gamma)
        for k in range(nb):
            R1 = axis_entries(a0, fp[18 * ls + k], fp[19 * ls + k])
            R12 = mul3(R1, axis_entries(a1, fp[20 * ls + k], fp[21 * ls + k]))
            Rb = mul3(R12, axis_entries(a2, fp[22 * ls + k], fp[23 * ls + k]))
            E0, E1, E2 = unit(a0), column(R1, a1), column(R12, a2)
            platform_row(plat, FPb, k, ls, 0, Rb, E0, E1, E2)
            platform_row(plat, FPb, k, ls, 1, Rb, E0, E1, E2)
            platform_row(plat, FPb, k, ls, 2, Rb, E0, E1, E2)
    else:                          # extrinsic: R = R3(gamma) R2(beta) R1(alpha)
        for k in range(nb):
            R1 = axis_entries(a2, fp[22 * ls + k], fp[23 * ls + k])
            R12 = mul3(R1, axis_entries(a1, fp[20 * ls + k], fp[21 * ls + k]))
            Rb = mul3(R12, axis_entries(a0, fp[18 * ls + k], fp[19 * ls + k]))
            E0, E1, E2 = column(R12, a0), column(R1, a1), unit(a2)
            platform_row(plat, FPb, k, ls, 0, Rb, E0, E1, E2)
            platform_row(plat, FPb, k, ls, 1, Rb, E0, E1, E2)
            platform_row(plat, FPb, k, ls, 2, Rb, E0, E1, E2)
