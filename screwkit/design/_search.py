"""Type synthesis of PMs for a motion pattern: search, verification, ranking.

:func:`synthesize_motion` takes a motion pattern (``"3T"``, ``"1T2R"``, ``"3R"``,
``"3T1R"``, ...), forms the candidate compositions of leg types
(:func:`screwkit.synthesis.compositions_for`), places each on the standard geometries
(:data:`screwkit.synthesis.GEOMETRIES`) and

1. **screens** it at the nominal home pose: each leg is built by its rules there
   (:func:`screwkit.legs.build_leg`, cached per leg type and vertex) and the
   instantaneous mobility of the legs (:func:`screwkit.pm.mobility_of_legs`, the rank
   of the union of their constraint systems) must have the motion's DOF and its counts of
   translations and rotations, i.e. the legs' systems span the complementary system at
   home (a candidate whose home is a special pose of its motion is screened out there
   and tried on the next geometry; legs that cannot be built by their rules at the
   nominal home are not tried on that geometry);
2. **verifies** the survivors with the engine (:func:`screwkit.design.verify_model`):
   full-cycle mobility along a finite motion from home, the pattern's finite
   invariant, ``J`` non-singular at home;
   Asymmetric candidates (``k`` legs of type ``A``, ``n - k`` of ``B``) are tried when
   the symmetric PM of ``A`` verified (the search grows mixed designs from verified
   symmetric ones: the 2-UPU+SPR from the spherical 3-UPU), or when ``B`` exerts no
   constraint and the ``k`` legs of ``A`` exert exactly the ``6 - dof`` constraints
   (constraining legs and unconstrained actuated legs without redundancy, as the
   4-SPS+SPR or the 3-SPU+PRRR).  This keeps one motion pattern to seconds: an
   over-constrained candidate that cannot move costs the engine's continuation from home.
   PMs of ``n`` actuated legs and one *passive* constraining leg
   (:func:`screwkit.synthesis.passive_compositions`: the 4-SPS + passive PRRR) come
   last, with a budget of their own; their ``J`` leaves out the passive leg's actuation
   row (:func:`screwkit.design.actuation_condition`).  The verifications are tasks
   (:func:`~screwkit.design.verify_candidate`) run through a ``mapper``: serial, or on a
   Dask cluster (``screwkit.maps.run_tasks``), with the same result;
3. **ranks** the verified PMs: fewer equivalent 1-DOF joints first, then actuators
   nearer the base (mean position of the actuated letter in its leg: 1 is on the
   base), then the better length-normalised condition number of ``J`` at home.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError, InputError, ScrewkitError
from ..legs import build_leg
from ..pm import load_pm, mobility_of_legs
from ..synthesis import (GEOMETRIES, compositions_for, geometries_for, leg_pool, model_yaml,
                         motion_pattern, passive_compositions, pm_definition, synthesis_catalog)
from ._tasks import monotonic_progress, run_round
from ._verify import Verdict

__all__ = ["MAX_LEGS", "MAX_VERIFIED", "SynthesizedPM", "TypeSynthesis", "synthesize_motion"]

#: Largest number of legs (the standard geometries have 3, 4 or 5 vertices).
MAX_LEGS = max(GEOMETRIES)
#: Default budget of engine verifications (a candidate on one geometry) of one search, for
#: the actuated compositions and again for the passive-leg ones.
MAX_VERIFIED = 60


@dataclass(frozen=True)
class SynthesizedPM:
    """One verified PM of :func:`synthesize_motion`.

    Attributes
    ----------
    rank : int
        1 is the best.
    name, string : str
        ``"2UPU/force+SPR"`` (catalog leg names) and the PM string ``"2UPU+SPR"``.
    motion : str
    legs : tuple of str
        Leg type per vertex.
    symmetric : bool
    geometry : str
        The standard geometry it was verified on.
    joints : int
        Equivalent 1-DOF joints of all legs.
    actuators : tuple of str
        The legs' strings with the actuated joint marked (``"U_PU"``).
    actuator_position : float
        Mean 1-based position of the actuated letter in its leg (1: every actuator on
        the base).
    condition_home : float
        Length-normalised condition number of ``J`` at home.
    verdict : Verdict
        The engine's verification (mobility at every checked pose, finite invariant).
    definition : dict
        The ``pms:`` entry (write it with :meth:`model_yaml`).
    passive : tuple of str
        The passive legs' types (no actuator; ``actuators`` lists the actuated legs only).
    """

    rank: int
    name: str
    string: str
    motion: str
    legs: tuple
    symmetric: bool
    geometry: str
    joints: int
    actuators: tuple
    actuator_position: float
    condition_home: float
    verdict: Verdict
    definition: dict
    passive: tuple = ()

    def model_yaml(self, as_actuated: bool = False) -> str:
        """The model YAML (``screwkit.load_pm`` reads it, with any extra leg types).

        A PM with a passive leg raises :class:`~screwkit.errors.InputError` unless
        ``as_actuated``: screwkit models cannot declare a passive leg yet, so the file
        would actuate every leg; its mobility and constraint rows are this PM's, its
        actuator forces those of the all-actuated PM (redundantly actuated)."""
        if self.passive and not as_actuated:
            from ..errors import InputError
            raise InputError(f"{self.name}: a model cannot declare the passive leg "
                             f"{', '.join(self.passive)} yet (model_yaml(as_actuated=True) "
                             "writes it with every leg actuated)")
        return model_yaml(self.name, self.definition)

    def to_dict(self) -> dict:
        v = self.verdict
        return {"rank": self.rank, "name": self.name, "string": self.string,
                "motion": self.motion, "legs": list(self.legs), "symmetric": self.symmetric,
                "geometry": self.geometry, "joints": self.joints,
                "actuators": list(self.actuators), "actuator_position": self.actuator_position,
                "condition_home": self.condition_home,
                "verified_poses": [{"pose": c.pose, "dof": c.dof, "motion_type": c.motion_type,
                                    "translations": c.translations, "rotations": c.rotations,
                                    "condition_number": c.condition_number} for c in v.checks],
                "path_samples_reached": v.reached, "singular_on_path": v.singular_on_path,
                "finite_check": v.finite, "notes": list(v.notes),
                "passive_legs": list(self.passive), "definition": self.definition}


@dataclass(frozen=True)
class TypeSynthesis:
    """Result of :func:`synthesize_motion`.

    Attributes
    ----------
    motion : MotionPattern
    n_legs : int
    pool : tuple of LegKind
        The leg types whose constraint systems fit the motion (counts).
    listed : tuple of SynthesizedPM
        The verified PMs, ranked (at most ``limit``).
    verified : int
        Verified PMs before the limit.
    tried : int
        Candidate compositions.
    rejected : tuple of (str, str)
        ``(name, reason)`` of the candidates that reached the engine and failed.
    screened_out : int
        Candidates whose legs did not span the complementary system at home on any
        geometry (or could not be built there by their rules).
    not_verified : int
        Candidates that passed the screen but were not verified: the budget
        ``max_verified`` of engine verifications was spent.
    pruned : int
        Asymmetric candidates not tried because the symmetric PM of the more
        constraining type did not verify (see the module docstring for the rule).
    """

    motion: object
    n_legs: int
    pool: tuple
    listed: tuple
    verified: int
    tried: int
    rejected: tuple
    screened_out: int
    not_verified: int = 0
    pruned: int = 0

    def __len__(self) -> int:
        return len(self.listed)

    def names(self) -> list:
        return [p.name for p in self.listed]

    def to_dict(self) -> dict:
        m = self.motion
        return {"motion": m.name, "dof": m.dof, "independent": list(m.independent),
                "complement": m.complement, "legs": self.n_legs,
                "pool": [{"name": k.name, "string": k.marked, "forces": k.forces,
                          "couples": k.couples} for k in self.pool],
                "tried": self.tried, "screened_out": self.screened_out,
                "not_verified": self.not_verified, "pruned": self.pruned,
                "verified": self.verified, "listed": [p.to_dict() for p in self.listed],
                "rejected": [{"name": n, "reason": r} for n, r in self.rejected],
                "units": {"length": "cm", "angle": "deg"}}


def _probe(motion, n, g, catalog, passive=False):
    """A model of ``n`` unconstrained legs on geometry ``g``: its placements at home."""
    probe = pm_definition(_unconstrained(n, passive), motion, g)
    try:
        return load_pm("probe", None, synthesis_catalog(catalog, {"probe": probe}))
    except ScrewkitError:
        return None


def _unconstrained(n, passive=False):
    from ..synthesis import Candidate, LegKind
    sps = LegKind("SPS", "SPS", "S_PS", 0, 0, 0, 7, 2)
    return Candidate((sps,) * n, f"{n}SPS", f"{n}SPS", True, (0,) if passive else ())


def _home_legs(kind_names, g, probe, specs, cache):
    """The legs built by their rules at the probe's home (cached per type, vertex, ``g``)."""
    legs = []
    for i, name in enumerate(kind_names):
        key = (name, i, g)
        if key not in cache:
            try:
                cache[key] = build_leg(specs[name].rules, probe.placement(i, probe.home_pose), True)
            except (GeometryError, ScrewkitError):
                cache[key] = None
        legs.append(cache[key])
    return legs


