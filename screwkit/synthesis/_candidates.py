"""Candidate PMs for a motion pattern: leg types, their compositions, model definitions.

This is the combinatorial half of the type synthesis of PMs (the engine-checked half
is :mod:`screwkit.design`).  For a :class:`~screwkit.synthesis.MotionPattern`:

1. **Leg pool** (:func:`~screwkit.synthesis.build_pool`, :mod:`screwkit.synthesis._pool`):
   the catalog's leg types, the user's and the ones generated for the pattern whose
   constraint systems fit its complementary wrench system; legs with no constraint
   (SPS, UPS, SPU) are kept as unconstrained actuated legs.
2. **Compositions** (:func:`compositions_for`).  ``n`` actuated legs (``n`` = the DOF,
   one actuator per leg): symmetric (``n`` legs of one type) and asymmetric (``k`` legs
   of one type, ``n - k`` of another, the more constraining type first), whose constraint
   dimensions add up to at least the ``6 - dof`` of the complementary system (the legs'
   systems can span it only then); and (:func:`passive_compositions`) ``n`` actuated legs
   plus one passive constraining leg that completes the system exactly.
3. **Model definitions** (:func:`pm_definition`).  A composition is placed on one of the
   standard geometries (:data:`GEOMETRIES`: triangle, rectangle, pentagon) as a ``pms:``
   entry, the schema of `docs/pm_models.md` (the default pose is home, where the
   engine has checked ``J``); :func:`model_yaml` writes it (with the definitions of
   the leg types it uses that the packaged catalog lacks) as a model YAML that
   ``screwkit.load_pm`` reads.

Whether the legs' systems really span the complementary system, at home and along a
finite motion, is decided by the engine in :mod:`screwkit.design`, not here.
"""

from __future__ import annotations

from dataclasses import dataclass

import yaml

from ._motions import MotionPattern

from ._geometries import (CENTRAL_GEOMETRIES, GEOMETRIES, PAIR_GEOMETRIES, PASSIVE_GEOMETRIES,
                          geometries_for)

__all__ = ["CENTRAL_GEOMETRIES", "GEOMETRIES", "PAIR_GEOMETRIES", "PASSIVE_GEOMETRIES", "Candidate",
           "catalog_compositions", "central_compositions", "compositions_for", "geometries_for",
           "literature_name", "model_yaml", "pair_compositions", "passive_compositions",
           "pm_definition"]

@dataclass(frozen=True)
class Candidate:
    """A composition of leg types, one per vertex (see :func:`compositions_for`).

    Attributes
    ----------
    legs : tuple of LegKind
        One per vertex, the more constraining type first.
    name : str
        ``"3UPU/couple"``, ``"2UPU/force+SPR"``: counts and catalog names
        (``"passive-SPR+2SPR+SPS"``: a passive constraining leg first).
    string : str
        The PM string (``"3UPU"``, ``"2UPU+SPR"``).
    symmetric : bool
    passive : tuple of int
        0-based indices of the passive legs (no actuator; :func:`passive_compositions`).
    central : bool
        The last leg is a central column from the base centre to the platform centre
        (:func:`central_compositions`).
    pair : bool
        Two legs of one type on a diameter, placed on the :data:`PAIR_GEOMETRIES`
        (:func:`pair_compositions`: the Exechon's 2-UPR+SPR).
    """

    legs: tuple
    name: str
    string: str
    symmetric: bool
    passive: tuple = ()
    central: bool = False
    pair: bool = False

    @property
    def joints(self) -> int:
        return sum(k.joints for k in self.legs)

    @property
    def actuated(self) -> tuple:
        """The actuated legs' kinds (all but the passive ones)."""
        return tuple(k for i, k in enumerate(self.legs) if i not in self.passive)

    @property
    def constraints(self) -> int:
        return sum(k.constraints for k in self.legs)

    @property
    def literature(self) -> str:
        """The name as the literature writes it (:func:`literature_name`)."""
        return literature_name(self)

    @property
    def preferred(self) -> bool:
        """Every leg type from the catalog (or the user's, or the extra ones)."""
        return all(k.preferred for k in self.legs)


def literature_name(cand: Candidate) -> str:
    """``"3-PRS"``, ``"3-RRPaR"``, ``"2-UPU+SPR"``, ``"3-UPS+UP/passive"``: the counts and
    letters of the actuated legs, then each passive leg's letters with ``/passive``."""
    parts: list = []
    for i, k in enumerate(cand.legs):
        if i in cand.passive:
            continue
        if parts and parts[-1][0] == k.string:
            parts[-1][1] += 1
        else:
            parts.append([k.string, 1])
    text = "+".join(f"{n}-{s}" if n > 1 else s for s, n in parts)
    text += "".join(f"+{cand.legs[i].string}/passive" for i in cand.passive)
    return text


