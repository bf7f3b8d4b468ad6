"""Inverse displacement of N poses by the kernels: the solved closures and the home
predictor (private).

Each pose is solved by :func:`screwkit.engine._kernels._closures.solve_pose`: Gauss-Newton
from a start (a warm start, or the home predictor), continuation from home in 4, 16, then
64 steps where Newton fails, a polish of poses left just short of convergence, and the
representation singularity (``beta`` given where ``sin(beta) = 0``, proper orders, or
``cos(beta) = 0``, Tait-Bryan, while ``alpha`` or ``gamma`` is dependent: the dependent angle
taken as its limit from both sides, or from the warm start's side, then the pose solved with
it given).

The home predictor is a polynomial model of the solution around home, fitted once per model
by least squares to exact solutions on a grid around home (+-0.15 rad, +-0.15 ``L``; no
level at home itself, so that no fitting pose sits at a representation singularity of
home).  Up to five independent parameters it is quartic: up to three, on the full grid of
five levels per parameter (-1, -1/2, 1/10, 1/2, 1 half-widths: 125 poses); with four or
five, on the grid of three levels (-1, 1/10, 1) and, for each pair of parameters, the
five-by-five grid of their plane (the others at 1/10: 161 and 373 poses), enough for a
quartic, whose monomials of a power above two involve at most two parameters.  With six
(5^6 poses, 210 monomials for each unknown of a pose) it stays cubic: three levels and, on
each parameter's axis, two more (a cubic needs four).  A quadratic leaves most random poses
of a 4SPS+SPR or a 6-SPS three Newton steps from their solution, the cubic two within the
fit; beyond it, a cubic leaves the poses of the benchmarks' wider ranges (a 3RRPRR's alpha
and beta in +-10 deg, Zo in 60-100 cm: up to twice the half-width) three steps away about
one time in seven, and since a block of poses iterates until its last lane is done, nearly
every block a third time; the quartic, two steps away but for about one in 500.  Far
outside the grid (more than four half-widths) the start is home itself.
"""

from __future__ import annotations

import dataclasses
import itertools
import weakref

import numpy as np

from ._chains import LENGTH_PARAMS, Chains, chains_of
from ._kernels._layout import ACCEPTED, CONVERGED

__all__ = ["Closure", "Closures", "solve_closures", "predictor_of", "is_representation_singular"]

_SING_TOL = 1e-7
#: Half-width of the predictor's fitting grid: radians, and fractions of ``L``.
_FIT_SPAN = 0.15


@dataclasses.dataclass(frozen=True, eq=False)
class Closure:
    """Solved loop closures of N poses: ``X (n_unknowns, N)``, ``residual``, ``iterations``,
    ``how`` (0: Newton from the start; 1: continuation from home; 2: not solved),
    ``singular_beta`` (a representation singularity resolved by continuity)."""

    chains: Chains
    X: np.ndarray
    frames: object
    residual: np.ndarray
    iterations: np.ndarray
    how: np.ndarray
    singular_beta: np.ndarray
    diagnostics: dict = dataclasses.field(default_factory=dict)


