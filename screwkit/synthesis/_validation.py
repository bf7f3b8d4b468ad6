"""Batch validation: synthesis by the observation rules, verification by the solver.

For every leg string (the paper's Table I by default) :func:`validate_string`

1. analyses a *generic* geometry (:func:`screwkit.legs.generic_leg`): connectivity,
   number of constraint wrenches ``k = 6 - rank``, dependent joints;
2. for every composition of a ``k``-system into pure forces and couples
   (``(1, 0)`` and ``(0, 1)`` when ``k = 1``; ``(2, 0)``, ``(1, 1)``, ``(0, 2)``
   when ``k = 2``...) asks :func:`screwkit.synthesis.synthesize` for a structural
   arrangement, over several random draws;
3. verifies every synthesized leg with :func:`verify`, which sees only the
   concrete :class:`~screwkit.legs.Leg` and the predicted wrenches: the
   reciprocal-screw system has the predicted dimension and contains each
   predicted wrench, the joints are independent (or the dependence was
   predicted), and the actuated joint has an actuation wrench.

:func:`validate_catalog` checks the catalog's accepted legs the same way: each
leg built by its rules must have the system its ``expect`` states, agree with the
observation rules, have an actuation wrench, and its composition must be one the
synthesis finds realizable for its string.

Examples
--------
>>> res = validate_string("SPR", draws=1)
>>> res.k, res.can_force, res.can_couple, res.ok
(1, True, False, True)
"""

from __future__ import annotations

import time
import zlib

import numpy as np

from ..errors import InputError
from ..legs import Placement, analyze_leg, generic_leg, parse_leg
from ..legs._analysis import has_actuation_wrench
from ._reports import (CatalogCheck, DrawResult, LegValidation, TargetResult, ValidationReport,
                       composition_label)
from ._synthesis import Synthesis, compositions, counting_rank, layouts_for, synthesize
from ._verify import verify

__all__ = ["validate_string", "validate_catalog", "validate_table1", "DEFAULT_DRAWS"]

#: Random draws per target by default.
DEFAULT_DRAWS = 3


# --------------------------------------------------------------------------- drivers
def _seed_for(seed: int, text: str, *more) -> list:
    return [int(seed) & 0xFFFFFFFF, zlib.crc32(text.encode()), *more]


def _rng_for(seed: int, text: str, *more) -> np.random.Generator:
    """``default_rng(_seed_for(seed, text, *more))``.  The entropy goes in as a uint32 array
    when every word fits (numpy turns a list of such ints into that very array, at twice
    the cost)."""
    words = _seed_for(seed, text, *more)
    if all(isinstance(w, int) and 0 <= w < 2**32 for w in words):
        return np.random.default_rng(np.array(words, dtype=np.uint32))
    return np.random.default_rng(words)


def validate_string(string, draws: int = DEFAULT_DRAWS, seed: int = 0,
                    placement: Placement | None = None) -> LegValidation:
    """Validate one leg string (see the module docstring).

    Parameters
    ----------
    string : str or LegString
    draws : int
        Random draws per target (each: new target geometry and new free choices).
    seed : int
    placement : Placement, optional

    Returns
    -------
    LegValidation
    """
    if int(draws) < 1:
        raise InputError(f"draws must be at least 1, got {draws}")
    ls = parse_leg(string) if isinstance(string, str) else string
    text = ls.marked
    problems = []
    notes = []
    analyses = [analyze_leg(generic_leg(ls, placement, seed=s))
                for s in _rng_for(seed, text).integers(0, 2**31, 2)]
    ranks = [a.connectivity for a in analyses]
    if ranks[0] != ranks[1]:
        problems.append(f"generic rank differs between two random geometries: {ranks}")
    g = analyses[0]
    r = max(ranks)
    k = 6 - r
    cnt = counting_rank(ls)
    if cnt != r:
        notes.append(f"generic rank {r} below the counting bound {cnt} (compound joints "
                     "share an idle motion)")
    targets = []
    comps = compositions(k) if k >= 1 else ()
    if k > 3:
        notes.append(f"{k} constraint wrenches: compositions with more than 3 wrenches are "
                     "not synthesized")
        comps = ()
    for ci, comp in enumerate(comps):
        if not layouts_for(comp):
            continue
        results = []
        first: Synthesis | None = None
        for d in range(int(draws)):
            rng = _rng_for(seed, text, ci, d)
            s = synthesize(ls, comp, rng, placement)
            ver = verify(s.leg, s.predicted_wrenches, allow_dependent=s.dependent,
                         actuation="wrench" if d == 0 else "rank") if s.realizable else None
            results.append(DrawResult(d, s.realizable, s.layout.name, s.how, s.reason, ver))
            if first is None:
                first = s
        targets.append(TargetResult(comp, first.realizable, first.layout.name, first.layout.words,
                                    first.how, first.reason, first.proof, tuple(results)))
    return LegValidation(ls, r, k, g.kinds_summary(), g.dependent_joints, cnt, tuple(targets),
                         tuple(notes), tuple(problems))


