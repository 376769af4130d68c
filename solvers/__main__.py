"""Command line: `python -m solvers list | params MISSION | solve MISSION ...`.

Bad input (unknown mission, method or key, values out of range) exits with code 2 and one
line on stderr; a solve that runs but does not converge exits 1 after printing its result.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from .mission import Mission
from .registry import get_mission, list_missions
from .solution import Solution

EXIT_BAD_INPUT = 2
EXIT_NOT_OPTIMAL = 1


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2, no usage dump
        raise _BadInput(message)


class _BadInput(Exception):
    pass


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="python -m solvers", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="the built-in missions and their methods")
    params = sub.add_parser("params", help="a mission's parameters with units and ranges")
    params.add_argument("mission")
    solve = sub.add_parser("solve", help="solve one mission")
    solve.add_argument("mission")
    solve.add_argument("--method", help="method key (default: the mission's first)")
    solve.add_argument("--nodes", type=int, help="node/segment count (default: the method's)")
    solve.add_argument("--backend", help="NLP back end, e.g. ipopt or sqp")
    solve.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       help="parameter value in SI units (repeatable)")
    solve.add_argument("--time-limit", type=float, help="stop the solve after this many s")
    solve.add_argument("--json", action="store_true", help="print one JSON object")
    solve.add_argument("--csv", metavar="FILE", help="write the dense trajectory as CSV")
    return parser


def parse_assignments(items: Sequence[str]) -> dict[str, float]:
    """`key=value` strings to a dict; values must parse as numbers."""
    values: dict[str, float] = {}
    for item in items:
        key, sep, raw = item.partition("=")
        if not sep or not key:
            raise _BadInput(f"--set expects KEY=VALUE, got '{item}'")
        try:
            values[key.strip()] = float(raw)
        except ValueError:
            raise _BadInput(f"--set {key}: '{raw}' is not a number") from None
    return values


def _cmd_list() -> str:
    lines = []
    for mission in list_missions():
        lines.append(f"{mission.key:22s} {mission.title} — {mission.source}")
        for m in mission.methods:
            lo, default, hi = m.nodes
            backends = f"; back ends {', '.join(m.backends)}" if m.backends else ""
            lines.append(
                f"    {m.key:20s} {m.label} ({m.nodes_label} {lo}..{hi}, default {default}"
                f"{backends})"
            )
    return "\n".join(lines)


def _cmd_params(mission: Mission) -> str:
    lines = [f"{mission.key}: parameters (SI units)"]
    for m in (None, *[meth.key for meth in mission.methods]):
        params = mission.params if m is None else mission.method(m).params
        if m is not None and params:
            lines.append(f"  method {m}:")
        for p in params:
            lines.append(f"    {p.key:18s} {p.default:<12g} {p.describe_range():28s} {p.label}")
    return "\n".join(lines)


def _result_dict(sol: Solution) -> dict:
    out = sol.to_dict()
    out["quantities"] = {k: q.value for k, q in sol.quantities.items()}
    return out


def _cmd_solve(args: argparse.Namespace) -> int:
    mission = get_mission(args.mission)
    values = parse_assignments(args.set)
    sol = mission.solve(values, method=args.method, nodes=args.nodes, backend=args.backend,
                        time_limit=args.time_limit)
    if args.csv:
        with open(args.csv, "w", encoding="utf-8") as fh:
            fh.write(sol.to_csv())
    if args.json:
        print(json.dumps(_result_dict(sol), allow_nan=False))
    else:
        label = mission.method(sol.method).nodes_label
        print(f"{mission.key} / {sol.method} ({sol.nodes} {label})")
        print(f"  {sol.summary()}")
        print(f"  {sol.message}")
        for key, value in sol.check.items():
            print(f"  check {key:24s} {value:.3e}")
    return 0 if sol.ok else EXIT_NOT_OPTIMAL


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = build_parser().parse_args(argv)
        if args.command == "list":
            print(_cmd_list())
            return 0
        if args.command == "params":
            print(_cmd_params(get_mission(args.mission)))
            return 0
        return _cmd_solve(args)
    except (_BadInput, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":
    sys.exit(main())