def synthesize_motion(motion, *, legs: int | None = None, limit: int | None = None,
                      asymmetric: bool = True, passive: bool = False,
                      max_verified: int | None = None, catalog=None, progress=None,
                      mapper=None) -> TypeSynthesis:
    """PMs with the motion pattern ``motion``, verified by the engine and ranked.

    Parameters
    ----------
    motion : str or MotionPattern
        ``"3T"``, ``"3R"``, ``"1T2R"`` (``"2R1T"``), ``"3T1R"``, ``"2T3R"``, ``"1T3R"``,
        ``"2T2R"``, ``"2T1R"``.
    legs : int, optional
        Number of actuated legs (default: the DOF; 3 to ``MAX_LEGS``, at least the DOF).
    limit : int, optional
        List at most this many (the best ranked).
    asymmetric : bool
        Also two-type compositions (``2UPU/force+SPR``).
    passive : bool
        Also the actuated legs plus one passive constraining leg
        (:func:`screwkit.synthesis.passive_compositions`; ``legs + 1`` legs, tried when a
        standard geometry has that many vertices, with a verification budget of their
        own).  Off by default: models cannot declare a passive leg yet, so these PMs are
        listed but cannot be written as a model (:meth:`SynthesizedPM.model_yaml`).
    max_verified : int, optional
        At most this many engine verifications (one candidate on one geometry; default
        ``MAX_VERIFIED``) for the actuated compositions, and as many for the passive-leg
        ones.  They go geometry by geometry (every candidate on the first geometry where
        it passed the screen, then the ones that failed there on their next), candidates
        symmetric first, then by joint count, so the budget goes to the simplest.
    catalog : Catalog, optional
        Leg types (default: the packaged catalog), plus the extra arrangements.
    progress : callable, optional
        ``progress(done, total)`` as candidates are screened and verified.
    mapper : callable, optional
        ``mapper(fn, items, progress)`` -> ``[fn(x) for x in items]`` in order: runs the
        engine verifications (``functools.partial(screwkit.maps.run_tasks, cluster)`` on a
        Dask cluster); default serial.  The result is the same either way.

    Returns
    -------
    TypeSynthesis

    Examples
    --------
    >>> res = synthesize_motion("3T", limit=3)          # doctest: +SKIP
    >>> res.listed[0].name, res.listed[0].verdict.checks[1].motion_type  # doctest: +SKIP
    ('3PRRR/translational', '3T')
    """
    m = motion_pattern(motion)
    n = m.dof if legs is None else legs
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not m.dof <= n <= MAX_LEGS \
            or int(n) not in GEOMETRIES:
        raise InputError(f"--legs must be an integer from {m.dof} (the DOF of {m.name}) to "
                         f"{MAX_LEGS} with a standard geometry "
                         f"({', '.join(map(str, sorted(GEOMETRIES)))} legs), got {legs!r:.20}")
    n = int(n)
    if limit is not None and (isinstance(limit, bool) or not isinstance(limit, (int, np.integer))
                              or limit < 1):
        raise InputError(f"--limit must be a positive integer, got {limit!r:.20}")
    if max_verified is not None and (isinstance(max_verified, bool) or not isinstance(
            max_verified, (int, np.integer)) or not 1 <= max_verified <= 10000):
        raise InputError(f"max_verified must be an integer from 1 to 10000, got {max_verified!r:.20}")
    pool = leg_pool(m, catalog)
    comps = sorted(compositions_for(m, pool, n, asymmetric),
                   key=lambda c: (not c.symmetric, c.joints))       # stable: pool order on ties
    if passive and n + 1 in GEOMETRIES:
        comps += sorted(passive_compositions(m, pool, n), key=lambda c: c.joints)
    total = len(comps)
    if progress is not None:
        progress = monotonic_progress(progress)
    screened = _screen(m, comps, catalog)                 # {index: ((g, definition), ...)}
    budget = MAX_VERIFIED if max_verified is None else max_verified
    # round 1: symmetric, and constraining + unconstrained legs without redundancy;
    # round 2: the other asymmetric ones, when the symmetric PM of their type verified
    # (the two share the budget); round 3: the passive-leg ones (a budget of their own)
    independent = [i for i, c in enumerate(comps) if not c.passive and (c.symmetric or (
        not c.legs[-1].constraints and c.constraints == m.constraints))]
    outcome: dict = {}
    sent = run_round(m, comps, screened, independent, budget, catalog, mapper, progress, outcome,
                      0, total)
    good = {comps[i].legs[0].name for i, r in outcome.items()
            if comps[i].symmetric and r.geometry is not None}
    rest = [i for i, c in enumerate(comps) if not c.passive and i not in set(independent)]
    pruned = sum(1 for i in rest if comps[i].legs[0].name not in good)
    rest = [i for i in rest if comps[i].legs[0].name in good]
    run_round(m, comps, screened, rest, budget - sent, catalog, mapper, progress, outcome,
               len(independent) + pruned, total)
    with_passive = [i for i, c in enumerate(comps) if c.passive]
    independent += with_passive
    run_round(m, comps, screened, with_passive, budget, catalog, mapper, progress, outcome,
               total - len(with_passive), total)
    found, rejected, skipped = [], [], 0
    for i, cand in enumerate(comps):
        r = outcome.get(i)
        if r is None:
            skipped += i in screened and (i in independent or cand.legs[0].name in good)
        elif r.geometry is not None:
            found.append((cand, r.geometry, r.definition, r.verdict))
        else:
            rejected.append((cand.name, r.reason))
    screened_out = sum(1 for i in range(total) if i not in screened and i not in outcome
                       and (i in independent or comps[i].legs[0].name in good))
    found.sort(key=lambda x: (x[0].joints, _act_pos(x[0]), x[3].condition_home, x[0].name))
    listed = []
    for r, (cand, g, d, verdict) in enumerate(found[:limit] if limit else found, start=1):
        nl = len(cand.legs)
        listed.append(SynthesizedPM(
            r, cand.name, cand.string, m.name, tuple(k.name for k in cand.legs), cand.symmetric,
            geometries_for(nl, bool(cand.passive))[g][0], cand.joints,
            tuple(k.marked for i, k in enumerate(cand.legs) if i not in cand.passive),
            _act_pos(cand), verdict.condition_home, verdict, d,
            tuple(cand.legs[i].name for i in cand.passive)))
    return TypeSynthesis(m, n, pool, tuple(listed), len(found), total, tuple(rejected),
                         screened_out, skipped, pruned)


def _act_pos(cand) -> float:
    return float(np.mean([k.actuated_position for k in cand.actuated]))


def _screen(m, comps, catalog) -> dict:
    """``{index: ((g, definition), ...)}`` of the candidates whose legs, built by their
    rules at the nominal home of a geometry ``g``, span the complementary system there."""
    specs = synthesis_catalog(catalog).legs
    probes: dict = {}
    cache: dict = {}
    out = {}
    for i, cand in enumerate(comps):
        key = (len(cand.legs), bool(cand.passive))
        if key not in probes:
            probes[key] = [_probe(m, key[0], g, catalog, key[1])
                           for g in range(len(geometries_for(*key)))]
        names = [k.name for k in cand.legs]
        ok = []
        for g, probe in enumerate(probes[key]):
            if probe is None:
                continue
            home = _home_legs(names, (*key, g), probe, specs, cache)
            if any(lg is None for lg in home):
                continue                         # not buildable at the nominal home
            mob = mobility_of_legs(home)
            if (mob.dof, mob.translations, mob.rotations) == (m.dof, m.translations, m.rotations):
                ok.append((g, pm_definition(cand, m, g)))
        if ok:
            out[i] = tuple(ok)
    return out
