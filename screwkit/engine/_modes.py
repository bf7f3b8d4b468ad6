"""Assembly modes: every real solution of the forward kinematics found from many seeds.

:func:`assembly_modes` starts the forward Gauss-Newton of :mod:`screwkit.engine._forward`
from ``seeds`` states at once (home, then random values of every passive revolute joint,
uniform in [-pi, pi], with the platform where the first leg then ends), with the actuated
joints at their targets, and keeps the distinct converged platform poses (two are the same when their centres agree to :data:`SAME` of the length
and their rotations to :data:`SAME` rad).  A seed search finds solutions, it does not prove
that there are no others: the count is a lower bound that grows with ``seeds``.

:func:`split_singular` reads the model's independent angle off a platform rotation at a
representation singularity of its Euler order, where only ``alpha + gamma`` (or
``alpha - gamma``) is determined: the independent angle ``x`` is the root of
``x + g(x) = s`` with ``g`` the dependent angle that the inverse displacement gives at
``x`` (a secant iteration, batched).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._chains import chains_of

__all__ = ["AssemblyModes", "assembly_modes", "SAME", "MAX_SEEDS"]

#: Two solutions are the same below this distance (centre / L, and rotation in rad).
SAME = 1e-6
#: Largest number of seeds of one search.
MAX_SEEDS = 100_000


@dataclass(frozen=True, eq=False)
class AssemblyModes:
    """The distinct real forward-kinematics solutions found at one set of actuator values.

    Attributes
    ----------
    solutions : ForwardResult
        One pose per distinct solution: those above the base first (home's side of the base
        plane), then in it, then below (mirror modes); within each, those of the working
        mode's ``det J`` sign first, then by ``Zo`` (highest first) and the rotation.
    seeds, converged : int
        Seeds tried, and seeds that converged.
    """

    solutions: object
    seeds: int
    converged: int
    actuators: np.ndarray = field(repr=False, default=None)

    def __len__(self):
        return len(self.solutions)

    @property
    def singular(self) -> np.ndarray:
        """``(len,)`` bool: confirmed solutions where ``J`` is rank-deficient.  Found in
        numbers, they are points of a continuum of poses at these actuator values (a
        self-motion), counted as often as the seeds land on it."""
        s = self.solutions
        return np.asarray(s.success) & (np.atleast_1d(s.analysis.conditioning) == "singular")

    def to_dict(self, units=None) -> dict:
        """JSON-ready: every solution as :meth:`ForwardResult.to_dict` (``units``: the
        model's, or ``"SI"``)."""
        return {"pm": self.solutions.model.name, "seeds": self.seeds,
                "converged": self.converged, "count": len(self),
                "singular_count": int(np.sum(self.singular)),
                "note": "a seed search: the count is a lower bound; singular solutions found "
                        "in numbers are points of a continuum (a self-motion), not isolated "
                        "assembly modes",
                "solutions": [self.solutions.to_dict(i, units) for i in range(len(self))]}


#: Seeds a Newton launch of :func:`assembly_modes` takes (the progress is said between them).
_CHUNK = 4096


def _distinct(R, o, L):
    """Indices of the distinct poses among ``R (3, 3, K)``, ``o (3, K)``."""
    keep = []
    for k in range(R.shape[-1]):
        same = False
        for j in keep:
            if np.max(np.abs(o[:, k] - o[:, j])) <= SAME * L and \
                    np.max(np.abs(R[..., k] - R[..., j])) <= SAME:
                same = True
                break
        if not same:
            keep.append(k)
    return np.array(keep, int)


def assembly_modes(model, actuators, *, seeds: int = 1000, seed: int = 0,
                   degrees: bool = False, progress=None) -> AssemblyModes:
    """Search ``seeds`` starts in one batch for the real forward-kinematics solutions at one
    set of actuator values (see the module docstring).

    Parameters
    ----------
    model : PMModel
    actuators : array_like (n,) or mapping
        As :func:`~screwkit.engine.forward_kinematics` (one pose).
    seeds : int
        At most :data:`MAX_SEEDS`.
    seed : int
        Of the random seeds (reproducible).
    progress : callable(done, total), optional
        Called as the seeds are solved (in chunks of 4096).

    Returns
    -------
    AssemblyModes
    """
    from ..errors import InputError
    from ._kernels._layout import CONVERGED
    from ._fk_inputs import actuator_targets
    from ._fk_newton import newton, seeds as make_seeds
    from ._forward import finish
    import numbers

    from ..legs._guards import check_seed
    if isinstance(seeds, bool) or not isinstance(seeds, numbers.Real) or int(seeds) != seeds \
            or not 1 <= seeds <= MAX_SEEDS:
        raise InputError(f"seeds must be an integer from 1 to {MAX_SEEDS}, got {seeds!r:.40}")
    seed = check_seed(seed)
    if progress is not None and not callable(progress):
        raise InputError(f"progress must be a callable(done, total), got {type(progress).__name__}")
    ch = chains_of(model)
    target, single = actuator_targets(model, actuators, degrees)
    if target.shape[0] != 1:
        raise InputError(f"{model.name}: assembly modes are searched at one set of actuator "
                         "values")
    K = int(seeds)
    R, o, q = make_seeds(model, ch, target, K, np.random.default_rng(seed))
    # the seeds' Newton runs in chunks (each seed alone: the same bits), the progress
    # said after each
    parts = []
    for k0 in range(0, K, _CHUNK):
        sl = slice(k0, min(K, k0 + _CHUNK))
        parts.append(newton(ch, R[..., sl], o[:, sl], q[..., sl], max_iter=80))
        if progress is not None:
            progress(sl.stop, K)
    R, o, q, res, its = (np.concatenate([p[j] for p in parts], axis=-1) for j in range(5))
    good = np.flatnonzero(res <= CONVERGED)
    keep = good[_distinct(R[..., good], o[:, good], ch.length)]
    if keep.size == 0:
        raise InputError(f"{model.name}: no seed of {K} converged at these actuator values")
    from ._quality import base_side
    side = base_side(model, o[:, keep].T)
    order = np.lexsort((np.round(R[2, 2, keep], 9), -np.round(o[2, keep], 9), -side))
    keep = keep[order]
    n = keep.size
    ref = {p: np.full(n, model.home_pose[p]) for p in ("alpha", "beta", "gamma")}
    def solutions(keep):
        return finish(model, ch, R[..., keep], o[:, keep], q[..., keep], res[keep], its[keep],
                      np.zeros(n, int), np.repeat(target, n, axis=0), False, ref)
    sols = solutions(keep)
    perm = np.lexsort((np.arange(n), ~sols.same_mode_as_reference, -sols.side))
    if np.any(perm != np.arange(n)):           # the working mode's sign first on each side
        sols = solutions(keep[perm])
    return AssemblyModes(sols, K, int(good.size), target[0])
