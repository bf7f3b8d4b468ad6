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
   over-constrained candidate that cannot move costs the engine's continuation from home;
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
from ..synthesis import (GEOMETRIES, compositions_for, leg_pool, model_yaml, motion_pattern,
                         pm_definition, synthesis_catalog)
from ._verify import Verdict, load_candidate, verify_model

__all__ = ["MAX_LEGS", "SynthesizedPM", "TypeSynthesis", "synthesize_motion"]

#: Largest number of legs (the standard geometries have 3, 4 or 5 vertices).
MAX_LEGS = max(GEOMETRIES)
#: Default budget of engine verifications of one search.
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

    def model_yaml(self) -> str:
        """The model YAML (``screwkit.load_pm`` reads it, with any extra leg types)."""
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
                "finite_check": v.finite, "notes": list(v.notes), "definition": self.definition}


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


def _probe(motion, n, g, catalog):
    """A model of ``n`` unconstrained legs on geometry ``g``: its placements at home."""
    probe = pm_definition(_unconstrained(n), motion, g)
    try:
        return load_pm("probe", None, synthesis_catalog(catalog, {"probe": probe}))
    except ScrewkitError:
        return None


def _unconstrained(n):
    from ..synthesis import Candidate, LegKind
    sps = LegKind("SPS", "SPS", "S_PS", 0, 0, 0, 7, 2)
    return Candidate((sps,) * n, f"{n}SPS", f"{n}SPS", True)


def _home_legs(kind_names, g, probe, specs, cache):
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
                      asymmetric: bool = True, max_verified: int | None = None, catalog=None,
                      progress=None) -> TypeSynthesis:
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
    max_verified : int, optional
        At most this many engine verifications (default ``MAX_VERIFIED``); candidates are
        taken symmetric first, then by joint count, so the budget goes to the simplest.
    catalog : Catalog, optional
        Leg types (default: the packaged catalog), plus the extra arrangements.
    progress : callable, optional
        ``progress(done, total)`` after each candidate.

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
    cat = synthesis_catalog(catalog)
    specs = cat.legs
    probes = [_probe(m, n, g, catalog) for g in range(len(GEOMETRIES[n]))]
    cache: dict = {}
    found, rejected, screened = [], [], 0
    budget = MAX_VERIFIED if max_verified is None else max_verified
    engine_runs, skipped, pruned = 0, 0, 0
    good = set()                                 # leg types whose symmetric PM verified
    for done, cand in enumerate(comps, start=1):
        names = [k.name for k in cand.legs]
        reason, hit = "", None
        if not cand.symmetric and cand.legs[0].name not in good and (
                cand.legs[-1].constraints or cand.constraints != m.constraints):
            pruned += 1
            if progress is not None:
                progress(done, len(comps))
            continue
        for g, probe in enumerate(probes):
            if probe is None:
                continue
            home = _home_legs(names, g, probe, specs, cache)
            if any(lg is None for lg in home):
                continue                         # not buildable at the nominal home
            mob = mobility_of_legs(home)
            if (mob.dof, mob.translations, mob.rotations) != (m.dof, m.translations, m.rotations):
                continue                         # the legs do not span the system here
            if engine_runs >= budget:
                skipped += 1
                reason = "skipped"
                break
            engine_runs += 1
            d = pm_definition(cand, m, g)
            model, exc = load_candidate(cand.name, synthesis_catalog(catalog, {cand.name: d}))
            if model is None:
                reason = reason or f"cannot be assembled: {exc}"
                continue
            verdict = verify_model(model, m)
            if verdict.success:
                hit = (g, d, verdict)
                break
            reason = verdict.reason
        if hit is not None:
            found.append((cand, *hit))
            if cand.symmetric:
                good.add(cand.legs[0].name)
        elif reason and reason != "skipped":
            rejected.append((cand.name, reason))
        elif not reason:
            screened += 1
        if progress is not None:
            progress(done, len(comps))
    found.sort(key=lambda x: (x[0].joints, float(np.mean([k.actuated_position for k in x[0].legs])),
                              x[3].condition_home, x[0].name))
    listed = []
    for r, (cand, g, d, verdict) in enumerate(found[:limit] if limit else found, start=1):
        listed.append(SynthesizedPM(
            r, cand.name, cand.string, m.name, tuple(k.name for k in cand.legs), cand.symmetric,
            GEOMETRIES[n][g][0], cand.joints, tuple(k.marked for k in cand.legs),
            float(np.mean([k.actuated_position for k in cand.legs])), verdict.condition_home,
            verdict, d))
    return TypeSynthesis(m, n, pool, tuple(listed), len(found), len(comps), tuple(rejected),
                         screened, skipped, pruned)
