"""Validation of the engine's inputs: pose parameters (numbers, arrays, a DataFrame) and warm
starts (private)."""

from __future__ import annotations

import weakref

import numpy as np

from .. import errors as _err
from ..legs._guards import (MAX_ANGLE_DEG, MAX_BATCH, MAX_LENGTH_FACTOR, did_you_mean,
                            real_array, shorten)
from ._chains import LENGTH_PARAMS, PARAMS, chains_of

__all__ = ["pose_arrays", "pose_index", "prepare", "check_keywords"]


def pose_index(i, n: int, one: bool = False):
    """Poses ``i`` of a batch of ``n``: an ``int`` for one pose (negative counts from the
    end), or an integer array ``(k,)`` for a sub-batch (from a slice, a sequence of
    integers or a boolean mask of length ``n``), as numpy indexes the pose axis.

    ``None``, ``True``/``False`` (numpy would add an axis) and nested sequences (a 2-D
    index) are an :class:`IndexError`, and so is a selection of no pose (``res[[]]``, an
    all-False mask, an empty slice): a batch holds at least one pose, as :func:`analyze`
    requires.  ``one``: only an ``int`` (one pose's index)."""
    from ..errors import PoseIndexError
    if one and (isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer))):
        raise PoseIndexError(f"one pose's index is an int, got {i!r}")
    msg = "a batch has one pose axis: index it with an int, a slice, integers or a boolean mask"
    if isinstance(i, tuple) or i is None or isinstance(i, (bool, np.bool_)) or \
            (isinstance(i, np.ndarray) and i.dtype == bool and i.ndim == 0):
        raise PoseIndexError(f"{msg}, got {i!r}")
    try:
        idx = np.arange(n)[i]
    except IndexError as exc:
        raise PoseIndexError(f"pose index {i!r} does not fit a batch of {n} poses ({exc})") from None
    if np.ndim(idx) == 0:
        return int(idx)
    if np.ndim(idx) != 1:
        raise PoseIndexError(f"{msg}, got an index of {np.ndim(idx)} dimensions")
    if idx.size == 0:
        raise PoseIndexError(f"pose index {i!r} selects none of the {n} poses (a sub-batch holds "
                         "at least one pose: test the mask first, e.g. 'if res.ok.any()')")
    return idx


def _errors():
    return _err


def pose_arrays(model, pose, degrees: bool = False):
    """Validate independent pose parameters; return ``(dict of (N,) arrays, N, single, notes,
    invalid)``.

    ``pose``: a mapping (or a pandas DataFrame) of the model's independent parameters
    to numbers or 1-D arrays of one length; missing ones take the model's default.
    Angles are limited to +-3600 degrees, lengths to 1e12 times the model's size
    (``screwkit.legs._guards``); booleans and strings are refused, and so are non-finite
    or out-of-range values of one pose.  In a batch, a pose with such a value is *flagged*
    and the others kept: ``invalid`` maps its index to the reason, and its values are
    replaced by the default pose's (solved, then marked unsolved by the caller).  An array
    longer than ``MAX_BATCH`` is refused before it is converted.
    """
    err = _err
    if pose is None:
        pose = {}
    if hasattr(pose, "columns") and hasattr(pose, "to_numpy"):      # a pandas DataFrame
        pose = {str(c): pose[c].to_numpy() for c in pose.columns}
    if not isinstance(pose, dict):
        raise err.InputError(f"{model.name}: the independent pose parameters must be a mapping "
                             f"name -> value of {', '.join(model.independent)}")
    vals, single, n = {}, True, None
    invalid: dict = {}
    plain = set()
    fresh = set()           # (N,) float arrays of this call's own (real_array's copies)
    lims = _plain_limits(model, degrees)
    for k, v in pose.items():
        # the common case, one pose of plain numbers, decided without numpy's conversions:
        # a float (or an int numpy converts exactly) of an independent parameter, well
        # within its limit (NaN fails the comparison); the rest, errors included, below
        t = type(v)
        if t is float or t is np.float64 or (t is int and -_EXACT < v < _EXACT):
            lim = lims.get(k)
            if lim is not None and abs(v) < lim:
                a = np.array([float(v)])
                vals[k] = np.radians(a) if degrees and k not in LENGTH_PARAMS else a
                plain.add(k)
                continue
        if k not in PARAMS:
            raise err.InputError(f"{model.name}: unknown pose parameter {shorten(k)}"
                                 f"{did_you_mean(k, model.independent)} (one of "
                                 f"{', '.join(PARAMS)})")
        if k not in model.independent:
            raise err.InputError(f"{model.name}: {k} is a dependent pose parameter; give "
                                 f"{', '.join(model.independent)}")
        # numbers only (no booleans, strings), sized before anything is converted
        a = real_array(v, f"{model.name}: pose parameter {k}", max_size=MAX_BATCH,
                       finite=not _is_batch(v))
        if a.ndim == 1:
            single = False
            fresh.add(k)
            if n is not None and a.size != n:
                raise err.InputError(f"{model.name}: pose parameter {k} has {a.size} values, "
                                     f"the others {n}")
            n = a.size
            bad = _flag(model, k, a, degrees, invalid)
            if bad is not None:
                a = np.where(bad, _default(model, k, degrees), a)
        else:
            _pose_bound(model, k, a, degrees)
        vals[k] = np.radians(a) if (degrees and k not in LENGTH_PARAMS) else a
    N = 1 if n is None else n
    if N == 0:
        raise err.InputError(f"{model.name}: no poses given (empty arrays)")
    notes = []
    missing = [k for k in model.independent if k not in vals]
    for k in missing:
        vals[k] = np.asarray(model.default_pose[k], float)
    if missing:
        notes.append(f"{', '.join(missing)} taken from the default pose")
    if N == 1 and len(plain) == len(vals):
        return vals, N, single, notes, invalid          # (each already a new (1,) array)
    return ({k: v if (k in plain and N == 1) or k in fresh else
             np.broadcast_to(v, (N,)).astype(float)
             for k, v in vals.items()}, N, single, notes, invalid)


