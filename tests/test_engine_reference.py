"""The one engine against the results of the per-pose pipeline it replaced (screwkit 0.1).

``tests/data/old_engine_reference.json`` was written by the 0.1 code (commit 14fee51, the
per-pose inverse displacement, Jacobian and statics that session 1 verified against the
paper's closed forms, Pinocchio and leg equilibrium) for every catalog PM at 20 random
regular poses, each solved from home.  The batched engine must give the same numbers:

* poses, extensions, active forces, each leg's total wrench: to 1e-10 (relative to the
  largest force of the pose, scaled up with the condition number beyond 100: both
  pipelines close the loops to a residual of about 1e-12, which determines a pose to about
  cond x 1e-12);
* constraint forces and couples as vectors (value x unit direction, so that a sign
  convention does not matter), per row where a leg has one member of its kind through
  its point, summed over the members of a kind otherwise (two forces through an S centre,
  two couples: a basis choice);
* where the 0.1 pipeline chose a leg's actuation wrench per pose (no line through two of
  the leg's named points carries it at every pose), the engine's canonical member is the
  least-norm one: there the constraint values differ by construction (F_c' = F_c - K F_a),
  and the check is on the active forces and the leg's total wrench, which do not depend on
  that choice.
"""

import json
from pathlib import Path

import numpy as np
import pytest

import screwkit
from screwkit.engine import PAPER_FORCE, PAPER_TORQUE
from screwkit.engine._pipeline import templates_of

# the paper's workload, stated (only 3RRPRR and 2SPS+2SPR declare it as their default)
PAPER_LOAD = {"force": (-20.0, -30.0, -60.0), "torque": (-30.0, -30.0, 100.0)}
PAPER_ARGS = ["--force=-20,-30,-60", "--torque=-30,-30,100"]

DATA = json.loads((Path(__file__).parent / "data" / "old_engine_reference.json").read_text())
PMS = sorted(DATA["pms"])


def _tol(cond):
    """Both pipelines stop the closures at a residual of about 1e-12: the pose is determined
    to about cond x 1e-12, and so are the forces (relative to the largest one)."""
    return 1e-10 * max(1.0, cond / 100.0)


def test_reference_workload_is_the_papers():
    assert DATA["workload"] == {"force": list(PAPER_FORCE), "torque": list(PAPER_TORQUE)}


@pytest.mark.parametrize("name", PMS)
def test_engine_equals_the_old_pipeline(name):
    recs = DATA["pms"][name]
    pm = screwkit.load_pm(name)
    pose = {p: np.array([r["independent"][p] for r in recs]) for p in pm.independent}
    res = screwkit.analyze(pm, pose, **PAPER_LOAD)          # one batch of 20 poses
    assert res.ok.all()
    st, sol, jac = res.statics, res.solution, res.jacobian
    templates = templates_of(pm)
    structural = [t.actuation.kind == "line" for t in templates]
    L = pm.normalisation.length
    for i, r in enumerate(recs):
        tol = _tol(r["condition_number"])
        fs = max(np.abs(r["active"]).max(), 1.0)
        for p, v in r["params"].items():
            scale = L if p in ("Xo", "Yo", "Zo") else 1.0
            assert abs(sol.params[p][i] - v) <= 1e-10 * scale, (name, i, p)
        np.testing.assert_allclose(sol.extensions[i], r["extensions"], rtol=0, atol=1e-10 * L)
        np.testing.assert_allclose(st.active[i], r["active"], rtol=0, atol=tol * fs)
        np.testing.assert_allclose(st.leg_wrenches[i], r["leg_wrenches"], rtol=0,
                                   atol=tol * fs * L)
        for leg in range(pm.n_legs):
            if not structural[leg]:
                continue
            old = [row for row in r["rows"] if row["leg"] == leg and row["kind"] != "actuation"]
            new = [k for k, row in enumerate(jac.info) if row.leg == leg and row.kind != "actuation"]
            groups_old, groups_new = {}, {}
            for row in old:
                groups_old.setdefault((row["kind"], row["point_name"]), []).append(row["vector"])
            for k in new:
                key = (jac.info[k].kind, jac.info[k].point_name)
                groups_new.setdefault(key, []).append(st.vectors[i, k])
            assert groups_old.keys() == groups_new.keys(), (name, leg)
            for key in groups_old:
                a = np.sum(groups_old[key], axis=0)
                b = np.sum(groups_new[key], axis=0)
                unit = L if key[0] == "couple" else 1.0
                np.testing.assert_allclose(b, a, rtol=0, atol=tol * fs * unit, err_msg=str(key))
            np.testing.assert_allclose(st.T_r[i, leg], r["T_r"][leg], rtol=0, atol=tol * fs * L)
            np.testing.assert_allclose(st.constraint_wrenches[i, leg],
                                       r["constraint_wrenches"][leg], rtol=0, atol=tol * fs * L)


def test_most_legs_keep_the_old_actuation_member():
    """The least-norm actuation member replaces the old per-pose choice only where that
    choice was not structural (a handful of leg types)."""
    names = {t.name for pm in PMS for t in templates_of(screwkit.load_pm(pm))
             if t.actuation.kind != "line"}
    assert names <= {"RPRU/force", "RPUR", "UPRR/force", "URPR/force", "PRRR", "RPRR", "UPR",
                     "RSR"}, names
