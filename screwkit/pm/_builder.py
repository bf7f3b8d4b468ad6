"""Building a PM in Python: legs with their attachments, the pose parametrisation, units.

:class:`PMBuilder` assembles, call by call, what a model file's ``pms:`` entry holds (as
Pinocchio's ``Model.addJoint`` assembles what a URDF holds), and :meth:`PMBuilder.build`
reads it with the very loader of model files (:func:`screwkit.pm.load_pm`: the same checks,
the same errors) into a frozen :class:`~screwkit.pm.PMModel`.  :meth:`PMBuilder.to_mapping`
is that entry; :meth:`PMModel.to_mapping` and :meth:`PMModel.to_yaml` write any model back,
and reading it again gives the same model.

A leg is added either

* as a **leg type**: a catalog name (``"RPS"``), a :class:`~screwkit.pm.LegSpec` or a leg-type
  mapping as a model file's ``legs:`` holds it, placed by its rules at its base attachment
  ``A_i`` (base frame) and its platform attachment ``a_i`` (platform frame); or
* as a **placed leg**: a :class:`~screwkit.legs.Leg` (:func:`screwkit.leg_from_joints`,
  :func:`screwkit.leg`), whose joints are kept as they are, given at the home pose in the
  base frame, or in a frame of its own placed by ``frame=`` (a ``(R, p)`` pair, a 4 x 4
  matrix, or an object with ``rotation`` and ``translation`` such as ``pinocchio.SE3``).  It
  is written as a leg type of literal points and directions (``{base: [x, y, z]}``).

The pose parametrisation (:meth:`PMBuilder.set_pose`) names the independent pose
parameters, their home values (where the placed legs are given and the typed legs built) and
the Euler order; angles are radians unless ``degrees=True``.

Examples
--------
>>> import numpy as np
>>> import screwkit
>>> b = screwkit.PMBuilder("my3RPS", units={"length": "mm", "force": "N"})
>>> for t in np.radians([90, 210, 330]):
...     u = np.array([np.cos(t), np.sin(t), 0.0])
...     _ = b.add_leg("RPS", base=70 * u, platform=25 * u)
>>> _ = b.set_pose(["alpha", "beta", "Zo"], home={"alpha": 0, "beta": 0, "Zo": 60})
>>> pm = b.build()
>>> pm.string, pm.independent, pm.units.length
('3RPS', ('alpha', 'beta', 'Zo'), 'mm')
"""

from __future__ import annotations

import copy
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..legs import PASSIVE_SUFFIX, Leg, parse_leg
from ..legs._guards import MAX_LEGS, MAX_MAGNITUDE, MAX_NAME, real, shorten
from ..screws import check_order, rotation_matrix
from ._model import LENGTH_PARAMS, PARAMS, PMModel

__all__ = ["PMBuilder", "leg_type_of"]