#: Integers numpy converts to float64 exactly.
_EXACT = 1 << 53
_ANGLE_LIMIT_RAD = float(np.radians(MAX_ANGLE_DEG))
_LIMITS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _plain_limits(model, degrees) -> dict:
    """Per independent parameter of ``model``, the magnitude below which a plain number
    needs no other check (well within the limits of :func:`_pose_bound`: half the length
    limit, 97 % of the angle limit), in the units given (cached per model)."""
    try:
        both = _LIMITS.get(model)
    except TypeError:                    # (a model that cannot be referenced weakly)
        both = None
    if both is None:
        size = float(getattr(getattr(model, "normalisation", None), "length", 1.0) or 1.0)
        both = tuple({k: 0.5 * MAX_LENGTH_FACTOR * size if k in LENGTH_PARAMS else 0.97 * a
                      for k in model.independent}
                     for a in (_ANGLE_LIMIT_RAD, MAX_ANGLE_DEG))
        try:
            _LIMITS[model] = both
        except TypeError:
            pass
    return both[1 if degrees else 0]


def _is_batch(v) -> bool:
    return (isinstance(v, np.ndarray) and v.ndim == 1) or isinstance(v, (list, tuple))


def _default(model, k, degrees):
    v = float(model.default_pose.get(k, 0.0)) if k in model.default_pose else 0.0
    return np.degrees(v) if (degrees and k not in LENGTH_PARAMS) else v


def _flag(model, k, a, degrees, invalid) -> np.ndarray | None:
    """The poses of a batch whose value of ``k`` is not finite or beyond the limits, each
    with its reason added to ``invalid`` (index -> text); None where there is none."""
    if k in LENGTH_PARAMS:
        size = float(getattr(getattr(model, "normalisation", None), "length", 1.0) or 1.0)
        lim, unit = MAX_LENGTH_FACTOR * size, ""
    else:
        lim = MAX_ANGLE_DEG if degrees else np.radians(MAX_ANGLE_DEG)
        unit = " deg" if degrees else " rad"
    # (NaN and the infinities are not within the limit either: two reductions settle the
    # common case, all within, without an array of the test)
    lo, hi = (float(np.min(a)), float(np.max(a))) if a.size else (0.0, 0.0)
    if -lim <= lo and hi <= lim:
        return None
    with np.errstate(invalid="ignore"):
        within = np.abs(a) <= lim
    if within.all():
        return None
    bad = ~within
    where = np.flatnonzero(bad)
    for i in where[:1000]:
        why = "is not a finite number" if not np.isfinite(a[i]) else \
            f"is beyond the limit +-{lim:g}{unit}"
        invalid.setdefault(int(i), []).append(f"pose parameter {k} = {a[i]:g}{unit} {why}")
    for i in where[1000:]:
        invalid.setdefault(int(i), []).append(f"pose parameter {k} is not valid")
    return bad


def _pose_bound(model, k, a, degrees):
    """Refuse a pose value beyond the limits: angles +-3600 deg, lengths 1e12 model sizes."""
    err = _errors()
    m = float(np.max(np.abs(a))) if a.size else 0.0
    if a.size and m > 0.0:              # (the value said as given: its sign too)
        m = float(a.reshape(-1)[int(np.argmax(np.abs(a)))])
    if k in LENGTH_PARAMS:
        norm = getattr(model, "normalisation", None)
        size = float(getattr(norm, "length", 1.0) or 1.0)
        lim = MAX_LENGTH_FACTOR * size
        if abs(m) > lim:
            raise err.InputError(f"{model.name}: pose parameter {k} = {m:g} is beyond the limit "
                                 f"+-{lim:g} ({MAX_LENGTH_FACTOR:g} times the model's size "
                                 f"{size:.4g})")
    else:
        deg = abs(m) if degrees else float(np.degrees(abs(m)))
        if deg > MAX_ANGLE_DEG:
            shown = f"{m:g} deg" if degrees else f"{m:g} rad"
            raise err.InputError(f"{model.name}: pose angle {k} = {shown} is beyond the limit "
                                 f"+-{MAX_ANGLE_DEG:g} deg (ten turns)")


