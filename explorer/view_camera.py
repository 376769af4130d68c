"""The cameras of one view, steered by the Play panel's camera mode: the overview frames the
drawn path (again only when the path leaves the framed box, and never under a hand), "follow
vehicle" chases the vehicle, "top view" looks straight at the path's plane; and the pose of
a screenshot."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable

import numpy as np
import viser

from .camera import Cameras, shot_pose, top_view
from .geometry import Geometry
from .panels.play import CAMERAS, PlayPanel
from .panels.side import PANEL_GAP, PLOT_PANEL

OVERVIEW, FOLLOW, TOP = CAMERAS

# What a view has drawn: (mission key, geometry in display units), None before a drawing.
Drawn = Callable[[], tuple[str, Geometry] | None]


class ViewCamera:
    """Every camera of the browsers watching one view."""

    def __init__(self, play: PlayPanel, lock: threading.RLock, drawn: Drawn,
                 vehicle_size: Callable[[], float]) -> None:
        self.cameras = Cameras(PLOT_PANEL[1] + PANEL_GAP)
        self._play = play
        self._lock = lock
        self._drawn = drawn
        self._vehicle_size = vehicle_size

    @property
    def clients(self) -> dict[int, viser.ClientHandle]:
        """The browsers watching, by client id."""
        return self.cameras.clients

    def attach(self, client: viser.ClientHandle) -> None:
        """A browser starts watching: frame what is drawn in its camera."""
        self.cameras.attach(client, lambda c: self.apply([c]))
        if self._drawn() is not None:
            self.apply([client])

    def detach(self, client: viser.ClientHandle) -> None:
        self.cameras.detach(client)

    def forget_frame(self) -> None:
        """Another mission: its first drawing frames the cameras afresh."""
        self.cameras.framed = None

    def frame_if_needed(self) -> None:
        """Frame the drawn path again if it left the framed box (after a drawing, a drag)."""
        with self._lock:
            drawn = self._drawn()
            if drawn is not None and self.cameras.needs_framing(*drawn):
                self.apply()

    def follow(self, position: np.ndarray) -> None:
        """The vehicle moved to `position`: a chasing camera goes with it."""
        drawn = self._drawn()
        if self._play.camera == FOLLOW and drawn is not None:
            self.cameras.chase(drawn[1], position, self._vehicle_size())

    def reset(self) -> None:
        """Back to the overview, forgetting the directions people orbited to."""
        self.cameras.forget_user_views()
        if self._play.camera != OVERVIEW:
            self._play.camera = OVERVIEW  # runs `apply` through its callback
        else:
            self.apply()

    def shot(self, aspect: float) -> tuple[np.ndarray, np.ndarray, float] | None:
        """A camera framing the path on a whole image of `aspect` (for the screenshot)."""
        drawn = self._drawn()
        return None if drawn is None else shot_pose(drawn[1], aspect)

    def apply(self, clients: Iterable[viser.ClientHandle] | None = None) -> None:
        """Point the cameras (of `clients`, default all watching) by the camera mode."""
        drawn = self._drawn()
        if drawn is None:
            return
        g = drawn[1]
        mode, track = self._play.camera, self._play.track
        follow = track.pose(self._play.t).position if mode == FOLLOW and track else None
        self.cameras.frame(g, top_view(g) if mode == TOP else None, clients, follow,
                           self._vehicle_size())