def validate_catalog(catalog=None, known: dict | None = None, draws: int = 1,
                     seed: int = 0) -> tuple:
    """Check every accepted leg of the catalog (see the module docstring).

    Parameters
    ----------
    catalog : Catalog, optional
        Default :func:`screwkit.pm.default_catalog`.
    known : dict, optional
        ``{marked string: LegValidation}`` already computed (reused for the
        composition check).
    draws, seed : int
        For strings not in ``known``.

    Returns
    -------
    tuple of CatalogCheck
    """
    from ..pm import default_catalog

    cat = catalog if catalog is not None else default_catalog()
    known = {} if known is None else known
    out = []
    for spec in cat.legs.values():
        problems = []
        e = spec.expect
        expected = composition_label((int(e.get("forces", 0)), int(e.get("couples", 0))))
        if e.get("screws"):
            expected += f"+{int(e['screws'])}W"
        if not e:
            expected = "(not stated)"       # a user leg type without an expect block
        try:
            leg = spec.build()
        except Exception as exc:  # a ScrewkitError or a bug in the entry: report it
            out.append(CatalogCheck(spec.name, spec.string.marked, expected, "-",
                                    (f"cannot be built: {exc}",)))
            continue
        an = leg.analyze()
        if e:
            problems += list(spec.check_expectation(an))
        if not an.agrees():
            problems.append("the decomposition does not agree with the observation rules")
        if not has_actuation_wrench(leg, an.system):     # the test of an.actuation is None
            problems.append("the actuated joint has no actuation wrench")
        v = known.get(spec.string.marked)
        if v is None:
            v = validate_string(spec.string, draws=draws, seed=seed)
            known[spec.string.marked] = v
        comp = (an.n_forces, an.n_couples)
        if an.n_screws == 0 and sum(comp) == v.k and v.k >= 1:
            t = v.target(comp)
            if t is not None and not t.realizable:
                problems.append(f"the synthesis says {composition_label(comp)} is not realizable "
                                f"for {spec.string.text}: {t.reason}")
        found = an.summary()
        if an.dependent_joints:
            found += f" (dependent: {', '.join(an.dependent_joints)})"
        out.append(CatalogCheck(spec.name, spec.string.marked, expected, found, tuple(problems)))
    return tuple(out)


def validate_table1(draws: int = DEFAULT_DRAWS, seed: int = 0, catalog=None,
                    strings=None, check_catalog: bool = True, progress=None,
                    mapper=None) -> ValidationReport:
    """Validate the paper's Table I (101 distinct strings) and the catalog legs.

    Parameters
    ----------
    draws : int
    seed : int
    catalog : Catalog, optional
    strings : sequence of str, optional
        Validate these strings instead of Table I.
    check_catalog : bool
        Also run :func:`validate_catalog`.
    progress : callable(done, total), optional
        Called after each string (``total``: the strings, plus one step for the catalog).
    mapper : callable, optional
        ``mapper(fn, items, progress)`` -> ``[fn(x) for x in items]`` in order, computed
        elsewhere (e.g. ``functools.partial(screwkit.maps.run_tasks, cluster)`` on a Dask
        cluster: ``screwkit validate --workers N``).  ``fn`` is picklable; each string's
        validation depends only on the string, ``draws`` and ``seed``, so the report equals
        the serial one (but for ``seconds``).
    """
    from functools import partial

    from ..pm import default_catalog

    t0 = time.perf_counter()
    cat = catalog if catalog is not None else default_catalog()
    todo = _distinct_legs(strings) if strings is not None else cat.table1_distinct()
    total = len(todo) + bool(check_catalog)
    done = []
    if mapper is not None:
        done = list(mapper(partial(validate_string, draws=draws, seed=seed), todo,
                           (lambda d, n: progress(d, total)) if progress is not None else None))
    else:
        for s in todo:
            done.append(validate_string(s, draws=draws, seed=seed))
            if progress is not None:
                progress(len(done), total)
    legs = tuple(done)
    known = {v.string.marked: v for v in legs}
    checks = validate_catalog(cat, known, draws=draws, seed=seed) if check_catalog else ()
    if progress is not None and check_catalog:
        progress(total, total)
    return ValidationReport(legs, checks, int(draws), int(seed), time.perf_counter() - t0)


def _distinct_legs(strings) -> list:
    """The strings without repetitions of one leg (``UPU`` and ``U_PU`` are one), in order;
    a string that does not parse is kept as it is (its validation says why)."""
    from ..errors import ScrewkitError
    seen, out = set(), []
    for s in strings:
        try:
            key = parse_leg(s).marked
        except ScrewkitError:
            key = s
        if key not in seen:
            seen.add(key)
            out.append(s)
    return out
