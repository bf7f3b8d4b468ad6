"""Independent leg-equilibrium check shared by the PM tests.

For leg i at a solved pose, its total wrench on the platform (from the statics) is dotted with the
leg's OWN joint twists (the virtual power of each joint): zero on every passive joint and F_ai on
the actuated one.  This uses the leg's chain, not the Jacobian rows the statics were solved with.
"""

import numpy as np

from screwkit.screws import Normalisation


def leg_equilibrium_error(sol, st, i):
    """max |J_leg^T w - (0.., F_a, ..0)| relative to the leg's wrench, in normalised coordinates."""
    leg = sol.legs[i]
    norm = Normalisation.for_points(np.vstack([lg.points for lg in sol.legs]))
    Tn = norm.twists(leg.twists)
    Tn = Tn / np.linalg.norm(Tn, axis=1, keepdims=True)
    w = st.leg_wrenches[i]
    wn = norm.wrenches(w)
    work = Tn @ wn
    # the actuated joint's work per unit twist equals F_a (twist scaled back to unit physical twist)
    ia = leg.actuated_index
    xi = leg.twists[ia]
    expected = np.zeros(len(work))
    act_rows = [k for k, r in enumerate(st.jacobian.rows) if r.leg == i and r.kind == "actuation"]
    if act_rows:
        expected[ia] = st.values[act_rows[0]] / (np.linalg.norm(norm.twists(xi)) * norm.length)
    scale = max(np.linalg.norm(norm.wrenches(st.workload)), np.linalg.norm(wn), 1e-300)
    return float(np.max(np.abs(work - expected)) / scale)
