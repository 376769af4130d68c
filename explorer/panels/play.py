"""The Play panel: play/pause, the time slider, speed, camera mode, read-outs at the vehicle,
and the solver's iterates (ghosts and a replay). The panel owns the animation clock (a
thread while playing) and calls the view back with the time to show."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

import viser

from ..player import SPEEDS, Track

FRAME_S = 1 / 20  # animation frame period (vehicle, follow camera)
SLOW_S = 1 / 3  # period of the slower animation updates (plot marker, read-outs, slider)
CAMERAS = ("overview", "follow vehicle", "top view")

ShowTime = Callable[[float, bool], None]  # (t, slow): move to t; slow also updates read-outs


class PlayPanel:
    """Animation controls; `show_time(t, slow)` draws the vehicle at t."""

    def __init__(self, gui: viser.GuiApi, show_time: ShowTime,
                 on_camera: Callable[[], None], on_reset: Callable[[], None],
                 on_ghosts: Callable[[], None], on_replay: Callable[[], None]) -> None:
        self.show_time_cb = show_time
        self.track: Track | None = None
        self.t = 0.0
        self.playing = False
        self._player: threading.Thread | None = None
        self._setting_time = False
        self._closed = threading.Event()
        self.button = gui.add_button("play", icon=viser.Icon.PLAYER_PLAY,
                                     hint="Play/pause the vehicle along the trajectory "
                                          "(key: space)")
        self.button.on_click(lambda _: self.toggle())
        self.time_slider = gui.add_slider("time [s]", 0.0, 1.0, 0.001, 0.0,
                                          hint="Animation time: drag to move the vehicle.")
        self.time_slider.on_update(self._slider_moved)
        self.speed = gui.add_dropdown("speed", tuple(SPEEDS), initial_value="1x",
                                      hint="1x plays the whole trajectory in 12 s.")
        self.camera_mode = gui.add_dropdown("camera", CAMERAS, initial_value=CAMERAS[0],
                                            hint="overview: the whole path; follow: chase the "
                                                 "vehicle; top: look straight at the path's "
                                                 "plane.")
        self.camera_mode.on_update(lambda _: on_camera())
        reset = gui.add_button("reset camera", icon=viser.Icon.FOCUS_CENTERED,
                               hint="Back to the overview (key: r)")
        reset.on_click(lambda _: on_reset())
        self.readout = gui.add_markdown("")
        with gui.add_folder("Solver iterations", expand_by_default=True):
            self.ghosts = gui.add_checkbox(
                "show iterates", False,
                hint="Draw the solver's intermediate trajectories, the earliest faintest.")
            self.ghosts.on_update(lambda _: on_ghosts())
            self.replay_button = gui.add_button(
                "replay iterations", icon=viser.Icon.PLAYER_TRACK_NEXT,
                hint="Step through the iterates one by one, fading into the optimum. To see "
                     "a whole convergence, solve from the initial guess first (Setup).")
            self.replay_button.on_click(lambda _: on_replay())
            self.replay_text = gui.add_markdown("")

    @property
    def camera(self) -> str:
        """The camera mode: overview, follow or top."""
        return str(self.camera_mode.value)

    @camera.setter
    def camera(self, mode: str) -> None:
        self.camera_mode.value = mode  # its callback applies it

    @property
    def ghosts_on(self) -> bool:
        """The solver's iterates are to be drawn."""
        return bool(self.ghosts.value)

    def show_replay(self, text: str) -> None:
        """The iteration replay's line ("" when none runs)."""
        self.replay_text.content = text

    def show_readout(self, markdown: str) -> None:
        """The vehicle's state at the animation time ("" with no trajectory)."""
        self.readout.content = markdown

    def set_track(self, track: Track | None, time_unit: str = "s",
                  time_scale: float = 1.0) -> None:
        """A new trajectory to animate: the slider spans its times (in the display unit)."""
        self.track = track
        if track is None:
            return
        self.t = min(max(self.t, track.t0), track.tf)
        self._setting_time = True
        try:
            span = (track.tf - track.t0) * time_scale
            self.time_scale = time_scale
            self.time_slider.label = f"time [{time_unit}]"
            self.time_slider.min = track.t0 * time_scale
            self.time_slider.max = track.tf * time_scale
            self.time_slider.step = float(f"{span / 500:.2g}") if span > 0 else 1.0
            self.time_slider.value = self.t * time_scale
        finally:
            self._setting_time = False

    time_scale = 1.0

    def toggle(self) -> None:
        if self.playing:
            self.playing = False
            return
        if self.track is None:
            return
        self.playing = True
        self.button.label = "pause"
        self.button.icon = viser.Icon.PLAYER_PAUSE
        if self._player is None or not self._player.is_alive():
            self._player = threading.Thread(target=self._play, daemon=True,
                                            name="explorer-player")
            self._player.start()

    def _play(self) -> None:
        last, slow_at = time.monotonic(), 0.0
        while self.playing and not self._closed.is_set():
            time.sleep(FRAME_S)
            now = time.monotonic()
            track = self.track
            if track is None:
                break
            t = track.step(self.t, now - last, SPEEDS[self.speed.value])
            last = now
            slow = now - slow_at >= SLOW_S or t >= track.tf
            if slow:
                slow_at = now
            self.t = t
            self.show_time_cb(t, slow)
            if slow:
                self.follow_slider(t)
            if t >= track.tf:
                break
        self.playing = False
        self.show_time_cb(self.t, True)  # read-outs and marker at the paused time
        self.follow_slider(self.t)
        self.button.label = "play"
        self.button.icon = viser.Icon.PLAYER_PLAY

    def follow_slider(self, t: float) -> None:
        """Move the slider to t without it calling back."""
        track = self.track
        if track is None:
            return
        self._setting_time = True
        try:
            self.time_slider.value = float(min(max(t, track.t0), track.tf)) * self.time_scale
        finally:
            self._setting_time = False

    def _slider_moved(self, _: Any) -> None:
        if not self._setting_time:
            self.t = float(self.time_slider.value) / self.time_scale
            self.show_time_cb(self.t, True)

    def close(self) -> None:
        self._closed.set()
        self.playing = False
