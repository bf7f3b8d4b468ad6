"""The decorators of the kernels, and borrowed views (private).

``inner`` for functions called only from other kernels (no CPython or C wrapper is built:
a large part of the compile time of functions taking tuples of arrays), ``borrowing`` for
such a function that only borrows arrays (no reference counting), ``borrowing_inlined`` for
one LLVM always inlines into its callers, ``entry`` for the ones Python calls, ``parallel``
for the ``prange`` drivers (both without the GIL), ``inlined`` for a function inlined into its
one caller.
Division follows numpy's error model (no Python exception branch on every division).
:func:`choose` is ``a if c else b`` as one ``select``: numba makes branches of a conditional
expression, and some lane loops with them stayed scalar.

No fast-math flag, not even ``contract``: with it LLVM may fuse a multiply and an add into
one FMA (one rounding instead of two), and which pairs it fuses depends on the IR it is
given, which depends on how the kernel was built: compiled in this process with its callees
or loaded from the on-disk cache, inlined into the serial or the ``prange`` driver.  A
freshly compiled kernel then differed in the last bits from the cached one (a Dask worker's
map from the serial map).  Strict IEEE arithmetic makes every result a function of the
inputs alone, however and wherever the kernel was compiled.

:func:`borrowed` gives views without a reference count. numba counts references to an
array's buffer atomically, and every kernel call taking the model tuple (22 arrays) or a
workspace tuple takes and drops one per array (16 % of the samples of a profile of the
analysis kernel), and, since the views of a packed tuple share one count, a cache line
bounced between the threads. The kernels never keep or return these views, and their owners
(the arrays Python passed, a range's workspace) outlive every use, so the count is not
needed.
"""

import functools
import threading

from numba import config, njit, types
from numba.core import cgutils, errors
from numba.core.caching import FunctionCache
from numba.core.registry import CPUDispatcher
from numba.extending import intrinsic

_OPTIONS = dict(cache=True, error_model="numpy")


class _Inner(CPUDispatcher):
    """A dispatcher compiled once per argument type, not once per constant: a call with a
    literal (``f(M, 0)``, ``g(x, True)``) uses the version for the argument's type (int64,
    bool), compiled for any other call too.  numba otherwise compiles a version for every
    literal value at a call site (a model tuple's 21 unpacking calls, ``forward`` at leg 0
    and at leg ``b``...), each with everything it calls: a first compile's time, for code
    the same up to the constant (which LLVM still folds where it inlines).  A function that
    needs its literal (typing fails without it) gets it, as before."""

    def get_call_template(self, args, kws):
        plain = tuple(types.unliteral(a) for a in args)
        if plain != tuple(args):
            try:
                return super().get_call_template(plain, kws)
            except errors.TypingError:
                pass
        return super().get_call_template(args, kws)


class _Deferred:
    """A kernel's dispatcher whose numba state is made on its first use: a dispatcher (an
    instance of its class, its ``py_func`` and name set) that runs numba's ``__init__`` on
    itself the first time an attribute it lacks is read (a compile, a cache lookup, numba's
    typing of a call to it), then becomes an instance of the class it stands for.

    Making a dispatcher costs numba some 0.4 ms (the function's signature read twice, its
    cache located and the cache folder tested for writing with a temporary file), and the
    kernel modules hold some 200 that Python never calls (``inner``, ``borrowing``,
    ``borrowing_inlined``, ``inlined``): a process that loads its entry points from the cache
    never needs them (nothing is compiled against them), and a cold command made them all
    (about 70 ms).  ``spec``: the plain class, the key of the template dispatcher whose
    options it takes (:func:`_template`), and the hooks to call on the made dispatcher
    (:func:`when_made`)."""

    def __getattr__(self, name):
        # (only for attributes the object lacks: while its numba state is unmade, most)
        return object.__getattribute__(made(self), name)

    # numba's ``compile`` and a call from Python read the C dispatcher's state first, which
    # its class gives before the dispatcher is made (``_can_compile`` False: "compilation
    # disabled"), so no attribute is missed: both make it first.  (The class's own method
    # then, not the attribute: the kernels' locks wrap a dispatcher's bound ``compile`` in
    # an attribute of its own, this one where it was still unmade.)
    def compile(self, sig):
        return type(made(self)).compile(self, sig)

    def __call__(self, *args, **kws):
        return type(made(self)).__call__(self, *args, **kws)


