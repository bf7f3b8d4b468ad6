"""A stiffness report (:meth:`StiffnessResult.to_dict`) converted to SI.

The stiffness maps a twist ``[v; w]`` (length/s, rad/s) to a wrench ``[f; m]``: with the
factors ``k`` of :func:`~screwkit.engine._report.output_scales` (a model-unit value times its
factor is the SI value), ``K_SI = diag(a) K diag(b)^-1`` where ``a = (kf, kf, kf, kt, kt,
kt)`` scales a wrench and ``b = (kl, kl, kl, 1, 1, 1)`` a twist; the compliance ``C_SI =
diag(b) C diag(a)^-1``.  A force row's stiffness is force/length (``kf / kl``), a couple's or
a rotary actuator's torque/rad (``kt``).
"""

from __future__ import annotations

import numpy as np

from ..engine._chains import LENGTH_PARAMS
from ..engine._report import output_scales


def in_units(d: dict, model, units) -> dict:
    """``d`` (one pose's report in the model's units) in ``units`` (``None``: as it is;
    ``"SI"``: m, N, N.m)."""
    if units is None or units == "model":
        return d
    ub, k = output_scales(model, units)
    kl, kf, kt = k["length"], k["force"], k["torque"]
    a = np.array([kf] * 3 + [kt] * 3)
    b = np.array([kl] * 3 + [1.0] * 3)

    def stiff(K):
        return None if K is None else np.asarray(K) * a[:, None] / b[None, :]

    out = dict(d)
    out["pose"] = {p: v * kl if p in LENGTH_PARAMS else v for p, v in d["pose"].items()}
    out["o"] = np.asarray(d["o"], float) * kl
    for key in ("stiffness", "elastic", "geometric"):
        if key in d:
            out[key] = stiff(d[key])
    out["compliance"] = np.asarray(d["compliance"]) * b[:, None] / a[None, :]
    if d["workload"] is not None:
        out["workload"] = dict(d["workload"], force=np.asarray(d["workload"]["force"]) * kf,
                               torque=np.asarray(d["workload"]["torque"]) * kt,
                               force_unit=ub["force"], torque_unit=ub["torque"])
    if d["deflection"] is not None:
        out["deflection"] = {"translation": np.asarray(d["deflection"]["translation"]) * kl,
                             "rotation": d["deflection"]["rotation"]}
    from ._compliance import twist_text
    free = []
    for x in d["unrestrained"]:
        t = np.asarray(x["twist"], float) * b
        free.append({"twist": t, "description": twist_text(t, ub["length"])})
    out["unrestrained"] = free
    pr = d["principal"]
    out["principal"] = dict(pr, translational=dict(
        pr["translational"], stiffness=np.asarray(pr["translational"]["stiffness"]) * kf / kl),
        rotational=dict(pr["rotational"],
                        stiffness=np.asarray(pr["rotational"]["stiffness"]) * kt))
    rows = []
    for r in d["rows"]:
        angular = "rad" in r["unit"]
        rows.append(dict(r, stiffness=r["stiffness"] * (kt if angular else kf / kl),
                         unit=f"{ub['torque']}/rad" if angular else f"{ub['force']}/m"))
    out["rows"] = rows
    f, t = ub["force"], ub["torque"]
    out["units"] = {"stiffness": {"f_per_v": f"{f}/m", "f_per_w": f"{f}/rad", "m_per_v": f,
                                  "m_per_w": f"{t}/rad"},
                    "compliance": {"v_per_f": f"m/{f}", "v_per_m": f"m/{t}",
                                   "w_per_f": f"rad/{f}", "w_per_m": f"rad/{t}"},
                    "deflection": {"translation": "m", "rotation": "rad"},
                    "principal": {"translational": f"{f}/m", "rotational": f"{t}/rad"},
                    "length": "m", "force": f, "torque": t, "angle": "deg",
                    "converted_from": {"length": model.units.length,
                                       "force": model.units.force}}
    return out
