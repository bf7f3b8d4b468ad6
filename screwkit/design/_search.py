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
   Three-leg *pair* compositions (:func:`screwkit.synthesis.pair_compositions`: two legs
   of one type on a base diameter whose constraint systems are redundant together, and a
   third type completing the complementary system, the Exechon's 2-UPR+SPR) come next,
   on the pair geometry, with a budget of their own (``MAX_PAIR``).
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

import numpy as np

from ..errors import GeometryError, InputError, ScrewkitError
from ..legs import build_leg
from ..pm import Catalog, load_pm, mobility_of_legs
from ..synthesis import (CENTRAL_GEOMETRIES, GEOMETRIES, PAIR_GEOMETRIES, build_pool,
                         catalog_compositions, central_compositions, compositions_for,
                         geometries_for, motion_pattern, pair_compositions,
                         passive_compositions, pm_definition, synthesis_catalog)
from ..synthesis._leg_types import VARIANTS
from ._results import SynthesizedPM, TypeSynthesis
from ._tasks import monotonic_progress, run_round

__all__ = ["MAX_LEGS", "MAX_MIX", "MAX_PAIR", "MAX_VERIFIED", "SynthesizedPM", "TypeSynthesis",
           "synthesize_motion"]

#: Largest number of legs (the standard geometries have 3, 4 or 5 vertices).
MAX_LEGS = max(GEOMETRIES)
#: Default budget of engine verifications (a candidate on one geometry) of one search, for
#: the actuated compositions and again for the passive-leg ones.
MAX_VERIFIED = 400
#: Leg types whose symmetric PMs verified that are mixed two by two (the best ranked).
MAX_MIX = 4
#: Budget of engine verifications of the pair compositions (two legs of one type on a
#: diameter, the Exechon's; :func:`screwkit.synthesis.pair_compositions`).
MAX_PAIR = 40


def _probe(motion, n, g, catalog, passive=False, central=False, pair=False):
    """A model of ``n`` unconstrained legs on geometry ``g``: its placements at home."""
    from ..pm import default_catalog
    probe = pm_definition(_unconstrained(n, passive, central, pair), motion, g)
    # the probe's SPS legs only place the vertices: the packaged SPS, whatever the catalog
    sps = {"SPS": default_catalog().legs["SPS"]}
    try:
        return load_pm("probe", None, synthesis_catalog(catalog, {"probe": probe}, sps))
    except ScrewkitError:
        return None


def _unconstrained(n, passive=False, central=False, pair=False):
    from ..synthesis import Candidate, LegKind
    sps = LegKind("SPS", "SPS", "S_PS", 0, 0, 0, 7, 2)
    if pair:
        return Candidate((sps,) * n, f"{n}SPS", f"{n}SPS", True, pair=True)
    if central or passive:
        text = f"{n - 1}SPS+SPS/passive"
        return Candidate((sps,) * n, text, text, False, (n - 1,) if central else (0,), central)
    return Candidate((sps,) * n, f"{n}SPS", f"{n}SPS", True)


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
                      asymmetric: bool = True, passive: bool | None = None,
                      max_verified: int | None = None, catalog=None, progress=None,
                      mapper=None, generate: bool = True, variants: int = VARIANTS,
                      wide: bool = False) -> TypeSynthesis:
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
        Also two-type compositions (``2-UPU+SPR``).
    passive : bool, optional
        Default: as ``asymmetric``.  Also the actuated legs plus one passive constraining
        leg (a verification budget of
        their own): unconstrained actuated legs and a generated central column that exerts
        the whole complementary system (:func:`screwkit.synthesis.central_compositions`,
        the Tricept), and the catalog's constraining leg types at vertex 1
        (:func:`screwkit.synthesis.passive_compositions`; ``legs + 1`` legs, tried when a
        standard geometry has that many vertices).  The written model declares the leg
        passive (``{leg: NAME, passive: true}``).
    max_verified : int, optional
        At most this many engine verifications (one candidate on one geometry; default
        ``MAX_VERIFIED``) for the actuated compositions, and as many for the passive-leg
        ones.  They go geometry by geometry (every candidate on the first geometry where
        it passed the screen, then the ones that failed there on their next), candidates
        symmetric first, the catalog's before generated ones, then by joint count.
    catalog : Catalog, optional
        Leg types (default: the packaged catalog, e.g. extended with a model file's leg
        types, :func:`screwkit.extend_catalog`), plus the extra arrangements.
    progress : callable, optional
        ``progress(done, total)`` as candidates are screened and verified.
    mapper : callable, optional
        ``mapper(fn, items, progress)`` -> ``[fn(x) for x in items]`` in order: runs the
        engine verifications (``functools.partial(screwkit.maps.run_tasks, cluster)`` on a
        Dask cluster); default serial.  The result is the same either way.
    generate : bool
        Add the leg types generated for the pattern to the pool
        (:func:`screwkit.synthesis.generated_legs`); ``False``: the catalog's only.
    variants, wide
        Of the leg generation: leg types kept per letter word, and the wide enumeration
        (H joints, five-joint legs of four or five letters; slower: use a Dask cluster).

    Returns
    -------
    TypeSynthesis

    Examples
    --------
    >>> res = synthesize_motion("3T", limit=3)          # doctest: +SKIP
    >>> res.listed[0].name, res.listed[0].verdict.checks[1].motion_type  # doctest: +SKIP
    ('3-PRRR', '3T')
    """
    m = motion_pattern(motion)
    for name, fn in (("mapper", mapper), ("progress", progress)):
        if fn is not None and not callable(fn):
            raise InputError(f"{name} must be a function or None, got {str(fn)[:40]}")
    if catalog is not None and not isinstance(catalog, Catalog):
        raise InputError(f"catalog must be a screwkit Catalog (screwkit.extend_catalog) or "
                         f"None, got {str(catalog)[:40]}")
    passive = bool(asymmetric) if passive is None else bool(passive)
    n = m.dof if legs is None else legs
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not m.dof <= n <= MAX_LEGS \
            or int(n) not in GEOMETRIES:
        raise InputError(f"--legs must be an integer from {m.dof} (the DOF of {m.name}) to "
                         f"{MAX_LEGS} with a standard geometry "
                         f"({', '.join(map(str, sorted(GEOMETRIES)))} legs), got {legs!r:.20}")
    n = int(n)
    for what, v, hi in (("--limit", limit, None), ("max_verified", max_verified, 10000),
                        ("variants", variants, 20)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, np.integer))
                              or v < 1 or (hi is not None and v > hi)):
            raise InputError(f"{what} must be a positive integer{f' up to {hi}' if hi else ''}, "
                             f"got {v!r:.20}")
    pool = build_pool(m, catalog, generate=generate, variants=int(variants), wide=bool(wide))
    kinds, cat = pool.kinds, pool.catalog
    order = {k.name: i for i, k in enumerate(kinds)}

    def first(c):
        return (not c.symmetric, not c.preferred, c.joints, order[c.legs[0].name])

    comps = compositions_for(m, kinds, n, asymmetric, among=frozenset())
    known = {c.name for c in comps}
    seeds = [c for c in catalog_compositions(m, kinds, cat, n) if c.name not in known
             and (asymmetric or c.symmetric)]
    comps = sorted(comps + seeds, key=first)
    n_mixes = _count_mixes(m, kinds, n) if asymmetric else 0
    total = n_mixes + len(comps)
    if progress is not None:
        progress = monotonic_progress(progress)
    budget = MAX_VERIFIED if max_verified is None else max_verified
    # round 1: symmetric, and constraining + unconstrained legs without redundancy
    outcome: dict = {}
    screened = _screen(m, comps, cat)                 # {index: ((g, definition), ...)}
    spent = run_round(m, comps, screened, list(range(len(comps))), budget, cat, mapper,
                      progress, outcome, 0, total)
    # round 2: mixes of two leg types whose symmetric PMs verified (the best MAX_MIX)
    good = [comps[i] for i, r in sorted(outcome.items()) if comps[i].symmetric
            and r.geometry is not None]
    good.sort(key=lambda c: _rank_key(c, outcome[comps.index(c)].verdict))
    top = frozenset(c.legs[0].name for c in good[:MAX_MIX])
    known = {c.name for c in comps}
    mixes = [c for c in compositions_for(m, kinds, n, asymmetric, among=top)
             if c.name not in known] if asymmetric else []
    start = len(comps)
    comps += sorted(mixes, key=first)
    screened.update({start + i: g for i, g in _screen(m, comps[start:], cat).items()})
    spent += run_round(m, comps, screened, list(range(start, len(comps))), budget - spent, cat,
                       mapper, progress, outcome, start, total)
    pruned = max(0, n_mixes - len(mixes) - sum(1 for c in comps[:start] if not c.symmetric))
    # round 2b: two legs of one type on a diameter and a third type (the Exechon's)
    if asymmetric and n in PAIR_GEOMETRIES:
        start = len(comps)
        among = frozenset(c.legs[0].name for c in good) | {k.name for k in kinds if k.preferred}
        pairs = pair_compositions(m, kinds, _pair_ranks(m, kinds, cat), among)
        comps += sorted(pairs, key=lambda c: (not c.preferred, c.joints, c.name))
        total += len(comps) - start
        screened.update({start + i: g for i, g in _screen(m, comps[start:], cat).items()})
        spent += run_round(m, comps, screened, list(range(start, len(comps))),
                           min(MAX_PAIR, budget), cat, mapper, progress, outcome, start, total)
    # round 3: the passive-leg ones (a budget of their own): a central column, or the
    # catalog's constraining leg types at vertex 1
    if passive:
        start = len(comps)
        extra = central_compositions(m, pool.columns, kinds, n) if n in CENTRAL_GEOMETRIES \
            else []
        if n + 1 in GEOMETRIES:
            extra += passive_compositions(m, [k for k in kinds if k.preferred], n)
        comps += sorted(extra, key=lambda c: (not c.central, not c.preferred, c.joints))
        total += len(comps) - start
        screened.update({start + i: g for i, g in _screen(m, comps[start:], cat).items()})
        spent += run_round(m, comps, screened, list(range(start, len(comps))), budget, cat,
                           mapper, progress, outcome, start, total)
    found, rejected, skipped = [], [], 0
    for i, cand in enumerate(comps):
        r = outcome.get(i)
        if r is None:
            skipped += i in screened
        elif r.geometry is not None:
            found.append((cand, r.geometry, r.definition, r.verdict))
        else:
            rejected.append((cand.name, r.reason))
    screened_out = sum(1 for i in range(len(comps)) if i not in screened and i not in outcome)
    found.sort(key=lambda x: _rank_key(x[0], x[3]))
    listed = []
    for r, (cand, g, d, verdict) in enumerate(found[:limit] if limit else found, start=1):
        nl = len(cand.legs)
        names = [k.name for k in cand.legs]
        listed.append(SynthesizedPM(
            r, cand.literature, cand.string, m.name, tuple(names), cand.symmetric,
            geometries_for(nl, bool(cand.passive), cand.central, cand.pair)[g][0], cand.joints,
            tuple(k.marked for i, k in enumerate(cand.legs) if i not in cand.passive),
            _act_pos(cand), verdict.condition_home, verdict, d,
            tuple(cand.legs[i].name for i in cand.passive), cand.name,
            tuple(pool.definitions(names)), tuple(k.origin for k in cand.legs)))
    return TypeSynthesis(m, n, kinds, tuple(listed), len(found), total, tuple(rejected),
                         screened_out, skipped, pruned, pool.generated, spent)


def _rank_key(cand, verdict) -> tuple:
    """Actuators nearer the base first, then fewer joints, the catalog's leg types before
    generated ones, the better condition number of ``J`` at home."""
    return (_act_pos(cand), cand.joints, not cand.preferred, verdict.condition_home, cand.name)


def _count_mixes(m, kinds, n) -> int:
    """The number of asymmetric compositions :func:`compositions_for` forms without
    ``among`` (counted, not formed)."""
    need = m.constraints
    count = 0
    for i, a in enumerate(kinds):
        if not a.constraints:
            continue
        for j, b in enumerate(kinds):
            if b is a or (b.constraints, -j) > (a.constraints, -i):
                continue
            count += sum(1 for k in range(1, n)
                         if k * a.constraints + (n - k) * b.constraints >= need)
    return count


def _act_pos(cand) -> float:
    return float(np.mean([k.actuated_position for k in cand.actuated]))


def _pair_ranks(m, kinds, catalog) -> dict:
    """``{name: rank}``: the rank of the constraint systems of two legs of each constraining
    type at vertices 1 and 2 of the pair geometry, built by their rules at its home."""
    probe = _probe(m, 3, 0, catalog, pair=True)
    out: dict = {}
    if probe is None:
        return out
    cache: dict = {}
    for k in kinds:
        if not k.constraints:
            continue
        legs = _home_legs([k.name, k.name], ("pair", 0), probe, catalog.legs, cache)
        if all(lg is not None for lg in legs):
            out[k.name] = 6 - mobility_of_legs(legs).dof
    return out


def _screen(m, comps, catalog) -> dict:
    """``{index: ((g, definition), ...)}`` of the candidates whose legs, built by their
    rules at the nominal home of a geometry ``g``, span the complementary system there
    (``catalog``: every leg type of the pool)."""
    specs = catalog.legs
    probes: dict = {}
    cache: dict = {}
    out = {}
    for i, cand in enumerate(comps):
        key = (len(cand.legs), bool(cand.passive), cand.central, cand.pair)
        if key not in probes:
            probes[key] = [_probe(m, key[0], g, catalog, *key[1:])
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