def _floats(v) -> list:
    """A 3-vector as a list of Python floats (finite, within the model files' bound), or an
    InputError."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError, OverflowError):
        a = None
    if a is None or a.shape != (3,) or not np.all(np.abs(a) <= MAX_MAGNITUDE):
        raise InputError(f"expected 3 finite numbers within +-{MAX_MAGNITUDE:g}, got "
                         f"{shorten(v)}")
    return [float(x) for x in a]


def _mapping(value, what: str) -> dict:
    """``value`` as a dict (a mapping of a model file's ``what:`` block), else InputError."""
    if not isinstance(value, Mapping):
        raise InputError(f"set_{what}: expected a mapping (as a model file's '{what}:' block), "
                         f"got {type(value).__name__}")
    return dict(value)


def _frame(frame):
    """``(R (3, 3), p (3,))`` of a placement: ``(R, p)``, a 4 x 4 matrix, or an object with
    ``rotation`` and ``translation`` (``pinocchio.SE3``)."""
    if frame is None:
        return np.eye(3), np.zeros(3)
    shape = ("frame must be (R, p), a 4 x 4 homogeneous matrix or an object with rotation "
             "and translation (pinocchio.SE3)")
    try:
        if hasattr(frame, "rotation") and hasattr(frame, "translation"):
            R, p = np.asarray(frame.rotation, float), np.asarray(frame.translation, float)
        elif isinstance(frame, (tuple, list)) and len(frame) == 2:
            R, p = np.asarray(frame[0], float), np.asarray(frame[1], float)
        else:
            M = np.asarray(frame, float)
            if M.shape != (4, 4) or not np.allclose(M[3], [0, 0, 0, 1]):
                raise InputError(shape)
            R, p = M[:3, :3], M[:3, 3]
    except InputError:
        raise
    except (TypeError, ValueError):
        raise InputError(f"{shape}, of numbers; got {str(frame)[:60]!r}") from None
    if R.shape != (3, 3) or p.reshape(-1).shape != (3,) or not np.all(np.isfinite(R)) or \
            not np.all(np.isfinite(p)) or \
            not np.allclose(R.T @ R, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise InputError("frame: the rotation must be a proper 3 x 3 rotation matrix and the "
                         "translation 3 finite numbers")
    return R, p.reshape(3)


def leg_type_of(leg: Leg, name: str | None = None) -> dict:
    """A leg-type mapping (as a model file's ``legs:`` holds it) of a placed leg: one literal
    rule per letter, its points and directions in the base frame (``{base: [x, y, z]}``), the
    string with its actuation marker and H pitches, so that the leg type builds this very
    leg wherever it is placed."""
    if not isinstance(leg, Leg):
        raise InputError(f"expected a screwkit Leg, got {type(leg).__name__}")
    by_pos: dict[int, list] = {}
    for j in leg.joints:
        by_pos.setdefault(j.spec.position, []).append(j)
    rules: list[dict[str, Any]] = []
    for pos, letter in enumerate(leg.string.letters, start=1):
        js = by_pos[pos]
        at = {"base": _floats(js[0].point)}
        if letter == "Pa":
            j = js[0]
            rules.append({"axis": {"base": _floats(j.hinge)}, "at": at,
                          "to": {"base": _floats(j.point + j.bar)}})
        elif letter in ("U", "S"):
            rules.append({"at": at, "axes": [{"base": _floats(j.direction)} for j in js]})
        else:                                      # R, P, H, C (coaxial P and R)
            rules.append({"axis": {"base": _floats(js[0].direction)}, "at": at})
    return {"name": name or leg.name, "string": leg.string.marked, "joints": rules}


def _pm_string(entries) -> str:
    """``3UPS+UP/passive``: consecutive legs of one string and passivity as one term."""
    terms: list[list] = []
    for text, passive in entries:
        if terms and terms[-1][1] == text and terms[-1][2] == passive:
            terms[-1][0] += 1
        else:
            terms.append([1, text, passive])
    return "+".join((str(c) if c > 1 else "") + t + (PASSIVE_SUFFIX if p else "")
                    for c, t, p in terms)


class PMBuilder:
    """A PM assembled in Python, leg by leg (see the module docstring).

    Parameters
    ----------
    name : str
        The model's name.
    units : mapping, optional
        ``{"length": "mm", "force": "N"}`` (the units of every number given; default: none
        declared).
    summary, source, note : str
        Words kept with the model.

    Notes
    -----
    Every method but :meth:`build` and :meth:`to_mapping` returns the builder, so calls
    chain: ``PMBuilder("p").add_leg(...).add_leg(...).set_pose(...).build()``.
    """

    def __init__(self, name: str, *, units: Mapping[str, str] | None = None,
                 summary: str = "", source: str = "", note: str = "") -> None:
        if not isinstance(name, str) or not name.strip() or len(name) > MAX_NAME:
            raise InputError(f"a PM name is a non-empty text of at most {MAX_NAME} characters")
        self.name = name.strip()
        self._legs: list[dict] = []
        self._fields: dict[str, Any] = {}
        if units is not None:
            if not isinstance(units, Mapping):
                raise InputError(f"units must be a mapping such as {{'length': 'mm', 'force': "
                                 f"'N'}}, got {shorten(units)}")
            self._fields["units"] = dict(units)
        for k, v in (("summary", summary), ("source", source), ("note", note)):
            if v:
                self._fields[k] = str(v)

    # -- legs ---------------------------------------------------------------------------
    def add_leg(self, leg: str | Mapping[str, Any] | Leg | Any, base: ArrayLike | None = None,
                platform: ArrayLike | None = None, *, passive: bool = False,
                axes: Mapping[str, Any] | None = None, frame: Any = None) -> "PMBuilder":
        """Add a leg.

        Parameters
        ----------
        leg : str, LegSpec, mapping or Leg
            A leg type (catalog name, :class:`~screwkit.pm.LegSpec`, or a leg-type mapping
            with ``name``, ``string``, ``joints`` ...), or a placed :class:`~screwkit.legs.Leg`.
        base : array_like (3,), optional
            The base attachment ``A_i`` in the base frame (model lengths).  Required for a
            leg type; for a placed leg, default its ``A`` (moved by ``frame``).
        platform : array_like (3,), optional
            The platform attachment ``a_i`` in the platform frame.  Required for a leg type;
            for a placed leg, default its ``a`` (moved by ``frame``) seen from the platform
            at home.
        passive : bool
            A leg without an actuator (:attr:`~screwkit.pm.PMModel.passive`).
        axes : mapping, optional
            For a leg type: joint axes replaced at this vertex, as a model file's ``axes:``.
        frame : optional
            For a placed leg: where its coordinates are, in the base frame (module docstring).
        """
        if len(self._legs) >= MAX_LEGS:
            raise InputError(f"a PM has at most {MAX_LEGS} legs")
        if not isinstance(passive, bool):
            raise InputError(f"passive must be True or False, got {shorten(passive)}")
        entry: dict[str, Any] = {}
        if isinstance(leg, Leg):
            if axes is not None:
                raise InputError("axes= replaces rules of a leg type; a placed leg's axes are "
                                 "its own")
            R, p = _frame(frame)
            placed = leg.moved(R, p) if frame is not None else leg
            entry["leg"] = leg_type_of(placed)
            A = _floats(placed.A if base is None else base)
            world_a = None if platform is not None else _floats(placed.a)
            text = placed.string.text
        else:
            if frame is not None:
                raise InputError("frame= places a Leg; a leg type is placed by its rules at "
                                 "base= and platform=")
            if base is None or platform is None:
                raise InputError("a leg type needs its attachments: base= (A_i, base frame) "
                                 "and platform= (a_i, platform frame)")
            entry["leg"] = self._leg_type(leg)
            A, world_a = _floats(base), None
            text = parse_leg(entry["leg"]["string"] if isinstance(entry["leg"], dict)
                             else self._string_of(entry["leg"])).text
            if axes is not None:
                entry["axes"] = copy.deepcopy(dict(axes))
        if passive:
            entry["passive"] = True
        self._legs.append({"entry": entry, "A": A, "a": None if platform is None
                           else _floats(platform), "world_a": world_a, "text": text,
                           "passive": passive})
        return self

    @staticmethod
    def _leg_type(leg):
        from ._catalog import LegSpec
        if isinstance(leg, str):
            return leg
        if isinstance(leg, LegSpec):
            if leg.definition is None:
                raise InputError(f"leg type {leg.name}: no definition to write")
            return copy.deepcopy(leg.definition)
        if isinstance(leg, Mapping):
            return copy.deepcopy(dict(leg))
        raise InputError(f"a leg is a leg type (name, LegSpec, mapping) or a placed Leg, got "
                         f"{type(leg).__name__}")

    @staticmethod
    def _string_of(name):
        from ._catalog import default_catalog
        spec = default_catalog().find_leg(name)
        if spec is None:
            raise InputError(f"unknown leg type {shorten(name)} (not in the catalog; give a "
                             "LegSpec or a leg-type mapping)")
        return spec.string.marked

    # -- the pose parametrisation ---------------------------------------------------------
    def set_pose(self, independent: Sequence[str], home: Mapping[str, float], *,
                 default: Mapping[str, float] | None = None,
                 guess: Mapping[str, float] | None = None, order: str = "XYZ",
                 motion: str = "", centre: ArrayLike | None = None,
                 degrees: bool = False) -> "PMBuilder":
        """The platform's pose parametrisation.

        Parameters
        ----------
        independent : sequence of str
            The independent pose parameters (a subset of ``Xo Yo Zo alpha beta gamma``):
            the DOF.
        home : mapping
            Their values at home, where the placed legs are given and the leg types built
            (angles in radians unless ``degrees``, lengths in model units).
        default : mapping, optional
            The default pose (default: home).
        guess : mapping, optional
            Values of dependent parameters at home (default 0; the platform centre's
            height, for instance, when it is dependent).
        order : str
            Euler order (scipy's convention: ``"XYZ"`` intrinsic, ``"xyz"`` extrinsic).
        motion : str
            The stated motion type (``"1T2R"``), checked against the finite motion computed
            from home when the model is loaded (``screwkit.load_pm(builder)``, which also
            assembles the default pose; :meth:`build` alone checks neither).
        centre : array_like (3,), optional
            The base-fixed point ``C`` of the leg rules.
        """
        check_order(order)
        ind = list(independent)
        if not ind or any(p not in PARAMS for p in ind) or len(set(ind)) != len(ind):
            raise InputError(f"independent must be distinct names among {', '.join(PARAMS)}")

        def deg(values, what, names):
            out = {}
            for k, v in dict(values or {}).items():
                if k not in names:
                    raise InputError(f"{what}: {k!r} is not one of {', '.join(names)}")
                x = real(v, f"{what}: {k}", bound=MAX_MAGNITUDE)
                out[k] = x if (k in LENGTH_PARAMS or degrees) else float(np.degrees(x))
            return out

        dep = [p for p in PARAMS if p not in ind]
        self._fields.update({"euler": order, "independent": ind, "dof": len(ind),
                             "home": deg(home, "home", ind),
                             "pose": deg(default if default is not None else home, "default",
                                         ind)})
        g = deg(guess, "guess", dep)
        if g:
            self._fields["guess"] = g
        if motion:
            self._fields["motion"] = str(motion)
        if centre is not None:
            self._fields["centre"] = _floats(centre)
        return self

    def set_limits(self, limits: Mapping[str, Any]) -> "PMBuilder":
        """The ``limits:`` block (joints, actuators, extensions, leg distances)."""
        self._fields["limits"] = copy.deepcopy(_mapping(limits, "limits"))
        return self

    def set_dynamics(self, dynamics: Mapping[str, Any]) -> "PMBuilder":
        """The ``dynamics:`` block (masses, inertias, friction, gravity, stiffness)."""
        self._fields["dynamics"] = copy.deepcopy(_mapping(dynamics, "dynamics"))
        return self

    def set_workload(self, workload: Mapping[str, Any]) -> "PMBuilder":
        """The ``workload:`` block: the default workload at ``o`` with its units
        (``{"force": [..], "torque": [..], "units": {"force": "N", "length": "m"}}``)."""
        self._fields["workload"] = copy.deepcopy(_mapping(workload, "workload"))
        return self

    # -- output ---------------------------------------------------------------------------
    def _home_platform(self):
        f = self._fields
        home = {p: 0.0 for p in PARAMS}
        home.update(f.get("guess", {}))
        home.update(f.get("home", {}))
        ang = [home[p] for p in ("alpha", "beta", "gamma")]
        R = rotation_matrix(f.get("euler", "XYZ"), *np.radians(ang))
        return R, np.array([home["Xo"], home["Yo"], home["Zo"]], float)

    def to_mapping(self) -> dict:
        """The PM's mapping, as a model file holds it under ``pms:`` (leg types of placed
        legs written inline)."""
        if not self._legs:
            raise InputError(f"{self.name}: no leg added (add_leg)")
        if "independent" not in self._fields:
            raise InputError(f"{self.name}: no pose parametrisation (set_pose)")
        R, o = self._home_platform()
        plat = []
        for lg in self._legs:
            if lg["a"] is not None:
                plat.append(lg["a"])
            else:                     # the placed leg's a, seen from the platform at home
                plat.append(_floats(R.T @ (np.asarray(lg["world_a"]) - o)))
        out: dict[str, Any] = {
            "string": _pm_string([(lg["text"], lg["passive"]) for lg in self._legs])}
        for k in ("summary", "source", "note", "units"):
            if k in self._fields:
                out[k] = copy.deepcopy(self._fields[k])
        out["base"] = {"points": [lg["A"] for lg in self._legs]}
        out["platform"] = {"points": plat}
        out["legs"] = [lg["entry"]["leg"] if list(lg["entry"]) == ["leg"] and
                       isinstance(lg["entry"]["leg"], str) else lg["entry"] for lg in self._legs]
        for k in ("centre", "euler", "independent", "home", "pose", "guess", "dof", "motion",
                  "limits", "dynamics", "workload"):
            if k in self._fields:
                out[k] = copy.deepcopy(self._fields[k])
        return copy.deepcopy(out)

    def build(self, catalog: Any = None) -> PMModel:
        """The frozen model, read from :meth:`to_mapping` by the loader of model files.

        It is checked as a file is (the same :class:`~screwkit.errors.CatalogError`); that
        its default pose assembles is checked by :func:`screwkit.load_pm` (``load_pm(b)``
        takes a builder) and by every solve.
        """
        from ._loader import load_pm
        return load_pm(self.to_mapping(), catalog=catalog, name=self.name)
