"""The status line: what the last solve returned, in markdown, from any `Solution`."""

from __future__ import annotations

import math

from solvers.solution import Solution

_UNIT_TOKENS = {"m", "s", "kg", "km", "rad", "deg", "N", "s2"}
KEPT = "_showing the last good trajectory (dimmed)_"
SHOWN = 3  # quantities and check items in the status; all of them are in the details


def check_label(key: str) -> tuple[str, str]:
    """Split a check key such as "radial_speed_m_s" into ("radial speed", "m/s")."""
    tokens = key.split("_")
    split = len(tokens)
    while split > 1 and tokens[split - 1] in _UNIT_TOKENS:
        split -= 1
    name, unit = " ".join(tokens[:split]), tokens[split:]
    return name, "/".join(unit) if unit else ""


def _num(value: float, digits: int) -> str:
    return "n/a" if not math.isfinite(value) else f"{value:.{digits}g}"


def headline(sol: Solution) -> str:
    """Status, cost and the mission's quantities of interest."""
    parts = [f"**{sol.status}**"]
    if math.isfinite(sol.cost.value):
        parts.append(f"{sol.cost.label} **{sol.cost.value:.6g} {sol.cost.unit}**".rstrip())
    parts += [f"{q.label} {_num(q.value, 6)} {q.unit}".rstrip()
              for q in sol.quantities.values() if q.label != sol.cost.label][:SHOWN]
    return " · ".join(parts)


def solver_line(sol: Solution) -> str:
    """Method, mesh, iterations and wall time."""
    method = f"{sol.method}/{sol.backend}" if sol.backend else sol.method
    parts = [f"{method}, {sol.nodes} nodes"]
    if "iterations" in sol.stats:
        parts.append(f"{int(sol.stats['iterations'])} iterations")
    if "wall_s" in sol.stats:
        parts.append(f"{1e3 * sol.stats['wall_s']:.0f} ms")
    return " · ".join(parts)


def check_line(sol: Solution) -> str:
    """Re-propagation miss (empty until `Solution.run_check` has run)."""
    if not sol.check:
        return ""
    items = []
    for key, value in list(sol.check.items())[:SHOWN]:
        name, unit = check_label(key)
        items.append(f"{name} {_num(value, 2)} {unit}".rstrip())
    more = " · …" if len(sol.check) > SHOWN else ""
    return "re-propagation check: " + " · ".join(items) + more


def details_markdown(sol: Solution) -> str:
    """Every quantity, statistic and check of a solution as a table (the status shows only
    the first few)."""
    rows = [f"| {sol.cost.label} (cost) | {_num(sol.cost.value, 8)} {sol.cost.unit} |"]
    rows += [f"| {q.label} | {_num(q.value, 8)} {q.unit} |" for q in sol.quantities.values()]
    rows += [f"| {key.replace('_', ' ')} | {_num(v, 6)} |" for key, v in sol.stats.items()]
    for key, value in sol.check.items():
        name, unit = check_label(key)
        rows.append(f"| check: {name} | {_num(value, 3)} {unit} |")
    return "\n".join(["| | |", "|---|---|", *rows])


def result_markdown(sol: Solution, checking: bool = False, kept: bool = False) -> str:
    """The full status; `kept` notes that an older good trajectory stays on screen."""
    lines = [headline(sol), solver_line(sol)]
    if not sol.ok:
        lines.append(f"_{sol.message}_")
        if kept:
            lines.append(KEPT)
    check = check_line(sol)
    lines.append(check if check else "re-propagation check running…" if checking else "")
    return "  \n".join(line for line in lines if line)


def progress_markdown(iteration: int, previous: str, elapsed: float | None = None,
                      limit: float | None = None, message: str = "") -> str:
    """'solving… iteration k (t s of the limit)' above the previous result, which stays
    readable; `message` is the solver's (or the comparison's) progress note."""
    head = f"**solving… iteration {iteration}**"
    if elapsed is not None:
        head += f" ({elapsed:.1f} s" + (f" of {limit:g} s limit)" if limit else ")")
    if message:
        head += f"  \n_{message}_"
    return f"{head}  \n{previous}" if previous else head


def rejected_markdown(message: str, kept: bool) -> str:
    return f"**request rejected**  \n{message}" + (f"  \n{KEPT}" if kept else "")