def _name(groups) -> tuple:
    name = "+".join(f"{n if n > 1 else ''}{k.name}" for k, n in groups)
    string = "+".join(f"{n if n > 1 else ''}{k.string}" for k, n in groups)
    return name, string


def compositions_for(motion: MotionPattern, pool, n_legs: int | None = None,
                     asymmetric: bool = True, among=None) -> list:
    """Symmetric and asymmetric compositions of ``n_legs`` legs (default: the DOF).

    A composition is kept when its legs' constraint dimensions add up to at least
    ``6 - dof`` (they cannot span the complementary system otherwise).  Symmetric ones
    first, then asymmetric (``k`` of the more constraining type ``A`` at vertices
    ``1..k``, ``n - k`` of ``B``), in pool order.  ``among`` (leg type names): the
    asymmetric ones only of two of these types with different letters, of ``n - 1`` legs
    of a catalog type with one of these (the Exechon's 2-UPR+SPR), or of one type and
    unconstrained legs that together exert exactly ``6 - dof`` constraints.
    """
    n = motion.dof if n_legs is None else int(n_legs)
    need = motion.constraints
    out = []
    for a in pool:
        if a.constraints and n * a.constraints >= need:
            name, string = _name([(a, n)])
            out.append(Candidate((a,) * n, name, string, True))
    if not asymmetric:
        return out
    for i, a in enumerate(pool):
        if not a.constraints:
            continue
        for j, b in enumerate(pool):
            if b is a or (b.constraints, -j) > (a.constraints, -i):
                continue            # A is the more constraining type (pool order on ties)
            for k in range(1, n):
                if k * a.constraints + (n - k) * b.constraints < need:
                    continue
                exact = not b.constraints and k * a.constraints == need
                # with ``among``: mixes of two listed types with different letters, or of
                # n - 1 catalog legs with one listed type (the Exechon's 2-UPR+SPR)
                both = a.name in among and b.name in among if among is not None else True
                seed = (among is not None and k == n - 1 and a.preferred and b.name in among)
                if among is not None and not exact and (a.string == b.string
                                                        or not (both or seed)):
                    continue
                name, string = _name([(a, k), (b, n - k)])
                out.append(Candidate((a,) * k + (b,) * (n - k), name, string, False))
    return out


def catalog_compositions(motion: MotionPattern, pool, catalog, n_legs: int | None = None) -> list:
    """The compositions of the catalog's PMs of ``motion`` with ``n_legs`` legs (their leg
    types in their order, every one in ``pool``): tried on the standard geometries like the
    others, so that a catalog design whose types do not mix by the rules of
    :func:`compositions_for` (the 2-UPU+SPR) is tried too."""
    n = motion.dof if n_legs is None else int(n_legs)
    kinds = {k.name: k for k in pool}
    out, seen = [], set()
    for d in (catalog.pms if catalog is not None else {}).values():
        if not isinstance(d, dict) or d.get("motion") != motion.name:
            continue
        names = [x.get("leg") if isinstance(x, dict) else x for x in d.get("legs") or []]
        if len(names) != n or not all(isinstance(x, str) and x in kinds for x in names):
            continue
        groups: list = []
        for x in names:
            if groups and groups[-1][0] is kinds[x]:
                groups[-1][1] += 1
            else:
                groups.append([kinds[x], 1])
        name, string = _name(groups)
        if name in seen:
            continue
        seen.add(name)
        out.append(Candidate(tuple(kinds[x] for x in names), name, string, len(groups) == 1))
    return out


def passive_compositions(motion: MotionPattern, pool, n_legs: int | None = None) -> list:
    """Compositions of ``n_legs`` actuated legs (default: the DOF) and ONE passive
    constraining leg (no actuator), placed first.

    The passive leg is a constraining leg type ``P`` of the pool; the actuated legs are
    ``n`` unconstrained legs of one type ``B`` (SPS, UPS, SPU: the passive leg supplies
    the whole complementary system, as the central leg of a Tricept), or ``k`` actuated
    legs of the type ``P`` and ``n - k`` of ``B``.  The constraint dimensions of all the
    legs add up to exactly ``6 - dof``: fewer cannot span the complementary system, more
    would make an over-constrained PM (the actuated compositions of
    :func:`compositions_for` cover those).  Examples: passive PRRR + 4 SPS (3T1R),
    passive SPR + 2 SPR + SPS (1T2R), passive SP + 4 SPS (1T3R).
    """
    n = motion.dof if n_legs is None else int(n_legs)
    need = motion.constraints
    free = [b for b in pool if not b.constraints]
    out = []
    for p in pool:
        if not p.constraints or p.constraints > need:
            continue
        k, r = divmod(need - p.constraints, p.constraints)
        if r or k >= n:
            continue
        for b in free:
            groups = [(p, k), (b, n - k)] if k else [(b, n)]
            name, string = _name(groups)
            legs = (p,) * (k + 1) + (b,) * (n - k)
            out.append(Candidate(legs, f"passive-{p.name}+{name}",
                                 f"{string}+{p.string}/passive", False, (0,)))
    return out


