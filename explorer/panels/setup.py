"""The Setup panel: controls generated from the mission contract alone (no per-mission GUI
code): mission, method, back end, nodes, presets, a "solve from the initial guess" action, one
slider-and-box per parameter (`value_input.NumberField`, display units, SI to the session),
dropdowns for choices, and the mission's view options in a Display folder (they redraw without
solving).
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from typing import Any

import viser

from solvers.mission import Mission
from solvers.problem import Param

from ..session import Session
from .value_input import NumberField, Report

NO_PRESET = "(choose a preset)"
# The panel's own folders: a mission's group of the same name (a mission file may use any
# name) gets " parameters" added, or the panel showed two "Problem" folders.
OWN_FOLDERS = ("Problem", "Display")


def group_params(params: Sequence[Param]) -> dict[str, list[Param]]:
    """Params by `Param.group` (renamed where it is one of `OWN_FOLDERS`), groups in order
    of first appearance."""
    groups: dict[str, list[Param]] = {}
    for p in params:
        label = f"{p.group} parameters" if p.group in OWN_FOLDERS else p.group
        groups.setdefault(label, []).append(p)
    return groups


class Controls:
    """The control folders of one view, rebuilt whenever the session's configuration
    changes (`rebuild`). `inputs` maps param keys (and "nodes") to their GUI handles."""

    def __init__(self, gui: viser.GuiApi, session: Session, missions: Sequence[Mission],
                 order: float = 10.0, container: Any = None,
                 report: Report | None = None) -> None:
        self.gui = gui
        self.report: Report = report or (lambda title, message: None)
        self.fields: dict[str, NumberField] = {}
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
        self.fields.clear()
        s = self.session
        with self.container if self.container is not None else contextlib.nullcontext():
            with self._folder(OWN_FOLDERS[0]):
                self._problem_controls(s)
            for group, params in group_params(s.mission.all_params(s.method)).items():
                with self._folder(group):
                    for p in params:
                        self.inputs[p.key] = self._param_control(p, s.values[p.key])
            if s.mission.view_params:
                with self._folder(OWN_FOLDERS[1]):
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
        nodes_param = Param("nodes", current.nodes_label, "", s.nodes, lo, hi, 1, integer=True)
        nodes = NumberField(self.gui, nodes_param, s.nodes, lambda _, n: s.set_nodes(int(n)),
                            self.report, hint=f"discretisation size of {current.label}")
        self.fields["nodes"] = nodes
        self.inputs["nodes"] = nodes.handle

        cold = self.gui.add_button(
            "solve from the initial guess", icon=viser.Icon.REFRESH,
            hint="Solve again from the method's initial guess instead of the last answer: "
                 "shows a whole convergence (replay it in Play), and whether the answer "
                 "depends on where the solver started.")
        cold.on_click(lambda _: s.submit(cold=True))

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
        field = NumberField(self.gui, p, value, apply, self.report, hint=hint)
        self.fields[p.key] = field
        return field.handle
