"""The home assembly of a PM: the dependent pose parameters at which every leg's structure holds.

At the home values of the independent pose parameters, :func:`_solve_home`
finds the dependent ones by Gauss-Newton on the legs' structure checks
(:func:`screwkit.legs.structure_vector`), so that each leg can be built by its
catalog rules there (joint values 0).
"""

from __future__ import annotations

import numpy as np

from ..errors import GeometryError
from ..legs import build_leg, structure_vector
from ..screws import is_singular
from ._model import LENGTH_PARAMS

# ``model`` is the PMModel prototype being built, ``ctx`` the loader's evaluation context
# (screwkit.pm._loader imports this module).


def _solve_home(model: "PMModel", start: dict, ctx: "_Ctx"):
    """Dependent pose parameters at home: every leg's structure checks vanish (Gauss-Newton)."""
    dep = model.dependent
    L = model.normalisation.length
    scale = np.array([L if p in LENGTH_PARAMS else 1.0 for p in dep])

    why = []

    def residual(x):
        pose = dict(start)
        pose.update(zip(dep, x))
        out = []
        for i, r in enumerate(model.leg_rules):
            pl = model.placement(i, pose)
            try:
                leg = build_leg(r, pl, check_structure=False)
                out.append(structure_vector(r, pl, leg))
            except GeometryError as exc:
                why[:] = [f"leg {i + 1}: {exc}"]
                return None
        return np.concatenate(out) if out else np.zeros(0)

    x = np.array([start[p] for p in dep], float)
    f = residual(x)
    if f is None:
        # the home pose (with the guess of its dependent parameters, where given) and the
        # dimensions place the legs: one of them is at fault, most often the home pose
        raise ctx.err(f"the legs cannot be built at the home pose ({why[0]}): check 'home', "
                      "'guess' where given, and the dimensions", "home")
    notes = []
    for it in range(100):
        if f.size == 0 or np.max(np.abs(f)) < 1e-14:
            break
        J = np.empty((f.size, len(dep)))
        for k in range(len(dep)):
            h = np.zeros(len(dep))
            h[k] = 1e-6 * scale[k]
            fp, fm = residual(x + h), residual(x - h)
            if fp is None or fm is None:
                raise ctx.err("the legs cannot be built near the home pose", "home")
            J[:, k] = (fp - fm) / (2e-6)
        dx = np.linalg.lstsq(J, -f, rcond=1e-10)[0] * scale
        t = 1.0
        for _ in range(30):
            fn = residual(x + t * dx)
            if fn is not None and np.linalg.norm(fn) < np.linalg.norm(f):
                break
            t *= 0.5
        else:
            break
        x, f = x + t * dx, fn
    res = float(np.max(np.abs(f))) if f.size else 0.0
    if res > 1e-9:
        raise ctx.err(f"no home pose satisfies the legs' structure checks near the guess "
                      f"(residual {res:.3g}); adjust 'home' or 'guess'", "home")
    home = {p: float(v) for p, v in start.items()}
    home.update(zip(dep, (float(v) for v in x)))
    if "beta" in home and is_singular(model.order, home["beta"]) and \
            any(p in dep for p in ("alpha", "gamma")):
        notes.append(f"the home pose is at a representation singularity of {model.order} "
                     "(beta = 0 or pi): the dependent angle kept its guess value")
    return home, notes
