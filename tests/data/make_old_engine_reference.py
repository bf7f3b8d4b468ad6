"""Reference results of the per-pose pipeline of screwkit 0.1 (before the one-engine rewrite).

Run once with the 0.1 code (commit 14fee51) to write ``old_engine_reference.json``: for every
catalog PM, 20 random regular poses drawn around its default pose (angles +-8 deg, lengths +-8 %
of |Zo|, seed 2026), each solved from home by ``analyze_pm`` under the paper's workload.  That
pipeline was verified independently in session 1 (paper closed forms, Pinocchio, leg
equilibrium).  The new engine is compared with this file in ``tests/test_engine_reference.py``.
Kept for the record: the code it calls no longer exists after the rewrite.
"""

import json
import sys
from pathlib import Path

import numpy as np

from screwkit.pinocchio_check import regular_analyses
from screwkit.pm import load_pm, pm_names


def _l(x):
    return np.asarray(x, float).tolist()


def record(analysis):
    sol, jac, st = analysis.solution, analysis.jacobian, analysis.statics
    rows = []
    for k, r in enumerate(jac.rows):
        rows.append({"leg": int(r.leg), "kind": r.kind, "member": r.member,
                     "point_name": r.point_name, "value": float(st.values[k]),
                     "vector": _l(st.vectors[k]), "unit_wrench": _l(jac.J[k])})
    return {
        "independent": {p: float(sol.params[p]) for p in analysis.model.independent},
        "params": {k: float(v) for k, v in sol.params.items()},
        "extensions": _l(sol.extensions),
        "actuator_values": _l(sol.actuator_values),
        "active": _l(st.active),
        "T_r": _l(st.T_r),
        "leg_wrenches": _l(st.leg_wrenches),
        "constraint_wrenches": _l(st.constraint_wrenches),
        "condition_number": float(jac.condition_number),
        "indeterminacy": int(jac.indeterminacy),
        "dof": int(analysis.mobility.dof),
        "rows": rows,
    }


def main(out):
    data = {"about": __doc__.strip().splitlines()[0], "workload": {
        "force": [-20.0, -30.0, -60.0], "torque": [-30.0, -30.0, 100.0]}, "pms": {}}
    for name in pm_names():
        model = load_pm(name)
        analyses = regular_analyses(model, 20, seed=2026)
        data["pms"][name] = [record(a) for a in analyses]
        print(name, len(analyses), file=sys.stderr)
    Path(out).write_text(json.dumps(data, indent=0))


if __name__ == "__main__":
    main(Path(__file__).with_name("old_engine_reference.json"))
