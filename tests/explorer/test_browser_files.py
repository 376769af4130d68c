"""Mission files in the running explorer (issue 13): a user's file appears in the mission
list, saving it reloads it within 2 s in the tab that shows it, and a broken file is reported
in the page with its line while the explorer keeps serving the last good version."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import pytest
from browser_support import BROWSER, PATIENCE, PATIENCE_MS, until

pytestmark = BROWSER
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "double_integrator.py"


def test_a_saved_mission_file_reloads_and_a_broken_one_is_reported(tmp_path):
    from explorer.app import ExplorerApp
    from explorer.capture import CAPTURE_TIME_LIMIT, chromium, free_port, open_tab

    path = tmp_path / "my_problem.py"
    shutil.copy(EXAMPLE, path)
    app = ExplorerApp("127.0.0.1", free_port(), "double-integrator", mission_files=(str(path),),
                      time_limit=CAPTURE_TIME_LIMIT)
    try:
        with chromium() as context:
            page, view = open_tab(app, context)
            first = view.session.mission
            assert first.key == "double-integrator" and view.session.latest.ok
            assert view.session.latest.cost.value == pytest.approx(6.0, rel=1e-6)
            # Save a new version: the distance default doubles, so the cost is 24.
            text = path.read_text()
            path.write_text(text.replace('Param("distance", "distance d", "m", 1.0,',
                                         'Param("distance", "distance d", "m", 2.0,'))
            saved = time.monotonic()
            until(lambda: view.session.mission is not first, "the reload", timeout=PATIENCE)
            assert time.monotonic() - saved < 2.0
            # The tab kept its values (distance 1 m was set in the old version too).
            assert view.session.wait_idle(60.0) and view.session.latest.ok
            # A syntax error: reported with the file and line, the last good mission stays.
            reloaded = view.session.mission
            path.write_text(text.replace("MISSION = UserMission(", "MISSION = UserMission(("))
            page.get_by_text("my_problem.py:").first.wait_for(timeout=PATIENCE_MS)
            assert view.session.mission is reloaded and view.session.latest.ok
            # The explorer keeps serving: another mission still solves in this tab.
            from solvers import get_mission

            view.session.select_mission(get_mission("lunar-landing"))
            until(lambda: view.session.wait_idle(60) and view.session.latest
                   and view.session.latest.mission == "lunar-landing"
                   and view.session.latest.ok, "a lunar solve after the broken file")
            # The file is still broken: an answer does not close its notice ...
            assert page.get_by_text("my_problem.py:").first.is_visible()
            # ... a good save does.
            path.write_text(text)
            page.get_by_text("my_problem.py:").first.wait_for(state="hidden",
                                                              timeout=PATIENCE_MS)
    finally:
        app.stop()