def pair_compositions(motion: MotionPattern, pool, pair_ranks: dict, among=None) -> list:
    """Three-leg compositions ``A, A, B`` for the :data:`PAIR_GEOMETRIES` (the two ``A`` legs
    on a diameter, in one plane through the base normal), where the two ``A`` legs share
    part of their constraint systems and ``B`` completes the complementary system exactly.

    ``pair_ranks`` maps a leg type's name to the rank of the constraint systems of two of
    its legs on that diameter at home (the caller builds them).  ``A`` is kept when its pair
    is redundant (rank below ``2 * A.constraints``: on the standard triangle the two legs
    would exert independent systems and over-constrain the PM) and leaves room (rank below
    ``6 - dof``); ``B`` is any other constraining type (of ``among``, leg type names, when
    given) whose constraint dimension is the rest, ``6 - dof - rank``.  The Exechon's
    2-UPR+SPR for 1T2R: two UPR legs, each a force normal to their plane and a couple along
    the base normal, of rank 2 together, and an SPR's force.
    """
    if motion.dof != 3:
        return []
    need = motion.constraints
    out = []
    for a in pool:
        r = pair_ranks.get(a.name)
        if not a.constraints or r is None or not r < min(2 * a.constraints, need):
            continue
        for b in pool:
            if b is a or b.constraints != need - r or (among is not None and b.name not in among):
                continue
            name, string = _name([(a, 2), (b, 1)])
            out.append(Candidate((a, a, b), f"{name}@pair", string, False, pair=True))
    return out


def central_compositions(motion: MotionPattern, columns, pool, n_legs: int | None = None
                         ) -> list:
    """``n_legs`` unconstrained actuated legs (default: the DOF; SPS, UPS, SPU of ``pool``)
    at the vertices and ONE passive central column of ``columns`` (generated with
    ``central=True``: from the base centre to the platform centre) that exerts the whole
    complementary system: the Tricept (3-UPS + a passive UP column) for 1T2R, a 3-UPS + a
    passive S column for 3R."""
    n = motion.dof if n_legs is None else int(n_legs)
    out = []
    for p in columns:
        if p.constraints != motion.constraints:
            continue
        for b in (k for k in pool if not k.constraints):
            name, string = _name([(b, n)])
            out.append(Candidate((b,) * n + (p,), f"{name}+{p.name}/passive",
                                 f"{string}+{p.string}/passive", False, (n,), True))
    return out


def pm_definition(cand: Candidate, motion: MotionPattern, geometry: int = 0) -> dict:
    """The ``pms:`` entry of a composition on standard geometry ``geometry`` (an index
    into :func:`geometries_for` its number of legs); angles in degrees, lengths in cm (the
    catalog's units).  A passive leg is written ``{leg: NAME, passive: true}``, and
    ``NAME/passive`` in the PM string."""
    n = len(cand.legs)
    geos = geometries_for(n, bool(cand.passive), cand.central, cand.pair)
    if not geos or not 0 <= geometry < len(geos):
        from ..errors import InputError
        raise InputError(f"no standard geometry {geometry} for {n} legs "
                         f"(geometries exist for {', '.join(map(str, sorted(GEOMETRIES)))} legs)")
    label, base, plat, dims, zo, extra = geos[geometry]
    home, guess = {}, {}
    for p in motion.independent:
        home[p] = zo if p == "Zo" else 0
    if "Zo" not in motion.independent:
        guess["Zo"] = zo
    d = {"summary": f"{cand.name}, synthesized for the {motion.name} motion",
         "source": f"screwkit synthesize {motion.name} (geometry: {label})",
         "string": cand.string, "dimensions": dict(dims), "base": dict(base),
         "platform": dict(plat), "euler": "XYZ",
         "legs": [{"leg": k.name, "passive": True} if i in cand.passive else k.name
                  for i, k in enumerate(cand.legs)],
         "independent": list(motion.independent), "home": home, "pose": dict(home),
         "dof": motion.dof, "motion": motion.name, "units": {"length": "cm", "force": "kN"}}
    if guess:
        d["guess"] = guess
    if cand.passive:
        which = ", ".join(f"{i + 1} ({cand.legs[i].name})" for i in cand.passive)
        d["note"] = (f"leg {which} is passive (no actuator)"
                     + (", a central column from the base centre to the platform centre"
                        if cand.central else "")
                     + ": its constraint system completes the complementary wrench system")
    d.update(extra)
    return d


def model_yaml(name: str, definition: dict, legs=()) -> str:
    """A model YAML (``pms: {name: definition}``, after the ``legs:`` entries ``legs`` of
    the leg types it uses that the packaged catalog lacks) that ``screwkit.load_pm(path)``
    reads."""
    data: dict = {}
    if legs:
        data["legs"] = [dict(e) for e in legs]
    data["pms"] = {name: definition}
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=100)
