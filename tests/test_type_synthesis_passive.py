"""Type synthesis with a passive constraining leg, and on a Dask cluster (screwkit.design).

The passive-leg PMs are checked against constraint systems derived by hand, not against
the search: an SPR leg exerts one force through its S centre parallel to its R axis; a
PRRR leg whose P and three R axes are along the base normal exerts two couples normal to
it; an SPS leg none, and its actuator a force along the leg line (reciprocal to both S).
From those rows alone (no engine) ``J`` is built: the constraint rows of every leg and the
actuation rows of the actuated legs only; it must be non-singular (the actuators control
the motion, the passive leg has none), and its constraint rows must leave the motion's
twists.  The engine's rows of the written model, analysed afresh, must be those lines.
The searches use a catalog of the few leg types needed (fast); the full searches are in
the benchmark.  A Dask LocalCluster run equals the serial one.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import screwkit
from screwkit.cli import main
from screwkit.design import actuation_condition, synthesize_motion
from screwkit.pm import Catalog, default_catalog
from screwkit.synthesis import leg_pool, motion_pattern, passive_compositions


def _catalog(*names):
    cat = default_catalog()
    return Catalog({n: cat.legs[n] for n in names}, cat.table1, {}, "<test>")


@pytest.fixture(scope="module")
def passive_1t2r():
    return synthesize_motion("1T2R", asymmetric=False, passive=True,
                             catalog=_catalog("SPR", "SPS"), generate=False)


@pytest.fixture(scope="module")
def passive_3t1r():
    return synthesize_motion("3T1R", asymmetric=False, passive=True,
                             catalog=_catalog("PRRR", "SPS"), generate=False)


def _listed(res, name):
    hit = [p for p in res.listed if p.variant == name]
    assert hit, f"{name} not in {res.variants()}"
    return hit[0]


def _home(p, tmp_path):
    path = tmp_path / (p.variant.replace("/", "-") + ".yaml")
    path.write_text(p.model_yaml(), encoding="utf-8")
    model = screwkit.load_pm(str(path))
    assert model.passive == (0,)                # written as a passive leg
    a = screwkit.analyze(model, {k: model.home_pose[k] for k in model.independent},
                         raise_on_singular=False)
    return model, a


def _points(model, a):
    """Base vertices A_i, platform vertices a_i (at home) and o, from the placements."""
    pl = [model.placement(i, dict(model.home_pose)) for i in range(len(model.legs))]
    A = np.array([np.asarray(q.A, float) for q in pl])
    av = np.array([np.asarray(q.a, float) for q in pl])
    return A, av, np.asarray(a.solution.position, float).reshape(3)


def _force(p, d):
    d = np.asarray(d, float) / np.linalg.norm(d)
    return np.concatenate([d, np.cross(p, d)])


def _couple(d):
    return np.concatenate([np.zeros(3), np.asarray(d, float) / np.linalg.norm(d)])


def _parallel(row, hand, tol=1e-9):
    r = np.asarray(row, float) / np.linalg.norm(row)
    h = hand / np.linalg.norm(hand)
    return min(np.linalg.norm(r - h), np.linalg.norm(r + h)) <= tol


def _twists(Jc):
    """Twists [v; w] reciprocal (f.v + m.w = 0) to the rows: the null space of Jc."""
    _, s, vt = np.linalg.svd(np.asarray(Jc, float))
    rank = int(np.sum(s > 1e-9 * s[0]))
    return vt[rank:]


def _normalised_cond(J, L):
    Jn = np.array(J, float)
    Jn[:, 3:] /= L                                   # moments in units of a length
    Jn /= np.linalg.norm(Jn, axis=1, keepdims=True)
    s = np.linalg.svd(Jn, compute_uv=False)
    return s[0] / s[-1]


def test_passive_compositions_complete_the_complementary_system_exactly():
    # by hand: 1T2R needs 3 constraints; a passive SPR (1 force) with 2 actuated SPR (1
    # each) and 1 SPS (0); 3T1R needs 2: a passive PRRR (2 couples) and 4 unconstrained
    for motion, name, legs in (("1T2R", "passive-SPR+2SPR+SPS", ("SPR", "SPR", "SPR", "SPS")),
                               ("3T1R", "passive-PRRR+4SPS", ("PRRR",) + ("SPS",) * 4)):
        m = motion_pattern(motion)
        comps = {c.name: c for c in passive_compositions(m, leg_pool(m, generate=False))}
        c = comps[name]
        assert tuple(k.name for k in c.legs) == legs and c.passive == (0,)
        assert len(c.actuated) == m.dof
        assert all(x.constraints == 6 - m.dof for x in comps.values())


def test_1t2r_lists_a_passive_spr_leg_against_its_hand_constraint_force(passive_1t2r, tmp_path):
    res = passive_1t2r
    assert (res.screened_out + len(res.rejected) + res.verified + res.not_verified
            + res.pruned) == res.tried
    p = _listed(res, "passive-SPR+2SPR+SPS")
    assert p.passive == ("SPR",) and p.actuators == ("S_PR", "S_PR", "S_PS")
    assert p.verdict.success and len(p.verdict.checks) >= 6
    assert all((c.dof, c.translations, c.rotations) == (3, 1, 2) for c in p.verdict.checks)
    model, a = _home(p, tmp_path)
    A, av, o = _points(model, a)
    z = np.array([0.0, 0.0, 1.0])
    # hand rows: SPR leg i: a force through A_i along the R axis (the platform tangent at
    # a_i: horizontal at home, normal to the radius o->a_i); every leg's actuator: a force
    # along its leg line A_i -> a_i
    tangent = [np.cross(z, av[i] - o) for i in range(4)]
    Jc_hand = np.array([_force(A[i], tangent[i]) for i in range(3)])
    Ja_hand = np.array([_force(A[i], av[i] - A[i]) for i in range(1, 4)])  # leg 0 passive
    J_hand = np.vstack([Ja_hand, Jc_hand])
    assert np.linalg.matrix_rank(J_hand, tol=1e-9 * np.abs(J_hand).max()) == 6
    # the constraint forces leave 3 twists: one pure translation (along z), 2 rotations
    tw = _twists(Jc_hand)
    assert tw.shape[0] == 3
    # the engine's rows of the written model at home are those lines
    rows = a.jacobian.info
    J = np.asarray(a.jacobian.J, float)
    c0 = [J[k] for k, r in enumerate(rows) if r.leg == 0 and r.kind != "actuation"]
    assert len(c0) == 1 and _parallel(c0[0], Jc_hand[0])
    for i in range(1, 4):
        act = [J[k] for k, r in enumerate(rows) if r.leg == i and r.kind == "actuation"]
        assert len(act) == 1 and _parallel(act[0], Ja_hand[i - 1])
    cond, sing = actuation_condition(a.jacobian, (0,))      # the written model, afresh
    assert not bool(np.ravel(sing)[0]) and np.ravel(cond)[0] == pytest.approx(p.condition_home)
    # and the hand J's conditioning is of the same order (different normalisation)
    L = float(model.normalisation.length)
    print("cond(J) home:", p.condition_home, "hand rows:", _normalised_cond(J_hand, L))
    assert 0.2 < p.condition_home / _normalised_cond(J_hand, L) < 5


def test_3t1r_lists_a_passive_prrr_leg_against_its_hand_couples(passive_3t1r, tmp_path):
    p = _listed(passive_3t1r, "passive-PRRR+4SPS")
    assert p.passive == ("PRRR",) and p.actuators == ("S_PS",) * 4
    model, a = _home(p, tmp_path)
    A, av, _ = _points(model, a)
    # hand rows: the PRRR (P and R axes along z) exerts couples along X and Y; four SPS
    # actuators exert forces along their legs
    Jc_hand = np.array([_couple([1, 0, 0]), _couple([0, 1, 0])])
    Ja_hand = np.array([_force(A[i], av[i] - A[i]) for i in range(1, 5)])
    J_hand = np.vstack([Ja_hand, Jc_hand])
    assert np.linalg.matrix_rank(J_hand, tol=1e-9 * np.abs(J_hand).max()) == 6
    tw = _twists(Jc_hand)               # 3 translations and the rotation about z
    assert tw.shape[0] == 4 and float(np.max(np.abs(tw[:, 3:5]))) <= 1e-12
    J = np.asarray(a.jacobian.J, float)
    c0 = np.array([J[k] for k, r in enumerate(a.jacobian.info)
                   if r.leg == 0 and r.kind != "actuation"])
    assert c0.shape == (2, 6) and float(np.max(np.abs(c0[:, :3]))) <= 1e-9 * np.abs(c0).max()
    assert float(np.max(np.abs(c0[:, 5]))) <= 1e-9 * np.abs(c0).max()
    # the finite motion keeps the platform normal vertical at the checked poses (afresh)
    poses = [c.pose for c in p.verdict.checks]
    batch = {k: np.array([q[k] for q in poses]) for k in model.independent}
    res = screwkit.analyze(model, batch, degrees=True, raise_on_singular=False)
    R = np.asarray(res.solution.rotation, float)
    assert bool(np.all(res.solution.success))
    assert float(np.max(np.abs(R[:, :, 2] - [0, 0, 1]))) <= 1e-9
    assert "passive" in p.definition["note"]
    # the written model declares leg 1 passive: no actuation row for it in the engine's J
    assert not [r for r in a.jacobian.info if r.leg == 0 and r.kind == "actuation"]
    assert {"leg": "PRRR", "passive": True} in p.definition["legs"]


def test_dask_synthesis_equals_the_serial_one(capsys):
    distributed = pytest.importorskip("distributed")
    args = ["synthesize", "3T1R", "--passive", "--no-generate", "--json", "--quiet"]
    assert main(args) == 0
    serial = json.loads(capsys.readouterr().out)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        assert main(args + ["--scheduler", cluster.scheduler_address]) == 0
        dask = json.loads(capsys.readouterr().out)
    assert dask == serial
    assert any(p["passive_legs"] == ["PRRR"] for p in serial["listed"])


def test_cli_workers_and_scheduler_together_is_one_line(capsys):
    assert main(["synthesize", "3T", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"]) == 2
    err = capsys.readouterr().err
    assert "either --workers" in err and len(err.strip().splitlines()) == 1
