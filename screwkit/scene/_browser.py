"""A view's page in a real headless browser: Chromium driven by Playwright.

Used by ``screwkit view --png`` (a screenshot), by the documentation's figures and by the
tests.  The browser is the system's Chromium (``chromium`` on the PATH, or the
``SCREWKIT_CHROMIUM`` environment variable); Playwright's own browser download is not
needed.  Every request other than the page itself is refused, so a page that tried to
reach the network would show it (:attr:`PageSession.requests`).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

from ..errors import InputError

__all__ = ["find_chromium", "browser", "open_page", "screenshot", "CHROMIUM_ARGS"]

#: The flags of a headless Chromium run as root in a container, with software WebGL.
CHROMIUM_ARGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run",
                 "--disable-dev-shm-usage")

_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def find_chromium() -> str | None:
    """The Chromium executable: ``$SCREWKIT_CHROMIUM``, else the first of chromium,
    chromium-browser, google-chrome on the PATH; None when there is none."""
    env = os.environ.get("SCREWKIT_CHROMIUM")
    if env:
        return env if Path(env).is_file() else None
    for name in _NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


def _require():
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        raise InputError('driving a browser needs playwright: pip install "screwkit[view]"') \
            from None
    exe = find_chromium()
    if exe is None:
        raise InputError("no Chromium found (install it, e.g. apt-get install chromium, or "
                         "set SCREWKIT_CHROMIUM to its path)")
    return sync_playwright, exe


class PageSession:
    """An open page: ``page`` (Playwright's), the console ``errors`` (messages of type
    error and uncaught exceptions) and the ``requests`` other than the page itself."""

    def __init__(self, page, url):
        self.page, self.url = page, url
        self.errors, self.requests = [], []

    def wait_drawn(self, timeout_ms: int = 30000) -> None:
        """Wait until plotly has drawn the 3D scene (its WebGL canvas exists) and the page
        has placed its labels for plotly's camera."""
        self.page.wait_for_function(
            "() => window.screwkitView && (!window.screwkitView.ready || window.screwkitView.ready()) "
            "&& document.querySelector('#sk-plot canvas') "
            "&& document.querySelector('#sk-plot .gl-container')", timeout=timeout_ms)
        self.page.wait_for_timeout(400)


class Browser:
    """A headless Chromium with a fresh profile (:func:`browser`); :meth:`open` opens a
    page in it."""

    def __init__(self, context):
        self.context = context

    def open(self, html_path) -> PageSession:
        """Open the page ``html_path``; every request but the page's own is refused and
        recorded."""
        url = Path(html_path).resolve().as_uri()
        page = self.context.new_page()
        session = PageSession(page, url)

        def route(r):
            if r.request.url == url or r.request.url.startswith("data:"):
                return r.continue_()
            session.requests.append(r.request.url)
            return r.abort()

        page.route("**/*", route)
        page.on("console", lambda m: session.errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: session.errors.append(str(e)))
        page.goto(url)
        return session


@contextmanager
def browser(width: int = 1400, height: int = 900):
    """A headless Chromium (yields a :class:`Browser`), closed on exit."""
    sync_playwright, exe = _require()
    from playwright.sync_api import Error as PlaywrightError

    with tempfile.TemporaryDirectory(prefix="screwkit-chromium-") as profile:
        try:
            with sync_playwright() as pw:
                # a fresh profile every time (nothing carried over between runs)
                context = pw.chromium.launch_persistent_context(
                    profile, executable_path=exe, args=list(CHROMIUM_ARGS), headless=True,
                    viewport={"width": width, "height": height})
                try:
                    yield Browser(context)
                finally:
                    context.close()
        except PlaywrightError as exc:
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise InputError(f"Chromium ({exe}) failed: {first}") from None


@contextmanager
def open_page(html_path, width: int = 1400, height: int = 900):
    """Open the page ``html_path`` in a headless Chromium of its own; yields a
    :class:`PageSession`."""
    with browser(width, height) as b:
        yield b.open(html_path)


def screenshot(html_path, png_path, *, state: int | None = None, width: int = 1400,
               height: int = 900) -> dict:
    """A PNG screenshot of the view's page (after plotly has drawn), optionally showing
    state ``state`` first.  Returns ``{"png": path, "errors": [...]}``."""
    png = Path(png_path)
    with open_page(html_path, width, height) as s:
        s.wait_drawn()
        if state is not None:
            s.page.evaluate(f"window.screwkitView.show({int(state)})")
            s.page.wait_for_timeout(600)
        try:
            png.parent.mkdir(parents=True, exist_ok=True)
            s.page.screenshot(path=str(png), full_page=True)
        except OSError as exc:
            raise InputError(f"cannot write {str(png)!r}: {exc.strerror or exc}") from None
        return {"png": str(png), "errors": list(s.errors), "requests": list(s.requests)}
