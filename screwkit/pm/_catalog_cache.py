"""The default catalog, kept parsed on disk (private).

Reading ``legs_catalog.yaml`` strictly (PyYAML's import, the parse, the checks of every node,
the catalog's validation) is a large part of a cold ``screwkit leg``.  The parsed
:class:`~screwkit.pm.Catalog` is a function of the file's bytes, of its path (which its
errors name) and of the code that reads it, so it is kept in a file named by a digest of
all of them: the bytes, the path, the source of every module of ``errors``, ``screws``,
``legs`` and ``pm``, PyYAML's ``__init__.py`` (its version) and the versions of Python and
numpy.  Any edit to the catalog or to that code reads it anew.

The folder is ``screwkit/__pycache__/catalog`` where the package is writable, else
``$XDG_CACHE_HOME/screwkit/catalog`` (``~/.cache/screwkit/catalog``).  A file is written
atomically, only from a catalog read from bytes equal to the ones hashed, and read back only
as a :class:`~screwkit.pm.Catalog`; anything unreadable is ignored and the catalog read
anew.  ``SCREWKIT_DISK_CACHE=0`` turns the disk off (and the finite motions kept by the
engine).
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys

__all__ = ["kept_catalog", "disk_cache_enabled", "cache_folder"]

_FORMAT = b"screwkit-catalog-1"
_LAYERS = ("screws", "legs", "pm")
_MAX_FILES = 64
_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))    # the package
_STAMP: list = []


def disk_cache_enabled() -> bool:
    """Whether parsed catalogs and finite motions are kept on disk (``SCREWKIT_DISK_CACHE``,
    on unless ``0``, ``no`` or ``off``)."""
    return os.environ.get("SCREWKIT_DISK_CACHE", "1").strip().lower() not in ("0", "no", "off")


def cache_folder(name: str) -> str:
    """``screwkit/__pycache__/<name>`` where the package is writable, else the user's cache
    directory's ``screwkit/<name>``."""
    pyc = os.path.join(_ROOT, "__pycache__")
    if os.access(pyc if os.path.isdir(pyc) else _ROOT, os.W_OK):
        return os.path.join(pyc, name)
    return user_cache(name)


def keep_file(folder: str, name: str, data: bytes, max_files: int) -> None:
    """Write ``data`` as ``folder/name`` atomically (a temporary file renamed), the folder
    bounded to ``max_files`` entries (the older half removed when it is full).  OSError
    goes to the caller, whose cache then simply keeps nothing."""
    os.makedirs(folder, exist_ok=True)
    names = [n for n in os.listdir(folder) if not n.endswith(".tmp")]
    if len(names) >= max_files:
        paths = sorted((os.path.join(folder, n) for n in names), key=os.path.getmtime)
        for p in paths[: len(paths) // 2]:
            os.remove(p)
    path = os.path.join(folder, name)
    tmp = os.path.join(folder, f".{name}.{os.getpid()}.tmp")
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def user_cache(name: str) -> str:
    """The user's cache directory's ``screwkit/<name>`` (``%LOCALAPPDATA%`` on Windows,
    ``~/Library/Caches`` on macOS, ``$XDG_CACHE_HOME`` or ``~/.cache`` elsewhere)."""
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA") or os.path.expanduser("~/AppData/Local")
    elif sys.platform == "darwin":
        base = os.path.expanduser("~/Library/Caches")
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache")
    return os.path.join(base, "screwkit", name)


def _stamp() -> bytes:
    if not _STAMP:
        import importlib.util

        import numpy as np
        h = hashlib.sha256(_FORMAT)
        h.update(f"{sys.version};{np.__version__}".encode())
        files = [os.path.join(_ROOT, "errors.py")]
        for layer in _LAYERS:
            folder = os.path.join(_ROOT, layer)
            files += [os.path.join(folder, n) for n in sorted(os.listdir(folder))
                      if n.endswith(".py")]
        spec = importlib.util.find_spec("yaml")         # found, not imported
        if spec is not None and spec.origin:
            files.append(spec.origin)
        for path in files:
            with open(path, "rb") as f:
                h.update(path.encode() + b"\0" + f.read())
        _STAMP.append(h.digest())
    return _STAMP[0]


def _read(path):
    from ..legs._guards import MAX_MODEL_BYTES
    with open(path, "rb") as f:
        raw = f.read(MAX_MODEL_BYTES + 1)
    return raw if len(raw) <= MAX_MODEL_BYTES else None


def kept_catalog(path, load, kind):
    """The catalog of the file ``path``: kept on disk (an instance of ``kind``), else
    ``load(path)`` (then kept)."""
    if not disk_cache_enabled():
        return load(path)
    try:
        raw = _read(path)
    except OSError:
        raw = None
    if raw is None:                                     # let the reader say what is wrong
        return load(path)
    digest = hashlib.sha256(_stamp() + str(path).encode() + b"\0" + raw).hexdigest()
    folder = cache_folder("catalog")
    kept = os.path.join(folder, digest + ".pickle")
    try:
        with open(kept, "rb") as f:
            cat = pickle.load(f)
        if type(cat) is kind:
            return cat
    except Exception:   # noqa: BLE001 - a missing, partial or foreign file: read anew
        pass
    cat = load(path)
    try:
        if _read(path) == raw:                          # the file did not change meanwhile
            keep_file(folder, digest + ".pickle",
                      pickle.dumps(cat, protocol=pickle.HIGHEST_PROTOCOL), _MAX_FILES)
    except (OSError, pickle.PicklingError, TypeError, AttributeError):
        pass
    return cat
