"""GUI controls generated from the mission contract alone (no per-mission GUI code).

Sliders show a `Param` in its display unit (shown value = SI value x `display_factor`);
the session always receives SI values. Choice params become dropdowns whose value is the
option's index.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Sequence
from typing import Any

import viser

from solvers.mission import Mission
from solvers.problem import Param

from ..session import Session

NO_PRESET = "(choose a preset)"


def _clean(x: float) -> float:
    """Drop binary noise from a unit conversion (0.9650000000000001 -> 0.965)."""
    return float(f"{x:.12g}")


def display_unit(p: Param) -> str:
    return p.display_unit if p.display_unit is not None else p.unit


def label_of(p: Param) -> str:
    unit = display_unit(p)
    return f"{p.label} [{unit}]" if unit and not p.options else p.label


def to_display(p: Param, si: float) -> float:
    return _clean(si * p.display_factor)


def from_display(p: Param, shown: float) -> float:
    """SI value of a shown value, clamped to [min, max] against round-off of the factor."""
    si = min(max(shown / p.display_factor, p.min), p.max)
    if p.integer or p.options:
        return float(round(si))
    lo_gap, hi_gap = abs(si - p.min), abs(si - p.max)
    tol = 1e-9 * max(abs(p.min), abs(p.max), abs(p.step))
    return float(p.min if lo_gap < tol else p.max if hi_gap < tol else _clean(si))


def display_range(p: Param) -> tuple[float, float, float]:
    """(min, max, step) of the slider in display units."""
    lo, hi = sorted((to_display(p, p.min), to_display(p, p.max)))
    return lo, hi, _clean(abs(p.step * p.display_factor))


def group_params(params: Sequence[Param]) -> dict[str, list[Param]]:
    """Params by `Param.group`, groups in order of first appearance."""
    groups: dict[str, list[Param]] = {}
    for p in params:
        groups.setdefault(p.group, []).append(p)
    return groups


class Controls:
    """The control folders of one view, rebuilt whenever the session's configuration
    changes (`rebuild`). `inputs` maps param keys (and "nodes") to their GUI handles."""

    def __init__(self, gui: viser.GuiApi, session: Session, missions: Sequence[Mission],
                 order: float = 10.0, container: Any = None) -> None:
        self.gui = gui
        self.container = container  # e.g. a tab; None: the panel's root
        self.session = session
        self.missions = {m.title: m for m in missions}
        self.order = order
        self.inputs: dict[str, Any] = {}
        self._containers: list[Any] = []

    def rebuild(self) -> None:
        """Remove the old controls and generate new ones from the session's mission."""
        for handle in self._containers:
            handle.remove()
        self._containers.clear()
        self.inputs.clear()
        s = self.session
        with self.container if self.container is not None else contextlib.nullcontext():
            with self._folder("Problem"):
                self._problem_controls(s)
            for group, params in group_params(s.mission.all_params(s.method)).items():
                with self._folder(group):
                    for p in params:
                        self.inputs[p.key] = self._param_control(p, s.values[p.key])
            if s.mission.view_params:
                with self._folder("Display"):
                    for p in s.mission.view_params:
                        self.inputs[p.key] = self._param_control(p, s.view[p.key], view=True)

    def _folder(self, label: str) -> viser.GuiFolderHandle:
        folder = self.gui.add_folder(label, order=self.order + len(self._containers))
        self._containers.append(folder)
        return folder

    def _problem_controls(self, s: Session) -> None:
        mission = self.gui.add_dropdown("mission", tuple(self.missions),
                                        initial_value=s.mission.title, hint=s.mission.summary)
        mission.on_update(lambda _: s.select_mission(self.missions[mission.value]))
        self.inputs["mission"] = mission

        labels = {m.label: m.key for m in s.mission.methods}
        current = s.mission.method(s.method)
        method = self.gui.add_dropdown("method", tuple(labels), initial_value=current.label,
                                       hint=f"{current.summary} ({current.source})")
        method.on_update(lambda _: s.select_method(labels[method.value]))
        self.inputs["method"] = method

        if len(current.backends) > 1:  # one back end is no choice: the method hint names it
            backend = self.gui.add_dropdown("NLP back end", current.backends,
                                            initial_value=s.backend)
            backend.on_update(lambda _: s.set_backend(backend.value))
            self.inputs["backend"] = backend

        lo, _, hi = current.nodes
        nodes = self.gui.add_slider(current.nodes_label, lo, hi, 1, s.nodes,
                                    hint=f"discretisation size of {current.label}")
        nodes.on_update(lambda _: s.set_nodes(int(nodes.value)))
        self.inputs["nodes"] = nodes

        if s.mission.presets:
            names = {p.name: p for p in s.mission.presets}
            preset = self.gui.add_dropdown(
                "preset", (NO_PRESET, *names), initial_value=s.preset or NO_PRESET,
                hint="Load a named case (values, and sometimes a method and mesh).")

            @preset.on_update
            def _(_: Any) -> None:
                if preset.value in names:
                    s.apply_preset(names[preset.value])

            self.inputs["preset"] = preset

    def _param_control(self, p: Param, value: float, view: bool = False) -> Any:
        s = self.session
        apply = s.set_view if view else s.set_value
        hint = p.help or None
        if p.options:
            handle = self.gui.add_dropdown(p.label, p.options, initial_value=p.options[int(value)],
                                           hint=hint)
            handle.on_update(lambda _: apply(p.key, p.options.index(handle.value)))
            return handle
        lo, hi, step = display_range(p)
        handle = self.gui.add_slider(label_of(p), lo, hi, step, to_display(p, value), hint=hint)
        handle.on_update(_setter(apply, p, handle))
        return handle


def _setter(apply: Callable[[str, float], None], p: Param, handle: Any
            ) -> Callable[[Any], None]:
    def update(_: Any) -> None:
        shown = float(handle.value)
        if math.isfinite(shown):
            apply(p.key, from_display(p, shown))

    return update
