"""Plot figures as the page receives them: plotly's JSON, written once per answer and shared.

A classroom's followers all draw the teacher's answer the same way; building and encoding the
figure for each of thirty tabs cost ~30 ms each, one after another (1.2 s for the last
follower). A `PageFigure` is the figure's plain JSON tree, never mutated once built; moving
the time marker re-encodes a shallow copy (0.5 ms). `SharedFigures` keeps the last few trees
by what they were built from, so views drawing the same answer share one.
"""

from __future__ import annotations

import json
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field

from .plots import marker_shapes

SHARED_SIZE = 16  # trees kept: a few answers in each of the views' looks (dark, page, dim)
TEXTS_KEPT = 4  # encoded JSON kept per tree (time markers)


@dataclass(frozen=True)
class PageFigure:
    """A figure's plotly JSON tree (shared: never mutated) and its number of subplots that
    carry the time marker."""

    tree: dict
    n_series: int
    _texts: dict = field(default_factory=dict, compare=False, repr=False)

    def text(self, t: float | None = None, dark: bool = True) -> str:
        """The JSON the page gets, with the time marker at `t` (None: no marker); the last
        few are kept (followers send the same one)."""
        key = (t, dark)
        text = self._texts.get(key)
        if text is None:
            layout = {**self.tree["layout"], "shapes": marker_shapes(self.n_series, t, dark)}
            text = json.dumps({"data": self.tree["data"], "layout": layout}, allow_nan=False)
            if len(self._texts) >= TEXTS_KEPT:
                self._texts.pop(next(iter(self._texts)))
            self._texts[key] = text
        return text


class SharedFigures:
    """The last `size` page figures, each by the answer it shows (the object itself: an
    entry keeps it alive, so its id is not reused) and a key naming the rest it was built
    from (view options, page, dim, theme)."""

    def __init__(self, size: int = SHARED_SIZE) -> None:
        self.size = size
        self._trees: OrderedDict[tuple[int, Hashable], tuple[object, PageFigure]] = \
            OrderedDict()
        self._lock = threading.Lock()
        self.built = 0  # trees built (tests count them)

    def get(self, answer: object, key: Hashable, build: Callable[[], PageFigure]
            ) -> PageFigure:
        """The figure of `answer` drawn as `key` says, built by `build` the first time."""
        slot = (id(answer), key)
        with self._lock:
            entry = self._trees.get(slot)
            if entry is not None and entry[0] is answer:
                self._trees.move_to_end(slot)
                return entry[1]
        figure = build()  # outside the lock: other views go on drawing meanwhile
        with self._lock:
            self.built += 1
            self._trees[slot] = (answer, figure)
            while len(self._trees) > self.size:
                self._trees.popitem(last=False)
        return figure


SHARED = SharedFigures()