@dataclasses.dataclass(frozen=True, eq=False)
class Closures:
    """The solver's arrays for N poses: ``X (n_unknowns, N)``, ``fixed`` (the independent
    parameters, ``(N,)`` each), ``residual``, ``iterations``, ``how`` (0: Newton from the
    start, 1: continuation, 2: not solved), ``singular_beta``; ``reversed`` (None: none)
    the poses whose only solution found runs a leg's linear actuator to a negative length
    (:mod:`._reversal`): closed, but unreachable (no real actuator assembles so)."""

    chains: Chains
    X: np.ndarray
    fixed: dict
    residual: np.ndarray
    iterations: np.ndarray
    how: np.ndarray
    singular_beta: np.ndarray
    reversed: np.ndarray = None

    def take(self, sl) -> "Closures":
        return Closures(self.chains, self.X[:, sl], {k: v[sl] for k, v in self.fixed.items()},
                        self.residual[sl], self.iterations[sl], self.how[sl],
                        self.singular_beta[sl],
                        None if self.reversed is None else self.reversed[sl])

    @property
    def reachable(self) -> np.ndarray:
        """``(N,)``: closed (residual at most ``ACCEPTED``) and not reversed."""
        ok = self.residual <= ACCEPTED
        return ok if self.reversed is None else ok & ~self.reversed

    @property
    def solved(self) -> np.ndarray:
        """``(N,)``: converged (residual at most ``CONVERGED``) and not reversed."""
        ok = self.residual <= CONVERGED
        return ok if self.reversed is None else ok & ~self.reversed

    def params(self, sl=slice(None)) -> np.ndarray:
        """``P6 (N, 6)`` of the poses ``sl``: the given parameters (the others 0)."""
        fx = {k: np.asarray(v, float)[sl] for k, v in self.fixed.items()}
        N = self.X[:, sl].shape[1]
        return self.chains.full_params(fx, N)

    def frames(self, sl=slice(None), **what) -> dict:
        """The kernels' frames of the poses ``sl`` (:func:`screwkit.engine._launch.frames`)."""
        from ._launch import frames
        ch = self.chains
        return frames(ch.flat, ch.flat.Z, self.params(sl), self.X[:, sl].T, **what)


def is_representation_singular(order: str, beta, tol: float = _SING_TOL):
    proper = order[0].lower() == order[2].lower()
    return np.abs(np.sin(beta) if proper else np.cos(beta)) <= tol


_PREDICTORS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _monomials(nf, degree):
    """The predictor's monomials in the kernel's order (:func:`._kernels._closures.predict`):
    1, then by degree the products ``z_a z_b ...`` with ``a <= b <= ...``."""
    return [c for d in range(degree + 1)
            for c in itertools.combinations_with_replacement(range(nf), d)]


def _least_squares(A, Y):
    """``C`` minimising ``|A C - Y|``: the normal equations, formed and solved in numpy's own
    loops (``einsum``), never through BLAS or LAPACK.  Their results depend on how many
    threads OpenBLAS runs (``numpy.linalg.solve`` of the 126 x 126 normal equations of a
    4SPS+SPR gave other bits on one core than on two), and a Dask worker runs it on one
    (``OPENBLAS_NUM_THREADS=1``): the predictor, so the starts and the last bits of every
    solution, must not depend on the process.  LAPACK's ``lstsq`` also handed matrices of
    these sizes to OpenBLAS's threads, which on a busy machine took 30-250 ms.  The
    monomials' Gram matrix is well enough conditioned (``A``'s condition number at most about
    200 on these grids) for a start, which needs a few digits; where failed fitting poses
    leave it near singular, the monomials it cannot tell apart are left out (their
    coefficients 0: :func:`_cholesky_solve`)."""
    return _cholesky_solve(np.einsum("pk,pl->kl", A, A), np.einsum("pk,px->kx", A, Y))


def _cholesky_solve(G, B, rtol=1e-5):
    """``X`` with ``G X = B`` for the symmetric positive semi-definite ``G (n, n)``, ``B (n,
    k)``, by its Cholesky factor formed column by column; a column whose pivot's square root
    is at most ``rtol`` times that of ``G``'s largest diagonal entry is dropped (its row of
    ``X`` 0: the solution on the other columns).  Every sum is an ``einsum`` (numpy's loops, the
    same bits whatever the threads)."""
    n = G.shape[0]
    L = np.zeros((n, n))
    keep = np.zeros(n, bool)
    floor = (rtol * rtol) * float(np.max(np.diag(G), initial=0.0))
    for j in range(n):
        v = G[j:, j] - np.einsum("ik,k->i", L[j:, :j], L[j, :j])
        if v[0] > floor:
            d = np.sqrt(v[0])
            L[j + 1:, j] = v[1:] / d
            L[j, j] = d
            keep[j] = True
    Z = np.zeros(B.shape)
    for i in range(n):
        if keep[i]:
            Z[i] = (B[i] - np.einsum("k,kx->x", L[i, :i], Z[:i])) / L[i, i]
    X = np.zeros(B.shape)
    for i in range(n - 1, -1, -1):
        if keep[i]:
            X[i] = (Z[i] - np.einsum("k,kx->x", L[i + 1:, i], X[i + 1:])) / L[i, i]
    return X