class _DeferredInner(_Deferred, _Inner):
    pass


class _DeferredCPU(_Deferred, CPUDispatcher):
    pass


#: Held while a deferred dispatcher is made (another thread's first read waits for it).
_MAKING = threading.RLock()
#: One real dispatcher per set of options, made on first need: the options numba gives
#: the dispatchers of ``njit(**options)`` (:func:`_template`).
_TEMPLATES: dict = {}


def _template_function():       # (a function of this file: numba caches its dispatcher)
    pass


def _template(key):
    """A dispatcher numba makes for ``njit(**dict(key))``: its target options, locals and
    compiler pipeline are those of every kernel decorated with the same options."""
    t = _TEMPLATES.get(key)
    if t is None:
        t = _TEMPLATES[key] = njit(**dict(key))(_template_function)
    return t


def _make(d, cls, key, hooks):
    """Make the deferred dispatcher ``d`` what ``njit(**dict(key))(d.py_func)`` makes, of
    class ``cls``, then call ``hooks`` on it."""
    t = _template(key)
    CPUDispatcher.__init__(d, d.py_func, locals=dict(t.locals),
                           targetoptions=dict(t.targetoptions),
                           pipeline_class=t._compiler.pipeline_class)
    if isinstance(t._cache, FunctionCache):
        d.enable_caching()
    d.__class__ = cls
    for hook in hooks:
        hook(d)


def _deferred(fn, cls, options):
    """``njit(**options)(fn)`` as a dispatcher of class ``cls``, made on first use."""
    if config.DISABLE_JIT:                      # (numba's own: the Python function)
        return njit(**options)(fn)
    kind = _DeferredInner if cls is _Inner else _DeferredCPU
    d = kind.__new__(kind)
    functools.update_wrapper(d, fn)
    d.py_func = fn
    d._deferred = (cls, tuple(sorted(options.items())), [])
    return d


def made(d):
    """``d``, a deferred dispatcher made now if it was not yet (any other dispatcher as it
    is)."""
    with _MAKING:
        spec = getattr(d, "__dict__", {}).pop("_deferred", None)
        if spec is not None:
            _make(d, *spec)
    return d


def is_deferred(d) -> bool:
    """Whether ``d`` is a deferred dispatcher whose numba state is not made yet."""
    return "_deferred" in getattr(d, "__dict__", {})


def when_made(d, hook) -> None:
    """``hook(d)`` once the dispatcher ``d`` has its numba state: now, or when it is made."""
    with _MAKING:
        spec = d.__dict__.get("_deferred")
        if spec is not None:
            spec[2].append(hook)
            return
    hook(d)


def _inner(fn, nrt=True, always_inline=False):
    # both flags given explicitly: numba otherwise lets a callee compiled for the first time
    # inside a caller inherit the caller's, and the code of a kernel would depend on which
    # caller happened to compile it first
    return _deferred(fn, _Inner, dict(no_cpython_wrapper=True, no_cfunc_wrapper=True,
                                      _nrt=nrt, forceinline=always_inline, **_OPTIONS))


inner = _inner


def borrowing(fn):
    """:func:`inner` for a kernel that only borrows arrays: it allocates none, returns none
    and calls no kernel that returns one (views of its arguments are fine), so that it needs
    no reference counting and is compiled without (numba's ``_nrt=False``).  numba otherwise
    takes and drops a reference to every array argument of every call, through a call of
    ``NRT_incref`` / ``NRT_decref`` each (not inlined, made even for the null counts of
    borrowed views): a kernel taking the model and rows workspace tuples (36 arrays) pays
    about 70 such calls a call.  A kernel that allocates does not compile this way; one that
    returned an array would hand out a reference it never took."""
    return _inner(fn, nrt=False)


def borrowing_inlined(fn):
    """:func:`borrowing`, and always inlined by LLVM into its callers (numba's
    ``forceinline``): for a kernel taking the model and workspace tuples on the hot path.  A
    call passes every array of its tuples as separate scalars on the stack (pointer, shape,
    strides...: about 340 words for the model and the rows workspace), which costs more than
    the arithmetic of a small kernel; inlined, the views are registers or constant offsets
    of the caller's.  The arithmetic is the same, operation for operation (no fast-math).
    Each caller gets a copy of the code: for kernels on the per-pose path with few callers."""
    return _inner(fn, nrt=False, always_inline=True)


