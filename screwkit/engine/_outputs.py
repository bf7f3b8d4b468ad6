"""The analysis kernel's outputs as arrays by name: views of its packed buffers (private).

A launch of the analysis kernel (:func:`._launch.run_poses`) fills a float and an integer
buffer laid out by its plan (:func:`._launch._plan`); here those buffers become the outputs
by name (:data:`OUTPUTS`): views of N poses' rows (:func:`views_of`), one pose's outputs as
fields of two records (:class:`OnePose`, cheaper for the 25 arrays of a warm pose), and the
buffers of a chunked analysis or a path that launches fill in place (:class:`OutputBuffers`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["FROZEN", "OUTPUTS", "OUT_KINDS", "OnePose", "OutputBuffers", "owned", "rows_of",
           "views_of"]

#: The outputs of the analysis kernel, in its order (``_kernels._layout.OUT_*``).
OUTPUTS = ("X", "residual", "iterations", "how", "singular_beta", "J", "scale", "rows_ok",
           "structure_ok", "centre", "length", "singular_values", "rank", "condition_number",
           "constraint_rank", "constraint_condition_number", "values", "equilibrium",
           "amplification", "det_sign", "twists", "lines", "platform", "excess",
           "reversed_mask")
OUT_KINDS = ("f", "f", "i", "i", "b", "f", "f", "b", "b", "f", "f", "f", "i", "f", "i", "f",
             "f", "f", "f", "f", "f", "f", "f", "f", "i")
#: The outputs a one-pose analysis hands out read-only (``JacobianResult``'s matrix, scale
#: and conditioning, ``StaticsResult``'s values, equilibrium residuals and amplification):
#: :meth:`OnePose.views` can give them read-only from the start.
FROZEN = frozenset(("J", "scale", "centre", "length", "singular_values", "rank",
                    "condition_number", "constraint_rank", "constraint_condition_number",
                    "values", "equilibrium", "amplification"))


class OnePose:
    """The outputs of a launch of one pose as fields of records over the float and the
    integer buffer (each output of one pose is contiguous in its buffer): a field's view
    costs a third of a slice and a reshape, and one pose's analysis takes 25 of them
    (:func:`views_of` for any N: the same arrays, shapes and values).  The outputs a
    result hands out read-only (:data:`FROZEN`: ``J``, its conditioning and the statics)
    are fields of records of their own, which :meth:`views` can make read-only as a whole:
    one flag a record instead of a read-only view an array (some 10 us of a warm pose's
    analysis, ``_frozen.freeze_fields``).  The outputs of no rows are new views of an empty
    array of their shape and dtype."""

    __slots__ = ("f", "i", "fz", "iz", "items")

    def __init__(self, layout, nf: int, ni: int):
        # (float, integer) x (other, frozen): names, formats, offsets
        fields = {key: ([], [], []) for key in ((0, 0), (0, 1), (1, 0), (1, 1))}
        self.items = []
        for name, (is_int, is_bool, o0, o1, sh) in zip(OUTPUTS, layout):
            if o1 == o0:
                self.items.append((name, 3, np.empty(sh or (0,), bool if is_bool else
                                                     np.int64 if is_int else float)))
                continue
            frozen = int(name in FROZEN and not is_bool)  # (a boolean is a copy: its own)
            names, formats, offsets = fields[int(is_int), frozen]
            names.append(name)
            formats.append(("i8" if is_int else "f8", () if sh is None else sh[1:]))
            offsets.append(8 * o0)
            self.items.append((name, 2 if is_bool else int(is_int) + 4 * frozen, None))
        self.f, self.fz, self.i, self.iz = (
            np.dtype({"names": fields[key][0], "formats": fields[key][1],
                      "offsets": fields[key][2], "itemsize": 8 * size})
            for key, size in (((0, 0), nf), ((0, 1), nf), ((1, 0), ni), ((1, 1), ni)))

    def views(self, f, i, frozen: bool = False) -> dict:
        """The outputs by name of the float and integer buffers ``f``, ``i`` of one pose;
        ``frozen``: those of :data:`FROZEN` read-only (the buffers' writers done)."""
        rf, ri = np.frombuffer(f, self.f), np.frombuffer(i, self.i)
        rz, qz = np.frombuffer(f, self.fz), np.frombuffer(i, self.iz)
        if frozen:
            rz.flags.writeable = qz.flags.writeable = False
        out = {}
        for name, kind, empty in self.items:
            if kind == 0:
                out[name] = rf[name]
            elif kind == 1:
                out[name] = ri[name]
            elif kind == 4:
                out[name] = rz[name]
            elif kind == 5:
                out[name] = qz[name]
            elif kind == 2:
                out[name] = ri[name].astype(bool)
            else:
                out[name] = empty.view()
        return out


def owned(comp):
    """``comp`` (a ``_run.Computed``) with its read-only outputs copied (a one pose's
    :data:`FROZEN`, :meth:`OnePose.views`): where a reversed pose is solved again, its
    relaunch's outputs are written in place (``_run._unreversed``)."""
    def own(a):
        return a.copy() if isinstance(a, np.ndarray) and not a.flags.writeable else a

    new = {k: own(v) for k, v in comp._asdict().items() if isinstance(v, np.ndarray)}
    cond = comp.conditioning
    if cond is not None:
        new["conditioning"] = dataclasses.replace(
            cond, **{f.name: own(getattr(cond, f.name)) for f in dataclasses.fields(cond)})
    return comp._replace(**new)


class OutputBuffers:
    """The analysis kernel's packed outputs of ``N`` poses (:func:`output_buffers`), filled
    by launches on consecutive ranges of the poses (``run_poses(..., out=(buffers, at))``),
    each writing its rows in place: a chunked analysis copies nothing and touches every
    output byte once.  The buffers are recycled memory (:class:`._memory.Recycler`): fresh
    memory costs a page fault a page, on a virtual machine that hands freed memory back to
    its host as much as the kernels' own work on it."""

    __slots__ = ("f", "i", "d", "layout", "N", "kind")

    def arrays(self, convert: bool = True) -> dict:
        """The outputs of all ``N`` poses by name (:data:`OUTPUTS`), views of the buffers
        (the booleans converted: copies; without ``convert``, views of their integers)."""
        return views_of(self.f, self.i, self.layout, convert)


def rows_of(buffers: OutputBuffers, at: int, n: int):
    """The descriptor and layout of rows ``at..at+n`` of ``buffers``' outputs (the arrays of
    no rows left as they are)."""
    d = buffers.d.copy()
    full = d[:, 2] == buffers.N
    per = d[:, 3] * d[:, 4]
    d[full, 1] += at * per[full]
    d[full, 2] = n
    layout = []
    for (is_int, is_bool, o0, o1, sh), f, q in zip(buffers.layout, full, per):
        if f:
            o0, o1 = o0 + at * int(q), o0 + (at + n) * int(q)
            sh = None if sh is None else (n,) + sh[1:]
        layout.append((is_int, is_bool, o0, o1, sh))
    # (read-only as every packed descriptor: numba types a read-only array apart, and a
    # writable one here compiled a second version of each analysis kernel, about a minute)
    d.setflags(write=False)
    return d, layout


def views_of(f, i, layout, convert):
    """The outputs by name (:data:`OUTPUTS`): views of the float and integer buffers ``f``,
    ``i`` as ``layout`` places them (the booleans converted where ``convert``: copies).  (A
    loop, not a function a view: one pose's analysis takes 25 of them.)"""
    out = {}
    for name, (is_int, is_bool, o0, o1, sh) in zip(OUTPUTS, layout):
        v = i[o0:o1] if is_int else f[o0:o1]
        if sh is not None:
            v = v.reshape(sh)
        out[name] = v.astype(bool) if is_bool and convert else v
    return out
