"""Tables of a :class:`~screwkit.engine.PMAnalysis`: a long pandas DataFrame
(:func:`to_frame`) and the HTML shown in Jupyter (:func:`to_html`).  pandas is imported
only by :func:`to_frame`."""

from __future__ import annotations

import html

import numpy as np

__all__ = ["long_records", "to_frame", "to_html"]

_COLUMNS = ("pose", "quantity", "leg", "kind", "value", "unit", "ok", "level")


def _per_pose(x, single):
    x = np.asarray(x)
    return x[None] if single else x


def long_records(res) -> dict:
    """Columns of the long table (one row per pose and quantity), as a dict of lists."""
    from ..pm import LENGTH_PARAMS

    pm, u = res.model, res.model.units
    single = res.single
    n = len(res)
    params = res.solution.params_degrees()
    ok = np.atleast_1d(res.ok)
    level = np.atleast_1d(np.asarray(res.level, dtype=object))
    cond = np.atleast_1d(res.jacobian.condition_number)
    ext = _per_pose(res.solution.extensions, single)
    vals = _per_pose(res.statics.values, single) \
        if res.statics is not None and res.has_workload else None
    rows = res.jacobian.info
    cols = {k: [] for k in _COLUMNS}

    def add(i, q, leg, kind, v, unit):
        for k, x in zip(_COLUMNS, (i, q, leg, kind, float(v), unit, bool(ok[i]), str(level[i]))):
            cols[k].append(x)

    for i in range(n):
        for k in ("Xo", "Yo", "Zo", "alpha", "beta", "gamma"):
            v = np.atleast_1d(params[k])[i]
            add(i, k, None, "pose", v, u.length if k in LENGTH_PARAMS else "deg")
        for leg in range(pm.n_legs):
            add(i, f"r{leg + 1}", leg + 1, "extension", ext[i, leg], u.length)
        if vals is not None:
            for j, row in enumerate(rows):
                unit = u.torque if getattr(row, "member", "force") == "couple" else u.force
                add(i, row.label, int(row.leg) + 1, row.kind, vals[i, j], unit)
        add(i, "condition_number", None, "conditioning", cond[i], "1")
    return cols


def to_frame(res):
    """The analysis as a long ``pandas.DataFrame``: one row per pose and quantity.

    Columns ``pose`` (0..N-1), ``quantity`` (``Xo``..``gamma``, ``r1``.., the row labels
    ``F_a1``, ``F_c2``, ``T_c1``.., ``condition_number``), ``leg`` (1-based, or None),
    ``kind`` (``pose``, ``extension``, ``actuation``, ``force``, ``couple``,
    ``conditioning``), ``value``, ``unit`` (the model's units; angles in degrees), ``ok``
    and ``level`` of the pose.  ``df.pivot(index="pose", columns="quantity",
    values="value")`` gives the wide table.
    """
    try:
        import pandas as pd
    except ImportError:
        from ..errors import InputError
        raise InputError("to_frame() needs pandas (pip install pandas, or screwkit[maps])") \
            from None
    df = pd.DataFrame(long_records(res), columns=list(_COLUMNS))
    df["leg"] = df["leg"].astype("Int64")          # 1-based leg, <NA> for pose-wide values
    return df


def _table(header, body) -> str:
    th = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    tr = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>"
                 for r in body)
    return f"<table><thead><tr>{th}</tr></thead><tbody>{tr}</tbody></table>"


def _g(x) -> str:
    return f"{float(x):.6g}"


def to_html(res, max_poses: int = 10) -> str:
    """HTML summary of an analysis (Jupyter's ``_repr_html_``): one pose in full, or the
    first ``max_poses`` poses of a batch."""
    cols = long_records(res) if res.single else None
    pm, u = res.model, res.model.units
    title = (f"<b>PMAnalysis {html.escape(pm.name)}</b> ({html.escape('+'.join(pm.legs))}; "
             f"lengths {html.escape(u.length)}, forces {html.escape(u.force)}, torques "
             f"{html.escape(u.torque)}, angles deg)")
    if res.single:
        body = [(q, "" if leg is None else leg, k, _g(v), un)
                for q, leg, k, v, un in zip(cols["quantity"], cols["leg"], cols["kind"],
                                            cols["value"], cols["unit"])]
        status = (f"conditioning <b>{html.escape(str(res.conditioning))}</b>, trust level "
                  f"{html.escape(str(res.level))}, ok {bool(res.ok)}, closure "
                  f"residual {float(res.residual):.2g}"
                  + ("" if res.has_workload else "; no workload: no statics"))
        return f"<div>{title}<br>{status}{_table(('quantity', 'leg', 'kind', 'value', 'unit'), body)}</div>"
    n = len(res)
    k = min(n, max_poses)
    labels = [r.label for r in res.jacobian.info]
    vals = res.statics.values if res.statics is not None and res.has_workload else \
        np.full((n, len(labels)), np.nan)
    params = res.solution.params_degrees()
    body = []
    for i in range(k):
        body.append([i, *(_g(np.atleast_1d(params[p])[i]) for p in pm.independent),
                     *(_g(v) for v in vals[i]), str(np.atleast_1d(res.level)[i])])
    status = (f"{n} poses: {int(np.sum(res.ok))} ok, {int(np.sum(res.singular))} singular, "
              f"{int(np.sum(res.unreachable))} unreachable" + (f"; first {k} shown" if k < n else "")
              + ("" if res.has_workload else "; no workload: no statics"))
    return (f"<div>{title}<br>{status}"
            f"{_table(('pose', *pm.independent, *labels, 'level'), body)}</div>")