def _fit_grid(nf):
    """``(G, degree)``: the predictor's fitting poses in half-widths ``G (poses, nf)`` and
    its degree (see the module docstring)."""
    if nf <= 3:
        levels = (-1.0, -0.5, 0.1, 0.5, 1.0)
        return np.array(list(itertools.product(levels, repeat=nf))).reshape(-1, nf), 4
    if nf <= 5:
        G = [np.array(list(itertools.product((-1.0, 0.1, 1.0), repeat=nf)))]
        face = np.array(list(itertools.product((-1.0, -0.5, 0.1, 0.5, 1.0), repeat=2)))
        for a, b in itertools.combinations(range(nf), 2):
            F = np.full((len(face), nf), 0.1)
            F[:, [a, b]] = face
            G.append(F)
        return np.unique(np.concatenate(G), axis=0), 4
    G = np.array(list(itertools.product((-1.0, 0.1, 1.0), repeat=nf)))
    axes = np.full((2 * nf, nf), 0.1)
    for k in range(nf):
        axes[2 * k, k], axes[2 * k + 1, k] = -1.0 / 3.0, 1.0 / 3.0
    return np.concatenate([G, axes]), 3


def predictor_of(ch: Chains) -> tuple:
    """The pose parametrisation ``Z`` of the kernels with the home predictor of the model
    (fitted once, cached with the chains; see the module docstring)."""
    Z = _PREDICTORS.get(ch)
    if Z is not None:
        return Z
    from ._launch import run_poses
    flat = ch.flat
    nf = len(ch.fixed)
    home = np.array([ch.home[p] for p in ch.fixed])
    span = np.array([_FIT_SPAN * ch.length if p in LENGTH_PARAMS else _FIT_SPAN
                     for p in ch.fixed])
    G, degree = _fit_grid(nf)
    fixed = {p: home[k] + span[k] * G[:, k] for k, p in enumerate(ch.fixed)}
    # (in this thread: a few milliseconds; in blocks where the parallel kernel is loaded
    # already (3 to 3.6 times less CPU), else by the serial kernel, so that a one-pose
    # command neither loads nor, on its first run, compiles the parallel kernel; the bits
    # do not depend on the kernel or the threads)
    out = run_poses(flat, flat.Z, ch.full_params(fixed, len(G)),
                    X0=ch.home_vector(len(G)).T, rows=False, workers=1, blocks=None)
    good = out["residual"] <= CONVERGED
    mono = _monomials(nf, degree)
    C = np.zeros((0, ch.n_unknowns))
    if good.sum() >= 2 * len(mono):
        Zs = G[good]
        A = np.stack([np.prod(Zs[:, list(c)], axis=1) for c in mono], axis=1)
        C = _least_squares(A, out["X"][good])
    Z = flat.with_predictor(C, home, span, degree)
    _PREDICTORS[ch] = Z
    return Z


def solve_closures(model, fixed: dict, start=None, *, side=None, continuation: bool = True,
                   workers=None) -> Closure:
    """Solve N poses of ``model`` (closures only).

    Parameters
    ----------
    model : PMModel
    fixed : dict str -> ndarray (N,)
        The independent pose parameters (radians, model lengths), finite.
    start : ndarray (n_unknowns, N), optional
        Warm starts; default the home predictor.
    side : ndarray (N,), optional
        Sign of ``beta - beta_singular`` of the warm start, for the one-sided limit at a
        representation singularity (0: both sides).
    continuation : bool
        Solve the poses where Newton fails again by continuation from home (default); a
        path's retries from a neighbour do without.
    """
    from ._launch import run_poses
    ch = chains_of(model)
    fixed = {p: np.asarray(fixed[p], float) for p in ch.fixed}
    N = len(next(iter(fixed.values())))
    X0 = None if start is None else np.asarray(start, float).T
    out = run_poses(ch.flat, predictor_of(ch), ch.full_params(fixed, N), X0=X0, side=side,
                    rows=False, continuation=continuation, workers=workers)
    return Closure(ch, out["X"].T, None, out["residual"], out["iterations"], out["how"],
                   out["singular_beta"])

