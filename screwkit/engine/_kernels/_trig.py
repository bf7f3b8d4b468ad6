"""Sine and cosine in straight-line arithmetic, compiled (private).

The products of exponentials take a sine and a cosine per joint and lane; the C library's
are calls, taken one lane at a time, while :func:`sin_cos` has no call and no branch taken
per value, so that a loop of it over a block's lanes vectorises (1.6 ns a pair against 9.7
ns, AVX-512).  fdlibm's (FreeBSD's) algorithm: the three-part Cody-Waite reduction by pi/2
and its minimax polynomials on [-pi/4, pi/4]; within 2.5 ulps of the exact values
(``tests/test_kernels_sincos.py`` against extended precision and the C library).  And
the ratio of a small angle to its sine (:func:`angle_over_sine`): the closure errors'
rotation vectors without a call of ``atan2``.  And whether a sine or cosine certainly
exceeds a small tolerance (:func:`trig_exceeds`): the representation singularity's tests
without a call of the C library for nearly every pose.
"""

import math

from ._jit import borrowing_inlined, choose, inlined

#: The largest angle (radians) :func:`sin_cos` reduces itself (its three-part Cody-Waite
#: reduction is exact for multiples of pi/2 below 2**20); beyond, and for a non-finite angle,
#: the caller takes libm's (:func:`sin_cos_fix`).
SIN_COS_MAX = 1e5
# fdlibm's (FreeBSD's) pi/2 in three parts of 33 bits (fn * part exact for |fn| < 2**20) and
# its minimax polynomials of sin and cos on [-pi/4, pi/4] (errors below one ulp)
_INV_PIO2 = 6.36619772367581382433e-01
_PIO2_1, _PIO2_2, _PIO2_3 = 1.57079632673412561417e+00, 6.07710050630396597660e-11, \
    2.02226624871116645580e-21
_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, \
    -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, \
    1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, \
    2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, \
    -1.13596475577881948265e-11


@inlined
def sin_cos(x):
    """``(sin x, cos x)`` for ``|x| <= SIN_COS_MAX``, in straight-line arithmetic (no call,
    no branch taken per value), so that a loop of them over a block's lanes vectorises
    (libm's ``sin`` and ``cos`` are calls, one lane at a time).  fdlibm's algorithm: ``x =
    fn pi/2 + r``, ``|r| <= pi/4``, and its minimax polynomials; within two ulps of
    correctly rounded (``tests/test_kernels_sincos.py`` measures it against libm).  Beyond
    ``SIN_COS_MAX`` or for a non-finite ``x`` the result is meaningless: see
    :func:`sin_cos_fix`."""
    fn = math.floor(x * _INV_PIO2 + 0.5)
    r = ((x - fn * _PIO2_1) - fn * _PIO2_2) - fn * _PIO2_3
    z = r * r
    w = z * z
    ps = _S2 + z * (_S3 + z * _S4) + z * w * (_S5 + z * _S6)
    sn = r + (z * r) * (_S1 + z * ps)
    pc = z * (_C1 + z * (_C2 + z * _C3)) + w * w * (_C4 + z * (_C5 + z * _C6))
    hz = 0.5 * z
    v = 1.0 - hz
    cs = v + (((1.0 - v) - hz) + z * pc)
    q = fn - 4.0 * math.floor(fn * 0.25)        # the quadrant, 0 to 3
    odd = q == 1.0 or q == 3.0
    s = cs if odd else sn
    c = sn if odd else cs
    s = -s if q >= 2.0 else s
    c = -c if q == 1.0 or q == 2.0 else c
    return s, c


@inlined
def sin_cos_fix(x, s, c):
    """``(s, c)`` from :func:`sin_cos`, or libm's where ``x`` is beyond its range (a loop of
    these after the vectorised one, where :func:`beyond_sin_cos` counts a lane)."""
    if abs(x) <= SIN_COS_MAX:
        return s, c
    return math.sin(x), math.cos(x)


@inlined
def beyond_sin_cos(x):
    """1 where :func:`sin_cos` does not hold for ``x`` (beyond :data:`SIN_COS_MAX`, or not
    finite), else 0: summed over a block's lanes in a loop of its own (vectorised), it tells
    whether the loop of :func:`sin_cos_fix` is needed at all (that loop is scalar, a lane
    and a branch at a time, and almost never changes a lane)."""
    return choose(abs(x) <= SIN_COS_MAX, 0, 1)


#: Below this angle (rad) :func:`angle_over_sine` holds: the next term of its series, ``35
#: s^8 / 1152``, is 3e-18 at 1e-2, below the rounding of 1.
SMALL_ANGLE = 1e-2
_ASIN1, _ASIN2, _ASIN3 = 1.0 / 6.0, 3.0 / 40.0, 5.0 / 112.0


@inlined
def angle_over_sine(z):
    """``asin(s) / s`` from ``z = s^2``, ``s`` the sine of an angle in ``[0, SMALL_ANGLE]``:
    the series ``1 + s^2 / 6 + 3 s^4 / 40 + 5 s^6 / 112`` (straight-line arithmetic, so that
    a lane loop of it vectorises; a closure error's rotation vector is its axial vector
    ``w``, of norm ``s``, times this)."""
    return 1.0 + z * (_ASIN1 + z * (_ASIN2 + z * _ASIN3))


#: 1 / pi.
_INV_PI = 0.3183098861837907


@borrowing_inlined
def trig_exceeds(b, sine, tol):
    """Whether ``|sin b|`` (``sine``) or ``|cos b|`` certainly exceeds ``tol`` (at most
    1e-2), told without a call of the C library: ``b``'s distance ``d`` to the nearest zero
    of the function (a multiple of pi, or of pi plus pi / 2) bounds it from below (``|sin
    d| >= 2 d / pi`` up to pi / 2), and ``d`` is computed to within 1e-9 for ``|b| <
    1e6``.  False where that does not settle it (then the caller takes the C library's
    value, as it always did: the same results, a call fewer for nearly every pose)."""
    if not abs(b) < 1e6:
        return False
    h = b * _INV_PI if sine else b * _INV_PI - 0.5
    k = math.floor(h + 0.5)
    d = abs(b - (k if sine else k + 0.5) * math.pi)
    return d > 1.5707963267948966 * tol + 1e-9
