"""Mission files given to the explorer, watched: saving a file reloads its mission in the
running app (the workers restart with it, every tab showing it rebuilds its controls and
solves again); a file that fails to load is reported — in the terminal and in the browsers —
with its line, and the mission it replaced stays. The files are read from the local disk of
the person who started the server; a browser never sends code."""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable, Sequence
from pathlib import Path

from solvers.mission import Mission
from solvers.mission_file import MissionFileError, load_mission_file
from solvers.registry import expand_mission_paths, register

# s between looks at the files: a change is loaded once the file has stayed the same for one
# look (an editor's save, or a write seen half done, is not read while it is still moving).
POLL_S = 0.25
Signature = tuple[int, int]  # (modification time in ns, size in bytes)


class MissionFiles:
    """Loads the files at start and watches them; `on_loaded(mission, path)` and
    `on_error(path, message)` are called from the watcher thread."""

    def __init__(self, paths: Sequence[str], on_loaded: Callable[[Mission, str], None],
                 on_error: Callable[[str, str], None]) -> None:
        self.paths = expand_mission_paths(list(paths))
        self.on_loaded, self.on_error = on_loaded, on_error
        self.errors: dict[str, str] = {}
        self._seen = {p: self._signature(p) for p in self.paths}
        self._pending: dict[Path, Signature] = {}
        self._stop = threading.Event()
        for path in self.paths:
            self._load(path, notify=False)
        self._thread = threading.Thread(target=self._watch, daemon=True, name="mission-files")
        self._thread.start()

    @staticmethod
    def _signature(path: Path) -> Signature:
        try:
            stat = path.stat()
        except OSError:
            return (-1, -1)
        return (stat.st_mtime_ns, stat.st_size)

    def _load(self, path: Path, notify: bool = True) -> None:
        try:
            mission = load_mission_file(path)
            register(mission, str(path))
        except (MissionFileError, ValueError) as exc:
            message = str(exc)
            self.errors[str(path)] = message
            print(f"mission file error: {message}", file=sys.stderr, flush=True)
            self.on_error(str(path), message)
            return
        self.errors.pop(str(path), None)
        if notify:
            print(f"reloaded {path} (mission '{mission.key}')", file=sys.stderr, flush=True)
            self.on_loaded(mission, str(path))

    def _watch(self) -> None:
        while not self._stop.wait(POLL_S):
            for path in self.paths:
                now = self._signature(path)
                if now != self._seen[path]:
                    self._pending[path] = self._seen[path] = now
                elif self._pending.get(path) == now:  # unchanged since the last look
                    del self._pending[path]
                    self._load(path)

    @property
    def files(self) -> list[str]:
        return [str(p) for p in self.paths]

    def stop(self) -> None:
        self._stop.set()
