"""`UserMission`: a mission made from a declaration alone, solved by the general methods.

Everything a built-in mission writes by hand comes from the declaration: the `OCP` for
Hermite–Simpson, LGL and multiple shooting (and their back ends), the parameters as sliders
and CLI flags, the quantities (final time, final states), the re-propagated miss of every
constrained final state, plots of every state, control and path constraint, a default 3D
view and the help text.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from ..context import Infeasible, SolveContext
from ..handles import AnyHandle, check_bindings
from ..methods import HERMITE_SIMPSON, LGL, MULTIPLE_SHOOTING
from ..mission import Mission
from ..ocp import OCP, OCPResult
from ..presentation import Presentation
from ..problem import Consistency, Method, Param, Preset, Published
from ..shapes import Shape
from ..solution import Quantity, Solution
from . import view
from .build import build_ocp, parameter_vector
from .declaration import Declaration, check, resolve, winding_angles
from .errors import DeclarationError, caller_location, function_location, warn_at
from .fixed_ends import broken_at_fixed_end, state_only_rows
from .functions import check_finite, trace
from .guesses import ENDS, check_guesses, control_guess, state_guess
from .misses import accuracy_targets, check_names, final_misses, screen_labels, targets_markdown
from .records import Control, FinalConstraint, FreeTime, PathConstraint, State

DEFAULT_METHODS = (HERMITE_SIMPSON, LGL, MULTIPLE_SHOOTING)
KEY_CHARACTERS = set("abcdefghijklmnopqrstuvwxyz0123456789-")


def _check_position(decl: Declaration) -> None:
    """A position function runs once on the cold-start guess and must give finite
    coordinates there (a NaN would draw nothing, with no word why)."""
    if not callable(decl.position):
        return
    values = decl.defaults
    states = state_guess(decl, values, ENDS)
    path = view._positions(decl, states, parameter_vector(decl, values))
    if not np.all(np.isfinite(path)):
        row = int(np.flatnonzero(~np.all(np.isfinite(path), axis=1))[0])
        raise DeclarationError(f"position is not finite ({_coords(path[row])}) at the "
                               f"cold-start guess's {('start', 'end')[row]}: x = "
                               f"{_coords(states[row])}", function_location(decl.position))


def _coords(v: np.ndarray) -> str:
    return "[" + ", ".join(f"{float(a):g}" for a in v) + "]"


class UserMission(Mission):
    """A mission declared in a few lines (the README's "Bring your own problem" describes
    every field).

    Raises `DeclarationError` (one line: "file:line: what is wrong") when the declaration
    cannot be solved: the dynamics are built once symbolically here, so a wrong size, an
    unknown name or a bound that excludes the initial state is found when the file loads.
    `tolerances` are the file's accuracy targets, and for every miss it gives none 1e-5 of
    the miss's scale (`misses.default_targets`); `warnings` says what loads but may mislead
    (an angle control bounded to more than one turn): in the About text, and as a
    `UserWarning` at its line when the file loads.
    """

    def __init__(
        self,
        *,
        key: str,
        title: str,
        states: tuple[State, ...] | list[State],
        controls: tuple[Control, ...] | list[Control],
        dynamics: Callable[..., Any],
        final_time: float | str | FreeTime,
        params: tuple[Param, ...] | list[Param] = (),
        lagrange: Callable[..., Any] | None = None,
        mayer: Callable[..., Any] | None = None,
        minimum_time: bool = False,
        maximize: bool = False,
        path: tuple[PathConstraint, ...] | list[PathConstraint] = (),
        final: tuple[FinalConstraint, ...] | list[FinalConstraint] = (),
        position: tuple[str, ...] | list[str] | Callable[..., Any] = (),
        position_unit: str | None = None,
        cost_scale: float = 1.0,
        summary: str = "",
        source: str = "",
        notes: str = "",
        cost_label: str = "cost",
        cost_unit: str = "",
        methods: tuple[Method, ...] = DEFAULT_METHODS,
        published: tuple[Published, ...] = (),
        tolerances: Mapping[str, float] | None = None,
        consistency: tuple[Consistency, ...] = (),
        presets: tuple[Preset, ...] = (),
        equations: tuple[tuple[str, str], ...] = (),
        handles: tuple[AnyHandle, ...] = (),
        shapes: tuple[Shape, ...] = (),
    ) -> None:
        where = caller_location()
        self.declaration = Declaration(
            states=tuple(states), controls=tuple(controls), params=tuple(params),
            dynamics=dynamics, final_time=final_time, lagrange=lagrange, mayer=mayer,
            minimum_time=minimum_time, maximize=maximize, path=tuple(path), final=tuple(final),
            position=tuple(position) if isinstance(position, list | tuple) else position,
            position_unit=position_unit, cost_scale=cost_scale, where=where)
        self.key, self.title, self.summary, self.source = key, title, summary, source
        self.notes = notes
        self.params = tuple(params)
        self.methods = tuple(methods)
        self.published, self.presets, self.equations = published, presets, equations
        self.tolerances = dict(tolerances or {})  # the file's; defaults added below
        self.consistency = consistency
        self.cost_label, self.cost_unit = cost_label, cost_unit
        self.handles, self.shapes = tuple(handles), tuple(shapes)  # dragged in the 3D view
        self._check_and_build(where)

    def _check_and_build(self, where: str) -> None:
        """Check the file's records (each refusal names its line) and build its OCP once."""
        self._check_records(where)
        decl, values = self.declaration, self.declaration.defaults
        check(decl)
        check_guesses(decl)
        self._traced = trace(decl)
        self._state_rows = state_only_rows(decl, self._traced)
        states = state_guess(decl, values, ENDS)
        check_finite(self._traced, decl, states[0], states[-1],
                     control_guess(decl, values, ENDS)[0], parameter_vector(decl, values))
        self._ocp = build_ocp(decl, self._traced)
        self._structure = decl.structure()  # tells warm starts that fit
        check_names(self, decl, where)
        self.given_tolerances = dict(self.tolerances)
        self.tolerances = accuracy_targets(decl, self.given_tolerances)
        self.labels = screen_labels(decl)
        _check_position(decl)
        winding = winding_angles(decl)
        self.warnings = tuple(message for message, _ in winding)  # shown in the About text
        for message, at in winding:
            warn_at(message, at)

    def _check_records(self, where: str) -> None:
        if not self.key or set(self.key) - KEY_CHARACTERS:
            raise DeclarationError(f"key '{self.key}': use lower-case letters, digits and '-' "
                                   "(it names the mission on the command line)", where)
        if not self.methods:
            raise DeclarationError("declare at least one method", where)
        for m in self.methods:
            if m.transcription is None:
                raise DeclarationError(f"method '{m.key}' is not a general method (use "
                                       "HERMITE_SIMPSON, LGL or MULTIPLE_SHOOTING)", where)
        try:
            check_bindings((*self.handles, *self.shapes), self.params, ())
        except ValueError as exc:
            raise DeclarationError(str(exc), where) from None

    # ---- the general direct path ---------------------------------------------------------
    def ocp(self, method: Method, values: dict[str, float]) -> OCP:
        return self._ocp

    def parameter_vector(self, values: dict[str, float]) -> np.ndarray:
        return parameter_vector(self.declaration, values)

    def solve_direct(self, values: dict[str, float], method: Method, nodes: int, backend: str,
                     warm: Solution | None, ctx: SolveContext) -> Solution:
        """The general direct solve; a warm start from a declaration of another structure
        (the file was edited and reloaded) is dropped: its NLP differs in size."""
        if warm is not None and (warm.warm is None
                                 or warm.warm.data.get("structure") != self._structure):
            warm = None
        return super().solve_direct(values, method, nodes, backend, warm, ctx)

    def precheck(self, values: dict[str, float], p: np.ndarray) -> None:
        """Parameter values that put a fixed initial or final state outside its bounds, make
        a fixed final time non-positive, or break a path constraint of the states at a fixed
        end (a start outside a glide-slope cone) are refused before any solve."""
        decl = self.declaration
        for s in decl.states:
            lo, hi = (resolve(b, values) for b in s.bounds)
            for end in ("initial", "final"):
                value = getattr(s, end)
                if value is not None and not lo <= resolve(value, values) <= hi:
                    raise Infeasible(f"{end} {s.name} = {resolve(value, values):g} {s.unit} is "
                                     f"outside its bounds [{lo:g}, {hi:g}]".replace("  ", " "))
        ft = decl.final_time
        if not isinstance(ft, FreeTime) and not resolve(ft, values) > 0:
            raise Infeasible(f"the final time must be positive, not {resolve(ft, values):g} s")
        broken = broken_at_fixed_end(decl, self._traced, self._state_rows, values, p)
        if broken is not None:
            raise Infeasible(broken)

    def record(self, sol: Solution, res: OCPResult, p: np.ndarray) -> None:
        """The cost as declared (a maximised value itself, not the NLP's negative), the final
        time and every final state as quantities."""
        decl = self.declaration
        if sol.warm is not None:
            sol.warm.data["structure"] = self._structure
        if decl.maximize:
            sol.cost = Quantity(-float(res.cost), self.cost_label, self.cost_unit)
        sol.quantities["tf"] = Quantity(float(res.T), "final time", "s")
        for s, value in zip(decl.states, res.X[-1], strict=True):
            sol.quantities[f"{s.name}_final"] = Quantity(float(value), f"final {s.label or s.name}",
                                                          s.unit)

    def terminal_miss(self, p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
        return final_misses(self.declaration, self._traced, p, x_final)

    # ---- presentation and help -------------------------------------------------------------
    def _present(self, sol: Solution, view_options: dict[str, float]) -> Presentation:
        return view.present(self.declaration, self._traced, sol)

    @property
    def help(self) -> str:
        return view.help_markdown(self, self.declaration, self.notes,
                                  targets_markdown(self.declaration, self.given_tolerances),
                                  self.warnings)
