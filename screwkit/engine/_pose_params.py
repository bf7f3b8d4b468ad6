"""Pose parameters of forward-kinematics solutions (private): the Euler angles of platform
rotations, and at a representation singularity of the model's order the model's split of
the determined combination of ``alpha`` and ``gamma`` (:func:`split_singular`)."""

from __future__ import annotations

import warnings

import numpy as np

from ._kernels._layout import CONVERGED

__all__ = ["pose_params", "split_singular", "unsplit_notes", "SPLIT_TOL"]

#: A split of ``alpha`` and ``gamma`` at a representation singularity is found when the
#: combination it gives back is within this of the rotation's (rad).
SPLIT_TOL = 1e-10


def pose_params(model, ch, R, o, reference, q=None):
    """The six pose parameters of platform poses ``R (3, 3, N)``, ``o (3, N)``: Euler angles
    of the model's order (moved by 2 pi towards ``reference``), and where the order is at
    its representation singularity the model's split of the determined combination (solved
    from the legs' joint values ``q (n, m, N)`` where given: the poses' own assembly).
    Returns ``(params, split, unsplit)``: ``split (N,)`` the poses so split, ``unsplit`` the
    indices of those at the singularity whose split was not found (:func:`split_singular`)."""
    from scipy.spatial.transform import Rotation
    R0, p0 = ch.frame
    Rb = np.einsum("ji,jkN->Nik", R0, R)
    ob = (R0.T @ (o - p0[:, None]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ang = Rotation.from_matrix(Rb).as_euler(model.order).T
    ref = np.array([reference[p] for p in ("alpha", "beta", "gamma")])
    ref = ref[:, None] if ref.ndim == 1 else ref
    # the two sets of angles of one rotation; the one nearer the reference (mod 2 pi)
    proper = model.order[0].lower() == model.order[2].lower()
    alt = np.stack([ang[0] + np.pi, -ang[1] if proper else np.pi - ang[1], ang[2] + np.pi])
    sets = [a + 2 * np.pi * np.round((ref - a) / (2 * np.pi)) for a in (ang, alt)]
    near = np.sum((sets[1] - ref) ** 2, axis=0) < np.sum((sets[0] - ref) ** 2, axis=0)
    ang = np.where(near, sets[1], sets[0])
    params = {"Xo": ob[0], "Yo": ob[1], "Zo": ob[2], "alpha": ang[0], "beta": ang[1],
              "gamma": ang[2]}
    from ._solve import is_representation_singular
    # (the inverse displacement's band, which is also where scipy's as_euler stops
    # splitting the combination and sets its third angle to 0: tests/test_forward.py
    # pins that; a narrower band left scipy's split, not the model's, between the two)
    sing = is_representation_singular(model.order, params["beta"])
    if sing.any():
        idx = np.flatnonzero(sing)
        split = split_singular(model, params, idx, q, ch)
        sing = sing.copy()
        sing[idx[~split]] = False
        return params, sing, idx[~split]
    return params, sing, np.zeros(0, int)


def _start(model, ch, params, q, idx):
    """A warm start (a :class:`PoseSolution`) at the poses ``idx``: their joint values ``q``
    and pose parameters as they are (the split's secant moves them a little)."""
    from ._solution import make_solution
    from ._solve import Closures
    K = idx.size
    X = np.empty((ch.n_unknowns, K))
    for k, u in enumerate(ch.unknown):
        X[k] = params[u][idx] / ch.x_scale[k]
    X[len(ch.unknown):] = (q[..., idx] / ch.q_scale[:, :, None]).reshape(ch.n * ch.m, K)
    fixed = {p: np.nan_to_num(params[p][idx]) for p in ch.fixed}
    return make_solution(model, Closures(ch, X, fixed, np.zeros(K), np.zeros(K, int),
                                         np.zeros(K, int), np.zeros(K, bool)), False, [])


def unsplit_notes(model, unsplit, res) -> tuple:
    closed = [int(i) for i in unsplit if res[i] <= CONVERGED]
    if not closed:
        return ()
    which = ", ".join(str(i + 1) for i in closed[:10]) + (", ..." if len(closed) > 10 else "")
    return (f"solution(s) {which}: the platform closes every leg, at beta = 0, a "
            f"representation singularity of {model.order} where only alpha and gamma's "
            "combination is determined, and no split of it that the inverse displacement "
            "reaches from these joint values was found: the Euler angles shown are one split "
            "of the rotation, and the analysis (which solves the pose from its independent "
            "parameters) does not confirm it",)


def split_singular(model, params: dict, idx, q=None, ch=None) -> np.ndarray:
    """Set the independent one of ``alpha``, ``gamma`` at the singular poses ``idx`` of
    ``params`` (in place; see the module docstring), each inverse displacement of the secant
    started from the poses' own joint values ``q (n, m, N)`` (of chains ``ch``) where given:
    their assembly, which home may not reach.  Where the combination as it is has no split
    the inverse displacement reaches, the same rotation's principal value (within +-pi) is
    split.  Returns ``(len(idx),)`` bool: the poses split so; the others keep the Euler
    angles they had (one split of the same rotation, not the model's)."""
    from ..screws import angular_jacobian
    from ._solution import solve
    k = np.asarray(idx)
    ind = model.independent
    if ("alpha" in ind) == ("gamma" in ind):       # both given or both solved: any split
        return np.ones(k.size, bool)
    x_name, y_name = ("alpha", "gamma") if "alpha" in ind else ("gamma", "alpha")
    E = angular_jacobian(model.order, 0.0, float(params["beta"][k[0]]), 0.0)
    sgn = 1.0 if float(E[:, 0] @ E[:, 2]) > 0 else -1.0
    share = 0.5 if x_name == "alpha" else 0.5 * sgn

    def roots(s, sel):
        """The independent angles splitting ``s`` at the poses ``k[sel]``, and which did."""
        base = {p: params[p][k[sel]] for p in ind}
        start = None if q is None else _start(model, ch, params, q, k[sel])

        def f(x):
            sol = solve(model, dict(base, **{x_name: x}), start, single=False,
                        raise_unreachable=False)
            y = np.asarray(sol._params[y_name])
            a, g = (x, y) if x_name == "alpha" else (y, x)
            return a + sgn * g - s

        x0, x1 = share * s, share * s + 1e-3
        f0 = f(x0)
        for _ in range(8):
            f1 = f(x1)
            if np.all(np.abs(f1) <= 1e-14):
                break
            den = np.where(f1 != f0, f1 - f0, 1.0)
            x2 = np.where(np.isfinite(f1) & (f1 != f0), x1 - f1 * (x1 - x0) / den, x1)
            x0, f0, x1 = x1, f1, x2
        else:
            f1 = f(x1)
        return x1, np.abs(f1) <= SPLIT_TOL

    s = params["alpha"][k] + sgn * params["gamma"][k]          # the determined combination
    x, comb = np.zeros(k.size), s.copy()
    ok = np.zeros(k.size, bool)
    principal = np.remainder(s + np.pi, 2 * np.pi) - np.pi
    for cand, sel in ((s, np.arange(k.size)), (principal, None)):
        if sel is None:
            sel = np.flatnonzero(~ok & (principal != s))
        if sel.size:
            x[sel], ok[sel] = roots(cand[sel], sel)
            comb[sel] = cand[sel]
    good = k[ok]
    if x_name == "alpha":
        params["alpha"][good], params["gamma"][good] = x[ok], sgn * (comb[ok] - x[ok])
    else:
        params["gamma"][good], params["alpha"][good] = x[ok], comb[ok] - sgn * x[ok]
    return ok
