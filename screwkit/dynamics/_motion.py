"""A motion: the independent pose parameters and their first and second time derivatives.

The dynamics need, at every sample, the rates and accelerations of the independent pose
parameters (``t`` is time in **seconds**).  They come

* from **expressions** in ``t`` (``--expr``): exact derivatives by automatic
  differentiation of the expression tree (:mod:`screwkit.dynamics._jets`);
* from **samples** (a CSV path, a :class:`~screwkit.paths.PathSpec`, arrays): a cubic
  smoothing spline per parameter (:func:`scipy.interpolate.make_smoothing_spline`; the
  smoothing ``lam`` chosen by generalised cross-validation, or given; ``lam = 0``
  interpolates), whose values, first and second derivatives are used together (the pose
  is the spline's, so positions, rates and accelerations belong to one motion; the largest
  deviation from the samples is in :attr:`Motion.notes`);
* given directly (:meth:`Motion.from_arrays`).

Angles in radians (rad/s, rad/s^2), lengths in the model's unit (per s, per s^2).

Examples
--------
>>> m = motion_from_expressions(["alpha=10*sin(2*pi*t)", "beta=0", "Zo=80+10*t"],
...                             ("alpha", "beta", "Zo"), samples=3)
>>> [round(float(x), 6) for x in m.rates["alpha"]]              # 10 deg * 2 pi cos(2 pi t)
[1.096623, -1.096623, 1.096623]
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..paths import ANGLE_PARAMETERS, PathSpec, path_from_csv, path_from_expressions
from ..pm import parse_expression
from ._jets import derivatives

__all__ = ["Motion", "motion_from_expressions", "motion_from_samples", "motion_from_csv",
           "motion_from_path", "motion_from_args"]


def _frozen(a):
    a = np.array(a, float).reshape(-1)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Motion:
    """The independent pose parameters of a motion and their time derivatives.

    Attributes
    ----------
    t : ndarray (N,)
        Time, seconds (strictly increasing).
    values, rates, accelerations : dict str -> ndarray (N,)
        Per independent parameter: radians or model lengths, per second, per second^2.
    source : str
        Where the motion came from.
    method : str
        How the derivatives were obtained (``automatic differentiation``, ``smoothing
        spline``, ``given``).
    notes : tuple of str
    """

    t: np.ndarray
    values: dict
    rates: dict
    accelerations: dict
    source: str = ""
    method: str = "given"
    notes: tuple = field(default=())

    def __post_init__(self):
        t = _frozen(self.t)
        object.__setattr__(self, "t", t)
        if t.size == 0 or np.any(np.diff(t) <= 0) or not np.all(np.isfinite(t)):
            raise InputError("a motion needs finite, strictly increasing times t")
        names = set(self.values)
        for what in ("values", "rates", "accelerations"):
            d = getattr(self, what)
            if set(d) != names:
                raise InputError(f"motion {what} name {', '.join(sorted(d))}; the values name "
                                 f"{', '.join(sorted(names))}")
            out = {}
            for k, v in d.items():
                a = _frozen(np.broadcast_to(np.asarray(v, float), t.shape))
                if not np.all(np.isfinite(a)):
                    raise InputError(f"motion {what} of {k} are not all finite")
                out[k] = a
            object.__setattr__(self, what, out)

    @classmethod
    def from_arrays(cls, t, values, rates, accelerations, source="arrays") -> "Motion":
        """A motion with its derivatives given (radians, seconds)."""
        return cls(t, dict(values), dict(rates), dict(accelerations), source, "given")

    def __len__(self) -> int:
        return int(self.t.size)

    @property
    def names(self) -> tuple:
        return tuple(self.values)

    @property
    def path(self) -> PathSpec:
        """The samples as a :class:`~screwkit.paths.PathSpec` (the static run's input)."""
        return PathSpec(self.t, dict(self.values), self.source, tuple(self.values))


def motion_from_expressions(exprs, independent, *, samples: int = 51, t_range=(0.0, 1.0),
                            angle_unit: str = "deg") -> Motion:
    """A motion given by one expression in ``t`` (seconds) per independent parameter, with
    exact derivatives (angles in degrees unless ``angle_unit="rad"``)."""
    spec = path_from_expressions(exprs, independent, samples=samples, t_range=t_range,
                                 angle_unit=angle_unit)
    if isinstance(exprs, dict):
        pairs = list(exprs.items())
    else:
        from ..paths import parse_assignment
        pairs = [parse_assignment(e) for e in ([exprs] if isinstance(exprs, str) else exprs)]
    vals, rates, accs = {}, {}, {}
    for name, text in pairs:
        try:
            f, d1, d2 = derivatives(parse_expression(text), spec.t)
        except InputError as exc:
            raise InputError(f"{name}: {exc}") from None
        k = np.pi / 180.0 if (name in ANGLE_PARAMETERS and angle_unit == "deg") else 1.0
        vals[name], rates[name], accs[name] = f * k, d1 * k, d2 * k
    return Motion(spec.t, vals, rates, accs, spec.source,
                  "automatic differentiation of the expressions (exact)")


def motion_from_samples(t, values, independent=None, *, smoothing=None, source="samples",
                        length_unit: str = "length") -> Motion:
    """A motion through samples: a cubic smoothing spline per parameter.

    Parameters
    ----------
    t : array_like (N,)
        Times (s), strictly increasing, N >= 5.
    values : mapping str -> array_like (N,)
        Radians and model lengths.
    independent : sequence of str, optional
        The names expected (default: those of ``values``).
    smoothing : float or None
        The spline's ``lam`` (:func:`scipy.interpolate.make_smoothing_spline`, natural ends:
        its second derivative is 0 at the first and last samples): None chooses it by
        generalised cross-validation; 0 interpolates the samples with a not-a-knot cubic
        spline (:class:`scipy.interpolate.CubicSpline`), whose ends are free.
    length_unit : str
        The model's length unit, for the notes.
    """
    from scipy.interpolate import CubicSpline, make_smoothing_spline

    t = np.asarray(t, float).reshape(-1)
    names = tuple(independent) if independent is not None else tuple(values)
    if set(values) != set(names):
        raise InputError(f"the samples give {', '.join(sorted(values))}; the independent "
                         f"parameters are {', '.join(names)}")
    if t.size < 5:
        raise InputError(f"a spline through samples needs at least 5 of them, got {t.size}")
    if smoothing is not None and not (np.isfinite(smoothing) and smoothing >= 0):
        raise InputError(f"smoothing must be a finite number >= 0, not {smoothing!r}")
    vals, rates, accs, notes = {}, {}, {}, []
    worst = []
    for k in names:
        y = np.asarray(values[k], float).reshape(-1)
        if y.shape != t.shape:
            raise InputError(f"{k} has {y.size} samples, t has {t.size}")
        if smoothing == 0:
            # interpolation: not-a-knot ends (the natural spline's second derivative is 0 at
            # the first and last samples: accelerations of 0 there, whatever the path)
            s = CubicSpline(t, y, bc_type="not-a-knot")
        else:
            s = make_smoothing_spline(t, y, lam=smoothing)
        vals[k], rates[k], accs[k] = s(t), s.derivative(1)(t), s.derivative(2)(t)
        dev = float(np.max(np.abs(vals[k] - y)))
        unit = "deg" if k in ANGLE_PARAMETERS else length_unit
        worst.append(f"{k} {np.degrees(dev) if unit == 'deg' else dev:.3g} {unit}")
    if smoothing == 0:
        notes.append("smoothing spline (lam = 0: interpolating, not-a-knot ends); largest "
                     "deviation from the samples: " + ", ".join(worst))
        return Motion(t, vals, rates, accs, source,
                      "cubic smoothing spline (lam = 0: interpolating, not-a-knot ends)",
                      tuple(notes))
    how = "GCV" if smoothing is None else f"lam = {smoothing:g}"
    notes.append(f"smoothing spline ({how}); largest deviation from the samples: "
                 + ", ".join(worst) + "; its second derivative is 0 at the first and last "
                 "samples (natural ends): the accelerations there and near them are not the "
                 "path's (--smoothing 0 interpolates with free ends)")
    return Motion(t, vals, rates, accs, source, f"cubic smoothing spline ({how})", tuple(notes))


def motion_from_path(path: PathSpec, *, smoothing=None, length_unit: str = "length") -> Motion:
    """A motion through the samples of a :class:`~screwkit.paths.PathSpec` (spline)."""
    if not isinstance(path, PathSpec):
        raise InputError(f"expected a PathSpec, got {type(path).__name__}")
    return motion_from_samples(path.t, path.values, path.independent, smoothing=smoothing,
                               source=path.source, length_unit=length_unit)


def motion_from_csv(path, independent, *, smoothing=None, angle_unit: str = "deg",
                    length_unit: str = "length") -> Motion:
    """A motion through the samples of a CSV path file (:func:`~screwkit.paths.path_from_csv`;
    ``t`` in seconds, angles in degrees)."""
    # (a header's length unit is read against the model's, as the static path reads it)
    declared = None if length_unit in ("length", "[L]") else length_unit
    return motion_from_path(path_from_csv(path, independent, angle_unit=angle_unit,
                                          length_unit=declared),
                            smoothing=smoothing, length_unit=length_unit)


def motion_from_args(args, independent, length_unit: str = "length") -> Motion:
    """The motion of the CLI's path options (``--expr``: exact; ``--path``: spline with
    ``--smoothing``)."""
    if getattr(args, "path", None) and getattr(args, "expr", None):
        raise InputError("give either --path FILE or --expr NAME=EXPR, not both")
    from ..paths._pathspec import expr_sampling
    samples, t_range = expr_sampling(args)
    if getattr(args, "expr", None):
        return motion_from_expressions(args.expr, independent, samples=samples, t_range=t_range)
    if getattr(args, "path", None):
        return motion_from_csv(args.path, independent, smoothing=getattr(args, "smoothing", None),
                               length_unit=length_unit)
    raise InputError(f"no path given: use --path FILE or --expr NAME=EXPR for each of "
                     f"{', '.join(independent)}")
