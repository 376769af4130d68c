"""Fixtures of the browser tests: one app and one chromium per test module, and new tabs on
it (optionally opened on a link), closed after each test."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from browser_support import HEIGHT, PATIENCE_MS, WIDTH, until


@pytest.fixture(scope="module")
def app(request) -> Iterator:
    """The module's app; a module's `MISSION_FILES` (paths) add users' missions to it."""
    pytest.importorskip("playwright.sync_api", reason="Python Playwright is not installed")
    from explorer.app import ExplorerApp
    from explorer.capture import CAPTURE_TIME_LIMIT, chromium, free_port

    # The screenshot's time limit, not the live 5 s: on a loaded machine a cold build may take
    # longer, and these tests are about what the page shows, not how fast.
    server = ExplorerApp("127.0.0.1", free_port(), "lunar-landing", "hermite-simpson",
                         time_limit=CAPTURE_TIME_LIMIT,
                         mission_files=getattr(request.module, "MISSION_FILES", ()))
    with chromium(WIDTH, HEIGHT) as context:
        context.set_default_timeout(PATIENCE_MS)
        server.context = context
        yield server
    server.stop()


@pytest.fixture()
def tab(app):
    """`tab(url_query="")`: a new tab on the module's app (on `/?url_query` when given) and
    its view."""
    from explorer.capture import close_webgl_toast, open_tab

    pages = []

    def open_one(url_query: str = ""):
        page = app.context.new_page()
        with app._lock:
            before = set(app.views)
        if url_query:  # open_tab navigates to the app's address; this one carries a case
            page.goto(f"{app.url}/?{url_query}")
            view = _attached(app, before)
        else:
            page, view = open_tab(app, app.context, page=page)
        close_webgl_toast(page, timeout=3.0)
        pages.append(page)
        return page, view

    yield open_one
    for page in pages:
        page.close()


def _attached(app, before: set[int]):
    """The view of the tab that connected after `before`, once it has drawn."""
    new = until(lambda: set(app.views) - before, "the new tab's view")
    with app._lock:
        view = app.views[min(new)]
    until(lambda: view.session.wait_idle(60) and view.drawn, "the first drawing")
    return view
