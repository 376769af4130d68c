"""Command line: `python -m solvers list | params MISSION | solve MISSION ... |
sweep MISSION --grid KEY=V1,V2 ... | launch-map --out DIR ...`.

Bad input (unknown mission, method, key or option, values out of range, an output file that
cannot be written) exits with code 2 and one line on stderr before any work starts; a solve
that runs but does not converge exits 1 after printing its result. Every solve has a time
limit (--time-limit, default {limit:g} s, 0 for none) that bounds it and its check together.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from .context import DEFAULT_TIME_LIMIT
from .mission import Mission
from .registry import expand_mission_paths, get_mission, list_missions, load_mission_files
from .request import SolveRequest
from .service import SolveService
from .solution import Solution
from .sweep import mission_grid

EXIT_BAD_INPUT = 2
EXIT_NOT_OPTIMAL = 1
EXIT_INTERRUPTED = 130
TIME_LIMIT_HELP = (f"seconds the solve and its check may take together (default "
                   f"{DEFAULT_TIME_LIMIT:g}; 0: no limit); hard: a solve still running 1 s "
                   "past it is stopped with its process")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2, no usage dump
        raise _BadInput(message)


class _BadInput(Exception):
    pass


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="python -m solvers",
                     description=(__doc__ or "").format(limit=DEFAULT_TIME_LIMIT))
    sub = parser.add_subparsers(dest="command", required=True)
    listing = sub.add_parser("list", help="the missions (built-in and from --mission-file) "
                                          "and their methods")
    params = sub.add_parser("params", help="a mission's parameters with units and ranges")
    params.add_argument("mission")
    solve = sub.add_parser("solve", help="solve one mission")
    solve.add_argument("mission")
    solve.add_argument("--method", help="method key (default: the mission's first)")
    solve.add_argument("--nodes", type=_nodes,
                       help="node/segment count (default: the method's), or 'auto': refine "
                            "until the re-propagated miss meets the accuracy targets")
    solve.add_argument("--tol", type=float,
                       help="with --nodes auto: the headline accuracy target, in its unit "
                            "(the mission's first target; the others scale with it)")
    solve.add_argument("--cold", action="store_true",
                       help="solve from the method's initial guess (the CLI has no previous "
                            "answer); with --nodes auto, every refinement step too")
    solve.add_argument("--multistart", type=int, default=1, metavar="K",
                       help="solve from K cold guesses, keep the best, report the distinct "
                            "optima")
    solve.add_argument("--backend", help="NLP back end, e.g. ipopt or sqp")
    solve.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       help="parameter value in SI units (repeatable)")
    solve.add_argument("--time-limit", type=_time_limit, default=DEFAULT_TIME_LIMIT,
                       metavar="S", help=TIME_LIMIT_HELP)
    solve.add_argument("--json", action="store_true", help="print one JSON object")
    solve.add_argument("--csv", metavar="FILE", help="write the dense trajectory as CSV")
    sweep = sub.add_parser("sweep", help="solve a mission over a grid of parameter values")
    sweep.add_argument("mission")
    sweep.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...",
                       required=True, help="an axis of the grid (repeatable)")
    sweep.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       help="a fixed parameter value in SI units (repeatable)")
    sweep.add_argument("--method")
    sweep.add_argument("--nodes", type=int)
    sweep.add_argument("--scheduler", help="dask.distributed scheduler address (tcp://...)")
    sweep.add_argument("--workers", type=_workers,
                       help="local worker processes (default: cores)")
    sweep.add_argument("--time-limit", type=_time_limit, default=DEFAULT_TIME_LIMIT,
                       metavar="S", help=TIME_LIMIT_HELP.replace("the solve", "each solve"))
    sweep.add_argument("--out", metavar="FILE", help="write every solution summary as JSON")
    for command in (listing, params, solve, sweep):
        command.add_argument("--mission-file", action="append", default=[], metavar="F",
                             help="a mission file (a folder: its *.py files); repeatable")
    sub.add_parser("launch-map", add_help=False,
                   help="asteroid launch-C3 map, PNG and data (python -m solvers launch-map -h)")
    return parser


def _time_limit(text: str) -> float | None:
    """--time-limit: seconds, positive; 0 means no limit (None)."""
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not (math.isfinite(seconds) and seconds >= 0):
        raise _BadInput(f"--time-limit must be a number of seconds (0: no limit), not '{text}'")
    return seconds or None


def _workers(text: str) -> int:
    """--workers: a whole number of processes, at least 1."""
    try:
        count = int(text)
    except ValueError:
        count = 0
    if count < 1:
        raise _BadInput(f"--workers must be a whole number of at least 1, not '{text}'")
    return count


def _nodes(text: str) -> int | str:
    """--nodes: a whole number or 'auto'."""
    if text == "auto":
        return text
    try:
        return int(text)
    except ValueError:
        raise _BadInput(f"--nodes expects a whole number or 'auto', got '{text}'") from None


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


def parse_axes(items: Sequence[str]) -> dict[str, list[float]]:
    """`key=v1,v2,...` strings to grid axes."""
    axes: dict[str, list[float]] = {}
    for item in items:
        key, sep, raw = item.partition("=")
        try:
            values = [float(v) for v in raw.split(",") if v.strip()]
        except ValueError:
            raise _BadInput(f"--grid {key}: '{raw}' is not a list of numbers") from None
        if not sep or not key or not values:
            raise _BadInput(f"--grid expects KEY=V1,V2,..., got '{item}'")
        axes[key.strip()] = values
    return axes


def _cmd_sweep(args: argparse.Namespace) -> int:
    mission = get_mission(args.mission)
    axes = parse_axes(args.grid)
    fixed = parse_assignments(args.set)
    check_request(mission, {**fixed, **{k: v[0] for k, v in axes.items()}}, args.method,
                  args.nodes, None)
    _writable(args.out, "--out")
    # Validate every grid point before any worker starts: bad input fails fast, exit 2.
    keys = list(axes)
    for key in keys:
        for value in axes[key]:
            mission.validate({**fixed, key: value}, args.method, args.nodes)
    rows = mission_grid(mission.key, axes, fixed, method=args.method, nodes=args.nodes,
                        scheduler=args.scheduler, workers=args.workers,
                        mission_files=args.files, time_limit=args.time_limit)
    if args.out is not None:
        _write(args.out, "--out", json.dumps(rows, allow_nan=False))
    print("  ".join([*keys, "status", rows[0]["cost"]["label"] if rows else "cost", "wall_s"]))
    for row in rows:
        cells = [f"{row['values'][k]:g}" for k in keys]
        cost = row["cost"]["value"]
        cells += [row["status"], "nan" if cost is None else f"{cost:.6g}",
                  f"{row['stats']['wall_s']:.3f}"]
        print("  ".join(cells))
    return 0 if all(r["status"] == "optimal" for r in rows) else EXIT_NOT_OPTIMAL


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


def _writable(path: str | None, option: str) -> None:
    """Refuse an output file that cannot be written (an empty name, a folder, a missing
    folder, no permission, a special file), before any work is done: opened for appending
    and closed again (a file that did not exist is removed again)."""
    if path is None:
        return
    target = Path(path)
    if not path.strip():
        raise _BadInput(f"{option} '{path}': an empty name is no file to write")
    if target.is_dir():
        raise _BadInput(f"{option} {path}: that is a folder; name a file in it")
    if not target.resolve().parent.is_dir():
        raise _BadInput(f"{option} {path}: the folder {target.parent} does not exist")
    existed = target.exists()
    try:
        with open(target, "a", encoding="utf-8"):
            pass
    except OSError as exc:
        raise _BadInput(f"{option} {path}: cannot be written ({exc.strerror})") from None
    if not existed:
        target.unlink(missing_ok=True)


def _write(path: str, option: str, text: str) -> None:
    """Write an output file checked by `_writable`; a failure now names option and path."""
    try:
        Path(path).write_text(text, encoding="utf-8")
    except OSError as exc:
        raise _BadInput(f"{option} {path}: writing failed ({exc.strerror}); the results "
                        "above are not saved") from None


def check_request(mission: Mission, values: dict[str, float], method: str | None,
                  nodes: int | None, backend: str | None) -> None:
    """Everything the CLI refuses before solving: values of another method, a back end the
    method does not have (exit 2)."""
    m = mission.method(method)
    known = {p.key for p in mission.all_params(m.key)}
    foreign = sorted(set(values) - known)
    if foreign:
        raise _BadInput(f"{', '.join(foreign)}: not a parameter of {mission.key} with method "
                        f"'{m.key}' (see `python -m solvers params {mission.key}`)")
    mission.validate(values, method, nodes)
    if backend is not None and backend not in m.backends:
        known_b = ", ".join(m.backends) or "none: this method has no choice of back end"
        raise _BadInput(f"method '{m.key}' has no back end '{backend}' (back ends: {known_b})")


def load_files(paths: Sequence[str]) -> list[str]:
    """Register the mission files given with --mission-file (a folder: its *.py files) and
    return them as absolute paths for the worker processes; a broken file is bad input."""
    errors = load_mission_files(list(paths))
    if errors:
        raise _BadInput(next(iter(errors.values())))
    return [str(p.resolve()) for p in expand_mission_paths(list(paths))]


def solve_isolated(request: SolveRequest, mission_files: Sequence[str] = ()) -> Solution:
    """Solve in a worker process of its own: Ctrl-C stops it at once (even inside a native
    solver) and the time limit is hard: the service stops a solve 1 s past it, and a check
    not back by then is given up (the process is stopped as the service closes).
    `mission_files` are loaded by the worker."""
    with SolveService(1, prebuild=False, mission_files=mission_files) as service:
        return service.submit(request).checked_result()


def _cmd_solve(args: argparse.Namespace) -> int:
    mission = get_mission(args.mission)
    values = parse_assignments(args.set)
    auto = args.nodes == "auto"
    check_request(mission, values, args.method, None if auto else args.nodes, args.backend)
    if args.tol is not None:
        mission.accuracy_targets(args.tol)  # a bad --tol is bad input (exit 2)
    if args.multistart < 1:
        raise _BadInput(f"--multistart must be at least 1, not {args.multistart}")
    _writable(args.csv, "--csv")
    sol = solve_isolated(SolveRequest(mission.key, args.method, args.nodes, args.backend,
                                      values, args.time_limit, args.tol, args.cold,
                                      args.multistart), args.files)
    if args.json:
        print(sol.to_json())
    else:
        label = mission.method(sol.method).nodes_label
        print(f"{mission.key} / {sol.method} ({sol.nodes} {label})")
        print(f"  {sol.summary()}")
        print(f"  {sol.message}")
        for key, value in sol.check.items():
            target = f"  (target {sol.targets[key]:g})" if key in sol.targets else ""
            print(f"  check {key:24s} {value:.3e}{target}")
        for step in sol.mesh:
            print(f"  mesh  {int(step['nodes']):5d} nodes: miss {step['miss']:.3e}, "
                  f"{step['worst_ratio']:.3g} x target, {step['solve_s']:.2f} s")
    if args.csv is not None:
        _write(args.csv, "--csv", sol.to_csv())
    return 0 if sol.ok else EXIT_NOT_OPTIMAL


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["launch-map"]:  # its own parser and options
        # Imported here: every other command starts without the launch map's ephemeris
        # and porkchop machinery.
        from .missions.asteroid_rendezvous.launch_map import main as launch_map_main

        return launch_map_main(argv[1:])
    try:
        args = build_parser().parse_args(argv)
        args.files = load_files(args.mission_file)
        if args.command == "list":
            print(_cmd_list())
            return 0
        if args.command == "params":
            print(_cmd_params(get_mission(args.mission)))
            return 0
        if args.command == "sweep":
            return _cmd_sweep(args)
        return _cmd_solve(args)
    except (_BadInput, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (OSError, RuntimeError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT


def run() -> None:
    """The command (`python -m solvers`, `trajectory-solve`): `main`, then exit with its
    code; on Ctrl-C without the interpreter's teardown: its final garbage collection of the
    loaded libraries took 0.2 s on a quiet machine and several seconds on a loaded one
    (py-spy: `gc_collect_main` after `main` returned), while the solve workers are already
    stopped and the output flushed."""
    code = main()
    if code != EXIT_INTERRUPTED:
        sys.exit(code)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    run()
