"""Writing an export's files (private): the folders made, and an error that names the cause."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

__all__ = ["write_text"]


def write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path``, making its folders; an :class:`InputError` naming
    the cause where it cannot (a part of the path that is a file, not a folder, was
    reported as "File exists")."""
    p = Path(path)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text, encoding="utf-8")
    except OSError as exc:
        blocker = next((q for q in p.parents if q.exists()), None)
        if blocker is not None and not blocker.is_dir():
            raise InputError(f"cannot write {str(p)!r}: {str(blocker)!r} is a file, not a "
                             "folder") from None
        raise InputError(f"cannot write {str(p)!r}: {exc.strerror or exc}") from None
    return p
