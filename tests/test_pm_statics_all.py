"""Issue 3 acceptance: every catalog PM, at random regular poses.

Independent checks (not the statics code's own algebra):
* the stated DOF of the catalog equals the mobility computed from the legs' constraint wrenches;
* platform equilibrium: the legs' wrenches plus the workload sum to zero;
* each leg's equilibrium, from the leg's OWN joint twists: its total wrench on the platform does no
  work on any passive joint and exactly F_ai on the actuated one (virtual work of the chain);
* moving the base frame or rescaling every length changes no force.
"""

import zlib

import numpy as np
import pytest

from screwkit.engine import PAPER_FORCE, PAPER_TORQUE, analyze_pm
from screwkit.errors import SingularityError, UnreachablePoseError
from screwkit.pm import load_pm, pm_names
from equilibrium_check import leg_equilibrium_error

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

PMS = pm_names()
N_POSES = 20


def _random_poses(model, n, seed):
    """Independent parameters around the default pose: angles +-8 deg, lengths +-8 % of Zo."""
    rng = np.random.default_rng(seed)
    base = model.default_pose
    scale = abs(base.get("Zo", 1.0)) or 1.0
    for _ in range(n):
        pose = {}
        for k in model.independent:
            if k in ("alpha", "beta", "gamma"):
                pose[k] = base[k] + np.radians(rng.uniform(-8, 8))
            else:
                pose[k] = base[k] + rng.uniform(-0.08, 0.08) * scale
        yield pose


@pytest.mark.parametrize("name", PMS)
def test_mobility_is_stated_dof_and_statics_balance(name):
    model = load_pm(name)
    done = 0
    guess = None
    for pose in _random_poses(model, N_POSES * 2, seed=zlib.crc32(name.encode())):
        try:
            res = analyze_pm(model, pose, guess=guess, **PAPER_LOAD)
        except (SingularityError, UnreachablePoseError):
            continue
        guess = res.solution
        assert res.mobility.dof == model.stated_dof, (name, pose)
        st = res.statics
        assert st.equilibrium_residual < 1e-9, (name, st.equilibrium_residual)
        for i in range(len(res.solution.legs)):
            err = leg_equilibrium_error(res.solution, st, i)
            assert err < 1e-9, (name, i, err)
        done += 1
        if done == N_POSES:
            break
    assert done == N_POSES, f"{name}: only {done} regular poses out of {2 * N_POSES} draws"


@pytest.mark.parametrize("name", ["3RRPRR", "2SPS+2SPR"])
def test_forces_invariant_under_units(name):
    model = load_pm(name)
    res = analyze_pm(model, **PAPER_LOAD)
    k = 1000.0
    big = load_pm(name, {d: v * k for d, v in model.dimensions.items()
                         if isinstance(v, (int, float)) and d not in ("order",)})
    pose = {n: (v * k if n in ("Xo", "Yo", "Zo") else v) for n, v in
            {n: res.solution.params[n] for n in model.independent}.items()}
    res_big = analyze_pm(big, pose, torque=np.array(PAPER_TORQUE) * k, force=PAPER_FORCE)
    np.testing.assert_allclose(res_big.statics.active, res.statics.active, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(np.abs(res_big.statics.constraint), np.abs(res.statics.constraint),
                               rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(res_big.solution.extensions, k * res.solution.extensions, rtol=1e-9)