#: Kernels Python calls release the GIL while they run: another Python thread of the process
#: works meanwhile (a map's numpy work on one block while the kernels solve the next).
entry = njit(nogil=True, **_OPTIONS)
parallel = njit(parallel=True, nogil=True, **_OPTIONS)
#: A function with a single caller that takes many tuples of arrays (the pose driver): its body
#: typed into the caller (numba's IR inlining).  A call passes every array of its tuples as
#: separate scalars (pointer, shape, strides...): the driver's hundred-odd arrays cost about
#: 1 us a pose, as much as a forward-kinematics pass.  It also compiles less: numba optimises
#: and generates the machine code of every compiled function with all it calls linked in, so
#: a large callee of one caller compiled on its own (``inner``) has its whole subtree compiled
#: once for itself and once more in its caller (the drivers' loops and the block's Newton,
#: typed into their callers: a first run 72 s of CPU instead of 80-90 s, the parallel kernel
#: 100 s instead of 126 s).  A function with several callers stays ``inner`` or ``borrowing``
#: (compiled once, called), else every call site would type and optimise it again.
def inlined(fn):
    return _deferred(fn, CPUDispatcher, dict(inline="always", no_cpython_wrapper=True,
                                             no_cfunc_wrapper=True, **_OPTIONS))


def _unowned(context, builder, ty, value):
    ary = context.make_array(ty)(context, builder, value=value)
    ary.meminfo = cgutils.get_null_value(ary.meminfo.type)
    ary.parent = cgutils.get_null_value(ary.parent.type)
    return ary._getvalue()


@intrinsic
def borrowed(typingctx, x):
    """``x`` (an array or a tuple of arrays) as views of the same data without a reference
    count: valid only while ``x``'s owner lives, never to be kept or returned to Python."""
    if isinstance(x, types.Array):
        def codegen(context, builder, sig, args):
            return _unowned(context, builder, x, args[0])
        return x(x), codegen
    if isinstance(x, types.BaseTuple) and all(isinstance(t, types.Array) for t in x):
        def codegen(context, builder, sig, args):
            out = args[0]
            for k, t in enumerate(x):
                v = builder.extract_value(args[0], k)
                out = builder.insert_value(out, _unowned(context, builder, t, v), k)
            return out
        return x(x), codegen
    return None


@intrinsic
def one_lane(typingctx, x):
    """``x`` (an array) as a block of one lane: the same data with a trailing axis of length
    one (``(..., 1)``), borrowed like :func:`borrowed` (no reference count).  The block
    kernels take their per-lane quantities with the lane axis last; a caller of one pose
    passes its own arrays through this view, so that one pose and a block run the same code.
    As with :func:`borrowed`, ``x``'s owner must outlive the view: numba frees a local array
    after its last use, so an array allocated in a kernel and used only through this view
    may be freed before the view is read (allocate it with its lane axis instead)."""
    if not isinstance(x, types.Array):
        return None
    out = types.Array(x.dtype, x.ndim + 1, "C" if x.layout == "C" else "A")

    def codegen(context, builder, sig, args):
        src = context.make_array(x)(context, builder, value=args[0])
        dst = context.make_array(out)(context, builder)
        shape = cgutils.unpack_tuple(builder, src.shape, x.ndim)
        strides = cgutils.unpack_tuple(builder, src.strides, x.ndim)
        one = context.get_constant(types.intp, 1)
        context.populate_array(dst, data=src.data, shape=shape + [one],
                               strides=strides + [src.itemsize], itemsize=src.itemsize,
                               meminfo=cgutils.get_null_value(dst.meminfo.type))
        return dst._getvalue()
    return out(x), codegen


