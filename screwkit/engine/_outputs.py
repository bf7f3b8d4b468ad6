"""The analysis kernel's outputs as arrays by name: views of its packed buffers (private).

A launch of the analysis kernel (:func:`._launch.run_poses`) fills a float and an integer
buffer laid out by its plan (:func:`._launch._plan`); here those buffers become the outputs
by name (:data:`OUTPUTS`): views of N poses' rows (:func:`views_of`), one pose's outputs as
fields of two records (:class:`OnePose`, cheaper for the 25 arrays of a warm pose), and the
buffers of a chunked analysis or a path that launches fill in place (:class:`OutputBuffers`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["OUTPUTS", "OUT_KINDS", "OnePose", "OutputBuffers", "rows_of", "views_of"]

#: The outputs of the analysis kernel, in its order (``_kernels._layout.OUT_*``).
OUTPUTS = ("X", "residual", "iterations", "how", "singular_beta", "J", "scale", "rows_ok",
           "structure_ok", "centre", "length", "singular_values", "rank", "condition_number",
           "constraint_rank", "constraint_condition_number", "values", "equilibrium",
           "amplification", "det_sign", "twists", "lines", "platform", "excess",
           "reversed_mask")
OUT_KINDS = ("f", "f", "i", "i", "b", "f", "f", "b", "b", "f", "f", "f", "i", "f", "i", "f",
             "f", "f", "f", "f", "f", "f", "f", "f", "i")


class OnePose:
    """The outputs of a launch of one pose as fields of two records, one over the float
    buffer and one over the integer buffer (each output of one pose is contiguous in its
    buffer): a field's view costs a third of a slice and a reshape, and one pose's analysis
    takes 25 of them (:func:`views_of` for any N: the same arrays, shapes and values).  The
    outputs of no rows are new views of an empty array of their shape and dtype."""

    __slots__ = ("f", "i", "items")

    def __init__(self, layout, nf: int, ni: int):
        fields = {False: ([], [], []), True: ([], [], [])}
        self.items = []
        for name, (is_int, is_bool, o0, o1, sh) in zip(OUTPUTS, layout):
            if o1 == o0:
                self.items.append((name, 3, np.empty(sh or (0,), bool if is_bool else
                                                     np.int64 if is_int else float)))
                continue
            names, formats, offsets = fields[is_int]
            names.append(name)
            formats.append(("i8" if is_int else "f8", () if sh is None else sh[1:]))
            offsets.append(8 * o0)
            self.items.append((name, 2 if is_bool else int(is_int), None))
        self.f, self.i = (np.dtype({"names": fields[k][0], "formats": fields[k][1],
                                    "offsets": fields[k][2], "itemsize": 8 * size})
                          for k, size in ((False, nf), (True, ni)))

    def views(self, f, i) -> dict:
        """The outputs by name of the float and integer buffers ``f``, ``i`` of one pose."""
        rf, ri = np.frombuffer(f, self.f), np.frombuffer(i, self.i)
        out = {}
        for name, kind, empty in self.items:
            if kind == 0:
                out[name] = rf[name]
            elif kind == 1:
                out[name] = ri[name]
            elif kind == 2:
                out[name] = ri[name].astype(bool)
            else:
                out[name] = empty.view()
        return out


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
