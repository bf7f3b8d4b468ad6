"""The ``bars:`` key of a leg in the ``dynamics:`` block: the bars of its parallelograms.

A parallelogram ``Pa`` is one equivalent joint (its first hinge axis through ``p``, its bar
vector ``b``, its translation direction ``d_0 = h x b / |b|`` at home); its two real bars
are parallel to ``b``, in the four-bar's plane (normal to the hinges ``h``), each hinged on
the near link at ``p + o d_0`` and on the far link at ``p + o d_0 + b``::

    legs:
      links:
        R2: {mass: 0.3, com: 0.25}           # the arm, up to the near hinges
        Pa3: {mass: 0.02, com: [..]}         # the far link (between the bars' far ends)
      bars:                                  # by the Pa's name: each of its two bars
        Pa3:
          mass: 0.05                         # each bar
          width: 40                          # the bars at -20 and +20 along d_0 from the
                                             # Pa's bar line; or offsets: [o1, o2]
          com: 0.5                           # fraction along the bar from its near hinge
          inertia: {rod: 180}                # about the com: {rod: l}, {cylinder: {length,
                                             # radius}} along the bar, moments or a 3x3
                                             # matrix in the base axes at home

The bodies are kept like the links' (base frame at home, model units): see
:class:`~screwkit.pm.BarPair`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BAR_KEYS", "read_bars"]

#: The keys of one parallelogram's ``bars:`` entry.
BAR_KEYS = ("mass", "com", "inertia", "width", "offsets")


def read_bars(v, fld, r, leg, inertia_of) -> tuple:
    """The :class:`~screwkit.pm.BarPair` of every parallelogram named in ``v``.

    Parameters
    ----------
    v : mapping
        ``{Pa name: {mass, width | offsets, com, inertia}}`` (module docstring).
    fld : str
        Where ``v`` is in the block (``legs[1].bars``), for messages.
    r : the block's reader (numbers in the model's units, errors naming the field)
    leg : Leg
        The leg at home, base frame.
    inertia_of : callable
        ``inertia_of(spec, fld, r, mass, axis=...)``: an inertia about the centre of mass
        (the block's inertia syntax).
    """
    from ._inertia import BarPair, Body

    pas = {j.name: k for k, j in enumerate(leg.joints) if j.spec.parallelogram}
    if not pas:
        raise r.err(f"leg {leg.name} has no parallelogram Pa (bars: gives a Pa's bars)", fld)
    r.mapping(v, fld, tuple(pas))
    out = []
    for name, spec in v.items():
        f = f"{fld}.{name}"
        j = leg.joints[pas[name]]
        s = r.mapping(spec, f, BAR_KEYS, ("mass",))
        if ("width" in s) == ("offsets" in s):
            raise r.err("give the bars' places: width (the bars at -width/2 and +width/2 "
                        "from the Pa's bar line) or offsets: [o1, o2], not both", f)
        m = r.num(s["mass"], f"{f}.mass", mass=1, positive=True)
        if "width" in s:
            w = r.num(s["width"], f"{f}.width", length=1, positive=True)
            if not w > 0:
                raise r.err("must be positive (the distance between the two bars)", f"{f}.width")
            offsets = (-0.5 * w, 0.5 * w)
        else:
            o = s["offsets"]
            if not (isinstance(o, (list, tuple)) and len(o) == 2):
                raise r.err("must be a list of 2 numbers (each bar's offset along the Pa's "
                            "translation direction)", f"{f}.offsets")
            offsets = tuple(r.num(x, f"{f}.offsets[{k}]", length=1) for k, x in enumerate(o))
            if offsets[0] == offsets[1]:
                raise r.err("the two bars are on one line: give two different offsets",
                            f"{f}.offsets")
        frac = r.num(s.get("com", 0.5), f"{f}.com")
        if not 0.0 <= frac <= 1.0:
            raise r.err(f"must be a fraction of the bar in [0, 1] from its near hinge, got "
                        f"{frac:g}", f"{f}.com")
        b = np.asarray(j.bar, float)
        inertia = inertia_of(s.get("inertia"), f"{f}.inertia", r, m,
                             axis=b / np.linalg.norm(b))
        p, d0 = np.asarray(j.point, float), np.asarray(j.direction, float)
        bodies = tuple(Body(m, p + o * d0 + frac * b, inertia, f"{name} bar {k + 1}")
                       for k, o in enumerate(offsets))
        out.append(BarPair(pas[name], offsets, bodies))
    return tuple(sorted(out, key=lambda x: x.slot))