def _start_of(model, guess, N, degrees=False):
    """Warm starts ``(X (n_unknowns, N), side, G6)`` from a guess (a dict's angles in degrees
    with ``degrees``), or ``(None, None, None)``.  ``G6 (N, 6)``: the pose parameters of a
    solution given as the guess (NaN where it has none), by which the kernels move each start
    (``run_poses``); a dict's guess has none (``None``)."""
    err = _errors()
    if guess is None:
        return None, None, None
    ch = chains_of(model)
    if not hasattr(guess, "closures") and hasattr(guess, "solution") and \
            hasattr(guess, "statics"):                              # a PMAnalysis: its poses
        guess = guess.solution
    if hasattr(guess, "closures") and hasattr(guess, "_params"):   # a PoseSolution
        if guess.model is not model and [len(lg.joints) for lg in guess.model.home_legs] != \
                [len(lg.joints) for lg in model.home_legs]:
            raise err.InputError(f"{model.name}: the guess is a solution of another PM")
        X = guess.closures.X
        b, G6 = guess._params["beta"], guess._pose6
        if X.shape[1] == 1 and N > 1:
            X, b, G6 = np.repeat(X, N, axis=1), np.repeat(b, N), np.repeat(G6, N, axis=0)
        if X.shape[1] != N:
            raise err.InputError(f"{model.name}: the guess has {X.shape[1]} poses for {N}")
        return X.copy(), b, G6
    if isinstance(guess, dict):
        X = ch.home_vector(N)
        for k, v in guess.items():
            if k not in PARAMS:
                raise err.InputError(f"{model.name}: bad guess entry {k}={v!r}")
            try:
                a = np.broadcast_to(np.asarray(v, float), (N,))
            except (TypeError, ValueError):
                raise err.InputError(f"{model.name}: bad guess entry {k}={v!r}") from None
            if not np.all(np.isfinite(a)):
                raise err.InputError(f"{model.name}: bad guess entry {k}={v!r}")
            if degrees and k not in LENGTH_PARAMS:
                a = np.radians(a)
                guess = dict(guess, **{k: a})
            if k in ch.unknown:
                X[ch.unknown.index(k)] = a / ch.x_scale[ch.unknown.index(k)]
        return X, np.broadcast_to(np.asarray(guess.get("beta", ch.home["beta"]), float),
                                  (N,)), None
    raise err.InputError(f"{model.name}: guess must be a PoseSolution, a PMAnalysis or a dict of pose "
                         "parameters")


def prepare(model, pose, guess, degrees):
    """Validated inputs of a solve: ``(fixed, N, single, notes, (X0, G6), side, invalid)``
    (the warm starts and the poses they solve: :func:`_start_of`)."""
    fixed, N, one, notes, invalid = pose_arrays(model, pose, degrees)
    X0, bside, G6 = _start_of(model, guess, N, degrees)
    side = None
    if bside is not None and "beta" in fixed:
        if N == 1:                       # (one pose: the same numbers without numpy's calls)
            d = float(bside[0]) - float(fixed["beta"][0])
            side = np.array([(1.0 if d > 0 else -1.0) if abs(d) > 1e-4 else 0.0])
        else:
            d = np.asarray(bside) - fixed["beta"]
            side = np.where(np.abs(d) > 1e-4, np.sign(d), 0.0)
    return fixed, N, one, notes, (X0, G6), side, invalid


_KEYWORDS: dict = {}


def check_forwarded(what: str, fn, kwargs: dict, also=()) -> None:
    """:func:`check_keywords` of the keywords a function forwards to ``fn``: those ``fn``
    takes by keyword, and ``also`` (the forwarding function's own).  Without it a keyword
    neither takes is a bare ``TypeError`` naming ``fn``, an internal function."""
    if not kwargs:
        return
    names = _KEYWORDS.get(fn)
    if names is None:
        import inspect
        names = frozenset(p.name for p in inspect.signature(fn).parameters.values()
                          if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD))
        _KEYWORDS[fn] = names
    if not names.issuperset(kwargs):
        check_keywords(what, {k: v for k, v in kwargs.items() if k not in names},
                       sorted(set(also) | {n for n in names if n not in ("pm", "model", "pose",
                                                                        "grid", "fix", "vary")}))


def forwarded(what: str, fn, *args, **kwargs):
    """``fn(*args, **kwargs)``, a keyword ``fn`` does not take a :class:`MisuseError` naming
    ``what`` (:func:`check_forwarded`)."""
    check_forwarded(what, fn, kwargs)
    return fn(*args, **kwargs)


def check_keywords(what: str, kwargs: dict, allowed, named: str = "") -> None:
    """A :class:`~screwkit.errors.MisuseError` for a keyword ``what`` does not take (a
    bare ``TypeError`` named an internal function)."""
    for k in sorted(set(kwargs) - set(allowed)):
        from ..errors import MisuseError
        raise MisuseError(f"{what} takes no keyword {k!r} (its keywords: {named}"
                          f"{', '.join(allowed)})")
