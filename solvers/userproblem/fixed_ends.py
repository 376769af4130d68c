"""A path constraint that the fixed start or the fixed end already breaks: the problem has no
solution, whatever the controls, so it is refused before a solve with the constraint named
(the NLP would only say it found no feasible point "from this guess").

Only constraints of the states and parameters count (one that reads a control may be met by
another control), and only an end where every state is fixed."""

from __future__ import annotations

from collections.abc import Sequence

import casadi as ca
import numpy as np

from .declaration import Declaration, resolve
from .functions import Traced

SLACK = 1e-9  # relative: a constraint met to rounding at the end (a landing's z = 0) holds


def state_only_rows(decl: Declaration, traced: Traced) -> tuple[int, ...]:
    """The path constraints that do not depend on the controls (checked once, at load)."""
    if traced.path is None:
        return ()
    x = ca.SX.sym("x", len(decl.states))
    u = ca.SX.sym("u", len(decl.controls))
    p = ca.SX.sym("p", len(decl.params))
    rows = traced.path(x, u, p)
    return tuple(i for i in range(rows.numel()) if not ca.depends_on(rows[i], u))


def broken_at_fixed_end(decl: Declaration, traced: Traced, rows: Sequence[int],
                        values: dict[str, float], p: np.ndarray) -> str | None:
    """Why the fixed start or end breaks a state-only path constraint, or None."""
    if not rows or traced.path is None:
        return None
    u = np.zeros(len(decl.controls))
    for end in ("initial", "final"):
        fixed = [getattr(s, end) for s in decl.states]
        if any(v is None for v in fixed):
            continue
        x = np.array([resolve(v, values) for v in fixed], float)
        g = np.asarray(traced.path(x, u, p), float).ravel()
        for i in rows:
            c = decl.path[i]
            lo, hi, value = c.lower, c.upper, float(g[i])
            unit = f" {c.unit}" if c.unit else ""
            if value < lo - SLACK * max(1.0, abs(lo)):
                need = f"≥ {lo:g}{unit}"
            elif value > hi + SLACK * max(1.0, abs(hi)):
                need = f"≤ {hi:g}{unit}"
            else:
                continue
            where = "start" if end == "initial" else "end"
            return (f"path constraint '{c.name}' is {value:.4g}{unit} at the fixed {where}; "
                    f"it must be {need}, so no trajectory meets it")
    return None
