"""What loading a model computes, kept on disk beside the compiled kernels (private): its
finite motion, and whether its default pose assembles (with the notes of that solution).

Classifying a model's finite motion solves its sampled poses and takes rotation vectors
with scipy, whose import alone is a large part of a cold command.  The result is a function
of the model's content and of the code and libraries that compute it, so it is kept in a
file named by a digest of all of them:

* the model: every field of the :class:`~screwkit.pm.PMModel`, walked to the last number
  (exact bytes of arrays, ``repr`` of floats) but ``definition`` (the recipe it was built
  from, which the engine never reads): any change to a leg, a dimension, a pose, a limit
  or a unit gives another digest;
* the code: the source of every module of the layers the computation runs through
  (``errors``, ``screws``, ``legs``, ``pm``, ``engine`` with its kernels), the sampling
  and classification constants as they are at the call, and the versions of Python,
  numpy, numba and scipy.

A model that cannot be walked (an object of a type not listed in :func:`_feed`) is never
kept.  Files are JSON (no code runs when one is read), written atomically, in
``<kernels' cache>/motion/``; a file that cannot be read or does not decode to the same
digest is ignored and recomputed.  ``SCREWKIT_DISK_CACHE=0`` turns the disk off.  A model
file checked again (``screwkit model check``) then computes nothing: neither numba nor
scipy is imported.
"""

from __future__ import annotations

import dataclasses
import hashlib
import importlib
import importlib.util
import json
import os
import sys

import numpy as np

__all__ = ["load", "store", "load_record", "store_record", "model_digest"]

_FORMAT = "screwkit-model-record-2"
_LAYERS = ("screws", "legs", "pm", "engine", os.path.join("engine", "_kernels"))
_MAX_FILES = 512
_CODE: list = []


class _Unhashable(Exception):
    pass


def _enabled() -> bool:
    from ..pm._catalog_cache import disk_cache_enabled
    return disk_cache_enabled()


def _feed(h, x) -> None:
    """Feed ``x`` to the digest ``h``: the type's name, then its content."""
    if x is None or isinstance(x, (bool, int, str)):
        h.update(f"{type(x).__name__}:{x!r};".encode())
    elif isinstance(x, float):
        h.update(f"float:{x!r};".encode())
    elif isinstance(x, np.generic):
        _feed(h, np.asarray(x))
    elif isinstance(x, np.ndarray):
        if x.dtype.hasobject:
            raise _Unhashable(x.dtype)
        a = np.ascontiguousarray(x)
        h.update(f"ndarray:{a.dtype.str}:{a.shape};".encode())
        h.update(a.tobytes())
    elif isinstance(x, (tuple, list)):
        h.update(f"{type(x).__name__}:{len(x)}[".encode())
        for v in x:
            _feed(h, v)
        h.update(b"]")
    elif isinstance(x, dict):
        h.update(f"dict:{len(x)}{{".encode())
        for k, v in x.items():              # in order: the order of a model's dicts is data
            _feed(h, k)
            _feed(h, v)
        h.update(b"}")
    elif isinstance(x, (set, frozenset)):
        h.update(f"{type(x).__name__}:{len(x)}{{".encode())
        for d in sorted(_digest_of(v) for v in x):
            h.update(d.encode())
        h.update(b"}")
    elif dataclasses.is_dataclass(x) and not isinstance(x, type):
        t = type(x)
        h.update(f"{t.__module__}.{t.__qualname__}(".encode())
        for f in dataclasses.fields(x):
            if f.name == "definition" and t.__name__ == "PMModel":
                continue
            h.update(f.name.encode() + b"=")
            _feed(h, getattr(x, f.name))
        h.update(b")")
    elif hasattr(x, "value") and hasattr(type(x), "__members__"):        # an Enum
        h.update(f"{type(x).__qualname__}.{x.name};".encode())
    else:
        raise _Unhashable(type(x))


def _digest_of(x) -> str:
    h = hashlib.sha256()
    _feed(h, x)
    return h.hexdigest()


def _code_stamp() -> str:
    """A digest of the sources and library versions the computation runs through."""
    if not _CODE:
        h = hashlib.sha256(_FORMAT.encode())
        h.update(f"{sys.version};{np.__version__};{installed_version('numba')};"
                 f"{installed_version('scipy')}".encode())
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        files = [os.path.join(root, "errors.py")]
        for layer in _LAYERS:
            folder = os.path.join(root, layer)
            files += [os.path.join(folder, n) for n in sorted(os.listdir(folder))
                      if n.endswith(".py")]
        for path in files:
            with open(path, "rb") as f:
                h.update(os.path.relpath(path, root).encode() + b"\0" + f.read())
        _CODE.append(h.hexdigest())
    return _CODE[0]


