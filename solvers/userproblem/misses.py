"""The re-propagated miss of every constrained final state and final constraint, by name,
its accuracy target (the file's `tolerances`, else 1e-5 of the miss's scale), and the check
that a mission's records (published numbers, accuracy targets, presets) only use names the
mission reports."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..mission import Mission
from ..problem import validate_values
from ..solution import Label
from .build import bound_scale, state_scaling
from .declaration import Declaration, resolve
from .errors import DeclarationError, refine
from .functions import Traced
from .locate import dict_key_line
from .records import unit_key

# What every direct solve reports besides its quantities (Solution.stats and .check).
STATS = ("iterations", "nlp_variables", "nlp_constraints", "constraint_violation", "wall_s",
         "max_defect")
# A miss's accuracy target where the file gives none, relative to the miss's scale: without
# one, any miss was `optimal` (a fixed-time transfer came back so with a final radial-speed
# miss of 0.097 in its own units).
TARGET_PER_SCALE = 1e-5


def miss_names(decl: Declaration) -> list[str]:
    """"<state>_miss_<unit>" per fixed final state, "<constraint>_miss_<unit>" per final
    constraint (e.g. "v_miss_m_s")."""
    names = [f"{s.name}_miss{unit_key(s.unit)}" for s in decl.states if s.final is not None]
    return names + [f"{c.name}_miss{unit_key(c.unit)}" for c in decl.final]


def default_targets(decl: Declaration) -> dict[str, float]:
    """`TARGET_PER_SCALE` of each miss's scale, the one the NLP divides by: a state's
    `scale`, else the half-width of its bounds, else its largest value; a final constraint's
    `scale`, else its largest nonzero bound, else 1 (at the parameters' defaults)."""
    defaults = decl.defaults
    scales = [state_scaling(s, defaults)[1] for s in decl.states if s.final is not None]
    scales += [bound_scale(c.scale, c.lower, c.upper) for c in decl.final]
    return {name: TARGET_PER_SCALE * scale
            for name, scale in zip(miss_names(decl), scales, strict=True)}


def accuracy_targets(decl: Declaration, given: Mapping[str, float]) -> dict[str, float]:
    """The file's own targets (in its order: the first is the headline), then the default
    target of every miss it gives none."""
    return {**given, **{k: v for k, v in default_targets(decl).items() if k not in given}}


def targets_markdown(decl: Declaration, given: Mapping[str, float]) -> str:
    """The About panel's line on the accuracy targets and where each comes from."""
    targets = accuracy_targets(decl, given)
    if not targets:
        return ""
    defaulted = [k for k in targets if k not in given]
    rule = f"{TARGET_PER_SCALE:g} × the state's or constraint's scale"
    if not given:
        source = f"from the scales, as no `tolerances` are given ({rule})"
    elif defaulted:
        source = (f"the file's `tolerances`, and for {', '.join(f'`{k}`' for k in defaulted)}"
                  f" the scale ({rule})")
    else:
        source = "the file's `tolerances`"
    items = ", ".join(f"`{k}` ≤ {v:.3g}" for k, v in targets.items())
    return f"Accuracy targets of the re-propagated final misses, {source}: {items}."


def screen_labels(decl: Declaration) -> dict[str, Label]:
    """The screen name of each state, control and miss (`Solution.labels`): the label the
    file gives (else the name) and the unit."""
    labels = {r.name: Label(r.label or r.name, r.unit) for r in (*decl.states, *decl.controls)}
    for s in decl.states:
        if s.final is not None:
            labels[f"{s.name}_miss{unit_key(s.unit)}"] = Label(f"final {s.label or s.name} miss",
                                                               s.unit)
    for c in decl.final:
        labels[f"{c.name}_miss{unit_key(c.unit)}"] = Label(f"final {c.name} miss", c.unit)
    return labels


def final_misses(decl: Declaration, traced: Traced, p: np.ndarray, x_final: np.ndarray
                 ) -> dict[str, float]:
    """Signed miss of each final condition at the end of a re-propagation (its units):
    the final state minus its target, a final constraint's distance outside its bounds."""
    values = dict(zip(decl.param_keys, np.asarray(p, float), strict=True))
    misses = []
    for s, xf in zip(decl.states, x_final, strict=True):
        if s.final is not None:
            misses.append(float(xf - resolve(s.final, values)))
    if traced.final is not None:
        g = np.ravel(np.asarray(traced.final(x_final, p), float))
        for c, gi in zip(decl.final, g, strict=True):
            misses.append(float(gi - np.clip(gi, c.lower, c.upper)))
    return dict(zip(miss_names(decl), misses, strict=True))


def known_names(decl: Declaration) -> set[str]:
    """Names a solution of this declaration reports: cost, quantities, statistics, misses."""
    return ({"cost", "tf"} | {f"{s.name}_final" for s in decl.states} | set(STATS)
            | set(miss_names(decl)))


def check_names(mission: Mission, decl: Declaration, where: str) -> None:
    """Published numbers, consistency records and accuracy targets name what the mission
    reports; presets and published cases set declared parameters only."""
    known = known_names(decl)
    listed = ", ".join(sorted(known))
    for name, what in ([(p.name, "published") for p in mission.published]
                       + [(c.name, "consistency") for c in mission.consistency]):
        if name not in known:
            raise DeclarationError(f"{what} '{name}' is not reported by this mission "
                                   f"(names: {listed})", where)
    misses = miss_names(decl)
    for key in mission.tolerances:
        if key not in misses:
            raise DeclarationError(f"tolerances: '{key}' is not a re-propagated miss (misses: "
                                   f"{', '.join(misses) or 'none: no final condition'})",
                                   refine(where, lambda path, line, k=key: dict_key_line(
                                       path, line, "tolerances", k)))
    cases = [(p.name, p.case.values) for p in mission.published if p.case is not None]
    for name, values in [(p.name, p.values) for p in mission.presets] + cases:
        try:
            validate_values(mission.params, values)
        except ValueError as exc:
            raise DeclarationError(f"'{name}': {exc}", where) from None
