"""What a mission class takes from its package's `problem` module, so the package's
`__init__` does not list it again (`class M(Mission, records=problem)`).

Records: each attribute of `RECORD_NAMES` from the module's constant of that name (the first
found), unless the class body sets it.

Hooks: a module function named like one of `HOOKS` is that hook of the mission, unless the
class body defines it. It takes any of the hook's arguments by name — `precheck(p)`,
`precheck(values)`, `ocp()` — so a problem module states only what it uses. A function of a
hook's name that asks for anything else is refused when the class is made: rename it or
define the hook in the class.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from types import ModuleType
from typing import Any

# A mission attribute and the names a mission's `problem` module gives it (the first found).
RECORD_NAMES: dict[str, tuple[str, ...]] = {
    "source": ("PAPER", "SOURCE"), "params": ("PARAMS",), "view_params": ("VIEW_PARAMS",),
    "handles": ("HANDLES",), "shapes": ("SHAPES",), "published": ("PUBLISHED",),
    "presets": ("PRESETS",), "equations": ("EQUATIONS",), "tolerances": ("TOLERANCES",),
    "labels": ("LABELS",), "consistency": ("CONSISTENCY",), "cost_label": ("COST_LABEL",),
    "cost_unit": ("COST_UNIT",),
}
HOOKS = ("check_values", "parameter_vector", "precheck", "ocp")


def adopt(cls: type, module: ModuleType) -> None:
    """Give `cls` the records and hooks `module` defines and its class body does not."""
    for attr, names in RECORD_NAMES.items():
        found = [getattr(module, n) for n in names if hasattr(module, n)]
        if found and attr not in cls.__dict__:
            setattr(cls, attr, found[0])
    for name in HOOKS:
        fn = getattr(module, name, None)
        if callable(fn) and name not in cls.__dict__:
            setattr(cls, name, _as_hook(getattr(cls, name), fn, module.__name__))


def _as_hook(base: Callable[..., Any], fn: Callable[..., Any], where: str
             ) -> Callable[..., Any]:
    """`fn` called as the method `base`: with those of `base`'s arguments it names."""
    offered = list(inspect.signature(base).parameters)[1:]  # after self
    wanted = list(inspect.signature(fn).parameters)
    unknown = [w for w in wanted if w not in offered]
    if unknown:
        raise TypeError(f"{where}.{base.__name__}({', '.join(wanted)}) cannot be the mission "
                        f"hook {base.__name__}({', '.join(offered)}): it asks for "
                        f"{', '.join(unknown)}; rename it or define the hook in the class")
    picks = [offered.index(w) for w in wanted]

    @functools.wraps(fn)
    def hook(self: object, *args: Any) -> Any:
        return fn(*(args[i] for i in picks))
    return hook