def installed_version(name: str) -> str:
    """The installed version of the package ``name`` without importing it: from the name of
    its one ``.dist-info`` folder beside it, else from its metadata (``importlib.metadata``,
    some 30 ms), else from the package.  A command that loads a model whose finite motion is
    kept and computes nothing (``model check`` of a file whose default pose is home) then
    imports neither numba (some 0.2 s) nor scipy."""
    spec = importlib.util.find_spec(name)
    if spec is not None and spec.origin:
        root, prefix = os.path.dirname(os.path.dirname(spec.origin)), name + "-"
        try:
            found = [e[len(prefix):-len(".dist-info")] for e in os.listdir(root)
                     if e.startswith(prefix) and e.endswith(".dist-info")]
        except OSError:
            found = []
        if len(found) == 1:
            return found[0]
    from importlib import metadata
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:       # (no metadata: the package's own)
        if name == "numba":                     # (imported as the kernels import it)
            from ._kernels import _configure
            return _configure().__version__
        return importlib.import_module(name).__version__


def model_digest(model, constants) -> str | None:
    """The file name of ``model``'s finite motion under ``constants`` (the sampling and
    classification constants), or None when the model cannot be walked."""
    h = hashlib.sha256(_code_stamp().encode())
    try:
        _feed(h, tuple(constants))
        _feed(h, model)
    except (_Unhashable, RecursionError):
        return None
    return h.hexdigest()


def _folder() -> str:
    from ._kernels import cache_dir
    return os.path.join(cache_dir(), "motion")


def _encode(fm) -> dict:
    out = {}
    for f in dataclasses.fields(fm):
        v = getattr(fm, f.name)
        if isinstance(v, np.ndarray):
            v = {"array": [float(x) for x in v.ravel()], "shape": list(v.shape),
                 "dtype": v.dtype.str}
        elif isinstance(v, tuple):
            v = {"tuple": list(v)}
        out[f.name] = v
    return out


def _decode(cls, data: dict):
    kw = {}
    for f in dataclasses.fields(cls):
        v = data[f.name]
        if isinstance(v, dict) and "array" in v:
            v = np.array(v["array"], dtype=np.dtype(v["dtype"])).reshape(v["shape"])
        elif isinstance(v, dict) and "tuple" in v:
            v = tuple(v["tuple"])
        kw[f.name] = v
    return cls(**kw)


def _same(a, b) -> bool:
    """Field by field, types included (arrays: dtype, shape and every bit)."""
    for f in dataclasses.fields(b):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if type(x) is not type(y):
            return False
        if isinstance(y, np.ndarray):
            if x.dtype != y.dtype or x.shape != y.shape or x.tobytes() != y.tobytes():
                return False
        elif isinstance(y, tuple):
            if any(type(u) is not type(v) for u, v in zip(x, y)) or x != y:
                return False
        elif x != y and not (isinstance(y, float) and x != x and y != y):
            return False
    return True


def load_record(model, constants):
    """``(digest, record or None)``: the JSON record kept for ``model`` under ``constants``
    (their first item names what it is), if any; ``(None, None)`` where nothing can be kept
    (the disk cache off, a model that cannot be walked)."""
    if not _enabled():
        return None, None
    digest = model_digest(model, constants)
    if digest is None:
        return None, None
    try:
        with open(os.path.join(_folder(), digest + ".json"), encoding="utf-8") as f:
            data = json.load(f)
        if data.get("digest") != digest or not isinstance(data.get("record"), dict):
            return digest, None
        return digest, data["record"]
    except (OSError, ValueError, TypeError, AttributeError):
        return digest, None


def store_record(digest, record: dict) -> None:
    """Keep the JSON ``record`` under ``digest`` (nothing when the folder is not writable)."""
    if digest is None or not _enabled():
        return
    try:
        from ..pm._catalog_cache import keep_file
        keep_file(_folder(), digest + ".json",
                  json.dumps({"digest": digest, "record": record}).encode("utf-8"),
                  _MAX_FILES)
    except (OSError, TypeError, ValueError):
        pass


def load(model, constants):
    """``(digest, FiniteMotion or None)``: the kept finite motion of ``model``, if any."""
    digest, record = load_record(model, ("finite motion",) + tuple(constants))
    if record is None:
        return digest, None
    try:
        from ..pm import FiniteMotion
        return digest, _decode(FiniteMotion, record)
    except (ValueError, KeyError, TypeError, AttributeError):
        return digest, None


def store(digest, fm) -> None:
    """Keep ``fm`` under ``digest`` (nothing when the folder is not writable)."""
    try:
        if not _same(_decode(type(fm), json.loads(json.dumps(_encode(fm)))), fm):
            return                      # a value JSON would not give back exactly
    except (TypeError, ValueError):
        return
    store_record(digest, _encode(fm))
