"""mkdocs hook: Sphinx roles in the numpydoc docstrings (``:func:`solve```, ``:class:`~a.B```)
are shown as code (mkdocstrings renders the role's target as code and leaves the role)."""

from __future__ import annotations

import re

_ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|data|attr|exc|obj|const):<code>~?([^<]*)</code>")


def _target(m: re.Match) -> str:
    name = m.group(1)
    short = name.rsplit(".", 1)[-1] if m.group(0).startswith(":") and "~" in m.group(0) else name
    return f"<code>{short}</code>"


def on_page_content(html: str, **kwargs) -> str:
    return _ROLE.sub(_target, html)
