"""Per-pose stiffness quantities of many poses, for maps (:func:`stiffness_fields`).

A map's block of cells is one :class:`~screwkit.engine.PMAnalysis`; this reads the
Cartesian stiffness of every cell off it (:func:`~._stiffness.stiffness_of`, no second
analysis) and reduces it to scalars a heatmap can show, each with its unit in the model's
units and a long name:

=========================  ============================================================
``stiffness_rank``         rank of ``K`` (length-normalised, ``RANK_RTOL``)
``k_translation_min/max``  smallest / largest principal translational stiffness (force at
                           ``o`` -> translation of ``o``), force/length; ``inf`` rigid
``k_rotation_min/max``     the same of the rotational block (couple -> rotation), torque/rad
``deflection_translation`` ``|dp_o|`` under the analysis' workload at ``o``, length
``deflection_rotation``    ``|dtheta|`` under it, rad
=========================  ============================================================

Unreachable, singular and unrestrained cells are NaN (``stiffness_rank`` is then -1).
"""

from __future__ import annotations

import numpy as np

__all__ = ["STIFFNESS_FIELDS", "stiffness_fields"]

#: Field name -> (unit kind of ``Units.of`` or a literal unit, long name).
STIFFNESS_FIELDS = {
    "stiffness_rank": ("1", "rank of the Cartesian stiffness K"),
    "k_translation_min": ("stiffness", "smallest principal translational stiffness at o"),
    "k_translation_max": ("stiffness", "largest principal translational stiffness at o"),
    "k_rotation_min": ("angular stiffness", "smallest principal rotational stiffness"),
    "k_rotation_max": ("angular stiffness", "largest principal rotational stiffness"),
    "deflection_translation": ("length", "elastic translation of o under the workload"),
    "deflection_rotation": ("rad", "elastic rotation of the platform under the workload"),
}


def stiffness_fields(analysis, params=None, *, actuator=None, force_stiffness=None,
                     couple_stiffness=None, rows=None) -> dict:
    """Scalar stiffness quantities at every pose of an analysis (module docstring).

    Parameters
    ----------
    analysis : PMAnalysis
        N poses (a map's block); its workload is the one deflected.
    params : DynamicsParameters, mapping or path, optional
        The legs' stiffnesses (default: the model's ``dynamics:`` block, if any).
    actuator, force_stiffness, couple_stiffness, rows
        As :func:`screwkit.dynamics.stiffness`.

    Returns
    -------
    dict
        ``name -> (values (N,), unit, long_name)``, the names of :data:`STIFFNESS_FIELDS`.

    Examples
    --------
    >>> import numpy as np, screwkit
    >>> from screwkit.dynamics import stiffness_fields
    >>> an = screwkit.analyze("3RRPRR", {"alpha": np.radians([0.0, 5.0]), "beta": 0.1,
    ...                                  "Zo": 80.0})
    >>> f = stiffness_fields(an, actuator=2000.0, force_stiffness=5000.0)
    >>> f["stiffness_rank"][0], f["k_translation_min"][1]
    (array([6, 6]), 'kN/cm')
    """
    from ._dynamics import resolve_parameters
    from ._stiffness import stiffness_of

    model = analysis.model
    if params is not None or model.dynamics is not None:
        params = resolve_parameters(model, params)
    st = stiffness_of(analysis, params, actuator=actuator, force_stiffness=force_stiffness,
                      couple_stiffness=couple_stiffness, rows=rows)
    N = len(st.K)
    good = np.asarray(st.restrained).reshape(N)
    kt = np.asarray(st.principal("translational")[0], float).reshape(N, 3)
    kr = np.asarray(st.principal("rotational")[0], float).reshape(N, 3)
    d = np.full((N, 6), np.nan) if st.deflection is None else \
        np.asarray(st.deflection, float).reshape(N, 6)        # (no workload: no deflection)
    rank = np.where(good, np.asarray(st.rank).reshape(N), -1)
    vals = {
        "stiffness_rank": rank,
        "k_translation_min": kt.min(axis=1), "k_translation_max": kt.max(axis=1),
        "k_rotation_min": kr.min(axis=1), "k_rotation_max": kr.max(axis=1),
        "deflection_translation": np.linalg.norm(d[:, :3], axis=1),
        "deflection_rotation": np.linalg.norm(d[:, 3:], axis=1),
    }
    u = model.units
    out = {}
    for name, (kind, long_name) in STIFFNESS_FIELDS.items():
        v = vals[name]
        if name != "stiffness_rank":
            v = np.where(good, v, np.nan)
        unit = kind if kind in ("1", "rad") else u.of(kind)
        out[name] = (v, unit, long_name)
    return out