@intrinsic
def flat(typingctx, x):
    """A C-contiguous array ``x`` as a one-dimensional view of all its elements, borrowed
    like :func:`borrowed`.  A lane loop indexes it as ``f[c * ls + k]`` with a lane stride
    ``ls`` known when LLVM optimises the loop: the entries a loop reads and writes are then
    at constant distances from one base pointer, so that LLVM checks one range per array
    instead of one per entry (with a row view per entry, a loop over a leg's rotation,
    translation and axes needs more run-time alias checks than LLVM allows, and stays
    scalar)."""
    if not isinstance(x, types.Array) or x.layout != "C":
        return None
    out = types.Array(x.dtype, 1, "C")

    def codegen(context, builder, sig, args):
        src = context.make_array(x)(context, builder, value=args[0])
        dst = context.make_array(out)(context, builder)
        size = context.get_constant(types.intp, 1)
        for n in cgutils.unpack_tuple(builder, src.shape, x.ndim):
            size = builder.mul(size, n)
        context.populate_array(dst, data=src.data, shape=[size], strides=[src.itemsize],
                               itemsize=src.itemsize,
                               meminfo=cgutils.get_null_value(dst.meminfo.type))
        return dst._getvalue()
    return out(x), codegen


@intrinsic
def lanes(typingctx, x):
    """A pointer to the first element of the C-contiguous array ``x``: what :func:`flat`
    gives, indexed without numba's wraparound of negative indices.  A lane loop indexes it
    ``p[base + k]``: where ``base`` is a run-time offset (a leg's, a joint's) LLVM cannot
    prove it non-negative, and the wraparound's select kept the address out of its reach
    ("cannot identify array bounds": the loop stayed scalar).  No bounds, no reference
    count: ``x``'s owner must outlive every use, and the offsets must stay inside ``x``."""
    if not isinstance(x, types.Array) or x.layout != "C":
        return None
    out = types.CPointer(x.dtype)

    def codegen(context, builder, sig, args):
        return context.make_array(x)(context, builder, value=args[0]).data
    return out(x), codegen


def _prefetch(write, name):
    """The typing and code of an intrinsic ``name(x, i)``: a prefetch of element ``i`` of
    the C-contiguous array ``x``, for a store where ``write`` (1), else for a load."""
    def typer(typingctx, x, i):
        if not (isinstance(x, types.Array) and x.layout == "C"
                and isinstance(i, types.Integer)):
            return None

        def codegen(context, builder, sig, args):
            from llvmlite import ir
            ary = context.make_array(sig.args[0])(context, builder, args[0])
            at = builder.gep(ary.data, [context.cast(builder, args[1], sig.args[1],
                                                     types.intp)])
            i8p, i32 = ir.IntType(8).as_pointer(), ir.IntType(32)
            # (named by llvmlite for the pointer type: llvm.prefetch.p0i8, which LLVMs with
            # opaque pointers take as llvm.prefetch.p0)
            fn = builder.module.declare_intrinsic(
                "llvm.prefetch", [i8p], ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]))
            # (read or write, keep in every cache level, data)
            builder.call(fn, [builder.bitcast(at, i8p), ir.Constant(i32, write),
                              ir.Constant(i32, 3), ir.Constant(i32, 1)])
            return context.get_dummy_value()
        return types.void(x, i), codegen
    typer.__name__ = typer.__qualname__ = name
    return typer


#: ``prefetch_read(x, i)``, ``prefetch_write(x, i)``: ask the processor for the cache line
#: of element ``i`` (flat, C order) of the C-contiguous array ``x``, to be read or written
#: soon; a hint (no fault, no result; ``i`` is not checked).  A launch's rows scattered over
#: a path's outputs miss the cache one sample after the other: fetched while the block
#: before computes, they do not wait.
prefetch_read = intrinsic(_prefetch(0, "prefetch_read"))
prefetch_write = intrinsic(_prefetch(1, "prefetch_write"))


@intrinsic
def choose(typingctx, cond, a, b):
    """``a if cond else b`` as one LLVM ``select``: the same value, without the branches
    numba makes of a conditional expression.  In a lane loop those branches kept LLVM from
    vectorising some loops (it would not make a select of them where a store depends on
    them: one scalar, branchy lane at a time); a ``select`` it vectorises as a blend."""
    if not isinstance(cond, types.Boolean):
        return None
    numbers = (types.Float, types.Integer)
    if not (isinstance(a, numbers) and isinstance(b, numbers)):
        return None
    ty = typingctx.unify_types(a, b)
    if ty is None:
        return None

    def codegen(context, builder, sig, args):
        x = context.cast(builder, args[1], sig.args[1], ty)
        y = context.cast(builder, args[2], sig.args[2], ty)
        return builder.select(args[0], x, y)
    return ty(cond, a, b), codegen
